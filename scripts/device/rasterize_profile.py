#!/usr/bin/env python3
"""Where one rast.rasterize call's time goes on a GPU (issue #42's fixed cost
per call): the call timed whole, the module's C++ entry alone (no Python
wrapper), and a torch.profiler trace of a few calls whose events (rast's
kernels, copies and the CUDA runtime's waits, seen through CUPTI) are printed
as one call's timeline, offsets from the call's start. Never part of the
tests; run on the GPU machine next to rasterize_vs_nvdiffrast.py:
  python3 scripts/device/rasterize_profile.py --rast .device/cuda/rast \\
      --models .device/shared/models --out $OUT/profile [--scenes box,duck]
"""
import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from rasterize_vs_nvdiffrast import clip_space_inputs  # noqa: E402


def median(v):
    v = sorted(v)
    return v[len(v) // 2]


def wall_ms(torch, fn, n):
    torch.cuda.synchronize()
    ms = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        torch.cuda.synchronize()
        ms.append((time.perf_counter() - t0) * 1e3)
    return median(ms)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rast", required=True)
    ap.add_argument("--models", required=True)
    ap.add_argument("--scenes", default="box,duck")
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    import torch
    import rast
    from torch.profiler import ProfilerActivity, profile
    w, h = (int(v) for v in a.size.split("x"))
    ctx = rast.RasterizeContext()
    for name in a.scenes.split(","):
        path = os.path.join(a.models, name + ".glb")
        clip, tri = clip_space_inputs(rast, a.rast, path, w, h)
        p = torch.from_numpy(clip).cuda().unsqueeze(0).contiguous()
        t = torch.from_numpy(tri).cuda().contiguous()
        full = lambda: rast.rasterize(p, t, (h, w), context=ctx)  # noqa: E731
        entry = lambda: rast._rast._rasterize(ctx, p, t, h, w)  # noqa: E731
        for _ in range(30):
            full()
        print(f"{name}: {len(tri)} triangles; wall median of 200: rast.rasterize {wall_ms(torch, full, 200):.4f} ms, "
              f"C++ entry alone {wall_ms(torch, entry, 200):.4f} ms", flush=True)
        # The Python wrapper's pieces, host time of each (median of 2000).
        out, ids = entry()
        stream = rast._rast.device_stream if hasattr(rast._rast, "device_stream") else 1
        pieces = {
            "_producer(pos)": lambda: rast._producer(p, "pos", np.float32, [("B", "V", 4), ("V", 4)]),
            "pos.__dlpack__(stream)": lambda: p.__dlpack__(stream=stream),
            "pos.__dlpack__()": lambda: p.__dlpack__(),
            "_legacy_ordered(pos)": lambda: rast._legacy_ordered(p),
            "to_dlpack(pos)": lambda: torch.utils.dlpack.to_dlpack(p),
            "torch.from_dlpack(out)": lambda: torch.from_dlpack(out),
            "from_dlpack(out capsule)": lambda: torch.from_dlpack(out.__dlpack__()),
            "current_stream(dev)": lambda: torch.cuda.current_stream(p.device),
        }
        for k, fn in pieces.items():
            ts = []
            for _ in range(2000):
                t0 = time.perf_counter()
                fn()
                ts.append((time.perf_counter() - t0) * 1e6)
            print(f"  {k:28s} {median(ts):8.2f} us", flush=True)
        with profile(activities=[ProfilerActivity.CPU, ProfilerActivity.CUDA]) as prof:
            for _ in range(12):
                full()
                torch.cuda.synchronize()
        prof.export_chrome_trace(os.path.join(a.out, f"{name}_trace.json"))
        print(prof.key_averages().table(sort_by="self_cpu_time_total", row_limit=30), flush=True)
        # The last call's events in time order.
        ev = sorted((e for e in prof.events() if e.time_range.start is not None), key=lambda e: e.time_range.start)
        syncs = [e for e in ev if e.name == "cudaDeviceSynchronize"]
        if len(syncs) >= 2:
            t0, t1 = syncs[-2].time_range.end, syncs[-1].time_range.end
            print(f"{name}: last call timeline (us from its start)", flush=True)
            for e in ev:
                if t0 <= e.time_range.start <= t1:
                    dev = getattr(e, "device_type", None)
                    print(f"  {e.time_range.start - t0:9.1f} +{e.time_range.elapsed_us():8.1f}  "
                          f"{'GPU' if str(dev).endswith('CUDA') else 'cpu'}  {e.name[:110]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

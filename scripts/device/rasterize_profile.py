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
import json
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


def timeline(trace, scene):
    """The last `call:<scene>` range of a Chrome trace with the host's CUDA
    calls and the GPU's kernels and copies inside it, as offsets from its
    start (CUPTI's GPU times may sit a few us off the host's clock)."""
    ev = trace["traceEvents"] if isinstance(trace, dict) else trace
    calls = sorted((e for e in ev if e.get("ph") == "X" and e.get("name") == "call:" + scene), key=lambda e: e["ts"])
    if not calls:
        return f"{scene}: no calls in the trace"
    durs = sorted(e["dur"] for e in calls[len(calls) // 4:])
    last = calls[-1]
    t0, t1 = last["ts"], last["ts"] + last["dur"]
    lines = [f"{scene}: last of {len(calls)} calls {last['dur']:.1f} us, median of the last 3/4 {durs[len(durs) // 2]:.1f} us"]
    keep = {"cuda_runtime": "host", "cuda_driver": "host", "kernel": "GPU ", "gpu_memcpy": "GPU ", "gpu_memset": "GPU "}
    rows = [e for e in ev if e.get("ph") == "X" and e.get("cat") in keep and t0 <= e["ts"] <= t1 + 50]
    for e in sorted(rows, key=lambda e: e["ts"]):
        lines.append(f"  {e['ts'] - t0:8.1f} +{e['dur']:7.1f}  {keep[e['cat']]}  {e['name'][:100]}")
    return "\n".join(lines)


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
    from torch.profiler import ProfilerActivity, profile, record_function
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
                with record_function("call:" + name):
                    full()
                    torch.cuda.synchronize()
        trace = os.path.join(a.out, f"{name}_trace.json")
        prof.export_chrome_trace(trace)
        print(prof.key_averages().table(sort_by="self_cpu_time_total", row_limit=30), flush=True)
        # The last call's host calls and GPU work in time order, from the
        # exported trace (prof.events() leaves the recorded frame's kernels out).
        with open(trace) as f:
            print(timeline(json.load(f), name), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

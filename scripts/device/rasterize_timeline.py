#!/usr/bin/env python3
"""One rast.rasterize call's timeline on the GPU machine (issue #42's fixed
cost per call): the host's CUDA runtime calls and the GPU's kernels and copies
of the last of N calls, each as an offset from the call's start, so launch
latency, waits and device work can be told apart. From torch.profiler's CUPTI
trace (the GPU image has no Nsight Systems), exported as Chrome trace JSON and
read back here; each call is a record_function range named after its scene.
Never part of the tests:

  python3 scripts/device/rasterize_timeline.py --rast R --models M --scenes duck --out DIR
"""
import argparse
import json
import os
import sys


def timeline(trace, scene):
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
    ap.add_argument("--scenes", default="box,duck,milktruck")
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--calls", type=int, default=40)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    import torch
    import rast
    from torch.profiler import ProfilerActivity, profile, record_function
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from rasterize_vs_nvdiffrast import clip_space_inputs
    w, h = (int(v) for v in a.size.split("x"))
    ctx = rast.RasterizeContext()
    for name in a.scenes.split(","):
        clip, tri = clip_space_inputs(rast, a.rast, os.path.join(a.models, name + ".glb"), w, h)
        p = torch.from_numpy(clip).cuda().unsqueeze(0).contiguous()
        t = torch.from_numpy(tri).cuda().contiguous()
        for _ in range(20):
            rast.rasterize(p, t, (h, w), context=ctx)
        torch.cuda.synchronize()
        with profile(activities=[ProfilerActivity.CPU, ProfilerActivity.CUDA]) as prof:
            for _ in range(a.calls):
                with record_function("call:" + name):
                    out, ids = rast.rasterize(p, t, (h, w), context=ctx)
                    torch.cuda.synchronize()
                del out, ids
        path = os.path.join(a.out, name + "_trace.json")
        prof.export_chrome_trace(path)
        with open(path) as f:
            print(timeline(json.load(f), name), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

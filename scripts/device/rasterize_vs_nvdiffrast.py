#!/usr/bin/env python3
"""rast.rasterize (the Python module of a CUDA build, docs/python.md) against
nvdiffrast's dr.rasterize on the same clip-space triangles, both fed torch
CUDA tensors and giving torch CUDA tensors back, each with its own context kept
across calls: the issue #42 comparison. Per scene it reports both median
times (CUDA events around the call, after warm-up; the same way for both), the
ratio, and how many pixels agree on coverage and on the triangle id.

  python3 scripts/device/rasterize_vs_nvdiffrast.py --rast .device/cuda/rast \\
      --models .device/shared/models --stress /tmp/stress --out OUT.csv [--size 1920x1080]

Needs PYTHONPATH with the CUDA build's module (rast) and nvdiffrast installed
(scripts/device/three_way.sh shows how); never part of the project's tests.
Triangles come from `rast export` (world space, one draw per node), the camera
from rast.Camera.framing, the projection as nvdiffrast_bench.py builds it.
"""
import argparse
import csv
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from nvdiffrast_bench import load_glb, view_proj  # noqa: E402


def median(v):
    v = sorted(v)
    n = len(v)
    return v[n // 2] if n % 2 else 0.5 * (v[n // 2 - 1] + v[n // 2])


def timed(torch, fn, frames, warmup):
    for _ in range(warmup):
        fn()
    torch.cuda.synchronize()
    ms = []
    for _ in range(frames):
        a, b = torch.cuda.Event(enable_timing=True), torch.cuda.Event(enable_timing=True)
        a.record()
        fn()
        b.record()
        b.synchronize()
        ms.append(a.elapsed_time(b))
    return median(ms), min(ms)


def clip_space_inputs(rast, rast_cli, path, w, h):
    """The scene's triangles as `rast export` writes them (world space) and
    their clip-space positions from rast's framing camera at w x h:
    (clip [V,4] float32, tri [T,3] int32). RuntimeError when the export fails."""
    with tempfile.TemporaryDirectory() as tmp:
        glb = os.path.join(tmp, "scene.glb")
        r = subprocess.run([rast_cli, "export", path, "-o", glb], capture_output=True, text=True, timeout=600)
        if r.returncode != 0:
            raise RuntimeError(f"rast export failed: {r.stderr.strip()}")
        pos, tri = load_glb(glb)
    cam = rast.Camera.framing(rast.Scene.load(path))
    mvp = view_proj(cam.eye, cam.target, cam.up, cam.fovy, cam.near, cam.far, w / h)
    return (np.c_[pos, np.ones(len(pos))] @ mvp.T).astype(np.float32), tri


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rast", required=True, help="a rast CLI (for `rast export`)")
    ap.add_argument("--models", required=True)
    ap.add_argument("--stress", default="", help="glref's gen_scenes.py output (tiny.glb: the 1 M-triangle scene)")
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--frames", type=int, default=100)
    ap.add_argument("--warmup", type=int, default=10)
    ap.add_argument("--out", required=True)
    a = ap.parse_args()
    import torch
    import nvdiffrast.torch as dr
    import rast
    print(f"rast {rast.__version__} ({rast.backend}, device {rast.device_index}), torch {torch.__version__}, "
          f"GPU {torch.cuda.get_device_name(0)}", flush=True)
    w, h = (int(v) for v in a.size.split("x"))
    scenes = [(m[:-4], os.path.join(a.models, m)) for m in
              ["box.glb", "checkerboard.glb", "cow.glb", "duck.glb", "engine.glb", "milktruck.glb"]]
    if a.stress:
        scenes.append(("tiny", os.path.join(a.stress, "tiny.glb")))
    glctx = dr.RasterizeCudaContext()
    rctx = rast.RasterizeContext()
    rows = []
    for name, path in scenes:
        if not os.path.exists(path):
            print(f"{name}: {path} is missing, skipped", flush=True)
            continue
        try:
            clip, tri = clip_space_inputs(rast, a.rast, path, w, h)
        except RuntimeError as e:
            print(f"{name}: {e}", flush=True)
            continue
        p = torch.from_numpy(clip).cuda().unsqueeze(0).contiguous()
        t = torch.from_numpy(tri).cuda().contiguous()
        res = (h, w)
        with torch.no_grad():
            nv_ms, nv_min = timed(torch, lambda: dr.rasterize(glctx, p, t, resolution=res), a.frames, a.warmup)
            ra_ms, ra_min = timed(torch, lambda: rast.rasterize(p, t, res, context=rctx), a.frames, a.warmup)
            nv_out, _ = dr.rasterize(glctx, p, t, resolution=res)
            ra_out, ra_ids = rast.rasterize(p, t, res, context=rctx)
        nv_ids = nv_out[0, :, :, 3].to(torch.int64) - 1
        ri = ra_ids[0].to(torch.int64)
        both = (nv_ids >= 0) | (ri >= 0)
        cov_agree = float(((nv_ids >= 0) == (ri >= 0)).float().mean().item())
        id_agree = float((nv_ids[both] == ri[both]).float().mean().item()) if both.any() else 1.0
        same_channel3 = bool(torch.equal(ra_out[0, :, :, 3], (ri + 1).to(torch.float32)))
        # Where both cover a pixel with different triangles: is it a depth tie
        # (the two winners' z/w equal to float precision), which each resolves
        # by its own rule (rast: the lower index; nvdiffrast: whichever lands)?
        differ = (nv_ids >= 0) & (ri >= 0) & (nv_ids != ri)
        n_differ = int(differ.sum().item())
        if n_differ:
            zn, zr = nv_out[0, :, :, 2][differ], ra_out[0, :, :, 2][differ]
            rel = (zn - zr).abs() / zr.abs().clamp_min(1e-30)
            ties = float((rel <= 1e-6).float().mean().item())
            max_rel = float(rel.max().item())
        else:
            ties, max_rel = 1.0, 0.0
        row = {"scene": name, "size": a.size, "triangles": int(len(tri)), "nvdiffrast_ms": nv_ms, "rast_ms": ra_ms,
               "nvdiffrast_min_ms": nv_min, "rast_min_ms": ra_min, "rast_over_nvdiffrast": ra_ms / nv_ms,
               "coverage_agree": cov_agree, "id_agree_covered": id_agree, "rast_channel3_is_id": same_channel3,
               "ids_differ": n_differ, "differ_at_depth_ties": ties, "differ_max_rel_zw": max_rel}
        rows.append(row)
        print(f"{name:>12} tris={len(tri):>8} nvdiffrast={nv_ms:.4f} ms rast={ra_ms:.4f} ms "
              f"ratio={ra_ms / nv_ms:.3f} coverage_agree={cov_agree:.6f} ids_agree={id_agree:.6f} "
              f"differ={n_differ} of_them_ties={ties:.3f} max_rel_zw={max_rel:.2e}", flush=True)
    with open(a.out, "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=list(rows[0].keys()) if rows else ["scene"])
        wr.writeheader()
        wr.writerows(rows)


if __name__ == "__main__":
    sys.exit(main())

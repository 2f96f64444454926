#!/usr/bin/env python3
"""rast's OpenMP frame against Mesa's llvmpipe (glref through EGL without a GPU)
on the same cores, scene, camera and lighting (issue #11's CPU table).

For every scene and size, glref and each rast binary given run one after the
other, --repeats times, so that load from other processes hits them alike;
each run reports a median over --frames, and the table keeps the smallest
median of the repeats (the least disturbed) next to the median of them.
rast uses --raster auto. Writes a CSV and prints the ratios rast/llvmpipe.

  python3 scripts/measure/cpu_vs_llvmpipe.py --glref G --rast NEW [--rast OLD ...] --models DIR --stress DIR \\
      --out F.csv [--sizes 1920x1080,800x800] [--frames 30] [--repeats 3]
"""
import argparse
import os
import re
import statistics
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from csv_rows import write_rows  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--glref", required=True)
ap.add_argument("--rast", action="append", required=True, help="rast binary (repeatable; label=path allowed)")
ap.add_argument("--models", default="", help="folder of .glb models (auto camera)")
ap.add_argument("--stress", default="", help="folder with glref's gen_scenes.py output (bigtri, tiny, overdraw)")
ap.add_argument("--scenes", default="", help="comma-separated subset of scene names")
ap.add_argument("--sizes", default="1920x1080")
ap.add_argument("--frames", type=int, default=30)
ap.add_argument("--warmup", type=int, default=5)
ap.add_argument("--repeats", type=int, default=3)
ap.add_argument("--out", required=True)
a = ap.parse_args()

rasts = []
for r in a.rast:
    label, _, path = r.rpartition("=")
    rasts.append((label or os.path.basename(os.path.dirname(os.path.abspath(path))) or "rast", path))

scenes = []
if a.models and os.path.isdir(a.models):
    for m in sorted(os.listdir(a.models)):
        if m.endswith(".glb"):
            scenes.append((m[:-4], os.path.join(a.models, m), None))
if a.stress and os.path.isdir(a.stress):
    for m in ["bigtri", "tiny", "overdraw"]:
        p = os.path.join(a.stress, m + ".glb")
        if os.path.exists(p):
            cam = ["--eye", "0,0,1", "--target", "0,0,0", "--up", "0,1,0", "--fovy", "45", "--near", "0.1",
                   "--far", "10"] if m == "bigtri" else None
            scenes.append((m, p, cam))
if a.scenes:
    keep = a.scenes.split(",")
    scenes = [s for s in scenes if s[0] in keep]


def run_glref(path, size, cam):
    cmd = [a.glref, path, "--size", size, "--frames", str(a.frames), "--warmup", str(a.warmup), "--no-ids"]
    cmd += cam if cam else ["--auto-camera"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    out = r.stdout + r.stderr
    m = re.search(r"median_ms=([0-9.]+)", out)
    cm = re.search(r"camera (?:\(auto\) )?(--eye .*)", out)
    if not m:
        print(f"glref failed on {path}: {out[-300:]}", file=sys.stderr)
    return (float(m.group(1)) if m else None), (cm.group(1).split() if cm else None)


def run_rast(exe, path, size, cam):
    cmd = [exe, "bench", path, "--size", size, "--frames", str(a.frames), "--warmup", str(a.warmup)] + (cam or [])
    env = dict(os.environ, OMP_PROC_BIND=os.environ.get("OMP_PROC_BIND", "false"))
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=900, env=env)
    # method vertex setup raster shade total min ...
    for line in r.stdout.splitlines():
        f = line.split()
        if len(f) >= 8 and f[0].startswith("auto"):
            return float(f[5]), f[0], {"vertex": float(f[1]), "setup": float(f[2]), "raster": float(f[3]),
                                       "shade": float(f[4])}
    print(f"rast failed on {path}: {r.stderr.strip()[-300:]}", file=sys.stderr)
    return None, None, {}


rows = []
for size in a.sizes.split(","):
    for name, path, cam in scenes:
        gl, rs = [], {label: [] for label, _ in rasts}
        stages, method = {}, {}
        for _ in range(a.repeats):
            ms, c = run_glref(path, size, cam)
            if ms is not None:
                gl.append(ms)
            cam_flags = cam or c
            for label, exe in rasts:
                ms, meth, st = run_rast(exe, path, size, cam_flags)
                if ms is not None:
                    rs[label].append(ms)
                    if label not in stages or ms <= min(rs[label]):
                        stages[label], method[label] = st, meth
        if not gl:
            continue
        row = {"scene": name, "size": size, "llvmpipe_min_ms": min(gl), "llvmpipe_median_ms": statistics.median(gl),
               "repeats": a.repeats, "frames": a.frames}
        line = f"{size:>10} {name:>12} llvmpipe={min(gl):8.2f}"
        for label, _ in rasts:
            if not rs[label]:
                continue
            row[f"{label}_min_ms"] = min(rs[label])
            row[f"{label}_median_ms"] = statistics.median(rs[label])
            row[f"{label}_method"] = method[label]
            for st, v in stages[label].items():
                row[f"{label}_{st}_ms"] = v
            row[f"{label}_ratio"] = min(rs[label]) / min(gl)
            line += f"  {label}={min(rs[label]):8.2f} ({row[f'{label}_ratio']:.2f}x)"
        rows.append(row)
        print(line, flush=True)

write_rows(a.out, rows)

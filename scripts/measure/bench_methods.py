#!/usr/bin/env python3
"""Benchmark every raster method (and `auto`) over the stability scenes, the
shared models and a triangle-size sweep; write one CSV row per
(scene, method, size). Charts: scripts/plot/plot_methods.py.

  python3 scripts/measure/bench_methods.py --rast build/openmp/rast --out docs/data/methods_openmp.csv
"""
import argparse
import csv
import io
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from csv_rows import write_rows  # noqa: E402
from progress import Progress  # noqa: E402

STABILITY = ["builtin:default", "builtin:bigtri", "builtin:tiny", "builtin:overdraw?layers=64",
             "builtin:overdraw?layers=64&order=front", "builtin:slivers", "builtin:nearplane",
             "builtin:degenerate", "builtin:extreme?scale=1e6", "builtin:extreme?scale=1e-6",
             "builtin:zfight"]
# The sweep draws one mesh (builtin:grid?n=64, 8192 triangles, side 2) from
# these distances; at 1080 rows a triangle's legs are 40.7/d pixels long.
SWEEP_N = 64
SWEEP_DISTANCES = [400, 100, 25, 8, 2.5, 0.8, 0.25]


def run_bench(rast, scene, size, frames, warmup, extra):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "rows.csv")
        cmd = [rast, "bench", scene, "--size", size, "--frames", str(frames), "--warmup", str(warmup),
               "--all-methods", "--csv", out] + extra
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            sys.exit(f"bench failed: {' '.join(cmd)}\n{r.stderr}")
        print(r.stdout.strip().split("\n", 1)[1], flush=True)
        with open(out) as f:
            return list(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rast", required=True)
    ap.add_argument("--out", required=True, help="CSV file to write")
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--frames", type=int, default=30)
    ap.add_argument("--warmup", type=int, default=3)
    ap.add_argument("--shared", default=os.path.join(HERE, "..", "..", "..", "shared"))
    ap.add_argument("--quick", action="store_true", help="small sizes and few frames (CI smoke run)")
    a = ap.parse_args()
    if a.quick:
        a.size, a.frames, a.warmup = "320x180", 3, 1

    rows = []
    scenes = list(STABILITY)
    if a.quick:
        scenes = [s.replace("builtin:tiny", "builtin:tiny?n=20000") for s in scenes]
    models = os.path.join(a.shared, "models")
    for m in ["cow.glb", "duck.glb", "milktruck.glb", "engine.glb"]:
        if os.path.exists(os.path.join(models, m)):
            scenes.append(os.path.join(models, m))
    progress = Progress("bench_methods: run", len(scenes) + len(SWEEP_DISTANCES))
    for s in scenes:
        progress.step(s)
        for r in run_bench(a.rast, s, a.size, a.frames, a.warmup, []):
            r["kind"] = "scene"
            r["scene"] = os.path.basename(s) if s.endswith(".glb") else s
            rows.append(r)
    height = int(a.size.split("x")[1])
    for d in SWEEP_DISTANCES:
        tri_px = (2.0 / SWEEP_N) * (height / 2) / (d * 0.41421356)
        extra = ["--eye", f"0.0137,0.0091,{d}", "--target", "0.0137,0.0091,0", "--near", str(d / 1000),
                 "--far", str(d * 10 + 10)]
        progress.step(f"sweep d={d}")
        for r in run_bench(a.rast, f"builtin:grid?n={SWEEP_N}", a.size, a.frames, a.warmup, extra):
            r["kind"] = "sweep"
            r["tri_px"] = f"{tri_px:.4g}"
            rows.append(r)
    progress.close()
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    write_rows(a.out, rows)
    print(f"wrote {a.out} ({len(rows)} rows)")


if __name__ == "__main__":
    main()

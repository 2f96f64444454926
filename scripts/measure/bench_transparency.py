#!/usr/bin/env python3
"""Transparency methods charted against each other (docs/transparency.md): for
each stress scene (builtin:layers variants where the methods are known to
fail) and each method (exact, kbuffer, weighted, sorted), its median frame
time (`rast bench --json`) and its error in linear light against `exact` and
against a supersampled exact reference (`--reference --reference-grid G`),
both read from `-o F.pfm` (the linear film). The opaque frame (the same scene
with n=0: the opaque backdrop alone) is timed too, for the cost ratio. One CSV row per (scene, method):

    scene, method, ms, opaque_ms, rmse_vs_exact, max_vs_exact, rmse_vs_reference, size, backend, shading, layers

`--sweep` takes the layer counts 1 to 256 instead (powers of two), of one
alpha (0.1) and of mixed alphas and hues: how each method's cost and error
grow with depth (chart: scripts/plot/plot_transparency_layers.py).

`--shading S` draws every frame with that shading (the built-in scenes'
default is Lambert's headlight, which lights their KHR_materials_unlit layers;
`--shading pbr` draws them as their materials say). Python standard library only. Chart: scripts/plot/plot_transparency.py.

  python3 scripts/measure/bench_transparency.py --rast build/openmp/rast --out docs/data/transparency_openmp.csv
"""
import argparse
import csv
import json
import math
import os
import struct
import subprocess
import tempfile

SCENES = [
    ("equal alpha x8", "builtin:layers?n=8&alpha=0.5"),
    ("mixed x8", "builtin:layers?n=8&mixed=1"),
    ("mixed x32", "builtin:layers?n=32&mixed=1"),
    ("intersecting x8", "builtin:layers?n=8&mixed=1&cross=1"),
    ("coplanar x6", "builtin:layers?n=6&mixed=1&equal=1"),
    ("strong front x8", "builtin:layers?n=8&mixed=1&near_alpha=0.95"),
    ("equal alpha x64", "builtin:layers?n=64&alpha=0.1"),
]
# --sweep: the full-frame layers of one alpha and of mixed ones, 1 to 256 deep.
SWEEP = [(f"{kind} x{n}", f"builtin:layers?n={n}&{query}")
         for kind, query in [("equal alpha", "alpha=0.1"), ("mixed", "mixed=1")]
         for n in [1, 2, 4, 8, 16, 32, 64, 128, 256]]
METHODS = ["exact", "kbuffer", "weighted", "sorted"]


def read_pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        ch = 3 if kind == b"PF" else 1
        data = f.read()
    fmt = ("<" if scale < 0 else ">") + f"{w * h * ch}f"
    return struct.unpack(fmt, data)


def errors(a, b):
    d = [abs(x - y) for x, y in zip(a, b)]
    return math.sqrt(sum(v * v for v in d) / max(len(d), 1)), max(d) if d else 0.0


def bench(rast, args, tmp):
    out = os.path.join(tmp, "bench.json")
    run([rast, "bench"] + args + ["--json", out])
    with open(out) as f:
        rows = json.load(f)
    return rows[0] if isinstance(rows, list) else rows


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"FAILED: {' '.join(cmd)}: {r.stderr.strip()}")
    return r.stdout


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rast", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--frames", default="20")
    ap.add_argument("--reference-grid", default="4", help="samples per pixel side of the exact reference (16: the issue's)")
    ap.add_argument("--scenes", default="", help="comma-separated indices into the scene list (default: all)")
    ap.add_argument("--sweep", action="store_true", help="the layer counts 1 to 256 instead of the stress scenes")
    ap.add_argument("--shading", default="", help="rast's --shading for every frame (default: the scenes' own, Lambert)")
    a = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="rast_transparency_")
    table = SWEEP if a.sweep else SCENES
    scenes = [table[int(i)] for i in a.scenes.split(",")] if a.scenes else table
    rows = []
    shading = ["--shading", a.shading] if a.shading else []
    for label, scene in scenes:
        common = [scene, "--size", a.size] + shading
        ref = os.path.join(tmp, "ref.pfm")
        run([a.rast, "render"] + common + ["--transparency", "exact", "--reference", "--reference-grid",
                                           a.reference_grid, "-o", ref])
        reference = read_pfm(ref)
        layers = next(int(kv[2:]) for kv in scene.split("?")[1].split("&") if kv.startswith("n="))
        exact = None
        opaque_scene = scene.split("?")[0] + "?n=0&" + "&".join(
            kv for kv in scene.split("?")[1].split("&") if not kv.startswith("n="))
        o = bench(a.rast, [opaque_scene, "--size", a.size, "--frames", a.frames] + shading, tmp)
        for m in METHODS:
            img = os.path.join(tmp, m + ".pfm")
            run([a.rast, "render"] + common + ["--transparency", m, "-o", img])
            film = read_pfm(img)
            if m == "exact":
                exact = film
            b = bench(a.rast, common + ["--transparency", m, "--frames", a.frames], tmp)
            ex_rmse, ex_max = errors(film, exact)
            ref_rmse, _ = errors(film, reference)
            rows.append({"scene": label, "method": m, "ms": b.get("total_median_ms"),
                         "opaque_ms": o.get("total_median_ms"), "rmse_vs_exact": ex_rmse, "max_vs_exact": ex_max,
                         "rmse_vs_reference": ref_rmse, "size": a.size, "backend": b.get("backend"),
                         "shading": a.shading or "lambert", "layers": layers})
            print(label, m, rows[-1]["ms"], f"{ex_rmse:.5f}", f"{ref_rmse:.5f}", flush=True)
    with open(a.out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


if __name__ == "__main__":
    main()

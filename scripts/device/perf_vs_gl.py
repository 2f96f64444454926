#!/usr/bin/env python3
"""rast against the hardware OpenGL rasterizer of the same GPU, side by side:
for every scene and size, glref (../shared/tools/glref) draws the scene through
EGL and prints its median ms/frame and camera; rast bench draws the same
triangles with the same camera and lighting with every raster method. Writes a
CSV and prints the ratio rast/hardware per scene (best method).

With --nvdiffrast, nvdiffrast's CUDA rasterizer (scripts/device/nvdiffrast_bench.py)
also draws the same triangles (exported by `rast export`) with the same camera,
raster only, in the same run: the three-way table of docs/performance.md.
--extra-camera NAME=SCENE:FLAGS adds a scene with a fixed camera (e.g. a view
from inside a dense model).

  python3 scripts/device/perf_vs_gl.py --rast R --glref G --models DIR --out F.csv [--sizes 1920x1080,...]
      [--nvdiffrast] [--extra-camera NAME=SCENE:--eye,x,y,z,--target,...]
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "measure"))
from csv_rows import write_rows  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--rast", required=True)
ap.add_argument("--glref", required=True)
ap.add_argument("--models", default="", help="folder of .glb models (auto camera)")
ap.add_argument("--stress", default="", help="folder with glref's gen_scenes.py output")
ap.add_argument("--sizes", default="1920x1080")
ap.add_argument("--frames", type=int, default=200)
ap.add_argument("--warmup", type=int, default=20)
ap.add_argument("--out", required=True)
ap.add_argument("--rast-label", default="rast")
ap.add_argument("--naive-max-pixels", type=int, default=2100000,
                help="bench the naive method only up to this many pixels (it takes seconds a frame on huge triangles)")
ap.add_argument("--nvdiffrast", action="store_true", help="also time nvdiffrast's CUDA rasterizer (raster only)")
ap.add_argument("--extra-camera", action="append", default=[],
                help="NAME=SCENE:FLAGS, FLAGS comma-separated (--eye,0,1,2,... is split at commas before a --)")
a = ap.parse_args()

nvdr = None
if a.nvdiffrast:
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from nvdiffrast_bench import Bench  # noqa: E402
    nvdr = Bench()

scenes = []  # (name, path, camera flags or None for auto)
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
for e in a.extra_camera:
    name, rest = e.split("=", 1)
    path, flags = rest.split(":", 1)
    toks, cam = flags.split(","), []
    for t in toks:  # "--eye,1,2,3,--fovy,45" -> ["--eye", "1,2,3", "--fovy", "45"]
        if t.startswith("--"):
            cam += [t, ""]
        else:
            cam[-1] = t if not cam[-1] else cam[-1] + "," + t
    scenes.append((name, path, cam))
scenes.append(("empty", None, None))  # rast's own frame-time floor (no glref run)

rows = []
for size in a.sizes.split(","):
    for name, path, cam in scenes:
        gl_ms, cam_flags = None, cam
        if path:
            cmd = [a.glref, path, "--size", size, "--frames", str(a.frames), "--warmup", str(a.warmup), "--no-ids"]
            cmd += cam if cam else ["--auto-camera"]
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
            out = r.stdout + r.stderr
            m = re.search(r"median_ms=([0-9.]+)", out)
            gl_ms = float(m.group(1)) if m else None
            cm = re.search(r"camera (?:\(auto\) )?(--eye .*)", out)
            if cm and not cam:
                cam_flags = cm.group(1).split()
            if gl_ms is None:
                print(f"glref failed on {name}: {out[-400:]}", file=sys.stderr)
        with tempfile.TemporaryDirectory() as tmp:
            js = os.path.join(tmp, "b.json")
            scene_arg = [path] if path else ["builtin:degenerate"]
            w, h = map(int, size.split("x"))
            methods = "naive,visbuffer,binned,auto" if w * h <= a.naive_max_pixels else "visbuffer,binned,auto"
            cmd = [a.rast, "bench"] + scene_arg + ["--size", size, "--frames", str(a.frames), "--warmup", str(a.warmup),
                                                   "--methods", methods, "--json", js] + (cam_flags or [])
            if not path:  # an empty frame: everything behind the camera
                cmd += ["--eye", "0,0,-5", "--target", "0,0,-10"]
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
            if r.returncode != 0:
                print(f"rast failed on {name}: {r.stderr.strip()}", file=sys.stderr)
                continue
            bench = json.load(open(js))
        # The best measured method; auto's run counts as a run of the method it
        # chose (above --naive-max-pixels it is the only run of naive).
        best = min(bench, key=lambda b: b["total_median_ms"])
        auto = [b for b in bench if b["requested"] == "auto"][0]
        row = {"scene": name, "size": size, "gl_median_ms": gl_ms, "best_method": best["method"],
               "best_ms": best["total_median_ms"], "auto_method": auto["method"], "auto_ms": auto["total_median_ms"],
               "triangles": best["triangles_in"], "backend": best["backend"], "rast": a.rast_label}
        for b in bench:
            if b["requested"] != "auto":
                row[b["method"] + "_ms"] = b["total_median_ms"]
                for st, v in b["stages_median_ms"].items():
                    row[f"{b['method']}_{st}_ms"] = v
        row["ratio_best_vs_gl"] = (best["total_median_ms"] / gl_ms) if gl_ms else None
        row["ratio_auto_vs_gl"] = (auto["total_median_ms"] / gl_ms) if gl_ms else None
        row["auto_vs_best"] = auto["total_median_ms"] / best["total_median_ms"]
        if nvdr and path and cam_flags:
            with tempfile.TemporaryDirectory() as tmp:
                glb = os.path.join(tmp, "scene.glb")
                r = subprocess.run([a.rast, "export", path, "-o", glb], capture_output=True, text=True, timeout=600)
                if r.returncode == 0:
                    nv = nvdr.time(glb, cam_flags, w, h, a.frames, a.warmup)
                    row["nvdiffrast_ms"] = nv["median_ms"]
                    row["nvdiffrast_covered"] = nv["covered_pixels"]
                    row["ratio_auto_vs_nvdiffrast"] = auto["total_median_ms"] / nv["median_ms"]
                    row["ratio_best_vs_nvdiffrast"] = best["total_median_ms"] / nv["median_ms"]
                else:
                    print(f"rast export failed on {name}: {r.stderr.strip()}", file=sys.stderr)
        rows.append(row)
        ratio = f"{row['ratio_best_vs_gl']:.3f}" if gl_ms else "-"
        print(f"{size:>10} {name:>12} tris={row['triangles']:>8} gl={gl_ms} rast_best={best['total_median_ms']:.4f}"
              f" ({best['method']}) auto={auto['method']} {auto['total_median_ms']:.4f} ratio={ratio}"
              + (f" nvdiffrast={row['nvdiffrast_ms']:.4f} auto/nvdr={row['ratio_auto_vs_nvdiffrast']:.3f}"
                 if "nvdiffrast_ms" in row else ""), flush=True)

write_rows(a.out, rows)

#!/usr/bin/env python3
"""rast's transparency against the hardware rasterizer's blending (issue #39,
docs/transparency.md "Against the hardware rasterizer's blending"): the same
glTF files (scripts/measure/blend_scenes.py: the stress layers and the
full-screen 8- and 64-layer cases of builtin:layers) drawn by glblend
(scripts/measure/glblend: OpenGL through EGL, opaque first, BLEND draws sorted
back to front by their centre and blended premultiplied into a float
framebuffer) and by rast with `--transparency exact` and `sorted`, with the
same camera and size. Per scene one CSV row: the median frame times, their
ratios to glblend's (its first --film), and the RMSE and largest difference
(linear light) between glblend's film, in each --film format, and rast's
(`rast render -o F.pfm`), sorted and exact, and the number of pixels that differ
by more than 0.01 (coverage or order, not rounding).

  python3 scripts/measure/blend_vs_gl.py --rast build/openmp/rast --glblend build/glblend/glblend \\
      --out docs/data/blend_vs_gl_openmp.csv [--size 1920x1080] [--frames 10] [--gl-frames 50]
      [--film rgba16f,rgba32f] [--repeats N]

Standard library only.
"""
import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile

here = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, here)
import blend_scenes  # noqa: E402
from csv_rows import write_rows  # noqa: E402
sys.path.insert(0, os.path.join(here, "..", "..", "tests", "support"))
import rastimg  # noqa: E402

# (label, file, transparent layers, camera flags or None: glblend's --auto-camera, given to rast too)
SCENES = [
    ("opaque (full screen)", "fullscreen_0.gltf", 0, blend_scenes.FULL_SCREEN_CAMERA),
    ("8 mixed, full screen", "fullscreen_8_mixed.gltf", 8, blend_scenes.FULL_SCREEN_CAMERA),
    ("64 alpha 0.1, full screen", "fullscreen_64_alpha0.1.gltf", 64, blend_scenes.FULL_SCREEN_CAMERA),
    ("8 parallel", "layers_parallel.gltf", 8, None),
    ("8 intersecting", "layers_intersecting.gltf", 8, None),
    ("6 coplanar", "layers_coplanar.gltf", 6, None),
]


def read_pfm(path):
    """(width, height, floats) of a PFM film (tests/support/rastimg.py reads it)."""
    w, h, _, data = rastimg.read_pfm(path)
    return w, h, data


def errors(a, b):
    if a[:2] != b[:2]:
        raise SystemExit(f"films of different sizes: {a[:2]} and {b[:2]}")
    d = [x - y for x, y in zip(a[2], b[2])]
    return math.sqrt(sum(v * v for v in d) / max(len(d), 1)), max((abs(v) for v in d), default=0.0)


def pixels_off(a, b, tol):
    """Pixels whose largest channel difference exceeds tol (RGB films)."""
    x, y = a[2], b[2]
    return sum(1 for i in range(0, len(x), 3)
               if max(abs(x[i] - y[i]), abs(x[i + 1] - y[i + 1]), abs(x[i + 2] - y[i + 2])) > tol)


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"FAILED ({r.returncode}): {' '.join(cmd)}: {r.stderr.strip()[-2000:]}")
    return r.stdout


def camera_flags(glblend_stdout):
    m = re.search(r"^glblend: camera(?: \(auto\))? (.*)$", glblend_stdout, re.M)
    if not m:
        raise SystemExit("glblend printed no camera line")
    return m.group(1).split()


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rast", required=True)
    ap.add_argument("--glblend", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--frames", default="10", help="rast bench frames")
    ap.add_argument("--warmup", default="2", help="rast bench warm-up frames")
    ap.add_argument("--gl-frames", default="50")
    ap.add_argument("--gl-warmup", default="5")
    ap.add_argument("--film", default="rgba16f,rgba32f",
                    help="glblend's framebuffers, comma-separated (rgba16f, rgba32f); the first is timed for the ratios")
    ap.add_argument("--scenes", default="", help="comma-separated indices into the scene list (default: all)")
    ap.add_argument("--repeats", type=int, default=1,
                    help="time each renderer this many times and keep the smallest median (a shared machine's noise)")
    ap.add_argument("--workdir", default="")
    ap.add_argument("--rast-flags", default="", help="extra flags for rast render and bench (space-separated)")
    a = ap.parse_args()
    tmp = a.workdir or tempfile.mkdtemp(prefix="rast_blend_vs_gl_")
    os.makedirs(tmp, exist_ok=True)
    run([sys.executable, os.path.join(here, "blend_scenes.py"), tmp, "--full-screen"])
    scenes = [SCENES[int(i)] for i in a.scenes.split(",")] if a.scenes else SCENES
    # Unlit BLEND materials: --shading pbr takes KHR_materials_unlit's path; no
    # anti-aliasing, no post-processing: the film is the composite.
    common = ["--size", a.size, "--shading", "pbr", "--aa", "none", "--tonemap", "none"] + a.rast_flags.split()
    rows = []
    films = a.film.split(",")
    for label, name, layers, cam in scenes:
        path = os.path.join(tmp, name)
        row = {"scene": label, "file": name, "layers": layers, "size": a.size}
        gl = {}
        for film in films:  # the first film's time is the one the ratios use
            gl_pfm, gl_json = os.path.join(tmp, f"gl_{film}.pfm"), os.path.join(tmp, "gl.json")
            times = []
            for _ in range(max(a.repeats, 1)):
                out = run([a.glblend, path, "--size", a.size, "--frames", a.gl_frames, "--warmup", a.gl_warmup,
                           "--film", film, "--out-pfm", gl_pfm, "--json", gl_json] + (cam if cam else ["--auto-camera"]))
                cam = camera_flags(out)
                with open(gl_json) as f:
                    gl[film] = json.load(f)
                times.append(gl[film]["total_median_ms"])
            row["glblend_ms" if film == films[0] else f"glblend_{film}_ms"] = min(times)
        for method in ("exact", "sorted"):
            img, bj = os.path.join(tmp, method + ".pfm"), os.path.join(tmp, method + ".json")
            flags = [path] + common + cam + ["--transparency", method]
            run([a.rast, "render"] + flags + ["-o", img])
            times = []
            for _ in range(max(a.repeats, 1)):
                run([a.rast, "bench"] + flags + ["--frames", a.frames, "--warmup", a.warmup, "--json", bj])
                with open(bj) as f:
                    b = json.load(f)
                b = b[0] if isinstance(b, list) else b
                times.append(b["total_median_ms"])
            film_rast = read_pfm(img)
            row[f"rast_{method}_ms"] = min(times)
            row[f"{method}_over_gl"] = min(times) / row["glblend_ms"]
            for film in films:
                gl_film = read_pfm(os.path.join(tmp, f"gl_{film}.pfm"))
                rmse, mx = errors(gl_film, film_rast)
                row[f"rmse_gl_{film}_vs_{method}"] = rmse
                row[f"max_gl_{film}_vs_{method}"] = mx
                # Off by more than half-float rounding: coverage or order, not arithmetic.
                row[f"px_off_gl_{film}_vs_{method}"] = pixels_off(gl_film, film_rast, 0.01)
            row["backend"] = b.get("backend")
        row["gl_renderer"] = gl[films[0]]["renderer"]
        rows.append(row)
        f0 = films[0]
        print(f"{label}: glblend ({f0}) {row['glblend_ms']:.3f} ms, rast exact {row['rast_exact_ms']:.3f} ms "
              f"({row['exact_over_gl']:.2f}x), sorted {row['rast_sorted_ms']:.3f} ms ({row['sorted_over_gl']:.2f}x); "
              + "; ".join(f"RMSE {f} vs sorted {row[f'rmse_gl_{f}_vs_sorted']:.2e} "
                          f"({row[f'px_off_gl_{f}_vs_sorted']} px off), vs exact {row[f'rmse_gl_{f}_vs_exact']:.2e} "
                          f"({row[f'px_off_gl_{f}_vs_exact']} px off)" for f in films), flush=True)
    write_rows(a.out, rows)


if __name__ == "__main__":
    main()

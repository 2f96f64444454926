#!/usr/bin/env python3
"""Window depth of rast and of OpenGL (glref, llvmpipe here) against the exact depth.

For every covered pixel, the exact depth is where the ray through the pixel
centre meets the plane of the triangle that renderer's id buffer names there,
in long double (tests/support/depth_reference.h, through build/.../tests/rast-depth-error).
The default view is the milk truck seen from inside the cab with the near plane
cutting through the body (issue #10); --slivers adds the two sliver scenes of
tests/pipeline/test_depth_precision.cpp (written by the test itself, RAST_DEPTH_SCENES).

Per renderer and scene: the largest and mean |depth - exact| over all covered
pixels, over the pixels of triangles the near plane cuts, and over the others.

  python3 scripts/measure/depth_error.py --rast build/openmp/rast \\
      [--tool build/openmp/tests/rast-depth-error] [--glref PATH | --shared ../shared] \\
      [--base-rast OLD/rast] [--slivers] [--size 960x540] [--model M.glb --camera "--eye ..."] \\
      [--out build/depth-error] [--json F]

--base-rast adds another rast binary (e.g. one built before a change) as a row.
Without --glref, glref is built from <shared>/tools/glref into <out>/glref-build;
when neither is available the OpenGL rows are left out (with a message).
Standard library only.
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TRUCK_CAMERA = "--eye 0.5,1.3,0.2 --target 3,1.0,0.5 --up 0,1,0 --fovy 45 --near 0.5 --far 807.250969"
SLIVER_CAMERA = "--eye 0,0,0 --target 0,0,-1 --up 0,1,0 --fovy 45 --near 0.1 --far 100"
LINE = re.compile(r"depth_error ids=(\S+) tris=(\S+) pixels=(\d+) max=(\S+) mean=(\S+) at=(\S+) id=(\d+)")

ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
ap.add_argument("--rast", default=os.path.join(REPO, "build", "openmp", "rast"))
ap.add_argument("--base-rast", default="", help="another rast binary to measure (e.g. before a change)")
ap.add_argument("--tool", default="", help="rast-depth-error (default: beside --rast, in tests/)")
ap.add_argument("--rast-tests", default="", help="rast_tests, to write the sliver scenes (default: beside --rast)")
ap.add_argument("--glref", default="", help="a built glref")
ap.add_argument("--shared", default=os.path.join(REPO, "..", "shared"))
ap.add_argument("--model", default="", help="default: <shared>/models/milktruck.glb")
ap.add_argument("--camera", default=TRUCK_CAMERA)
ap.add_argument("--size", default="960x540")
ap.add_argument("--slivers", action="store_true", help="also the sliver scenes of tests/pipeline/test_depth_precision.cpp")
ap.add_argument("--out", default=os.path.join(REPO, "build", "depth-error"))
ap.add_argument("--json", default="")
args = ap.parse_args()

bindir = os.path.dirname(os.path.abspath(args.rast))
tool = args.tool or os.path.join(bindir, "tests", "rast-depth-error")
rast_tests = args.rast_tests or os.path.join(bindir, "tests", "rast_tests")
for exe in (args.rast, tool):
    if not os.access(exe, os.X_OK):
        sys.exit(f"depth_error: error: {exe} is not an executable (build the rast and rast-depth-error targets)")
os.makedirs(args.out, exist_ok=True)
env = dict(os.environ)
env.setdefault("OMP_PROC_BIND", "false")


def run(cmd, **kw):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env, **kw)
    if r.returncode != 0:
        sys.exit(f"depth_error: error: {' '.join(cmd)} failed ({r.returncode}):\n{r.stdout[-2000:]}")
    return r.stdout


def find_glref():
    if args.glref:
        return args.glref
    src = os.path.join(args.shared, "tools", "glref")
    if not os.path.isdir(src) or not shutil.which("cmake"):
        print(f"(no glref: {src} is absent or cmake is missing; OpenGL rows left out)")
        return ""
    build = os.path.join(args.out, "glref-build")
    exe = os.path.join(build, "glref")
    if not os.access(exe, os.X_OK):
        run(["cmake", "-S", src, "-B", build, "-DCMAKE_BUILD_TYPE=Release"])
        run(["cmake", "--build", build, "--parallel", str(os.cpu_count() or 2)])
    return exe


def measure(scene, camera, size, tag):
    """Rows {renderer, tris, pixels, max, mean, at, id} for one scene."""
    cam = camera.split()
    w, h = size.split("x")
    pairs, names = [], []
    rasts = [("rast", args.rast)] + ([("rast (base)", args.base_rast)] if args.base_rast else [])
    for name, exe in rasts:
        stem = os.path.join(args.out, f"{tag}.{name.split()[-1].strip('()')}")
        run([exe, "render", scene, "-o", stem + ".png", "--size", size, *cam,
             "--aov", f"depth={stem}.depth.pfm,primid={stem}.ids.bin"])
        pairs += [stem + ".ids.bin", stem + ".depth.pfm"]
        names.append(name)
    if glref:
        stem = os.path.join(args.out, f"{tag}.glref")
        out = run([glref, scene, "--size", size, *cam, "--frames", "1", "--warmup", "0",
                   "--out-png", stem + ".png", "--out-ids", stem + ".ids.bin", "--out-depth", stem + ".depth.pfm"])
        m = re.search(r"renderer=(.*?) tris=", out)
        pairs += [stem + ".ids.bin", stem + ".depth.pfm"]
        names.append("OpenGL (" + (m.group(1) if m else "glref") + ")")
    rows = []
    for line in run([tool, scene, "--size", size, *cam, *pairs]).splitlines():
        m = LINE.match(line)
        if m:
            rows.append({"scene": tag, "renderer": names[pairs.index(m.group(1)) // 2], "tris": m.group(2),
                         "pixels": int(m.group(3)), "max": float(m.group(4)), "mean": float(m.group(5)),
                         "at": m.group(6), "id": int(m.group(7))})
    return rows


glref = find_glref()
rows = []
model = args.model or os.path.join(args.shared, "models", "milktruck.glb")
if os.path.isfile(model):
    rows += measure(model, args.camera, args.size, os.path.splitext(os.path.basename(model))[0])
else:
    print(f"(no {model}: the model row is left out)")
if args.slivers:
    if not os.access(rast_tests, os.X_OK):
        sys.exit(f"depth_error: error: {rast_tests} is not an executable (needed for --slivers)")
    env["RAST_DEPTH_SCENES"] = args.out
    run([rast_tests, "[depth]~[shared]"])
    del env["RAST_DEPTH_SCENES"]
    for s in ("slivers_crossing", "slivers_in_front"):
        rows += measure(os.path.join(args.out, s + ".glb"), SLIVER_CAMERA, "320x240", s)

print(f"\n| scene | renderer | triangles | pixels | max error | mean error | worst pixel (id) |")
print("|---|---|---|--:|--:|--:|---|")
for r in rows:
    if r["pixels"] == 0:
        continue
    print(f"| {r['scene']} | {r['renderer']} | {r['tris']} | {r['pixels']} | {r['max']:.3g} | {r['mean']:.3g} | "
          f"{r['at']} ({r['id']}) |")
if args.json:
    with open(args.json, "w") as f:
        json.dump(rows, f, indent=1)

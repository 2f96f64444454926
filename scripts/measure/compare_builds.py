#!/usr/bin/env python3
"""Two rast binaries (before and after a change) on the same scenes and flags:
ids and depth must be bit-identical, colours within a tolerance (1/255 by
default). Renders builtin scenes, the shared models (../shared/models), a few
of assimp's glTF test models and several shading modes, filters, AA and raster
methods; prints one line per case and exits non-zero on any difference.

  python3 scripts/measure/compare_builds.py --old OLD_RAST --new NEW_RAST [--size 480x270] [--tol 1]
"""
import argparse
import filecmp
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "support"))
from rastimg import read_png_rgba  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--old", required=True)
ap.add_argument("--new", required=True)
ap.add_argument("--size", default="480x270")
ap.add_argument("--tol", type=int, default=1, help="largest colour difference allowed, in 1/255")
ap.add_argument("--quick", action="store_true", help="fewer cases")
a = ap.parse_args()

root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
shared = os.path.join(root, "..", "shared", "models")
if not os.path.isdir(shared):
    shared = "/work/shared/models"
assimp = "/usr/share/assimp/models/glTF2"

scenes = ["builtin:default", "builtin:bigtri", "builtin:tiny?n=20000", "builtin:overdraw", "builtin:slivers",
          "builtin:nearplane", "builtin:zfight", "builtin:grid", "builtin:lines", "builtin:points"]
if os.path.isdir(shared):
    scenes += [os.path.join(shared, m) for m in sorted(os.listdir(shared)) if m.endswith(".glb")]
for m in ["BoxTextured-glTF/BoxTextured.gltf", "2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
          "BoxTexcoords-glTF/BoxTexcoords.gltf"]:
    if os.path.exists(os.path.join(assimp, m)):
        scenes.append(os.path.join(assimp, m))
variants = [[], ["--shading", "blinn-phong", "--light", "0.3,0.5,1,0.7", "--light", "-1,0.2,0.3,0.4"],
            ["--filter", "trilinear"], ["--filter", "nearest"], ["--shading", "normals"], ["--shading", "uv"],
            ["--shading", "depth"], ["--shading", "miplevel"], ["--aa", "msaa4"], ["--raster", "visbuffer"],
            ["--raster", "naive"], ["--cull", "back", "--background", "0.2,0.3,0.4"], ["--wireframe"],
            ["--interp", "affine"], ["--exposure", "0.5", "--tonemap", "aces"]]
if a.quick:
    variants = variants[:3]

tmp = tempfile.mkdtemp(prefix="rast_cmp_")
bad = 0
cases = 0
worst = 0
for sc in scenes:
    for v in variants:
        outs = []
        for tag, exe in (("old", a.old), ("new", a.new)):
            base = os.path.join(tmp, tag)
            # Lambert: what both builds shade alike (newer builds shade glTF files with pbr by default).
            cmd = [exe, "render", sc, "--size", a.size, "-o", base + ".png", "--shading", "lambert", "--aov",
                   f"depth={base}_d.pfm,primid={base}_id.bin"] + v
            r = subprocess.run(cmd, capture_output=True, text=True)
            outs.append((r.returncode, r.stderr.strip().splitlines()[-1:] if r.returncode else "", base))
        name = os.path.basename(sc) + " " + " ".join(v)
        if outs[0][0] != outs[1][0]:
            print(f"DIFF exit status {name}: {outs[0][:2]} vs {outs[1][:2]}")
            bad += 1
            continue
        if outs[0][0] != 0:
            continue  # both refuse these flags for this scene
        cases += 1
        o, n = outs[0][2], outs[1][2]
        same_ids = filecmp.cmp(o + "_id.bin", n + "_id.bin", shallow=False)
        same_depth = filecmp.cmp(o + "_d.pfm", n + "_d.pfm", shallow=False)
        diff = 0
        off = 0
        if not filecmp.cmp(o + ".png", n + ".png", shallow=False):
            _, _, ca = read_png_rgba(o + ".png")
            _, _, cb = read_png_rgba(n + ".png")
            for x, y in zip(ca, cb):
                d = abs(x - y)
                if d:
                    off += 1
                    diff = max(diff, d)
        worst = max(worst, diff)
        ok = same_ids and same_depth and diff <= a.tol
        bad += not ok
        print(f"{'ok  ' if ok else 'DIFF'} {name}: ids {'same' if same_ids else 'DIFFER'}, depth "
              f"{'same' if same_depth else 'DIFFER'}, colour max {diff}/255 in {off} channels")
print(f"{cases} cases, {bad} failing, largest colour difference {worst}/255")
sys.exit(1 if bad else 0)

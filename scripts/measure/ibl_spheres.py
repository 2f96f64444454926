#!/usr/bin/env python3
"""rast's image-based light against the Khronos glTF Sample Renderer's, alone.

Ten spheres (metal above, dielectric below, roughness 0, 0.25, .. 1 from left
to right, base colour (0.9, 0.6, 0.3)) lit by one environment only: the
reference renders a glTF file of them (written here, 96x48 segments a
sphere) with ../shared/tools/khronos-ref; rast's side is the hidden Catch2
case "[.ibl_spheres]" (tests/pipeline/test_environment.cpp), which ray casts
the same spheres and shades every hit with iblShade (pipeline/shade/
ibl_shading.h), so that the comparison measures the environment filtering
and the IBL maths and nothing else of the renderer. Both use tone map none
(the reference's: clamp, then the power 1/2.2). The agreement figures are
fidelity.py's (within3, within8, mae over the interior pixels).

  python3 scripts/measure/ibl_spheres.py --tests build/openmp/tests/rast_tests \\
      [--env ../shared/envs/chinese_garden_1k.hdr ...] [--out build/ibl-spheres]

Without --env: both shared environments. --show-env draws the environment
behind the spheres on both sides (the reference blurs it as rast's
envBackground does) and compares every pixel. Standard library only; the
reference's first filtering of an environment takes minutes on 2 cores.
"""
import argparse
import base64
import json
import math
import os
import struct
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
SHARED = os.path.join(os.path.dirname(REPO), "shared")
# The layout the Catch2 case ray casts (keep the two in step).
W, H, EYE_Z, FOVY, RADIUS = 640, 320, 9.0, 30.0, 0.5
BASE = (0.9, 0.6, 0.3)


def sphere_gltf(path):
    seg, rings = 96, 48
    pos, nrm, idx = [], [], []
    for j in range(rings + 1):
        th = math.pi * j / rings
        for i in range(seg + 1):
            ph = 2 * math.pi * i / seg
            n = (math.sin(th) * math.cos(ph), math.cos(th), math.sin(th) * math.sin(ph))
            nrm += n
            pos += [RADIUS * c for c in n]
    for j in range(rings):
        for i in range(seg):
            a, b = j * (seg + 1) + i, (j + 1) * (seg + 1) + i
            idx += [a, a + 1, b, a + 1, b + 1, b]  # counter-clockwise seen from outside
    pb = struct.pack("<%df" % len(pos), *pos)
    nb = struct.pack("<%df" % len(nrm), *nrm)
    ib = struct.pack("<%dI" % len(idx), *idx)
    blob = pb + nb + ib
    nv = len(pos) // 3
    doc = {
        "asset": {"version": "2.0", "generator": "rast scripts/measure/ibl_spheres.py"},
        "buffers": [{"byteLength": len(blob),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": len(pb), "target": 34962},
                        {"buffer": 0, "byteOffset": len(pb), "byteLength": len(nb), "target": 34962},
                        {"buffer": 0, "byteOffset": len(pb) + len(nb), "byteLength": len(ib), "target": 34963}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3",
                       "min": [-RADIUS] * 3, "max": [RADIUS] * 3},
                      {"bufferView": 1, "componentType": 5126, "count": nv, "type": "VEC3"},
                      {"bufferView": 2, "componentType": 5125, "count": len(idx), "type": "SCALAR"}],
        "materials": [], "meshes": [], "nodes": [], "scenes": [{"nodes": list(range(10))}], "scene": 0,
    }
    for s in range(10):
        doc["materials"].append({"pbrMetallicRoughness": {"baseColorFactor": list(BASE) + [1.0],
                                                          "metallicFactor": 1.0 if s < 5 else 0.0,
                                                          "roughnessFactor": (s % 5) * 0.25}})
        doc["meshes"].append({"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}, "indices": 2,
                                              "material": s}]})
        doc["nodes"].append({"mesh": s, "translation": [(s % 5 - 2) * 1.1, 0.55 if s < 5 else -0.55, 0.0]})
    with open(path, "w") as f:
        json.dump(doc, f)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--tests", required=True, help="the rast_tests executable")
    ap.add_argument("--env", nargs="*", default=None)
    ap.add_argument("--out", default=os.path.join(REPO, "build", "ibl-spheres"))
    ap.add_argument("--khronos-ref", default=os.path.join(SHARED, "tools", "khronos-ref"))
    ap.add_argument("--show-env", action="store_true", help="the environment as the background too (envBackground)")
    a = ap.parse_args()
    envs = a.env if a.env is not None else [os.path.join(SHARED, "envs", n) for n in
                                            ("chinese_garden_1k.hdr", "qwantani_afternoon_puresky_1k.hdr")]
    os.makedirs(a.out, exist_ok=True)
    scene = os.path.join(a.out, "spheres.gltf")
    sphere_gltf(scene)
    jobs, rows = [], []
    for env in envs:
        name = os.path.splitext(os.path.basename(env))[0]
        name += "_shown" if a.show_env else ""
        jobs.append({"scene": scene, "out": os.path.join(a.out, name + "_ref.png"), "size": "%dx%d" % (W, H),
                     "eye": "0,0,%g" % EYE_Z, "target": "0,0,0", "up": "0,1,0", "fovy": str(FOVY), "near": "1",
                     "far": "30", "env": env, "tonemap": "none"})
        if a.show_env:
            jobs[-1]["show-env"] = True
    batch = os.path.join(a.out, "jobs.jsonl")
    with open(batch, "w") as f:
        for j in jobs:
            f.write(json.dumps(j) + "\n")
    subprocess.run(["node", os.path.join(a.khronos_ref, "khronos_ref.mjs"), "--batch", batch], check=True)
    for env, j in zip(envs, jobs):
        mine = j["out"].replace("_ref.png", "_rast.png")
        subprocess.run([a.tests, "[.ibl_spheres]"], check=True,
                       env=dict(os.environ, RAST_IBL_ENV=env, RAST_IBL_OUT=mine, OMP_PROC_BIND="false",
                                RAST_IBL_SHOW_ENV="1" if a.show_env else "0"))
        # With the background shown, every pixel is covered: fidelity.py then
        # compares the whole image (its background colour matches nothing).
        r = subprocess.run([os.path.join(a.khronos_ref, "fidelity.py"), j["out"], mine, "--json"] +
                           (["--bg", "1,0,1"] if a.show_env else []), check=True,
                           capture_output=True, text=True)
        fig = json.loads(r.stdout)
        rows.append((os.path.basename(env), fig))
        print("%s: %s" % (os.path.basename(env), json.dumps(fig)))
    return 0


if __name__ == "__main__":
    sys.exit(main())

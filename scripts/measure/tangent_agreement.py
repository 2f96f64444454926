#!/usr/bin/python3
"""Agreement of rast's generated tangents (host/scene/tangents.h) with
MikkTSpace, the generator the Khronos glTF Sample Renderer runs where a file
has no TANGENT (issue #37 asks how rast's generation differs and by how much;
docs/gltf-support.md has the figures).

For each model: rast-tangent-dump (tests/tools) gives the tangents rast's
loader keeps, with their vertices; the same triangles, unwelded as the Sample
Renderer unwelds them, go through the Sample Renderer's own MikkTSpace build
(mikktspace.js and its WebAssembly, installed with ../shared/tools/khronos-ref
into ~/.cache/khronos-ref), whose w is negated as the renderer negates it.
Per triangle corner: the angle between the two tangents and whether the
handedness agrees.

  scripts/measure/tangent_agreement.py --dump build/openmp/tests/rast-tangent-dump MODEL...

--add-normal-map measures models that have no normal maps (a .glb copy whose
materials all name texture 0 as their normal texture: only the geometry and
coordinates matter here). Prints a Markdown table; --json FILE also writes
the figures.
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from pbr_fidelity import read_gltf, write_glb  # noqa: E402

LIBS = os.path.expanduser("~/.cache/khronos-ref/node_modules/@khronosgroup/gltf-viewer/dist/libs")

NODE = r"""
import fs from 'fs';
const libs = process.argv[2];
const m = await import(libs + '/mikktspace.js');
await m.default(fs.readFileSync(libs + '/mikktspace_bg.wasm'));
const prims = JSON.parse(fs.readFileSync(process.argv[3], 'utf8'));
const out = prims.map(p => Array.from(m.generateTangents(new Float32Array(p.positions),
    new Float32Array(p.normals), new Float32Array(p.uvs))));
fs.writeFileSync(process.argv[4], JSON.stringify(out));
"""


def percentile(sorted_values, q):
    if not sorted_values:
        return float("nan")
    k = min(len(sorted_values) - 1, max(0, int(round(q * (len(sorted_values) - 1)))))
    return sorted_values[k]


def measure(dump, model, work):
    rast = json.loads(subprocess.run([dump, model], check=True, capture_output=True, text=True).stdout)["prims"]
    soups = []
    for p in rast:
        pos, nrm, uv = [], [], []
        for i in p["indices"]:
            pos += p["positions"][3 * i:3 * i + 3]
            nrm += p["normals"][3 * i:3 * i + 3]
            uv += p["uvs"][2 * i:2 * i + 2]
        soups.append({"positions": pos, "normals": nrm, "uvs": uv})
    src, dst, script = (os.path.join(work, n) for n in ("in.json", "out.json", "mikk.mjs"))
    with open(src, "w") as f:
        json.dump(soups, f)
    with open(script, "w") as f:
        f.write(NODE)
    subprocess.run(["node", script, LIBS, src, dst], check=True)
    mikk = json.load(open(dst))
    angles, same_w, corners = [], 0, 0
    for p, m in zip(rast, mikk):
        for c, i in enumerate(p["indices"]):
            a = p["tangents"][4 * i:4 * i + 4]
            b = m[4 * c:4 * c + 4]
            b[3] = -b[3]  # the Sample Renderer's flip (glTF's v runs down the image)
            if a[3] == 0.0:
                continue  # no tangent (degenerate coordinates): the shader's per-triangle frame
            la = math.sqrt(sum(x * x for x in a[:3]))
            lb = math.sqrt(sum(x * x for x in b[:3]))
            if la == 0.0 or lb == 0.0:
                continue
            d = sum(x * y for x, y in zip(a[:3], b[:3])) / (la * lb)
            angles.append(math.degrees(math.acos(max(-1.0, min(1.0, d)))))
            same_w += (a[3] < 0) == (b[3] < 0)
            corners += 1
    angles.sort()
    return {
        "model": os.path.basename(model),
        "primitives": len(rast),
        "corners": corners,
        "median_deg": percentile(angles, 0.5),
        "p95_deg": percentile(angles, 0.95),
        "max_deg": angles[-1] if angles else float("nan"),
        "within_1deg": sum(x <= 1.0 for x in angles) / max(1, corners),
        "within_5deg": sum(x <= 5.0 for x in angles) / max(1, corners),
        "same_handedness": same_w / max(1, corners),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dump", required=True, help="rast-tangent-dump (tests/tools)")
    ap.add_argument("--json", help="also write the figures here")
    ap.add_argument("--add-normal-map", action="store_true", help="give every material a normal texture first")
    ap.add_argument("models", nargs="+")
    args = ap.parse_args()
    if not os.path.exists(os.path.join(LIBS, "mikktspace_bg.wasm")):
        print(f"skipped: no MikkTSpace build at {LIBS} (bash ../shared/tools/khronos-ref/setup.sh installs it)")
        return 0
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for model in args.models:
            if args.add_normal_map:
                doc, binary = read_gltf(model)
                if binary is None or not doc.get("textures"):
                    print(f"{model}: skipped (--add-normal-map takes a .glb with a texture)")
                    continue
                for m in doc.get("materials", []):
                    m.setdefault("normalTexture", {"index": 0})
                copy = os.path.join(work, os.path.basename(model))
                write_glb(copy, doc, binary)
                rows.append(measure(args.dump, copy, work))
            else:
                rows.append(measure(args.dump, model, work))
    print("| model | primitives | corners | median angle | 95th percentile | max | within 1 deg | within 5 deg | same handedness |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['model']} | {r['primitives']} | {r['corners']} | {r['median_deg']:.3f} | {r['p95_deg']:.3f} | "
              f"{r['max_deg']:.2f} | {r['within_1deg']:.3f} | {r['within_5deg']:.3f} | {r['same_handedness']:.3f} |")
    if args.json:
        with open(args.json, "w") as f:
            json.dump(rows, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())

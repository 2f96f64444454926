#!/usr/bin/python3
"""Side-by-side images of the glTF feature probes (docs/gltf-support.md,
"Feature probes"): for each probe a row of rast | the Khronos Sample Renderer
(its golden, tests/golden/probes/) | their difference (x4), rast's linear
output encoded with the reference's 2.2 curve, as the test compares them.

  python3 scripts/plot/plot_probes.py --rast build/openmp/rast -o docs/gltf_probes.png [PROBE...]
"""
import argparse
import os
import subprocess
import tempfile

import sys

import numpy as np
from PIL import Image, ImageDraw

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "tests", "support"))
from probe_files import probe_file, read_pfm  # noqa: E402  (probe-transform's file gets its KHR_texture_transform)
GOLDEN = os.path.normpath(os.path.join(HERE, "..", "..", "tests", "golden", "probes"))
FLAGS = ["--size", "200x150", "--aa", "none", "--env", "none", "--tonemap", "none", "--shading", "pbr"]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rast", required=True)
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("probes", nargs="*", default=["spheres", "normalmap", "mask", "lights"])
    a = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for p in a.probes:
            glb, pfm = os.path.join(tmp, p + ".glb"), os.path.join(tmp, p + ".pfm")
            subprocess.run([a.rast, "export", "builtin:probe-" + p, "-o", glb + ".export"], check=True, capture_output=True)
            probe_file(glb + ".export", p, glb)
            subprocess.run([a.rast, "render", glb, "--camera", "0", *FLAGS, "-o", pfm], check=True, capture_output=True)
            ours = (np.power(np.clip(read_pfm(pfm), 0, 1), 1 / 2.2) * 255 + 0.5).astype(np.uint8)
            ref = np.asarray(Image.open(os.path.join(GOLDEN, p + ".png")).convert("RGB"))
            diff = np.clip(np.abs(ours.astype(int) - ref.astype(int)) * 4, 0, 255).astype(np.uint8)
            rows.append(np.concatenate([ours, ref, diff], axis=1))
    img = Image.fromarray(np.concatenate(rows, axis=0))
    d = ImageDraw.Draw(img)
    for i, p in enumerate(a.probes):
        d.text((4, 150 * i + 2), p + ": rast", fill=(255, 255, 255))
        d.text((204, 150 * i + 2), "Khronos Sample Renderer", fill=(255, 255, 255))
        d.text((404, 150 * i + 2), "|difference| x 4", fill=(255, 255, 255))
    img.save(a.out, optimize=True)


if __name__ == "__main__":
    main()

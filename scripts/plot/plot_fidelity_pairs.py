#!/usr/bin/python3
"""Side-by-side images of whole models against the Khronos Sample Renderer
(docs/gltf-support.md, "Agreement with the Khronos Sample Renderer"): for
each model a row of the reference | rast | their difference (x4), from what
scripts/measure/pbr_fidelity.py left in its output folder (OUT/<name>.ref.png,
and rast's linear output encoded with the reference's 2.2 curve,
OUT/<name>.rast_g22.png, which is what its `gamma 2.2` columns compare). Why a
script of its own: the feature probes' pictures (plot_probes.py) render rast
themselves against committed goldens; the models' references are made by the
slow headless Sample Renderer, once, by pbr_fidelity.py.

  python3 scripts/plot/plot_fidelity_pairs.py OUT -o docs/gltf_models_vs_reference.png [NAME...]
"""
import argparse
import os

import numpy as np
from PIL import Image, ImageDraw


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("folder", help="pbr_fidelity.py's --out folder")
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--width", type=int, default=240, help="width of each picture in the montage")
    ap.add_argument("names", nargs="*", help="models (default: every NAME.ref.png with its NAME.rast_g22.png)")
    a = ap.parse_intermixed_args()
    names = a.names or sorted(f[:-len(".ref.png")] for f in os.listdir(a.folder)
                              if f.endswith(".ref.png") and
                              os.path.exists(os.path.join(a.folder, f[:-len(".ref.png")] + ".rast_g22.png")))
    if not names:
        raise SystemExit(f"plot_fidelity_pairs.py: no NAME.ref.png with NAME.rast_g22.png in {a.folder}")
    rows = []
    for n in names:
        ref = np.asarray(Image.open(os.path.join(a.folder, n + ".ref.png")).convert("RGB")).astype(np.int16)
        ours = np.asarray(Image.open(os.path.join(a.folder, n + ".rast_g22.png")).convert("RGB")).astype(np.int16)
        if ref.shape != ours.shape:
            raise SystemExit(f"plot_fidelity_pairs.py: {n}: sizes differ ({ref.shape} against {ours.shape})")
        diff = np.clip(np.abs(ref - ours) * 4, 0, 255)
        row = np.concatenate([ref, ours, diff], axis=1).astype(np.uint8)
        h = int(round(row.shape[0] * (3 * a.width) / row.shape[1]))
        img = Image.fromarray(row).resize((3 * a.width, h), Image.LANCZOS)
        ImageDraw.Draw(img).text((4, 4), n, fill=(255, 255, 0))
        rows.append(np.asarray(img))
    head = Image.new("RGB", (3 * a.width, 16), (0, 0, 0))
    d = ImageDraw.Draw(head)
    for k, t in enumerate(["Khronos Sample Renderer", "rast (2.2 curve)", "|difference| x 4"]):
        d.text((k * a.width + 4, 2), t, fill=(255, 255, 255))
    Image.fromarray(np.concatenate([np.asarray(head)] + rows, axis=0)).save(a.out, optimize=True)
    print(f"wrote {a.out} ({len(names)} models)")


if __name__ == "__main__":
    main()

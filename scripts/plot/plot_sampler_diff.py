#!/usr/bin/python3
"""Where rast and the Khronos Sample Renderer disagree on a textured model
(docs/gltf-support.md, "Agreement with the Khronos Sample Renderer": the
mipmap and anisotropy measurement of issue #37). For each NAME, a row of
the reference | rast (its linear output with the reference's 2.2 curve, as
pbr_fidelity.py compares them) | the reference dimmed, with the interior
pixels beyond 3/255 in yellow and beyond 8/255 in red; each row cropped to
what the two cover.

  scripts/measure/pbr_fidelity.py --rast build/openmp/rast --out F MODEL...
  scripts/plot/plot_sampler_diff.py F NAME... -o docs/gltf_sampler_diff.png [--scale 2]
"""
import argparse
import os
import sys

import numpy as np
from PIL import Image, ImageDraw

# The interior pixels as pbr_fidelity.py (and fidelity.py) count them.
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "measure"))
from pbr_fidelity import erode  # noqa: E402


def row(folder, name, scale):
    ref = np.asarray(Image.open(os.path.join(folder, name + ".ref.png")).convert("RGB")).astype(np.int32)
    ours = np.asarray(Image.open(os.path.join(folder, name + ".rast_g22.png")).convert("RGB")).astype(np.int32)
    cover = np.any(ref > 0, axis=2) | np.any(ours > 0, axis=2)
    inner = erode(np.any(ref > 0, axis=2) & np.any(ours > 0, axis=2))  # as fidelity.py counts
    d = np.abs(ref - ours).max(axis=2)
    marked = (ref * 0.45).astype(np.int32)
    marked[inner & (d > 3)] = (255, 210, 0)
    marked[inner & (d > 8)] = (255, 0, 0)
    ys, xs = np.where(cover)
    y0, y1, x0, x1 = max(ys.min() - 4, 0), ys.max() + 5, max(xs.min() - 4, 0), xs.max() + 5
    panels = [Image.fromarray(a[y0:y1, x0:x1].astype(np.uint8)) for a in (ref, ours, marked)]
    w, h = panels[0].size
    n = int(inner.sum())
    title = (f"{name}: reference | rast | beyond 3/255 (yellow), 8/255 (red): "
             f"{np.sum(inner & (d > 3)) / n:.1%}, {np.sum(inner & (d > 8)) / n:.1%}")
    # As wide as the title too (6 pixels a character in PIL's default font), so that it is not cut.
    out = Image.new("RGB", (max(3 * w * scale + 8, 6 * len(title) + 4), h * scale + 14), (40, 40, 40))
    for k, p in enumerate(panels):
        out.paste(p.resize((w * scale, h * scale), Image.NEAREST), (k * (w * scale + 4), 14))
    ImageDraw.Draw(out).text((2, 1), title, fill=(230, 230, 230))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("folder")
    ap.add_argument("names", nargs="+")
    ap.add_argument("-o", "--out", required=True)
    ap.add_argument("--scale", type=int, default=1)
    a = ap.parse_args()
    rows = [row(a.folder, n, a.scale) for n in a.names]
    out = Image.new("RGB", (max(r.size[0] for r in rows), sum(r.size[1] + 4 for r in rows)), (40, 40, 40))
    y = 0
    for r in rows:
        out.paste(r, (0, y))
        y += r.size[1] + 4
    out.save(a.out, optimize=True)


if __name__ == "__main__":
    main()

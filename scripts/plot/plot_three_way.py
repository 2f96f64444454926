#!/usr/bin/env python3
"""Chart of scripts/device/three_way.sh's CSV: rast's frame (auto) over the
hardware OpenGL rasterizer's and over nvdiffrast's raster-only time, per scene,
with the goals of docs/performance.md as lines.

  python3 scripts/plot/plot_three_way.py docs/data/three_way_h100.csv --out docs/performance_three_way.png [--size 1920x1080]
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("csv")
ap.add_argument("--out", required=True)
ap.add_argument("--size", default="1920x1080")
a = ap.parse_args()

rows = [r for r in csv.DictReader(open(a.csv)) if r["size"] == a.size and r.get("nvdiffrast_ms")]
names = [r["scene"] for r in rows]
vs_gl = [float(r["auto_ms"]) / float(r["gl_median_ms"]) for r in rows]
vs_nv = [float(r["auto_ms"]) / float(r["nvdiffrast_ms"]) for r in rows]
x = range(len(rows))
fig, ax = plt.subplots(figsize=(10, 4.2))
ax.bar([i - 0.2 for i in x], vs_gl, 0.4, label="rast auto / hardware OpenGL (glref, EGL)")
ax.bar([i + 0.2 for i in x], vs_nv, 0.4, label="rast auto / nvdiffrast CUDA raster only")
ax.axhline(0.2, color="C0", ls="--", lw=1, label="goal vs OpenGL: 0.2")
ax.axhline(0.7, color="C1", ls="--", lw=1, label="goal vs nvdiffrast: 0.7")
ax.axhline(1.0, color="gray", lw=0.8)
ax.set_xticks(list(x))
ax.set_xticklabels(names, rotation=30, ha="right")
ax.set_ylabel("time ratio (lower is better)")
ax.set_title(f"H100, {a.size}: rast's whole frame against two GPU rasterizers")
ax.legend(fontsize=8, loc="upper left")
fig.tight_layout()
fig.savefig(a.out, dpi=110)
print(f"wrote {a.out}")

#!/usr/bin/env python3
"""Charts of the post-processing passes (docs/post.md):

  left:  SSAO error (RMSE of AO against rast's ray-traced reference) versus the
         SSAO pass's time, one line per scene, one point per sample count;
  right: per-pass median time at 1920x1080 from `rast bench --csv` files
         (one group of bars per file, e.g. OpenMP here and CUDA on the H100).

usage: plot_post.py --ssao a.csv [b.csv ...] --bench openmp.csv [h100.csv ...] --out docs/post_ssao.png
Needs matplotlib (Debian's /usr/bin/python3 has it)."""
import argparse
import csv
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PASSES = ["ssao", "exposure", "bloom", "tonemap", "encode"]

ap = argparse.ArgumentParser()
ap.add_argument("--ssao", nargs="+", required=True)
ap.add_argument("--bench", nargs="*", default=[])
ap.add_argument("--out", required=True)
a = ap.parse_args()

def tag(f, files):
    # With several files (e.g. before/after a change), each label says which.
    return f" [{os.path.splitext(os.path.basename(f))[0]}]" if len(files) > 1 else ""


rows = []
for f in a.ssao:
    with open(f) as fh:
        for r in csv.DictReader(fh):
            r["scene"] = os.path.basename(r["scene"]) + tag(f, a.ssao)
            rows.append(r)
fig, axes = plt.subplots(1, 2 if a.bench else 1, figsize=(12 if a.bench else 6.5, 4.5))
ax = axes[0] if a.bench else axes
for scene in dict.fromkeys(r["scene"] for r in rows):
    rs = [r for r in rows if r["scene"] == scene]
    xs = [float(r["ssao_median_ms"]) for r in rs]
    ys = [float(r["rmse"]) for r in rs]
    ax.plot(xs, ys, "o-", label=scene)
    for r, x, y in zip(rs, xs, ys):
        ax.annotate(r["samples"], (x, y), textcoords="offset points", xytext=(3, 3), fontsize=7)
r0 = rows[0]
ax.set_xscale("log")
ax.set_yscale("log")
ax.set_xlabel(f"SSAO pass, ms at {r0['width']}x{r0['height']} ({r0['backend']})")
ax.set_ylabel(f"AO RMSE vs ray-traced ({r0['reference_rays']} rays/pixel, {r0['error_width']}x{r0['error_height']})")
ax.set_title("SSAO: error against time (labels: samples per pixel)")
ax.grid(True, which="both", alpha=0.3)
ax.legend(fontsize=8)

if a.bench:
    ax = axes[1]
    groups = []
    for f in a.bench:
        with open(f) as fh:
            for r in csv.DictReader(fh):
                groups.append((f"{r['backend']} {os.path.basename(r['scene'])} {r['width']}x{r['height']}{tag(f, a.bench)}",
                               [float(r.get(p + "_median_ms") or 0.0) for p in PASSES]))
    width = 0.8 / max(1, len(groups))
    for g, (label, vals) in enumerate(groups):
        ax.bar([i + g * width for i in range(len(PASSES))], vals, width, label=label)
    ax.set_xticks([i + 0.4 - width / 2 for i in range(len(PASSES))])
    ax.set_xticklabels(PASSES)
    ax.set_yscale("log")
    ax.set_ylabel("median ms per frame")
    ax.set_title("post passes per frame (rast bench)")
    ax.grid(True, axis="y", which="both", alpha=0.3)
    ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(a.out, dpi=110)
print(f"wrote {a.out}")

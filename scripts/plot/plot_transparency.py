#!/usr/bin/env python3
"""Chart of scripts/measure/bench_transparency.py's rows (docs/transparency.md):
for each transparency method, its error in linear light (RMSE against `exact`,
and against the supersampled exact reference) versus its frame time as a
multiple of the opaque frame, one point per stress scene.

  /usr/bin/python3 scripts/plot/plot_transparency.py docs/data/transparency_openmp.csv --out docs/transparency_openmp.png
"""
import argparse
import csv

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("csv")
ap.add_argument("--out", required=True)
ap.add_argument("--note", default="", help="a line under the title (e.g. how loaded the machine was)")
a = ap.parse_args()
rows = list(csv.DictReader(open(a.csv)))
markers = {"exact": "o", "kbuffer": "s", "weighted": "^", "sorted": "D"}
fig, axes = plt.subplots(1, 2, figsize=(12, 5), sharex=True)
for ax, col, title in [(axes[0], "rmse_vs_exact", "error against exact"),
                       (axes[1], "rmse_vs_reference", "error against the supersampled exact reference")]:
    for m, mk in markers.items():
        pts = [(float(r["ms"]) / float(r["opaque_ms"]), max(float(r[col]), 1e-7), r["scene"]) for r in rows
               if r["method"] == m and r["opaque_ms"] and float(r["opaque_ms"]) > 0]
        if not pts:
            continue
        ax.scatter([p[0] for p in pts], [p[1] for p in pts], marker=mk, label=m)
        for x, y, s in pts:
            ax.annotate(s, (x, y), fontsize=6, alpha=0.6)
    ax.set_yscale("log")
    ax.set_xscale("log")
    ax.set_xlabel("frame time / opaque frame time")
    ax.set_ylabel("RMSE, linear light (1e-7: exact)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend()
b = rows[0]
fig.suptitle(f"transparency methods, {b['size']}, {b['backend']}" + (f"\n{a.note}" if a.note else ""))
fig.tight_layout()
fig.savefig(a.out, dpi=110)

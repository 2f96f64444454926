#!/usr/bin/env python3
"""Chart of `scripts/measure/bench_transparency.py --sweep` (docs/transparency.md,
"Error against cost"): for each transparency method, how its frame time (as a
multiple of the opaque frame) and its error in linear light (RMSE against the
supersampled exact reference) grow with the number of full-frame layers, 1 to
256, for layers of one alpha and of mixed alphas and hues. The stress-scene
chart (plot_transparency.py) puts error against cost; this one puts both
against depth, where the methods part ways.

  /usr/bin/python3 scripts/plot/plot_transparency_layers.py docs/data/transparency_h200_layers.csv \\
      --out docs/transparency_h200_layers.png
"""
import argparse
import csv

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("csv")
ap.add_argument("--out", required=True)
ap.add_argument("--note", default="", help="a line under the title (e.g. the build and machine)")
a = ap.parse_args()
rows = [r for r in csv.DictReader(open(a.csv)) if r.get("layers")]
if not rows:
    raise SystemExit(f"{a.csv}: no rows with a layers column (bench_transparency.py --sweep writes them)")
markers = {"exact": "o", "kbuffer": "s", "weighted": "^", "sorted": "D"}
# The sweep's two kinds of layers, named by the scene label before " xN".
kinds = sorted({r["scene"].rsplit(" x", 1)[0] for r in rows})
fig, axes = plt.subplots(2, len(kinds), figsize=(6 * len(kinds), 9), sharex=True, squeeze=False)
for col, kind in enumerate(kinds):
    mine = [r for r in rows if r["scene"].rsplit(" x", 1)[0] == kind]
    for m, mk in markers.items():
        pts = sorted((int(r["layers"]), float(r["ms"]) / float(r["opaque_ms"]), max(float(r["rmse_vs_reference"]), 1e-7))
                     for r in mine if r["method"] == m and float(r["opaque_ms"]) > 0)
        if not pts:
            continue
        axes[0][col].plot([p[0] for p in pts], [p[1] for p in pts], marker=mk, label=m)
        axes[1][col].plot([p[0] for p in pts], [p[2] for p in pts], marker=mk, label=m)
    axes[0][col].set_title(kind)
    axes[0][col].set_ylabel("frame time / opaque frame time")
    axes[1][col].set_ylabel("RMSE against the supersampled exact reference\n(linear light; 1e-7: exact)")
    axes[1][col].set_xlabel("layers")
    for ax in (axes[0][col], axes[1][col]):
        ax.set_xscale("log", base=2)
        ax.set_yscale("log")
        ax.grid(alpha=0.3, which="both")
        ax.legend()
    # Errors at float rounding's level stay at the bottom, not spread over the panel.
    axes[1][col].set_ylim(5e-8, max(1e-5, axes[1][col].get_ylim()[1]))
b = rows[0]
fig.suptitle(f"transparency methods by depth, {b['size']}, {b['backend']}, shading {b.get('shading', '')}" +
             (f"\n{a.note}" if a.note else ""))
fig.tight_layout()
fig.savefig(a.out, dpi=110)

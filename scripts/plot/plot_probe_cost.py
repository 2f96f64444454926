#!/usr/bin/python3
"""The chart of error against cost per glTF feature (docs/gltf-support.md,
"Feature probes") from scripts/measure/probe_cost.py's CSV: for each property
a probe shows, its cost (rast's instructions per frame with it, minus with the
file that lacks it, in percent of the frame) against the share of the probe's
interior pixels beyond 3/255 of the Khronos Sample Renderer, with the property
(filled) and without it (open), joined by a line: what honouring the feature
costs, and what ignoring it would cost in error.

  python3 scripts/plot/plot_probe_cost.py docs/data/probe_cost.csv -o docs/gltf_probe_cost.png
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("-o", "--out", required=True)
    a = ap.parse_args()
    rows = list(csv.DictReader(open(a.csv)))
    full = {r["probe"]: r for r in rows if r["without"] == "(all)"}
    fig, ax = plt.subplots(figsize=(9, 6))
    cmap = plt.get_cmap("tab10")
    probes = list(full)
    floor = 1e-4  # a probe with every pixel within 3/255 is drawn here (log scale)
    for r in rows:
        if r["without"] == "(all)":
            continue
        f = full[r["probe"]]
        cost = 100.0 * int(r["feature_cost"]) / float(f["frame_instructions"])
        e_with = max(1.0 - float(f["within3"]), floor)
        e_without = max(1.0 - float(r["within3"]), floor)
        c = cmap(probes.index(r["probe"]) % 10)
        ax.plot([cost, cost], [e_with, e_without], color=c, lw=1, alpha=0.6)
        ax.scatter([cost], [e_with], color=c, s=30, zorder=3)
        ax.scatter([cost], [e_without], facecolors="none", edgecolors=c, s=30, zorder=3)
        ax.annotate(r["without"].split(" (")[0], (cost, e_without), fontsize=7, xytext=(4, 2),
                    textcoords="offset points", color=c)
    for p in probes:
        ax.scatter([], [], color=cmap(probes.index(p) % 10), label="probe-" + p)
    ax.set_yscale("log")
    ax.set_ylim(floor / 2, 1.5)
    ax.set_xscale("symlog", linthresh=0.5)
    ax.set_xlim(-3, 150)
    ax.set_xlabel("cost: rast's instructions per frame with the property minus without it, % of the frame "
                  "(callgrind, 1 thread, 200x150)", fontsize=8)
    ax.set_ylabel("share of interior pixels beyond 3/255 of the reference\n(filled: rast with the property; "
                  "open: without it)", fontsize=8)
    ax.set_title("glTF feature probes: error against cost per property (OpenMP, this VM)", fontsize=10)
    ax.axhline(0.05, color="grey", lw=0.8, ls="--")
    ax.text(ax.get_xlim()[0], 0.055, " issue #37's bar: 95% within 3/255", fontsize=7, color="grey")
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(True, which="major", alpha=0.3)
    fig.tight_layout()
    fig.savefig(a.out, dpi=100)


if __name__ == "__main__":
    main()

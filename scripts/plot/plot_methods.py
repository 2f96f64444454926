#!/usr/bin/python3
"""Charts of scripts/measure/bench_methods.py's CSV (Debian's matplotlib):
  <prefix>_scenes.png  median frame time per raster method on each scene (log scale)
  <prefix>_sweep.png   median raster-stage and frame time versus on-screen triangle size

  python3 scripts/plot/plot_methods.py docs/data/methods_openmp.csv --prefix docs/methods_openmp
"""
import argparse
import csv
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

METHODS = ["naive", "visbuffer", "binned"]
COLORS = {"naive": "#d62728", "visbuffer": "#1f77b4", "binned": "#2ca02c"}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv")
    ap.add_argument("--prefix", required=True)
    ap.add_argument("--title", default="")
    a = ap.parse_args()
    rows = list(csv.DictReader(open(a.csv)))
    backend = rows[0]["backend"] if rows else "?"
    size = f"{rows[0]['width']}x{rows[0]['height']}" if rows else "?"
    title = a.title or f"{backend}, {size}"

    # Per scene: one bar per method, and which method auto picked.
    scenes, times, auto = [], defaultdict(dict), {}
    for r in rows:
        if r["kind"] != "scene":
            continue
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
        if r["requested"] == "auto":
            auto[r["scene"]] = r["method"]
        else:
            times[r["scene"]][r["method"]] = float(r["total_median_ms"])
    fig, ax = plt.subplots(figsize=(12, 5))
    w = 0.8 / len(METHODS)
    for k, m in enumerate(METHODS):
        xs = [i + (k - 1) * w for i in range(len(scenes))]
        ys = [times[s].get(m, float("nan")) for s in scenes]
        ax.bar(xs, ys, w, label=m, color=COLORS[m])
    for i, s in enumerate(scenes):
        if s in auto and auto[s] in times[s]:
            k = METHODS.index(auto[s])
            ax.text(i + (k - 1) * w, times[s][auto[s]], "auto", ha="center", va="bottom", fontsize=7, rotation=90)
    ax.set_yscale("log")
    ax.set_ylabel("median frame time (ms, log)")
    ax.set_xticks(range(len(scenes)))
    ax.set_xticklabels([s.replace("builtin:", "") for s in scenes], rotation=30, ha="right", fontsize=8)
    ax.set_title(f"Raster methods per scene ({title})")
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0))
    fig.tight_layout()
    fig.savefig(a.prefix + "_scenes.png", dpi=110)

    # Sweep: time versus triangle size.
    sweep = defaultdict(list)
    for r in rows:
        if r["kind"] == "sweep" and r["requested"] != "auto":
            sweep[r["method"]].append((float(r["tri_px"]), float(r["raster_median_ms"]), float(r["total_median_ms"])))
    fig, ax = plt.subplots(figsize=(8, 5))
    for m in METHODS:
        pts = sorted(sweep.get(m, []))
        if pts:
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", color=COLORS[m], label=f"{m} raster stage")
            ax.plot([p[0] for p in pts], [p[2] for p in pts], "--", color=COLORS[m], alpha=0.5, label=f"{m} frame")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("triangle leg on screen (pixels, log)")
    ax.set_ylabel("median time (ms, log)")
    ax.set_title(f"One 8192-triangle mesh from tiny to huge ({title})")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.prefix + "_sweep.png", dpi=110)
    print(f"wrote {a.prefix}_scenes.png and {a.prefix}_sweep.png")


if __name__ == "__main__":
    main()

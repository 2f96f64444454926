#!/usr/bin/python3
"""Quality against cost from scripts/measure/quality_sweep.py's CSV: one subplot per
scene, x = median frame time (ms, log scale), y = error against the reference,
one labelled point per configuration (aa/filter[/method]), and the Pareto front
(the lowest error reachable within at most that frame time) as a step line.

  /usr/bin/python3 scripts/plot/plot_quality.py docs/data/quality_openmp.csv -o docs/quality_openmp.png [--metric ssim|rmse|edge_rmse|frac_gt1|frac_gt8]

Rows without error values (no reference) are left out. Rows measured against a
FAKE reference are plotted, and the figure title says so.
(Debian's /usr/bin/python3 has matplotlib.)
"""
import argparse
import csv
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

METRICS = {
    "ssim": ("1 - SSIM (luma)", lambda r: 1.0 - float(r["ssim"]), "ssim"),
    "rmse": ("RMSE, linear light", lambda r: float(r["rmse_linear"]), "rmse_linear"),
    "edge_rmse": ("RMSE on edge pixels, linear light", lambda r: float(r["edge_rmse"]), "edge_rmse"),
    "frac_gt1": ("fraction of pixels off by > 1/255", lambda r: float(r["frac_gt1"]), "frac_gt1"),
    "frac_gt8": ("fraction of pixels off by > 8/255", lambda r: float(r["frac_gt8"]), "frac_gt8"),
}


def pareto(points):
    """points: (ms, err, ...). Those with lower error than every point at most
    as fast, in order of time."""
    front, best = [], math.inf
    for p in sorted(points, key=lambda p: (p[0], p[1])):
        if p[1] < best:
            front.append(p)
            best = p[1]
    return front


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("csv", help="CSV from scripts/measure/quality_sweep.py")
    ap.add_argument("-o", "--out", default="quality.png", help="PNG to write")
    ap.add_argument("--metric", choices=sorted(METRICS), default="ssim")
    ap.add_argument("--logy", action="store_true", help="symmetric-log error axis")
    ap.add_argument("--time", choices=["median", "min"], default="median",
                    help="frame time column: ms (median) or ms_min (fastest frame; steadier on a busy machine)")
    a = ap.parse_args()
    ylabel, err, col = METRICS[a.metric]
    tcol = "ms" if a.time == "median" else "ms_min"

    with open(a.csv, newline="") as f:
        rows = [r for r in csv.DictReader(f) if r.get(col, "") not in ("", None) and r.get(tcol, "")]
    if not rows:
        raise SystemExit(f"plot_quality: no rows with both '{col}' and '{tcol}' in {a.csv} (was there a reference?)")
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    several_methods = len({r["method"] for r in rows}) > 1
    fake = any(r.get("reference", "").startswith("FAKE") for r in rows)

    n = len(scenes)
    cols = min(n, 3)
    nrows = (n + cols - 1) // cols
    fig, axes = plt.subplots(nrows, cols, figsize=(5.5 * cols, 4.2 * nrows), squeeze=False)
    for i, scene in enumerate(scenes):
        ax = axes[i // cols][i % cols]
        pts = []
        for r in rows:
            if r["scene"] != scene:
                continue
            label = f"{r['aa']}/{r['filter']}" + (f"/{r['method']}" if several_methods else "")
            pts.append((float(r[tcol]), err(r), label))
        front = pareto(pts)
        on_front = {id(p) for p in front}
        for p in pts:
            ax.scatter(p[0], p[1], s=22, color="tab:red" if id(p) in on_front else "tab:blue", zorder=3)
            ax.annotate(p[2], (p[0], p[1]), textcoords="offset points", xytext=(4, 3), fontsize=7)
        if front:
            xs = [p[0] for p in front] + [max(p[0] for p in pts)]
            ys = [p[1] for p in front] + [front[-1][1]]
            ax.step(xs, ys, where="post", color="tab:red", lw=1.2, label="Pareto front", zorder=2)
            ax.legend(fontsize=7, loc="upper right")
        ax.set_xscale("log")
        if a.logy:
            ax.set_yscale("symlog", linthresh=max(1e-6, min((p[1] for p in pts if p[1] > 0), default=1e-6)))
        ax.set_title(scene, fontsize=10)
        ax.set_xlabel(f"{a.time} frame time (ms)")
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
    for j in range(n, nrows * cols):
        axes[j // cols][j % cols].axis("off")
    sizes = sorted({r.get("size", "") for r in rows} - {""})
    title = f"error against the reference vs frame time ({', '.join(sizes)})"
    if fake:
        title += "\nFAKE reference (bilinear no-AA render): pipeline test only"
    fig.suptitle(title, fontsize=11, color="tab:red" if fake else "black")
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print(f"plot_quality: wrote {a.out} ({len(rows)} points, {n} scenes, metric {a.metric})")


if __name__ == "__main__":
    main()

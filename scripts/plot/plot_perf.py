#!/usr/bin/python3
"""Chart of scripts/device/perf_vs_gl.py's CSVs (Debian's matplotlib): per image
size, the median frame time of each scene for the GPU run (rast on CUDA and the
hardware OpenGL rasterizer of the same GPU) and the CPU run (rast on OpenMP and
Mesa's llvmpipe on the same cores), log scale. Each rast bar is its best
measured raster method.

  python3 scripts/plot/plot_perf.py --gpu docs/data/perf_h100.csv --cpu docs/data/perf_openmp.csv \
      --out docs/performance.png [--table tables.md]

--table also writes the figures as Markdown tables, one per size.
"""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def load(path):
    rows = {}
    for r in csv.DictReader(open(path)):
        rows[(r["size"], r["scene"])] = r
    return rows


def num(x):
    try:
        return float(x)
    except (TypeError, ValueError):
        return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--gpu", required=True, help="perf_vs_gl.py CSV of the GPU run")
    ap.add_argument("--cpu", required=True, help="perf_vs_gl.py CSV of the CPU run")
    ap.add_argument("--gpu-label", default="H100")
    ap.add_argument("--cpu-label", default="2 CPU cores")
    ap.add_argument("--out", required=True)
    ap.add_argument("--table", help="also write Markdown tables to this file")
    a = ap.parse_args()
    gpu, cpu = load(a.gpu), load(a.cpu)
    sizes = []
    for s, _ in list(gpu) + list(cpu):
        if s not in sizes:
            sizes.append(s)
    sizes.sort(key=lambda s: int(s.split("x")[0]) * int(s.split("x")[1]))
    series = [  # (label, table, column, colour)
        (f"OpenGL hardware ({a.gpu_label})", gpu, "gl_median_ms", "#7f7f7f"),
        (f"rast CUDA ({a.gpu_label})", gpu, "best_ms", "#1f77b4"),
        (f"llvmpipe ({a.cpu_label})", cpu, "gl_median_ms", "#ff7f0e"),
        (f"rast OpenMP ({a.cpu_label})", cpu, "best_ms", "#2ca02c"),
    ]
    fig, axes = plt.subplots(len(sizes), 1, figsize=(11, 3.4 * len(sizes)), squeeze=False)
    for ax, size in zip(axes[:, 0], sizes):
        scenes = []
        for t in (gpu, cpu):
            for s, sc in t:
                if s == size and sc not in scenes:
                    scenes.append(sc)
        width = 0.8 / len(series)
        for k, (label, table, col, colour) in enumerate(series):
            xs, ys = [], []
            for i, sc in enumerate(scenes):
                v = num(table.get((size, sc), {}).get(col))
                if v:
                    xs.append(i + (k - (len(series) - 1) / 2) * width)
                    ys.append(v)
            ax.bar(xs, ys, width, label=label, color=colour)
        ax.set_yscale("log")
        ax.set_xticks(range(len(scenes)))
        ax.set_xticklabels(scenes)
        ax.set_ylabel("ms per frame (median)")
        ax.set_title(size)
        ax.grid(axis="y", which="both", alpha=0.3)
    axes[0, 0].legend(ncol=2, fontsize=8)
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)
    print(f"plot_perf.py: wrote {a.out}")
    if a.table:
        write_tables(a, sizes, gpu, cpu)


def fmt(v, digits=3):
    return "-" if v is None else f"{v:.{digits}f}"


def write_tables(a, sizes, gpu, cpu):
    out = []
    for size in sizes:
        out.append(f"### {size}\n")
        out.append(f"| scene | triangles | GL {a.gpu_label} (ms) | rast CUDA best (ms) | method | ratio | auto picks (ms) "
                   f"| llvmpipe (ms) | rast OpenMP best (ms) | method | ratio |")
        out.append("|---|---:|---:|---:|---|---:|---|---:|---:|---|---:|")
        scenes = []
        for t in (gpu, cpu):
            for s, sc in t:
                if s == size and sc not in scenes:
                    scenes.append(sc)
        for sc in scenes:
            g, c = gpu.get((size, sc), {}), cpu.get((size, sc), {})
            gl, gb = num(g.get("gl_median_ms")), num(g.get("best_ms"))
            ll, cb = num(c.get("gl_median_ms")), num(c.get("best_ms"))
            auto = f"{g.get('auto_method', '-')} ({fmt(num(g.get('auto_ms')))})" if g else "-"
            out.append(f"| {sc} | {g.get('triangles') or c.get('triangles', '-')} | {fmt(gl, 4)} | {fmt(gb)} "
                       f"| {g.get('best_method', '-')} | {fmt(gb / gl if gl and gb else None)} | {auto} "
                       f"| {fmt(ll, 1)} | {fmt(cb, 1)} | {c.get('best_method', '-')} "
                       f"| {fmt(cb / ll if ll and cb else None, 2)} |")
        out.append("")
    open(a.table, "w").write("\n".join(out))
    print(f"plot_perf.py: wrote {a.table}")


if __name__ == "__main__":
    main()

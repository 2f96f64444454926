#!/usr/bin/python3
"""Error against cost per glTF feature (docs/gltf-support.md, "Feature
probes"; chart by scripts/plot/plot_probe_cost.py): for each feature probe and
each of its controls (the file with one property removed,
tests/support/probe_files.py), rast's agreement with the probe's golden (the
Khronos Sample Renderer's image; gamma-2.2 encoding, interior pixels, as
tests/cli/cli_probe_goldens.py measures it) and the instructions of one frame
(callgrind, OMP_NUM_THREADS=1: a `rast bench` of 9 frames minus one of 1,
divided by 8, so that loading and set-up cancel). A feature's cost is the
probe's instructions minus its control's; its error is the probe's share of
pixels beyond 3/255, against the control's (what ignoring the feature costs).

  scripts/measure/probe_cost.py --rast build/openmp/rast --csv docs/data/probe_cost.csv [--work /tmp/probe_cost]
"""
import argparse
import csv
import json
import os
import subprocess
import sys

import numpy as np
from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "tests", "support"))
from probe_files import CONTROLS, probe_file, read_glb, read_pfm, write_glb  # noqa: E402

FLAGS = ["--camera", "0", "--size", "200x150", "--aa", "none", "--env", "none", "--tonemap", "none", "--shading", "pbr"]


def agreement(golden, pfm):
    ref = np.asarray(Image.open(golden).convert("RGB")).astype(int)
    test = (np.power(np.clip(read_pfm(pfm), 0, 1), 1 / 2.2) * 255 + 0.5).astype(int)
    both = ref.any(axis=2) & test.any(axis=2)
    inner = both.copy()
    inner[1:, :] &= both[:-1, :]; inner[:-1, :] &= both[1:, :]; inner[:, 1:] &= both[:, :-1]; inner[:, :-1] &= both[:, 1:]
    inner[0, :] = inner[-1, :] = False; inner[:, 0] = inner[:, -1] = False
    d = np.abs(ref - test)[inner]
    worst = d.max(axis=1)
    return float(np.mean(worst <= 3)), float(np.mean(worst <= 8)), float(d.mean())


def instructions(rast, glb, frames, work):
    out = os.path.join(work, "cg.out")
    env = dict(os.environ, OMP_NUM_THREADS="1", OMP_PROC_BIND="false")
    subprocess.run(["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", rast, "bench", glb, *FLAGS,
                    "--frames", str(frames), "--warmup", "0"], check=True, capture_output=True, env=env)
    for line in open(out):
        if line.startswith("summary:") or line.startswith("totals:"):
            return int(line.split()[1])
    raise SystemExit("probe_cost: no totals in callgrind's output")


def per_frame(rast, glb, work):
    return (instructions(rast, glb, 9, work) - instructions(rast, glb, 1, work)) / 8.0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rast", required=True)
    ap.add_argument("--csv", required=True)
    ap.add_argument("--work", default="/tmp/probe_cost")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    rows = []
    for probe, controls in CONTROLS.items():
        golden = os.path.join(ROOT, "tests", "golden", "probes", probe + ".png")
        exported = os.path.join(a.work, probe + ".export.glb")
        subprocess.run([a.rast, "export", "builtin:probe-" + probe, "-o", exported], check=True, capture_output=True)
        glb = probe_file(exported, probe, os.path.join(a.work, probe + ".glb"))
        doc, binary = read_glb(glb)
        variants = [("(all)", glb)]
        for what, edit in controls:
            d = json.loads(json.dumps(doc))
            edit(d)
            path = os.path.join(a.work, f"{probe}.without.{len(variants)}.glb")
            write_glb(path, d, binary)
            variants.append((what, path))
        base = None
        for what, path in variants:
            pfm = path[:-4] + ".pfm"
            subprocess.run([a.rast, "render", path, *FLAGS, "-o", pfm], check=True, capture_output=True)
            w3, w8, mae = agreement(golden, pfm)
            ins = per_frame(a.rast, path, a.work)
            if base is None:
                base = (ins, w3)
            row = {"probe": probe, "without": what, "within3": round(w3, 4), "within8": round(w8, 4), "mae": round(mae, 2),
                   "frame_instructions": int(ins), "feature_cost": int(base[0] - ins) if what != "(all)" else 0}
            rows.append(row)
            print(row, flush=True)
    with open(a.csv, "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=list(rows[0]))
        wr.writeheader()
        wr.writerows(rows)


if __name__ == "__main__":
    main()

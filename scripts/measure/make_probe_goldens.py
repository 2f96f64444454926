#!/usr/bin/python3
"""Makes the goldens of the glTF feature probes (tests/golden/probes/*.png,
checked by tests/cli/cli_probe_goldens.py; docs/gltf-support.md, "Feature
probes"): each built-in probe (scenes/material_probes.cpp) exported with
`rast export` and rendered by the Khronos glTF Sample Renderer
(../shared/tools/khronos-ref) from the probe's own camera, punctual light only
(no environment), tone map none, no anti-aliasing, 200x150; probe-transform's
file gets KHR_texture_transform first (tests/support/probe_files.py). The reference
runs once for all probes (its start-up filters an environment: minutes on 2
cores). CI never runs this: the goldens are committed files.

  scripts/measure/make_probe_goldens.py --rast build/openmp/rast [--out tests/golden/probes] [--work /tmp/probes]
      [--size 200x150] [PROBE...]

The reference encodes its PNGs with a 2.2 power curve (the test encodes
rast's linear output the same way before comparing)."""
import argparse
import json
import os
import shutil
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
KREF = os.path.normpath(os.path.join(ROOT, "..", "shared", "tools", "khronos-ref"))
PROBES = ["spheres", "normalmap", "emissive", "mask", "wrap", "transform", "lights", "clearcoat"]
sys.path.insert(0, os.path.join(ROOT, "tests", "support"))
from probe_files import probe_file  # noqa: E402  (probe-transform's file gets its KHR_texture_transform)


def export(rast, probe, path):
    """Exports builtin:probe-<probe> to path; returns its camera flags as a dict (from rast's line)."""
    r = subprocess.run([rast, "export", "builtin:probe-" + probe, "-o", path], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"make_probe_goldens: rast export failed: {r.stderr.strip()}")
    words = (r.stdout + r.stderr).split("view it with", 1)[1].split()
    return dict(zip((w[2:] for w in words[0::2]), words[1::2]))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rast", required=True)
    ap.add_argument("--out", default=os.path.join(ROOT, "tests", "golden", "probes"))
    ap.add_argument("--work", default="/tmp/rast_probe_goldens")
    ap.add_argument("--size", default="200x150")
    ap.add_argument("probes", nargs="*", default=PROBES)
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    os.makedirs(a.out, exist_ok=True)
    jobs = []
    for p in a.probes:
        glb = os.path.join(a.work, p + ".glb")
        cam = export(a.rast, p, os.path.join(a.work, p + ".export.glb"))
        probe_file(os.path.join(a.work, p + ".export.glb"), p, glb)
        job = {"scene": glb, "out": os.path.join(a.work, p + ".ref.png"), "size": a.size, "tonemap": "none"}
        for k in ("eye", "target", "up", "fovy", "near", "far"):
            job[k] = cam[k]
        jobs.append(job)
    batch = os.path.join(a.work, "jobs.jsonl")
    with open(batch, "w") as f:
        for j in jobs:
            f.write(json.dumps(j) + "\n")
    subprocess.run(["node", os.path.join(KREF, "khronos_ref.mjs"), "--batch", batch], check=True)
    for p, j in zip(a.probes, jobs):
        shutil.copyfile(j["out"], os.path.join(a.out, p + ".png"))
        print(f"make_probe_goldens: {os.path.join(a.out, p + '.png')}")


if __name__ == "__main__":
    main()

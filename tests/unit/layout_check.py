#!/usr/bin/env python3
"""The source tree's layout rules (docs/architecture.md), checked on every
ctest run so that the tree cannot drift back into one flat folder:

* layers: every quoted #include points to a folder of a lower layer or to the
  same folder; so no two folders include each other, and nothing compiled once
  (base/, host/, scenes/) includes the per-execution-space code (backends/,
  pipeline/);
* size: no C++ source over MAX_LINES lines, no folder whose top level holds
  more than MAX_FILES files;
* every C++ and Python source opens with a comment or docstring that says why
  (a .cpp file may instead open by including its own header, which does).

  python3 tests/unit/layout_check.py --root REPO
"""
import argparse
import os
import re
import sys

# Lower number = lower layer. A folder may include its own files and those of
# folders with a strictly lower number.
LAYERS = {
    "include/rast": -1,  # the installed API's headers (docs/library.md): Kokkos and std only
    "base": 0,
    "host/scene": 1,
    "host/settings": 2, "host/gltf": 2, "host/image": 2, "host/distributed": 2,
    "scenes": 3,
    "backends": 3,
    "pipeline/data": 4,
    "pipeline/rules": 5,
    "pipeline/geometry": 6, "pipeline/raster": 6,
    "pipeline/shade": 7, "pipeline/post": 7,
    "pipeline/cpu": 8,
    "pipeline/blend": 8.5,  # MASK and BLEND passes (docs/transparency.md); the resolve lights runs with the CPU's span maths
    "pipeline/frame": 9,
    "pipeline/distributed": 9.5,  # sort-last compositing: hooks into the renderer (docs/distributed.md)
    "api": 10,  # the library behind include/rast/rast.h
    "app": 10,
    "python": 11,  # the Python module, over include/rast only
    "app/viewer": 11,
    "tests/support": 99,
    "host": 2,
}
# Standalone programs (microbenchmarks run on the GPU machine; examples built
# against the installed package): sizes and
# opening comments checked, not layers.
STANDALONE = ("scripts/", "examples/")
COMPILED_ONCE = ("base", "host/", "scenes")
PER_SPACE = ("backends", "pipeline/")
TESTS = "tests"
MAX_LINES = 720
MAX_FILES = 24
SOURCE_DIRS = ["include", "base", "host", "scenes", "backends", "pipeline", "api", "app", "python", "examples",
               "tests", "scripts"]

ap = argparse.ArgumentParser()
ap.add_argument("--root", required=True)
a = ap.parse_args()
root = os.path.abspath(a.root)
problems = []


def folder_of(rel):
    return os.path.dirname(rel)


def layer(folder):
    if folder in LAYERS:
        return LAYERS[folder]
    if folder.startswith(TESTS):
        return 100
    return None


include = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
edges = {}
files = []
for top in SOURCE_DIRS:
    for dirpath, dirnames, filenames in os.walk(os.path.join(root, top)):
        dirnames[:] = [d for d in dirnames if d not in ("corpus", "golden", "__pycache__", "data")]
        rel_dir = os.path.relpath(dirpath, root)
        entries = [f for f in filenames if not f.startswith(".")]
        if len(entries) > MAX_FILES:
            problems.append(f"{rel_dir}/ holds {len(entries)} files at its top level (at most {MAX_FILES})")
        for f in entries:
            files.append(os.path.join(rel_dir, f))

for rel in sorted(files):
    path = os.path.join(root, rel)
    if rel.endswith((".h", ".cpp", ".cu")):
        with open(path, encoding="utf-8", errors="replace") as fh:
            lines = fh.read().split("\n")
        if len(lines) > MAX_LINES:
            problems.append(f"{rel}: {len(lines)} lines (at most about {MAX_LINES - 20})")
        own_header = rel.endswith(".cpp") and re.match(
            r'#include "' + re.escape(rel[:-4]) + r'\.h"', lines[0])  # the paragraph is in its header
        if not lines[0].startswith("//") and not own_header:
            problems.append(f"{rel}: does not open with a comment saying why it exists")
        src = folder_of(rel)
        if rel.startswith(STANDALONE):
            continue
        src_layer = layer(src)
        if src_layer is None:
            problems.append(f"{rel}: folder {src}/ has no layer in tests/unit/layout_check.py")
            continue
        for n, ln in enumerate(lines, 1):
            m = include.match(ln)
            if not m:
                continue
            target = m.group(1)
            if not os.path.exists(os.path.join(root, target)):
                if os.path.exists(os.path.join(os.path.dirname(path), target)) and src.startswith(TESTS):
                    continue  # a test's neighbour
                if src.startswith(TESTS) or "/" not in target:
                    continue  # outside the tree (glref's headers for a test tool)
                problems.append(f"{rel}:{n}: includes {target}, which is not a path from the repository root")
                continue
            dst = folder_of(target)
            if dst == src:
                continue
            edges.setdefault((src, dst), f"{rel}:{n}")
            if src.startswith(COMPILED_ONCE) and dst.startswith(PER_SPACE):
                problems.append(f"{rel}:{n}: compiled once, but includes per-space code {target}")
            dst_layer = layer(dst)
            if dst_layer is None:
                problems.append(f"{rel}:{n}: includes {target} from a folder with no layer")
            elif dst_layer >= src_layer:
                problems.append(f"{rel}:{n}: {src}/ (layer {src_layer}) includes {target} of {dst}/ (layer {dst_layer}): "
                                "includes must point down")
    elif rel.endswith(".py"):
        with open(path, encoding="utf-8", errors="replace") as fh:
            head = fh.read(400).lstrip()
        if head.startswith("#!"):
            head = head.split("\n", 1)[1].lstrip() if "\n" in head else ""
        if not (head.startswith('"""') or head.startswith("#")):
            problems.append(f"{rel}: does not open with a docstring or comment saying why it exists")

for (s, d), where in sorted(edges.items()):
    if (d, s) in edges:
        problems.append(f"{s}/ and {d}/ include each other ({where} and {edges[(d, s)]})")

for p in problems:
    print("layout:", p)
print(f"{len(files)} files checked, {len(problems)} problems")
sys.exit(1 if problems else 0)

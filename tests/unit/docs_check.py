#!/usr/bin/env python3
"""The reference pages name only what exists: every repository path and every
kernel label (rast::stage::...) that README.md and docs/*.md mention must be
in the tree. The journal (docs/journal/) and raw data (docs/data/) record the
past and are not checked. Run by ctest (docs_check), so a rename that forgets
the docs fails.

  python3 tests/unit/docs_check.py --root REPO
"""
import argparse
import glob
import os
import re
import sys

ap = argparse.ArgumentParser()
ap.add_argument("--root", required=True)
root = os.path.abspath(ap.parse_args().root)

pages = [os.path.join(root, "README.md")] + sorted(glob.glob(os.path.join(root, "docs", "*.md")))
tops = "base|host|scenes|backends|pipeline|app|tests|scripts|docs|cmake|examples|include|python|api"
path_re = re.compile(r"(?<![\w./-])((?:" + tops + r")/[\w./*-]*\.(?:h|cpp|py|sh|md|cmake|txt|png|csv|json|cu|toml))")
label_re = re.compile(r"(?<![\w:])rast::(?:vertex|setup|raster|shade|post)(?:::[a-z_]+)*(?:::)?")

labels = set()
for d in ("pipeline", "backends", "app"):
    for dirpath, _, files in os.walk(os.path.join(root, d)):
        for f in files:
            if f.endswith((".h", ".cpp")):
                with open(os.path.join(dirpath, f), encoding="utf-8", errors="replace") as fh:
                    labels.update(re.findall(r'"(rast::[a-z_:]+)"', fh.read()))

problems = []
for page in pages:
    rel_page = os.path.relpath(page, root)
    with open(page, encoding="utf-8") as fh:
        for n, line in enumerate(fh, 1):
            for p in path_re.findall(line):
                p = p.rstrip(".")
                if "*" in p:
                    if not glob.glob(os.path.join(root, p)):
                        problems.append(f"{rel_page}:{n}: no file matches {p}")
                elif not os.path.exists(os.path.join(root, p)):
                    problems.append(f"{rel_page}:{n}: {p} does not exist")
            for lab in label_re.findall(line):
                if not any(l == lab or l.startswith(lab.rstrip(":") + "::") or l.startswith(lab) for l in labels):
                    problems.append(f"{rel_page}:{n}: kernel label {lab} is in no source")
for p in problems:
    print("docs:", p)
print(f"{len(pages)} pages checked, {len(problems)} problems")
sys.exit(1 if problems else 0)

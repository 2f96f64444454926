#!/usr/bin/env python3
# Several rast binaries against each other on the GPU machine, interleaved:
# each round runs every scene with every binary (the order reversed every
# other round), `rast bench` at 1920x1080 with FRAMES timed frames after 20
# warm-up, and the table gives each binary's median over the rounds of its
# frame medians. ab_frames.sh compares two binaries; this one compares
# variants of one change in one run (docs/performance.md, issue #11).
#
#   python3 scripts/device/ab_multi.py OUT.csv ROUNDS FRAMES name=BINARY ...
#
# Run from the repository root next to .device/ (scripts/device/pack.sh); the
# scenes are scripts/device/scenes.txt's (read next to this file, or from there).
# AB_SCENES=a,b limits the scenes; AB_METHOD (default auto) picks the method.
# OUT.csv: one row per round, scene and binary, with the stage medians.
import csv, json, os, subprocess, sys, tempfile, statistics
out, rounds, frames = sys.argv[1], int(sys.argv[2]), sys.argv[3]
if not os.path.exists("/tmp/stress/bigtri.glb"):
    os.makedirs("/tmp/stress", exist_ok=True)
    subprocess.run([sys.executable, ".device/glref_src/gen_scenes.py", "/tmp/stress"], check=True,
                   stdout=subprocess.DEVNULL)
bins = [a.split("=", 1) for a in sys.argv[4:]]
scenes = {}  # scenes.txt's NAME|ARGS lines, placeholders filled in
here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scenes.txt")  # or a copy's repository
for line in open(here if os.path.exists(here) else "scripts/device/scenes.txt"):
    if line.strip() and not line.startswith("#"):
        name, args = line.rstrip("\n").split("|", 1)
        scenes[name] = args.replace("{models}", ".device/shared/models").replace("{stress}", "/tmp/stress")
only = os.environ.get("AB_SCENES")
if only: scenes = {k: v for k, v in scenes.items() if k in only.split(",")}
res = {}
rows = []
for r in range(rounds):
    for name, args in scenes.items():
        order = bins if r % 2 == 0 else bins[::-1]
        for label, exe in order:
            with tempfile.TemporaryDirectory() as tmp:
                js = os.path.join(tmp, "b.json")
                cmd = [exe, "bench"] + args.split() + ["--size", "1920x1080", "--frames", frames, "--warmup", "20",
                                                       "--methods", os.environ.get("AB_METHOD", "auto"), "--json", js,
                                                       "--shading", os.environ.get("AB_SHADING", "lambert")]
                p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
                if p.returncode:
                    print(f"{label} failed on {name}: {p.stderr.strip()[-300:]}", flush=True); continue
                b = json.load(open(js))[-1]
                stages = {k: v for k, v in b.items() if k.endswith("_median_ms")}
                res.setdefault((name, label), []).append(b["total_median_ms"])
                rows.append({"round": r, "scene": name, "binary": label, "method": b["method"], **stages})
keys = sorted({k for row in rows for k in row})
with open(out, "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=keys); w.writeheader(); w.writerows(rows)
labels = [l for l, _ in bins]
print("scene".ljust(15) + "".join(l.rjust(10) for l in labels))
for name in scenes:
    line = name.ljust(15)
    for l in labels:
        v = res.get((name, l))
        line += (f"{statistics.median(v):10.4f}" if v else "      fail")
    print(line, flush=True)

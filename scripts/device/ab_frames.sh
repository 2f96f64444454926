#!/usr/bin/env bash
# Two rast binaries, the same scenes and cameras, interleaved: the frame time
# (median of RAST_AB_FRAMES after 20 warm-up frames, per stage) of a change
# against its base, on the GPU machine (and the frames timed stage by stage:
# "staged"). Scenes: the empty frame, the shared
# models at rast's own framing, glref's stress scenes and the two views from
# inside dense models of three_way.sh.
#
#   bash scripts/device/ab_frames.sh OUTDIR BASE_RAST NEW_RAST [METHODS]
#
# METHODS: comma-separated, default visbuffer,auto. Writes OUTDIR/ab.csv
# (one row per binary, scene and method) and prints a table with the ratio.
set -uo pipefail
out=${1:?usage: ab_frames.sh OUTDIR BASE NEW [METHODS]}
base=${2:?base binary}
new=${3:?new binary}
methods=${4:-visbuffer,auto}
frames=${RAST_AB_FRAMES:-200}
root=$(cd "$(dirname "$0")/../.." && pwd)
dev=$root/.device
m=$dev/shared/models
mkdir -p "$out" /tmp/stress
python3 "$dev/glref_src/gen_scenes.py" /tmp/stress > /dev/null
# NAME|ARGS lines of scenes.txt, placeholders filled in.
mapfile -t scenes < <(sed -e '/^#/d' -e '/^$/d' -e "s|{models}|$m|g" -e 's|{stress}|/tmp/stress|g' "$root/scripts/device/scenes.txt")
python3 - "$out" "$base" "$new" "$methods" "$frames" "${scenes[@]}" <<'EOF'
import csv, json, os, subprocess, sys, tempfile
out, base, new, methods, frames = sys.argv[1:6]
rows = []
for spec in sys.argv[6:]:
    name, args = spec.split("|", 1)
    for label, exe in (("base", base), ("new", new)):
        with tempfile.TemporaryDirectory() as tmp:
            js = os.path.join(tmp, "b.json")
            cmd = [exe, "bench"] + args.split() + ["--size", "1920x1080", "--frames", frames, "--warmup", "20",
                                                   "--methods", methods, "--json", js]
            r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
            if r.returncode:
                print(f"{label} failed on {name}: {r.stderr.strip()[-300:]}", file=sys.stderr)
                continue
            for b in json.load(open(js)):
                rows.append({"scene": name, "binary": label, "requested": b["requested"], "method": b["method"],
                             "total_ms": b["total_median_ms"], "enqueue_host_ms": b.get("enqueue_host_median_ms", ""),
                             # before the bench timed whole frames apart, its total was the staged sum
                             "staged_ms": b.get("staged_total_median_ms", b["total_median_ms"]),
                             **{"stage_" + k: v for k, v in b["stages_median_ms"].items()}})
keys = []
for r in rows:
    keys += [k for k in r if k not in keys]
with open(os.path.join(out, "ab.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=keys)
    w.writeheader()
    w.writerows(rows)
print(f"{'scene':14} {'requested':10} {'base ms':>8} {'new ms':>8} {'new/base':>8}  new stages (ms), host enqueue")
for r in rows:
    if r["binary"] != "new":
        continue
    b = [x for x in rows if x["binary"] == "base" and x["scene"] == r["scene"] and x["requested"] == r["requested"]]
    bt = b[0]["total_ms"] if b else float("nan")
    st = " ".join(f"{k[6:]}={v:.3f}" for k, v in r.items() if k.startswith("stage_"))
    bs = b[0]["staged_ms"] if b else float("nan")
    print(f"{r['scene']:14} {r['requested']:10} {bt:8.3f} {r['total_ms']:8.3f} {r['total_ms'] / bt:8.2f}  "
          f"staged {bs:.3f}->{r['staged_ms']:.3f}  {st} enq={r['enqueue_host_ms']}")
EOF

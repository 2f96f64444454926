#!/usr/bin/env bash
# Per-kernel device time of rast's frames under Nsight Compute (ncu, on the GPU
# machine's image): the duration of every kernel of the last frames of a
# bench, by name, with no launch gaps or host time in it. Use it to see where a
# frame's device time goes; frame times come from `rast bench`.
#
#   bash scripts/device/ncu_frame.sh OUTDIR [METHOD]
#
# Writes OUTDIR/<scene>.csv (ncu's raw CSV) and prints, per scene, each
# kernel's median duration in microseconds and their sum per frame.
set -uo pipefail
out=${1:?usage: ncu_frame.sh OUTDIR [METHOD]}
method=${2:-visbuffer}
root=$(cd "$(dirname "$0")/../.." && pwd)
dev=$root/.device
m=$dev/shared/models
rast=${RAST_NCU_BIN:-$dev/cuda/rast}
ncu=$(command -v ncu || ls /opt/nvidia/nsight-compute/*/ncu 2>/dev/null | sed -n 1p)
mkdir -p "$out" /tmp/stress
python3 "$dev/glref_src/gen_scenes.py" /tmp/stress > /dev/null
# NAME|ARGS lines of scenes.txt, placeholders filled in; RAST_NCU_SCENES (comma-
# separated names) picks some: by default all but checkerboard, tiny and
# overdraw, whose kernels the others cover.
keep=${RAST_NCU_SCENES:-empty,box,cow,duck,engine,milktruck,bigtri,engine_inside,milktruck_cab}
scenes=()
while IFS= read -r spec; do
  case ",$keep," in *",${spec%%|*},"*) scenes+=("$spec") ;; esac
done < <(sed -e '/^#/d' -e '/^$/d' -e "s|{models}|$m|g" -e 's|{stress}|/tmp/stress|g' "$root/scripts/device/scenes.txt")
for spec in "${scenes[@]}"; do
  name=${spec%%|*}
  args=${spec#*|}
  # shellcheck disable=SC2086
  RAST_FRAME_GRAPHS=0 "$ncu" --clock-control none --metrics gpu__time_duration.sum --csv --print-units base \
    "$rast" bench $args --size 1920x1080 --frames 5 --warmup 3 --methods "$method" > "$out/$name.csv" 2> "$out/$name.err"
  python3 - "$out/$name.csv" "$name" <<'PY'
import csv, io, re, statistics, sys
path, name = sys.argv[1:3]
text = open(path).read()
start = text.find('"ID"')
rows = list(csv.DictReader(io.StringIO(text[start:]))) if start >= 0 else []
by = {}
order = []
for r in rows:
    if r.get("Metric Name") != "gpu__time_duration.sum":
        continue
    k = r["Kernel Name"]
    # Kokkos kernels are named by their functor: ParallelFor<Functor, Policy...>
    mt = re.search(r"(Parallel(?:For|Reduce|Scan)\w*)<(.+?), Kokkos::", k)
    k = f"{mt.group(1)} {mt.group(2)}" if mt else k[:90]
    if k not in by:
        order.append(k)
    by.setdefault(k, []).append(float(r["Metric Value"].replace(",", "")) / 1000.0)
print(f"== {name}")
total = 0.0
for k in order:
    v = by[k][len(by[k]) // 2:]  # later frames only
    med = statistics.median(v)
    total += med
    print(f"  {med:8.2f} us  x{len(by[k]):3d}  {k}")
print(f"  {total:8.2f} us  sum of medians")
PY
done

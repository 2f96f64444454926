#!/usr/bin/env bash
# The transparency methods on the GPU machine (docs/transparency.md): the
# Catch2 and CLI transparency tests of a CUDA build, then the methods' error
# against exact and against the supersampled exact reference versus frame time
# at 1920x1080 (scripts/measure/bench_transparency.py) and its chart.
#
#   bash scripts/device/transparency.sh BUILD_DIR OUTDIR
#
# BUILD_DIR: a configured and built CUDA tree (cmake --preset cuda; its rast,
# rast_tests). Writes OUTDIR/transparency_cuda.csv, OUTDIR/transparency_cuda.png
# and OUTDIR/tests.log.
set -uo pipefail
build=${1:?usage: transparency.sh BUILD_DIR OUTDIR}
out=${2:?usage: transparency.sh BUILD_DIR OUTDIR}
root=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$out"
# The Catch2 cases are named "MASK: ...", "BLEND: ..." (tests/pipeline/test_transparency.cpp).
ctest --test-dir "$build" -R "BLEND|MASK|transparency" --output-on-failure > "$out/tests.log" 2>&1
echo "tests: rc $? (log in $out/tests.log)"
python3 "$root/scripts/measure/bench_transparency.py" --rast "$build/rast" --out "$out/transparency_cuda.csv" \
  --size 1920x1080 --frames 50 --reference-grid 16
python3 "$root/scripts/plot/plot_transparency.py" "$out/transparency_cuda.csv" --out "$out/transparency_cuda.png" ||
  echo "no chart (matplotlib missing): the CSV is the result"

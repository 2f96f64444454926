#!/usr/bin/env bash
# The glTF feature probes on the GPU machine (#37; docs/gltf-support.md,
# "Feature probes"): tests/cli/cli_probe_goldens.py with the CUDA build (every
# probe within the goldens' tolerances, every control missing them), then the
# CUDA and OpenMP images of each probe compared (colours within 1/255, as the
# parity rule asks; the test's PFMs are linear).
#
#   bash scripts/device/probes_h100.sh CUDA_RAST OPENMP_RAST OUT_DIR
#
# Writes OUT_DIR/cuda/ and OUT_DIR/openmp/ (the test's work folders, with
# agreement.json) and prints the test's lines and one parity line a probe.
set -uo pipefail
cuda=$1 cpu=$2 out=$3
root=$(cd "$(dirname "$0")/../.." && pwd)
export OMP_PROC_BIND=false
status=0
for b in cuda openmp; do
  exe=$cuda; [ $b = openmp ] && exe=$cpu
  python3 "$root/tests/cli/cli_probe_goldens.py" --rast "$exe" --workdir "$out/$b" || status=1
done
python3 - "$out" "$root/tests/support" <<'EOF2' || status=1
import sys
out, support = sys.argv[1], sys.argv[2]
sys.path.insert(0, support)
import rastimg
bad = 0
for p in ["spheres", "normalmap", "emissive", "mask", "wrap", "transform", "lights", "clearcoat"]:
    a = rastimg.read_pfm(f"{out}/cuda/{p}.pfm")[3]
    b = rastimg.read_pfm(f"{out}/openmp/{p}.pfm")[3]
    worst = max(abs(min(x, 1.0) - min(y, 1.0)) for x, y in zip(a, b)) if len(a) == len(b) else 1.0
    ok = worst <= 1 / 255
    bad += not ok
    print(f"{'ok  ' if ok else 'FAIL'} probe-{p}: CUDA and OpenMP within 1/255 (max linear diff {worst:.2e})")
sys.exit(1 if bad else 0)
EOF2
exit $status

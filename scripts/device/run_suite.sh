#!/usr/bin/env bash
# Run on the GPU machine, from the repository root, with .device/ made by
# scripts/device/pack.sh next to the working tree. Nothing is built there.
#
#   bash scripts/device/run_suite.sh [OUTDIR]      (default: $OUT, else ./device-out)
#
# Steps: GPU list; `rast info`; every Catch2 test of the CUDA build; the CLI
# parity test, CUDA against the OpenMP build (ids and depth bit-identical,
# colours within 1/255); `rast bench` of five scenes at 1920x1080 with every
# raster method (JSON per scene, summary table); the post passes per frame and
# SSAO error per sample count (CSV, docs/post.md); kernel launches per frame when
# .device/kokkos_count.so is present. Every step runs even if an earlier one
# fails; the exit status is non-zero when any failed. Set RAST_SUITE_SKIP to a
# comma list of steps (tests,parity,bench,post,count) to leave some out.
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
out=${1:-${OUT:-$root/device-out}}
mkdir -p "$out"
rm -f "$out/failed_steps.txt"
dev=$root/.device
[ -x "$dev/cuda/rast" ] || { echo "run_suite.sh: $dev/cuda/rast missing: run scripts/device/pack.sh first" >&2; exit 1; }
skip=",${RAST_SUITE_SKIP:-},"
frames=${RAST_BENCH_FRAMES:-200}

[ -d "$dev/lib" ] && export LD_LIBRARY_PATH="$dev/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export OMP_PROC_BIND=false
# Test data: environment overrides of the paths compiled into rast_tests.
export RAST_SHARED_DIR=$dev/shared RAST_ASSIMP_GLTF_DIR=$dev/assimp
# Test files of the built sources (pack.sh copies them to .device/src), else this checkout's.
src=$root
linked=""
[ -f "$dev/src/tests/cli/cli_parity.py" ] && src=$dev/src
# The golden tests read tests/golden/ under the source path compiled in at build
# time; when that path does not exist here, make it a link to $src.
if [ -f "$dev/build.env" ]; then
  build_src=$(sed -n 's/^RAST_BUILD_SOURCE_DIR=//p' "$dev/build.env")
  if [ -n "$build_src" ] && [ ! -e "$build_src" ]; then
    mkdir -p "$(dirname "$build_src")" 2>/dev/null && ln -s "$src" "$build_src" 2>/dev/null &&
      linked="run_suite.sh: linked $build_src -> $src (golden images)"
  fi
fi

status=0
step() {  # step NAME CMD...: run, log its status, remember failures
  local name=$1; shift
  echo "=== $name: $*"
  local t0=${EPOCHREALTIME/,/.}
  "$@"; local rc=$?
  local t1=${EPOCHREALTIME/,/.}
  echo "=== $name: exit $rc ($(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }') s)"
  [ "$rc" -eq 0 ] || { status=1; echo "$name rc=$rc" >> "$out/failed_steps.txt"; }
  return 0
}

{
  echo "=== date: $(date -u +%Y-%m-%dT%H:%M:%SZ) host: $(hostname)"
  [ -f "$dev/build.env" ] && cat "$dev/build.env"
  [ -n "$linked" ] && echo "$linked"
  step gpus nvidia-smi -L
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv 2>/dev/null
  step info "$dev/cuda/rast" info
  step info-openmp "$dev/openmp/rast" info

  case $skip in *,tests,*) ;; *)
    step tests "$dev/cuda/rast_tests" --durations yes
    ;;
  esac

  case $skip in *,parity,*) ;; *)
    rm -rf /tmp/parity
    step parity python3 "$src/tests/cli/cli_parity.py" --rast "$dev/cuda/rast" --rast-serial "$dev/openmp/rast" \
      --shared "$dev/shared" --assimp "$dev/assimp" --workdir /tmp/parity
    ;;
  esac

  case $skip in *,bench,*) ;; *)
    for s in default duck cow milktruck engine; do
      if [ "$s" = default ]; then scene=builtin:default; else scene=$dev/shared/models/$s.glb; fi
      [ "$s" = default ] || [ -f "$scene" ] || { echo "=== bench-$s: $scene absent, skipped"; continue; }
      step "bench-$s" "$dev/cuda/rast" bench "$scene" --size 1920x1080 --all-methods --frames "$frames" \
        --json "$out/bench_$s.json"
    done
    python3 - "$out" <<'PY'
import glob, json, os, sys
out = sys.argv[1]
lines = []
for f in sorted(glob.glob(os.path.join(out, "bench_*.json"))):
    rows = json.load(open(f))
    if not rows:
        continue
    stages = list(rows[0]["stages_median_ms"].keys())
    r0 = rows[0]
    lines.append(f"\n{os.path.basename(r0['scene'])}  ({r0['width']}x{r0['height']}, {r0['backend']}, "
                 f"median of {r0['frames']} frames, ms; {r0['triangles_in']} triangles in)")
    lines.append("| method | " + " | ".join(stages) + " | total | min | raster tris | device MiB |")
    lines.append("|---" * (len(stages) + 5) + "|")
    seen = set()
    for r in rows:
        # --all-methods benches every method, then auto, which reports the method it chose.
        label = r["method"] if r["method"] not in seen else f"auto ({r['method']})"
        seen.add(r["method"])
        lines.append(f"| {label} | " + " | ".join(f"{r['stages_median_ms'][s]:.3f}" for s in stages) +
                     f" | {r['total_median_ms']:.3f} | {r['total_min_ms']:.3f} | {r['triangles_raster']} |"
                     f" {r['device_bytes'] / 1048576:.1f} |")
text = "\n".join(lines) + "\n"
open(os.path.join(out, "bench_summary.md"), "w").write(text)
print(text)
PY
    ;;
  esac

  # Post-processing passes (docs/post.md): per-pass times at 1920x1080, and
  # SSAO's error against the ray-traced reference with its cost per sample count.
  case $skip in *,post,*) ;; *)
    for s in default duck cow milktruck engine checkerboard box; do
      if [ "$s" = default ]; then scene=builtin:default; else scene=$dev/shared/models/$s.glb; fi
      [ "$s" = default ] || [ -f "$scene" ] || { echo "=== post-$s: $scene absent, skipped"; continue; }
      step "post-$s" "$dev/cuda/rast" bench "$scene" --size 1920x1080 --frames "$frames" \
        --exposure 0.5 --bloom --ssao --tonemap aces --csv "$out/post_$s.csv"
    done
    # SSAO's higher-quality setting (16 directions) where the frame is full.
    for s in default box; do
      if [ "$s" = default ]; then scene=builtin:default; else scene=$dev/shared/models/$s.glb; fi
      [ "$s" = default ] || [ -f "$scene" ] || continue
      step "post-$s-ssao16" "$dev/cuda/rast" bench "$scene" --size 1920x1080 --frames "$frames" \
        --ssao=0,16 --csv "$out/post_${s}_ssao16.csv"
    done
    [ -f "$dev/shared/models/duck.glb" ] && step post-ssao-error "$dev/cuda/rast" ssao-error "$dev/shared/models/duck.glb" \
      --size 1920x1080 --error-size 480x270 --rays 256 --samples 1,2,4,8,16,32 --frames 50 --csv "$out/post_ssao.csv"
    ;;
  esac

  case $skip in *,count,*) ;; *)
    if [ -f "$dev/kokkos_count.so" ]; then
      for m in $("$dev/cuda/rast" info | sed -n 's/^raster methods://p'); do
        step "count-$m" env KOKKOS_TOOLS_LIBS="$dev/kokkos_count.so" KOKKOS_PROFILE_LIBRARY="$dev/kokkos_count.so" "$dev/cuda/rast" bench builtin:default \
          --size 1920x1080 --raster "$m" --frames 10 --warmup 0
      done
    fi
    ;;
  esac
  echo "=== suite: $([ $status -eq 0 ] && echo PASSED || echo "FAILED: $(tr '\n' ' ' < "$out/failed_steps.txt")")"
  [ $status -eq 0 ]
} 2>&1 | tee "$out/log.txt"

#!/usr/bin/env bash
# The glTF shading (`--shading pbr`, #37) on the GPU machine: its frame time
# against Blinn-Phong's on the shared models at 1920x1080 (rast bench, median
# of 200 frames), punctual light alone (--env none) and with the default
# environment, and parity of the CUDA build with the OpenMP build (ids and
# depth identical, colours within 1/255) on the same views, and on the
# normal-map probes of scripts/measure/tangent_probe.py (TANGENT, generated).
#
#   bash scripts/device/pbr_h100.sh CUDA_RAST OPENMP_RAST MODELS_DIR OUT_DIR [extra render flags]
#
# Writes OUT_DIR/pbr_bench.csv (model, shading, total and per-stage medians)
# and prints the parity lines and a summary.
set -euo pipefail
cuda=$1 cpu=$2 models=$3 out=$4
shift 4
extra=("$@")
mkdir -p "$out"
export OMP_PROC_BIND=false
# Parity: the same view of FILE on CUDA and on OpenMP (ids and depth
# identical, colours within 1/255).
parity() {
  local m=$1 file=$2
  for b in cuda cpu; do
    exe=$cuda; [ $b = cpu ] && exe=$cpu
    "$exe" render "$file" --size 640x400 --shading pbr -o "$out/$m.$b.png" \
      --aov "primid=$out/$m.$b.ids.bin,depth=$out/$m.$b.depth.pfm" "${extra[@]}" > /dev/null 2>&1
  done
  python3 - "$out" "$m" <<'EOF'
import sys, zlib, struct
out, m = sys.argv[1], sys.argv[2]
same_ids = open(f"{out}/{m}.cuda.ids.bin", "rb").read() == open(f"{out}/{m}.cpu.ids.bin", "rb").read()
same_depth = open(f"{out}/{m}.cuda.depth.pfm", "rb").read() == open(f"{out}/{m}.cpu.depth.pfm", "rb").read()
def rgba(p):
    d = open(p, "rb").read(); i = 8; w = h = 0; idat = b""; bpp = 4
    while i < len(d):
        n, t = struct.unpack(">I4s", d[i:i + 8]); c = d[i + 8:i + 8 + n]
        if t == b"IHDR": w, h = struct.unpack(">II", c[:8]); bpp = 4 if c[9] == 6 else 3  # RGBA or RGB
        if t == b"IDAT": idat += c
        i += 12 + n
    raw = zlib.decompress(idat); stride = w * bpp; rows = []; prev = bytearray(stride); p = 0
    for y in range(h):
        f = raw[p]; line = bytearray(raw[p + 1:p + 1 + stride]); p += 1 + stride
        for x in range(stride):
            a = line[x - bpp] if x >= bpp else 0; b = prev[x]; c = prev[x - bpp] if x >= bpp else 0
            if f == 1: line[x] = (line[x] + a) & 255
            elif f == 2: line[x] = (line[x] + b) & 255
            elif f == 3: line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                pa, pb, pc = abs(b - c), abs(a - c), abs(a + b - 2 * c)
                line[x] = (line[x] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line)); prev = line
    return b"".join(rows)
a, b = rgba(f"{out}/{m}.cuda.png"), rgba(f"{out}/{m}.cpu.png")
diff = max(abs(x - y) for x, y in zip(a, b))
ok = same_ids and same_depth and diff <= 1
print(f"{'ok  ' if ok else 'FAIL'} parity {m}: ids {'identical' if same_ids else 'DIFFER'}, depth "
      f"{'identical' if same_depth else 'DIFFER'}, max colour diff {diff}")
EOF
}

echo "model,shading,total_ms,shade_ms" > "$out/pbr_bench.csv"
for m in box checkerboard cow duck engine milktruck; do
  for v in "blinn-phong:--shading blinn-phong" "pbr-punctual:--shading pbr --env none" "pbr-env:--shading pbr"; do
    s=${v%%:*}
    read -r -a flags <<< "${v#*:}"
    "$cuda" bench "$models/$m.glb" --size 1920x1080 --frames 200 --warmup 20 "${flags[@]}" --json "$out/$m.$s.json" \
      "${extra[@]}" > "$out/$m.$s.txt" 2>&1 || { echo "bench $m $s failed"; tail -3 "$out/$m.$s.txt"; continue; }
    python3 - "$out/$m.$s.json" "$m" "$s" >> "$out/pbr_bench.csv" <<'EOF'
import json, sys
rows = json.load(open(sys.argv[1]))
r = rows[-1]
st = r.get("stages_median_ms", r.get("stageMedianMs", {}))
shade = sum(v for k, v in st.items() if "shade" in k) if isinstance(st, dict) else float("nan")
print(f"{sys.argv[2]},{sys.argv[3]},{r.get('total_median_ms')},{shade}")
EOF
  done
  parity "$m" "$models/$m.glb"
done
# Normal maps with a file's TANGENT and with generated tangents (the shared
# models have none): scripts/measure/tangent_probe.py's two squares.
here=$(cd "$(dirname "$0")" && pwd)
python3 "$here/../measure/tangent_probe.py" "$out/probe"
for m in tangent_file tangent_none; do parity "$m" "$out/probe/$m.gltf"; done
echo "== frame medians (ms) =="
cat "$out/pbr_bench.csv"

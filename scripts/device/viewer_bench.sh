#!/usr/bin/env bash
# The CUDA rast-viewer on the GPU machine, in a GLX window under a carried
# Xvfb (docs/viewer.md): frame rates per scene, size and overlay, with and
# without CUDA-GL interop, window screenshots, and the 100,000-frame soak.
#
# The machine has no display and no X packages. The GL context comes from
# NVIDIA's GLX library (__GLX_VENDOR_LIBRARY_NAME=nvidia) talking to an Xvfb
# whose own GLX extension needs Mesa's swrast driver; both travel as Debian
# packages (scripts/device/fetch_x_debs.sh) and are unpacked under /tmp/x, never
# over the machine's own /.
#
#   bash scripts/device/viewer_bench.sh OUTDIR [--quick]
#
# Needs, next to the working tree: .dview/rast-viewer (CUDA build), models in
# .dview/models/{cow,duck,engine}.glb, and the packages in .xdeb/ and .xmesa/
# (or already unpacked in /tmp/x by an earlier call on the same machine).
set -uo pipefail
out=${1:?usage: viewer_bench.sh OUTDIR [--quick]}
quick=${2:-}
mkdir -p "$out"
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
x=/tmp/x
mkdir -p "$x"
for d in .xmesa .xdeb; do
  [ -d "$d" ] || continue
  for f in "$d"/*.deb; do dpkg -x "$f" "$x"; done
done
[ -e "$x/usr/lib/x86_64-linux-gnu/libLLVM-15.so.1" ] || { echo "viewer_bench: Mesa's packages (.xmesa) were not unpacked" >&2; exit 1; }
export LD_LIBRARY_PATH=$x/usr/lib/x86_64-linux-gnu:$x/lib/x86_64-linux-gnu:/usr/local/nvidia/lib64${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
export LIBGL_DRIVERS_PATH=$x/usr/lib/x86_64-linux-gnu/dri
# Xvfb looks for its GL driver and for xkbcomp at compiled-in paths.
[ -e /usr/lib/x86_64-linux-gnu/dri ] || ln -s "$x/usr/lib/x86_64-linux-gnu/dri" /usr/lib/x86_64-linux-gnu/dri
[ -e /usr/bin/xkbcomp ] || ln -s "$x/usr/bin/xkbcomp" /usr/bin/xkbcomp
"$x/usr/bin/Xvfb" :99 -screen 0 2560x1440x24 -xkbdir "$x/usr/share/X11/xkb" +extension GLX -nolisten tcp \
  > "$out/xvfb.log" 2>&1 &
xpid=$!
trap 'kill $xpid 2>/dev/null' EXIT
sleep 2
export DISPLAY=:99 __GLX_VENDOR_LIBRARY_NAME=nvidia
viewer=.dview/rast-viewer
m=.dview/models
log=$out/viewer_runs.txt
: > "$log"
{
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  nvidia-smi --query-gpu=name,driver_version --format=csv,noheader
  [ -f .dview/build.env ] && cat .dview/build.env
} >> "$log"

frames=1000
[ "$quick" = --quick ] && frames=300
csv=$out/viewer_fps.csv
echo "scene,size,overlay,display,frames,median_frame_ms,fps,render_ms,upload_ms,draw_ms,overlay_ms,swap_ms,without_swap_ms,without_swap_fps" > "$csv"
run() {  # run SCENE SIZE OVERLAY(on|off) INTEROP(on|off)
  local scene=$1 size=$2 ov=$3 ip=$4 args=()
  [ "$ov" = off ] && args+=(--no-overlay)
  [ "$ip" = off ] && args+=(--no-interop)
  local line
  line=$(timeout 300 "$viewer" "$scene" --size "$size" --no-vsync --frames "$frames" "${args[@]}" 2>>"$log" |
    sed -n 's/^rast-viewer: \([0-9]* frames at .*\)$/\1/p')
  echo "$scene $size overlay=$ov interop=$ip: $line" >> "$log"
  # "N frames at WxH, median frame F ms (R fps): render A ms, upload B ms (copy-out C ms), draw D ms,
  #  overlay E ms, swap S ms; without the swap W ms (X fps); display P; ..."
  echo "$line" | awk -v sc="$(basename "$scene" .glb)" -v sz="$size" -v ov="$ov" -v ip="$ip" '
    { n=$1; match($0, /median frame [0-9.]+/); f=substr($0, RSTART+13, RLENGTH-13)
      match($0, /render [0-9.]+/); r=substr($0, RSTART+7, RLENGTH-7)
      match($0, /upload [0-9.]+/); u=substr($0, RSTART+7, RLENGTH-7)
      match($0, /draw [0-9.]+/); d=substr($0, RSTART+5, RLENGTH-5)
      match($0, /overlay [0-9.]+/); o=substr($0, RSTART+8, RLENGTH-8)
      match($0, /swap [0-9.]+/); s=substr($0, RSTART+5, RLENGTH-5)
      match($0, /without the swap [0-9.]+/); w=substr($0, RSTART+17, RLENGTH-17)
      disp = (ip == "on") ? "interop" : "host-copy"
      if ($0 ~ /display host copy \(interop unavailable: [^-]/) disp = "host-copy(fallback)"
      if (f > 0) printf "%s,%s,%s,%s,%s,%s,%.1f,%s,%s,%s,%s,%s,%s,%.1f\n", sc, sz, ov, disp, n, f, 1000/f, r, u, d, o, s, w, 1000/w }' >> "$csv"
}

for scene in "$m/cow.glb" "$m/duck.glb" "$m/engine.glb" builtin:tiny; do
  for size in 1280x720 1920x1080; do
    for ov in on off; do run "$scene" "$size" "$ov" on; done
    run "$scene" "$size" off off
  done
done

# Window screenshots (overlay included) for the docs.
"$viewer" "$m/duck.glb" --size 1280x720 --no-vsync --frames 60 --window-screenshot "$out/viewer_duck_window.png" >> "$log" 2>&1
"$viewer" builtin:tiny --size 1280x720 --no-vsync --frames 60 --window-screenshot "$out/viewer_tiny_window.png" >> "$log" 2>&1

# The soak: 100,000 frames orbiting and toggling every mode key.
soak_frames=100000
[ "$quick" = --quick ] && soak_frames=5000
python3 scripts/measure/viewer_soak.py --viewer "$viewer" --frames "$soak_frames" --size 640x360 --sample-every 10000 \
  --scene "$m/duck.glb" --json "$out/viewer_soak.json" > "$out/viewer_soak.txt" 2>&1
echo "soak exit $?" >> "$out/viewer_soak.txt"
cat "$csv"
tail -4 "$out/viewer_soak.txt"

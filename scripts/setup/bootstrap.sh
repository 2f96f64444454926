#!/usr/bin/env bash
# Bootstrap the build dependencies of the Kokkos rasterizer on Debian 12 (bookworm).
#
#   bash scripts/setup/bootstrap.sh [--no-viewer] [--hip [--hip-arch gfx90a|gfx908|gfx906]]
#
# Idempotent: installs only the Debian packages that are missing (apt-get update only
# when something must be installed) and builds Kokkos only when none is found.
#
# Kokkos resolution, first match wins:
#   1. <repo>/.deps/kokkos/install already holds a KokkosConfig.cmake  -> nothing to do
#   2. env Kokkos_ROOT is set, or an OpenMP-enabled KokkosConfig.cmake is
#      found under /usr/local, /usr, /opt                               -> nothing to do
#   3. env RAST_KOKKOS_SOURCE points at a Kokkos source tree            -> build + install it
#   4. Kokkos 3.4.1 from Debian's trilinos source package (deb-src)     -> build + install it
# Builds install into <repo>/.deps/kokkos/install (OpenMP + Serial, Release, C++17), which
# cmake/RastKokkos.cmake finds without further flags.
#
# With --hip it also installs Debian's HIP compiler (hipcc, libamdhip64-dev 5.2.3, which
# pull clang-15 and the ROCm device libraries) and builds the same Kokkos 3.4.1 source with
# its HIP backend (+ Serial) for one AMD GPU architecture into <repo>/.deps/kokkos-hip/install,
# which `cmake --preset hip` finds. Kokkos 3.4.1 predates gfx90a: the script adds that
# architecture option to a private copy of the source (see patch_kokkos_hip_arch).
# gfx1030 (RDNA2) is refused with the reason: it needs a Kokkos >= 4 (docs/hip.md).
#
# Options:
#   --check-source-index  only make Debian's trilinos source package visible to apt
#                (the step fresh machines failed at random), then stop
#   --no-viewer  skip the windowed viewer's packages (GLFW, Dear ImGui, Xvfb, Mesa GL/EGL),
#                which are installed by default so that the viewer is built and tested
#   --hip        also install hipcc and build Kokkos with HIP (default architecture gfx90a)
#   --hip-arch A AMD GPU architecture for --hip (implies it): gfx90a (MI200, default),
#                gfx908 (MI100), gfx906 (MI50/60); not gfx1030 (see docs/hip.md)
#   -h|--help  show this help
set -euo pipefail

REPO_ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
DEPS_DIR="$REPO_ROOT/.deps"
SRC_CACHE="$DEPS_DIR/src"
KOKKOS_DIR="$DEPS_DIR/kokkos"
KOKKOS_PREFIX="$KOKKOS_DIR/install"
KOKKOS_LOG="$KOKKOS_DIR/build.log"
KOKKOS_STAMP="$KOKKOS_DIR/STAMP"
DEB_SRC_FILE=/etc/apt/sources.list.d/rast-bookworm-src.sources
APT_LOCK_OPT=(-o DPkg::Lock::Timeout=600)

log() { printf '[bootstrap] %s\n' "$*"; }
# Under `set -o pipefail` a reader that stops early (grep -q, head) kills the writer with
# SIGPIPE and fails the pipeline at random. Every filter below reads its whole input:
# grep to /dev/null instead of grep -q, first_line instead of head -n1.
first_line() { sed -n '1p'; }
die() { printf '[bootstrap] ERROR: %s\n' "$*" >&2; exit 1; }

WITH_VIEWER=1
CHECK_SRC_ONLY=0
WITH_HIP=0
HIP_ARCH=gfx90a
while [ "$#" -gt 0 ]; do
  arg="$1"; shift
  case "$arg" in
    --check-source-index) CHECK_SRC_ONLY=1 ;;
    --hip) WITH_HIP=1 ;;
    --hip-arch) [ "$#" -gt 0 ] || die "--hip-arch needs an architecture (gfx90a, gfx1030, ...)"
                WITH_HIP=1; HIP_ARCH="$1"; shift ;;
    --hip-arch=*) WITH_HIP=1; HIP_ARCH="${arg#--hip-arch=}" ;;
    --viewer) WITH_VIEWER=1 ;;  # the default; kept for compatibility
    --no-viewer) WITH_VIEWER=0 ;;
    -h|--help) sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) die "unknown argument: $arg (try --help)" ;;
  esac
done

# Kokkos' name for each AMD GPU architecture (Kokkos_ARCH_<name>).
case "$HIP_ARCH" in
  gfx90a) HIP_KOKKOS_ARCH=VEGA90A ;;
  # RDNA (gfx10xx) runs 32-wide wavefronts; Kokkos 3.4.1's HIP backend hard-codes 64
  # (HIPTraits::WarpSize, 32-bit __ballot masks in its atomics, team reductions and scans),
  # and HIP 5.2's own header refuses the 64-wide mode on GFX10 ("HIP is not supported on
  # GFX10 with wavefront size 64"). Only a Kokkos that knows 32-wide wavefronts (4.x) works.
  gfx1030|gfx10*) die "--hip-arch $HIP_ARCH: Kokkos 3.4.1 assumes 64-wide wavefronts and HIP 5.2 refuses them on RDNA (gfx10xx); build a Kokkos >= 4 with HIP for it and set Kokkos_ROOT (docs/hip.md)" ;;
  gfx908) HIP_KOKKOS_ARCH=VEGA908 ;;
  gfx906) HIP_KOKKOS_ARCH=VEGA906 ;;
  *) die "unsupported --hip-arch $HIP_ARCH (gfx90a, gfx908 or gfx906)" ;;
esac

T_START=$(date +%s)

# ---------------------------------------------------------------- privileges
SUDO=()
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO=(sudo); else SUDO=(__no_root__); fi
fi
as_root() {
  if [ "${SUDO[0]:-}" = "__no_root__" ]; then
    die "need root for: $* (run as root or install sudo)"
  fi
  "${SUDO[@]}" "$@"
}
export DEBIAN_FRONTEND=noninteractive

APT_UPDATED=0
apt_update() {
  if [ "$APT_UPDATED" -eq 0 ]; then
    log "apt-get update"
    as_root env DEBIAN_FRONTEND=noninteractive apt-get "${APT_LOCK_OPT[@]}" update -qq
    APT_UPDATED=1
  fi
}

# Makes trilinos' source package visible to apt (a deb-src entry for bookworm
# copied from the machine's own, then apt-get update) unless it already is.
ensure_src_index() {
  have_src_index() { apt-cache showsrc --only-source trilinos 2>/dev/null | grep '^Package: trilinos$' >/dev/null; }
  if ! have_src_index; then
    if [ ! -e "$DEB_SRC_FILE" ]; then
      # copy URIs/Signed-By of the machine's own bookworm entry (deb822 or one-line format)
      uris="" signed=""
      if [ -r /etc/apt/sources.list.d/debian.sources ]; then
        stanza="$(awk 'BEGIN{RS=""} /(^|\n)Suites:[^\n]*[ \t]bookworm([ \t\n]|$)/ {print; exit}' \
                   /etc/apt/sources.list.d/debian.sources)"
        uris="$(printf '%s\n' "$stanza" | sed -n 's/^URIs:[[:space:]]*//p' | first_line)"
        signed="$(printf '%s\n' "$stanza" | sed -n 's/^Signed-By:[[:space:]]*//p' | first_line)"
      fi
      if [ -z "$uris" ] && [ -r /etc/apt/sources.list ]; then
        uris="$(awk '$1=="deb" && $0 ~ / bookworm / {for(i=2;i<=NF;i++) if ($i ~ /^[a-z]+:\/\//) {print $i; exit}}' /etc/apt/sources.list)"
      fi
      uris="${uris:-http://deb.debian.org/debian}"
      signed="${signed:-/usr/share/keyrings/debian-archive-keyring.gpg}"
      log "adding deb-src entry $DEB_SRC_FILE ($uris)"
      printf 'Types: deb-src\nURIs: %s\nSuites: bookworm\nComponents: main\nSigned-By: %s\n' \
        "$uris" "$signed" | as_root tee "$DEB_SRC_FILE" >/dev/null
    fi
    APT_UPDATED=0
    apt_update
    have_src_index || die "no trilinos source package visible after apt-get update"
  fi
}

if [ "$CHECK_SRC_ONLY" -eq 1 ]; then  # the step that failed at random (scripts/setup/check_bootstrap_repeat.sh)
  ensure_src_index
  log "trilinos source package visible"
  exit 0
fi

# ---------------------------------------------------------------- Debian packages
PACKAGES=(build-essential cmake ninja-build git pkg-config ca-certificates xz-utils dpkg-dev
          libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev catch2 libcli11-dev
          python3 python3-matplotlib assimp-testmodels
          libdraco-dev libmeshoptimizer-dev ffmpeg  # compressed glTF (docs/compression.md), videos (docs/animation.md)
          python3-dev python3-numpy pybind11-dev python3-pybind11 libdlpack-dev python3-torch  # the Python module (python/, docs/python.md; torch for its DLPack tests)
          python3-pip python3-setuptools python3-wheel  # `pip install .` (tests/cli/cli_pip_install.py)
          libopenexr-dev  # -o F.exr (app/exr_output.h)
          clang-14 libclang-rt-14-dev libomp-14-dev  # libFuzzer + ASan/UBSan (scripts/fuzz/fuzz_loader.sh)
          libopenmpi-dev openmpi-bin)  # distributed runs, RAST_MPI (docs/distributed.md, tests/cli/cli_distributed.py)
VIEWER_PACKAGES=(libglfw3-dev libimgui-dev xvfb xauth libgl1-mesa-dri libegl-mesa0
                 libgl-dev libegl-dev libopengl-dev)
[ "$WITH_VIEWER" -eq 1 ] && PACKAGES+=("${VIEWER_PACKAGES[@]}")
# AMD GPU build (--hip): Debian's HIP 5.2.3 compiler driver and runtime headers/library.
HIP_PACKAGES=(hipcc libamdhip64-dev)
[ "$WITH_HIP" -eq 1 ] && PACKAGES+=("${HIP_PACKAGES[@]}")
# ---- glref reference renderer: tests/cli/cli_glref_agreement.py builds ../shared/tools/glref
# (libepoxy, EGL/OpenGL headers; tinygltf/stb/glm/json are above) and runs it on Mesa
# llvmpipe through EGL (libegl-mesa0, libgl1-mesa-dri). See docs/glref-agreement.md.
GLREF_PACKAGES=(libepoxy-dev libegl-dev libopengl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri)
for p in "${GLREF_PACKAGES[@]}"; do
  case " ${PACKAGES[*]} " in *" $p "*) ;; *) PACKAGES+=("$p") ;; esac
done
# ---- end glref

# "ii" = installed and configured; anything else (absent, half-configured, ...) is missing
INSTALLED=" $(dpkg-query -W -f='${db:Status-Abbrev}${Package}\n' "${PACKAGES[@]}" 2>/dev/null \
              | awk '/^ii/ {printf "%s ", substr($0, 4)}' || true)"
MISSING=()
for p in "${PACKAGES[@]}"; do
  case "$INSTALLED" in *" $p "*) ;; *) MISSING+=("$p") ;; esac
done
if [ "${#MISSING[@]}" -gt 0 ]; then
  log "installing missing packages: ${MISSING[*]}"
  apt_update
  as_root env DEBIAN_FRONTEND=noninteractive apt-get "${APT_LOCK_OPT[@]}" install -y -qq \
      --no-install-recommends "${MISSING[@]}" >/dev/null
  log "packages installed"
else
  log "all ${#PACKAGES[@]} Debian packages already installed"
fi

# ---------------------------------------------------------------- Kokkos
kokkos_config_in() {  # prints the first KokkosConfig.cmake below prefix $1
  find "$1" -maxdepth 5 -path '*/cmake/Kokkos/KokkosConfig.cmake' -print -quit 2>/dev/null || true
}

kokkos_has_openmp() {  # $1 = directory holding KokkosConfig.cmake
  grep -rqsiE 'Kokkos_DEVICES[" ]+[^)]*OPENMP' "$1" 2>/dev/null
}

finish() {
  log "done in $(( $(date +%s) - T_START )) s"
  exit 0
}

build_kokkos() {  # $1 = Kokkos source dir, $2 = description of where it came from
  local src="$1" origin="$2" t0 t1
  [ -f "$src/CMakeLists.txt" ] && [ -d "$src/core/src" ] || die "$src is not a Kokkos source tree"
  mkdir -p "$KOKKOS_DIR"
  rm -rf "$KOKKOS_DIR/build"
  : >"$KOKKOS_LOG"
  log "configuring Kokkos from $src (log: $KOKKOS_LOG)"
  t0=$(date +%s)
  if ! cmake -S "$src" -B "$KOKKOS_DIR/build" -G Ninja \
        -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_CXX_STANDARD=17 \
        -DCMAKE_POSITION_INDEPENDENT_CODE=ON \
        -DCMAKE_INSTALL_PREFIX="$KOKKOS_PREFIX" \
        -DKokkos_ENABLE_OPENMP=ON \
        -DKokkos_ENABLE_SERIAL=ON \
        -DKokkos_ENABLE_TESTS=OFF \
        -DKokkos_ENABLE_EXAMPLES=OFF >>"$KOKKOS_LOG" 2>&1; then
    tail -n 30 "$KOKKOS_LOG" >&2; die "Kokkos configure failed (see $KOKKOS_LOG)"
  fi
  log "building + installing Kokkos into $KOKKOS_PREFIX"
  if ! cmake --build "$KOKKOS_DIR/build" --parallel "$(nproc)" >>"$KOKKOS_LOG" 2>&1 \
     || ! cmake --install "$KOKKOS_DIR/build" >>"$KOKKOS_LOG" 2>&1; then
    tail -n 30 "$KOKKOS_LOG" >&2; die "Kokkos build failed (see $KOKKOS_LOG)"
  fi
  t1=$(date +%s)
  local cfg version
  cfg="$(ls "$KOKKOS_PREFIX"/lib*/cmake/Kokkos/KokkosConfig.cmake | first_line)"
  version="$(sed -n 's/.*PACKAGE_VERSION "\([0-9.]*\)".*/\1/p' "$(dirname "$cfg")/KokkosConfigVersion.cmake" | first_line)"
  {
    echo "kokkos_version=${version:-unknown}"
    echo "origin=$origin"
    echo "source=$src"
    echo "prefix=$KOKKOS_PREFIX"
    echo "config=$cfg"
    echo "devices=OpenMP;Serial"
    echo "build_seconds=$((t1 - t0))"
    echo "built_at=$(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "compiler=$(c++ --version | first_line)"
  } >"$KOKKOS_STAMP"
  log "Kokkos ${version:-?} installed in $((t1 - t0)) s: $cfg"
}

# Kokkos 3.4.1 out of Debian's trilinos source package (packages/kokkos), extracted once
# into $KOKKOS_DIR/src; sets KOKKOS_SRC and KOKKOS_ORIGIN. Used by both Kokkos builds.
kokkos_debian_source() {
  if [ -f "$KOKKOS_DIR/src/CMakeLists.txt" ]; then  # extracted before: no tarball needed
    KOKKOS_SRC="$KOKKOS_DIR/src"
    KOKKOS_ORIGIN="$(sed -n 's/^origin=//p' "$KOKKOS_STAMP" 2>/dev/null | first_line || true)"
    KOKKOS_ORIGIN="${KOKKOS_ORIGIN:-debian-trilinos-source (extracted in $KOKKOS_SRC)}"
    return 0
  fi
  mkdir -p "$SRC_CACHE"
  orig_tarball() { ls "$SRC_CACHE"/trilinos_*.orig.tar.* 2>/dev/null | first_line || true; }

  if [ -z "$(orig_tarball)" ]; then
    ensure_src_index
    log "downloading Debian trilinos source package into $SRC_CACHE (~166 MB)"
    sandbox=()
    [ "$(id -u)" -eq 0 ] && sandbox=(-o APT::Sandbox::User=root)
    (cd "$SRC_CACHE" && apt-get "${sandbox[@]}" -qq source --download-only trilinos >/dev/null)
    [ -n "$(orig_tarball)" ] || die "apt-get source trilinos did not produce an orig tarball"
  else
    log "using cached $(orig_tarball)"
  fi

  tarball="$(orig_tarball)"
  kokkos_src="$KOKKOS_DIR/src"
  if [ ! -f "$kokkos_src/CMakeLists.txt" ]; then
    log "extracting packages/kokkos from $(basename "$tarball")"
    tmp="$KOKKOS_DIR/extract.tmp"
    rm -rf "$tmp" "$kokkos_src"
    mkdir -p "$tmp"
    tar -xf "$tarball" -C "$tmp" --wildcards '*/packages/kokkos/*'
    found="$(find "$tmp" -maxdepth 3 -type d -path '*/packages/kokkos' -print -quit)"
    [ -n "$found" ] || die "packages/kokkos not found in $tarball"
    mv "$found" "$kokkos_src"
    rm -rf "$tmp"
  fi
  KOKKOS_SRC="$kokkos_src"
  KOKKOS_ORIGIN="debian-trilinos-source:$(basename "$tarball")"
}

# The host Kokkos (OpenMP + Serial) every build uses, unless one is already there.
ensure_host_kokkos() {
  existing="$(ls "$KOKKOS_PREFIX"/lib*/cmake/Kokkos/KokkosConfig.cmake 2>/dev/null | first_line || true)"
  if [ -n "$existing" ]; then
    log "Kokkos already installed: $existing"
    return 0
  fi

  if [ -n "${Kokkos_ROOT:-}" ]; then
    log "Kokkos_ROOT=$Kokkos_ROOT is set: using it, not building Kokkos"
    return 0
  fi

  for prefix in /usr/local /usr /opt; do
    cfg="$(kokkos_config_in "$prefix")"
    if [ -n "$cfg" ]; then
      if kokkos_has_openmp "$(dirname "$cfg")"; then
        log "found system Kokkos with OpenMP: $cfg (not building Kokkos)"
        return 0
      else
        log "ignoring $cfg: no OpenMP backend (e.g. Debian's serial-only libtrilinos-kokkos-dev)"
      fi
    fi
  done

  if [ -n "${RAST_KOKKOS_SOURCE:-}" ]; then
    [ -d "$RAST_KOKKOS_SOURCE" ] || die "RAST_KOKKOS_SOURCE=$RAST_KOKKOS_SOURCE is not a directory"
    build_kokkos "$(cd "$RAST_KOKKOS_SOURCE" && pwd)" "RAST_KOKKOS_SOURCE"
    return 0
  fi

  kokkos_debian_source
  build_kokkos "$KOKKOS_SRC" "$KOKKOS_ORIGIN"
}

# --- HIP (--hip): Kokkos 3.4.1 with its HIP backend, for one AMD GPU architecture ---
HIP_KOKKOS_DIR="$DEPS_DIR/kokkos-hip"
HIP_KOKKOS_PREFIX="$HIP_KOKKOS_DIR/install"
HIP_KOKKOS_LOG="$HIP_KOKKOS_DIR/build.log"
HIP_KOKKOS_STAMP="$HIP_KOKKOS_DIR/STAMP"

# Kokkos 3.4.1 knows AMD GPUs up to gfx908 (MI100). Its HIP backend itself compiles for
# gfx90a (MI200, 64-wide wavefronts like gfx908) with Debian's hipcc 5.2.3 (clang 15); only
# the CMake option that names the architecture is missing. Adds Kokkos_ARCH_VEGA90A beside
# VEGA908, the same way VEGA908 is declared, to the private copy in $1.
patch_kokkos_hip_arch() {
  local f="$1/cmake/kokkos_arch.cmake"
  if grep -F 'VEGA90A' "$f" >/dev/null; then return 0; fi  # a Kokkos that knows gfx90a
  grep -F 'KOKKOS_ARCH_OPTION(VEGA908 ' "$f" >/dev/null && grep -F 'CHECK_AMDGPU_ARCH(VEGA908 gfx908)' "$f" >/dev/null \
    || die "$f: no VEGA908 entries to add gfx90a beside (not Kokkos 3.4?)"
  sed -i \
    -e '/^KOKKOS_ARCH_OPTION(VEGA908 /a KOKKOS_ARCH_OPTION(VEGA90A         GPU  "AMD GPU MI200 GFX90A (added by rast bootstrap.sh)")' \
    -e '/^CHECK_AMDGPU_ARCH(VEGA908 gfx908)/a CHECK_AMDGPU_ARCH(VEGA90A gfx90a)' \
    "$f"
  grep -F 'CHECK_AMDGPU_ARCH(VEGA90A gfx90a)' "$f" >/dev/null || die "patching $f failed"
}

ensure_hip_kokkos() {
  local cfg stamp_arch t0 t1 src
  cfg="$(ls "$HIP_KOKKOS_PREFIX"/lib*/cmake/Kokkos/KokkosConfig.cmake 2>/dev/null | first_line || true)"
  stamp_arch="$(sed -n 's/^hip_arch=//p' "$HIP_KOKKOS_STAMP" 2>/dev/null | first_line || true)"
  if [ -n "$cfg" ] && [ "$stamp_arch" = "$HIP_ARCH" ]; then
    log "Kokkos with HIP for $HIP_ARCH already installed: $cfg"
    return 0
  fi
  command -v hipcc >/dev/null 2>&1 || die "hipcc not found after installing ${HIP_PACKAGES[*]}"
  kokkos_debian_source
  # A private, patched copy: the host Kokkos' source stays as Debian ships it.
  src="$HIP_KOKKOS_DIR/src"
  rm -rf "$src" "$HIP_KOKKOS_DIR/build" "$HIP_KOKKOS_PREFIX"
  mkdir -p "$HIP_KOKKOS_DIR"
  cp -a "$KOKKOS_SRC" "$src"
  patch_kokkos_hip_arch "$src"
  : >"$HIP_KOKKOS_LOG"
  log "configuring Kokkos with HIP for $HIP_ARCH (Kokkos_ARCH_$HIP_KOKKOS_ARCH; log: $HIP_KOKKOS_LOG)"
  t0=$(date +%s)
  if ! cmake -S "$src" -B "$HIP_KOKKOS_DIR/build" -G Ninja \
        -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_CXX_STANDARD=17 \
        -DCMAKE_CXX_COMPILER=hipcc \
        -DCMAKE_INSTALL_PREFIX="$HIP_KOKKOS_PREFIX" \
        -DKokkos_ENABLE_HIP=ON \
        -DKokkos_ENABLE_SERIAL=ON \
        "-DKokkos_ARCH_$HIP_KOKKOS_ARCH=ON" \
        -DKokkos_ENABLE_TESTS=OFF \
        -DKokkos_ENABLE_EXAMPLES=OFF >>"$HIP_KOKKOS_LOG" 2>&1; then
    tail -n 30 "$HIP_KOKKOS_LOG" >&2; die "Kokkos (HIP) configure failed (see $HIP_KOKKOS_LOG)"
  fi
  log "building + installing Kokkos (HIP) into $HIP_KOKKOS_PREFIX"
  if ! cmake --build "$HIP_KOKKOS_DIR/build" --parallel "$(nproc)" >>"$HIP_KOKKOS_LOG" 2>&1 \
     || ! cmake --install "$HIP_KOKKOS_DIR/build" >>"$HIP_KOKKOS_LOG" 2>&1; then
    tail -n 30 "$HIP_KOKKOS_LOG" >&2; die "Kokkos (HIP) build failed (see $HIP_KOKKOS_LOG)"
  fi
  t1=$(date +%s)
  cfg="$(ls "$HIP_KOKKOS_PREFIX"/lib*/cmake/Kokkos/KokkosConfig.cmake | first_line)"
  {
    echo "origin=$KOKKOS_ORIGIN (patched: scripts/setup/bootstrap.sh patch_kokkos_hip_arch)"
    echo "prefix=$HIP_KOKKOS_PREFIX"
    echo "config=$cfg"
    echo "devices=HIP;Serial"
    echo "hip_arch=$HIP_ARCH"
    echo "kokkos_arch=$HIP_KOKKOS_ARCH"
    echo "build_seconds=$((t1 - t0))"
    echo "built_at=$(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "compiler=$(hipcc --version 2>/dev/null | grep -E 'HIP version|clang version' | tr '\n' ' ' || true)"
  } >"$HIP_KOKKOS_STAMP"
  log "Kokkos with HIP for $HIP_ARCH installed in $((t1 - t0)) s: $cfg"
}

ensure_host_kokkos
if [ "$WITH_HIP" -eq 1 ]; then
  ensure_hip_kokkos
fi
finish

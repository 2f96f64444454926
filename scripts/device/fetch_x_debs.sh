#!/usr/bin/env bash
# Download (not install) the Debian packages that scripts/device/viewer_bench.sh
# unpacks on the GPU machine to open GLX windows there: Xvfb with its GLX
# extension (Mesa's swrast driver and LLVM) into .xmesa/, everything else
# (GLFW, libglvnd, X client libraries, xkbcomp, glxinfo; Draco and meshoptimizer,
# which the glTF loader links) into .xdeb/. Two
# folders because one call to the GPU machine carries at most 64 MiB: the
# first call unpacks .xmesa, the next ones carry .xdeb and the binaries.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
cd "$root"
exclude=$(git rev-parse --git-path info/exclude)
for d in .xdeb .xmesa .dview; do
  grep -qxF "/$d/" "$exclude" 2>/dev/null || echo "/$d/" >> "$exclude"
done
mesa="libgl1-mesa-dri libllvm15 libz3-4 libicu72 libxml2"
rest="libaudit-common libaudit1 libbrotli1 libbsd0 libbz2-1.0 libcap-ng0 libcap2 libdrm-amdgpu1 libdrm-common
libdrm-intel1 libdrm-nouveau2 libdrm-radeon1 libdrm2 libedit2 libegl-mesa0 libegl1 libelf1 libexpat1 libffi8
libfontenc1 libfreetype6 libgbm1 libgl1 libglapi-mesa libgles2 libglfw3 libglvnd0 libglx-mesa0 libglx0 libice6
liblz4-1 libmd0 libopengl0 libpciaccess0 libpixman-1-0 libpng16-16 libsensors-config libsensors5 libsm6 libstb0
libtinfo6 libunwind8 libwayland-client0 libwayland-egl1 libwayland-server0 libx11-6 libx11-data libx11-xcb1
libxau6 libxaw7 libxcb-dri2-0 libxcb-dri3-0 libxcb-glx0 libxcb-present0 libxcb-randr0 libxcb-shm0 libxcb-sync1
libxcb-xfixes0 libxcb1 libxdmcp6 libxext6 libxfixes3 libxfont2 libxkbfile1 libxmu6 libxpm4 libxrandr2 libxrender1
libxshmfence1 libxt6 libxxf86vm1 mesa-utils mesa-utils-bin x11-common x11-xkb-utils xkb-data xserver-common xvfb
libgomp1 libepoxy0 libdraco7 libmeshoptimizer2d"
mkdir -p .xmesa .xdeb
(cd .xmesa && apt-get download $mesa)
(cd .xdeb && apt-get download $rest)
du -sh .xmesa .xdeb

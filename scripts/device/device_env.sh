# Sourced by the GPU-machine scripts (session_h100.sh; before distributed_scale.sh):
# the environment .device/ binaries need there. Why a file of its own: which
# OpenMPI the binaries load must be decided the same way by every script.
#  - .device/lib: Debian's runtime libraries the builds link (libgomp, Draco,
#    meshoptimizer, OpenEXR), in case the machine lacks them;
#  - OpenMPI: the machine's own libmpi.so.40 (OpenMPI 4.1.x, the soname of
#    Debian's 4.1.4) when ldconfig or its mpirun's lib folder has one, so that
#    mpirun and the library agree; else Debian's from .device/lib-mpi, enough
#    for single-process runs (they never start MPI);
#  - NCCL from the machine's PyTorch environment (rast loads it at run time);
#  - NCCL_NVLS_ENABLE=0 on the shared hosts; mpirun as root allowed.
_dev_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
_dev=$_dev_root/.device
_prepend() { [ -d "$1" ] && export LD_LIBRARY_PATH="$1${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"; return 0; }
export OMP_PROC_BIND=false NCCL_NVLS_ENABLE=0 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
RAST_DEVICE_MPI=$(ldconfig -p 2>/dev/null | awk '/libmpi\.so\.40 / {print $NF; exit}')
if [ -z "$RAST_DEVICE_MPI" ] && command -v mpirun > /dev/null; then
  _d=$(cd "$(dirname "$(readlink -f "$(command -v mpirun)")")/../lib" 2>/dev/null && pwd)
  if [ -n "$_d" ] && [ -e "$_d/libmpi.so.40" ]; then RAST_DEVICE_MPI=$_d/libmpi.so.40; _prepend "$_d"; fi
fi
[ -z "$RAST_DEVICE_MPI" ] && _prepend "$_dev/lib-mpi" && RAST_DEVICE_MPI="$_dev/lib-mpi (Debian's, no mpirun)"
_prepend "$_dev/lib"
_nccl=$(python3 -c 'import nvidia.nccl; print(list(nvidia.nccl.__path__)[0])' 2>/dev/null || true)
[ -n "$_nccl" ] && [ -e "$_nccl/lib/libnccl.so.2" ] && _prepend "$_nccl/lib"
export RAST_DEVICE_MPI
echo "device_env: MPI $RAST_DEVICE_MPI; mpirun $(command -v mpirun || echo none); NCCL ${_nccl:-none}"

# RastHip.cmake -- HIP-only build settings (included when RAST_EXEC_SPACE is HIP).
#
# hipcc compiles every .cpp as HIP and, when a compile or link line names no
# GPU architecture, asks rocm_agent_enumerator for the machine's GPU (printing
# a Python traceback where there is none, as in CI). Kokkos' targets carry the
# architecture it was built for (--amdgpu-target=gfxNNN); pass the same flag to
# the links, and let rast_thirdparty, which does not use Kokkos, see it too
# (RAST_HIP_ARCH_FLAG).
include_guard(GLOBAL)

set(RAST_HIP_ARCH_FLAG "")
foreach(_tgt Kokkos::kokkoscore Kokkos::kokkos)
  if(TARGET ${_tgt} AND NOT RAST_HIP_ARCH_FLAG)
    get_target_property(_opts ${_tgt} INTERFACE_COMPILE_OPTIONS)
    string(REGEX MATCH "--(amdgpu-target|offload-arch)=gfx[0-9a-z]+" RAST_HIP_ARCH_FLAG "${_opts}")
  endif()
endforeach()
if(RAST_HIP_ARCH_FLAG)
  add_link_options(${RAST_HIP_ARCH_FLAG})
  message(STATUS "RastHip: ${RAST_HIP_ARCH_FLAG}")
else()
  message(WARNING "RastHip: no AMD GPU architecture found in Kokkos' compile options "
                  "(was Kokkos built with Kokkos_ENABLE_HIP and a Kokkos_ARCH_VEGA*/NAVI* option?)")
endif()
unset(_opts)
unset(_tgt)

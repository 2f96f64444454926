# RastCuda.cmake -- CUDA-only build settings (included when RAST_EXEC_SPACE is Cuda).
#
# Static CUDA runtime. An installed CUDA Kokkos exports Kokkos::kokkos with
# INTERFACE_LINK_LIBRARIES "CUDA::cuda_driver;CUDA::cudart", and CUDA::cudart is
# the shared libcudart.so.<major>. A binary linked that way only starts where the
# same CUDA runtime major version is installed. nvcc links libcudart_static by
# default anyway, so pointing CUDA::cudart at the static archive (plus its
# dl/rt/pthread dependencies) leaves only libcuda.so, which comes with the
# driver, as a CUDA dependency: the binaries run on any machine whose driver is
# at least as new as the toolkit they were built with.
#
# Set RAST_CUDA_STATIC_RUNTIME=OFF to keep Kokkos' shared runtime.
include_guard(GLOBAL)

option(RAST_CUDA_STATIC_RUNTIME "link the CUDA runtime statically (libcudart_static)" ON)

if(NOT TARGET CUDA::cudart_static AND NOT TARGET CUDA::cudart)
  # Kokkos built in-tree (source/download route) does not always load FindCUDAToolkit.
  find_package(CUDAToolkit QUIET)
endif()

if(RAST_CUDA_STATIC_RUNTIME AND TARGET CUDA::cudart AND TARGET CUDA::cudart_static)
  get_target_property(_rast_cudart_static CUDA::cudart_static IMPORTED_LOCATION)
  get_target_property(_rast_cudart_imported CUDA::cudart IMPORTED)
  if(_rast_cudart_static AND _rast_cudart_imported)
    set_target_properties(CUDA::cudart PROPERTIES IMPORTED_LOCATION "${_rast_cudart_static}")
    # Per-configuration locations would win over IMPORTED_LOCATION; drop them.
    foreach(_cfg RELEASE DEBUG RELWITHDEBINFO MINSIZEREL NOCONFIG)
      get_target_property(_loc CUDA::cudart IMPORTED_LOCATION_${_cfg})
      if(_loc)
        set_target_properties(CUDA::cudart PROPERTIES IMPORTED_LOCATION_${_cfg} "${_rast_cudart_static}")
      endif()
    endforeach()
    set_property(TARGET CUDA::cudart PROPERTY IMPORTED_SONAME "")
    set_property(TARGET CUDA::cudart PROPERTY IMPORTED_NO_SONAME TRUE)
    if(TARGET CUDA::cudart_static_deps)
      set_property(TARGET CUDA::cudart APPEND PROPERTY INTERFACE_LINK_LIBRARIES CUDA::cudart_static_deps)
    else()
      find_package(Threads REQUIRED)
      set_property(TARGET CUDA::cudart APPEND PROPERTY INTERFACE_LINK_LIBRARIES
                   Threads::Threads ${CMAKE_DL_LIBS} rt)
    endif()
    message(STATUS "RastCuda: static CUDA runtime (${_rast_cudart_static})")
  endif()
  unset(_rast_cudart_static)
  unset(_rast_cudart_imported)
  unset(_loc)
elseif(RAST_CUDA_STATIC_RUNTIME)
  message(STATUS "RastCuda: CUDA::cudart / CUDA::cudart_static not found; runtime linkage left to Kokkos")
endif()

# backends/backend_cuda.cpp includes <cuda_runtime.h>. nvcc (through nvcc_wrapper)
# finds it on its own; name the toolkit's include directory too for tools reading
# compile_commands.json -- unless it is a system directory (Debian's toolkit lives
# in /usr/include), where -isystem would reorder the C library's headers.
if(CUDAToolkit_INCLUDE_DIRS)
  foreach(_dir ${CUDAToolkit_INCLUDE_DIRS})
    if(NOT _dir MATCHES "^/usr(/local)?/include/?$")
      include_directories(SYSTEM "${_dir}")
    endif()
  endforeach()
  unset(_dir)
endif()

# The Python module (python/, docs/python.md): `import rast`, built with
# Debian's pybind11 for Debian's Python (/usr/bin/python3, which has numpy),
# even when another python3 comes first on PATH. RAST_PYTHON defaults to ON
# when pybind11 and the Python headers are found.
include_guard(GLOBAL)
if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "Python the rast module is built for")
endif()
set(PYBIND11_FINDPYTHON ON)
find_package(pybind11 CONFIG QUIET)
# DLPack's header (Debian's libdlpack-dev): the module's arrays in and out.
find_path(RAST_DLPACK_INCLUDE_DIR dlpack/dlpack.h)

# The module is a shared object that links the static libraries, Kokkos'
# included: an installed static Kokkos built without -fPIC (Kokkos' default)
# cannot go into it, and the link fails late with relocation errors. So such a
# Kokkos is probed once (a shared library linking it) and named in one line at
# configure time. In-tree Kokkos (RastKokkos routes b, c) is built with this
# project's position-independent code; the bootstrap's Kokkos too.
function(_rast_kokkos_links_into_shared out)
  set(${out} TRUE PARENT_SCOPE)
  if(NOT RAST_KOKKOS_ROUTE STREQUAL "installed" OR NOT TARGET Kokkos::kokkoscore)
    return()
  endif()
  get_target_property(_type Kokkos::kokkoscore TYPE)
  if(NOT _type STREQUAL "STATIC_LIBRARY")
    return()
  endif()
  set(_key "${Kokkos_DIR}|${CMAKE_CXX_COMPILER}")
  if(DEFINED RAST_KOKKOS_SHARED_PROBE AND RAST_KOKKOS_SHARED_PROBE_KEY STREQUAL _key)
    set(${out} ${RAST_KOKKOS_SHARED_PROBE} PARENT_SCOPE)
    return()
  endif()
  set(_dir "${CMAKE_BINARY_DIR}/CMakeFiles/rast_kokkos_shared_probe")
  file(REMOVE_RECURSE "${_dir}")
  file(WRITE "${_dir}/CMakeLists.txt"
       "cmake_minimum_required(VERSION 3.16)\nproject(rast_kokkos_shared_probe CXX)\n"
       "find_package(Kokkos REQUIRED CONFIG)\nadd_library(probe SHARED probe.cpp)\n"
       "target_link_libraries(probe PRIVATE Kokkos::kokkos)\n")
  file(WRITE "${_dir}/probe.cpp"
       "#include <Kokkos_Core.hpp>\nint rast_probe() { Kokkos::initialize(); Kokkos::finalize(); return 0; }\n")
  message(STATUS "rast: checking that the static Kokkos (${Kokkos_DIR}) links into a shared object")
  try_compile(_ok "${_dir}/build" "${_dir}" rast_kokkos_shared_probe
              CMAKE_FLAGS "-DKokkos_DIR=${Kokkos_DIR}" "-DCMAKE_CXX_COMPILER=${CMAKE_CXX_COMPILER}"
                          "-DCMAKE_CXX_STANDARD=17"
              OUTPUT_VARIABLE _log)
  set(RAST_KOKKOS_SHARED_PROBE ${_ok} CACHE INTERNAL "")
  set(RAST_KOKKOS_SHARED_PROBE_KEY "${_key}" CACHE INTERNAL "")
  set(${out} ${_ok} PARENT_SCOPE)
endfunction()

set(_rast_python_default OFF)
set(_rast_kokkos_pic TRUE)
if((pybind11_FOUND AND Python_Development.Module_FOUND OR pybind11_FOUND AND Python_Development_FOUND)
   AND RAST_DLPACK_INCLUDE_DIR)
  _rast_kokkos_links_into_shared(_rast_kokkos_pic)
  set(_rast_python_default ${_rast_kokkos_pic})
endif()
string(CONCAT _rast_pic_hint "the Kokkos at ${Kokkos_DIR} is a static library built without -fPIC, which a Python "
                   "module cannot link: rebuild it with -DCMAKE_POSITION_INDEPENDENT_CODE=ON (docs/python.md)")
if(NOT _rast_kokkos_pic AND NOT DEFINED CACHE{RAST_PYTHON})
  message(STATUS "rast: Python module off by default: ${_rast_pic_hint}")
endif()
option(RAST_PYTHON "build the Python module (needs pybind11-dev python3-dev)" ${_rast_python_default})
if(NOT RAST_PYTHON)
  message(STATUS "rast: Python module not built (RAST_PYTHON=OFF; pybind11 found: ${pybind11_FOUND}, "
                 "dlpack/dlpack.h: ${RAST_DLPACK_INCLUDE_DIR})")
  return()
endif()
if(NOT pybind11_FOUND OR NOT RAST_DLPACK_INCLUDE_DIR)
  message(FATAL_ERROR "RAST_PYTHON=ON needs pybind11 and DLPack (Debian: pybind11-dev python3-pybind11 python3-dev libdlpack-dev)")
endif()
if(NOT _rast_kokkos_pic)
  message(FATAL_ERROR "RAST_PYTHON=ON: ${_rast_pic_hint}")
endif()
set(RAST_PYTHON_DIR ${PROJECT_BINARY_DIR}/python CACHE INTERNAL "")
pybind11_add_module(_rast MODULE python/rast_module.cpp)
target_link_libraries(_rast PRIVATE rast_lib)
target_include_directories(_rast PRIVATE ${RAST_DLPACK_INCLUDE_DIR})
set_target_properties(_rast PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${RAST_PYTHON_DIR}/rast)
# The pure-Python front (input conversion from numpy and DLPack) beside the extension.
configure_file(${PROJECT_SOURCE_DIR}/python/rast/__init__.py ${RAST_PYTHON_DIR}/rast/__init__.py COPYONLY)
message(STATUS "rast: Python module for ${Python_EXECUTABLE} in ${RAST_PYTHON_DIR}")

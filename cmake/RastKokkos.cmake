# RastKokkos.cmake -- resolve Kokkos for the rasterizer.
#
# include(cmake/RastKokkos.cmake) after project(). Afterwards:
#   Kokkos::kokkos          target to link against (imported, or Kokkos' in-tree alias)
#   Kokkos_VERSION          e.g. 3.4.01 / 4.7.01
#   Kokkos_DEVICES          enabled backends, upper case, e.g. OPENMP;SERIAL
#   RAST_KOKKOS_ROUTE       installed | source | download
#   RAST_EXEC_SPACE         cache STRING: Default | Serial | OpenMP | Cuda | HIP
#
# Routes, first match wins:
#   (a) installed: find_package(Kokkos CONFIG) honouring Kokkos_ROOT / CMAKE_PREFIX_PATH,
#       with ${PROJECT_SOURCE_DIR}/.deps/kokkos/install (scripts/setup/bootstrap.sh) as a hint,
#       or .deps/kokkos-hip/install (bootstrap.sh --hip) when RAST_EXEC_SPACE is HIP;
#   (b) source:    -DRAST_KOKKOS_SOURCE=<Kokkos source tree> is built in-tree
#                  (OpenMP+Serial by default, CUDA when -DKokkos_ENABLE_CUDA=ON);
#   (c) download:  RAST_KOKKOS_DOWNLOAD=ON (default) fetches the official Kokkos release
#                  tarball with FetchContent (needs internet);
#   (d) otherwise a fatal error pointing at scripts/setup/bootstrap.sh.
include_guard(GLOBAL)

if(POLICY CMP0074)   # find_package honours <Pkg>_ROOT (variable and environment)
  cmake_policy(SET CMP0074 NEW)
endif()
if(POLICY CMP0135)   # URL downloads: extracted files get the extraction time stamp
  cmake_policy(SET CMP0135 NEW)
endif()

set(RAST_EXEC_SPACE "Default" CACHE STRING
    "Kokkos execution space the rasterizer runs on (Default = Kokkos::DefaultExecutionSpace)")
set_property(CACHE RAST_EXEC_SPACE PROPERTY STRINGS Default Serial OpenMP Cuda HIP)

set(RAST_KOKKOS_SOURCE "" CACHE PATH
    "Local Kokkos source tree to build in-tree when no installed Kokkos is found")
option(RAST_KOKKOS_DOWNLOAD
       "Download a Kokkos release with FetchContent when no installed Kokkos is found" ON)
set(RAST_KOKKOS_URL
    "https://github.com/kokkos/kokkos/releases/download/4.7.01/kokkos-4.7.01.tar.gz"
    CACHE STRING "Kokkos release tarball used by RAST_KOKKOS_DOWNLOAD")
set(RAST_KOKKOS_URL_HASH
    "SHA256=404cf33e76159e83b8b4ad5d86f6899d442b5da4624820ab457412116cdcd201"
    CACHE STRING "Hash of RAST_KOKKOS_URL (ALGO=hex); empty disables the check")
set(RAST_CUDA_ARCH "" CACHE STRING
    "Kokkos GPU arch (e.g. HOPPER90, AMPERE80) for in-tree CUDA builds of Kokkos; empty = Kokkos' choice")

if(NOT DEFINED CMAKE_CXX_STANDARD)
  set(CMAKE_CXX_STANDARD 17)
endif()

# Backend defaults for in-tree (source/download) builds of Kokkos; cache entries the user
# set on the command line win.
macro(_rast_kokkos_intree_defaults)
  set(Kokkos_ENABLE_SERIAL ON CACHE BOOL "Kokkos Serial backend")
  set(Kokkos_ENABLE_OPENMP ON CACHE BOOL "Kokkos OpenMP backend")
  set(Kokkos_ENABLE_TESTS OFF CACHE BOOL "Kokkos unit tests")
  set(Kokkos_ENABLE_EXAMPLES OFF CACHE BOOL "Kokkos examples")
  if(Kokkos_ENABLE_CUDA AND RAST_CUDA_ARCH)
    set(Kokkos_ARCH_${RAST_CUDA_ARCH} ON CACHE BOOL "Kokkos GPU arch (from RAST_CUDA_ARCH)")
  endif()
  if(Kokkos_ENABLE_CUDA AND NOT CMAKE_CXX_COMPILER MATCHES "nvcc_wrapper|clang")
    message(WARNING "RastKokkos: Kokkos_ENABLE_CUDA=ON usually needs "
                    "CMAKE_CXX_COMPILER=<kokkos>/bin/nvcc_wrapper (now ${CMAKE_CXX_COMPILER})")
  endif()
endmacro()

# Kokkos_VERSION / Kokkos_DEVICES of an in-tree Kokkos live in its directory scope.
macro(_rast_kokkos_intree_info _dir)
  if(NOT Kokkos_VERSION)
    get_directory_property(Kokkos_VERSION DIRECTORY "${_dir}" DEFINITION Kokkos_VERSION)
  endif()
  if(NOT Kokkos_DEVICES)
    get_directory_property(Kokkos_DEVICES DIRECTORY "${_dir}" DEFINITION KOKKOS_ENABLED_DEVICES)
  endif()
  if(NOT Kokkos_DEVICES)
    get_directory_property(Kokkos_DEVICES DIRECTORY "${_dir}" DEFINITION Kokkos_DEVICES)
  endif()
endmacro()

set(RAST_KOKKOS_ROUTE "")

# (a) an installed Kokkos
if(RAST_EXEC_SPACE STREQUAL "HIP")
  set(_rast_kokkos_hint "${PROJECT_SOURCE_DIR}/.deps/kokkos-hip/install")
else()
  set(_rast_kokkos_hint "${PROJECT_SOURCE_DIR}/.deps/kokkos/install")
endif()
find_package(Kokkos CONFIG QUIET HINTS "${_rast_kokkos_hint}")
unset(_rast_kokkos_hint)
if(Kokkos_FOUND)
  set(RAST_KOKKOS_ROUTE "installed")
  set(_rast_kokkos_where "${Kokkos_DIR}")

# (b) a local Kokkos source tree, built in-tree
elseif(RAST_KOKKOS_SOURCE)
  get_filename_component(_rast_src "${RAST_KOKKOS_SOURCE}" ABSOLUTE BASE_DIR "${PROJECT_SOURCE_DIR}")
  if(NOT EXISTS "${_rast_src}/CMakeLists.txt" OR NOT IS_DIRECTORY "${_rast_src}/core/src")
    message(FATAL_ERROR "RastKokkos: RAST_KOKKOS_SOURCE=${RAST_KOKKOS_SOURCE} is not a Kokkos source tree")
  endif()
  _rast_kokkos_intree_defaults()
  add_subdirectory("${_rast_src}" "${CMAKE_BINARY_DIR}/_deps/kokkos-build")
  _rast_kokkos_intree_info("${_rast_src}")
  set(RAST_KOKKOS_ROUTE "source")
  set(_rast_kokkos_where "${_rast_src}")

# (c) the official release tarball
elseif(RAST_KOKKOS_DOWNLOAD)
  include(FetchContent)
  _rast_kokkos_intree_defaults()
  set(_rast_hash_arg "")
  if(RAST_KOKKOS_URL_HASH)
    set(_rast_hash_arg URL_HASH "${RAST_KOKKOS_URL_HASH}")
  endif()
  message(STATUS "RastKokkos: no installed Kokkos found; fetching ${RAST_KOKKOS_URL}")
  FetchContent_Declare(kokkos URL "${RAST_KOKKOS_URL}" ${_rast_hash_arg})
  FetchContent_MakeAvailable(kokkos)
  _rast_kokkos_intree_info("${kokkos_SOURCE_DIR}")
  set(RAST_KOKKOS_ROUTE "download")
  set(_rast_kokkos_where "${RAST_KOKKOS_URL}")

# (d) nothing
else()
  message(FATAL_ERROR "RastKokkos: no Kokkos found (set Kokkos_ROOT or RAST_KOKKOS_SOURCE); "
                      "run `bash scripts/setup/bootstrap.sh` to build one into .deps/kokkos/install")
endif()

if(NOT TARGET Kokkos::kokkos)
  message(FATAL_ERROR "RastKokkos: route '${RAST_KOKKOS_ROUTE}' did not provide Kokkos::kokkos")
endif()

string(TOUPPER "${Kokkos_DEVICES}" Kokkos_DEVICES)
message(STATUS "RastKokkos: route=${RAST_KOKKOS_ROUTE} (${_rast_kokkos_where}) "
               "Kokkos ${Kokkos_VERSION}, devices: ${Kokkos_DEVICES}, RAST_EXEC_SPACE=${RAST_EXEC_SPACE}")

if(NOT RAST_EXEC_SPACE STREQUAL "Default")
  string(TOUPPER "${RAST_EXEC_SPACE}" _rast_space)
  if(NOT _rast_space IN_LIST Kokkos_DEVICES)
    message(WARNING "RastKokkos: RAST_EXEC_SPACE=${RAST_EXEC_SPACE} but this Kokkos only "
                    "enables ${Kokkos_DEVICES}")
  endif()
  unset(_rast_space)
endif()
unset(_rast_kokkos_where)
unset(_rast_hash_arg)
unset(_rast_src)

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
set(_rast_python_default OFF)
if((pybind11_FOUND AND Python_Development.Module_FOUND OR pybind11_FOUND AND Python_Development_FOUND)
   AND RAST_DLPACK_INCLUDE_DIR)
  set(_rast_python_default ON)
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
set(RAST_PYTHON_DIR ${PROJECT_BINARY_DIR}/python CACHE INTERNAL "")
pybind11_add_module(_rast MODULE python/rast_module.cpp)
target_link_libraries(_rast PRIVATE rast_lib)
target_include_directories(_rast PRIVATE ${RAST_DLPACK_INCLUDE_DIR})
set_target_properties(_rast PROPERTIES LIBRARY_OUTPUT_DIRECTORY ${RAST_PYTHON_DIR}/rast)
# The pure-Python front (input conversion from numpy and DLPack) beside the extension.
configure_file(${PROJECT_SOURCE_DIR}/python/rast/__init__.py ${RAST_PYTHON_DIR}/rast/__init__.py COPYONLY)
message(STATUS "rast: Python module for ${Python_EXECUTABLE} in ${RAST_PYTHON_DIR}")

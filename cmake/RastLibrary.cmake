# rast as a library (docs/library.md): the target rast_lib, exported as
# rast::rast, with its public headers in include/rast/ and a CMake package
# (rastConfig.cmake, rastConfigVersion.cmake, rastTargets.cmake).
#
# The library is one self-contained static archive: the api/ layer's objects
# plus those of rast_pipeline, rast_host and rast_thirdparty (the same objects,
# not compiled again). So the installed package exports one target whose only
# public dependency is Kokkos::kokkos; the internal libraries and the
# header-only Debian dependencies (rast::deps: tinygltf, stb, glm, nlohmann,
# CLI11) stay private and are neither installed nor needed by a consumer, since
# the public headers include only Kokkos and the standard library.
include_guard(GLOBAL)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

if(RAST_EXEC_SPACE MATCHES "^(HIP|Default)$")
  set(RAST_LIB_EXEC_TYPE "Kokkos::DefaultExecutionSpace")
else()
  set(RAST_LIB_EXEC_TYPE "Kokkos::${RAST_EXEC_SPACE}")
endif()
set(RAST_GENERATED_INCLUDE ${PROJECT_BINARY_DIR}/generated/include)
configure_file(${PROJECT_SOURCE_DIR}/cmake/rast_config.h.in ${RAST_GENERATED_INCLUDE}/rast/config.h @ONLY)

set(RAST_API_SOURCES api/scene_api.cpp api/renderer_api.cpp api/rasterize_api.cpp)
add_library(rast_lib STATIC ${RAST_API_SOURCES}
  $<TARGET_OBJECTS:rast_pipeline> $<TARGET_OBJECTS:rast_host> $<TARGET_OBJECTS:rast_thirdparty>)
add_library(rast::rast ALIAS rast_lib)
set_target_properties(rast_lib PROPERTIES OUTPUT_NAME rast EXPORT_NAME rast)
add_dependencies(rast_lib rast_pipeline rast_host rast_thirdparty)
# Compiling api/ needs the internal headers and definitions (private to the build).
target_include_directories(rast_lib PRIVATE ${PROJECT_SOURCE_DIR}
  $<TARGET_PROPERTY:rast_deps,INTERFACE_INCLUDE_DIRECTORIES>)
target_compile_definitions(rast_lib PRIVATE $<TARGET_PROPERTY:rast_pipeline,INTERFACE_COMPILE_DEFINITIONS>
  $<TARGET_PROPERTY:rast_deps,INTERFACE_COMPILE_DEFINITIONS>)
target_include_directories(rast_lib PUBLIC
  $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include> $<BUILD_INTERFACE:${RAST_GENERATED_INCLUDE}>
  $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
# The glTF loader's decoders (shared libraries: not in the archive).
target_link_libraries(rast_lib PUBLIC Kokkos::kokkos draco::draco meshoptimizer::meshoptimizer)
target_compile_features(rast_lib PUBLIC cxx_std_17)

# The package needs Kokkos as a package too: a Kokkos built inside this tree
# (RAST_KOKKOS_SOURCE, download) is not installed with rast.
if(NOT RAST_KOKKOS_ROUTE STREQUAL "installed")
  message(STATUS "rast: Kokkos was built in-tree (${RAST_KOKKOS_ROUTE}): the rast package is not installed")
  return()
endif()
set(RAST_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/rast)
install(TARGETS rast_lib EXPORT rastTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES include/rast/rast.h include/rast/error.h ${RAST_GENERATED_INCLUDE}/rast/config.h
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/rast)
install(EXPORT rastTargets NAMESPACE rast:: DESTINATION ${RAST_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/rastConfig.cmake.in
  ${PROJECT_BINARY_DIR}/rastConfig.cmake INSTALL_DESTINATION ${RAST_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/rastConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/rastConfig.cmake ${PROJECT_BINARY_DIR}/rastConfigVersion.cmake
  DESTINATION ${RAST_CMAKE_DIR})

# Header-only dependencies from Debian's packages (see scripts/setup/bootstrap.sh):
# tinygltf + nlohmann-json, stb, GLM, CLI11. Exposed as the interface target
# rast::deps.
include_guard(GLOBAL)

find_path(RAST_TINYGLTF_INCLUDE tiny_gltf.h)
find_path(RAST_STB_INCLUDE stb/stb_image_write.h)
find_path(RAST_GLM_INCLUDE glm/glm.hpp)
find_path(RAST_JSON_INCLUDE nlohmann/json.hpp)
find_path(RAST_CLI11_INCLUDE CLI/CLI.hpp)
foreach(v RAST_TINYGLTF_INCLUDE RAST_STB_INCLUDE RAST_GLM_INCLUDE RAST_JSON_INCLUDE RAST_CLI11_INCLUDE)
  if(NOT ${v})
    message(FATAL_ERROR "${v} not found: run `bash scripts/setup/bootstrap.sh` (Debian packages "
                        "libtinygltf-dev nlohmann-json3-dev libstb-dev libglm-dev libcli11-dev)")
  endif()
endforeach()

add_library(rast_deps INTERFACE)
target_include_directories(rast_deps SYSTEM INTERFACE
  ${RAST_TINYGLTF_INCLUDE} ${RAST_STB_INCLUDE} ${RAST_GLM_INCLUDE} ${RAST_JSON_INCLUDE} ${RAST_CLI11_INCLUDE})
target_compile_definitions(rast_deps INTERFACE GLM_FORCE_CXX17 TINYGLTF_USE_CPP14)
add_library(rast::deps ALIAS rast_deps)

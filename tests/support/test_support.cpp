#include "tests/support/test_support.h"

#include <catch2/catch.hpp>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <unistd.h>
#include <fstream>
#include <sys/stat.h>

namespace rast::test {

RenderSettings withIdsAndDepth(const int width, const int height) {
  RenderSettings rs;
  rs.width = width;
  rs.height = height;
  rs.wantPrimId = true;
  rs.wantDepth = true;
  return rs;
}

Frame renderFrame(const Scene& s, const Camera& cam, RenderSettings rs) {
  rs.wantPrimId = true;
  rs.wantDepth = true;
  Renderer r(s);
  Frame f;
  f.stats = r.render(cam, rs);
  f.width = rs.width;
  f.height = rs.height;
  f.color = r.colorTopDown();
  f.ids = r.primIdsBottomUp();
  f.depth = r.depthBottomUp();
  return f;
}

Scene trianglesScene(const std::vector<float3>& positions, const std::vector<uint32_t>& indices,
                     const std::vector<float2>* uvs) {
  Scene s;
  s.name = "test";
  s.materials.push_back(Material{});
  const uint32_t p = addPrim(s, positions, nullptr, uvs, nullptr, indices, 0);
  s.draws.push_back(Draw{p, glm::dmat4(1.0)});
  return s;
}

Camera milktruckCabCamera() {
  Camera cab;
  cab.eye = {0.5, 1.3, 0.2};
  cab.target = {3.0, 1.0, 0.5};
  cab.up = {0.0, 1.0, 0.0};
  cab.fovyDeg = 45.0;
  cab.znear = 0.5;
  cab.zfar = 807.25;
  return cab;
}

Camera identityCamera() {
  Camera c;
  c.viewProjOverride = glm::dmat4(1.0);
  return c;
}

float3 windowToNdc(double x, double y, double z, int width, int height) {
  return float3{float(x / width * 2.0 - 1.0), float(y / height * 2.0 - 1.0), float(z)};
}

bool fileExists(const std::string& p) {
  struct stat st;
  return ::stat(p.c_str(), &st) == 0;
}

// The data folders are compile-time paths of the build machine; an environment
// variable of the same name wins, for running a copied build elsewhere
// (scripts/device/run_suite.sh).
static std::string dirSetting(const char* env, const char* compiled) {
  const char* e = std::getenv(env);
  return (e && *e) ? std::string(e) : std::string(compiled);
}

std::string sharedDir() {
  const std::string d = dirSetting("RAST_SHARED_DIR", RAST_SHARED_DIR);
  return fileExists(d + "/models") ? d : std::string();
}

std::string assimpDir() {
  const std::string d = dirSetting("RAST_ASSIMP_GLTF_DIR", RAST_ASSIMP_GLTF_DIR);
  return fileExists(d) ? d : std::string();
}

std::string scratchPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("rast_test_" + std::to_string(getpid()) + "_" + name)).string();
}

void skipTest(const std::string& reason) {
  WARN("SKIPPED: " << reason);
  std::string name = Catch::getResultCapture().getCurrentTestName();
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  const std::string dir = std::string(RAST_BINARY_DIR) + "/tests/skipped";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  std::ofstream(dir + "/" + name + ".txt") << reason << "\n";
}

}  // namespace rast::test

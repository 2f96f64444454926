// rast-depth-error: a renderer's depth buffer against the exact depth of the
// triangles its id buffer names (tests/support/depth_reference.h), for
// scripts/measure/depth_error.py. Reads glref's file formats, which rast also writes.
//
//   rast-depth-error SCENE --size WxH --eye x,y,z --target x,y,z --up x,y,z
//                    --fovy F --near N --far F  IDS.bin DEPTH.pfm [IDS.bin DEPTH.pfm ...]
//   rast-depth-error SCENE [--size, camera flags] --which-nearer [--at 0.5,0.5] A.bin B.bin
//
// The second form lists the pixels where two id buffers differ, with the exact
// depth of both triangles there: which of the two is really in front.
//
// The first prints one line per pair: "depth_error ids=... pixels=N max=E mean=M at=X,Y id=I got=G want=W"
// (X, Y in window pixels, y up). Exit 2 on bad input.
#include "tests/support/depth_reference.h"
#include "host/image/image_io.h"
#include "scenes/procedural.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

using namespace rast;

namespace {

glm::dvec3 parseVec3(const char* s) {
  glm::dvec3 v;
  if (std::sscanf(s, "%lf,%lf,%lf", &v.x, &v.y, &v.z) != 3) throw Error(std::string("expected x,y,z, got ") + s);
  return v;
}

int run(int argc, char** argv) {
  if (argc < 2) throw Error("usage: rast-depth-error SCENE --size WxH [camera flags] IDS.bin DEPTH.pfm ...");
  const Scene scene = loadSceneArg(argv[1]);
  Camera cam = defaultCamera(scene);
  int width = 1920, height = 1080;
  std::vector<std::string> files;
  bool nearer = false;
  double ox = 0.5, oy = 0.5;  // where in the pixel to compare (MSAA: sample 0)
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() -> const char* {
      if (i + 1 >= argc) throw Error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--size") {
      if (std::sscanf(next(), "%dx%d", &width, &height) != 2 || width <= 0 || height <= 0) throw Error("bad --size");
    } else if (a == "--eye") cam.eye = parseVec3(next());
    else if (a == "--target") cam.target = parseVec3(next());
    else if (a == "--up") cam.up = parseVec3(next());
    else if (a == "--fovy") cam.fovyDeg = std::atof(next());
    else if (a == "--near") cam.znear = std::atof(next());
    else if (a == "--far") cam.zfar = std::atof(next());
    else if (a == "--which-nearer") nearer = true;
    else if (a == "--at") {
      if (std::sscanf(next(), "%lf,%lf", &ox, &oy) != 2) throw Error("--at takes x,y within the pixel (y up)");
    }
    else if (a.rfind("--", 0) == 0) throw Error("unknown option " + a);
    else files.push_back(a);
  }
  if (files.empty() || files.size() % 2) throw Error("give pairs of IDS.bin DEPTH.pfm");
  const std::vector<test::ClipTriangle> tris =
      test::drawnTrianglesInClipSpace(scene, cam.viewProjection(width, height));
  if (nearer) {
    if (files.size() != 2) throw Error("--which-nearer takes two id files");
    int aw, ah, bw, bh;
    const std::vector<uint32_t> a = readIdsBin(files[0], aw, ah), b = readIdsBin(files[1], bw, bh);
    if (aw != width || ah != height || bw != width || bh != height) throw Error("id buffer sizes differ from --size");
    int differ = 0, aNearer = 0, bNearer = 0;
    for (int row = 0; row < height; ++row)
      for (int x = 0; x < width; ++x) {
        const size_t i = size_t(row) * width + x;
        if (a[i] == b[i]) continue;
        ++differ;
        const int y = height - 1 - row;  // ids are top row first; window y is up
        double da = 1.0, db = 1.0;  // background: the far plane
        if (a[i] && a[i] <= tris.size()) test::exactWindowDepth(tris[a[i] - 1], width, height, x + ox, y + oy, da);
        if (b[i] && b[i] <= tris.size()) test::exactWindowDepth(tris[b[i] - 1], width, height, x + ox, y + oy, db);
        aNearer += da < db;
        bNearer += db < da;
        std::printf("pixel %d,%d: %u (exact %.9g) vs %u (exact %.9g): %s nearer\n", x, y, a[i], da, b[i], db,
                    da < db ? "first" : db < da ? "second" : "neither");
      }
    std::printf("which_nearer differ=%d first=%d second=%d\n", differ, aNearer, bNearer);
    return 0;
  }
  for (size_t f = 0; f < files.size(); f += 2) {
    int iw, ih, dw, dh, ch;
    const std::vector<uint32_t> idsTop = readIdsBin(files[f], iw, ih);
    const std::vector<float> depth = readPfm(files[f + 1], dw, dh, ch);
    if (iw != width || ih != height || dw != width || dh != height || ch != 1)
      throw Error("image sizes differ from --size: " + files[f] + ", " + files[f + 1]);
    std::vector<uint32_t> ids(idsTop.size());
    for (int y = 0; y < height; ++y)
      std::memcpy(&ids[size_t(y) * width], &idsTop[size_t(height - 1 - y) * width], sizeof(uint32_t) * width);
    for (int which = 0; which < 3; ++which) {
    const test::DepthError e = test::depthError(tris, width, height, ids, depth, which);
    std::printf("depth_error ids=%s tris=%s pixels=%lld max=%.9g mean=%.9g at=%lld,%lld id=%u got=%.9g want=%.9g\n",
                files[f].c_str(), which == 0 ? "all" : which == 1 ? "near-clipped" : "unclipped", (long long)e.pixels, e.maxErr, e.pixels ? e.sumErr / double(e.pixels) : 0.0,
                (long long)e.maxX, (long long)e.maxY, e.maxId, e.maxGot, e.maxWant);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rast-depth-error: error: %s\n", e.what());
    return 2;
  }
}

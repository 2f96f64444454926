// A consumer of the installed rast package (examples/cpp_consumer): it owns
// Kokkos, builds a two-triangle scene from Kokkos Views, renders it through
// rast::lib::Renderer (the frame's views are reused), checks the ids, depth and
// barycentrics it gets back, loads a built-in scene, and checks that bad input comes
// back as rast::Error rather than ending the program. Exit status 0: all good.
#include <rast/rast.h>

#include <cstdio>

namespace {
int failures = 0;
void check(bool ok, const char* what) {
  std::printf("%s %s\n", ok ? "ok  " : "FAIL", what);
  failures += !ok;
}
}  // namespace

int main(int argc, char** argv) {
  Kokkos::ScopeGuard kokkos(argc, argv);
  {
    rast::ExecutionSpace exec;
    // Two triangles side by side at z = 0, seen from +z: the left one is triangle 0.
    rast::View<float* [3]> pos("pos", 6);
    rast::View<uint32_t* [3]> tri("tri", 2);
    Kokkos::parallel_for(
        "fill", Kokkos::RangePolicy<rast::ExecutionSpace>(exec, 0, 1), KOKKOS_LAMBDA(int) {
          const float p[6][3] = {{-1, -0.5f, 0}, {-0.1f, -0.5f, 0}, {-0.5f, 0.5f, 0},
                                 {0.1f, -0.5f, 0}, {1, -0.5f, 0},    {0.5f, 0.5f, 0}};
          for (int v = 0; v < 6; ++v)
            for (int k = 0; k < 3; ++k) pos(v, k) = p[v][k];
          for (int t = 0; t < 2; ++t)
            for (int k = 0; k < 3; ++k) tri(t, k) = uint32_t(3 * t + k);
        });
    rast::lib::MeshViews mesh;
    mesh.positions = pos;
    mesh.indices = tri;
    const rast::lib::Scene scene = rast::lib::Scene::fromViews(exec, mesh);
    check(scene.triangleCount() == 2, "the scene from views has 2 triangles");

    rast::lib::Camera cam;
    cam.eye = {0, 0, 3};
    rast::lib::Settings s;
    s.width = 64;
    s.height = 48;
    rast::lib::Renderer renderer(scene);
    const rast::lib::Frame& f = renderer.render(exec, cam, s);
    auto ids = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f.primIds);
    auto depth = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f.depth);
    const int y = s.height / 2;
    const int left = 3 * s.width / 8, right = 5 * s.width / 8, mid = s.width / 2;
    check(ids(y, left) == 1 && ids(y, right) == 2 && ids(y, mid) == 0,
          "ids: left triangle 0 (+1), right triangle 1 (+1), background 0 between them");
    check(depth(y, left) < 1.0f && depth(y, mid) == 1.0f, "depth: < 1 on a triangle, 1 on background");
    s.barycentrics = true;
    const rast::lib::Frame& fb = renderer.render(exec, cam, s);
    auto bary = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), fb.barycentrics);
    const float sum = bary(y, left, 0) + bary(y, left, 1) + bary(y, left, 2);
    check(sum > 0.9999f && sum < 1.0001f && bary(y, mid, 0) == 0.0f, "barycentrics sum to 1 on a triangle, 0 elsewhere");
    s.barycentrics = false;
    const uint32_t* before = f.color.data();
    renderer.render(exec, cam, s);
    check(f.color.data() == before, "a second frame reuses the same colour buffer");

    const rast::lib::Scene builtin = rast::lib::Scene::load("builtin:bigtri");
    rast::lib::Renderer second(builtin);
    const rast::lib::Frame& g = second.render(exec, rast::lib::Camera::framing(builtin), s);
    check(g.trianglesIn > 0, "builtin:bigtri renders with its own camera");

    // Clip-space triangles from the caller's own device views, drawn by a
    // context kept across calls (nvdiffrast's dr.rasterize).
    rast::View<float* [4]> clip("clip", 3);
    rast::View<int32_t* [3]> tris("tris", 1);
    auto hp = Kokkos::create_mirror_view(clip);
    auto ht = Kokkos::create_mirror_view(tris);
    const float corners[3][4] = {{-0.5f, -0.5f, 0.0f, 1.0f}, {0.5f, -0.5f, 0.0f, 1.0f}, {0.0f, 0.5f, 0.0f, 1.0f}};
    for (int v = 0; v < 3; ++v) {
      for (int k = 0; k < 4; ++k) hp(v, k) = corners[v][k];
      ht(0, v) = v;
    }
    Kokkos::deep_copy(clip, hp);
    Kokkos::deep_copy(tris, ht);
    rast::View<float** [4]> out("out", 32, 32);
    rast::View<int32_t**> rid("ids", 32, 32);
    rast::lib::Rasterizer rasterizer;
    rasterizer.rasterize(exec, clip, tris, 32, 32, out, rid);
    rasterizer.rasterize(exec, clip, tris, 32, 32, out, rid);  // the same buffers again
    auto hid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), rid);
    check(hid(16, 16) == 0 && hid(1, 1) == -1, "rasterize: triangle 0 at the centre, -1 in the corner");

    bool threw = false;
    try {
      rast::lib::Scene::load("/no/such/file.glb");
    } catch (const rast::Error& e) {
      threw = true;
      std::printf("     (rast::Error: %s)\n", e.what());
    }
    check(threw, "a missing file is a rast::Error");
    threw = false;
    try {
      rast::lib::Settings bad = s;
      bad.shading = "glossy";
      renderer.render(exec, cam, bad);
    } catch (const rast::Error&) {
      threw = true;
    }
    check(threw, "an unknown shading name is a rast::Error");
    std::printf("rast %s, %s backend\n", rast::lib::version().c_str(), rast::lib::backend().c_str());
  }
  return failures ? 1 : 0;
}

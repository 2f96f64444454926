// nvdiffrast's dr.rasterize on rast's pipeline (include/rast/rast.h,
// rast::lib::rasterize): clip-space triangles in, (u, v, z/w, id + 1) per pixel
// out. Coverage, depth order and ids are the pipeline's own (the triangles'
// x/w, y/w, z/w drawn with an identity camera); the perspective-correct
// barycentrics and z/w are then computed per covered pixel from the caller's
// clip-space vertices.
#include "api/api_internal.h"

#include "pipeline/frame/renderer.h"

namespace rast {
namespace lib {

void rasterize(const ExecutionSpace& exec, View<const float* [4]> pos, View<const int32_t* [3]> tri, int width,
               int height, View<float** [4]> out, View<int32_t**> ids) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw Error("rasterize: resolution " + std::to_string(width) + "x" + std::to_string(height) +
                " is outside 1..16384 per side");
  if (out.extent(0) != size_t(height) || out.extent(1) != size_t(width) || ids.extent(0) != size_t(height) ||
      ids.extent(1) != size_t(width))
    throw Error("rasterize: output views must be [height][width][4] and [height][width]");
  const int64_t nv = int64_t(pos.extent(0)), nt = int64_t(tri.extent(0));
  exec.fence();
  // The first bad vertex and the first bad index (nv / nt*3 when none).
  int64_t badVertex = nv, badIndex = 3 * nt;
  Kokkos::parallel_reduce(
      "rast::api::check_positions", Kokkos::RangePolicy<ExecutionSpace>(exec, 0, nv),
      KOKKOS_LAMBDA(const int64_t i, int64_t& first) {
        bool ok = true;
        for (int k = 0; k < 4; ++k) ok = ok && (pos(i, k) - pos(i, k)) == 0.0f;  // false for NaN and infinities
        if (!(ok && pos(i, 3) > 0.0f) && i < first) first = i;
      },
      Kokkos::Min<int64_t>(badVertex));
  Kokkos::parallel_reduce(
      "rast::api::check_indices", Kokkos::RangePolicy<ExecutionSpace>(exec, 0, 3 * nt),
      KOKKOS_LAMBDA(const int64_t i, int64_t& first) {
        const int32_t v = tri(i / 3, i % 3);
        if ((v < 0 || v >= nv) && i < first) first = i;
      },
      Kokkos::Min<int64_t>(badIndex));
  exec.fence();
  if (badVertex < nv) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kokkos::subview(pos, badVertex, Kokkos::ALL));
    throw Error("rasterize: vertex " + std::to_string(badVertex) + " is (" + std::to_string(h(0)) + ", " +
                std::to_string(h(1)) + ", " + std::to_string(h(2)) + ", " + std::to_string(h(3)) +
                "): positions must be finite with w > 0 (near-plane clipping of clip-space input is not supported yet)");
  }
  if (badIndex < 3 * nt) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tri);
    throw Error("rasterize: triangle " + std::to_string(badIndex / 3) + " has index " +
                std::to_string(h(badIndex / 3, badIndex % 3)) + ", outside 0.." + std::to_string(nv - 1));
  }
  if (nt == 0) {
    Kokkos::deep_copy(exec, out, 0.0f);
    Kokkos::deep_copy(exec, ids, -1);
    exec.fence();
    return;
  }

  // The pipeline draws x/w, y/w, z/w with w = 1: the same window positions and
  // the same depth order (z/w) as the clip-space input.
  auto hp = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), pos);
  auto ht = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), tri);
  std::vector<float3> p3(static_cast<size_t>(nv)), n3(static_cast<size_t>(nv), float3{0.0f, 0.0f, 1.0f});
  for (int64_t i = 0; i < nv; ++i) p3[i] = float3{hp(i, 0) / hp(i, 3), hp(i, 1) / hp(i, 3), hp(i, 2) / hp(i, 3)};
  std::vector<uint32_t> idx(static_cast<size_t>(3 * nt));
  for (int64_t i = 0; i < 3 * nt; ++i) idx[i] = uint32_t(ht(i / 3, i % 3));
  const ::rast::Scene scene = meshScene(p3, &n3, nullptr, nullptr, idx, nullptr, {});
  ::rast::Renderer renderer(scene);
  ::rast::Camera cam;
  cam.viewProjOverride = glm::dmat4(1.0);
  RenderSettings rs;
  rs.width = width;
  rs.height = height;
  rs.shading = ShadingMode::Depth;
  rs.wantPrimId = true;
  renderer.render(cam, rs);
  const auto prim = renderer.frameBuffers().primId;

  Kokkos::parallel_for(
      "rast::api::barycentrics",
      Kokkos::MDRangePolicy<ExecutionSpace, Kokkos::Rank<2>>(exec, {0, 0}, {int64_t(height), int64_t(width)}),
      KOKKOS_LAMBDA(const int64_t y, const int64_t x) {
        const uint32_t id = prim(y * width + x);
        if (id == 0) {
          for (int k = 0; k < 4; ++k) out(y, x, k) = 0.0f;
          ids(y, x) = -1;
          return;
        }
        const int64_t t = int64_t(id) - 1;
        double px[3], py[3], iw[3], zw[3];
        for (int k = 0; k < 3; ++k) {
          const int32_t v = tri(t, k);
          iw[k] = 1.0 / double(pos(v, 3));
          px[k] = double(pos(v, 0)) * iw[k];
          py[k] = double(pos(v, 1)) * iw[k];
          zw[k] = double(pos(v, 2)) * iw[k];
        }
        const PixelBarycentrics w = pixelBarycentrics(x, y, width, height, px, py, iw);
        out(y, x, 0) = float(w.p[0]);
        out(y, x, 1) = float(w.p[1]);
        out(y, x, 2) = float(w.b[0] * zw[0] + w.b[1] * zw[1] + w.b[2] * zw[2]);
        out(y, x, 3) = float(id);
        ids(y, x) = int32_t(t);
      });
  exec.fence();
}

}  // namespace lib
}  // namespace rast

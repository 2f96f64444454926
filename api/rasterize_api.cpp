// nvdiffrast's dr.rasterize on rast's pipeline (include/rast/rast.h,
// rast::lib::rasterize): clip-space triangles in, (u, v, z/w, id + 1) per pixel
// out. Coverage, depth order and ids are the pipeline's own (the triangles'
// x/w, y/w, z/w drawn with an identity camera); the perspective-correct
// barycentrics and z/w are then computed per covered pixel from the caller's
// clip-space vertices. A Rasterizer keeps its renderer across calls, so the
// caller's device data goes straight into the scene's buffers.
#include "api/api_internal.h"

#include "backends/device_index.h"
#include "pipeline/frame/renderer.h"

#include <limits>

namespace rast {
namespace lib {

namespace {

void checkSizes(const View<const int32_t* [3]>& tri, int width, int height, const View<float** [4]>& out,
                const View<int32_t**>& ids) {
  if (width < 1 || height < 1 || width > 16384 || height > 16384)
    throw Error("rasterize: resolution " + std::to_string(width) + "x" + std::to_string(height) +
                " is outside 1..16384 per side");
  if (out.extent(0) != size_t(height) || out.extent(1) != size_t(width) || ids.extent(0) != size_t(height) ||
      ids.extent(1) != size_t(width))
    throw Error("rasterize: output views must be [height][width][4] and [height][width]");
  if (tri.extent(0) > size_t(std::numeric_limits<uint32_t>::max() - 2) / 3)
    throw Error("rasterize: too many triangles (" + std::to_string(tri.extent(0)) + ")");
}

// A vertex the pipeline can draw: finite, w > 0 (false for NaN and infinities).
KOKKOS_INLINE_FUNCTION bool goodVertex(float x, float y, float z, float w) {
  return (x - x) == 0.0f && (y - y) == 0.0f && (z - z) == 0.0f && (w - w) == 0.0f && w > 0.0f;
}

// The error for the first bad input j (vertices first, then the 3 nt
// indices), in the words the CLI and the Python module print.
[[noreturn]] void badInput(const View<const float* [4]>& pos, const View<const int32_t* [3]>& tri, int64_t j) {
  const int64_t nv = int64_t(pos.extent(0));
  if (j < nv) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kokkos::subview(pos, j, Kokkos::ALL));
    throw Error("rasterize: vertex " + std::to_string(j) + " is (" + std::to_string(h(0)) + ", " +
                std::to_string(h(1)) + ", " + std::to_string(h(2)) + ", " + std::to_string(h(3)) +
                "): positions must be finite with w > 0 (near-plane clipping of clip-space input is not supported yet)");
  }
  const int64_t i = j - nv;
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kokkos::subview(tri, i / 3, Kokkos::ALL));
  throw Error("rasterize: triangle " + std::to_string(i / 3) + " has index " + std::to_string(h(i % 3)) +
              ", outside 0.." + std::to_string(nv - 1));
}

bool defaultInstance(const ExecutionSpace& exec) {
#if KOKKOS_VERSION >= 40000
  return exec.impl_instance_id() == ExecutionSpace().impl_instance_id();
#else
  (void)exec;
  return false;
#endif
}

// One pixel's (u, v, z/w, id + 1), stored whole.
struct alignas(16) Pixel4 {
  float x, y, z, w;
};
KOKKOS_INLINE_FUNCTION void putPixel(const View<float** [4]>& out, Pixel4* wide, int64_t p, int64_t y, int64_t x,
                                     const Pixel4& v) {
  if (wide) {
    wide[p] = v;
  } else {
    out(y, x, 0) = v.x;
    out(y, x, 1) = v.y;
    out(y, x, 2) = v.z;
    out(y, x, 3) = v.w;
  }
}

}  // namespace

// The renderer of a context is made for a vertex count, a triangle count and
// a size; its scene's positions and indices are then overwritten on the device
// each call. Nothing in the renderer is derived from the positions at upload
// (no bounds, no per-triangle data: pipeline/data/device_scene.h), so the
// frame is the one a fresh renderer of the same triangles draws.
//
// The inputs are checked by the kernel that writes them into the scene: the
// first bad one (by position in the input) goes to a device scalar, which the
// output pass's first thread copies to page-locked host memory along with the
// frame's counters (FrameKeys::publish), read once the frame is done, which the
// frame waits for anyway (its buffers' fit). So a call waits for the device
// once, and never just to check its inputs. Bad vertices and indices are
// replaced by harmless ones (vertex 0 at the origin) for the frame that is
// then thrown away.
struct Rasterizer::Impl {
  std::unique_ptr<::rast::Renderer> renderer;
  int64_t nv = -1, nt = -1;
  Kokkos::View<int64_t, MemorySpace> firstBad;
  Kokkos::View<int64_t, PinnedSpace> firstBadHost;
};

Rasterizer::Rasterizer() : impl_(std::make_unique<Impl>()) {}
Rasterizer::~Rasterizer() = default;
Rasterizer::Rasterizer(Rasterizer&&) noexcept = default;
Rasterizer& Rasterizer::operator=(Rasterizer&&) noexcept = default;

void Rasterizer::rasterize(const ExecutionSpace& exec, View<const float* [4]> pos, View<const int32_t* [3]> tri,
                           int width, int height, View<float** [4]> out, View<int32_t**> ids) {
  checkSizes(tri, width, height, out, ids);
  const int64_t nv = int64_t(pos.extent(0)), nt = int64_t(tri.extent(0));
  if (nt == 0) {
    // Nothing to draw; the positions are still checked (one reduction).
    int64_t first = nv;
    Kokkos::parallel_reduce(
        "rast::api::check_positions", Kokkos::RangePolicy<ExecutionSpace>(exec, 0, nv),
        KOKKOS_LAMBDA(const int64_t j, int64_t& f) {
          if (!goodVertex(pos(j, 0), pos(j, 1), pos(j, 2), pos(j, 3)) && j < f) f = j;
        },
        Kokkos::Min<int64_t>(first));
    if (first < nv) badInput(pos, tri, first);
    Kokkos::deep_copy(exec, out, 0.0f);
    Kokkos::deep_copy(exec, ids, -1);
    exec.fence();
    return;
  }
  Impl& im = *impl_;
  if (!im.renderer || im.nv != nv || im.nt != nt) {
    // A placeholder mesh of the right counts (every triangle on vertex 0),
    // uploaded once; the caller's data replaces it below.
    im.renderer.reset();
    const std::vector<float3> p0(size_t(nv), float3{0.0f, 0.0f, 0.0f}), n0(size_t(nv), float3{0.0f, 0.0f, 1.0f});
    const std::vector<uint32_t> idx(size_t(3 * nt), 0u);
    im.renderer = std::make_unique<::rast::Renderer>(meshScene(p0, &n0, nullptr, nullptr, idx, nullptr, {}));
    im.nv = nv;
    im.nt = nt;
  }
  const int64_t none = nv + 3 * nt;
  if (!im.firstBad.data()) {
    im.firstBad = Kokkos::View<int64_t, MemorySpace>("rast::api::first_bad");
    im.firstBadHost = Kokkos::View<int64_t, PinnedSpace>("rast::api::first_bad_host");
    Kokkos::deep_copy(exec, im.firstBad, std::numeric_limits<int64_t>::max());
  }
  // The pipeline draws x/w, y/w, z/w with w = 1: the same window positions and
  // the same depth order (z/w) as the clip-space input. The division rounds as
  // the host's (IEEE, no contraction: docs/determinism.md), so every backend
  // draws the same triangles.
  const DeviceScene& ds = im.renderer->scene();
  const auto positions = ds.positions;
  const auto indices = ds.indices;
  const auto firstBad = im.firstBad;
  // Written by the output pass where the device can write page-locked host
  // memory (kPinnedFromDevice), else copied after the frame.
  int64_t* const firstBadOut = kPinnedFromDevice ? im.firstBadHost.data() : nullptr;
  Kokkos::parallel_for(
      // Lightweight (pipeline/data/device.h): its functor, over 512 bytes,
      // travels as a kernel argument, not through Kokkos' constant-memory
      // launch and its host-side wait.
      "rast::api::inputs_in", lightweight(Kokkos::RangePolicy<ExecutionSpace>(exec, 0, none)),
      KOKKOS_LAMBDA(const int64_t j) {
        bool ok;
        if (j < nv) {
          const float x = pos(j, 0), y = pos(j, 1), z = pos(j, 2), w = pos(j, 3);
          ok = goodVertex(x, y, z, w);
          positions(j) = ok ? float3{x / w, y / w, z / w} : float3{0.0f, 0.0f, 0.0f};
        } else {
          const int64_t i = j - nv;
          const int32_t v = tri(i / 3, i % 3);
          ok = v >= 0 && v < nv;
          indices(i) = ok ? uint32_t(v) : 0u;
        }
        if (!ok) Kokkos::atomic_fetch_min(&firstBad(), j);
      });
  // The renderer draws on the space's default instance: exec's work must be
  // done first, unless exec is that instance (then the order is the stream's).
  if (!defaultInstance(exec)) exec.fence();
  ::rast::Camera cam;
  cam.viewProjOverride = glm::dmat4(1.0);
  RenderSettings rs;
  rs.width = width;
  rs.height = height;
  // The frame stops at its visibility keys (RenderSettings::keysOnly): no
  // colour nobody reads. One pass then turns each pixel's key into the
  // outputs (its raster triangle's primitive, the barycentrics), queued
  // behind the frame before the renderer reads its counters (the fit of its
  // buffers), so that one wait covers both; a frame that did not fit is drawn
  // again with grown buffers, and the pass with it. The pass runs on the
  // renderer's instance, behind its frame, and reads the scene's checked
  // indices, never the caller's raw ones. It clears the keys as the shade
  // stage does (FrameKeys), so the next frame needs no clearing pass.
  rs.keysOnly = true;
  ::rast::Renderer& r = *im.renderer;
  for (int attempt = 1;; ++attempt) {
    r.enqueue(cam, rs);
    const FrameKeys keys = r.takeKeys();
    // A pixel's four outputs in one 16-byte store where the view allows it
    // (contiguous rows, aligned: the module's own outputs always are), which
    // a GPU issues as one wide store instead of four strided ones.
    Pixel4* const wide = out.span_is_contiguous() && reinterpret_cast<uintptr_t>(out.data()) % alignof(Pixel4) == 0
                             ? reinterpret_cast<Pixel4*>(out.data())
                             : nullptr;
    Kokkos::parallel_for(
        "rast::api::barycentrics",
        lightweight(Kokkos::RangePolicy<ExecutionSpace>(ExecutionSpace(), 0, int64_t(height) * width)),
        KOKKOS_LAMBDA(const int64_t p) {
          // One thread a pixel along rows: neighbouring threads write neighbouring
          // outputs. 32-bit arithmetic (p < 2^28): a 64-bit division is several
          // times longer on a GPU, and this pass is bound by its instructions.
          const uint32_t pu = uint32_t(p), w32 = uint32_t(width), yu = pu / w32;
          const int64_t y = int64_t(yu), x = int64_t(pu - yu * w32);
          if (p == 0) {  // the frame's counters and the inputs' first bad element, for the host's one wait
            keys.publish();
            if (firstBadOut) *firstBadOut = firstBad();
          }
          const int64_t drawn = keys.take(p, int32_t(x), int32_t(y));  // the input triangle, not a clipped piece
          if (drawn < 0) {
            putPixel(out, wide, p, y, x, Pixel4{0.0f, 0.0f, 0.0f, 0.0f});
            ids(y, x) = -1;
            return;
          }
          const uint32_t t = uint32_t(drawn);
          double px[3], py[3], iw[3], zw[3];
          for (int k = 0; k < 3; ++k) {
            const uint32_t v = indices(3 * int64_t(t) + k);
            iw[k] = 1.0 / double(pos(v, 3));
            px[k] = double(pos(v, 0)) * iw[k];
            py[k] = double(pos(v, 1)) * iw[k];
            zw[k] = double(pos(v, 2)) * iw[k];
          }
          const PixelBarycentrics w = pixelBarycentrics(x, y, width, height, px, py, iw);
          putPixel(out, wide, p, y, x,
                   Pixel4{float(w.p[0]), float(w.p[1]), float(w.b[0] * zw[0] + w.b[1] * zw[1] + w.b[2] * zw[2]),
                          float(t + 1u)});
          ids(y, x) = int32_t(t);
        });
    if (r.lastFrameFit()) break;
    // Counters are deterministic: the second attempt fits (as Renderer::render).
    if (attempt >= 3) throw Error("internal: frame buffers did not converge");
  }
  // firstBadHost: written by the output pass, which lastFrameFit waited for.
  if (!kPinnedFromDevice) Kokkos::deep_copy(im.firstBadHost, im.firstBad);
  if (im.firstBadHost() < none) {
    const int64_t j = im.firstBadHost();
    Kokkos::deep_copy(exec, im.firstBad, std::numeric_limits<int64_t>::max());
    exec.fence();
    badInput(pos, tri, j);
  }
}

void rasterize(const ExecutionSpace& exec, View<const float* [4]> pos, View<const int32_t* [3]> tri, int width,
               int height, View<float** [4]> out, View<int32_t**> ids) {
  Rasterizer().rasterize(exec, pos, tri, width, height, out, ids);
}

int deviceIndex() { return ::rast::deviceIndex(); }
uintptr_t deviceStream() { return ::rast::deviceStream(); }
bool deviceStreamFollowsLegacy() { return ::rast::deviceStreamFollowsLegacy(); }

}  // namespace lib
}  // namespace rast

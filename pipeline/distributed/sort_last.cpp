#include "pipeline/distributed/sort_last.h"

#include "backends/stage_timer.h"
#include "host/distributed/ranks.h"
#include "pipeline/rules/raster_rules.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace rast {
namespace {

// The rank whose share holds x: the last r with start(r) <= x (empty shares
// share their start with the next).
KOKKOS_INLINE_FUNCTION int findRank(const DView<uint64_t>& start, int ranks, uint64_t x) {
  int lo = 0, hi = ranks;  // start(lo) <= x < start(hi)
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (start(mid) <= x) lo = mid;
    else hi = mid;
  }
  return lo;
}

// The rank that owns a global key's primitive; the background is rank 0's.
KOKKOS_INLINE_FUNCTION int ownerOf(const ShareTables& t, uint64_t key) {
  const uint32_t w = uint32_t(key & 0xffffffffu);
  if (w == 0) return 0;
  const uint32_t k = w - 1;
  if (!(k & kLineFlag)) return findRank(t.tStart, t.ranks, k);
  const uint64_t item = k & ~kLineFlag;
  if (item < t.L) return findRank(t.lStart, t.ranks, item);
  if (item < t.L + t.P) return findRank(t.pStart, t.ranks, item - t.L);
  const uint64_t e = item - t.L - t.P;  // triangle edges, then corners: 3 per triangle
  return findRank(t.tStart, t.ranks, (e < 3 * t.T ? e : e - 3 * t.T) / 3);
}

// A rank's local triangle made global: its range's are offset by t0, those
// rank 0 holds whole beyond it (BLEND draws) are found in their runs.
KOKKOS_INLINE_FUNCTION uint64_t globalTri(const ShareTables& t, uint64_t l) {
  if (l < t.Tr || t.runs == 0) return t.t0 + l;
  int lo = 0, hi = t.runs;  // runLocal(lo) <= l < runLocal(hi)
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (t.runLocal(mid) <= l) lo = mid;
    else hi = mid;
  }
  return t.runGlobal(lo) + (l - t.runLocal(lo));
}

// A rank's key made global: its raster triangle's drawn triangle, or its
// point/line item, numbered as in the whole scene (raster_lines.h's key space,
// whose edges and corners are 3 per local triangle).
KOKKOS_INLINE_FUNCTION uint64_t globalKey(const ShareTables& t, const DView<RasterTri>& tris, uint64_t key) {
  const uint32_t w = uint32_t(key & 0xffffffffu);
  if (w == 0) return key;
  const uint64_t hi = key & 0xffffffff00000000ull;
  const uint32_t k = w - 1;
  if (!(k & kLineFlag)) return hi | (globalTri(t, tris(k).prim) + 1);
  const uint64_t it = k & ~kLineFlag, Lr = t.Lr, Pr = t.Pr, Tl = t.Tl;
  uint64_t g;
  if (it < Lr) {
    g = t.l0 + it;
  } else if (it < Lr + Pr) {
    g = t.L + t.p0 + (it - Lr);
  } else {
    const bool edge = it < Lr + Pr + 3 * Tl;
    const uint64_t e = it - Lr - Pr - (edge ? 0 : 3 * Tl);
    g = t.L + t.P + (edge ? 0 : 3 * t.T) + 3 * globalTri(t, e / 3) + e % 3;
  }
  return hi | ((uint64_t(kLineFlag) | g) + 1);
}

// A rank's primitive id (shade's output: local triangles, then segments, then
// points, from 1) made global.
KOKKOS_INLINE_FUNCTION uint32_t globalId(const ShareTables& t, uint32_t v) {
  if (v == 0) return 0;
  if (v <= t.Tl) return uint32_t(globalTri(t, v - 1) + 1);
  if (v <= t.Tl + t.Lr) return uint32_t(t.T + t.l0 + (v - t.Tl));
  return uint32_t(t.T + t.L + t.p0 + (v - t.Tl - t.Lr));
}

DView<uint64_t> startTable(const char* name, const std::vector<ShareRange>& s, uint64_t ShareRange::*first,
                           uint64_t ShareRange::*last) {
  std::vector<uint64_t> h;
  for (const ShareRange& r : s) h.push_back(r.*first);
  h.push_back(s.back().*last);
  DView<uint64_t> d = allocUninit<uint64_t>(name, h.size());
  Kokkos::View<uint64_t*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> hv(h.data(), h.size());
  Kokkos::deep_copy(d, hv);
  return d;
}

}  // namespace

SortLast::SortLast(const std::vector<ShareRange>& shares, int me, const std::vector<TriRun>& blendWhole,
                   bool sceneBlends)
    : sceneBlends_(sceneBlends) {
  if (shares.empty() || me < 0 || me >= int(shares.size())) throw Error("internal: sort-last rank outside its shares");
  ShareTables& t = tables_;
  t.ranks = int(shares.size());
  t.me = me;
  t.T = shares.back().t1;
  t.L = shares.back().l1;
  t.P = shares.back().p1;
  if (t.T + t.L + t.P >= uint64_t(kLineFlag) - 1)
    throw Error("--distribute: " + std::to_string(t.T + t.L + t.P) + " primitives; global ids stop at 2^31");
  const ShareRange& mine = shares[size_t(me)];
  t.t0 = mine.t0;
  t.l0 = mine.l0;
  t.p0 = mine.p0;
  t.Tr = uint32_t(mine.t1 - mine.t0);
  t.Lr = uint32_t(mine.l1 - mine.l0);
  t.Pr = uint32_t(mine.p1 - mine.p0);
  uint64_t Tl = t.Tr;
  std::vector<uint64_t> local, global;
  for (const TriRun& r : blendWhole) {
    if (r.local != Tl || me != 0) throw Error("internal: BLEND triangles held whole out of order");
    local.push_back(r.local);
    global.push_back(r.global);
    Tl += r.count;
  }
  t.Tl = uint32_t(Tl);
  t.runs = int(local.size());
  if (t.runs > 0) {
    t.runLocal = allocUninit<uint64_t>("composite.runLocal", local.size());
    t.runGlobal = allocUninit<uint64_t>("composite.runGlobal", global.size());
    using H = Kokkos::View<uint64_t*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>;
    Kokkos::deep_copy(t.runLocal, H(local.data(), local.size()));
    Kokkos::deep_copy(t.runGlobal, H(global.data(), global.size()));
  }
  t.tStart = startTable("composite.tStart", shares, &ShareRange::t0, &ShareRange::t1);
  t.lStart = startTable("composite.lStart", shares, &ShareRange::l0, &ShareRange::l1);
  t.pStart = startTable("composite.pStart", shares, &ShareRange::p0, &ShareRange::p1);
}

SortLast::~SortLast() = default;

const char* SortLast::transport() const {
  return nccl_ ? "NCCL" : kOnDevice ? "MPI (staged through host memory)" : "MPI";
}

uint64_t SortLast::frameBytes(int width, int height, int samples) const {
  const uint64_t n = uint64_t(width) * uint64_t(height), ns = n * uint64_t(samples);
  uint64_t b = ns * 8 + n;
  if (samples > 1) b += n * 4;
  if (kOnDevice && !nccl_) b += ns * 8 + n * sizeof(float4);  // hostKeys_, hostWords_ (the largest merged buffer)
  b += uint64_t(tables_.runs) * 2 * sizeof(uint64_t);  // rank 0's runs of BLEND triangles held whole
  return b;
}

void SortLast::connect() {
  connected_ = true;
  const char* env = std::getenv("RAST_COMPOSITE");
  const std::string mode = env && *env ? env : "auto";
  if (mode != "auto" && mode != "nccl" && mode != "mpi")
    throw AgreedFailure("RAST_COMPOSITE=" + printable(mode, 40) + ": expected auto, nccl or mpi");
  if (mode != "mpi" && tables_.ranks > 1) {
    std::string why;
    nccl_ = NcclComposite::load(&why);
    const std::string all = Ranks::agree(nccl_ ? "" : why);
    if (!all.empty()) {
      nccl_.reset();
      if (mode == "nccl") throw AgreedFailure("RAST_COMPOSITE=nccl: " + all);
    } else {
      std::string error;
      try {
        nccl_->join();
      } catch (const std::exception& e) {
        error = e.what();
      }
      agree(error);
    }
  }
  if (tables_.me == 0)
    std::printf("rast: compositing %d ranks over %s%s\n", tables_.ranks, transport(),
                nccl_ ? (" " + nccl_->version()).c_str() : "");
}

void SortLast::agree(const std::string& error) {
  const std::string all = Ranks::agree(error);
  if (!all.empty()) throw AgreedFailure(all);
}

bool SortLast::all(bool ok) { return Ranks::agree(ok ? "" : "x").empty(); }

void SortLast::afterRaster(const DeviceScene& s, FrameBuffers& f, const FramePlan& plan, const DView<LightGPU>& lights,
                           StageTimer* timer) {
  if (!connected_) connect();
  const double start = Ranks::seconds();
  const int S = f.vp.samples.count;
  const size_t n = size_t(f.vp.width) * size_t(f.vp.height), ns = n * size_t(S);
  ensureCapacity(global_, "composite.keys", ns);
  ensureCapacity(flag_, "composite.flag", n);
  const ShareTables t = tables_;
  const DView<uint64_t> vis = f.vis, g = global_;
  const DView<RasterTri> tris = f.tris;
  const DView<uint8_t> flag = flag_;
  Kokkos::parallel_for("rast::composite::keys", Range(0, int64_t(ns)),
                       KOKKOS_LAMBDA(const int64_t i) { g(i) = globalKey(t, tris, vis(i)); });
  // The exchange: every rank gets the minimum of every rank's keys.
  if (nccl_) {
    nccl_->allMinU64(g.data(), ns);
  } else if (kOnDevice) {
    hostKeys_.resize(ns);
    Kokkos::View<uint64_t*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(hostKeys_.data(), ns);
    Kokkos::deep_copy(h, Kokkos::subview(g, std::make_pair(size_t(0), ns)));
    Ranks::allMinU64(hostKeys_.data(), ns);
    Kokkos::deep_copy(Kokkos::subview(g, std::make_pair(size_t(0), ns)), h);
  } else {
    Exec().fence();
    Ranks::allMinU64(g.data(), ns);
  }
  // Each rank keeps the keys it won; the others become clear (background),
  // which shading skips cheaply and the merge masks out.
  Kokkos::parallel_for("rast::composite::own", Range(0, int64_t(n)), KOKKOS_LAMBDA(const int64_t i) {
    if (S == 1) {
      const int o = ownerOf(t, g(i));
      flag(i) = o == t.me ? 1 : 0;
      if (o != t.me && vis(i) != kClearKey) vis(i) = kClearKey;
      return;
    }
    int first = -1;
    bool mixed = false;
    for (int q = 0; q < S; ++q) {
      const uint64_t k = g(i * S + q);
      if ((k & 0xffffffffu) == 0) continue;
      const int o = ownerOf(t, k);
      if (first < 0) first = o;
      else if (o != first) mixed = true;
    }
    if (!mixed) {
      const int o = first < 0 ? 0 : first;
      flag(i) = o == t.me ? 1 : 0;
      if (o != t.me)
        for (int q = 0; q < S; ++q) vis(i * S + q) = kClearKey;
      return;
    }
    flag(i) = 2;
    for (int q = 0; q < S; ++q) {
      const uint64_t k = g(i * S + q);
      if ((k & 0xffffffffu) == 0 || ownerOf(t, k) != t.me) vis(i * S + q) = kClearKey;
    }
  });
  mixed_.pixels = 0;
  if (S > 1 && countMixed(flag_, mixed_, n) > 0) shadeMixed(s, f, plan.shadeParams, lights, flag_, mixed_);
  f.visClear = false;
  Exec().fence();
  compositeMs_ = (Ranks::seconds() - start) * 1e3;
  if (timer) timer->mark("composite");
}

template <class T>
void SortLast::merge(DView<T>& v, size_t n) {
  static_assert(sizeof(T) % 4 == 0, "merged buffers are words");
  if (!v.data() || n == 0) return;
  const size_t words = n * sizeof(T) / 4;
  if (nccl_) {
    nccl_->sumToRoot(reinterpret_cast<uint32_t*>(v.data()), words);
    return;
  }
  if (!kOnDevice) {
    Ranks::orToRoot(reinterpret_cast<uint32_t*>(v.data()), words);
    return;
  }
  hostWords_.resize(words);
  Kokkos::View<T*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> h(reinterpret_cast<T*>(hostWords_.data()), n);
  Kokkos::deep_copy(h, Kokkos::subview(v, std::make_pair(size_t(0), n)));
  Ranks::orToRoot(hostWords_.data(), words);
  if (tables_.me == 0) Kokkos::deep_copy(Kokkos::subview(v, std::make_pair(size_t(0), n)), h);
}

void SortLast::afterShade(const DeviceScene& s, FrameBuffers& f, const FramePlan& plan, const DView<LightGPU>& lights,
                          StageTimer* timer) {
  const double start = Ranks::seconds();
  const ShadeParams& p = plan.shadeParams;
  const int S = f.vp.samples.count;
  const size_t n = size_t(f.vp.width) * size_t(f.vp.height);
  const ShareTables t = tables_;
  const DView<uint8_t> flag = flag_;
  const DView<uint64_t> g = global_;
  const DView<uint32_t> color = f.color, primId = f.primId;
  const DView<float4> hdr = f.post.hdr, geom = f.post.geom;
  const DView<float> depth = f.depth, viewDepth = f.post.depth;
  const DView<float3> normal = f.normal;
  const int floatOut = p.floatOut, wantDepth = p.wantDepth, wantId = p.wantPrimId, wantNormals = p.wantNormals,
            wantGeom = p.wantGeom;
  // Outputs of pixels this rank does not own become zero; its ids global.
  Kokkos::parallel_for("rast::composite::mask", Range(0, int64_t(n)), KOKKOS_LAMBDA(const int64_t i) {
    const int fl = flag(i);
    // A pixel's ids, depth, normal and geometry are its first sample's.
    const bool ids = fl == 1 || (fl == 2 && ownerOf(t, g(i * S)) == t.me);
    if (fl != 1) {
      if (floatOut) hdr(i) = float4{0.0f, 0.0f, 0.0f, 0.0f};
      else color(i) = 0;
    }
    if (!ids) {
      if (wantDepth) depth(i) = 0.0f;
      if (wantId) primId(i) = 0;
      if (wantNormals) normal(i) = float3{0.0f, 0.0f, 0.0f};
      if (wantGeom) {
        geom(i) = float4{0.0f, 0.0f, 0.0f, 0.0f};
        viewDepth(i) = 0.0f;
      }
    } else if (wantId) {
      primId(i) = globalId(t, primId(i));
    }
  });
  Exec().fence();
  if (floatOut) merge(f.post.hdr, n);
  else merge(f.color, n);
  if (wantDepth) merge(f.depth, n);
  if (wantId) merge(f.primId, n);
  if (wantNormals) merge(f.normal, n);
  if (wantGeom) {
    merge(f.post.geom, n);
    merge(f.post.depth, n);
  }
  if (S > 1 && mixed_.pixels > 0) {
    merge(mixed_.colour, size_t(mixed_.pixels) * size_t(S));
    merge(mixed_.count, size_t(mixed_.pixels) * size_t(S));
    if (tables_.me == 0) resolveMixed(s, f, p, lights, flag_, global_, mixed_);
  }
  Exec().fence();
  mergeMs_ = (Ranks::seconds() - start) * 1e3;
  if (timer) timer->mark("merge");
}

}  // namespace rast

// The library's scenes (include/rast/rast.h): loaded as the CLI loads them, or
// built from a caller's arrays or Views; and the public camera.
#include "api/api_internal.h"

#include "scenes/procedural.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>

namespace rast {
namespace lib {

std::string version() { return RAST_VERSION_STRING; }
std::string backend() { return Exec::name(); }

::rast::Scene meshScene(const std::vector<float3>& pos, const std::vector<float3>* nrm, const std::vector<float2>* uv,
                        const std::vector<float4>* col, const std::vector<uint32_t>& idx,
                        const std::vector<int32_t>* triMaterial, const std::vector<std::array<float, 4>>& materials) {
  if (pos.empty() || idx.empty()) throw Error("scene: positions and indices must not be empty");
  if (idx.size() / 3 > size_t(std::numeric_limits<uint32_t>::max() - 2))
    throw Error("scene: too many triangles (" + std::to_string(idx.size() / 3) + ")");
  for (size_t i = 0; i < pos.size(); ++i)
    if (!std::isfinite(pos[i].x) || !std::isfinite(pos[i].y) || !std::isfinite(pos[i].z))
      throw Error("scene: position " + std::to_string(i) + " is not finite");
  ::rast::Scene s;
  s.name = "arrays";
  for (const auto& m : materials) s.materials.push_back(Material{float4{m[0], m[1], m[2], m[3]}, -1});
  const uint32_t nTri = uint32_t(idx.size() / 3);
  if (triMaterial) {
    if (triMaterial->size() != nTri) throw Error("scene: triangleMaterial needs one entry per triangle");
    for (uint32_t t = 0; t < nTri; ++t)
      if ((*triMaterial)[t] < -1 || (*triMaterial)[t] >= int32_t(materials.size()))
        throw Error("scene: triangle " + std::to_string(t) + " has material " + std::to_string((*triMaterial)[t]) +
                    ", outside -1.." + std::to_string(int64_t(materials.size()) - 1));
  }
  const uint32_t whole = addPrim(s, pos, nrm, uv, col, idx, triMaterial ? (*triMaterial)[0] : -1);
  if (!triMaterial) {
    s.draws.push_back(Draw{whole, glm::dmat4(1.0)});
  } else {
    // Runs of equal material share the vertex range: draw order = triangle order.
    const MeshPrim all = s.prims[whole];
    s.prims.pop_back();
    for (uint32_t t = 0; t < nTri;) {
      uint32_t e = t + 1;
      while (e < nTri && (*triMaterial)[e] == (*triMaterial)[t]) ++e;
      MeshPrim p = all;
      p.firstTri = all.firstTri + t;
      p.triCount = e - t;
      p.material = (*triMaterial)[t];
      s.prims.push_back(p);
      s.draws.push_back(Draw{uint32_t(s.prims.size() - 1), glm::dmat4(1.0)});
      t = e;
    }
  }
  s.validate();
  return s;
}

namespace {

template <class T, int N>
std::vector<T> gather(const float* p, size_t n) {
  std::vector<T> v(n);
  if (p) std::memcpy(static_cast<void*>(v.data()), p, n * N * sizeof(float));
  return v;
}

template <class T, class V>
std::vector<T> toHostVector(const V& view) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), view);
  std::vector<T> v(view.extent(0));
  static_assert(sizeof(T) == sizeof(typename V::value_type) * (V::rank == 1 ? 1 : V::static_extent(1)), "layout");
  if (!v.empty()) std::memcpy(static_cast<void*>(v.data()), h.data(), v.size() * sizeof(T));
  return v;
}

Scene wrap(::rast::Scene s) {
  Scene out;
  auto impl = std::make_shared<Scene::Impl>();
  impl->scene = std::move(s);
  out.impl = std::move(impl);
  return out;
}

}  // namespace

Scene Scene::load(const std::string& path, bool allowExternalFiles, uint64_t maxMemory) {
  LoadOptions o;
  o.allowExternalFiles = allowExternalFiles;
  o.maxMemory = maxMemory;
  return wrap(loadSceneArg(path, o));
}

Scene Scene::fromArrays(const MeshArrays& m) {
  if (!m.positions || !m.indices) throw Error("scene: positions and indices are required");
  const std::vector<float3> pos = gather<float3, 3>(m.positions, m.vertexCount);
  std::vector<uint32_t> idx(m.indices, m.indices + 3 * m.triangleCount);
  std::vector<float3> nrm;
  std::vector<float2> uv;
  std::vector<float4> col;
  std::vector<int32_t> mat;
  if (m.normals) nrm = gather<float3, 3>(m.normals, m.vertexCount);
  if (m.uvs) uv = gather<float2, 2>(m.uvs, m.vertexCount);
  if (m.colors) col = gather<float4, 4>(m.colors, m.vertexCount);
  if (m.triangleMaterial) mat.assign(m.triangleMaterial, m.triangleMaterial + m.triangleCount);
  return wrap(meshScene(pos, m.normals ? &nrm : nullptr, m.uvs ? &uv : nullptr, m.colors ? &col : nullptr, idx,
                        m.triangleMaterial ? &mat : nullptr, m.materials));
}

Scene Scene::fromViews(const ExecutionSpace& exec, const MeshViews& m) {
  exec.fence();
  if (!m.positions.data() || !m.indices.data()) throw Error("scene: positions and indices are required");
  const size_t nv = m.positions.extent(0);
  const auto sized = [nv](size_t n, const char* what) {
    if (n != nv) throw Error(std::string("scene: ") + what + " has " + std::to_string(n) + " rows, positions " + std::to_string(nv));
  };
  const std::vector<float3> pos = toHostVector<float3>(m.positions);
  const std::vector<uint32_t> idx3 = [&] {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), m.indices);
    return std::vector<uint32_t>(h.data(), h.data() + 3 * h.extent(0));
  }();
  std::vector<float3> nrm;
  std::vector<float2> uv;
  std::vector<float4> col;
  std::vector<int32_t> mat;
  if (m.normals.data()) sized(m.normals.extent(0), "normals"), nrm = toHostVector<float3>(m.normals);
  if (m.uvs.data()) sized(m.uvs.extent(0), "uvs"), uv = toHostVector<float2>(m.uvs);
  if (m.colors.data()) sized(m.colors.extent(0), "colors"), col = toHostVector<float4>(m.colors);
  if (m.triangleMaterial.data()) mat = toHostVector<int32_t>(m.triangleMaterial);
  return wrap(meshScene(pos, m.normals.data() ? &nrm : nullptr, m.uvs.data() ? &uv : nullptr,
                        m.colors.data() ? &col : nullptr, idx3, m.triangleMaterial.data() ? &mat : nullptr,
                        m.materials));
}

uint32_t Scene::triangleCount() const { return impl ? impl->scene.triangleCount() : 0; }

std::array<double, 6> Scene::bounds() const {
  if (!impl) throw Error("scene: empty");
  glm::dvec3 lo, hi;
  impl->scene.worldBounds(lo, hi);
  return {lo.x, lo.y, lo.z, hi.x, hi.y, hi.z};
}

::rast::Camera toCamera(const Camera& p) {
  ::rast::Camera c;
  c.eye = {p.eye[0], p.eye[1], p.eye[2]};
  c.target = {p.target[0], p.target[1], p.target[2]};
  c.up = {p.up[0], p.up[1], p.up[2]};
  c.fovyDeg = p.fovyDeg;
  c.znear = p.znear;
  c.zfar = p.zfar;
  if (p.viewProjection) {
    glm::dmat4 m;
    for (int i = 0; i < 16; ++i) {
      if (!std::isfinite((*p.viewProjection)[i])) throw Error("camera: viewProjection has a non-finite value");
      m[i / 4][i % 4] = (*p.viewProjection)[i];
    }
    c.viewProjOverride = m;
    return c;
  }
  if (!(c.fovyDeg > 0.0 && c.fovyDeg < 180.0)) throw Error("--fovy must be in (0, 180) degrees");
  if (!(c.znear > 0.0) || !(c.zfar > c.znear) || !std::isfinite(c.zfar))
    throw Error("--near/--far: need 0 < near < far");
  if (glm::length(c.eye - c.target) == 0.0) throw Error("--eye and --target must differ");
  if (glm::length(glm::cross(c.target - c.eye, c.up)) == 0.0)
    throw Error("--up must not be parallel to the view direction");
  return c;
}

Camera fromCamera(const ::rast::Camera& c) {
  Camera p;
  p.eye = {c.eye.x, c.eye.y, c.eye.z};
  p.target = {c.target.x, c.target.y, c.target.z};
  p.up = {c.up.x, c.up.y, c.up.z};
  p.fovyDeg = c.fovyDeg;
  p.znear = c.znear;
  p.zfar = c.zfar;
  return p;
}

Camera Camera::framing(const Scene& scene, double fovyDeg) {
  if (!scene.impl) throw Error("camera: empty scene");
  if (!(fovyDeg > 0.0 && fovyDeg < 180.0)) throw Error("--fovy must be in (0, 180) degrees");
  return fromCamera(defaultCamera(scene.impl->scene, fovyDeg));
}

std::string Camera::flags() const { return toCamera(*this).flags(); }

}  // namespace lib
}  // namespace rast

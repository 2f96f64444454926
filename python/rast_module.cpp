// The Python extension `rast._rast` (docs/python.md), over the public C++ API
// (include/rast/rast.h) only. numpy buffers are wrapped as unmanaged Kokkos
// Views, no copy; DLPack tensors (torch, CuPy, ...) on the library's device are
// wrapped the same way, and outputs go back as DLPack arrays in the library's
// memory (python/dlpack_arrays.h). Input checks happen in rast/__init__.py
// first, and are repeated here where a bad buffer could crash. rast::Error
// becomes ValueError. The module initialises Kokkos on import when its caller
// has not, and finalises it at interpreter exit when no array or context of
// its own still holds Kokkos memory.
#include <rast/rast.h>  // as a consumer of the installed package includes it

#include "dlpack_arrays.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdlib>
#include <cstring>

namespace py = pybind11;
using namespace rast;
using rast_python::Borrowed;
using rast_python::DeviceArray;
using rast_python::KokkosHold;

namespace {

// numpy's buffers as views; moved to the library's memory space only when it is
// not the host's (GPU builds), else used in place.
template <class T>
using HostView = Kokkos::View<T, Kokkos::LayoutRight, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>>;

template <class T>
py::array_t<T, py::array::c_style> checked(const py::handle& h, const char* name, int ndim, py::ssize_t last) {
  if (!py::isinstance<py::array_t<T, py::array::c_style>>(h))
    throw py::type_error(std::string(name) + ": expected a C-contiguous array of " + py::str(py::dtype::of<T>()).cast<std::string>());
  auto a = py::reinterpret_borrow<py::array_t<T, py::array::c_style>>(h);
  if (a.ndim() != ndim || (last > 0 && a.shape(ndim - 1) != last))
    throw py::value_error(std::string(name) + ": expected " + std::to_string(ndim) + " dimensions, the last of size " +
                          std::to_string(last));
  return a;
}

lib::Scene sceneFromArrays(py::handle pos, py::handle idx, py::handle nrm, py::handle uv, py::handle col,
                           py::handle triMat, std::vector<std::array<float, 4>> materials) {
  auto p = checked<float>(pos, "positions", 2, 3);
  auto i = checked<uint32_t>(idx, "indices", 2, 3);
  lib::MeshArrays m;
  m.positions = p.data();
  m.vertexCount = size_t(p.shape(0));
  m.indices = i.data();
  m.triangleCount = size_t(i.shape(0));
  py::array_t<float, py::array::c_style> n, u, c;
  py::array_t<int32_t, py::array::c_style> t;
  const auto perVertex = [&](const py::array& a, const char* what) {
    if (a.shape(0) != p.shape(0))
      throw py::value_error(std::string(what) + ": " + std::to_string(a.shape(0)) + " rows, positions have " +
                            std::to_string(p.shape(0)));
  };
  if (!nrm.is_none()) n = checked<float>(nrm, "normals", 2, 3), perVertex(n, "normals"), m.normals = n.data();
  if (!uv.is_none()) u = checked<float>(uv, "uvs", 2, 2), perVertex(u, "uvs"), m.uvs = u.data();
  if (!col.is_none()) c = checked<float>(col, "colors", 2, 4), perVertex(c, "colors"), m.colors = c.data();
  if (!triMat.is_none()) {
    t = checked<int32_t>(triMat, "triangle_material", 1, 0);
    if (t.shape(0) != i.shape(0)) throw py::value_error("triangle_material: one entry per triangle expected");
    m.triangleMaterial = t.data();
  }
  m.materials = std::move(materials);
  return lib::Scene::fromArrays(m);
}

// A frame's [H][W][3] output, top row first.
DeviceArray topDown3(const View<const float** [3]>& v, const char* label) {
  const int64_t h = int64_t(v.extent(0)), w = int64_t(v.extent(1));
  auto a = DeviceArray::allocate<float>(label, {h, w, 3});
  float* o = a.data<float>();
  Kokkos::parallel_for(
      "rast::python::frame_out_vec3", Kokkos::RangePolicy<ExecutionSpace>(0, h * w), KOKKOS_LAMBDA(const int64_t p) {
        const int64_t y = p / w, x = p % w, src = h - 1 - y;
        for (int k = 0; k < 3; ++k) o[3 * p + k] = v(src, x, k);
      });
  return a;
}

// The frame's outputs as arrays in the library's memory, top row first (the
// frame keeps OpenGL's bottom-up rows), ids as int64 with -1 where empty.
py::dict frameArrays(const lib::Frame& f, bool normals, bool barycentrics) {
  const int64_t h = f.height, w = f.width;
  auto color = DeviceArray::allocate<uint8_t>("rast::python::color", {h, w, 4});
  auto depth = DeviceArray::allocate<float>("rast::python::depth", {h, w});
  auto ids = DeviceArray::allocate<int64_t>("rast::python::ids", {h, w});
  {
    uint8_t* c = color.data<uint8_t>();
    float* d = depth.data<float>();
    int64_t* i = ids.data<int64_t>();
    const auto fc = f.color, fi = f.primIds;
    const auto fd = f.depth;
    Kokkos::parallel_for(
        "rast::python::frame_out", Kokkos::RangePolicy<ExecutionSpace>(0, h * w), KOKKOS_LAMBDA(const int64_t p) {
          const int64_t y = p / w, x = p % w, src = h - 1 - y;
          const uint32_t rgba = fc(src, x);
          for (int k = 0; k < 4; ++k) c[4 * p + k] = uint8_t(rgba >> (8 * k));
          d[p] = fd(src, x);
          i[p] = int64_t(fi(src, x)) - 1;
        });
  }
  py::dict out;
  if (normals) out["normals"] = topDown3(f.normals, "rast::python::normals");
  if (barycentrics) out["barycentrics"] = topDown3(f.barycentrics, "rast::python::barycentrics");
  Kokkos::fence();
  out["color"] = color;
  out["depth"] = depth;
  out["ids"] = ids;
  out["triangles"] = f.trianglesIn;
  out["method"] = f.method;
  return out;
}

py::dict render(const lib::Scene& scene, const lib::Camera& cam, int width, int height, const std::string& shading,
                const std::string& cull, const std::string& filter, const std::string& raster, const std::string& aa,
                std::optional<std::array<float, 3>> background, bool normals, bool barycentrics) {
  lib::Settings s;
  s.width = width;
  s.height = height;
  s.shading = shading;
  s.cull = cull;
  s.filter = filter;
  s.raster = raster;
  s.aa = aa;
  s.background = background;
  s.normals = normals;
  s.barycentrics = barycentrics;
  lib::Renderer r(scene);
  const lib::Frame* f = nullptr;
  {
    py::gil_scoped_release nogil;
    f = &r.render(ExecutionSpace(), cam, s);
  }
  return frameArrays(*f, normals, barycentrics);
}

void copyToHost(void* dst, const char* src, size_t bytes) {
  Kokkos::View<char*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> d(static_cast<char*>(dst), bytes);
  Kokkos::View<const char*, MemorySpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> s(src, bytes);
  Kokkos::deep_copy(d, s);
}

// A DeviceArray as a numpy array: a writable view of the same buffer in host
// builds (numpy's own from_dlpack makes read-only ones), a copy in GPU builds.
py::array toNumpy(const DeviceArray& a) {
  const DLDataType t = a.dtype();
  const py::dtype dt(std::string(t.code == kDLFloat ? "<f" : t.code == kDLInt ? "<i" : "<u") + std::to_string(t.bits / 8));
  const std::vector<py::ssize_t> shape(a.shape().begin(), a.shape().end());
  // C-order strides given, not left to pybind11: Debian's pybind11 (2.10)
  // reads the item size from numpy 1's dtype layout, and under numpy 2 (the
  // H100 machine's) got 0, so every element aliased the first.
  std::vector<py::ssize_t> strides(shape.size());
  py::ssize_t step = py::ssize_t(t.bits / 8) * py::ssize_t(t.lanes);
  for (size_t i = shape.size(); i-- > 0;) {
    strides[i] = step;
    step *= shape[i];
  }
  if (rast_python::libraryDevice().device_type == kDLCPU)
    return py::array(dt, shape, strides, a.data<void>(), a.keeper());
  py::array host(dt, shape, strides);
  const size_t bytes = size_t(step);  // not host.nbytes(): the same item size
  copyToHost(host.mutable_data(), a.data<const char>(), bytes);
  return host;
}

// A Kokkos Tools profile region, closed by end() or at the scope's end
// (exceptions included), so that tools see where a call's host time goes.
class ProfileRegion {
 public:
  explicit ProfileRegion(const char* name) { Kokkos::Profiling::pushRegion(name); }
  ~ProfileRegion() { end(); }
  ProfileRegion(const ProfileRegion&) = delete;
  ProfileRegion& operator=(const ProfileRegion&) = delete;
  void end() {
    if (open_) Kokkos::Profiling::popRegion();
    open_ = false;
  }

 private:
  bool open_ = true;
};

// nvdiffrast's RasterizeCudaContext: a lib::Rasterizer kept across calls.
struct RasterizeContext {
  KokkosHold hold;  // first: destroyed after the Kokkos memory below
  lib::Rasterizer rasterizer;
  rast_python::BufferPool outputs;
};

// A [N, width] input in the library's memory: the producer's buffer itself
// when it is there already, else a copy of its host buffer.
template <class T, int Width>
View<const T* [Width]> inLibraryMemory(const Borrowed& b, int64_t rows) {
  if (b.onLibraryDevice()) return View<const T* [Width]>(b.data<T>(), size_t(rows));
  if (!b.onHost()) b.wrongDevice();
  const HostView<const T* [Width]> host(b.data<T>(), size_t(rows));
  return Kokkos::create_mirror_view_and_copy(MemorySpace(), host);
}

// pos [B,V,4] or [V,4] float32, tri [T,3] int32, any DLPack producers (numpy
// arrays too). Returns (out [B,H,W,4] float32, ids [B,H,W] int32) as DLPack
// arrays in the library's memory, rows bottom first as nvdiffrast's.
py::tuple rasterize(RasterizeContext& ctx, py::handle posH, py::handle triH, int height, int width) {
  if (height < 1 || width < 1 || height > 16384 || width > 16384)
    throw py::value_error("resolution: (height, width) must be within 1..16384");
  // Profile regions (Kokkos Tools): a call's host time is mostly its fixed
  // cost on small scenes (docs/python.md), split here into the inputs' import
  // and the library's call.
  ProfileRegion whole("rast::python::rasterize"), inputs("rast::python::rasterize::inputs");
  Borrowed pb(posH, "pos"), tb(triH, "tri", pb.ordered());
  const int pr = pb.check<float>({2, 3}, 4);
  tb.check<int32_t>({2}, 3);
  const int64_t batch = pr == 3 ? pb.dim(0) : 1, nv = pb.dim(pr - 2), nt = tb.dim(0);
  const auto pos = inLibraryMemory<float, 4>(pb, batch * nv);
  const auto tri = inLibraryMemory<int32_t, 3>(tb, nt);
  auto out = ctx.outputs.take<float>("rast::python::rasterize_out", {batch, height, width, 4});
  auto ids = ctx.outputs.take<int32_t>("rast::python::rasterize_ids", {batch, height, width});
  inputs.end();
  {
    py::gil_scoped_release nogil;
    const int64_t pixels = int64_t(height) * width;
    for (int64_t b = 0; b < batch; ++b)
      ctx.rasterizer.rasterize(ExecutionSpace(), View<const float* [4]>(pos.data() + b * nv * 4, size_t(nv)), tri,
                               width, height, View<float** [4]>(out.data<float>() + b * pixels * 4, height, width),
                               View<int32_t**>(ids.data<int32_t>() + b * pixels, height, width));
  }
  ProfileRegion outputs("rast::python::rasterize::outputs");
  return py::make_tuple(out, ids);
}

}  // namespace

PYBIND11_MODULE(_rast, m) {
  m.doc() = "rast: a portable Kokkos rasterizer (docs/python.md)";
  if (!Kokkos::is_initialized()) {  // (Kokkos 3.4 has no is_finalized)
    if (!std::getenv("OMP_PROC_BIND")) setenv("OMP_PROC_BIND", "false", 0);  // as the CLI (app/guarded_main.cpp)
    Kokkos::initialize();
    py::module_::import("atexit").attr("register")(py::cpp_function([] {
      // Arrays and contexts still alive are freed after this hook, and Kokkos
      // aborts on a view freed after finalize: then the last of them finalises.
      if (!Kokkos::is_initialized()) return;
      if (rast_python::liveKokkosObjects() == 0) Kokkos::finalize();
      else rast_python::finalizeWhenFree() = true;
    }));
  }
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const rast::Error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  m.attr("__version__") = lib::version();
  m.attr("backend") = lib::backend();
  m.attr("_follows_legacy_stream") = lib::deviceStreamFollowsLegacy();
  m.attr("on_device") = !Kokkos::SpaceAccessibility<ExecutionSpace, Kokkos::HostSpace>::accessible;

  py::class_<lib::Scene>(m, "Scene", "a scene: geometry, materials, textures, lights")
      .def_static("load", &lib::Scene::load, py::arg("path"), py::arg("allow_external_files") = false,
                  py::arg("max_memory") = 0, "a glTF file, 'builtin:<name>' or '' (the default scene)")
      .def_static("from_arrays", &sceneFromArrays, py::arg("positions"), py::arg("indices"),
                  py::arg("normals") = py::none(), py::arg("uvs") = py::none(), py::arg("colors") = py::none(),
                  py::arg("triangle_material") = py::none(),
                  py::arg("materials") = std::vector<std::array<float, 4>>{})
      .def_property_readonly("triangle_count", &lib::Scene::triangleCount)
      .def_property_readonly("bounds", &lib::Scene::bounds);

  py::class_<lib::Camera>(m, "Camera", "pinhole camera, OpenGL conventions")
      .def(py::init<>())
      .def_readwrite("eye", &lib::Camera::eye)
      .def_readwrite("target", &lib::Camera::target)
      .def_readwrite("up", &lib::Camera::up)
      .def_readwrite("fovy", &lib::Camera::fovyDeg)
      .def_readwrite("near", &lib::Camera::znear)
      .def_readwrite("far", &lib::Camera::zfar)
      .def_readwrite("view_projection", &lib::Camera::viewProjection)
      .def_static("framing", &lib::Camera::framing, py::arg("scene"), py::arg("fovy") = 45.0)
      .def("flags", &lib::Camera::flags);

  m.attr("device_index") = lib::deviceIndex();

  py::class_<DeviceArray>(m, "DeviceArray",
                          "an output array in the library's memory (the GPU's in GPU builds), shared through DLPack: "
                          "torch.from_dlpack, numpy.from_dlpack (host builds) and cupy.from_dlpack take it without a copy")
      .def("__dlpack__", [](const DeviceArray& a, py::args, py::kwargs) { return a.capsule(); })
      .def("__dlpack_device__",
           [](const DeviceArray&) {
             const DLDevice d = rast_python::libraryDevice();
             return py::make_tuple(int(d.device_type), d.device_id);
           })
      .def_property_readonly("shape", [](const DeviceArray& a) { return py::tuple(py::cast(a.shape())); })
      .def_property_readonly("dtype", [](const DeviceArray& a) { return rast_python::describe(a.dtype()); })
      .def_property_readonly("data_ptr", [](const DeviceArray& a) { return reinterpret_cast<uintptr_t>(a.data<void>()); },
                             "the buffer's address (in the build's memory space)")
      .def("numpy", &toNumpy, "a numpy array: the same buffer in CPU builds, a copy in host memory in GPU builds")
      .def("__repr__", [](const DeviceArray& a) {
        std::string s = "rast.DeviceArray(shape=(";
        for (size_t i = 0; i < a.shape().size(); ++i) s += (i ? ", " : "") + std::to_string(a.shape()[i]);
        return s + "), dtype=" + rast_python::describe(a.dtype()) + ", backend=" + lib::backend() + ")";
      });

  py::class_<RasterizeContext>(m, "RasterizeContext",
                               "buffers kept across rasterize calls, as nvdiffrast's RasterizeCudaContext")
      .def(py::init<>());

  m.def("_render", &render);
  m.def("_rasterize", &rasterize);
}

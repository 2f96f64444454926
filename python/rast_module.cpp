// The Python extension `rast._rast` (docs/python.md), over the public C++ API
// (include/rast/rast.h) only. numpy buffers are wrapped as unmanaged Kokkos
// Views, no copy; input checks and DLPack conversion happen in rast/__init__.py
// first, and are repeated here where a bad buffer could crash. rast::Error
// becomes ValueError. The module initialises Kokkos on import when its caller
// has not, and finalises it at interpreter exit.
#include <rast/rast.h>  // as a consumer of the installed package includes it

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cstdlib>
#include <cstring>

namespace py = pybind11;
using namespace rast;

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
  lib::Frame f;
  {
    py::gil_scoped_release nogil;
    f = r.render(ExecutionSpace(), cam, s);
  }
  // Top row first, as images are stored (the frame keeps OpenGL's bottom-up rows).
  const size_t h = size_t(f.height), w = size_t(f.width);
  const auto fc = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f.color);
  const auto fd = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f.depth);
  const auto fi = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f.primIds);
  py::array_t<uint8_t> color({h, w, size_t(4)});
  py::array_t<float> depth({h, w});
  py::array_t<int64_t> ids({h, w});
  for (size_t y = 0; y < h; ++y) {
    const size_t src = h - 1 - y;
    std::memcpy(color.mutable_data(y), &fc(src, 0), w * 4);
    std::memcpy(depth.mutable_data(y), &fd(src, 0), w * sizeof(float));
    int64_t* d = ids.mutable_data(y);
    for (size_t x = 0; x < w; ++x) d[x] = int64_t(fi(src, x)) - 1;
  }
  py::dict out;
  out["color"] = color;
  out["depth"] = depth;
  out["ids"] = ids;
  if (normals) {
    py::array_t<float> n({h, w, size_t(3)});
    const auto fn = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f.normals);
    for (size_t y = 0; y < h; ++y) std::memcpy(n.mutable_data(y), &fn(h - 1 - y, 0, 0), w * 3 * sizeof(float));
    out["normals"] = n;
  }
  if (barycentrics) {
    py::array_t<float> b({h, w, size_t(3)});
    const auto fb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f.barycentrics);
    for (size_t y = 0; y < h; ++y) std::memcpy(b.mutable_data(y), &fb(h - 1 - y, 0, 0), w * 3 * sizeof(float));
    out["barycentrics"] = b;
  }
  out["triangles"] = f.trianglesIn;
  out["method"] = f.method;
  return out;
}

py::tuple rasterize(py::handle posH, py::handle triH, int height, int width) {
  auto pos = checked<float>(posH, "pos", 2, 4);
  auto tri = checked<int32_t>(triH, "tri", 2, 3);
  if (height < 1 || width < 1 || height > 16384 || width > 16384)
    throw py::value_error("resolution: (height, width) must be within 1..16384");
  py::array_t<float> out({size_t(height), size_t(width), size_t(4)});
  py::array_t<int32_t> ids({size_t(height), size_t(width)});
  const HostView<const float* [4]> hp(pos.data(), size_t(pos.shape(0)));
  const HostView<const int32_t* [3]> ht(tri.data(), size_t(tri.shape(0)));
  const HostView<float** [4]> ho(out.mutable_data(), size_t(height), size_t(width));
  const HostView<int32_t**> hi(ids.mutable_data(), size_t(height), size_t(width));
  {
    py::gil_scoped_release nogil;
    const auto p = Kokkos::create_mirror_view_and_copy(MemorySpace(), hp);
    const auto t = Kokkos::create_mirror_view_and_copy(MemorySpace(), ht);
    const auto o = Kokkos::create_mirror_view(MemorySpace(), ho);
    const auto i = Kokkos::create_mirror_view(MemorySpace(), hi);
    lib::rasterize(ExecutionSpace(), p, t, width, height, o, i);
    Kokkos::deep_copy(ho, o);  // nothing to do where they are the same buffer (host builds)
    Kokkos::deep_copy(hi, i);
  }
  return py::make_tuple(out, ids);
}

}  // namespace

PYBIND11_MODULE(_rast, m) {
  m.doc() = "rast: a portable Kokkos rasterizer (docs/python.md)";
  if (!Kokkos::is_initialized()) {  // (Kokkos 3.4 has no is_finalized)
    if (!std::getenv("OMP_PROC_BIND")) setenv("OMP_PROC_BIND", "false", 0);  // as the CLI (app/guarded_main.cpp)
    Kokkos::initialize();
    py::module_::import("atexit").attr("register")(py::cpp_function([] {
      if (Kokkos::is_initialized()) Kokkos::finalize();
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

  m.def("_render", &render);
  m.def("_rasterize", &rasterize);
}

// DLPack in and out for the Python module (docs/python.md): why it exists is
// that torch, CuPy, JAX and numpy all speak DLPack, so a GPU build can take
// their device tensors and hand its outputs back without a copy through the
// host, and a CPU build can do the same with host memory. Debian's
// libdlpack-dev (0.6) supplies the header; the capsule protocol is the one in
// its documentation (a "dltensor" capsule, renamed "used_dltensor" by the
// consumer, whose deleter the consumer calls when done).
//
// Kokkos aborts when a view is freed after Kokkos::finalize, and arrays handed
// to Python (and contexts) can outlive the interpreter's atexit hooks, so
// every such object counts itself in liveKokkosObjects(); the module
// finalises Kokkos at exit when none is left, else the last one to go does.
#pragma once

#include <rast/rast.h>

#include <dlpack/dlpack.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <string>
#include <vector>

namespace rast_python {

namespace py = pybind11;

inline std::atomic<long>& liveKokkosObjects() {
  static std::atomic<long> n{0};
  return n;
}
// Set by the module's exit hook when objects were still alive then: the last
// of them to go finalises Kokkos (Kokkos complains at process end otherwise).
inline std::atomic<bool>& finalizeWhenFree() {
  static std::atomic<bool> pending{false};
  return pending;
}

// Counts an object holding Kokkos memory for as long as it lives. It must be
// the first member of its holder, so that it goes after the Kokkos memory
// (members are destroyed last to first).
struct KokkosHold {
  KokkosHold() { ++liveKokkosObjects(); }
  KokkosHold(const KokkosHold&) { ++liveKokkosObjects(); }
  KokkosHold& operator=(const KokkosHold&) = default;
  ~KokkosHold() {
    if (--liveKokkosObjects() == 0 && finalizeWhenFree().exchange(false) && Kokkos::is_initialized())
      Kokkos::finalize();
  }
};

// Where the library's memory lives, as DLPack names it.
inline DLDevice libraryDevice() {
  if (Kokkos::SpaceAccessibility<Kokkos::HostSpace, rast::MemorySpace>::accessible) return DLDevice{kDLCPU, 0};
#if defined(KOKKOS_ENABLE_HIP)
  return DLDevice{kDLROCM, rast::lib::deviceIndex()};
#else
  return DLDevice{kDLCUDA, rast::lib::deviceIndex()};
#endif
}

template <class T>
DLDataType dlType() {
  if (std::is_floating_point<T>::value) return DLDataType{kDLFloat, uint8_t(8 * sizeof(T)), 1};
  if (std::is_signed<T>::value) return DLDataType{kDLInt, uint8_t(8 * sizeof(T)), 1};
  return DLDataType{kDLUInt, uint8_t(8 * sizeof(T)), 1};
}

inline std::string describe(DLDataType t) {
  const char* kind = t.code == kDLFloat ? "float" : t.code == kDLInt ? "int" : t.code == kDLUInt ? "uint" : "type";
  return std::string(kind) + std::to_string(int(t.bits)) + (t.lanes != 1 ? "x" + std::to_string(int(t.lanes)) : "");
}

// An output buffer in the library's memory space, exported through DLPack
// (torch.from_dlpack, np.from_dlpack, cupy.from_dlpack take it without a copy).
class DeviceArray {
 public:
  template <class T>
  static DeviceArray allocate(const std::string& label, std::vector<int64_t> shape) {
    Kokkos::View<char*, rast::MemorySpace> v(Kokkos::view_alloc(label, Kokkos::WithoutInitializing),
                                             std::max<size_t>(1, bytesOf<T>(shape)));
    return wrap<T>(std::make_shared<Owned>(v), v.data(), std::move(shape));
  }
  // Another array over a buffer held by `owner` (BufferPool's reuse).
  template <class T>
  static DeviceArray wrap(std::shared_ptr<void> owner, void* data, std::vector<int64_t> shape) {
    DeviceArray a;
    a.data_ = data;
    a.owner_ = std::move(owner);
    a.shape_ = std::move(shape);
    a.dtype_ = dlType<T>();
    return a;
  }
  template <class T>
  static size_t bytesOf(const std::vector<int64_t>& shape) {
    size_t n = sizeof(T);
    for (int64_t s : shape) n *= size_t(s);
    return n;
  }
  const std::shared_ptr<void>& owner() const { return owner_; }
  template <class T>
  T* data() const { return static_cast<T*>(data_); }
  const std::vector<int64_t>& shape() const { return shape_; }
  DLDataType dtype() const { return dtype_; }

  // A Python object that keeps the buffer alive (the base of a numpy view).
  py::capsule keeper() const {
    auto* keep = new std::shared_ptr<void>(owner_);
    return py::capsule(keep, [](void* p) { delete static_cast<std::shared_ptr<void>*>(p); });
  }

  // __dlpack__(stream=None): the library fences its work before returning an
  // array, so any stream may read it at once.
  py::capsule capsule() const {
    auto* e = new Exported{};
    e->owner = owner_;
    e->shape = shape_;
    DLTensor& t = e->managed.dl_tensor;
    t.data = data_;
    t.device = libraryDevice();
    t.ndim = int(e->shape.size());
    t.dtype = dtype_;
    t.shape = e->shape.data();
    t.strides = nullptr;  // compact, row-major
    t.byte_offset = 0;
    e->managed.manager_ctx = e;
    e->managed.deleter = [](DLManagedTensor* m) { delete static_cast<Exported*>(m->manager_ctx); };
    PyObject* cap = PyCapsule_New(&e->managed, "dltensor", &capsuleDestructor);
    if (!cap) {
      delete e;
      throw py::error_already_set();
    }
    return py::reinterpret_steal<py::capsule>(cap);
  }

 private:
  struct Owned {  // a buffer, counted while it lives
    explicit Owned(Kokkos::View<char*, rast::MemorySpace> v) : view(std::move(v)) {}
    KokkosHold hold;  // first: destroyed after the view
    Kokkos::View<char*, rast::MemorySpace> view;
  };
  struct Exported {
    DLManagedTensor managed{};
    std::shared_ptr<void> owner;
    std::vector<int64_t> shape;
  };
  // A capsule nobody consumed frees its tensor; a consumed one was renamed.
  static void capsuleDestructor(PyObject* cap) {
    if (PyCapsule_IsValid(cap, "used_dltensor")) return;
    PyObject *type, *value, *trace;
    PyErr_Fetch(&type, &value, &trace);
    auto* m = static_cast<DLManagedTensor*>(PyCapsule_GetPointer(cap, "dltensor"));
    if (m && m->deleter) m->deleter(m);
    if (!m) PyErr_WriteUnraisable(cap);
    PyErr_Restore(type, value, trace);
  }

  void* data_ = nullptr;
  std::shared_ptr<void> owner_;
  std::vector<int64_t> shape_;
  DLDataType dtype_{};
};

// The output buffers of one context, reused once nothing outside holds them
// (the pool's own reference is the last): a 1080p rasterize hands out 41 MB a
// call, and allocating device memory each time costs more than drawing small
// scenes. The GIL serialises the checks and the releases.
class BufferPool {
 public:
  template <class T>
  DeviceArray take(const std::string& label, std::vector<int64_t> shape) {
    const size_t bytes = std::max<size_t>(1, DeviceArray::bytesOf<T>(shape));
    for (const Entry& e : entries_)
      if (e.bytes == bytes && e.owner.use_count() == 1) return DeviceArray::wrap<T>(e.owner, e.data, std::move(shape));
    if (entries_.size() >= kMaxIdle) {  // forget one that is free, if any (bounded memory)
      for (size_t i = 0; i < entries_.size(); ++i)
        if (entries_[i].owner.use_count() == 1) {
          entries_.erase(entries_.begin() + long(i));
          break;
        }
    }
    DeviceArray a = DeviceArray::allocate<T>(label, std::move(shape));
    entries_.push_back(Entry{bytes, a.owner(), a.data<void>()});
    return a;
  }

 private:
  static constexpr size_t kMaxIdle = 8;
  struct Entry {
    size_t bytes;
    std::shared_ptr<void> owner;
    void* data;
  };
  std::vector<Entry> entries_;
};

// A producer's tensor borrowed for one call: its DLManagedTensor is released
// (the producer's deleter) when this goes out of scope.
class Borrowed {
 public:
  // obj: anything with __dlpack__, or a "dltensor" capsule. A producer on the
  // library's GPU is given the library's stream (the DLPack protocol's
  // `stream`): it orders its own pending work before the library's on the
  // device (torch records an event on its current stream for the library's
  // stream to wait on), so no caller waits on the host.
  // One producer's event covers the others of the same call (torch records
  // it on its current stream, behind all the work queued there): later ones
  // pass ordered = true and skip the protocol's cost (about 15 us of Python
  // a tensor).
  Borrowed(py::handle obj, const std::string& name, bool ordered = false) : name_(name) {
    py::object cap;
    if (!py::hasattr(obj, "__dlpack__")) {
      cap = py::reinterpret_borrow<py::object>(obj);
    } else if (!ordered && onLibraryGpu(obj)) {
      cap = obj.attr("__dlpack__")(py::arg("stream") = libraryStreamArgument());
      ordered_ = true;
    } else {
      cap = obj.attr("__dlpack__")();
    }
    if (!PyCapsule_IsValid(cap.ptr(), "dltensor"))
      throw py::type_error(name + ": expected an object with __dlpack__ (or an unused DLPack capsule)");
    m_ = static_cast<DLManagedTensor*>(PyCapsule_GetPointer(cap.ptr(), "dltensor"));
    PyCapsule_SetName(cap.ptr(), "used_dltensor");
  }
  ~Borrowed() {
    if (m_ && m_->deleter) m_->deleter(m_);
  }
  Borrowed(const Borrowed&) = delete;
  Borrowed& operator=(const Borrowed&) = delete;

  const DLTensor& tensor() const { return m_->dl_tensor; }
  // The producer was asked to order its pending work before the library's.
  bool ordered() const { return ordered_; }
  int64_t dim(int i) const { return m_->dl_tensor.shape[i]; }

  // Checks dtype, rank (one of ranks), the last extent and compact row-major
  // strides; returns the rank.
  template <class T>
  int check(std::initializer_list<int> ranks, int64_t last) const {
    const DLTensor& t = m_->dl_tensor;
    const DLDataType want = dlType<T>();
    if (t.dtype.code != want.code || t.dtype.bits != want.bits || t.dtype.lanes != want.lanes)
      throw py::type_error(name_ + ": expected dtype " + describe(want) + ", got " + describe(t.dtype));
    bool rankOk = false;
    for (int r : ranks) rankOk = rankOk || t.ndim == r;
    if (!rankOk || t.shape[t.ndim - 1] != last)
      throw py::value_error(name_ + ": expected " + std::to_string(*ranks.begin()) + " dimensions (or " +
                            std::to_string(*(ranks.end() - 1)) + "), the last of size " + std::to_string(last));
    if (t.strides) {
      int64_t expect = 1;
      for (int i = t.ndim - 1; i >= 0; --i) {
        if (t.shape[i] != 1 && t.strides[i] != expect)
          throw py::value_error(name_ + ": the tensor is not contiguous: pass " + name_ + ".contiguous()");
        expect *= t.shape[i];
      }
    }
    return t.ndim;
  }

  // Host memory for host builds; on GPU builds the library's own device, or
  // host memory that the caller then copies over.
  bool onLibraryDevice() const {
    const DLDevice d = m_->dl_tensor.device, lib = libraryDevice();
    if (lib.device_type == kDLCPU) return d.device_type == kDLCPU || d.device_type == kDLCUDAHost;
    return d.device_type == lib.device_type && d.device_id == lib.device_id;
  }
  bool onHost() const {
    const DLDevice d = m_->dl_tensor.device;
    return d.device_type == kDLCPU || d.device_type == kDLCUDAHost;
  }
  [[noreturn]] void wrongDevice() const {
    const DLDevice d = m_->dl_tensor.device, lib = libraryDevice();
    throw py::value_error(name_ + ": the tensor is on DLPack device (" + std::to_string(int(d.device_type)) + ", " +
                          std::to_string(d.device_id) + "); this rast build (" + rast::lib::backend() +
                          ") works on (" + std::to_string(int(lib.device_type)) + ", " +
                          std::to_string(lib.device_id) + "): move it there first");
  }

  template <class T>
  T* data() const {
    return reinterpret_cast<T*>(static_cast<char*>(m_->dl_tensor.data) + m_->dl_tensor.byte_offset);
  }

 private:
  // A producer that says (__dlpack_device__) it lives on the library's GPU.
  static bool onLibraryGpu(py::handle obj) {
    const DLDevice lib = libraryDevice();
    if (lib.device_type == kDLCPU || !py::hasattr(obj, "__dlpack_device__")) return false;
    const py::tuple d = obj.attr("__dlpack_device__")();
    return d.size() == 2 && d[0].cast<int>() == int(lib.device_type) && d[1].cast<int>() == lib.device_id;
  }
  // DLPack's stream numbers: CUDA's legacy default stream is 1 (0 is not
  // allowed there); ROCm's default stream is 0.
  static py::int_ libraryStreamArgument() {
    const uintptr_t s = rast::lib::deviceStream();
    if (s == 0 && libraryDevice().device_type == kDLCUDA) return py::int_(1);
    return py::int_(size_t(s));
  }

  std::string name_;
  DLManagedTensor* m_ = nullptr;
  bool ordered_ = false;
};

}  // namespace rast_python

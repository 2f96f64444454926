"""rast from Python (docs/python.md): render a scene into numpy arrays, and
rasterize clip-space triangles as nvdiffrast's dr.rasterize does.

Inputs may be numpy arrays, torch tensors or anything with __dlpack__; they
are taken without a copy when they already have the dtype, layout and device
this build needs (host memory in CPU builds; the GPU's, or host memory copied
over, in GPU builds), and refused with a clear exception otherwise. Outputs
are made in the build's memory and shared through DLPack (rast.DeviceArray):
numpy arrays in CPU builds, torch tensors for torch inputs, with no copy.
"""
import numpy as np

from ._rast import Camera, DeviceArray, RasterizeContext, Scene, __version__, backend, device_index, on_device  # noqa: F401
from . import _rast

__all__ = ["Camera", "DeviceArray", "RasterizeContext", "Scene", "render", "rasterize", "backend", "on_device",
           "device_index", "__version__"]

_DLPACK_CPU = 1
_OUTPUTS = ("auto", "numpy", "torch", "dlpack")
_default_context = None


def _release_default_context():
    """Frees the default context's device buffers before the module finalises Kokkos (atexit runs this first)."""
    global _default_context
    _default_context = None


import atexit  # noqa: E402

atexit.register(_release_default_context)


def _context(context):
    global _default_context
    if context is not None:
        if not isinstance(context, RasterizeContext):
            raise TypeError(f"context: expected a rast.RasterizeContext, got {type(context).__name__}")
        return context
    if _default_context is None:
        _default_context = RasterizeContext()
    return _default_context


def _output(a, output):
    """An output DeviceArray as the caller asked: numpy (copied from the GPU in GPU builds), torch, or as it is."""
    if output == "dlpack" or (output == "auto" and on_device):
        return a
    if output == "torch":
        import torch
        # The library fenced its work before returning the array: its capsule
        # needs no stream exchange (torch.from_dlpack(a) would ask for one).
        return torch.from_dlpack(a.__dlpack__())
    return a.numpy()  # writable, the same buffer in CPU builds; a host copy in GPU builds


def _legacy_ordered(x):
    """Whether torch's work on CUDA tensor x is ordered before rast's without
    a DLPack stream exchange: torch's current stream is CUDA's legacy default
    stream, and the library's stream (Kokkos' own, created blocking) waits
    for everything queued there before it. The exchange (torch's
    __dlpack__(stream=...)) costs about 20 us of Python a call."""
    if not x.is_cuda or not _rast._follows_legacy_stream:
        return False
    import torch
    raw = getattr(torch._C, "_cuda_getCurrentRawStream", None)
    return raw is not None and raw(x.device.index) == 0


def _capsule(x):
    """A torch tensor's DLPack capsule without the protocol's stream exchange (see _legacy_ordered)."""
    if not _is_torch(x):
        return x
    import torch.utils.dlpack
    return torch.utils.dlpack.to_dlpack(x)


def _check_output(output):
    if output not in _OUTPUTS:
        raise ValueError(f"output: expected one of {', '.join(_OUTPUTS)}, got {output!r}")


def _is_torch(x):
    return type(x).__module__.split(".")[0] == "torch"


def _to_numpy(x, name):
    """An ndarray view of x (numpy, DLPack producer or sequence), without a copy where possible."""
    if isinstance(x, np.ndarray):
        return x
    if hasattr(x, "__dlpack__"):
        if hasattr(x, "__dlpack_device__"):
            dev = x.__dlpack_device__()
            if int(dev[0]) != _DLPACK_CPU:
                where = getattr(x, "device", dev)
                raise ValueError(f"{name}: the tensor is on device {where}; this rast build ({backend}) "
                                 f"takes host memory: move it with .cpu()")
        if _is_torch(x) and getattr(x, "requires_grad", False):
            x = x.detach()
        if _is_torch(x) and not x.is_contiguous():
            raise ValueError(f"{name}: the tensor is not contiguous (strides {tuple(x.stride())}); "
                             f"pass {name}.contiguous()")
        return np.from_dlpack(x)
    if isinstance(x, (list, tuple)):
        return np.asarray(x)
    raise TypeError(f"{name}: expected a numpy array, a tensor or an object with __dlpack__, "
                    f"got {type(x).__name__}")


def _strict(x, name, dtype, shapes):
    """x as a C-contiguous ndarray of dtype whose shape matches one of shapes (a name: any size)."""
    a = _to_numpy(x, name)
    if a.dtype != dtype:
        raise TypeError(f"{name}: expected dtype {np.dtype(dtype).name}, got {a.dtype.name}")
    if not any(a.ndim == len(s) and all(isinstance(w, str) or w == d for w, d in zip(s, a.shape)) for s in shapes):
        want = " or ".join("[" + ",".join(str(w) for w in s) + "]" for s in shapes)
        raise ValueError(f"{name}: expected shape {want}, got {list(a.shape)}")
    if not a.flags.c_contiguous:
        raise ValueError(f"{name}: the array is not C-contiguous (strides {a.strides}); "
                         f"pass np.ascontiguousarray({name})")
    return a


def _loose(x, name, dtype, width):
    """x converted (copied if need be) to a C-contiguous [N, width] array of dtype."""
    a = _to_numpy(x, name)
    if a.dtype.kind not in "fiu" or (np.dtype(dtype).kind in "iu" and a.dtype.kind == "f"):
        raise TypeError(f"{name}: expected {np.dtype(dtype).name} values, got dtype {a.dtype.name}")
    if a.ndim != 2 or a.shape[1] != width:
        raise ValueError(f"{name}: expected shape [N,{width}], got {list(a.shape)}")
    if np.dtype(dtype).kind == "u" and a.size and (a.min() < 0 or a.max() > np.iinfo(np.uint32).max):
        raise ValueError(f"{name}: indices must be within 0..{np.iinfo(np.uint32).max}")
    return np.ascontiguousarray(a, dtype=dtype)


def _scene(scene):
    if isinstance(scene, Scene):
        return scene
    if scene is None or isinstance(scene, str):
        return Scene.load(scene or "")
    if isinstance(scene, dict):
        known = {"positions", "indices", "normals", "uvs", "colors", "triangle_material", "materials"}
        extra = set(scene) - known
        if extra:
            raise ValueError(f"scene: unknown keys {sorted(extra)} (known: {sorted(known)})")
        if "positions" not in scene or "indices" not in scene:
            raise ValueError("scene: a dict scene needs 'positions' [V,3] and 'indices' [T,3]")
        opt = {k: (None if scene.get(k) is None else _loose(scene[k], k, np.float32, w))
               for k, w in (("normals", 3), ("uvs", 2), ("colors", 4))}
        tm = scene.get("triangle_material")
        if tm is not None:
            tm = np.ascontiguousarray(_to_numpy(tm, "triangle_material"), dtype=np.int32)
        return Scene.from_arrays(_loose(scene["positions"], "positions", np.float32, 3),
                                 _loose(scene["indices"], "indices", np.uint32, 3), opt["normals"], opt["uvs"],
                                 opt["colors"], tm, [tuple(map(float, m)) for m in scene.get("materials", [])])
    raise TypeError(f"scene: expected a path, 'builtin:<name>', a rast.Scene or a dict of arrays, "
                    f"got {type(scene).__name__}")


def render(scene=None, camera=None, size=(1920, 1080), shading="lambert", cull="none", filter="bilinear",
           raster="auto", aa="none", background=None, normals=False, barycentrics=False, output="auto"):
    """Renders one frame; returns a dict of arrays, top row first:
    color [H,W,4] uint8 (sRGB), depth [H,W] float32 (window depth, 1 = empty),
    ids [H,W] int64 (triangle index in draw order, -1 = empty), normals
    [H,W,3] float32 (when normals=True), barycentrics [H,W,3] float32 (when
    barycentrics=True: the perspective-correct weights of the pixel's
    triangle's three corners at its centre, zero where empty); and triangles, method.

    scene: a glTF path, 'builtin:<name>', None (the default scene), a
    rast.Scene or a dict {positions, indices[, normals, uvs, colors,
    triangle_material, materials]}. camera: a rast.Camera; None frames the
    scene as `rast render` does without camera flags. output: "auto" (numpy
    arrays in CPU builds, rast.DeviceArray on the GPU in GPU builds), "numpy",
    "torch" (tensors on the build's device, no copy) or "dlpack"."""
    _check_output(output)
    sc = _scene(scene)
    if camera is None:
        camera = Camera.framing(sc)
    elif not isinstance(camera, Camera):
        raise TypeError(f"camera: expected a rast.Camera or None, got {type(camera).__name__}")
    try:
        w, h = (int(v) for v in size)
    except (TypeError, ValueError):
        raise ValueError(f"size: expected (width, height), got {size!r}") from None
    bg = None if background is None else tuple(float(c) for c in background)
    if bg is not None and len(bg) != 3:
        raise ValueError("background: expected (r, g, b)")
    r = _rast._render(sc, camera, w, h, shading, cull, filter, raster, aa, bg, bool(normals), bool(barycentrics))
    for k in ("color", "depth", "ids", "normals", "barycentrics"):
        if k in r:
            r[k] = _output(r[k], output)
    return r


def _producer(x, name, dtype, shapes):
    """x checked (dtype, shape, contiguity, device) where it can be read here, as something with __dlpack__."""
    if _is_torch(x):
        if x.requires_grad:
            x = x.detach()
        # The common case first, in few Python steps (a call's fixed cost):
        # the module checks the same again from the DLPack tensor.
        if (x.is_contiguous() and str(x.dtype) == _TORCH_NAME[dtype] and (on_device or not x.is_cuda)
                and any(len(x.shape) == len(s) and x.shape[-1] == s[-1] for s in shapes)):
            return x
        want = str(np.dtype(dtype))
        got = str(x.dtype).replace("torch.", "")
        if got != want:
            raise TypeError(f"{name}: expected dtype {want}, got {got}")
        _check_shape(tuple(x.shape), name, shapes)
        if not x.is_contiguous():
            raise ValueError(f"{name}: the tensor is not contiguous (strides {tuple(x.stride())}); "
                             f"pass {name}.contiguous()")
        if x.device.type == "cuda" and not on_device:
            raise ValueError(f"{name}: the tensor is on device {x.device}; this rast build ({backend}) "
                             f"takes host memory: move it with .cpu()")
        return x
    if hasattr(x, "__dlpack__") and not isinstance(x, np.ndarray) and hasattr(x, "__dlpack_device__"):
        dev = x.__dlpack_device__()
        if int(dev[0]) != _DLPACK_CPU and not on_device:
            raise ValueError(f"{name}: the tensor is on device {dev}; this rast build ({backend}) "
                             f"takes host memory: move it with .cpu()")
        if int(dev[0]) != _DLPACK_CPU:
            return x  # checked by the module (python/dlpack_arrays.h)
        _strict(x, name, dtype, shapes)
        return x  # the producer itself: numpy's view of it is read-only, which numpy will not export again
    a = _strict(x, name, dtype, shapes)
    # numpy exports no read-only array through DLPack (it has no flag for it): those alone are copied.
    return a if a.flags.writeable else a.copy()


_TORCH_NAME = {np.float32: "torch.float32", np.int32: "torch.int32"}


def _check_shape(shape, name, shapes):
    if not any(len(shape) == len(s) and all(isinstance(w, str) or w == d for w, d in zip(s, shape)) for s in shapes):
        want = " or ".join("[" + ",".join(str(w) for w in s) + "]" for s in shapes)
        raise ValueError(f"{name}: expected shape {want}, got {list(shape)}")


def rasterize(pos, tri, resolution, context=None, output="auto"):
    """nvdiffrast's dr.rasterize(glctx, pos, tri, resolution) on rast.

    pos: [B,V,4] or [V,4] float32 clip-space positions; tri: [T,3] int32;
    resolution: (height, width). Returns (out, ids): out [B,H,W,4] float32 =
    (u, v, z/w, triangle id + 1), zero where empty, rows bottom first like
    nvdiffrast's; ids [B,H,W] int32, the exact triangle index, -1 where empty.
    context: a rast.RasterizeContext whose buffers are reused across calls
    (None: the module's own). output: "auto" (torch tensors for torch inputs,
    numpy arrays for numpy inputs, else rast.DeviceArray), "numpy", "torch"
    or "dlpack". Inputs already in the build's memory are read in place;
    outputs are shared, not copied (numpy in GPU builds excepted)."""
    _check_output(output)
    torch_in = _is_torch(pos)
    numpy_in = isinstance(pos, (np.ndarray, list, tuple))
    p = _producer(pos, "pos", np.float32, [("B", "V", 4), ("V", 4)])
    t = _producer(tri, "tri", np.int32, [("T", 3)])
    try:
        h, w = (int(v) for v in resolution)
    except (TypeError, ValueError):
        raise ValueError(f"resolution: expected (height, width), got {resolution!r}") from None
    # Tensors on the GPU are ordered before rast's reads by the DLPack
    # protocol (the module passes its stream to __dlpack__), not by a wait
    # here; or, when torch queues on CUDA's legacy default stream, by that
    # stream itself (_legacy_ordered), and then their capsules go in as they are.
    if torch_in and on_device and _legacy_ordered(p):
        p, t = _capsule(p), _capsule(t)
    out, ids = _rast._rasterize(_context(context), p, t, h, w)
    if output == "auto":
        output = "torch" if torch_in else "numpy" if numpy_in or not on_device else "dlpack"
    return _output(out, output), _output(ids, output)

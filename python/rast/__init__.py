"""rast from Python (docs/python.md): render a scene into numpy arrays, and
rasterize clip-space triangles as nvdiffrast's dr.rasterize does.

Inputs may be numpy arrays, torch tensors or anything with __dlpack__; they
are taken without a copy when they already have the dtype, layout and device
this build needs, and refused with a clear exception otherwise.
"""
import numpy as np

from ._rast import Camera, Scene, __version__, backend, on_device  # noqa: F401
from . import _rast

__all__ = ["Camera", "Scene", "render", "rasterize", "backend", "on_device", "__version__"]

_DLPACK_CPU = 1


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
           raster="auto", aa="none", background=None, normals=False, barycentrics=False):
    """Renders one frame; returns a dict of numpy arrays, top row first:
    color [H,W,4] uint8 (sRGB), depth [H,W] float32 (window depth, 1 = empty),
    ids [H,W] int64 (triangle index in draw order, -1 = empty), normals
    [H,W,3] float32 (when normals=True), barycentrics [H,W,3] float32 (when
    barycentrics=True: the perspective-correct weights of the pixel's
    triangle's three corners at its centre, zero where empty); and triangles, method.

    scene: a glTF path, 'builtin:<name>', None (the default scene), a
    rast.Scene or a dict {positions, indices[, normals, uvs, colors,
    triangle_material, materials]}. camera: a rast.Camera; None frames the
    scene as `rast render` does without camera flags."""
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
    return _rast._render(sc, camera, w, h, shading, cull, filter, raster, aa, bg, bool(normals), bool(barycentrics))


def rasterize(pos, tri, resolution):
    """nvdiffrast's dr.rasterize(glctx, pos, tri, resolution) on rast.

    pos: [B,V,4] or [V,4] float32 clip-space positions; tri: [T,3] int32;
    resolution: (height, width). Returns (out, ids): out [B,H,W,4] float32 =
    (u, v, z/w, triangle id + 1), zero where empty, rows bottom first like
    nvdiffrast's; ids [B,H,W] int32, the exact triangle index, -1 where empty.
    torch tensors in give torch tensors out (sharing the numpy buffers)."""
    torch_out = _is_torch(pos)
    p = _strict(pos, "pos", np.float32, [("B", "V", 4), ("V", 4)])
    t = _strict(tri, "tri", np.int32, [("T", 3)])
    try:
        h, w = (int(v) for v in resolution)
    except (TypeError, ValueError):
        raise ValueError(f"resolution: expected (height, width), got {resolution!r}") from None
    batch = p if p.ndim == 3 else p[None]
    outs, ids = [], []
    for b in range(batch.shape[0]):
        o, i = _rast._rasterize(batch[b], t, h, w)
        outs.append(o)
        ids.append(i)
    out, idv = np.stack(outs), np.stack(ids)
    if torch_out:
        import torch
        return torch.from_numpy(out), torch.from_numpy(idv)
    return out, idv

#!/usr/bin/env python3
"""The Python module (python/, docs/python.md) as a user meets it, run by
ctest with Debian's python3 and numpy (and torch when installed):

 - rast.render gives the same colour, depth and ids as `rast render` with the
   same settings (the CLI's PNG, PFM and glref-ids files);
 - rast.rasterize (nvdiffrast's dr.rasterize) gives the ids that the renderer
   draws for the same triangles, independent coverage checks at pixel centres
   well inside triangles, barycentrics in range that reproduce each pixel's
   centre and z/w, and z/w consistent with the renderer's depth;
 - DLPack producers are read without a copy; bad input (shapes, dtypes, NaN,
   w <= 0, indices out of range, non-contiguous arrays, another device,
   unknown names, missing files) raises TypeError/ValueError with a clear
   message, the CLI's for the same mistake."""
import argparse
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import rastimg  # noqa: E402
from skip import skip  # noqa: E402
from cli_checks import Tally  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--rast", required=True)
ap.add_argument("--workdir", required=True)
args = ap.parse_args()
os.makedirs(args.workdir, exist_ok=True)
try:
    import numpy as np
except ImportError:
    skip(args.workdir, "numpy is not installed for this python (Debian: python3-numpy)")
import rast  # noqa: E402

check = Tally()  # check(ok, what); check.failed counts the failures


def render(*a, **k):
    """rast.render with numpy outputs (a GPU build's default is rast.DeviceArray: copied to the host here)."""
    k.setdefault("output", "numpy")
    return rast.render(*a, **k)


def raises(exc, words, fn, *a, **k):
    try:
        fn(*a, **k)
    except exc as e:
        msg = str(e)
        ok = all(w in msg for w in words)
        check(ok, f"{exc.__name__}: {msg}" + ("" if ok else f" (expected the words {words})"))
        return msg
    except Exception as e:  # noqa: BLE001
        check(False, f"expected {exc.__name__} with {words}, got {type(e).__name__}: {e}")
        return ""
    check(False, f"expected {exc.__name__} with {words}, nothing raised")
    return ""


def wd(n):
    return os.path.join(args.workdir, n)


def cli(*a):
    env = dict(os.environ, OMP_PROC_BIND="false")
    return subprocess.run([args.rast] + list(a), capture_output=True, text=True, env=env, timeout=600)


print(f"rast {rast.__version__}, {rast.backend} backend, on device: {rast.on_device}")

# ---- render against the command line
W, H = 96, 64
out = render(None, size=(W, H))
check(out["color"].shape == (H, W, 4) and out["color"].dtype == np.uint8, f"color {out['color'].shape} uint8")
check(out["depth"].shape == (H, W) and out["depth"].dtype == np.float32, "depth [H,W] float32")
check(out["ids"].shape == (H, W) and out["ids"].dtype == np.int64, "ids [H,W] int64")
r = cli("render", "--size", f"{W}x{H}", "--aa", "none", "-o", wd("cli.png"),
        "--aov", f"depth={wd('cli_depth.pfm')},primid={wd('cli_ids.bin')}")
check(r.returncode == 0, "rast render ran: " + r.stderr.strip())
if r.returncode == 0:
    _, _, _, png = rastimg.read_png(wd("cli.png"))
    check(np.array_equal(np.frombuffer(png, np.uint8).reshape(H, W, 4), out["color"]),
          "rast.render colour == rast render's PNG (default scene, framed as the CLI frames it)")
    _, _, ids = rastimg.read_ids(wd("cli_ids.bin"))
    check(np.array_equal(np.array(ids, np.int64).reshape(H, W) - 1, out["ids"]), "ids == the CLI's --aov primid")
    _, _, _, d = rastimg.read_pfm(wd("cli_depth.pfm"))
    check(np.array_equal(np.array(d, np.float32).reshape(H, W)[::-1], out["depth"]), "depth == the CLI's --aov depth")
check((out["ids"] >= 0).any() and (out["ids"] == -1).any(), "the default scene covers some pixels, not all")
n = render("builtin:bigtri", size=(32, 24), normals=True)
check(n["normals"].shape == (24, 32, 3) and np.isfinite(n["normals"]).all(), "normals [H,W,3]")

# frame barycentrics: the weights of the pixel's triangle's corners, which rebuild
# the pixel centre through the camera's view-projection (given here as a matrix)
P = np.array([[1.2, 0, 0, 0], [0, 1.8, 0, 0], [0, 0, -1.02, -0.202], [0, 0, -1, 0]])  # a perspective projection
world = np.array([[-1, -1, -3], [1.5, -1, -4], [0, 1.5, -2], [-2, 0.5, -6], [1, 1, -5], [0.5, -1.5, -2.5]], np.float32)
pcam = rast.Camera()
pcam.view_projection = list(P.T.reshape(-1))  # column-major
fb = render({"positions": world, "indices": [[0, 1, 2], [3, 4, 5]]}, camera=pcam, size=(80, 60), barycentrics=True)
bary, fid = fb["barycentrics"], fb["ids"]
hit = fid >= 0
check(hit.sum() > 100 and np.all(bary[~hit] == 0), f"barycentrics [H,W,3], zero where empty ({hit.sum()} pixels hit)")
check(np.abs(bary[hit].sum(-1) - 1).max() < 1e-5 and bary[hit].min() > -1e-4, "they sum to 1 and are in range")
clipc = np.concatenate([world.astype(np.float64), np.ones((6, 1))], 1) @ P.T  # [6,4]
tri_idx = np.array([[0, 1, 2], [3, 4, 5]])
cc = (bary[hit][..., None].astype(np.float64) * clipc[tri_idx[fid[hit]]]).sum(1)
yy, xx = np.nonzero(hit)
ex = np.abs(cc[:, 0] / cc[:, 3] - ((2 * xx + 1) / 80 - 1)).max()
ey = np.abs(cc[:, 1] / cc[:, 3] - (1 - (2 * yy + 1) / 60)).max()  # render's rows are top first
check(max(ex, ey) < 1e-4, f"frame barycentrics rebuild the pixel centres (max error {max(ex, ey):.2e})")
check(fb["depth"].shape == (60, 80), "depth still there with barycentrics")

# ---- rasterize: clip-space triangles, nvdiffrast's layout
rng = np.random.default_rng(7)
T = 60
centres = rng.uniform(-0.8, 0.8, (T, 2))
tri_xy = centres[:, None, :] + rng.uniform(-0.25, 0.25, (T, 3, 2))
w = rng.uniform(1.0, 3.0, (T, 3))
z = rng.uniform(-0.9, 0.9, (T, 3))
pos = np.concatenate([tri_xy * w[..., None], (z * w)[..., None], w[..., None]], axis=2).reshape(-1, 4)
pos = np.ascontiguousarray(pos, dtype=np.float32)
tri = np.arange(3 * T, dtype=np.int32).reshape(T, 3)
RH, RW = 72, 120
o, ids = rast.rasterize(pos, tri, (RH, RW))
check(o.shape == (1, RH, RW, 4) and o.dtype == np.float32, f"out {o.shape} float32")
check(ids.shape == (1, RH, RW) and ids.dtype == np.int32, "ids [1,H,W] int32")
o, ids = o[0], ids[0]
cov = ids >= 0
check(np.array_equal(o[..., 3], np.where(cov, ids + 1, 0).astype(np.float32)), "out[...,3] == triangle id + 1, 0 empty")
check(np.all(o[~cov] == 0), "empty pixels are all zero")

# the renderer draws the same triangles (x/w, y/w, z/w, identity camera): the same ids, rows flipped
cam = rast.Camera()
cam.view_projection = [1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0, 0, 0, 0, 0, 1.0]
ndc = pos[:, :3] / pos[:, 3:]
ref = render({"positions": ndc, "indices": tri.astype(np.uint32)}, camera=cam, size=(RW, RH))
check(np.array_equal(ref["ids"][::-1], ids), "rasterize ids == the renderer's ids for the same triangles")
zw_from_depth = 2.0 * ref["depth"][::-1].astype(np.float64) - 1.0
check(np.abs(zw_from_depth[cov] - o[..., 2][cov]).max() < 2e-4, "z/w == 2 * the renderer's window depth - 1")

# barycentrics: in range, and they rebuild the pixel centre and z/w from the clip-space corners
u, v = o[..., 0].astype(np.float64), o[..., 1].astype(np.float64)
bw = np.stack([u, v, 1 - u - v], -1)[cov]
check(bw.min() > -1e-4 and bw.max() < 1 + 1e-4, f"barycentrics in [0, 1] (min {bw.min():.2e}, max {bw.max():.6f})")
corners = pos[tri[ids[cov]]].astype(np.float64)  # [N,3,4]
clip = (bw[..., None] * corners).sum(1)
yy, xx = np.nonzero(cov)
cx, cy = (2 * xx + 1) / RW - 1, (2 * yy + 1) / RH - 1
err = max(np.abs(clip[:, 0] / clip[:, 3] - cx).max(), np.abs(clip[:, 1] / clip[:, 3] - cy).max())
check(err < 1e-4, f"perspective-correct barycentrics rebuild the pixel centres (max error {err:.2e})")
check(np.abs(clip[:, 2] / clip[:, 3] - o[..., 2][cov]).max() < 1e-4, "and z/w")

# independent coverage: pixel centres well inside exactly one triangle, and nearest z/w among overlaps
ndc2 = ndc[:, :2].astype(np.float64).reshape(T, 3, 2)
agree = tested = 0
for y in range(0, RH, 3):
    for x in range(0, RW, 3):
        p = np.array([(2 * x + 1) / RW - 1, (2 * y + 1) / RH - 1])
        inside, margin = [], []
        for t in range(T):
            a, b, c = ndc2[t]
            d = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
            if abs(d) < 1e-9:
                continue
            l1 = ((p[0] - a[0]) * (c[1] - a[1]) - (p[1] - a[1]) * (c[0] - a[0])) / d
            l2 = ((b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])) / d
            ls = (1 - l1 - l2, l1, l2)
            if min(ls) > 0.02:
                inside.append((float(np.dot(ls, ndc[tri[t], 2])), t))
            margin.append(min(ls))
        if not inside or any(-0.02 < m <= 0.02 for m in margin):
            continue  # on or near an edge: the fill rule decides, not checked here
        zs = sorted(inside)
        if len(zs) > 1 and zs[1][0] - zs[0][0] < 1e-4:
            continue  # a depth tie
        tested += 1
        agree += ids[y, x] == zs[0][1]
check(tested > 50 and agree == tested, f"independent coverage + nearest z/w: {agree}/{tested} pixel centres agree")

# a batch: [B,V,4] renders each image; the second is the first mirrored in x
mirror = pos * np.array([-1, 1, 1, 1], np.float32)
ob, ib = rast.rasterize(np.stack([pos, mirror]), tri, (RH, RW))
check(ob.shape == (2, RH, RW, 4) and np.array_equal(ib[0], ids), "a batch's first image == the single call")
check((ib[1] >= 0).sum() > 0 and set(np.unique(ib[1])) <= set(range(-1, T)), "the batch's second image has ids")

# DLPack in, no copy: an object that only offers __dlpack__ / __dlpack_device__


class OnlyDlpack:
    def __init__(self, a, device=(1, 0)):
        self.a, self.device = a, device

    def __dlpack__(self, stream=None):
        return self.a.__dlpack__()

    def __dlpack_device__(self):
        return self.device


o2, i2 = rast.rasterize(OnlyDlpack(pos), OnlyDlpack(tri), (RH, RW), output="numpy")
check(np.array_equal(i2[0], ids) and np.array_equal(o2[0], o), "DLPack inputs give the same result")
dl = OnlyDlpack(pos)
check(rast._producer(dl, "pos", np.float32, [("V", 4)]) is dl and rast._producer(pos, "pos", np.float32, [("V", 4)]) is pos,
      "DLPack producers and numpy arrays go to the module as they are (read there in place, no copy)")

# ---- outputs through DLPack: rast.DeviceArray, shared with numpy and torch without a copy
od, idd = rast.rasterize(pos, tri, (RH, RW), output="dlpack")
check(isinstance(idd, rast.DeviceArray) and idd.shape == (1, RH, RW) and idd.dtype == "int32"
      and od.shape == (1, RH, RW, 4) and od.dtype == "float32", f"output='dlpack' gives DeviceArrays: {idd!r}")
if not rast.on_device:
    check(idd.__dlpack_device__() == (1, 0), "a CPU build's arrays are on DLPack's CPU device")
    check(np.array_equal(np.from_dlpack(idd)[0], ids) and np.array_equal(np.from_dlpack(od)[0], o),
          "numpy.from_dlpack reads them: the same ids and (u, v, z/w, id + 1)")
    check(np.shares_memory(idd.numpy(), idd.numpy()) and idd.numpy().flags.writeable,
          "DeviceArray.numpy() is a writable view of the same buffer, not a copy")
check(np.array_equal(idd.numpy()[0], ids), "DeviceArray.numpy() holds the ids")
nd = rast.render(None, size=(W, H), output="dlpack")
check(isinstance(nd["ids"], rast.DeviceArray) and np.array_equal(nd["ids"].numpy(), out["ids"])
      and np.array_equal(nd["color"].numpy(), out["color"]), "render(output='dlpack') gives the same frame")
raises(ValueError, ["output", "dlpack"], rast.rasterize, pos, tri, (RH, RW), output="cupy")
raises(TypeError, ["context"], rast.rasterize, pos, tri, (RH, RW), context="ctx")

# ---- a context reused across calls (nvdiffrast's RasterizeCudaContext): its
# scene is rewritten in place when the counts stay, rebuilt when they change;
# every call draws what a fresh context draws.
ctx = rast.RasterizeContext()
moved = pos.copy()
moved[:, 0] = -moved[:, 0] + 0.1 * moved[:, 3]  # mirrored and shifted: other pixels, same counts
r1 = rast.rasterize(pos, tri, (RH, RW), context=ctx)
r2 = rast.rasterize(moved, tri, (RH, RW), context=ctx)
r3 = rast.rasterize(moved, tri[::-1].copy(), (RH, RW), context=ctx)
f2 = rast.rasterize(moved, tri, (RH, RW), context=rast.RasterizeContext())
f3 = rast.rasterize(moved, tri[::-1].copy(), (RH, RW), context=rast.RasterizeContext())
check(np.array_equal(r1[1][0], ids) and np.array_equal(r1[0][0], o), "a context's first call == the module's")
check(not np.array_equal(r2[1], r1[1]) and np.array_equal(r2[1], f2[1]) and np.array_equal(r2[0], f2[0]),
      "new positions, same counts: the reused context == a fresh one")
check(np.array_equal(r3[1], f3[1]) and np.array_equal(r3[0], f3[0]), "new triangles, same counts: == a fresh one")
# Output buffers: a context reuses one only once nothing outside holds it.
keep = rast.rasterize(pos, tri, (RH, RW), context=ctx, output="dlpack")
addr = keep[1].data_ptr
check(rast.on_device or keep[1].numpy().ctypes.data == addr, "DeviceArray.data_ptr is its buffer's address")
again = rast.rasterize(moved, tri, (RH, RW), context=ctx, output="dlpack")
check(again[1].data_ptr != addr and np.array_equal(keep[1].numpy()[0], ids),
      "an output still held is never handed out again (the first call's ids intact)")
del keep, again
reuse = rast.rasterize(pos, tri, (RH, RW), context=ctx, output="dlpack")
check(reuse[1].data_ptr == addr and np.array_equal(reuse[1].numpy()[0], ids),
      "a released output buffer is reused by the next call")
if not rast.on_device:
    held = np.from_dlpack(reuse[1])
    del reuse
    again = rast.rasterize(moved, tri, (RH, RW), context=ctx, output="dlpack")
    check(again[1].data_ptr != addr, "a numpy view of an output keeps it from reuse")
    del held, again
else:
    del reuse
r4 = rast.rasterize(pos[: 3 * (T // 2)], tri[: T // 2], (RH // 2, RW), context=ctx)
f4 = rast.rasterize(pos[: 3 * (T // 2)], tri[: T // 2], (RH // 2, RW), context=rast.RasterizeContext())
check(r4[1].shape == (1, RH // 2, RW) and np.array_equal(r4[1], f4[1]), "other counts and size: rebuilt, == a fresh one")

# Triangles crossing the far plane (z/w from 0 to 3 over each) are clipped
# into two each: more than a new renderer's buffers hold, so the first call
# draws again with grown buffers, and its barycentric pass with it.
NC = 2000
cc = np.random.default_rng(7).uniform(-0.8, 0.8, size=(NC, 2)).astype(np.float32)
cpos = np.zeros((3 * NC, 4), np.float32)
cpos[0::3, :2], cpos[1::3, :2], cpos[2::3, :2] = cc, cc + [0.1, 0.0], cc + [0.0, 0.1]
cpos[1::3, 2] = 3.0
cpos[:, 3] = 1.0
ctri = np.arange(3 * NC, dtype=np.int32).reshape(NC, 3)
cctx = rast.RasterizeContext()
first = rast.rasterize(cpos, ctri, (RH, RW), context=cctx)
second = rast.rasterize(cpos, ctri, (RH, RW), context=cctx)
cov = first[1][0] >= 0
check(np.array_equal(first[1], second[1]) and np.array_equal(first[0], second[0]),
      "a call whose clipped triangles outgrow the buffers == the next call (drawn again, with its barycentrics)")
check(cov.sum() > 100 and float(first[0][0][..., 2][cov].max()) <= 1.0 + 1e-6,
      "clipped at the far plane: every covered pixel has z/w <= 1")
# the ids are the input triangles, not the clipped pieces: each covered pixel's
# barycentrics rebuild its centre from its triangle's corners
cids, cout = first[1][0], first[0][0]
cb = np.stack([cout[..., 0], cout[..., 1], 1 - cout[..., 0] - cout[..., 1]], -1)[cov].astype(np.float64)
cclip = (cb[..., None] * cpos[ctri[cids[cov]]].astype(np.float64)).sum(1)
cy, cx = np.nonzero(cov)
cerr = max(np.abs(cclip[:, 0] / cclip[:, 3] - ((2 * cx + 1) / RW - 1)).max(),
           np.abs(cclip[:, 1] / cclip[:, 3] - ((2 * cy + 1) / RH - 1)).max())
check(cerr < 1e-4, f"clipped triangles keep their input ids (centres rebuilt, max error {cerr:.2e})")

# ---- bad input: clear exceptions, never a crash
raises(ValueError, ["pos", "shape"], rast.rasterize, pos[:, :3].copy(), tri, (RH, RW))
raises(TypeError, ["pos", "float32", "float64"], rast.rasterize, pos.astype(np.float64), tri, (RH, RW))
raises(TypeError, ["tri", "int32", "int64"], rast.rasterize, pos, tri.astype(np.int64), (RH, RW))
raises(ValueError, ["tri", "shape"], rast.rasterize, pos, tri.reshape(-1), (RH, RW))
nanpos = pos.copy()
nanpos[5, 1] = np.nan
raises(ValueError, ["vertex 5", "finite"], rast.rasterize, nanpos, tri, (RH, RW))
behind = pos.copy()
behind[7, 3] = -1.0
raises(ValueError, ["vertex 7", "w > 0"], rast.rasterize, behind, tri, (RH, RW))
badtri = tri.copy()
badtri[3, 2] = 10**6
raises(ValueError, ["triangle 3", "1000000", "outside"], rast.rasterize, pos, badtri, (RH, RW))
badtri[3, 2] = -2
raises(ValueError, ["triangle 3", "-2"], rast.rasterize, pos, badtri, (RH, RW))
# A context's inputs are checked by the kernel that reads them (the first bad
# one reported, vertices before indices); the context stays usable after.
raises(ValueError, ["vertex 5"], rast.rasterize, nanpos, badtri, (RH, RW), context=ctx)
badtri[1, 0] = 10**6
raises(ValueError, ["triangle 1", "1000000"], rast.rasterize, pos, badtri, (RH, RW), context=ctx)
after = rast.rasterize(pos, tri, (RH, RW), context=ctx)
check(np.array_equal(after[1][0], ids) and np.array_equal(after[0][0], o),
      "a context that raised draws the next good call as before")
raises(ValueError, ["contiguous"], rast.rasterize, np.asfortranarray(pos), tri, (RH, RW))
raises(ValueError, ["contiguous"], rast.rasterize, pos[::2], tri[: T // 2], (RH, RW))
if not rast.on_device:  # a CPU build takes host memory only
    raises(ValueError, ["device", ".cpu()"], rast.rasterize, OnlyDlpack(pos, device=(2, 0)), tri, (RH, RW))
raises(ValueError, ["resolution"], rast.rasterize, pos, tri, (0, 10))
raises(ValueError, ["resolution"], rast.rasterize, pos, tri, "big")
raises(TypeError, ["pos", "dict"], rast.rasterize, {"a": 1}, tri, (RH, RW))
msg = raises(ValueError, ["glossy"], rast.render, None, size=(8, 8), shading="glossy")
r = cli("render", "--size", "8x8", "--shading", "glossy", "-o", wd("x.png"))
check(r.stderr.strip() == f"rast: error: {msg}", f"the same message as the CLI: {r.stderr.strip()}")
msg = raises(ValueError, ["no_such_file.glb"], rast.render, wd("no_such_file.glb"), size=(8, 8))
r = cli("render", wd("no_such_file.glb"), "--size", "8x8", "-o", wd("x.png"))
check(r.stderr.strip() == f"rast: error: {msg}", f"the same message as the CLI: {r.stderr.strip()}")
raises(ValueError, ["size"], rast.render, None, size=(0, 8))
raises(ValueError, ["positions", "shape"], rast.render, {"positions": np.zeros((3, 2)), "indices": [[0, 1, 2]]})
raises(ValueError, ["index 5", "out of range"], rast.render,
       {"positions": np.zeros((3, 3)), "indices": [[0, 1, 5]]}, size=(8, 8))
raises(ValueError, ["not finite"], rast.render,
       {"positions": [[0, 0, 0], [1, 0, 0], [0, np.inf, 0]], "indices": [[0, 1, 2]]}, size=(8, 8))
raises(TypeError, ["camera"], rast.render, None, camera="front", size=(8, 8))

# ---- torch (CPU), when installed: tensors in, tensors out, no copy in
try:
    import torch
except ImportError:
    torch = None
if torch is None:
    print("torch is not installed: its checks are skipped (Debian: python3-torch)")
else:
    tp, tt = torch.from_numpy(pos), torch.from_numpy(tri)
    ot, it = rast.rasterize(tp, tt, (RH, RW))
    it = it.cpu()  # a GPU build answers with tensors on its GPU
    check(isinstance(ot, torch.Tensor) and torch.equal(it[0], torch.from_numpy(ids)), "torch tensors in and out")
    raises(ValueError, ["contiguous"], rast.rasterize, tp.t().contiguous().t(), tt, (RH, RW))
    raises(TypeError, ["pos", "float32", "float64"], rast.rasterize, tp.double(), tt, (RH, RW))
    ta = torch.from_dlpack(idd)
    check(torch.equal(ta[0].cpu(), torch.from_numpy(ids)) and ta.data_ptr() == idd.data_ptr
          and torch.from_dlpack(idd).data_ptr() == idd.data_ptr,
          "torch.from_dlpack shares a DeviceArray's buffer (no copy)")
    tr = rast.render(None, size=(W, H), output="torch")
    check(isinstance(tr["depth"], torch.Tensor) and torch.equal(tr["ids"].cpu(), torch.from_numpy(out["ids"])),
          "render(output='torch') gives tensors")
    check(rast._producer(tp, "pos", np.float32, [("V", 4)]) is tp, "a torch tensor goes to the module as it is")
    tg = tp.clone().requires_grad_(True)
    check(torch.equal(rast.rasterize(tg, tt, (RH, RW))[1].cpu(), it), "a tensor that requires grad is read (detached)")
    if torch.cuda.is_available() and not rast.on_device:
        raises(ValueError, ["device"], rast.rasterize, tp.cuda(), tt, (RH, RW))
    if torch.cuda.is_available() and rast.on_device:
        # A CUDA build with CUDA tensors: read in place, answered on the same GPU.
        tpc, ttc = tp.cuda(), tt.cuda()
        oc, ic = rast.rasterize(tpc, ttc, (RH, RW))
        check(ic.is_cuda and oc.is_cuda and torch.equal(ic.cpu(), it) and torch.equal(oc.cpu(), ot.cpu()),
              "CUDA tensors in, CUDA tensors out, the same ids and (u, v, z/w, id + 1)")
        check(rast._producer(tpc, "pos", np.float32, [("V", 4)]) is tpc, "a CUDA tensor goes to the module as it is")
        od2, id2 = rast.rasterize(tpc, ttc, (RH, RW), output="dlpack")
        check(id2.__dlpack_device__() == (2, rast.device_index) and torch.from_dlpack(id2).data_ptr() == id2.data_ptr,
              "outputs on the GPU (DLPack device 2), shared with torch without a copy")
        raises(ValueError, ["contiguous"], rast.rasterize, tpc.t().contiguous().t(), ttc, (RH, RW))
sys.exit(1 if check.failed else 0)

#!/usr/bin/env python3
"""nvdiffrast's CUDA rasterizer (RasterizeCudaContext: the maintained port of
Laine & Karras' cudaraster) on the same triangles and camera as rast, timed
raster-only: `dr.rasterize` alone, no interpolation or shading, median of
CUDA-event times (docs/performance.md).

Used by scripts/device/perf_vs_gl.py --nvdiffrast; also on its own:

  python3 scripts/device/nvdiffrast_bench.py SCENE.glb --size 1920x1080 --eye x,y,z --target x,y,z
      --up x,y,z --fovy DEG --near N --far F [--frames 200] [--warmup 20]

SCENE.glb must be written by `rast export` (one node per draw, its matrix, one
triangle primitive per mesh, float positions, 32-bit indices), so that the
triangles are exactly rast's draws. Needs torch and nvdiffrast (never part of
the project: built on the GPU machine from a fetched copy,
`pip install --no-build-isolation`).
"""
import argparse
import json
import math
import struct
import sys

import numpy as np


def load_glb(path):
    """World-space positions (float64, N x 3) and triangles (int32, T x 3) of every triangle draw."""
    data = open(path, "rb").read()
    magic, _, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF":
        raise SystemExit(f"{path}: not a binary glTF")
    off, js, bin_ = 12, None, None
    while off < length:
        clen, ctype = struct.unpack_from("<II", data, off)
        chunk = data[off + 8: off + 8 + clen]
        if ctype == 0x4E4F534A:
            js = json.loads(chunk)
        elif ctype == 0x004E4942:
            bin_ = chunk
        off += 8 + clen

    def acc(i, dtype, comps):
        a = js["accessors"][i]
        v = js["bufferViews"][a["bufferView"]]
        start = v.get("byteOffset", 0) + a.get("byteOffset", 0)
        n = a["count"] * comps
        return np.frombuffer(bin_, dtype=dtype, count=n, offset=start).reshape(a["count"], comps)

    positions, tris, base = [], [], 0
    for node in js.get("nodes", []):
        if "mesh" not in node:
            continue
        m = np.array(node.get("matrix", [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]), dtype=np.float64)
        M = m.reshape(4, 4).T  # glTF matrices are column-major
        for prim in js["meshes"][node["mesh"]]["primitives"]:
            if prim.get("mode", 4) != 4:
                continue
            p = acc(prim["attributes"]["POSITION"], np.float32, 3).astype(np.float64)
            if "indices" in prim:
                ct = js["accessors"][prim["indices"]]["componentType"]
                dt = {5125: np.uint32, 5123: np.uint16, 5121: np.uint8}[ct]
                idx = acc(prim["indices"], dt, 1).reshape(-1).astype(np.int64)
            else:
                idx = np.arange(len(p), dtype=np.int64)
            w = np.c_[p, np.ones(len(p))] @ M.T
            positions.append(w[:, :3])
            tris.append(idx.reshape(-1, 3) + base)
            base += len(p)
    return np.concatenate(positions), np.concatenate(tris).astype(np.int32)


def view_proj(eye, target, up, fovy, near, far, aspect):
    """OpenGL's lookAt and perspective, in double (rast rounds its MVP from double too)."""
    eye, target, up = (np.array(v, dtype=np.float64) for v in (eye, target, up))
    f = target - eye
    f /= np.linalg.norm(f)
    s = np.cross(f, up)
    s /= np.linalg.norm(s)
    u = np.cross(s, f)
    V = np.eye(4)
    V[0, :3], V[1, :3], V[2, :3] = s, u, -f
    V[:3, 3] = -V[:3, :3] @ eye
    t = 1.0 / math.tan(math.radians(fovy) / 2)
    P = np.zeros((4, 4))
    P[0, 0], P[1, 1] = t / aspect, t
    P[2, 2], P[2, 3] = (far + near) / (near - far), 2 * far * near / (near - far)
    P[3, 2] = -1.0
    return P @ V


def camera_from_flags(flags):
    d = {flags[i][2:]: flags[i + 1] for i in range(0, len(flags) - 1, 2) if flags[i].startswith("--")}
    vec = lambda k: [float(x) for x in d[k].split(",")]  # noqa: E731
    return vec("eye"), vec("target"), vec("up"), float(d["fovy"]), float(d["near"]), float(d["far"])


class Bench:
    def __init__(self):
        import torch
        import nvdiffrast.torch as dr
        self.torch, self.dr = torch, dr
        self.ctx = dr.RasterizeCudaContext()

    def time(self, glb, cam_flags, width, height, frames=200, warmup=20):
        torch, dr = self.torch, self.dr
        pos, tri = load_glb(glb)
        eye, target, up, fovy, near, far = camera_from_flags(cam_flags)
        mvp = view_proj(eye, target, up, fovy, near, far, width / height)
        clip = (np.c_[pos, np.ones(len(pos))] @ mvp.T).astype(np.float32)
        p = torch.from_numpy(clip).cuda().unsqueeze(0).contiguous()
        t = torch.from_numpy(tri).cuda().contiguous()
        res = [height, width]
        with torch.no_grad():
            for _ in range(warmup):
                out, _ = dr.rasterize(self.ctx, p, t, resolution=res)
            torch.cuda.synchronize()
            ms = []
            for _ in range(frames):
                a, b = torch.cuda.Event(enable_timing=True), torch.cuda.Event(enable_timing=True)
                a.record()
                out, _ = dr.rasterize(self.ctx, p, t, resolution=res)
                b.record()
                b.synchronize()
                ms.append(a.elapsed_time(b))
            covered = int((out[0, :, :, 3] > 0).sum().item())
        ms.sort()
        n = len(ms)
        med = ms[n // 2] if n % 2 else 0.5 * (ms[n // 2 - 1] + ms[n // 2])
        return {"median_ms": med, "min_ms": ms[0], "triangles": int(len(tri)), "covered_pixels": covered}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("glb")
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--frames", type=int, default=200)
    ap.add_argument("--warmup", type=int, default=20)
    a, cam = ap.parse_known_args()
    w, h = (int(v) for v in a.size.split("x"))
    r = Bench().time(a.glb, cam, w, h, a.frames, a.warmup)
    print(json.dumps(r))


if __name__ == "__main__":
    sys.exit(main())

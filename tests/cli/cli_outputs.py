#!/usr/bin/env python3
"""Outputs that other tools read (issue #42): `--aov NAME=F.npy` writes NumPy
arrays (top row first) holding exactly the values of the PFM / glref-ids AOVs,
and `rast bench --json` reports the device, the backend and triangles per
second (drawn triangles over the median frame time). Standard library only:
the .npy header is parsed here."""
import ast
import json
import os
import struct
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import rastimg  # noqa: E402
from cli_checks import Tally, cli_setup  # noqa: E402

args, env = cli_setup()
check = Tally()  # check(ok, what); check.failed counts the failures


def rast(*a):
    r = subprocess.run([args.rast] + list(a), capture_output=True, text=True, env=env, timeout=600)
    if r.returncode != 0:
        raise SystemExit(f"FAILED: rast {' '.join(a)}: {r.stderr.strip()}")
    return r.stdout


def wd(n):
    return os.path.join(args.workdir, n)


def read_npy(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x93NUMPY\x01\x00":
        raise ValueError(f"{path}: not a .npy 1.0 file")
    n = struct.unpack("<H", data[8:10])[0]
    header = ast.literal_eval(data[10:10 + n].decode("latin1"))
    if (10 + n) % 64:
        raise ValueError(f"{path}: header not padded to 64 bytes")
    count = 1
    for s in header["shape"]:
        count *= s
    code = {"<f4": "f", "<u4": "I"}[header["descr"]]
    return header, struct.unpack(f"<{count}{code}", data[10 + n:10 + n + 4 * count])


W, H = 40, 30
rast("render", "--size", f"{W}x{H}", "-o", wd("c.png"), "--aov",
     f"depth={wd('d.pfm')},primid={wd('i.bin')},normals={wd('n.pfm')}")
rast("render", "--size", f"{W}x{H}", "-o", wd("c2.png"), "--aov",
     f"depth={wd('d.npy')},primid={wd('i.npy')},normals={wd('n.npy')}")
hd, d = read_npy(wd("d.npy"))
check(hd["shape"] == (H, W) and hd["descr"] == "<f4" and not hd["fortran_order"], f"depth.npy header {hd}")
_, _, _, dp = rastimg.read_pfm(wd("d.pfm"))  # bottom row first
flip = [dp[(H - 1 - y) * W + x] for y in range(H) for x in range(W)]
check(list(d) == flip, "depth.npy == depth.pfm, top row first")
hi, ids = read_npy(wd("i.npy"))
_, _, ref = rastimg.read_ids(wd("i.bin"))  # top row first
check(hi["shape"] == (H, W) and hi["descr"] == "<u4" and list(ids) == list(ref), "primid.npy == the glref-ids file")
hn, n = read_npy(wd("n.npy"))
_, _, ch, nrm = rastimg.read_pfm(wd("n.pfm"))
flipn = [nrm[((H - 1 - y) * W + x) * 3 + c] for y in range(H) for x in range(W) for c in range(3)]
check(hn["shape"] == (H, W, 3) and list(n) == flipn, "normals.npy == normals.pfm [H,W,3]")

rast("bench", "builtin:bigtri", "--size", "64x48", "--frames", "3", "--warmup", "1", "--json", wd("b.json"))
with open(wd("b.json")) as f:
    rows = json.load(f)
row = rows[0]
check(bool(row.get("device")) and row.get("backend") in ("OpenMP", "Serial", "Cuda", "HIP"),
      f"bench --json: device '{row.get('device')}', backend {row.get('backend')}")
tps = row.get("triangles_per_second", 0)
expect = row["triangles_in"] / (row["total_median_ms"] * 1e-3)
check(tps > 0 and abs(tps - expect) <= 1e-5 * expect, f"triangles_per_second {tps:.6g} = triangles_in / median frame")
sys.exit(1 if check.failed else 0)

#!/usr/bin/env python3
"""Compare rast's primitive ids (and depth, colour) with the glref OpenGL reference.

For every model, glref renders at its auto camera (--auto-camera) and prints the
camera it used (`glref: camera (auto) --eye ... --far ...`); rast then renders
with exactly those camera flags and writes its primitive-id and depth AOVs. The
script compares, per model:

  * primitive ids: agreement = % of ALL pixels whose ids are equal (0 = background
    on both sides counts as agreeing); also the % over pixels covered by either
    renderer, the coverage mismatches (exactly one renderer covers the pixel:
    "g-only" = only glref, "r-only" = only rast) and the id mismatches on pixels
    both cover;
  * window-space depth on pixels where both give the same id: max / median / mean
    absolute difference;
  * colour (information only, never a failure): mean absolute difference per RGB
    channel (0..255) and % of pixels with a channel off by more than 8/255, over
    pixels covered by either renderer. rast's default texture filter is bilinear
    without mipmaps while glref always uses trilinear mipmaps
    (GL_LINEAR_MIPMAP_LINEAR), so textured models differ in colour even where the
    ids agree; `--rast-args="--filter trilinear"` brings them close.

The exit status is 1 if any model's agreement is below --min-agreement (default
99.9) or a renderer failed on it, 0 otherwise, 2 on a usage error.

Standard library only (no numpy). Usage:

  python3 scripts/measure/glref_compare.py --rast build/openmp/rast --glref build/glref/glref \\
      [--size 1920x1080] [--models duck cow /path/x.glb ...] [--out DIR] \\
      [--min-agreement 99.9] [--json results.json] [--markdown table.md] \\
      [--images always|fail|never] [--rast-args="--filter trilinear"]

--models takes file paths, or names from the default list (e.g. `duck`,
`BoxTextured`, `Mesh_PrimitiveMode_04`). The default list is every .glb in the
shared models folder (--shared, default <repo>/../shared/models; skipped when
absent) plus the glTF 2.0 test models of Debian's assimp-testmodels listed in
ASSIMP_MODELS below (--assimp, default /usr/share/assimp/models/glTF2).

Under --out (default build/glref-compare/<WxH>) each model gets a folder with
glref's and rast's ids/depth/colour, and, for failing models (or all, with
--images always), false-colour pictures: ids_glref.png, ids_rast.png and
diff.png (black: background in both; grey: same id; red: only glref covers;
green: only rast covers; yellow: both cover, different ids).
"""
import argparse
import array
import datetime
import json
import os
import platform
import re
import struct
import subprocess
import sys
import time
import zlib

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# Debian assimp-testmodels glTF 2.0 files that are valid and contain triangles
# (the malformed ones, points/lines-only and missing-buffer files are left out;
# Draco and skins too: glref decodes no Draco and draws no skins, which rast
# does since #40 (docs/animation.md compares those with the Khronos Sample Renderer);
# and ClearCoatTest, whose BLEND and MASK materials rast draws since #39 and
# glref draws opaque (docs/transparency.md)).
ASSIMP_MODELS = [
    "BoxTextured-glTF-Binary/BoxTextured.glb",
    "BoxTextured-glTF/BoxTextured.gltf",
    "BoxTexcoords-glTF/boxTexcoords.gltf",
    "2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
    "textureTransform/TextureTransformTest.gltf",
    "cameras/Cameras.gltf",
    "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_04.gltf",  # strip
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_05.gltf",  # fan
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_06.gltf",  # triangles
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_11.gltf",  # indexed strip
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_12.gltf",  # indexed fan
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_13.gltf",  # u32 indices
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_14.gltf",  # u8 indices
    "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_15.gltf",  # u16 indices
]

CAMERA_RE = re.compile(r"^glref: camera(?: \(auto\))? (--eye \S+ --target \S+ --up \S+ "
                       r"--fovy \S+ --near \S+ --far \S+)\s*$", re.M)
GLREF_TRIS_RE = re.compile(r"^glref: renderer=.* tris=(\d+) size=\S+ median_ms=([0-9.eE+-]+)", re.M)
GLREF_RENDERER_RE = re.compile(r"^glref: GL_RENDERER=(.*)$", re.M)
RAST_TRIS_RE = re.compile(r"\((\d+)x(\d+), (\d+) triangles")
RAST_CAMERA_RE = re.compile(r"^rast: camera \(auto\) (--eye \S+ --target \S+ --up \S+ "
                            r"--fovy \S+ --near \S+ --far \S+)\s*$", re.M)


# ------------------------------------------------------------------ file readers
def read_ids(path):
    """glref-ids raw file -> (w, h, array('I') top row first)."""
    with open(path, "rb") as f:
        data = f.read()
    if not data.startswith(b"glref-ids "):
        raise ValueError(f"{path}: not a 'glref-ids W H u32le top-down' file")
    nl = data.index(b"\n")
    tok = data[:nl].split()
    if len(tok) != 5 or tok[3] != b"u32le" or tok[4] != b"top-down":
        raise ValueError(f"{path}: unexpected header {data[:nl]!r}")
    w, h = int(tok[1]), int(tok[2])
    ids = array.array("I")
    if ids.itemsize != 4:
        raise RuntimeError("array('I') is not 32-bit here")
    ids.frombytes(data[nl + 1:nl + 1 + 4 * w * h])
    if len(ids) != w * h:
        raise ValueError(f"{path}: truncated ({len(ids)} of {w * h} ids)")
    if sys.byteorder != "little":
        ids.byteswap()
    return w, h, ids


def read_pfm(path):
    """Greyscale PFM -> (w, h, array('f') top row first)."""
    with open(path, "rb") as f:
        data = f.read()
    parts, pos = [], 0
    while len(parts) < 4:
        while data[pos:pos + 1].isspace():
            pos += 1
        start = pos
        while not data[pos:pos + 1].isspace():
            pos += 1
        parts.append(data[start:pos].decode("ascii"))
    pos += 1
    kind, w, h, scale = parts[0], int(parts[1]), int(parts[2]), float(parts[3])
    if kind != "Pf":
        raise ValueError(f"{path}: only greyscale PFM (Pf) is supported, got {kind}")
    vals = array.array("f")
    vals.frombytes(data[pos:pos + 4 * w * h])
    if len(vals) != w * h:
        raise ValueError(f"{path}: truncated")
    if (scale < 0) != (sys.byteorder == "little"):
        vals.byteswap()
    out = array.array("f")
    for y in range(h - 1, -1, -1):  # PFM rows are bottom to top
        out.extend(vals[y * w:(y + 1) * w])
    return w, h, out


def _swar_add(a, b, m7, m8):
    """Bytewise (mod 256) sum of two byte strings packed into ints."""
    return ((a & m7) + (b & m7)) ^ ((a ^ b) & m8)


def read_png(path):
    """8-bit non-interlaced PNG (grey, RGB, grey+alpha, RGBA) -> (w, h, bytes RGB top row first)."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError(f"{path}: not a PNG")
    pos, idat, hdr = 8, [], None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        tag = data[pos + 4:pos + 8]
        body = data[pos + 8:pos + 8 + length]
        pos += 12 + length
        if tag == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif tag == b"IDAT":
            idat.append(body)
        elif tag == b"IEND":
            break
    w, h, depth, ctype, _, _, interlace = hdr
    channels = {0: 1, 2: 3, 4: 2, 6: 4}.get(ctype)
    if depth != 8 or channels is None or interlace != 0:
        raise ValueError(f"{path}: unsupported PNG (depth {depth}, colour type {ctype}, interlace {interlace})")
    raw = zlib.decompress(b"".join(idat))
    bpp, stride = channels, w * channels
    nbits = 8 * stride
    m8 = int.from_bytes(b"\x80" * stride, "little")
    m7 = int.from_bytes(b"\x7f" * stride, "little")
    out = bytearray(h * stride)
    prev = bytes(stride)
    for y in range(h):
        ft = raw[y * (stride + 1)]
        line = raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)]
        if ft == 0:
            cur = bytes(line)
        elif ft == 1 or ft == 2:
            x = int.from_bytes(line, "little")
            if ft == 1:   # Sub: prefix sum with stride bpp, by doubling (bytewise mod 256)
                s = 8 * bpp
                while s < nbits:
                    x = _swar_add(x, (x << s) & ((1 << nbits) - 1), m7, m8)
                    s *= 2
            else:         # Up
                x = _swar_add(x, int.from_bytes(prev, "little"), m7, m8)
            cur = x.to_bytes(stride, "little")
        elif ft == 3:     # Average
            c = bytearray(line)
            for i in range(stride):
                left = c[i - bpp] if i >= bpp else 0
                c[i] = (c[i] + ((left + prev[i]) >> 1)) & 255
            cur = bytes(c)
        elif ft == 4:     # Paeth
            c = bytearray(line)
            for i in range(stride):
                if i >= bpp:
                    a, cc = c[i - bpp], prev[i - bpp]
                else:
                    a = cc = 0
                b = prev[i]
                p = a + b - cc
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - cc)
                pred = a if (pa <= pb and pa <= pc) else (b if pb <= pc else cc)
                c[i] = (c[i] + pred) & 255
            cur = bytes(c)
        else:
            raise ValueError(f"{path}: bad PNG filter {ft}")
        out[y * stride:(y + 1) * stride] = cur
        prev = cur
    if channels == 3:
        return w, h, bytes(out)
    rgb = bytearray(3 * w * h)
    if channels == 4:
        for c in range(3):
            rgb[c::3] = out[c::4]
    elif channels == 2:
        for c in range(3):
            rgb[c::3] = out[0::2]
    else:
        for c in range(3):
            rgb[c::3] = out
    return w, h, bytes(rgb)


def write_png(path, w, h, rgb):
    """rgb: bytes-like, 3*w*h, top row first."""
    stride = 3 * w
    raw = b"".join(b"\x00" + bytes(rgb[y * stride:(y + 1) * stride]) for y in range(h))

    def chunk(tag, payload):
        c = struct.pack(">I", len(payload)) + tag + payload
        return c + struct.pack(">I", zlib.crc32(tag + payload) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 6)))
        f.write(chunk(b"IEND", b""))


def id_colour(v):  # same hash as glref's ids_tool.py
    if v == 0:
        return (0, 0, 0)
    x = (v * 2654435761) & 0xFFFFFFFF
    return (64 + (x & 0xBF), 64 + ((x >> 8) & 0xBF), 64 + ((x >> 16) & 0xBF))


def ids_picture(path, w, h, ids):
    lut = {}
    rgb = bytearray(3 * w * h)
    for i, v in enumerate(ids):
        if v:
            c = lut.get(v)
            if c is None:
                c = lut[v] = bytes(id_colour(v))
            rgb[3 * i:3 * i + 3] = c
    write_png(path, w, h, rgb)


def diff_picture(path, w, h, g, r):
    rgb = bytearray(3 * w * h)
    grey, red, green, yellow = b"\x46\x46\x46", b"\xff\x30\x30", b"\x30\xff\x30", b"\xff\xff\x00"
    for i, (a, b) in enumerate(zip(g, r)):
        if a == b:
            if a:
                rgb[3 * i:3 * i + 3] = grey
        elif not b:
            rgb[3 * i:3 * i + 3] = red
        elif not a:
            rgb[3 * i:3 * i + 3] = green
        else:
            rgb[3 * i:3 * i + 3] = yellow
    write_png(path, w, h, rgb)


# ------------------------------------------------------------------ comparison
def compare(w, h, g_ids, r_ids, g_depth, r_depth, g_rgb, r_rgb):
    n = w * h
    gb, rb = memoryview(g_ids).cast("B"), memoryview(r_ids).cast("B")
    zero_row = bytes(4 * w)
    agree = 0
    only_g = only_r = both_diff = 0
    dd = array.array("d")
    mism_rows = []
    cov_rows = []
    for y in range(h):
        o = y * w
        grow, rrow = gb[4 * o:4 * (o + w)], rb[4 * o:4 * (o + w)]
        if grow == rrow:
            agree += w
            if grow != zero_row:
                cov_rows.append(y)
            continue
        mism_rows.append(y)
        cov_rows.append(y)
    bbox = None
    for y in mism_rows:
        o = y * w
        for x, (a, b) in enumerate(zip(g_ids[o:o + w], r_ids[o:o + w])):
            if a == b:
                agree += 1
            else:
                if not b:
                    only_g += 1
                elif not a:
                    only_r += 1
                else:
                    both_diff += 1
                if bbox is None:
                    bbox = [x, y, x, y]
                else:
                    bbox[0] = min(bbox[0], x)
                    bbox[2] = max(bbox[2], x)
                    bbox[3] = y
    # depth on pixels covered by both with the same id; colour on pixels covered by either
    csum = [0, 0, 0]
    coff = 0
    union = 0
    for y in cov_rows:
        o = y * w
        for i in range(o, o + w):
            a, b = g_ids[i], r_ids[i]
            if not (a or b):
                continue
            union += 1
            if a == b:
                dd.append(abs(g_depth[i] - r_depth[i]))
            if g_rgb is not None:
                j = 3 * i
                d0 = abs(g_rgb[j] - r_rgb[j])
                d1 = abs(g_rgb[j + 1] - r_rgb[j + 1])
                d2 = abs(g_rgb[j + 2] - r_rgb[j + 2])
                csum[0] += d0
                csum[1] += d1
                csum[2] += d2
                if d0 > 8 or d1 > 8 or d2 > 8:
                    coff += 1
    res = {
        "pixels": n,
        "covered_glref": n - g_ids.count(0),
        "covered_rast": n - r_ids.count(0),
        "covered_union": union,
        "agree_px": agree,
        "agreement_pct": 100.0 * agree / n,
        "agreement_covered_pct": 100.0 * (union - (n - agree)) / union if union else 100.0,
        "mismatch_px": n - agree,
        "coverage_mismatch_glref_only": only_g,
        "coverage_mismatch_rast_only": only_r,
        "id_mismatch_both_covered": both_diff,
        "mismatch_bbox_xyxy": bbox,
    }
    if dd:
        s = sorted(dd)
        res.update(depth_compared_px=len(s), depth_max_abs=s[-1], depth_median_abs=s[len(s) // 2],
                   depth_mean_abs=sum(s) / len(s))
    else:
        res.update(depth_compared_px=0, depth_max_abs=None, depth_median_abs=None, depth_mean_abs=None)
    if g_rgb is not None and union:
        res.update(colour_mean_abs_rgb=[c / union for c in csum], colour_off8_pct=100.0 * coff / union)
    else:
        res.update(colour_mean_abs_rgb=None, colour_off8_pct=None)
    return res


# ------------------------------------------------------------------ driver
def run(cmd, timeout, env=None):
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=timeout, env=env)
        out = p.stdout.decode("utf-8", "replace")
        rc = p.returncode
    except subprocess.TimeoutExpired as e:
        out = (e.stdout or b"").decode("utf-8", "replace") + f"\n(timed out after {timeout} s)"
        rc = 124
    return rc, out, time.monotonic() - t0


def default_models(shared_dir, assimp_dir):
    models = []
    if shared_dir and os.path.isdir(shared_dir):
        for f in sorted(os.listdir(shared_dir)):
            if f.endswith(".glb"):
                models.append((os.path.splitext(f)[0], os.path.join(shared_dir, f)))
    if assimp_dir and os.path.isdir(assimp_dir):
        for rel in ASSIMP_MODELS:
            p = os.path.join(assimp_dir, rel)
            if os.path.isfile(p):
                models.append((os.path.splitext(rel)[0], p))
    return models


def resolve_models(args_models, defaults):
    out = []
    for m in args_models:
        if os.path.isfile(m):
            out.append((os.path.splitext(os.path.basename(m))[0], os.path.abspath(m)))
            continue
        hits = [d for d in defaults if d[0] == m or os.path.basename(d[0]) == m
                or os.path.splitext(os.path.basename(d[1]))[0] == m]
        if not hits:
            print(f"glref_compare: no model file or default model named '{m}' (see --list)", file=sys.stderr)
            raise SystemExit(2)
        out.extend(h for h in hits if h not in out)
    return out


def safe_name(name):
    return re.sub(r"[^A-Za-z0-9._-]+", "_", name)


def compare_model(name, path, args, w, h, env):
    d = os.path.join(args.out, safe_name(name))
    os.makedirs(d, exist_ok=True)
    f = {k: os.path.join(d, v) for k, v in dict(
        g_ids="glref_ids.bin", g_depth="glref_depth.pfm", g_png="glref.png",
        r_ids="rast_ids.bin", r_depth="rast_depth.pfm", r_png="rast.png").items()}
    for p in f.values():
        if os.path.exists(p):
            os.remove(p)
    res = {"model": name, "path": path, "size": f"{w}x{h}", "status": "ERROR", "error": None}
    gcmd = [args.glref, path, "--auto-camera", "--size", f"{w}x{h}", "--frames", str(args.glref_frames),
            "--warmup", str(args.glref_warmup), "--out-png", f["g_png"], "--out-ids", f["g_ids"],
            "--out-depth", f["g_depth"]]
    rc, gout, gsec = run(gcmd, args.timeout, env)
    with open(os.path.join(d, "glref.log"), "w") as lf:
        lf.write(" ".join(gcmd) + "\n" + gout)
    res["glref_s"] = round(gsec, 3)
    m = CAMERA_RE.search(gout)
    if rc != 0 or not m:
        res["error"] = f"glref failed (rc {rc}): " + gout.strip().splitlines()[-1:][0] if gout.strip() else f"glref rc {rc}"
        return res
    camera = m.group(1)
    res["camera"] = camera
    mt = GLREF_TRIS_RE.search(gout)
    res["tris_glref"] = int(mt.group(1)) if mt else None
    res["glref_median_ms"] = float(mt.group(2)) if mt else None
    mr = GLREF_RENDERER_RE.search(gout)
    res["glref_renderer"] = mr.group(1).strip() if mr else None
    # glref draws every face with Lambert under a headlight: so does rast's Lambert shading
    # (the glTF shading culls single-sided back faces).
    rcmd = [args.rast, "render", path, "-o", f["r_png"], "--size", f"{w}x{h}", "--shading", "lambert"] + camera.split() + \
        ["--aov", f"primid={f['r_ids']},depth={f['r_depth']}"] + args.rast_args.split()
    rc, rout, rsec = run(rcmd, args.timeout, env)
    with open(os.path.join(d, "rast.log"), "w") as lf:
        lf.write(" ".join(rcmd) + "\n" + rout)
    res["rast_s"] = round(rsec, 3)
    res["rast_cmd"] = " ".join(rcmd)
    if rc != 0 or not os.path.isfile(f["r_ids"]):
        lines = [l for l in rout.splitlines() if l.startswith("rast")] or rout.strip().splitlines() or [""]
        res["error"] = f"rast failed (rc {rc}): {lines[-1]}"
        return res
    mt = RAST_TRIS_RE.search(rout)
    res["tris_rast"] = int(mt.group(3)) if mt else None
    if args.check_auto_camera:
        # rast's own auto camera (no camera flags) must print the same line as glref's
        acmd = [args.rast, "render", path, "-o", os.path.join(d, "rast_autocam.png"), "--size", "64x36"]
        _, aout, _ = run(acmd, args.timeout, env)
        ma = RAST_CAMERA_RE.search(aout)
        res["rast_auto_camera"] = ma.group(1) if ma else None
        res["auto_camera_match"] = bool(ma) and ma.group(1) == camera
    try:
        gw, gh, g_ids = read_ids(f["g_ids"])
        rw, rh, r_ids = read_ids(f["r_ids"])
        if (gw, gh) != (w, h) or (rw, rh) != (w, h):
            raise ValueError(f"id buffer sizes glref {gw}x{gh}, rast {rw}x{rh}, expected {w}x{h}")
        _, _, g_depth = read_pfm(f["g_depth"])
        _, _, r_depth = read_pfm(f["r_depth"])
        g_rgb = r_rgb = None
        if not args.no_colour:
            _, _, g_rgb = read_png(f["g_png"])
            _, _, r_rgb = read_png(f["r_png"])
    except (OSError, ValueError) as e:
        res["error"] = f"reading outputs: {e}"
        return res
    t0 = time.monotonic()
    res.update(compare(w, h, g_ids, r_ids, g_depth, r_depth, g_rgb, r_rgb))
    res["compare_s"] = round(time.monotonic() - t0, 3)
    ok = res["agreement_pct"] >= args.min_agreement
    warnings = []
    if res["tris_glref"] is not None and res["tris_rast"] is not None and res["tris_glref"] != res["tris_rast"]:
        warnings.append(f"triangle counts differ: glref {res['tris_glref']}, rast {res['tris_rast']}")
    if res.get("auto_camera_match") is False:
        warnings.append("rast's auto camera differs from glref's")
    if warnings:
        res["warning"] = "; ".join(warnings)
    res["status"] = "ok" if ok else "FAIL"
    if args.images == "always" or (args.images == "fail" and not ok):
        ids_picture(os.path.join(d, "ids_glref.png"), w, h, g_ids)
        ids_picture(os.path.join(d, "ids_rast.png"), w, h, r_ids)
        diff_picture(os.path.join(d, "diff.png"), w, h, g_ids, r_ids)
        res["images"] = [os.path.join(d, x) for x in ("ids_glref.png", "ids_rast.png", "diff.png")]
    return res


def fmt(v, spec):
    return "-" if v is None else format(v, spec)


def print_table(results, min_agreement):
    hdr = (f"{'model':<44} {'tris':>7} {'agree%':>9} {'cov%':>9} {'g-only':>7} {'r-only':>7} "
           f"{'id-diff':>7} {'dmax':>8} {'dmed':>8} {'col-mad':>7} {'col>8%':>6}  status")
    print(hdr)
    print("-" * len(hdr))
    for r in results:
        name = r["model"] if len(r["model"]) <= 44 else "..." + r["model"][-41:]
        if r.get("error"):
            print(f"{name:<44} {'':>7} {r['status']:>9}  {r['error']}")
            continue
        cm = r.get("colour_mean_abs_rgb")
        print(f"{name:<44} {fmt(r.get('tris_glref'), 'd'):>7} {r['agreement_pct']:>9.4f} "
              f"{r['agreement_covered_pct']:>9.4f} {r['coverage_mismatch_glref_only']:>7d} "
              f"{r['coverage_mismatch_rast_only']:>7d} {r['id_mismatch_both_covered']:>7d} "
              f"{fmt(r['depth_max_abs'], '8.1e'):>8} {fmt(r['depth_median_abs'], '8.1e'):>8} "
              f"{fmt(sum(cm) / 3 if cm else None, '7.2f'):>7} {fmt(r.get('colour_off8_pct'), '6.2f'):>6}  "
              f"{r['status']}{'  (' + r['warning'] + ')' if r.get('warning') else ''}")
    print(f"agree% = equal ids over all pixels (pass >= {min_agreement}); cov% = over pixels either covers; "
          "g-only / r-only = covered only by glref / rast; id-diff = both cover, different ids; "
          "dmax / dmed = |depth| difference where ids agree; col-mad = mean |RGB| difference (0..255), "
          "col>8% = % of covered pixels off by > 8/255 (colour is information only: rast's default "
          "filter is bilinear without mipmaps, glref's trilinear with mipmaps)")


def markdown_table(results):
    lines = ["| model | tris | agreement % | % of covered | coverage mismatch (g-only / r-only) | "
             "id mismatch (both covered) | depth max / median abs diff | colour mean abs / % > 8 |",
             "|---|---:|---:|---:|---:|---:|---:|---:|"]
    for r in results:
        if r.get("error"):
            lines.append(f"| {r['model']} | | {r['status']} | | | | | {r['error']} |")
            continue
        cm = r.get("colour_mean_abs_rgb")
        col = f"{sum(cm) / 3:.2f} / {r['colour_off8_pct']:.2f}" if cm else "-"
        lines.append(f"| {r['model']} | {fmt(r.get('tris_glref'), 'd')} | {r['agreement_pct']:.4f} | "
                     f"{r['agreement_covered_pct']:.4f} | {r['coverage_mismatch_glref_only']} / "
                     f"{r['coverage_mismatch_rast_only']} | {r['id_mismatch_both_covered']} | "
                     f"{fmt(r['depth_max_abs'], '.1e')} / {fmt(r['depth_median_abs'], '.1e')} | {col} |")
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rast", required=True, help="rast executable")
    ap.add_argument("--glref", required=True, help="glref executable")
    ap.add_argument("--size", default="1920x1080", help="WxH (default 1920x1080)")
    ap.add_argument("--models", nargs="+", help="model files or default-list names (default: all)")
    ap.add_argument("--shared", default=os.path.join(os.path.dirname(REPO), "shared", "models"),
                    help="folder of shared .glb models (default <repo>/../shared/models)")
    ap.add_argument("--assimp", default="/usr/share/assimp/models/glTF2",
                    help="assimp-testmodels glTF2 folder")
    ap.add_argument("--out", help="output folder (default build/glref-compare/<WxH>)")
    ap.add_argument("--min-agreement", type=float, default=99.9, help="percent (default 99.9)")
    ap.add_argument("--json", help="write the results as JSON here")
    ap.add_argument("--markdown", help="write the table as Markdown here (for docs/glref-agreement.md)")
    ap.add_argument("--images", choices=("always", "fail", "never"), default="fail",
                    help="write false-colour id / diff pictures (default: for failing models)")
    ap.add_argument("--no-colour", action="store_true", help="skip the (information-only) colour comparison")
    ap.add_argument("--rast-args", default="",
                    help="extra rast render arguments, e.g. '--filter trilinear' (closer colours to glref)")
    ap.add_argument("--glref-frames", type=int, default=3)
    ap.add_argument("--glref-warmup", type=int, default=1)
    ap.add_argument("--timeout", type=float, default=300, help="seconds per renderer run")
    ap.add_argument("--no-auto-camera-check", dest="check_auto_camera", action="store_false",
                    help="do not check that rast's own auto camera line equals glref's (information only)")
    ap.add_argument("--list", action="store_true", help="print the default model list and exit")
    args = ap.parse_args(argv)

    m = re.fullmatch(r"(\d+)x(\d+)", args.size)
    if not m:
        ap.error(f"bad --size {args.size}")
    w, h = int(m.group(1)), int(m.group(2))
    defaults = default_models(args.shared, args.assimp)
    if args.list:
        for name, p in defaults:
            print(f"{name}\t{p}")
        return 0
    models = resolve_models(args.models, defaults) if args.models else defaults
    if not models:
        print("glref_compare: no models (neither --shared nor --assimp folder has any)", file=sys.stderr)
        return 2
    for exe in (args.rast, args.glref):
        if not (os.path.isfile(exe) and os.access(exe, os.X_OK)):
            print(f"glref_compare: not an executable: {exe}", file=sys.stderr)
            return 2
    args.rast, args.glref = os.path.abspath(args.rast), os.path.abspath(args.glref)
    args.out = os.path.abspath(args.out or os.path.join(REPO, "build", "glref-compare", f"{w}x{h}"))
    os.makedirs(args.out, exist_ok=True)
    env = dict(os.environ)
    env.setdefault("OMP_PROC_BIND", "false")

    t_start = time.monotonic()
    results = []
    for name, path in models:
        r = compare_model(name, path, args, w, h, env)
        results.append(r)
        if r.get("error"):
            print(f"[{name}] {r['status']}: {r['error']}", flush=True)
        else:
            print(f"[{name}] {r['agreement_pct']:.4f}% ids agree ({r['mismatch_px']} px differ) "
                  f"glref {r['glref_s']:.1f}s rast {r['rast_s']:.1f}s compare {r['compare_s']:.1f}s "
                  f"{r['status']}", flush=True)
    total = time.monotonic() - t_start
    print()
    print_table(results, args.min_agreement)
    bad = [r["model"] for r in results if r["status"] != "ok"]
    print(f"\n{len(results) - len(bad)}/{len(results)} models at >= {args.min_agreement}% id agreement "
          f"({w}x{h}, {total:.1f} s){'; below / failed: ' + ', '.join(bad) if bad else ''}")
    if args.json:
        renderer = next((r.get("glref_renderer") for r in results if r.get("glref_renderer")), None)
        doc = {"date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
               "host": platform.node(), "platform": platform.platform(), "glref_renderer": renderer,
               "size": f"{w}x{h}", "min_agreement_pct": args.min_agreement, "seconds": round(total, 2),
               "rast": args.rast, "glref": args.glref, "passed": not bad, "models": results}
        os.makedirs(os.path.dirname(os.path.abspath(args.json)), exist_ok=True)
        with open(args.json, "w") as jf:
            json.dump(doc, jf, indent=1)
    if args.markdown:
        with open(args.markdown, "w") as mf:
            mf.write(markdown_table(results))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

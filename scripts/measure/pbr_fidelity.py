#!/usr/bin/python3
"""Agreement of rast's glTF shading (`--shading pbr`) with the Khronos glTF
Sample Renderer, the reference implementation of the glTF material model
(issue #37; docs/gltf-support.md has the figures).

For each model: a copy of the file with one directional light added when it
has none (KHR_lights_punctual, so that both renderers light it the same way),
rendered by rast from its own auto-framed camera and by
../shared/tools/khronos-ref from the same camera flags, then compared with
../shared/tools/khronos-ref/fidelity.py. The reference runs once for all
models (its start-up filters an environment: minutes on 2 cores); with
--env once per model, unless --one-context (below).

--one-context runs a copy of the reference (in OUT) whose page keeps one
WebGL context for the batch, so that with --env too all models share one
start-up; see one_context_kref.

  scripts/measure/pbr_fidelity.py --rast build/openmp/rast --out /tmp/fid \\
      [--size 480x360] [--env FILE.hdr --tonemap pbr-neutral] [--extra-flags "..."]
      [--one-context] [--samplers nomip|mipnear] [--by-material [--group LABEL=REGEX]... [--self-shift PX]] MODEL...

--samplers changes the copies' samplers, both renderers drawing the same
copy (docs/gltf-support.md, "Mipmaps and anisotropy"): `nomip` sets every
minification filter to the magnification filter (no mipmaps, and so no
anisotropic filtering on either side: the Sample Renderer asks WebGL for 16x
only with *_MIPMAP_LINEAR, rast likewise), `mipnear` to LINEAR_MIPMAP_NEAREST
(NEAREST_MIPMAP_NEAREST under a NEAREST magnification: the nearest level,
no anisotropy); the rows are named MODEL_nomip, MODEL_mipnear. The copies
live in OUT only.

--by-material adds, per model, where the disagreement lies: rast draws a
material-id image (every material unlit in a colour of its own, opaque) from
the same camera, and the `gamma 2.2` comparison's interior pixels are split by
material (pixels, beyond 3 and 8/255, mean and signed mean difference per
channel); `--group LABEL=REGEX` adds a row for the materials whose name
matches. `--self-shift PX` compares rast with itself instead of the reference
(no reference is run), its camera moved sideways by PX pixels: how much a
pixel depends on where exactly it samples the surface (docs/gltf-support.md,
"ClearCoatTest, part by part").

Writes OUT/<name>.rast.png, OUT/<name>.ref.png and OUT/fidelity.json, and
prints a Markdown table; models with no interior (points and lines one pixel
wide, which the erosion removes) get a second table over the pixels both
renderers cover, not eroded, and a third that tells their coverage apart
by simulating it with the reference's subpixel precision and with rast's. The reference encodes its output with a 2.2 power
curve where rast writes the sRGB curve (both clamp at 1): the table gives the
figures for rast's PNG and, in the `gamma 2.2` columns, for rast's linear
output (`-o F.pfm`) encoded the reference's way, which separates the
shading's differences from that choice.
"""
import argparse
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
SHARED = os.path.normpath(os.path.join(HERE, "..", "..", "..", "shared"))
KREF = os.path.join(SHARED, "tools", "khronos-ref")


def read_gltf(path):
    """The JSON of a .gltf or .glb, and the GLB's binary chunk (or None)."""
    data = open(path, "rb").read()
    if data[:4] != b"glTF":
        return json.loads(data.decode("utf-8")), None
    length = struct.unpack_from("<I", data, 8)[0]
    off, doc, binary = 12, None, None
    while off + 8 <= length:
        n, kind = struct.unpack_from("<II", data, off)
        chunk = data[off + 8:off + 8 + n]
        if kind == 0x4E4F534A:
            doc = json.loads(chunk.decode("utf-8"))
        elif kind == 0x004E4942:
            binary = chunk
        off += 8 + n
    return doc, binary


def write_glb(path, doc, binary):
    js = json.dumps(doc).encode("utf-8")
    js += b" " * ((4 - len(js) % 4) % 4)
    out = struct.pack("<II", len(js), 0x4E4F534A) + js
    if binary is not None:
        b = binary + b"\0" * ((4 - len(binary) % 4) % 4)
        out += struct.pack("<II", len(b), 0x004E4942) + b
    open(path, "wb").write(struct.pack("<III", 0x46546C67, 2, 12 + len(out)) + out)


def quat_from_minus_z(d):
    """The rotation taking -Z to unit vector d, as glTF's (x, y, z, w)."""
    a = (0.0, 0.0, -1.0)
    c = (a[1] * d[2] - a[2] * d[1], a[2] * d[0] - a[0] * d[2], a[0] * d[1] - a[1] * d[0])
    w = 1.0 + sum(x * y for x, y in zip(a, d))
    n = math.sqrt(sum(x * x for x in c) + w * w)
    return [c[0] / n, c[1] / n, c[2] / n, w / n]


def change_samplers(doc, kind):
    """--samplers: every texture's sampler (one added where a texture has none)
    without mipmaps (`nomip`) or with the nearest level (`mipnear`)."""
    samplers = doc.setdefault("samplers", [])
    for t in doc.get("textures", []):
        if "sampler" not in t:
            samplers.append({})
            t["sampler"] = len(samplers) - 1
    for s in samplers:
        nearest = s.get("magFilter", 9729) == 9728
        if kind == "nomip":
            s["minFilter"] = 9728 if nearest else 9729  # NEAREST, LINEAR
        else:
            s["minFilter"] = 9984 if nearest else 9985  # NEAREST_MIPMAP_NEAREST, LINEAR_MIPMAP_NEAREST


def with_light(src, dst_dir, direction, intensity, add=True, samplers=None):
    """A copy of `src` in dst_dir that has a directional light if it had none (and `add`)."""
    doc, binary = read_gltf(src)
    has = bool(doc.get("extensions", {}).get("KHR_lights_punctual", {}).get("lights")) or not add
    name = os.path.splitext(os.path.basename(src))[0]
    if samplers:
        change_samplers(doc, samplers)
        name += "_" + samplers
    if not has:
        n = math.sqrt(sum(x * x for x in direction))
        d = [x / n for x in direction]
        doc.setdefault("extensions", {})["KHR_lights_punctual"] = {
            "lights": [{"type": "directional", "intensity": intensity, "color": [1, 1, 1]}]}
        used = doc.setdefault("extensionsUsed", [])
        if "KHR_lights_punctual" not in used:
            used.append("KHR_lights_punctual")
        doc.setdefault("nodes", []).append({"name": "added_sun", "rotation": quat_from_minus_z(d),
                                            "extensions": {"KHR_lights_punctual": {"light": 0}}})
        scenes = doc.setdefault("scenes", [{"nodes": []}])
        scenes[doc.get("scene", 0)].setdefault("nodes", []).append(len(doc["nodes"]) - 1)
    if binary is not None:
        out = os.path.join(dst_dir, name + ".glb")
        write_glb(out, doc, binary)
    else:
        # External buffers and images stay where the file names them: copy its folder.
        folder = os.path.join(dst_dir, name + "_src")
        if os.path.exists(folder):
            shutil.rmtree(folder)
        shutil.copytree(os.path.dirname(os.path.abspath(src)), folder)
        out = os.path.join(folder, name + ".lit.gltf")
        json.dump(doc, open(out, "w"))
    return name, out, not has


def read_pfm(path):
    """A PFM's pixels as rows of (r, g, b) floats, top row first."""
    import numpy as np
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = (int(x) for x in f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    c = 3 if kind == b"PF" else 1
    return data.reshape(h, w, c)[::-1]


def gamma22(pfm):
    """A linear PFM as the reference encodes (2.2 power curve, clamped), integer bytes."""
    import numpy as np
    return (np.power(np.clip(read_pfm(pfm), 0.0, 1.0), 1 / 2.2) * 255 + 0.5).astype(np.int64)


def write_gamma22_png(pfm, png):
    import numpy as np
    from PIL import Image
    Image.fromarray(gamma22(pfm).astype(np.uint8)).save(png)


def camera_flags(rast, scene, size, out_dir):
    """rast's auto-framed camera for the scene, as flags (it prints them)."""
    r = subprocess.run([rast, "render", scene, "--size", size, "-o", os.path.join(out_dir, "camera_probe.png"),
                        "--shading", "depth"], capture_output=True, text=True)
    for line in (r.stdout + r.stderr).splitlines():
        if "camera (auto)" in line or "camera (" in line:
            return line.split(") ", 1)[1].split()
    raise SystemExit(f"pbr_fidelity: no camera line from rast for {scene}: {r.stderr.strip()}")


def erode(m):
    """The pixels whose four neighbours are in m too (fidelity.py's interior)."""
    e = m.copy()
    e[1:, :] &= m[:-1, :]
    e[:-1, :] &= m[1:, :]
    e[:, 1:] &= m[:, :-1]
    e[:, :-1] &= m[:, 1:]
    return e


def material_ids(rast, model, out, cam, size):
    """--by-material: per pixel, the index of the material drawn there (-1: none), and the names."""
    import numpy as np
    doc, binary = read_gltf(model)
    mats = doc.get("materials", [])
    if len(mats) > 250:
        raise SystemExit("pbr_fidelity: --by-material takes at most 250 materials")
    for i, m in enumerate(mats):
        mats[i] = {"name": m.get("name", str(i)), "doubleSided": m.get("doubleSided", False),
                   "pbrMetallicRoughness": {"baseColorFactor": [(i + 1) / 255.0, 0, 0, 1]},
                   "extensions": {"KHR_materials_unlit": {}}}
    used = doc.setdefault("extensionsUsed", [])
    if "KHR_materials_unlit" not in used:
        used.append("KHR_materials_unlit")
    if binary is not None:
        path = os.path.join(out, "material_ids.glb")
        write_glb(path, doc, binary)
    else:
        folder = os.path.join(out, "material_ids_src")
        if os.path.exists(folder):
            shutil.rmtree(folder)
        shutil.copytree(os.path.dirname(os.path.abspath(model)), folder)
        path = os.path.join(folder, "material_ids.gltf")
        json.dump(doc, open(path, "w"))
    pfm = os.path.join(out, "material_ids.pfm")
    subprocess.run([rast, "render", path, "--size", size, "-o", pfm, "--shading", "pbr", "--aa", "none",
                    "--tonemap", "none", "--env", "none"] + cam, check=True, capture_output=True)
    return np.rint(read_pfm(pfm)[..., 0] * 255).astype(int) - 1, [m["name"] for m in mats]


def moved_camera(cam, size, px):
    """The camera flags moved sideways by px pixels (measured at the target's distance)."""
    import numpy as np
    flags = dict(zip(cam[0::2], cam[1::2]))
    eye = np.array([float(x) for x in flags["--eye"].split(",")])
    target = np.array([float(x) for x in flags["--target"].split(",")])
    dist = np.linalg.norm(target - eye)
    pixel = 2 * dist * math.tan(math.radians(float(flags.get("--fovy", "45"))) / 2) / int(size.split("x")[1])
    right = np.cross((target - eye) / dist, [0.0, 1.0, 0.0])
    d = right / np.linalg.norm(right) * px * pixel
    out = list(cam)
    out[out.index("--eye") + 1] = ",".join(repr(float(x)) for x in eye + d)
    out[out.index("--target") + 1] = ",".join(repr(float(x)) for x in target + d)
    return out


def material_table(a, row):
    """--by-material: the table of one model."""
    import numpy as np
    from PIL import Image
    ids, names = material_ids(a.rast, row["source"], a.out, row["camera"], a.size)
    if a.self_shift is None:
        ref = np.asarray(Image.open(row["ref"]).convert("RGB")).astype(np.int64)
        ours = np.asarray(Image.open(row["rast"].replace(".rast.png", ".rast_g22.png")).convert("RGB")).astype(np.int64)
        what = "rast (gamma 2.2) against the reference"
    else:
        ref = gamma22(row["rast"].replace(".png", ".pfm"))
        moved = row["rast"].replace(".rast.png", ".moved.pfm")
        cmd = list(row["command"])
        cmd[cmd.index(row["rast"].replace(".png", ".pfm"))] = moved  # the command that drew the PFM
        cmd = cmd[:cmd.index(row["camera"][0])] + moved_camera(row["camera"], a.size, a.self_shift) + \
            cmd[cmd.index(row["camera"][0]) + len(row["camera"]):]
        subprocess.run(cmd, capture_output=True, text=True, check=True)
        ours = gamma22(moved)
        what = f"rast (gamma 2.2) against itself moved by {a.self_shift} px"
    inner = erode(np.any(ref > 0, axis=2) & np.any(ours > 0, axis=2))  # black background, as fidelity.py
    dmax = np.abs(ref - ours).max(axis=2)
    print(f"\n{row['model']}, {what}: {int(inner.sum())} interior pixels, {int(np.sum(inner & (dmax > 8)))} beyond 8/255\n")
    print("| material | interior px | beyond 3/255 | beyond 8/255 | share beyond 8 | mean diff /255 | signed mean r, g, b |")
    print("|---|---|---|---|---|---|---|")

    def line(label, sel):
        m = inner & sel
        n = int(m.sum())
        if n:
            d = (ours - ref)[m]
            print(f"| {label} | {n} | {int(np.sum(dmax[m] > 3))} | {int(np.sum(dmax[m] > 8))} | {np.mean(dmax[m] > 8):.3f} | "
                  f"{np.abs(d).mean():.2f} | {d[:, 0].mean():+.2f}, {d[:, 1].mean():+.2f}, {d[:, 2].mean():+.2f} |")

    for i, n in enumerate(names):
        line(n, ids == i)
    line("(no material in the id image)", ids < 0)
    for g in a.group:
        label, _, rx = g.partition("=")
        sel = np.zeros(ids.shape, dtype=bool)
        for i, n in enumerate(names):
            if re.search(rx, n):
                sel |= ids == i
        line(f"**{label}**", sel)


def one_context_kref(out):
    """--one-context: a copy of khronos-ref in OUT whose page keeps one WebGL
    context for a whole batch. As shipped the page makes a context per scene
    but keeps the environment it filtered in the first one, whose textures the
    later contexts cannot use: with --env a batch drew only its first scene
    right. With one context a batch's scenes match runs of their own to the
    bit (docs/gltf-support.md, "glTF-Asset-Generator's primitive modes")."""
    dst = os.path.join(out, "khronos-ref-one-context")
    os.makedirs(dst, exist_ok=True)
    for f in ("khronos_ref.mjs", "black.hdr"):
        shutil.copyfile(os.path.join(KREF, f), os.path.join(dst, f))
    page = open(os.path.join(KREF, "page.html")).read()
    old = """  const canvas = document.createElement('canvas');
  canvas.width = p.width; canvas.height = p.height;
  document.body.replaceChildren(canvas);
  const gl = canvas.getContext('webgl2', { alpha: true, antialias: !!p.antialias, preserveDrawingBuffer: true });
  const view = new GltfView(gl);
  const state = view.createState();
  const loader = new ResourceLoader(view);"""
    new = """  if (!window.ctx || ctx.w !== p.width || ctx.h !== p.height || ctx.aa !== !!p.antialias) {
    const canvas = document.createElement('canvas');
    canvas.width = p.width; canvas.height = p.height;
    document.body.replaceChildren(canvas);
    const gl = canvas.getContext('webgl2', { alpha: true, antialias: !!p.antialias, preserveDrawingBuffer: true });
    const view = new GltfView(gl);
    window.ctx = { w: p.width, h: p.height, aa: !!p.antialias, canvas, view, loader: new ResourceLoader(view) };
    envs.clear();
  }
  const canvas = ctx.canvas, view = ctx.view, loader = ctx.loader;
  const state = view.createState();"""
    if old not in page:
        raise SystemExit("pbr_fidelity: --one-context does not know this khronos-ref page.html")
    open(os.path.join(dst, "page.html"), "w").write(page.replace(old, new))
    return os.path.join(dst, "khronos_ref.mjs")


def covered_both(ref_png, test_png):
    """Points and lines one pixel wide have no interior (fidelity.py erodes it
    away): the pixels both images cover, not eroded, and how far their colours
    differ, with each image's covered pixel count."""
    import numpy as np
    from PIL import Image
    ref = np.asarray(Image.open(ref_png).convert("RGB")).astype(np.int64)
    test = np.asarray(Image.open(test_png).convert("RGB")).astype(np.int64)
    cr, ct = np.any(ref > 0, axis=2), np.any(test > 0, axis=2)
    both = cr & ct
    d = np.abs(ref - test)[both]
    n = int(both.sum())
    return {"ref_px": int(cr.sum()), "test_px": int(ct.sum()), "both_px": n,
            "within3": float(np.mean(np.all(d <= 3, axis=1))) if n else 0.0,
            "within8": float(np.mean(np.all(d <= 8, axis=1))) if n else 0.0,
            "mae": float(d.mean()) if n else 0.0}


def node_matrix(n):
    """A glTF node's local matrix (column vectors), from `matrix` or T * R * S."""
    import numpy as np
    if "matrix" in n:
        return np.array(n["matrix"], dtype=np.float64).reshape(4, 4).T
    x, y, z, w = n.get("rotation", [0, 0, 0, 1])
    r = np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])
    m = np.eye(4)
    m[:3, :3] = r * np.array(n.get("scale", [1, 1, 1]))
    m[:3, 3] = n.get("translation", [0, 0, 0])
    return m


def snap_check(row, size):
    """Points and lines: their pixels simulated from the file's positions and
    the camera, window coordinates snapped to 1/16 pixel (4 subpixel bits, the
    reference's SwiftShader) and to 1/256 (8 bits, rast); points as squares of
    size 1, lines one pixel per column (x-major) or row at the pixel centre,
    the pixels within one of a segment's ends left out (their rules differ).
    Returns how many pixels each simulation gets wrong against each image."""
    import numpy as np
    from PIL import Image
    doc, binary = read_gltf(row["source"])
    folder = os.path.dirname(os.path.abspath(row["source"]))

    def floats(i):
        a = doc["accessors"][i]
        v = doc["bufferViews"][a["bufferView"]]
        b = binary if binary is not None else open(os.path.join(folder, doc["buffers"][v["buffer"]]["uri"]), "rb").read()
        n = {"SCALAR": 1, "VEC3": 3}[a["type"]]
        dt = {5126: "<f4", 5125: "<u4", 5123: "<u2", 5121: "u1"}[a["componentType"]]
        stride = v.get("byteStride", 0) or n * np.dtype(dt).itemsize
        raw = np.frombuffer(b, dtype=np.uint8, count=stride * (a["count"] - 1) + n * np.dtype(dt).itemsize,
                            offset=v.get("byteOffset", 0) + a.get("byteOffset", 0))
        return np.array([np.frombuffer(raw[k * stride:k * stride + n * np.dtype(dt).itemsize], dtype=dt)
                         for k in range(a["count"])], dtype=np.float64)

    segs, pts = [], []

    def walk(i, parent):
        m = parent @ node_matrix(doc["nodes"][i])
        for p in doc["meshes"][doc["nodes"][i]["mesh"]]["primitives"] if "mesh" in doc["nodes"][i] else []:
            pos = floats(p["attributes"]["POSITION"])
            pos = (np.c_[pos, np.ones(len(pos))] @ m.T)[:, :3]
            idx = floats(p["indices"])[:, 0].astype(int) if "indices" in p else np.arange(len(pos))
            mode = p.get("mode", 4)
            if mode == 0:
                pts.extend(pos[idx])
            elif mode in (1, 2, 3):
                pairs = list(zip(idx[0::2], idx[1::2])) if mode == 1 else list(zip(idx[:-1], idx[1:]))
                pairs += [(idx[-1], idx[0])] if mode == 2 else []
                segs.extend((pos[a], pos[b]) for a, b in pairs)
        for c in doc["nodes"][i].get("children", []):
            walk(c, m)

    for i in doc["scenes"][doc.get("scene", 0)]["nodes"]:
        walk(i, np.eye(4))
    flags = dict(zip(row["camera"][0::2], row["camera"][1::2]))
    eye, target, up = (np.array([float(x) for x in flags[k].split(",")]) for k in ("--eye", "--target", "--up"))
    f = (target - eye) / np.linalg.norm(target - eye)
    r = np.cross(f, up)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    w, h = (int(x) for x in size.split("x"))
    t = math.tan(math.radians(float(flags.get("--fovy", "45"))) / 2)

    def window(p):
        v = np.asarray(p) - eye
        z = v @ f
        return ((v @ r) / (z * t * w / h) + 1) / 2 * w, ((v @ u) / (z * t) + 1) / 2 * h

    def draw(bits):
        q = float(2 ** bits)
        snap = lambda c: round(c * q) / q  # noqa: E731
        img, ends = np.zeros((h, w), bool), np.zeros((h, w), bool)
        for p in pts:
            x, y = (snap(c) for c in window(p))
            img[h - 1 - (math.ceil(y) - 1), math.ceil(x) - 1] = True
        for a, b in segs:
            (x0, y0), (x1, y1) = ([snap(c) for c in window(e)] for e in (a, b))
            for ex, ey in ((x0, y0), (x1, y1)):
                ends[max(0, h - 2 - math.floor(ey)):h + 1 - math.floor(ey), max(0, math.floor(ex) - 1):math.floor(ex) + 2] = True
            ymajor = abs(y1 - y0) > abs(x1 - x0)
            if ymajor:
                x0, y0, x1, y1 = y0, x0, y1, x1
            if x1 < x0:
                x0, y0, x1, y1 = x1, y1, x0, y0
            for c in range(math.floor(x0), math.ceil(x1) + 1):
                if x0 <= c + 0.5 <= x1:
                    m = math.floor(y0 + (y1 - y0) * (c + 0.5 - x0) / (x1 - x0))
                    X, Y = (m, c) if ymajor else (c, m)
                    img[h - 1 - Y, X] = True
        return img, ends

    ref = np.any(np.asarray(Image.open(row["ref"]).convert("RGB")) > 0, axis=2)
    ours = np.any(np.asarray(Image.open(row["rast"]).convert("RGB")) > 0, axis=2)
    (s4, e4), (s8, e8) = draw(4), draw(8)
    keep = ~(e4 | e8)
    return {"ref_vs_rast": int(np.sum((ref != ours) & keep)), "ends_ref_vs_rast": int(np.sum((ref != ours) & ~keep)),
            "snap16_vs_ref": int(np.sum((s4 != ref) & keep)), "snap16_vs_rast": int(np.sum((s4 != ours) & keep)),
            "snap256_vs_ref": int(np.sum((s8 != ref) & keep)), "snap256_vs_rast": int(np.sum((s8 != ours) & keep))}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rast", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--size", default="480x360")
    ap.add_argument("--env", default=None)
    ap.add_argument("--tonemap", default="none", help="rast's name: none|pbr-neutral")
    ap.add_argument("--light", default="-0.5,-1,-0.7", help="direction of the added sun")
    ap.add_argument("--intensity", type=float, default=3.0)
    ap.add_argument("--extra-flags", default="", help="more rast render flags")
    ap.add_argument("--skip-ref", action="store_true", help="reuse OUT/*.ref.png")
    ap.add_argument("--no-added-light", action="store_true", help="add no light to files without any (with --env)")
    ap.add_argument("--one-context", action="store_true",
                    help="with --env, one reference run for all models, its page keeping one WebGL context (above)")
    ap.add_argument("--samplers", choices=["nomip", "mipnear"], help="change every sampler of the copies (above)")
    ap.add_argument("--by-material", action="store_true", help="where the disagreement lies, material by material")
    ap.add_argument("--group", action="append", default=[], help="with --by-material: a row LABEL for names matching REGEX")
    ap.add_argument("--self-shift", type=float, default=None, help="with --by-material: rast against itself moved by PX pixels")
    ap.add_argument("models", nargs="+")
    a = ap.parse_args()
    if (a.group or a.self_shift is not None) and not a.by_material:
        ap.error("--group and --self-shift go with --by-material")
    os.makedirs(a.out, exist_ok=True)
    direction = [float(x) for x in a.light.split(",")]
    jobs, rows = [], []
    for m in a.models:
        name, lit, added = with_light(m, a.out, direction, a.intensity, not a.no_added_light, a.samplers)
        cam = camera_flags(a.rast, lit, a.size, a.out)
        rast_png = os.path.join(a.out, name + ".rast.png")
        ref_png = os.path.join(a.out, name + ".ref.png")
        # --anisotropy 16: the reference asks WebGL for 16x anisotropic
        # filtering; rast's default is the sampler's own filter.
        cmd = [a.rast, "render", lit, "--size", a.size, "-o", rast_png, "--shading", "pbr", "--aa", "none",
               "--tonemap", a.tonemap, "--anisotropy", "16"] + cam + a.extra_flags.split()
        # The reference has no image-based light without --env: neither has rast then.
        cmd += ["--env", a.env or "none"]
        r = subprocess.run(cmd, capture_output=True, text=True)
        if r.returncode != 0:
            rows.append({"model": name, "error": r.stderr.strip().splitlines()[-1]})
            continue
        pfm = os.path.join(a.out, name + ".rast.pfm")
        cmd[cmd.index(rast_png)] = pfm
        subprocess.run(cmd, capture_output=True, text=True, check=True)
        flags = dict(zip(cam[0::2], cam[1::2]))
        job = {"scene": lit, "out": ref_png, "size": a.size, "tonemap": {"none": "none", "pbr-neutral": "khr"}[a.tonemap]}
        for k in ("eye", "target", "up", "fovy", "near", "far"):
            if "--" + k in flags:
                job[k] = flags["--" + k]
        if a.env:
            job["env"] = a.env
        jobs.append(job)
        rows.append({"model": name, "rast": rast_png, "ref": ref_png, "light_added": added, "source": m,
                     "camera": cam, "command": cmd})
    if a.self_shift is not None:
        for row in rows:
            if "error" not in row:
                material_table(a, row)
        return 0
    if not a.skip_ref and jobs:
        # One batch shares the reference's start-up; with an environment a
        # batch drew only its first scene right (the later ones came out
        # unlit or empty, 2026-11-26), so then each scene runs on its own.
        # --one-context: a copy of the reference that keeps one WebGL context,
        # whose batches draw every scene right (one_context_kref).
        groups = [[j] for j in jobs] if a.env and not a.one_context else [jobs]
        kref = one_context_kref(a.out) if a.one_context else os.path.join(KREF, "khronos_ref.mjs")
        for k, group in enumerate(groups):
            batch = os.path.join(a.out, f"jobs{k}.jsonl")
            with open(batch, "w") as f:
                for j in group:
                    f.write(json.dumps(j) + "\n")
            subprocess.run(["node", kref, "--batch", batch], check=False)
    print("| model | interior px | within 3/255 | within 8/255 | mean diff /255 | gamma 2.2: within 3 | within 8 | mean diff | coverage IoU |")
    print("|---|---|---|---|---|---|---|---|---|")
    for row in rows:
        if "error" in row:
            print(f"| {row['model']} | | rast failed: {row['error']} | | | | |")
            continue
        if not os.path.exists(row["ref"]):
            print(f"| {row['model']} | | reference failed | | | | |")
            continue
        def fidelity(test):
            r = subprocess.run(["/usr/bin/python3", os.path.join(KREF, "fidelity.py"), row["ref"], test, "--json"],
                               capture_output=True, text=True)
            return json.loads(r.stdout)
        f = fidelity(row["rast"])
        g22 = row["rast"].replace(".rast.png", ".rast_g22.png")
        write_gamma22_png(row["rast"].replace(".png", ".pfm"), g22)
        g = fidelity(g22)
        row["srgb"], row["gamma22"] = f, g
        own = bool(read_gltf(row["source"])[0].get("extensions", {}).get("KHR_lights_punctual", {}).get("lights"))
        print(f"| {row['model']}{' (own lights)' if own else ''} | {f['interior']} | {f['within3']:.3f} | "
              f"{f['within8']:.3f} | {f['mae']:.2f} | {g['within3']:.3f} | {g['within8']:.3f} | {g['mae']:.2f} | "
              f"{f['coverage_iou']:.3f} |")
        if f["interior"] == 0:
            row["covered_both"] = {"srgb": covered_both(row["ref"], row["rast"]), "gamma22": covered_both(row["ref"], g22)}
            row["snap"] = snap_check(row, a.size)
    thin = [r for r in rows if "covered_both" in r]
    if thin:
        print("\nNo interior (points, lines): the pixels both cover, not eroded (gamma 2.2 columns: rast's PFM encoded as the reference does)\n")
        print("| model | reference px | rast px | both | within 3/255 | within 8/255 | mean diff /255 | gamma 2.2: within 3 | within 8 | mean diff |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for r in thin:
            c, g = r["covered_both"]["srgb"], r["covered_both"]["gamma22"]
            print(f"| {r['model']} | {c['ref_px']} | {c['test_px']} | {c['both_px']} | {c['within3']:.3f} | {c['within8']:.3f} | "
                  f"{c['mae']:.2f} | {g['within3']:.3f} | {g['within8']:.3f} | {g['mae']:.2f} |")
        print("\nWhere their pixels differ: the coverage simulated with window coordinates snapped to 1/16 pixel "
              "(the reference's SwiftShader) and to 1/256 (rast), away from the segments' ends (snap_check)\n")
        print("| model | pixels ref != rast | of them at segment ends | 1/16 sim != ref | 1/16 sim != rast | "
              "1/256 sim != ref | 1/256 sim != rast |")
        print("|---|---|---|---|---|---|---|")
        for r in thin:
            c = r["snap"]
            print(f"| {r['model']} | {c['ref_vs_rast']} | {c['ends_ref_vs_rast']} | {c['snap16_vs_ref']} | "
                  f"{c['snap16_vs_rast']} | {c['snap256_vs_ref']} | {c['snap256_vs_rast']} |")
    json.dump(rows, open(os.path.join(a.out, "fidelity.json"), "w"), indent=1)
    if a.by_material:
        for row in rows:
            if "gamma22" in row:
                material_table(a, row)


if __name__ == "__main__":
    sys.exit(main())

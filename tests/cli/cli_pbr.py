#!/usr/bin/env python3
"""The glTF material model from the command line (#37):

 - a glTF file renders with `--shading pbr` by default (the same bytes as
   asking for it), and differently from `--shading lambert`; a built-in scene
   keeps its Lambert look by default;
 - the file's own light replaces the headlight: turning the light away
   darkens the image (without an environment);
 - the built-in neutral environment lights glTF files by default (`--env none`
   turns it off), `--env FILE.hdr` reads a Radiance panorama, and a file that
   is not one is refused in one line;
 - `--filter auto` (the default) honours the file's sampler filters under pbr
   (a nearest-filtered texture renders differently from a linear one);
   anisotropic filtering is off by default, and `--anisotropy 16` brings a
   grazing view closer to the supersampled reference;
   `--tonemap pbr-neutral` is accepted and changes a bright image;
 - KHR_materials_clearcoat on Khronos' ClearCoatTest (Debian's
   assimp-testmodels; skipped with a note when absent): `rast info` marks it
   honoured; the coat changes the image under the environment and under
   punctual light alone; a clearcoatFactor of 0 on every material draws the
   bytes of the file without the extension, both ways; a clearcoat texture
   index that does not exist is one clear error (the formulas themselves:
   tests/unit/test_clearcoat.cpp);
 - Serial and OpenMP builds agree (ids and depth identical, colours within 1/255)
   when both are given.
Standard library only."""
import base64
import json
import os
import shutil
import struct
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from cli_checks import Tally, cli_setup, one_line_error  # noqa: E402
import rastimg  # noqa: E402

args, env = cli_setup()
check = Tally()  # check(ok, what); check.failed counts the failures


def run(*a, exe=None):
    return subprocess.run([exe or args.rast] + list(a), capture_output=True, text=True, env=env, timeout=600)


def rgba_png(width, height, pixel):
    """A width x height RGBA PNG whose pixel (x, y) is pixel(x, y), 4 bytes."""
    import zlib
    rows = b"".join(b"\0" + b"".join(pixel(x, y) for x in range(width)) for y in range(height))
    def chunk(t, d):
        return struct.pack(">I", len(d)) + t + d + struct.pack(">I", zlib.crc32(t + d) & 0xffffffff)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def checker_png(size):
    # A size x size RGBA checkerboard of 2x2 cells.
    return rgba_png(size, size, lambda x, y: bytes((255, 255, 255, 255)) if ((x // 2) + (y // 2)) % 2
                    else bytes((0, 0, 255, 255)))


# A textured square facing +z, a sun shining along -z (onto it), a metal-ish material.
pos = struct.pack("<12f", -1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0)
nrm = struct.pack("<12f", 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1)
uv = struct.pack("<8f", 0, 1, 1, 1, 1, 0, 0, 0)
idx = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
blob = pos + nrm + uv + idx
image = checker_png(16)


# The square's mesh, accessors and buffer (blob), material 0 on it: the part
# of every glTF file of this test that is not its material or lights.
QUAD = {
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3,
                                "material": 0}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
                  {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
                  {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"},
                  {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                    {"buffer": 0, "byteOffset": 96, "byteLength": 32}, {"buffer": 0, "byteOffset": 128, "byteLength": 12}],
    "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," + base64.b64encode(blob).decode()}],
}


def write_doc(name, doc):
    path = os.path.join(args.workdir, name + ".gltf")
    with open(path, "w") as f:
        json.dump(doc, f)
    return path


def scene(name, sun_rotation=(0, 0, 0, 1), mag=9729, min_=9729, intensity=3.0):
    doc = {
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": intensity}]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"rotation": list(sun_rotation), "extensions": {"KHR_lights_punctual": {"light": 0}}}],
        "materials": [{"pbrMetallicRoughness": {"metallicFactor": 0.2, "roughnessFactor": 0.5,
                                                "baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": mag, "minFilter": min_}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(image).decode()}],
        **QUAD,
    }
    return write_doc(name, doc)


VIEW = ["--size", "96x96", "--eye", "0,0,3", "--target", "0,0,0", "--near", "0.1", "--far", "10"]


def render(path, *flags, exe=None, tag="x"):
    out = os.path.join(args.workdir, f"{os.path.basename(path)}_{tag}.png")
    r = run("render", path, "-o", out, *VIEW, *flags, exe=exe)
    check(r.returncode == 0, f"render {os.path.basename(path)} {' '.join(flags)} ({r.stderr.strip()[-200:]})")
    return open(out, "rb").read() if r.returncode == 0 else b"", out


lit = scene("lit")
default, _ = render(lit, tag="default")
pbr, _ = render(lit, "--shading", "pbr", tag="pbr")
lambert, _ = render(lit, "--shading", "lambert", tag="lambert")
check(default == pbr, "a glTF file renders with --shading pbr by default")
check(pbr != lambert, "pbr differs from lambert")

r = run("render", "builtin:tiny?n=16", "-o", os.path.join(args.workdir, "b1.png"), "--size", "64x64")
r2 = run("render", "builtin:tiny?n=16", "-o", os.path.join(args.workdir, "b2.png"), "--size", "64x64", "--shading", "lambert")
check(r.returncode == 0 and r2.returncode == 0 and open(os.path.join(args.workdir, "b1.png"), "rb").read() ==
      open(os.path.join(args.workdir, "b2.png"), "rb").read(), "a built-in scene keeps Lambert by default")


# The file's light: turned 90 degrees away (about x), the square goes dark.
_, lit_png = render(lit, "--env", "none", tag="litpng")
away = scene("away", sun_rotation=(0.7071068, 0, 0, 0.7071068))
_, away_png = render(away, "--env", "none", tag="awaypng")
away_env, _ = render(away, tag="awayenv")
check(away_env != open(away_png, "rb").read(), "the built-in environment lights the scene by default (--env none differs)")
hdr = os.path.join(args.shared, "envs", "qwantani_afternoon_puresky_1k.hdr") if args.shared else ""
if hdr and os.path.exists(hdr):
    garden, _ = render(away, "--env", hdr, tag="hdr")
    check(len(garden) > 0 and garden != away_env, "--env FILE.hdr lights with that panorama")
else:
    print("(no ../shared/envs: --env FILE.hdr is not tried)")
bad = os.path.join(args.workdir, "not.hdr")
with open(bad, "w") as f:
    f.write("hello\n")
r = run("render", away, "-o", os.path.join(args.workdir, "bad.png"), *VIEW, "--env", bad)
lines = r.stderr.strip().splitlines()
check(r.returncode != 0 and len(lines) == 1 and "hdr" in lines[0].lower(), f"a file that is not .hdr is refused in one line ({lines})")
p1 = rastimg.read_png(lit_png)[3]
p2 = rastimg.read_png(away_png)[3]
s1, s2 = sum(p1), sum(p2)
check(s2 < 0.5 * s1, f"the file's light lights the scene (sum {s1} lit, {s2} with the light turned away)")

# Sampler filters under --filter auto: nearest magnification is blocky, linear is smooth.
near = scene("near", mag=9728, min_=9728)
a, _ = render(near, tag="auto")
b, _ = render(lit, tag="auto_linear")
c, _ = render(near, "--filter", "bilinear", tag="forced")
check(a != b, "--filter auto honours the sampler's nearest filter")
check(c == b, "--filter bilinear overrides the sampler")

bright = scene("bright", intensity=40.0)
t0, _ = render(bright, tag="t0")
t1, _ = render(bright, "--tonemap", "pbr-neutral", tag="t1")
check(len(t1) > 0 and t0 != t1, "--tonemap pbr-neutral compresses a bright image")

# The debug views of the glTF shading (--shading basecolor|metalrough|
# occlusion|emissive|shading-normals): each shows one input, at the centre of
# a square whose material is known. Colours go through the sRGB curve, data
# is stored raw, as the normals view stores it.
def solid_png(rgba):
    return rgba_png(2, 2, lambda x, y: bytes(rgba))


def srgb(v):
    return round(rastimg.srgb(v))


vdoc = {
    "asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.3, 0.2, 1.0], "metallicFactor": 0.6,
                                            "roughnessFactor": 0.4},
                   "emissiveFactor": [0.1, 0.2, 0.3], "occlusionTexture": {"index": 0, "strength": 0.5}}],
    "textures": [{"source": 0}],
    "images": [{"uri": "data:image/png;base64," + base64.b64encode(solid_png((128, 0, 0, 255))).decode()}],
    **QUAD,
}
views_path = write_doc("views", vdoc)
ao = 1.0 + 0.5 * (128 / 255 - 1.0)
expect = {"basecolor": (srgb(0.8), srgb(0.3), srgb(0.2)), "metalrough": (0, round(0.4 * 255), round(0.6 * 255)),
          "occlusion": (round(ao * 255),) * 3, "emissive": (srgb(0.1), srgb(0.2), srgb(0.3)),
          "shading-normals": (128, 128, 255)}
_, lit_out = render(views_path, tag="view_pbr")
for view, want in expect.items():
    _, out = render(views_path, "--shading", view, tag="view_" + view)
    if not os.path.exists(out):
        continue
    w, h, _, px = rastimg.read_png(out)
    k = 4 * ((h // 2) * w + w // 2)
    got = tuple(px[k:k + 3])
    check(all(abs(g - e) <= 1 for g, e in zip(got, want)), f"--shading {view}: centre {got}, expected {want} (+-1)")
if os.path.exists(lit_out):
    w, h, _, px = rastimg.read_png(lit_out)
    k = 4 * ((h // 2) * w + w // 2)
    check(tuple(px[k:k + 3]) not in expect.values(), "--shading pbr is none of its views")

# Anisotropic filtering (--anisotropy, off by default): a checkered square
# seen at a grazing angle, its sampler trilinear (LINEAR_MIPMAP_LINEAR), unlit
# so that only the texture shows. Isotropic trilinear filtering takes the
# level of the footprint's longer side and blurs the checks across the
# shorter one too; 16 taps along the longer side keep them, closer to the
# supersampled reference (--reference: 16x16 samples a pixel, level 0).
grazing = scene("grazing_src", mag=9729, min_=9987)
adoc = json.load(open(grazing))
adoc["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_unlit", "KHR_texture_transform"]
adoc["materials"][0]["extensions"] = {"KHR_materials_unlit": {}}
adoc["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
    "KHR_texture_transform": {"scale": [6, 6]}}
aniso_path = write_doc("aniso", adoc)
GRAZE = ["--size", "96x96", "--eye", "0,-0.9,0.3", "--target", "0,1,0", "--up", "0,0,1", "--aa", "none"]


def graze(*flags, tag):
    out = os.path.join(args.workdir, f"aniso_{tag}.png")
    r = run("render", aniso_path, "-o", out, *GRAZE, *flags)
    check(r.returncode == 0, f"render aniso {tag} ({r.stderr.strip()[-200:]})")
    return out


ref = graze("--reference", tag="ref")
iso, a16, dflt = graze("--anisotropy", "1", tag="a1"), graze("--anisotropy", "16", tag="a16"), graze(tag="default")


def rmse(test):
    j = os.path.join(args.workdir, os.path.basename(test) + ".json")
    r = run("compare", ref, test, "--json", j)
    return json.load(open(j))["rmse_linear"] if r.returncode == 0 else float("nan")


e1, e16 = rmse(iso), rmse(a16)
check(open(dflt, "rb").read() == open(iso, "rb").read(), "anisotropic filtering is off by default (--anisotropy 1)")
check(e16 < 0.8 * e1, f"--anisotropy 16 is closer to the supersampled reference at a grazing angle "
      f"(RMSE {e16:.4f} against {e1:.4f} with 1)")


def clearcoat_checks():
    """KHR_materials_clearcoat on ClearCoatTest (see the top of the file)."""
    src_dir = os.path.join(args.assimp or "", "ClearCoat-glTF")
    src = os.path.join(src_dir, "ClearCoatTest.gltf")
    if not args.assimp or not os.path.exists(src):
        print("note: ClearCoat-glTF/ClearCoatTest.gltf absent (Debian's assimp-testmodels): clear coat checks skipped")
        return
    # The file's folder copied, so that edited copies find their buffers and images.
    work = os.path.join(args.workdir, "clearcoat")
    shutil.rmtree(work, ignore_errors=True)
    shutil.copytree(src_dir, work)
    doc = json.load(open(src))

    def coats(d):
        return [m["extensions"]["KHR_materials_clearcoat"] for m in d["materials"]
                if "KHR_materials_clearcoat" in m.get("extensions", {})]

    def variant(name, edit):
        d = json.loads(json.dumps(doc))
        edit(d)
        path = os.path.join(work, name + ".gltf")
        json.dump(d, open(path, "w"))
        return path

    def without(d):
        for m in d["materials"]:
            m.get("extensions", {}).pop("KHR_materials_clearcoat", None)
        d["extensionsUsed"] = [e for e in d.get("extensionsUsed", []) if e != "KHR_materials_clearcoat"]

    def zero(d):
        for c in coats(d):
            c["clearcoatFactor"] = 0.0

    def bad_index(d):
        coats(d)[0]["clearcoatTexture"] = {"index": 99}

    check(len(coats(doc)) == 6, f"ClearCoatTest has six coated materials ({len(coats(doc))})")
    files = {"coated": src, "without": variant("without", without), "zero": variant("zero", zero)}
    r = run("info", src)
    lines = [l for l in r.stdout.splitlines() if "KHR_materials_clearcoat" in l]
    check(r.returncode == 0 and len(lines) == 2 and all(l.rstrip().endswith("honoured") for l in lines),
          f"rast info marks KHR_materials_clearcoat honoured (material feature and extension used): {lines}")
    for light in (["--env", "none"], []):
        what = "punctual light (--env none)" if light else "the built-in environment"
        px = {}
        for k, f in files.items():
            pfm = os.path.join(args.workdir, f"clearcoat.{k}{'.none' if light else ''}.pfm")
            r = run("render", f, "--size", "240x180", "--aa", "none", *light, "-o", pfm)
            if check(r.returncode == 0, f"ClearCoatTest ({k}) renders under {what} ({r.stderr.strip()[-200:]})"):
                px[k] = rastimg.read_pfm(pfm)[3]
        if len(px) < 3:
            continue
        check(px["zero"] == px["without"], f"clearcoatFactor 0 draws the bytes of no extension under {what}")
        # (Under the headlight the coats show mostly at their rims and highlights: 511
        # values of 129600 change by more than 2/255 there, 2026-11-27; none without them.)
        changed = sum(abs(a - b) > 2 / 255 for a, b in zip(px["coated"], px["without"]))
        check(changed > 0.002 * len(px["coated"]),
              f"the coat changes the image under {what} ({changed} of {len(px['coated'])} values by more than 2/255)")
    r = subprocess.run([args.rast, "render", variant("bad", bad_index), "--size", "64x48", "-o",
                        os.path.join(args.workdir, "clearcoat_bad.png")], capture_output=True, env=env, timeout=600)
    problems = one_line_error(r, ["clearcoatTexture.index 99 does not exist"])
    check(not problems, f"a clearcoat texture index out of range is one clear error: {problems}")


clearcoat_checks()

serial = args.rast_serial
if serial:
    for path in (lit, near):
        outs = []
        for exe, tag in ((args.rast, "omp"), (serial, "serial")):
            base = os.path.join(args.workdir, f"par_{tag}_{os.path.basename(path)}")
            r = run("render", path, "-o", base + ".png", *VIEW, "--aov", f"primid={base}.bin", "--aov", f"depth={base}.pfm", exe=exe)
            check(r.returncode == 0, f"{tag} renders {os.path.basename(path)}")
            outs.append((open(base + ".bin", "rb").read(), open(base + ".pfm", "rb").read(), rastimg.read_png(base + ".png")[3]))
        same = outs[0][0] == outs[1][0] and outs[0][1] == outs[1][1]
        cdiff = max(abs(x - y) for x, y in zip(outs[0][2], outs[1][2]))
        check(same and cdiff <= 1, f"Serial and OpenMP: ids/depth {'identical' if same else 'DIFFER'}, max colour diff {cdiff}")
else:
    print("(no --rast-serial: the Serial comparison is skipped)")

print(f"{'FAILED' if check.failed else 'passed'}: {check.failed} failure(s)")
sys.exit(1 if check.failed else 0)


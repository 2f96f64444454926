#!/usr/bin/env python3
"""Writes the loader fuzzer's seed corpus (tests/fuzz/corpus): small glTF and
GLB files that reach the loader's main paths (embedded and external buffers,
GLB chunks, indices of each type, strips and fans, sparse accessors, strides,
node hierarchies, textures by URI and by bufferView), and what rast's own
exporter writes (with --rast PATH). Run it again after changing it; the
files are kept in the repository.

    make_seeds.py [--rast build/openmp/rast]"""
import base64
import json
import os
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import adversarial  # noqa: E402

out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")
os.makedirs(out, exist_ok=True)
TRI = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)


def data_uri(b):
    return "data:application/octet-stream;base64," + base64.b64encode(b).decode()


def doc(prims, buf, views, accessors, **extra):
    d = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
         "meshes": [{"primitives": prims}], "buffers": [buf], "bufferViews": views, "accessors": accessors}
    d.update(extra)
    return d


def save(name, d):
    with open(os.path.join(out, name), "wb") as f:
        f.write(json.dumps(d, separators=(",", ":")).encode())


def glb(name, d, binary):
    js = json.dumps(d, separators=(",", ":")).encode()
    js += b" " * (-len(js) % 4)
    binary += b"\0" * (-len(binary) % 4)
    total = 12 + 8 + len(js) + 8 + len(binary)
    with open(os.path.join(out, name), "wb") as f:
        f.write(struct.pack("<4sII", b"glTF", 2, total) + struct.pack("<I4s", len(js), b"JSON") + js +
                struct.pack("<I4s", len(binary), b"BIN\0") + binary)


pos = {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}
# 1. one triangle, buffer as a data: URI
save("triangle.gltf", doc([{"attributes": {"POSITION": 0}}], {"byteLength": 36, "uri": data_uri(TRI)},
                          [{"buffer": 0, "byteLength": 36}], [pos]))
# 2. external buffer a.bin (the harness writes 64 zero bytes beside the input)
save("external.gltf", doc([{"attributes": {"POSITION": 0}}], {"byteLength": 64, "uri": "a.bin"},
                          [{"buffer": 0, "byteLength": 36}], [pos]))
# 3. GLB with u16 indices, normals, colours and a strip and a fan
nrm = struct.pack("<9f", 0, 0, 1, 0, 0, 1, 0, 0, 1)
col = struct.pack("<12f", 1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1)
idx = struct.pack("<6H", 0, 1, 2, 2, 1, 0)
b = TRI + nrm + col + idx
glb("strip_fan.glb", doc(
    [{"attributes": {"POSITION": 0, "NORMAL": 1, "COLOR_0": 2}, "indices": 3, "mode": 5},
     {"attributes": {"POSITION": 0}, "indices": 3, "mode": 6},
     {"attributes": {"POSITION": 0}, "indices": 3, "mode": 4}],
    {"byteLength": len(b)},
    [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 36},
     {"buffer": 0, "byteOffset": 72, "byteLength": 48}, {"buffer": 0, "byteOffset": 120, "byteLength": 12}],
    [pos, {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"},
     {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC4"},
     {"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}]), b)
# 4. sparse accessor without a bufferView, u8 and u32 indices, byteStride
sp_idx = struct.pack("<3B", 0, 1, 2) + b"\0"
sp_val = TRI
u32 = struct.pack("<3I", 0, 1, 2)
strided = b"".join(struct.pack("<3f", *v) + b"\0" * 4 for v in [(0, 0, 0), (1, 0, 0), (0, 1, 0)])
b = sp_idx + sp_val + u32 + strided
save("sparse_stride.gltf", doc(
    [{"attributes": {"POSITION": 0}}, {"attributes": {"POSITION": 1}, "indices": 2}],
    {"byteLength": len(b), "uri": data_uri(b)},
    [{"buffer": 0, "byteOffset": 0, "byteLength": 3}, {"buffer": 0, "byteOffset": 4, "byteLength": 36},
     {"buffer": 0, "byteOffset": 40, "byteLength": 12}, {"buffer": 0, "byteOffset": 52, "byteLength": 48, "byteStride": 16}],
    [{"componentType": 5126, "count": 3, "type": "VEC3",
      "sparse": {"count": 3, "indices": {"bufferView": 0, "componentType": 5121}, "values": {"bufferView": 1}}},
     {"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3"},
     {"bufferView": 2, "componentType": 5125, "count": 3, "type": "SCALAR"}]))
# 5. node hierarchy with transforms, no scene (root nodes), a camera
d = doc([{"attributes": {"POSITION": 0}}], {"byteLength": 36, "uri": data_uri(TRI)},
        [{"buffer": 0, "byteLength": 36}], [pos])
del d["scene"], d["scenes"]
d["nodes"] = [{"children": [1, 2], "rotation": [0, 0.7071, 0, 0.7071]},
              {"mesh": 0, "translation": [1, 2, 3], "scale": [2, 2, 2]},
              {"mesh": 0, "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1]}]
d["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]
save("hierarchy.gltf", d)
# 6. texture by URI (a.png beside the input) with a sampler
with open(os.path.join(out, "textured.gltf"), "wb") as f:
    pass
adversarial.textured_triangle(out, "textured.gltf", "a.png")
t = json.load(open(os.path.join(out, "textured.gltf")))
t["samplers"] = [{"wrapS": 33071, "wrapT": 33648, "magFilter": 9729}]
t["textures"][0]["sampler"] = 0
save("textured.gltf", t)
# 7. GLB with the texture in a bufferView
png = adversarial._png(2, 2)
b = TRI + struct.pack("<6f", 0, 0, 1, 0, 0, 1) + png
glb("textured.glb", {
    "asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}],
    "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "baseColorFactor": [1, 1, 1, 1]}}],
    "textures": [{"source": 0}], "images": [{"bufferView": 2, "mimeType": "image/png"}],
    "buffers": [{"byteLength": len(b)}],
    "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 24},
                    {"buffer": 0, "byteOffset": 60, "byteLength": len(png)}],
    "accessors": [pos, {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}]}, b)


def glb_image(name, image):
    """A GLB whose texture is `image` in a bufferView (formats and truncation, issue 38)."""
    b = TRI + struct.pack("<6f", 0, 0, 1, 0, 0, 1) + image
    b += b"\0" * (-len(b) % 4)
    glb(name, {
        "asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}], "images": [{"bufferView": 2, "mimeType": "image/png"}],
        "buffers": [{"byteLength": len(b)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 24},
                        {"buffer": 0, "byteOffset": 60, "byteLength": len(image)}],
        "accessors": [pos, {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}]}, b)


# 8. images glTF does not allow, and cut ones: a PNM header without pixels,
#    a PSD header, a PNG without its IEND, a JPEG without its end (issue 38)
glb_image("image_pnm.glb", b"P6\n64 64\n255\n")
glb_image("image_psd.glb", b"8BPS\x00\x01" + bytes(6) + b"\x00\x03" + struct.pack(">II", 64, 64) + b"\x00\x08\x00\x03")
glb_image("image_png_cut.glb", png[:-12])
glb_image("image_jpeg_cut.glb", b"\xff\xd8\xff\xe0\x00\x10JFIF\x00\x01\x01\x00\x00\x01\x00\x01\x00\x00\xff\xda\x00\x08")
# 9. a data: buffer whose byteLength is wrong, and URIs with a bad escape and
#    naming the folder itself
save("datauri_length.gltf", doc([{"attributes": {"POSITION": 0}}], {"byteLength": 40, "uri": data_uri(TRI)},
                                [{"buffer": 0, "byteLength": 36}], [pos]))
d = doc([{"attributes": {"POSITION": 0}}], {"byteLength": 36, "uri": "%zz.bin"}, [{"buffer": 0, "byteLength": 36}], [pos])
d["buffers"].append({"byteLength": 4, "uri": "."})
d["images"] = [{"uri": "a%zzb.png"}]
save("uri_escapes.gltf", d)
# 10. cameras placed by nodes (perspective, orthographic), a light, and a
#     base-colour texture transform with a texCoord override (#37)
c = json.load(open(os.path.join(out, "textured.gltf")))
c["nodes"] += [{"camera": 0, "translation": [0, 0, 4]}, {"camera": 1, "rotation": [0.7071, 0, 0, 0.7071]},
               {"extensions": {"KHR_lights_punctual": {"light": 0}}}]
c["scenes"] = [{"nodes": [0, 1, 2, 3]}]
c["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 40, "aspectRatio": 1.5}},
                {"type": "orthographic", "name": "top", "orthographic": {"xmag": 2, "ymag": 1, "znear": 0, "zfar": 9}}]
c["extensionsUsed"] = ["KHR_texture_transform", "KHR_lights_punctual"]
c["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "spot", "spot": {"outerConeAngle": 0.5}}]}}
c["materials"][0]["pbrMetallicRoughness"]["baseColorTexture"]["extensions"] = {
    "KHR_texture_transform": {"offset": [0.5, 0.25], "rotation": 0.4, "scale": [2, 0.5], "texCoord": 0}}
save("cameras_transform.gltf", c)
# 13. the glTF material model and every light type (#37): factors, the four
#     other texture slots on one image, emissive strength, unlit, double-sided,
#     samplers with filters; a point light with a range, a directional one
m = json.load(open(os.path.join(out, "textured.gltf")))
m["nodes"] += [{"extensions": {"KHR_lights_punctual": {"light": 0}}, "translation": [0, 0, 2]},
               {"extensions": {"KHR_lights_punctual": {"light": 1}}, "rotation": [0.38, 0, 0, 0.92]}]
m["scenes"] = [{"nodes": [0, 1, 2]}]
m["extensionsUsed"] = ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_unlit"]
m["extensions"] = {"KHR_lights_punctual": {"lights": [{"type": "point", "intensity": 20, "range": 5, "color": [1, 0.5, 0.2]},
                                                      {"type": "directional", "intensity": 2}]}}
mat = m["materials"][0]
mat["pbrMetallicRoughness"].update({"metallicFactor": 0.3, "roughnessFactor": 0.6, "baseColorFactor": [1, 0.8, 0.6, 1],
                                    "metallicRoughnessTexture": {"index": 0}})
mat.update({"normalTexture": {"index": 0, "scale": 0.5}, "occlusionTexture": {"index": 0, "strength": 0.7},
            "emissiveTexture": {"index": 0}, "emissiveFactor": [0.2, 0.1, 0.0], "doubleSided": True,
            "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 4.0}}})
m["materials"].append({"extensions": {"KHR_materials_unlit": {}}, "alphaMode": "MASK", "alphaCutoff": 0.3})
m["samplers"] = [{"magFilter": 9728, "minFilter": 9986, "wrapS": 33648, "wrapT": 33071}]
for t in m["textures"]:
    t["sampler"] = 0
save("materials_lights.gltf", m)
# 11. what moves (#40): a triangle skinned to two joints, a morph target, and
#     animations of translation (LINEAR), rotation (STEP), scale (CUBICSPLINE)
#     and weights; then the same file broken in each way the loader refuses:
#     times not increasing, a NaN key, an output count that disagrees with the
#     input's, a joint index beyond the skin, a joint hierarchy with a cycle.
def animated(times=(0.0, 1.0), key=1.0, out_keys=2, joint=1, cycle=False):
    tri = TRI
    joints = struct.pack("<12B", 0, 0, 0, 0, joint, 0, 0, 0, 1, 0, 0, 0)
    weights = struct.pack("<12f", 1, 0, 0, 0, 1, 0, 0, 0, 0.5, 0.5, 0, 0)
    target = struct.pack("<9f", 0, -1, 0, 0, 0, 0, 0, 0, 0)
    target2 = struct.pack("<9f", 0, 0, 0, 0.5, 0.5, 0, 0, 0, 0)
    ibm = struct.pack("<32f", *([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1] * 2))
    tin = struct.pack(f"<{len(times)}f", *times)
    tr = struct.pack(f"<{3 * out_keys}f", *([0, 0, 0] + [key, 0, 0] * (out_keys - 1)))
    rot = struct.pack("<8f", 0, 0, 0, 1, 0, 0, 0.7071, 0.7071)
    sc = struct.pack("<18f", 0, 0, 0, 1, 1, 1, 0, 0, 0, 0, 0, 0, 2, 2, 2, 0, 0, 0)
    wt = struct.pack("<4f", 0, 0.5, 1, 0)  # two targets: a single-weight channel trips up viewers that unwrap it
    parts = [tri, joints, weights, target, ibm, tin, tr, rot, sc, wt, target2]
    views, off = [], 0
    for p in parts:
        views.append({"buffer": 0, "byteOffset": off, "byteLength": len(p)})
        off += len(p)
    acc = [pos, {"bufferView": 1, "componentType": 5121, "count": 3, "type": "VEC4"},
           {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC4"},
           {"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3"},
           {"bufferView": 4, "componentType": 5126, "count": 2, "type": "MAT4"},
           {"bufferView": 5, "componentType": 5126, "count": len(times), "type": "SCALAR"},
           {"bufferView": 6, "componentType": 5126, "count": out_keys, "type": "VEC3"},
           {"bufferView": 7, "componentType": 5126, "count": 2, "type": "VEC4"},
           {"bufferView": 8, "componentType": 5126, "count": 6, "type": "VEC3"},
           {"bufferView": 9, "componentType": 5126, "count": 4, "type": "SCALAR"},
           {"bufferView": 10, "componentType": 5126, "count": 3, "type": "VEC3"}]
    d = doc([{"attributes": {"POSITION": 0, "JOINTS_0": 1, "WEIGHTS_0": 2}, "targets": [{"POSITION": 3}, {"POSITION": 10}]}],
            {"byteLength": off, "uri": data_uri(b"".join(parts))}, views, acc)
    d["nodes"] = [{"mesh": 0, "skin": 0, "weights": [0.5, 0.25]}, {"children": [2]}, {"children": [1] if cycle else []},
                  {"children": [1]}]
    d["scenes"] = [{"nodes": [0, 3]}]
    d["skins"] = [{"joints": [1, 2], "inverseBindMatrices": 4}]
    d["animations"] = [{"name": "move", "samplers": [
        {"input": 5, "output": 6}, {"input": 5, "output": 7, "interpolation": "STEP"},
        {"input": 5, "output": 8, "interpolation": "CUBICSPLINE"}, {"input": 5, "output": 9}],
        "channels": [{"sampler": 0, "target": {"node": 2, "path": "translation"}},
                     {"sampler": 1, "target": {"node": 1, "path": "rotation"}},
                     {"sampler": 2, "target": {"node": 2, "path": "scale"}},
                     {"sampler": 3, "target": {"node": 0, "path": "weights"}}]}]
    return d


save("anim_skin_morph.gltf", animated())
save("anim_bad_times.gltf", animated(times=(1.0, 1.0)))
save("anim_bad_nan.gltf", animated(key=float("nan")))
save("anim_bad_count.gltf", animated(out_keys=3))
save("anim_bad_joint.gltf", animated(joint=7))
save("anim_bad_cycle.gltf", animated(cycle=True))
# 12. compressed geometry (#40, docs/compression.md): a 3x3 grid of 8 triangles
#     as EXT_meshopt_compression streams (with a fallback buffer holding no data)
#     and as a KHR_draco_mesh_compression stream, then broken: meshopt bytes
#     flipped, a Draco stream cut short, a fallback flag that is a number, a meshopt view claiming 2^28 vertices
#     (over a small budget, decoded size charged first). The streams were made by
#     Debian's libmeshoptimizer 0.18 and libdraco 1.5.5 encoders (as
#     tests/unit/test_compression.cpp makes its own).
MO_VERTS = "a00000010f3cc000ffffffffff0133cf00007e7d7e7d7e000001000c0000ff01030000007e000001003fc000ffffffff0100cf00007c7b7c0000000000000000000000000000000000000000000000000000000000000000"
MO_INDICES = "e0fe0ffe136f0f5f020f0801f304040104007687566778a9866589689801690000"
DRACO = ("445241434f02020101000000090800080200037fda07ff011101ff0000010009030000000000003f0000003f0000003e0000000000"
         "00003f000000000000000000000000000000000000003f00000000000000000000803f0000003f0000803e0000803f000000000000"
         "00000000803f0000803f0000003e0000003f0000803f0000803e000000000000803f00000000")


def meshopt_doc(vb, ib, count=9, fallback=True):
    vb, ib = bytes.fromhex(vb), bytes.fromhex(ib)
    pad = b"\0" * (-len(vb) % 4)
    blob = vb + pad + ib

    def ext(off, n, stride, cnt, mode):
        return {"EXT_meshopt_compression": {"buffer": 0, "byteOffset": off, "byteLength": n, "byteStride": stride,
                                            "count": cnt, "mode": mode}}
    return {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
            "extensionsUsed": ["EXT_meshopt_compression"], "extensionsRequired": ["EXT_meshopt_compression"],
            "buffers": [{"byteLength": len(blob), "uri": data_uri(blob)},
                        {"byteLength": count * 12 + 96, "extensions": {"EXT_meshopt_compression": {"fallback": fallback}}}],
            "bufferViews": [{"buffer": 1, "byteLength": count * 12, "byteStride": 12, "extensions": ext(0, len(vb), 12, count, "ATTRIBUTES")},
                            {"buffer": 1, "byteOffset": count * 12, "byteLength": 96,
                             "extensions": ext(len(vb) + len(pad), len(ib), 4, 24, "TRIANGLES")}],
            "accessors": [{"bufferView": 0, "componentType": 5126, "count": count, "type": "VEC3"},
                          {"bufferView": 1, "componentType": 5125, "count": 24, "type": "SCALAR"}]}


def draco_doc(stream):
    b = bytes.fromhex(stream)
    return {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
            "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "extensions": {
                "KHR_draco_mesh_compression": {"bufferView": 0, "attributes": {"POSITION": 0}}}}]}],
            "extensionsUsed": ["KHR_draco_mesh_compression"], "extensionsRequired": ["KHR_draco_mesh_compression"],
            "buffers": [{"byteLength": len(b), "uri": data_uri(b)}], "bufferViews": [{"buffer": 0, "byteLength": len(b)}],
            "accessors": [{"componentType": 5126, "count": 9, "type": "VEC3"},
                          {"componentType": 5125, "count": 24, "type": "SCALAR"}]}


save("meshopt_grid.gltf", meshopt_doc(MO_VERTS, MO_INDICES))
save("meshopt_bad_stream.gltf", meshopt_doc(MO_VERTS[:8] + "ff" * 40 + MO_VERTS[88:], MO_INDICES))
save("meshopt_bad_count.gltf", meshopt_doc(MO_VERTS, MO_INDICES, count=1 << 28))
save("meshopt_bad_fallback.gltf", meshopt_doc(MO_VERTS, MO_INDICES, fallback=1))
save("draco_grid.gltf", draco_doc(DRACO))
save("draco_bad_cut.gltf", draco_doc(DRACO[:len(DRACO) // 2]))

# 14. what rast's exporter writes for a scene that moves (#40, scenes/gltf_export_motion.cpp):
#     the built-in skinned models and the animated seed of section 11 through `rast export`
#     (GLB: nodes, a skin with JOINTS/WEIGHTS as the exporter writes them, morph targets,
#     LINEAR and CUBICSPLINE samplers). They need a rast executable: make_seeds.py --rast PATH;
#     without it the files already in the corpus are kept.
rast = sys.argv[sys.argv.index("--rast") + 1] if "--rast" in sys.argv else None
if rast:
    import subprocess
    for scene, name in (("builtin:skin-arm", "export_skin_arm.glb"), ("builtin:skin-tail", "export_skin_tail.glb"),
                        (os.path.join(out, "anim_skin_morph.gltf"), "export_anim_skin_morph.glb")):
        subprocess.run([rast, "export", scene, "-o", os.path.join(out, name)], check=True, stdout=subprocess.DEVNULL)
else:
    print("make_seeds: no --rast given: the exported seeds (export_*.glb) are kept as they are")
print(f"wrote {len(os.listdir(out))} seeds to {out}")

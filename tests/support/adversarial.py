"""Small files that claim a lot: the inputs of the memory-budget tests
(tests/cli/cli_security.py) and of scripts/measure/measure_memory.py. Each is generated
here, so nothing large is kept in the repository. Python standard library only."""
import base64
import json
import os
import struct
import zlib


def _gltf(doc):
    return json.dumps(doc, separators=(",", ":")).encode()


def tiny_counts(folder, primitives=4):
    """A ~400-byte glTF whose one accessor has no bufferView and claims 2^24
    vertices, drawn as a strip by several primitives (each loads it again)."""
    doc = {
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "mode": 5}] * primitives}],
        "accessors": [{"componentType": 5126, "count": 1 << 24, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 1]}],
    }
    p = os.path.join(folder, "tiny_counts.gltf")
    with open(p, "wb") as f:
        f.write(_gltf(doc))
    return p


def _png(width, height):
    """An RGBA8 PNG of zeros: deflate shrinks it about 1000:1."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)
    comp = zlib.compressobj(9)
    row = b"\0" * (1 + 4 * width)
    idat = b"".join(comp.compress(row) for _ in range(height)) + comp.flush()
    ihdr = struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", idat) + chunk(b"IEND", b"")


def textured_triangle(folder, name, image_uri):
    """One textured triangle whose image is `image_uri` (buffer as a data: URI)."""
    pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    uv = struct.pack("<6f", 0, 0, 1, 0, 0, 1)
    data = pos + uv
    doc = {
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": 0}]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}}}],
        "textures": [{"source": 0}],
        "images": [{"uri": image_uri}],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 24}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}],
    }
    p = os.path.join(folder, name)
    with open(p, "wb") as f:
        f.write(_gltf(doc))
    return p


def huge_png(folder, side=16384):
    """A PNG of about 1 MB (at 16384) that decodes to side x side RGBA texels,
    and a glTF that textures a triangle with it."""
    with open(os.path.join(folder, "huge.png"), "wb") as f:
        f.write(_png(side, side))
    return textured_triangle(folder, "huge_png.gltf", "huge.png")


def strip(folder, indices=20_000_000):
    """A GLB triangle strip of `indices` u8 indices over 3 vertices (20 MB at
    the default): one visible triangle, then degenerate ones."""
    pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    idx = bytes([0, 1, 2]) + bytes(indices - 3)
    idx += b"\0" * (-len(idx) % 4)
    binary = pos + idx
    doc = {
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 5}]}],
        "buffers": [{"byteLength": len(binary)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": indices}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5121, "count": indices, "type": "SCALAR"}],
    }
    js = _gltf(doc)
    js += b" " * (-len(js) % 4)
    total = 12 + 8 + len(js) + 8 + len(binary)
    glb = (struct.pack("<4sII", b"glTF", 2, total) + struct.pack("<I4s", len(js), b"JSON") + js +
           struct.pack("<I4s", len(binary), b"BIN\0") + binary)
    p = os.path.join(folder, "strip.glb")
    with open(p, "wb") as f:
        f.write(glb)
    return p


def far_triangle(folder, scale):
    """One triangle with vertices at +-scale (1e38: near float's limit)."""
    pos = struct.pack("<9f", -scale, 0, 0, scale, 0, 0, 0, scale, 0)
    doc = {
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
        "buffers": [{"byteLength": 36,
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(pos).decode()}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [-scale, 0, 0], "max": [scale, scale, 0]}],
    }
    p = os.path.join(folder, "far.gltf")
    with open(p, "wb") as f:
        f.write(_gltf(doc))
    return p


def triangle_scene(folder, name, image_uris=(), buffer_uri=None, byte_length=None, image_refs=None):
    """One triangle with texture coordinates. Its buffer is written beside the
    scene as `buffer_uri` (a data: URI when None; `byte_length` overrides the
    declared byteLength); each entry of `image_uris` is one glTF image, and the
    material uses image 0 (`image_refs`: the images the textures name, one
    material per texture, all drawn)."""
    pos = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    uv = struct.pack("<6f", 0, 0, 1, 0, 0, 1)
    data = pos + uv
    if buffer_uri is None:
        buf = {"byteLength": len(data) if byte_length is None else byte_length,
               "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}
    else:
        buf = {"byteLength": len(data) if byte_length is None else byte_length, "uri": buffer_uri}
        if "%" not in buffer_uri and not buffer_uri.startswith("/") and buffer_uri != ".":
            with open(os.path.join(folder, buffer_uri), "wb") as f:
                f.write(data)
    refs = list(image_refs) if image_refs is not None else ([0] if image_uris else [])
    doc = {
        "asset": {"version": "2.0"},
        "scenes": [{"nodes": list(range(max(1, len(refs))))}],
        "nodes": [{"mesh": i} for i in range(max(1, len(refs)))],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "material": i}]}
                   for i in range(max(1, len(refs)))],
        "buffers": [buf],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                        {"buffer": 0, "byteOffset": 36, "byteLength": 24}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                       "min": [0, 0, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"}],
    }
    if refs:
        doc["materials"] = [{"pbrMetallicRoughness": {"baseColorTexture": {"index": i}}} for i in range(len(refs))]
        doc["textures"] = [{"source": r} for r in refs]
        doc["images"] = [{"uri": u} for u in image_uris]
    else:
        doc["meshes"][0]["primitives"][0].pop("material")
    p = os.path.join(folder, name)
    with open(p, "wb") as f:
        f.write(_gltf(doc))
    return p


def png(width, height):
    """A valid RGBA8 PNG of zeros (see _png)."""
    return _png(width, height)

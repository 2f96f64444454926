#!/usr/bin/python3
"""Writes the normal-map probe of docs/gltf-support.md (#37): a square facing
+Z with a normal texture of ridges running along v (the normal tilts along
the tangent, +-45 degrees), lit by one directional light from +X, in two
files: OUT/tangent_file.gltf, whose TANGENT is (0, 1, 0, 1) at every vertex
(rotated 90 degrees from dP/du, so the ridges tilt along +-Y and the light
from +X sees them flat), and OUT/tangent_none.gltf, the same without TANGENT
(tangents generated: dP/du = +X, the ridges lit and shadowed). A renderer
that ignores a file's TANGENT draws the first as the second.

  scripts/measure/tangent_probe.py OUT
  scripts/measure/pbr_fidelity.py --rast build/openmp/rast --out F OUT/tangent_file.gltf OUT/tangent_none.gltf
"""
import base64
import json
import math
import os
import struct
import sys
import zlib


def png(width, height, rows):
    raw = b"".join(b"\0" + bytes(r) for r in rows)

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xffffffff)

    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    n = 64
    rows = []
    for y in range(n):
        row = []
        for x in range(n):
            a = math.radians(45) * math.sin(2 * math.pi * 4 * (x + 0.5) / n)  # 4 ridges across u
            t = (math.sin(a), 0.0, math.cos(a))
            row += [int(round((c * 0.5 + 0.5) * 255)) for c in t]
        rows.append(row)
    image = base64.b64encode(png(n, n, rows)).decode()
    pos = [-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0]
    nrm = [0, 0, 1] * 4
    uv = [0, 1, 1, 1, 1, 0, 0, 0]
    tan = [0, 1, 0, 1] * 4
    idx = [0, 1, 2, 0, 2, 3]
    for name, with_tangent in (("tangent_file", True), ("tangent_none", False)):
        blob = struct.pack("<12f", *pos) + struct.pack("<12f", *nrm) + struct.pack("<8f", *uv)
        blob += struct.pack("<16f", *tan) if with_tangent else b""
        idx_at = len(blob)
        blob += struct.pack("<6H", *idx) + b"\0\0"
        views = [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 48},
                 {"buffer": 0, "byteOffset": 96, "byteLength": 32}]
        acc = [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1, -1, 0], "max": [1, 1, 0]},
               {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"},
               {"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}]
        attrs = {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}
        if with_tangent:
            views.append({"buffer": 0, "byteOffset": 128, "byteLength": 64})
            acc.append({"bufferView": 3, "componentType": 5126, "count": 4, "type": "VEC4"})
            attrs["TANGENT"] = 3
        views.append({"buffer": 0, "byteOffset": idx_at, "byteLength": 12})
        acc.append({"bufferView": len(views) - 1, "componentType": 5123, "count": 6, "type": "SCALAR"})
        s, c = math.sin(math.pi / 8), math.cos(math.pi / 8)  # the light 45 degrees from +Z towards +X
        doc = {
            "asset": {"version": "2.0"},
            "extensionsUsed": ["KHR_lights_punctual"],
            "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 3.0}]}},
            "scene": 0, "scenes": [{"nodes": [0, 1]}],
            "nodes": [{"mesh": 0}, {"rotation": [0, s, 0, c], "extensions": {"KHR_lights_punctual": {"light": 0}}}],
            "meshes": [{"primitives": [{"attributes": attrs, "indices": len(acc) - 1, "material": 0}]}],
            "materials": [{"pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0,
                                                    "roughnessFactor": 0.7},
                           "normalTexture": {"index": 0}}],
            "textures": [{"source": 0}],
            "images": [{"uri": "data:image/png;base64," + image}],
            "buffers": [{"byteLength": len(blob), "uri": "data:application/octet-stream;base64," +
                         base64.b64encode(blob).decode()}],
            "bufferViews": views, "accessors": acc,
        }
        with open(os.path.join(out, name + ".gltf"), "w") as f:
            json.dump(doc, f)
    return 0


if __name__ == "__main__":
    sys.exit(main())

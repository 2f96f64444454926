#!/usr/bin/env python3
"""glTF files of transparent layers for comparing rast's BLEND methods with
the Khronos glTF Sample Renderer (issue #39, docs/transparency.md): the
built-in `builtin:layers` scenes are not exported with their BLEND materials
(rast export writes stress scenes with the neutral matte material), so this
writes the same kind of scene directly: an opaque red backdrop and n unlit
BLEND quads of mixed colours and alphas in front of it, each quad its own
node (the Sample Renderer sorts transparent primitives by their centre's
depth, as `--transparency sorted` does), parallel, or with neighbours tilted
opposite ways so that they intersect, or all at one depth (coplanar); and
the intersecting layers with an opaque grey quad drawn after them that cuts
through their right half (occluded: BLEND fragments behind opaque ones, whose
triangles come last, as under a sort-last split the last rank holds them).

  scripts/measure/blend_scenes.py OUT_DIR    # writes layers_{parallel,intersecting,coplanar,occluded}.gltf
  scripts/measure/blend_scenes.py OUT_DIR --full-screen
      # also fullscreen_{0,8_mixed,64_alpha0.1}.gltf: builtin:layers?n=0, ?n=8&mixed=1 and
      # ?n=64&alpha=0.1 (scenes/transparency_scenes.cpp) quad for quad, colour for colour,
      # for the camera FULL_SCREEN_CAMERA (the built-in scenes' camera)

Then scripts/measure/pbr_fidelity.py --extra-flags "--transparency sorted"
OUT_DIR/*.gltf compares rast with the reference, and scripts/measure/blend_vs_gl.py
times and compares rast with the hardware rasterizer's blending (glblend).
Standard library only.
"""
import base64
import json
import math
import os
import struct
import sys

HALF_W, HALF_H = 1.2, 0.9
COLOURS = [(0.1, 0.3, 1.0), (0.1, 1.0, 0.2), (1.0, 0.9, 0.1), (0.9, 0.2, 0.9), (0.1, 0.9, 0.9),
           (1.0, 0.5, 0.1), (0.5, 0.2, 1.0), (0.9, 0.9, 0.9)]


# builtin:layers' geometry (scenes/transparency_scenes.cpp): the plane z = 0 seen
# from (0, 0, 5) with fovy 45 spans about x in [-3.7, 3.7], y in [-2.07, 2.07].
FS_HALF_H = 2.0710678
FS_HALF_W = FS_HALF_H * 16.0 / 9.0
FULL_SCREEN_CAMERA = ["--eye", "0,0,5", "--target", "0,0,0", "--up", "0,1,0", "--fovy", "45", "--near", "0.1",
                      "--far", "100"]
FULL_SCREEN = [("fullscreen_0", 0, 0.5, False), ("fullscreen_8_mixed", 8, 0.5, True),
               ("fullscreen_64_alpha0.1", 64, 0.1, False)]


def scene(n, tilt, equal, full_screen=None, occluder=False):
    pos, idx, nodes, meshes, materials, accessors, views = [], [], [], [], [], [], []
    blob = bytearray()

    def quad(z0, slope, half_w, half_h, colour, alpha, blend, cx=0.0):
        # Four corners, z = z0 + slope * x (a tilt about the vertical axis), centred on x = cx.
        corners = [(cx - half_w, -half_h), (cx + half_w, -half_h), (cx + half_w, half_h), (cx - half_w, half_h)]
        p = b"".join(struct.pack("<3f", x, y, z0 + slope * x) for x, y in corners)
        i = struct.pack("<6H", 0, 1, 2, 0, 2, 3)
        zs = [z0 + slope * x for x, _ in corners]
        for data, count, kind, comp, extra in ((p, 4, "VEC3", 5126, {"min": [cx - half_w, -half_h, min(zs)],
                                                                         "max": [cx + half_w, half_h, max(zs)]}),
                                                (i, 6, "SCALAR", 5123, {})):
            while len(blob) % 4:
                blob.append(0)
            views.append({"buffer": 0, "byteOffset": len(blob), "byteLength": len(data)})
            blob.extend(data)
            accessors.append({"bufferView": len(views) - 1, "componentType": comp, "count": count, "type": kind,
                              **extra})
        materials.append({"pbrMetallicRoughness": {"baseColorFactor": [*colour, alpha]},
                          "alphaMode": "BLEND" if blend else "OPAQUE", "doubleSided": True,
                          "extensions": {"KHR_materials_unlit": {}}})
        meshes.append({"primitives": [{"attributes": {"POSITION": len(accessors) - 2}, "indices": len(accessors) - 1,
                                       "material": len(materials) - 1}]})
        nodes.append({"mesh": len(meshes) - 1})

    if full_screen is not None:  # builtin:layers?n=N&alpha=A[&mixed=1], submitted back to front
        alpha, mixed = full_screen
        quad(-1.0, 0.0, FS_HALF_W * 1.5, FS_HALF_H * 1.5, (1.0, 0.0, 0.0), 1.0, False)
        for k in range(n):
            layer = n - 1 - k  # layer 0 is the nearest
            colour = (0.0, 0.0, 1.0)
            a = alpha
            if mixed:
                h = 6.0 * layer / n
                colour = (abs(math.fmod(h, 2.0) - 1.0), (layer % 3) / 2.0, float(1 - layer % 2))
                a = 0.2 + 0.7 * math.fmod(layer * 0.618034, 1.0)
            f32 = lambda v: struct.unpack("<f", struct.pack("<f", v))[0]  # noqa: E731 (rast rounds to float)
            quad(-0.9 * layer / n, 0.0, FS_HALF_W * 1.2, FS_HALF_H * 1.2, tuple(f32(c) for c in colour), f32(a), True)
        n = 0
    else:
        quad(-1.0, 0.0, HALF_W * 1.5, HALF_H * 1.5, (1.0, 0.0, 0.0), 1.0, False)  # the backdrop
    for layer in range(n):  # back to front, as builtin:layers submits them
        z = 0.0 if equal else -0.9 * (n - 1 - layer) / n
        slope = (0.08 if layer % 2 else -0.08) if tilt else 0.0
        alpha = 0.3 + 0.5 * ((layer * 3) % 7) / 6.0
        quad(z, slope, HALF_W, HALF_H, COLOURS[layer % len(COLOURS)], alpha, True)
    if occluder:  # opaque, through the middle of the stack, tilted across it, over the right half
        quad(-0.45, 0.4, HALF_W * 0.6, HALF_H * 0.8, (0.5, 0.5, 0.5), 1.0, False, cx=HALF_W * 0.5)
    return {"asset": {"version": "2.0", "generator": "rast scripts/measure/blend_scenes.py"},
            "extensionsUsed": ["KHR_materials_unlit"], "scene": 0,
            "scenes": [{"nodes": list(range(len(nodes)))}], "nodes": nodes, "meshes": meshes,
            "materials": materials, "accessors": accessors, "bufferViews": views,
            "buffers": [{"byteLength": len(blob),
                         "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(blob)).decode()}]}


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "."
    os.makedirs(out, exist_ok=True)
    for name, n, tilt, equal in (("parallel", 8, False, False), ("intersecting", 8, True, False),
                                 ("coplanar", 6, False, True), ("occluded", 8, True, False)):
        path = os.path.join(out, f"layers_{name}.gltf")
        with open(path, "w") as f:
            json.dump(scene(n, tilt, equal, occluder=name == "occluded"), f)
        print(path)
    if "--full-screen" in sys.argv[2:]:
        for name, n, alpha, mixed in FULL_SCREEN:
            path = os.path.join(out, name + ".gltf")
            with open(path, "w") as f:
                json.dump(scene(n, False, False, (alpha, mixed)), f)
            print(path)


if __name__ == "__main__":
    main()

"""The glTF files of the feature probes as the golden test
(tests/cli/cli_probe_goldens.py) and the golden maker
(scripts/measure/make_probe_goldens.py) both need them: a .glb's JSON read and
written back (standard library only), and the KHR_texture_transform that
probe-transform's export gets (rast bakes transforms into coordinates at load,
so its scenes hold none to export), and each probe's controls: the properties
it shows, each with the edit of its file that removes it."""
import json
import struct


def read_glb(path):
    """(JSON document, binary chunk) of a .glb."""
    data = open(path, "rb").read()
    n = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20:20 + n].decode("utf-8"))
    rest = data[20 + n:]
    return doc, rest[8:8 + struct.unpack_from("<I", rest, 0)[0]]


def write_glb(path, doc, binary):
    js = json.dumps(doc).encode("utf-8")
    js += b" " * ((4 - len(js) % 4) % 4)
    b = binary + b"\0" * ((4 - len(binary) % 4) % 4)
    body = struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(b), 0x004E4942) + b
    open(path, "wb").write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)) + body)


# probe-transform's four squares: offset; rotation; scale; all three.
TRANSFORMS = [{"offset": [0.25, -0.5]}, {"rotation": 0.6}, {"scale": [2.0, 1.5]},
              {"offset": [0.1, 0.3], "rotation": -1.1, "scale": [0.7, 1.8]}]


def add_texture_transform(doc):
    """Gives probe-transform's materials their KHR_texture_transform (in place)."""
    for m, t in zip(doc["materials"], TRANSFORMS):
        m["pbrMetallicRoughness"]["baseColorTexture"].setdefault("extensions", {})["KHR_texture_transform"] = dict(t)
    used = doc.setdefault("extensionsUsed", [])
    if "KHR_texture_transform" not in used:
        used.append("KHR_texture_transform")


def probe_file(rast_export_glb, probe, out):
    """The file the probe's golden was made from: the export itself, or with its transforms for probe-transform."""
    doc, binary = read_glb(rast_export_glb)
    if probe == "transform":
        add_texture_transform(doc)
    write_glb(out, doc, binary)
    return out


# Controls: probe -> [(the property removed, the edit of the file's JSON that removes it)].
def materials(doc):
    return doc.get("materials", [])


def coats(doc):
    return [m["extensions"]["KHR_materials_clearcoat"] for m in materials(doc)
            if "KHR_materials_clearcoat" in m.get("extensions", {})]


def lights(doc):
    return doc["extensions"]["KHR_lights_punctual"]["lights"]


def set_all(items, key, value):
    for m in items:
        m[key] = value


def drop(items, key):
    for m in items:
        m.pop(key, None)


CONTROLS = {
    "spheres": [
        ("metallicFactor (all 0)", lambda d: set_all([m["pbrMetallicRoughness"] for m in materials(d)], "metallicFactor", 0.0)),
        ("roughnessFactor (all 0.6)", lambda d: set_all([m["pbrMetallicRoughness"] for m in materials(d)], "roughnessFactor", 0.6)),
    ],
    "normalmap": [
        ("normalTexture", lambda d: drop(materials(d), "normalTexture")),
        ("normalTexture.scale (all 1)", lambda d: set_all([m["normalTexture"] for m in materials(d)], "scale", 1.0)),
    ],
    "emissive": [
        ("emissiveFactor", lambda d: drop(materials(d), "emissiveFactor")),
        ("emissiveTexture", lambda d: drop(materials(d), "emissiveTexture")),
        ("KHR_materials_emissive_strength", lambda d: drop(materials(d), "extensions")),
    ],
    "mask": [
        ("alphaMode MASK (as OPAQUE)", lambda d: drop(materials(d), "alphaMode")),
        ("alphaCutoff (the default 0.5)", lambda d: drop(materials(d), "alphaCutoff")),
        ("single-sided culling (all doubleSided)", lambda d: set_all(materials(d), "doubleSided", True)),
        ("doubleSided (none)", lambda d: drop(materials(d), "doubleSided")),
    ],
    "wrap": [
        ("CLAMP_TO_EDGE (as REPEAT)", lambda d: [s.update(wrapS=10497 if s.get("wrapS") == 33071 else s.get("wrapS", 10497),
                                                           wrapT=10497 if s.get("wrapT") == 33071 else s.get("wrapT", 10497))
                                                  for s in d["samplers"]]),
        ("MIRRORED_REPEAT (as REPEAT)", lambda d: [s.update(wrapS=10497 if s.get("wrapS") == 33648 else s.get("wrapS", 10497),
                                                             wrapT=10497 if s.get("wrapT") == 33648 else s.get("wrapT", 10497))
                                                    for s in d["samplers"]]),
        ("magFilter LINEAR (as NEAREST)", lambda d: set_all(d["samplers"], "magFilter", 9728)),
    ],
    "transform": [
        ("KHR_texture_transform", lambda d: [m["pbrMetallicRoughness"]["baseColorTexture"].pop("extensions", None)
                                             for m in materials(d)]),
        ("texture rotation", lambda d: [m["pbrMetallicRoughness"]["baseColorTexture"]["extensions"]
                                        ["KHR_texture_transform"].pop("rotation", None) for m in materials(d)]),
    ],
    "clearcoat": [
        ("KHR_materials_clearcoat", lambda d: drop(materials(d), "extensions")),
        ("clearcoatTexture (coat 1 everywhere)", lambda d: drop(coats(d), "clearcoatTexture")),
        ("clearcoatNormalTexture", lambda d: drop(coats(d), "clearcoatNormalTexture")),
    ],
    "lights": [
        ("directional light (off)", lambda d: [l.update(intensity=0.0) for l in lights(d) if l["type"] == "directional"]),
        ("point light range", lambda d: drop(lights(d), "range")),
        ("spot cone angles (the defaults)", lambda d: [l.update(spot={"innerConeAngle": 0.0, "outerConeAngle": 0.7853981634})
                                                       for l in lights(d) if l["type"] == "spot"]),
        ("spot light (as a point light)", lambda d: [l.update(type="point") for l in lights(d) if l["type"] == "spot"]),
    ],
}


def read_pfm(path):
    """A PFM's pixels as a numpy array [height, width, channels], top row
    first (the measurement scripts' reader; numpy imported here only)."""
    import numpy as np
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = (int(x) for x in f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    return data.reshape(h, w, 3 if kind == b"PF" else 1)[::-1]

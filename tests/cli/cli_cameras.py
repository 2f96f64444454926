#!/usr/bin/env python3
"""glTF cameras and `rast info SCENE` from the command line (#37):

 - `rast info FILE` lists the file's cameras (index, name, projection), its
   lights, material features and extensions, each marked honoured or ignored;
 - `rast render FILE --camera N|NAME` renders through that camera and prints
   it as flags; rendering with those flags gives the same bytes;
 - bad choices (an index out of range, an unknown name, --camera with --eye,
   --ssao with an orthographic camera) end in one line and exit 1.
Standard library only."""
import base64
import json
import re
import os
import struct
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from cli_checks import Tally, cli_setup  # noqa: E402

args, env = cli_setup()
check = Tally()  # check(ok, what); check.failed counts the failures


def run(*a):
    return subprocess.run([args.rast] + list(a), capture_output=True, text=True, env=env, timeout=600)


# Two triangles, a perspective camera ("front", on its node) and an
# orthographic one ("top"), a directional light and a MASK material.
pos = struct.pack("<18f", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, -1, 1, 0, -1, 0, 1, -1)
doc = {
    "asset": {"version": "2.0"},
    "extensionsUsed": ["KHR_lights_punctual"],
    "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 3.0}]}},
    "scene": 0,
    "scenes": [{"nodes": [0, 1, 2, 3]}],
    "nodes": [{"mesh": 0},
              {"camera": 0, "name": "front", "translation": [0.3, 0.3, 4.0]},
              {"camera": 1, "translation": [0.3, 0.3, 5.0]},
              {"extensions": {"KHR_lights_punctual": {"light": 0}}}],
    "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "znear": 0.1, "zfar": 50.0}},
                {"type": "orthographic", "name": "top",
                 "orthographic": {"xmag": 1.0, "ymag": 1.0, "znear": 0.0, "zfar": 20.0}}],
    "materials": [{"alphaMode": "MASK", "doubleSided": True}],
    "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
    "accessors": [{"bufferView": 0, "componentType": 5126, "count": 6, "type": "VEC3",
                   "min": [0, 0, -1], "max": [1, 1, 0]}],
    "bufferViews": [{"buffer": 0, "byteLength": len(pos)}],
    "buffers": [{"byteLength": len(pos), "uri": "data:application/octet-stream;base64," + base64.b64encode(pos).decode()}],
}
scene = os.path.join(args.workdir, "cameras.gltf")
with open(scene, "w") as f:
    json.dump(doc, f)

r = run("info", scene)
check(r.returncode == 0, f"rast info SCENE exits 0 ({r.stderr.strip()})")
out = r.stdout
check("cameras: 2" in out, "info counts the cameras")
check("0 'front': perspective yfov 34.3775 deg" in out, "info lists camera 0 with its projection")
check("1 'top': orthographic xmag 1 ymag 1" in out, "info lists camera 1 by name")
check("1 declared (1 directional, 0 point, 0 spot), placed by 1 nodes" in out, "info counts the lights")
check("alphaMode MASK" in out and "doubleSided" in out, "info lists the material features used")
check("honoured by --shading pbr" in out, "info says the lights are honoured (--shading pbr)")
check(re.search(r"alphaMode MASK\s+1 material: honoured", out) is not None, "info marks alphaMode MASK honoured")

for spec in ("0", "front", "top"):
    png = os.path.join(args.workdir, f"cam_{spec}.png")
    r = run("render", scene, "--camera", spec, "--size", "160x120", "-o", png)
    check(r.returncode == 0, f"--camera {spec} renders ({r.stderr.strip()})")
    line = [l for l in r.stdout.splitlines() if l.startswith("rast: camera (file camera")]
    check(len(line) == 1, f"--camera {spec} prints the camera as flags")
    if r.returncode or not line:
        continue
    flags = line[0].split(") ", 1)[1].split()
    check(("--ortho" in flags) == (spec == "top"), f"--camera {spec}: --ortho exactly for the orthographic camera")
    again = os.path.join(args.workdir, f"flags_{spec}.png")
    r2 = run("render", scene, "--size", "160x120", "-o", again, *flags)
    same = r2.returncode == 0 and open(png, "rb").read() == open(again, "rb").read()
    check(same, f"--camera {spec} and its printed flags give the same image ({r2.stderr.strip()})")

for bad, expect in ((["--camera", "2"], "the scene has 2 cameras (0..1)"),
                    (["--camera", "side"], "no camera named 'side'"),
                    (["--camera", "0", "--eye", "1,2,3"], "--camera sets the view"),
                    (["--camera", "top", "--ssao"], "--ssao needs a perspective camera"),
                    (["--ortho", "-1"], "--ortho must be a positive half height")):
    r = run("render", scene, "--size", "64x48", "-o", os.path.join(args.workdir, "bad.png"), *bad)
    err = r.stderr.strip()
    check(r.returncode == 1 and expect in err and len(err.splitlines()) == 1,
          f"{' '.join(bad)}: one line, exit 1 ({err})")
r = run("render", "builtin:default", "--camera", "0", "-o", os.path.join(args.workdir, "bad.png"))
check(r.returncode == 1 and "has no cameras" in r.stderr, "--camera on a scene without cameras: one line")

print(f"{'FAILED' if check.failed else 'all passed'}: {check.failed} failing")
sys.exit(1 if check.failed else 0)

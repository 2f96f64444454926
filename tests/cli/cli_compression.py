#!/usr/bin/env python3
"""Compressed glTF from the command line (#40, docs/compression.md): the fuzz corpus' meshopt and
Draco seeds render, their broken twins end in one line; Debian's 2CylinderEngine
with Draco covers the same pixels as the uncompressed .glb from the same camera (coverage IoU of
the primitive-id images at least 0.995), `rast info` marks the compression extensions honoured,
and a Draco file whose stream is cut ends in one line. Skips (77) without assimp-testmodels.
Standard library only."""
import json
import os
import shutil
import struct
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from cli_checks import Tally, cli_setup  # noqa: E402

args, env = cli_setup()
check = Tally()  # check(ok, what); check.failed counts the failures
draco = os.path.join(args.assimp, "draco", "2CylinderEngine.gltf")
glb = os.path.join(args.assimp, "2CylinderEngine-glTF-Binary", "2CylinderEngine.glb")


def run(*a):
    return subprocess.run([args.rast] + list(a), capture_output=True, text=True, env=env, timeout=600)


# The fuzz corpus' compressed seeds (tests/fuzz/make_seeds.py, section 12).
corpus = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fuzz", "corpus")
for seed, expect in (("meshopt_grid", None), ("draco_grid", None),
                     ("meshopt_bad_stream", "EXT_meshopt_compression: the compressed stream is corrupt"),
                     ("meshopt_bad_count", "over the memory budget"),
                     ("draco_bad_cut", "KHR_draco_mesh_compression: the compressed stream is corrupt")):
    r = run("render", os.path.join(corpus, seed + ".gltf"), "--size", "64x48", "--max-memory", "256M",
            "-o", os.path.join(args.workdir, seed + ".png"))
    err = r.stderr.strip()
    if expect is None:
        check(r.returncode == 0 and "8 triangles" in r.stdout, f"{seed}: renders its 8 triangles ({err})")
    else:
        check(r.returncode == 1 and expect in err and len(err.splitlines()) == 1, f"{seed}: one line ({err[:160]})")

if not (os.path.exists(draco) and os.path.exists(glb)):
    print(f"SKIPPED: no {draco} or {glb} (apt-get install assimp-testmodels)")
    sys.exit(1 if check.failed else 77)


def coverage(path):
    with open(path, "rb") as f:
        data = f.read()
    head, _, body = data.partition(b"\n")
    w, h = int(head.split()[1]), int(head.split()[2])
    ids = struct.unpack(f"<{w * h}I", body[:4 * w * h])
    return [i != 0 for i in ids]


r = run("render", glb, "--size", "320x200", "-o", os.path.join(args.workdir, "glb.png"),
        "--aov", "primid=" + os.path.join(args.workdir, "glb.bin"))
check(r.returncode == 0, f"the uncompressed engine renders ({r.stderr.strip()})")
flags = r.stdout.split("camera (auto) ")[1].split("\n")[0].split() if "camera (auto) " in r.stdout else []
r = run("render", draco, "--size", "320x200", "-o", os.path.join(args.workdir, "draco.png"),
        "--aov", "primid=" + os.path.join(args.workdir, "draco.bin"), *flags)
check(r.returncode == 0, f"the Draco engine renders from the same camera ({r.stderr.strip()})")
if not check.failed:
    a, b = coverage(os.path.join(args.workdir, "glb.bin")), coverage(os.path.join(args.workdir, "draco.bin"))
    both = sum(x and y for x, y in zip(a, b))
    either = sum(x or y for x, y in zip(a, b))
    iou = both / max(1, either)
    check(iou >= 0.995 and either > 1000, f"coverage IoU {iou:.4f} over {either} pixels (at least 0.995)")

r = run("info", draco)
check(r.returncode == 0 and "KHR_draco_mesh_compression" in r.stdout and "honoured" in r.stdout.split("KHR_draco_mesh_compression")[1][:60],
      "rast info marks KHR_draco_mesh_compression honoured")

# The Draco file with its binary cut in half: one line, no crash.
bad = os.path.join(args.workdir, "cut")
os.makedirs(bad, exist_ok=True)
doc = json.load(open(draco))
binary = open(os.path.join(os.path.dirname(draco), doc["buffers"][0]["uri"]), "rb").read()
cut = bytearray(binary)
for v in doc["bufferViews"]:
    o = v.get("byteOffset", 0)
    cut[o + v["byteLength"] // 2:o + v["byteLength"]] = b"\x07" * (v["byteLength"] - v["byteLength"] // 2)
open(os.path.join(bad, doc["buffers"][0]["uri"]), "wb").write(bytes(cut))
shutil.copy(draco, os.path.join(bad, "engine.gltf"))
r = run("render", os.path.join(bad, "engine.gltf"), "--size", "64x48", "-o", os.path.join(args.workdir, "bad.png"))
err = r.stderr.strip()
check(r.returncode == 1 and "KHR_draco_mesh_compression" in err and len(err.splitlines()) == 1,
      f"a corrupt Draco stream: one line ({err[:200]})")

print(f"{'FAILED' if check.failed else 'all passed'}: {check.failed} failing")
sys.exit(1 if check.failed else 0)

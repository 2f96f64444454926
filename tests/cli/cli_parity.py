#!/usr/bin/env python3
"""Backend and method parity: the same scene gives bit-identical primitive ids
and depth on every backend (the OpenMP rast and its Serial twin) and with every
raster method, and colours within 1/255; repeated runs are identical.
Exit 77 (skipped) when the Serial twin was not built."""
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import rastimg  # noqa: E402
from skip import skip
from script_args import arg_parser  # noqa: E402

ap = arg_parser()
ap.add_argument("--size", default="320x240")
ap.add_argument("--methods", default="")
args = ap.parse_args()
os.makedirs(args.workdir, exist_ok=True)

scenes = ["", "builtin:default", "builtin:bigtri", "builtin:tiny?n=20000", "builtin:overdraw?layers=64",
          "builtin:slivers", "builtin:nearplane", "builtin:degenerate", "builtin:extreme?scale=1e6", "builtin:zfight",
          # points and lines (docs/points-lines.md); "SCENE|FLAGS" adds render flags
          "builtin:lines?n=20000", "builtin:lines?n=5000|--line-width|2.5", "builtin:points?n=20000|--point-size|3",
          "builtin:default|--polygon|line", "builtin:default|--polygon|point|--point-size|2",
          "builtin:default|--hidden-line", "builtin:nearplane|--wireframe|--aa|msaa4"]
if args.assimp and os.path.isdir(args.assimp):
    for rel in ["BoxTextured-glTF-Binary/BoxTextured.glb", "2CylinderEngine-glTF-Binary/2CylinderEngine.glb"]:
        p = os.path.join(args.assimp, rel)
        if os.path.exists(p):
            scenes.append(p)
if args.shared and os.path.isdir(os.path.join(args.shared, "models")):
    for m in ["duck.glb", "cow.glb", "milktruck.glb", "engine.glb", "checkerboard.glb"]:
        p = os.path.join(args.shared, "models", m)
        if os.path.exists(p):
            scenes.append(p)
else:
    print("note: ../shared absent: parity runs on the built-in and Debian scenes only")

methods = args.methods.split(",") if args.methods else \
    subprocess.run([args.rast, "info"], capture_output=True, text=True, check=True).stdout.split(
        "raster methods:")[1].split("\n")[0].split()
exes = [("openmp", args.rast)]
if args.rast_serial:
    exes.append(("serial", args.rast_serial))
else:
    skip(args.workdir, "no Serial twin built (RAST_SERIAL_TWIN off or Kokkos without Serial)")


def render(exe, scene, method, tag):
    base = os.path.join(args.workdir, tag)
    scene, *flags = scene.split("|")
    cmd = [exe, "render"] + ([scene] if scene else []) + flags + [
        "--size", args.size, "--raster", method, "-o", base + ".png",
        "--aov", f"primid={base}.ids,depth={base}.pfm"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    if r.returncode != 0:
        raise SystemExit(f"FAILED: {' '.join(cmd)}: {r.stderr.strip()}")
    with open(base + ".ids", "rb") as f:
        ids = f.read()
    with open(base + ".pfm", "rb") as f:
        depth = f.read()
    return ids, depth, rastimg.read_png(base + ".png")[3]


passed = failed = 0
for si, scene in enumerate(scenes):
    ref = None
    for name, exe in exes:
        for m in methods:
            # The first configuration runs twice: repeated runs must be identical too.
            for rep in range(2 if (name == exes[0][0] and m == methods[0]) else 1):
                got = render(exe, scene, m, f"s{si}_{name}_{m}_{rep}")
                label = f"{scene or '(default)'} {name} {m}"
                if ref is None:
                    ref = (got, label)
                    continue
                ok = got[0] == ref[0][0] and got[1] == ref[0][1]
                cdiff = max(abs(a - b) for a, b in zip(got[2], ref[0][2]))
                ok = ok and cdiff <= 1
                print(f"{'ok  ' if ok else 'FAIL'} {label} vs {ref[1]}: ids/depth "
                      f"{'identical' if got[0] == ref[0][0] and got[1] == ref[0][1] else 'DIFFER'}, "
                      f"max colour diff {cdiff}")
                passed += ok
                failed += not ok
# The post chain (exposure, bloom, SSAO, ACES): Serial and OpenMP within 1/255,
# and repeated runs identical.
post = ["--exposure", "0.5", "--bloom=0.6,0.8,12", "--ssao", "--tonemap", "aces"]
for si, scene in enumerate(s for s in scenes if s in ("", "builtin:overdraw?layers=64") or s.endswith(
        ("duck.glb", "engine.glb", "2CylinderEngine.glb"))):
    outs = []
    for name, exe in exes + [exes[0]]:
        base = os.path.join(args.workdir, f"post{si}_{name}_{len(outs)}")
        cmd = [exe, "render"] + ([scene] if scene else []) + ["--size", args.size, "-o", base + ".png"] + post
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
        if r.returncode != 0:
            raise SystemExit(f"FAILED: {' '.join(cmd)}: {r.stderr.strip()}")
        outs.append((name, rastimg.read_png(base + ".png")[3]))
    cdiff = max(abs(a - b) for a, b in zip(outs[0][1], outs[1][1]))
    ok = cdiff <= 1 and outs[0][1] == outs[2][1]
    print(f"{'ok  ' if ok else 'FAIL'} post chain {scene or '(default)'}: serial vs openmp max colour diff {cdiff}, "
          f"repeat {'identical' if outs[0][1] == outs[2][1] else 'DIFFERS'}")
    passed += ok
    failed += not ok
print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)

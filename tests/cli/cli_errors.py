#!/usr/bin/env python3
"""Bad input ends in one clear line on stderr and a non-zero exit: never a crash,
a hang or a partial image.

Each case runs `rast render ... -o OUT.png` (OUT.png deleted first) and checks:
exit status != 0, stderr exactly one non-empty line starting with
"rast: error:" (and holding the expected words), OUT.png not created, and the
run finished within 60 s. One good render checks the opposite. Python standard
library only."""
import os
import shutil
import struct
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from script_args import arg_parser  # noqa: E402

args = arg_parser().parse_args()

TIMEOUT_S = 60
work = os.path.abspath(args.workdir)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
out_png = os.path.join(work, "out.png")
env = dict(os.environ)
env.setdefault("OMP_PROC_BIND", "false")  # else Kokkos prints OpenMP advice on stderr

# Malformed or unsupported files of assimp-testmodels' glTF2 folder, with words
# their error must contain (the same outcomes as tests/unit/test_loader.cpp's table).
ASSIMP_BAD = {
    "BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf": "requires extension KHR_technique_webgl",
    "BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb": "non-finite",
    "IndexOutOfRange/IndexOutOfRange.gltf": "out of range",
    "IndexOutOfRange/AllIndicesOutOfRange.gltf": "out of range",
    "MissingBin/BoxTextured.gltf": "BoxTextured0.bin' is missing",
    "RecursiveNodes/RecursiveNodes.gltf": "cycle",
    "SchemaFailures/sceneWrongType.gltf": "scene: expected an index",
    "TestNoRootNode/NoScene.gltf": "no triangles, lines or points to draw",
    "TestNoRootNode/SceneWithoutNodes.gltf": "no triangles, lines or points to draw",
    "issue_3269/texcoord_crash.gltf": "TEXCOORD_0",
    "wrongTypes/badArray.gltf": "primitives: expected an array",
    "wrongTypes/badExtension.gltf": "KHR_texture_transform: expected an object",
    "wrongTypes/badNumber.gltf": "scale: expected a number",
    "wrongTypes/badObject.gltf": "pbrMetallicRoughness: expected an object",
    "wrongTypes/badString.gltf": "name: expected a string",
    "wrongTypes/badUint.gltf": "index: expected an index",
}
# (Mesh_PrimitiveMode_00..03 and 07..10, points and lines, load and render
# since issue 14: tests/pipeline/test_lines_points.cpp.)

# Cases that fail because of code outside this test's reach, reported but not
# counted until fixed (then this script says so: remove them from here).
KNOWN_ISSUES = set()  # cases that fail for a reason outside the loader; none now

passed = failed = known = 0


def run(cmd):
    try:
        r = subprocess.run(cmd, capture_output=True, timeout=TIMEOUT_S, env=env)
    except subprocess.TimeoutExpired:
        return None
    return r


def report(name, problems):
    global passed, failed, known
    if name in KNOWN_ISSUES:
        if problems:
            known += 1
            print(f"KNOWN   {name}: {'; '.join(problems)}")
        else:
            passed += 1
            print(f"ok      {name} (listed in KNOWN_ISSUES but passes: remove it from there)")
        return
    if problems:
        failed += 1
        print(f"FAIL    {name}: {'; '.join(problems)}")
    else:
        passed += 1
        print(f"ok      {name}")


def expect_error(name, argv, words="", outputs=()):
    """rast ARGV must fail with one 'rast: error:' line holding WORDS and leave
    out.png (and OUTPUTS) uncreated."""
    files = [out_png] + list(outputs)
    for f in files:
        if os.path.exists(f):
            os.remove(f)
    cmd = [args.rast] + argv
    r = run(cmd)
    problems = []
    if r is None:
        report(name, [f"did not finish within {TIMEOUT_S} s: {' '.join(cmd)}"])
        return
    err = r.stderr.decode("utf-8", "replace")
    lines = err.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    if r.returncode == 0:
        problems.append("exit status 0")
    elif r.returncode < 0:
        problems.append(f"killed by signal {-r.returncode}")
    if len(lines) != 1 or not err.endswith("\n"):
        problems.append(f"stderr is {len(lines)} lines, not one: {err!r}")
    elif not lines[0].startswith("rast: error: ") or len(lines[0]) <= len("rast: error: "):
        problems.append(f"stderr does not start with 'rast: error: ': {lines[0]!r}")
    elif words and words not in lines[0]:
        problems.append(f"stderr lacks {words!r}: {lines[0]!r}")
    for f in files:
        if os.path.exists(f):
            problems.append(f"{os.path.basename(f)} was created")
    report(name, problems)


def render_args(scene, *extra):
    return ["render"] + ([scene] if scene else []) + ["--size", "64x48", "-o", out_png] + list(extra)


def write(name, data):
    p = os.path.join(work, name)
    with open(p, "wb") as f:
        f.write(data)
    return p


# ---------------------------------------------------------------- files
good = ""
if args.assimp and os.path.isdir(args.assimp):
    good = os.path.join(args.assimp, "BoxTextured-glTF-Binary", "BoxTextured.glb")

expect_error("missing file", render_args(os.path.join(work, "no-such-file.gltf")), "No such file")
os.makedirs(os.path.join(work, "adir.gltf"), exist_ok=True)
expect_error("directory as scene", render_args(os.path.join(work, "adir.gltf")), "is a directory")
expect_error("empty file", render_args(write("empty.gltf", b"")), "is empty")
expect_error("garbage bytes", render_args(write("garbage.gltf", bytes(range(256)) * 8)), "invalid JSON")
expect_error("garbage .glb", render_args(write("garbage.glb", b"glTF" + bytes(range(256)) * 8)), "GLB")
expect_error("JSON that is not glTF", render_args(write("notgltf.gltf", b'{"hello": [1, 2, 3]}')), "asset")
expect_error("deeply nested JSON",
             render_args(write("deep.gltf", b'{"asset":{"version":"2.0"},"extras":' + b"[" * 200000 + b"]" * 200000 + b"}")),
             "nested deeper")
expect_error("unknown builtin scene", render_args("builtin:no-such-scene"), "unknown builtin scene")

if good and os.path.exists(good):
    with open(good, "rb") as f:
        glb = f.read()
    expect_error("truncated .glb (half)", render_args(write("half.glb", glb[: len(glb) // 2])), "truncated GLB")
    expect_error("truncated .glb (header only)", render_args(write("header.glb", glb[:16])), "truncated GLB")
    expect_error("truncated .glb (JSON cut)", render_args(write("jsoncut.glb", glb[:200])), "truncated GLB")
    # A BIN chunk length that reaches past the end of the file.
    json_len = struct.unpack_from("<I", glb, 12)[0]
    bad = bytearray(glb)
    struct.pack_into("<I", bad, 20 + json_len, 0x7FFFFF00)
    expect_error(".glb with a lying BIN chunk length", render_args(write("lying.glb", bytes(bad))), "BIN chunk")

    for rel, words in sorted(ASSIMP_BAD.items()):
        p = os.path.join(args.assimp, rel)
        if not os.path.exists(p):
            report(f"assimp {rel}", ["file missing from assimp-testmodels"])
            continue
        expect_error(f"assimp {rel}", render_args(p), words)

    # Unreadable textures: BoxTextured.gltf beside its buffer, with the PNG
    # replaced by garbage, by nothing, by an absurd size.
    src = os.path.join(args.assimp, "BoxTextured-glTF")
    for case, png in [("corrupt", b"\x89PNG\r\n\x1a\n" + b"not a png" * 10), ("missing", None),
                      ("absurd size", b"\x89PNG\r\n\x1a\n" + struct.pack(">I", 13) + b"IHDR" +
                       struct.pack(">II", 20000, 10000) + bytes([8, 6, 0, 0, 0]) + b"\0\0\0\0"),
                      ("a directory", "dir")]:
        d = os.path.join(work, "tex_" + case.replace(" ", "_"))
        os.makedirs(d, exist_ok=True)
        shutil.copy(os.path.join(src, "BoxTextured.gltf"), d)
        shutil.copy(os.path.join(src, "BoxTextured0.bin"), d)
        tex = os.path.join(d, "CesiumLogoFlat.png")
        if png == "dir":
            os.makedirs(tex, exist_ok=True)
        elif png is not None:
            with open(tex, "wb") as f:
                f.write(png)
        expect_error(f"texture: {case}", render_args(os.path.join(d, "BoxTextured.gltf")), "image")
else:
    print("note: assimp-testmodels absent: the file cases run on synthetic files only")

# ---------------------------------------------------------------- options
scene = good if good and os.path.exists(good) else ""  # "" = the embedded default scene
expect_error("--size 0x0", ["render", scene, "--size", "0x0", "-o", out_png], "--size")
expect_error("--size 100000x100000", ["render", scene, "--size", "100000x100000", "-o", out_png], "--size")
expect_error("--size abc", ["render", scene, "--size", "abc", "-o", out_png], "--size")
expect_error("--size -5x10", ["render", scene, "--size", "-5x10", "-o", out_png], "--size")
expect_error("--eye 1,2", render_args(scene, "--eye", "1,2"), "--eye")
expect_error("--eye 1,2,nan", render_args(scene, "--eye", "1,2,nan"), "--eye")
expect_error("--near -1", render_args(scene, "--near", "-1"), "near")
expect_error("--far below --near", render_args(scene, "--near", "10", "--far", "1"), "near")
expect_error("--fovy 0", render_args(scene, "--fovy", "0"), "fovy")
expect_error("--shading bogus", render_args(scene, "--shading", "bogus"), "bogus")
expect_error("--raster bogus", render_args(scene, "--raster", "bogus"), "bogus")
expect_error("--cull bogus", render_args(scene, "--cull", "bogus"), "bogus")
expect_error("--polygon bogus", render_args(scene, "--polygon", "bogus"), "bogus")
expect_error("--line-width 0", render_args(scene, "--line-width", "0"), "--line-width")
expect_error("--line-width nan", render_args(scene, "--line-width", "nan"), "line")
expect_error("--point-size 65", render_args(scene, "--point-size", "65"), "--point-size")
expect_error("--aov bogus=x", render_args(scene, "--aov", "bogus=x"), "--aov")
expect_error("--aov without file", render_args(scene, "--aov", "depth="), "--aov")
expect_error("output in a nonexistent directory", ["render", scene, "--size", "64x48", "-o", "/nonexistent/dir/out.png"],
             "/nonexistent/dir/out.png")
expect_error("aov output in a nonexistent directory",
             render_args(scene, "--aov", "depth=/nonexistent/dir/d.pfm"), "/nonexistent/dir/d.pfm")
if os.path.exists("/dev/full"):
    expect_error("output device full", ["render", scene, "--size", "64x48", "-o", "/dev/full"], "/dev/full")
expect_error("--kokkos-threads=abc", render_args(scene, "--kokkos-threads=abc"), "")
# Post-processing options (docs/post.md).
expect_error("--tonemap bogus", render_args(scene, "--tonemap", "bogus"), "bogus")
expect_error("--exposure nan", render_args(scene, "--exposure", "nan"), "exposure")
expect_error("--bloom=abc", render_args(scene, "--bloom=abc"), "--bloom")
expect_error("--bloom radius 0", render_args(scene, "--bloom=1,0.5,0"), "--bloom")
expect_error("--bloom four values", render_args(scene, "--bloom=1,2,3,4"), "--bloom")
expect_error("--ssao=0.1,0", render_args(scene, "--ssao=0.1,0"), "--ssao")
expect_error("--ssao negative radius", render_args(scene, "--ssao=-1"), "--ssao")
expect_error("--aov ao without --ssao", render_args(scene, "--aov", "ao=" + os.path.join(work, "ao.pfm")), "--ssao")
# CLI11 parse errors (exit 2).
expect_error("unknown flag", render_args(scene, "--no-such-flag"), "--no-such-flag")
expect_error("option without its value", ["render", scene, "-o", out_png, "--size"], "--size")
expect_error("non-numeric --fovy", render_args(scene, "--fovy", "abc"), "fovy")
expect_error("unknown subcommand", ["no-such-command"], "")

# ---------------------------------------------------------------- and one good render
if os.path.exists(out_png):
    os.remove(out_png)
r = run([args.rast] + render_args(scene))
problems = []
if r is None:
    problems.append(f"did not finish within {TIMEOUT_S} s")
else:
    if r.returncode != 0:
        problems.append(f"exit status {r.returncode}: {r.stderr.decode('utf-8', 'replace').strip()!r}")
    elif r.stderr:
        problems.append(f"stderr not empty: {r.stderr.decode('utf-8', 'replace')!r}")
    if not os.path.exists(out_png):
        problems.append("out.png not created")
    else:
        with open(out_png, "rb") as f:
            head = f.read(24)
        if head[:8] != b"\x89PNG\r\n\x1a\n" or struct.unpack(">II", head[16:24]) != (64, 48):
            problems.append("out.png is not a 64x48 PNG")
report(f"good render of {scene or 'the default scene'}", problems)

print(f"{passed} passed, {failed} failed" + (f", {known} known issues (see KNOWN above)" if known else ""))
sys.exit(1 if failed else 0)

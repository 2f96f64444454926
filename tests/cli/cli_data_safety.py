#!/usr/bin/env python3
"""Never lose the user's data (issue 38; docs/security.md, "Outputs"): each
case runs the real rast binary and checks the bytes on disk afterwards.

1. An output (-o or --aov) that is the scene file, a file the scene reads
   (external buffer, texture), a symlink or hard link to one, or another output
   of the same run is refused with one line, and the input is unchanged.
2. Outputs are atomic: a write that fails (a file size limit with SIGXFSZ
   ignored, or the signal killing rast) leaves the file that was at the path
   byte for byte, and no temporary file behind; a good render replaces it,
   keeping its permissions and a symlink as a symlink.
3. Images glTF does not allow (PNM, PSD, BMP, GIF, WebP, KTX2) are refused by
   signature; a PNM header without pixels no longer renders garbage.
(5., the thread flags, is tests/cli/cli_kokkos_flags.py.)
6. One line always, naming the problem: a newline in -o, a 4 MB data: URI with
   a wrong byteLength, %zz, a buffer URI '.', /proc/self/environ.
Python standard library only."""
import os
import resource
import shutil
import signal
import stat
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import adversarial  # noqa: E402
from cli_checks import one_line_error  # noqa: E402
from script_args import arg_parser  # noqa: E402

args = arg_parser().parse_args()
TIMEOUT_S = 120
work = os.path.abspath(args.workdir)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
env = dict(os.environ)
env.setdefault("OMP_PROC_BIND", "false")
failed = 0


def check(name, problems):
    global failed
    if problems:
        failed += 1
        print(f"FAIL    {name}: {'; '.join(problems)}")
    else:
        print(f"ok      {name}")


def run(argv, extra_env=None, preexec=None):
    e = dict(env)
    e.update(extra_env or {})
    try:
        return subprocess.run([args.rast] + argv, capture_output=True, timeout=TIMEOUT_S, env=e, preexec_fn=preexec)
    except subprocess.TimeoutExpired:
        return None


def snapshot(paths):
    out = {}
    for p in paths:
        with open(p, "rb") as f:
            out[p] = f.read()
    return out


def unchanged(before):
    problems = []
    for p, data in before.items():
        if not os.path.exists(p):
            problems.append(f"{os.path.basename(p)} was removed")
            continue
        with open(p, "rb") as f:
            now = f.read()
        if now != data:
            problems.append(f"{os.path.basename(p)} changed ({len(data)} -> {len(now)} bytes)")
    return problems


def leftovers(folder):
    return [f"temporary file {f} left behind" for f in os.listdir(folder) if ".rast-" in f]


def expect_refusal(name, argv, words, protect, folder=work, extra_env=None):
    before = snapshot(protect)
    r = run(argv, extra_env)
    check(name, one_line_error(r, words) + unchanged(before) + leftovers(folder))


small = ["--size", "64x48"]

# ---------------------------------------------------------------- 1. never write over an input
scene_glb = os.path.join(work, "scene.glb")
r = run(["export", "builtin:default", "-o", scene_glb])
if r is None or r.returncode != 0 or not os.path.exists(scene_glb):
    check("export builtin:default as a .glb to render", ["export failed"])
else:
    expect_refusal("render scene.glb -o scene.glb", ["render", scene_glb, "-o", scene_glb] + small,
                   ["-o:", "is the scene file", "refusing to write over an input"], [scene_glb])
    expect_refusal("export scene.glb -o scene.glb", ["export", scene_glb, "-o", scene_glb],
                   "refusing to write over an input", [scene_glb])
    link = os.path.join(work, "link.png")
    os.symlink(scene_glb, link)
    expect_refusal("-o link.png, a symlink to the scene", ["render", scene_glb, "-o", link] + small,
                   "is the scene file", [scene_glb])
    check("the symlink is still a symlink", [] if os.path.islink(link) else ["link.png replaced"])
    hard = os.path.join(work, "hard.png")
    os.link(scene_glb, hard)
    expect_refusal("-o hard.png, a hard link to the scene", ["render", scene_glb, "-o", hard] + small,
                   "is the scene file", [scene_glb])
    rel = os.path.relpath(scene_glb)
    expect_refusal("--aov depth=<the scene by another spelling>",
                   ["render", scene_glb, "-o", os.path.join(work, "x.png"), "--aov",
                    "depth=" + os.path.join(work, ".", "scene.glb")] + small,
                   ["--aov depth", "is the scene file"], [scene_glb])

ext = os.path.join(work, "ext")
os.makedirs(ext)
with open(os.path.join(ext, "tex.png"), "wb") as f:
    f.write(adversarial.png(4, 4))
ext_scene = adversarial.triangle_scene(ext, "tri.gltf", image_uris=["tex.png"], buffer_uri="tri.bin")
protect = [ext_scene, os.path.join(ext, "tri.bin"), os.path.join(ext, "tex.png")]
expect_refusal("-o tri.bin, the scene's external buffer", ["render", ext_scene, "-o", os.path.join(ext, "tri.bin")] + small,
               ["is a file the scene reads", "tri.bin"], protect, ext)
expect_refusal("-o tex.png, the scene's texture", ["render", ext_scene, "-o", os.path.join(ext, "tex.png")] + small,
               "is a file the scene reads", protect, ext)
expect_refusal("--aov normals=tri.bin", ["render", ext_scene, "-o", os.path.join(work, "y.png"), "--aov",
                                         "normals=" + os.path.join(ext, "tri.bin")] + small,
               "is a file the scene reads", protect, ext)
same = os.path.join(work, "same.pfm")
with open(same, "wb") as f:
    f.write(b"keep me")
expect_refusal("-o same.pfm --aov depth=same.pfm", ["render", "-o", same, "--aov", "depth=" + same] + small,
               ["--aov depth", "same file as the output of -o"], [same])
expect_refusal("--aov depth=a.pfm,normals=a.pfm", ["render", "-o", os.path.join(work, "z.png"), "--aov",
                                                   f"depth={work}/a.pfm,normals={work}/./a.pfm"] + small,
               "same file as the output of --aov depth", [])

# ---------------------------------------------------------------- 2. atomic outputs
out_pfm = os.path.join(work, "out.pfm")
old = b"the user's earlier image\n" * 10
with open(out_pfm, "wb") as f:
    f.write(old)


def limit_files(ignore_signal):
    def f():
        resource.setrlimit(resource.RLIMIT_FSIZE, (4096, 4096))  # ulimit -f 4
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN if ignore_signal else signal.SIG_DFL)
    return f


r = run(["render", "-o", out_pfm, "--size", "256x256"], preexec=limit_files(True))
check("ulimit -f 4, SIGXFSZ ignored: error, the old file intact",
      one_line_error(r, ["cannot write", "File too large"]) + unchanged({out_pfm: old}) + leftovers(work))
r = run(["render", "-o", out_pfm, "--size", "256x256"], preexec=limit_files(False))
problems = [] if r is not None and r.returncode == -signal.SIGXFSZ else [f"status {r and r.returncode}, not SIGXFSZ"]
check("ulimit -f 4, SIGXFSZ default: killed, the old file intact, no partial file",
      problems + unchanged({out_pfm: old}) + leftovers(work))
# The same for the AOVs of a run: nothing is renamed into place before all are complete.
depth = os.path.join(work, "depth.pfm")
with open(depth, "wb") as f:
    f.write(b"old depth")
r = run(["render", "-o", out_pfm, "--aov", "depth=" + depth, "--size", "256x256"], preexec=limit_files(True))
check("a failed colour write keeps the old AOV too",
      one_line_error(r, "cannot write") + unchanged({out_pfm: old, depth: b"old depth"}) + leftovers(work))
# SIGTERM during a long render (kept from before: nothing is written before the end).
p = subprocess.Popen([args.rast, "render", "-o", out_pfm, "--reference", "--size", "512x512"], env=env,
                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
try:
    p.wait(timeout=1.0)
except subprocess.TimeoutExpired:
    p.send_signal(signal.SIGTERM)
    p.wait(timeout=60)
    check("SIGTERM during a render: the old file intact", unchanged({out_pfm: old}) + leftovers(work))
# A good render replaces the file, keeping its permission bits; through a symlink, the target.
os.chmod(out_pfm, 0o640)
r = run(["render", "-o", out_pfm] + small)
problems = [] if r is not None and r.returncode == 0 else ["render failed"]
with open(out_pfm, "rb") as f:
    head = f.read(2)
if head != b"PF":
    problems.append("not replaced by a PFM")
if stat.S_IMODE(os.stat(out_pfm).st_mode) != 0o640:
    problems.append(f"mode {oct(stat.S_IMODE(os.stat(out_pfm).st_mode))}, not 0o640")
check("a good render replaces the file, keeping its mode", problems + leftovers(work))
target = os.path.join(work, "target.png")
with open(target, "wb") as f:
    f.write(b"old")
shot = os.path.join(work, "shot.png")
os.symlink(target, shot)
r = run(["render", "-o", shot] + small)
with open(target, "rb") as f:
    t = f.read(8)
check("-o through a symlink to a non-input writes its target, the link kept",
      ([] if r is not None and r.returncode == 0 else ["render failed"]) +
      ([] if os.path.islink(shot) else ["the link was replaced"]) +
      ([] if t == b"\x89PNG\r\n\x1a\n" else ["target not written"]))
r = run(["render", "-o", "/dev/null"] + small)
check("-o /dev/null (not a regular file) still works",
      [] if r is not None and r.returncode == 0 else [f"failed: {r and r.stderr[:200]!r}"])

# ---------------------------------------------------------------- 3. glTF's image formats only
img = os.path.join(work, "img")
os.makedirs(img)
for label, data, words in [
    ("a 14-byte PNM header without pixels", b"P6\n64 64\n255\n", "is PNM, not PNG or JPEG"),
    ("a 19-byte PNM header claiming 16384x16384", b"P6\n16384 16384\n255\n", "is PNM, not PNG or JPEG"),
    ("a 26-byte PSD header", b"8BPS\x00\x01" + bytes(6) + b"\x00\x03" + (16384).to_bytes(4, "big") * 2 +
     b"\x00\x08\x00\x03", "is PSD, not PNG or JPEG"),
    ("a BMP", b"BM" + bytes(60), "is BMP"),
    ("a GIF", b"GIF89a\x01\x00\x01\x00\x80\x00\x00", "is GIF"),
    ("a Radiance HDR", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 1\n\x02\x02\x02\x80", "is Radiance HDR"),
    ("a WebP", b"RIFF\x1a\x00\x00\x00WEBPVP8L" + bytes(14), "is WebP"),
    ("a KTX2", b"\xabKTX 20\xbb\r\n\x1a\n" + bytes(64), "is KTX2"),
    ("random bytes", bytes(range(7, 64)), "is not a PNG or JPEG image"),
    ("a PNG cut in half", adversarial.png(64, 64)[:40], "image 0"),
]:
    name = "t" + str(abs(hash(label)) % 100000)
    with open(os.path.join(img, name + ".img"), "wb") as f:
        f.write(data)
    sc = adversarial.triangle_scene(img, name + ".gltf", image_uris=[name + ".img"])
    out = os.path.join(img, "out.png")
    r = run(["render", sc, "-o", out] + small)
    check(f"texture: {label}", one_line_error(r, words) + ([f"out.png written"] if os.path.exists(out) else []))

# ---------------------------------------------------------------- 6. one line, naming the problem
r = run(["render", "-o", os.path.join(work, "no\nsuch\ndir", "x.png")] + small)
check("-o with newlines in the path", one_line_error(r, "no?such?dir"))
big = os.path.join(work, "big")
os.makedirs(big)
payload = "A" * 4_000_000
sc = adversarial.triangle_scene(big, "datauri.gltf", byte_length=61)
with open(sc) as f:
    text = f.read()
import json  # noqa: E402
doc = json.loads(text)
doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + payload
with open(sc, "w") as f:
    json.dump(doc, f)
r = run(["render", sc, "-o", os.path.join(big, "o.png")] + small)
check("a 4 MB data: URI with a wrong byteLength",
      one_line_error(r, ["buffers[0]: its data: URI decodes to 3000000 bytes, but its byteLength says 61"]))
sc = adversarial.triangle_scene(big, "good_data_wrong_len.gltf", byte_length=59)
r = run(["render", sc, "-o", os.path.join(big, "o.png")] + small)
check("a data: URI of 60 bytes, byteLength 59", one_line_error(r, "decodes to 60 bytes, but its byteLength says 59"))
sc = adversarial.triangle_scene(big, "pct.gltf", buffer_uri="tri%zz.bin")
r = run(["render", sc, "-o", os.path.join(big, "o.png")] + small)
check("buffer URI with %zz", one_line_error(r, "invalid percent escape '%zz'"))
sc = adversarial.triangle_scene(big, "pctimg.gltf", image_uris=["a%zzb.png"])
r = run(["render", sc, "-o", os.path.join(big, "o.png")] + small)
check("image URI with %zz", one_line_error(r, "invalid percent escape '%zz'"))
sc = adversarial.triangle_scene(big, "dot.gltf", buffer_uri=".")
r = run(["render", sc, "-o", os.path.join(big, "o.png")] + small)
check("buffer URI '.'", one_line_error(r, "names the scene's folder itself, not a file"))
if os.path.exists("/proc/self/environ"):
    sc = adversarial.triangle_scene(big, "proc.gltf", buffer_uri="/proc/self/environ")
    r = run(["render", sc, "-o", os.path.join(big, "o.png"), "--allow-external-files"] + small)
    check("/proc/self/environ with --allow-external-files",
          one_line_error(r, ["refusing to read '/proc/", "/environ': its size is 0"]) +
          (["'//proc' in the message"] if r is not None and b"//proc" in r.stderr else []))

print("all passed" if not failed else f"{failed} failed")
sys.exit(1 if failed else 0)

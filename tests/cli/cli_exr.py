#!/usr/bin/env python3
"""OpenEXR output (#42; app/exr_output.h) from the command line:

 - `-o F.exr` with `--aov depth=F.exr,primid=F.exr,normals=F.exr` writes one
   multi-channel file whose R, G, B, Z, id and N.X/N.Y/N.Z are the very
   values of the PFM and ids outputs of the same render (rows flipped to
   EXR's top-first order), with A in [0, 1], ZIP compressed;
 - an AOV in its own .exr holds that channel alone, and .npy/.pfm outputs
   beside it are unchanged;
 - BLEND layers over a transparent background keep their alpha: A is
   1 - (1 - a)^n for n layers of alpha a with nothing opaque behind, and the
   PNG's alpha, the colour premultiplied by it (the PNG's straight colour
   times A), under every transparency method (#39);
 - a failed run leaves an existing .exr as it was.
Read back with tests/support/exr_read.py (OpenEXR's Python bindings are not in
Debian). Skips (77) when the build has no OpenEXR."""
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import rastimg  # noqa: E402
from exr_read import read_exr  # noqa: E402
from script_args import arg_parser  # noqa: E402
from cli_checks import Tally  # noqa: E402
from skip import skip  # noqa: E402

args = arg_parser().parse_args()
wd = os.path.abspath(args.workdir)
os.makedirs(wd, exist_ok=True)
env = dict(os.environ, OMP_PROC_BIND="false")
check = Tally()  # check(ok, what); check.failed counts the failures


def rast(*a):
    return subprocess.run([args.rast, *a], capture_output=True, text=True, env=env, timeout=300)


def p(name):
    return os.path.join(wd, name)


scene = ["builtin:default", "--size", "48x32"]
r = rast("render", *scene, "-o", p("probe.exr"))
if r.returncode != 0 and "OpenEXR output is not built in" in r.stderr:
    skip(wd, "this build has no OpenEXR (libopenexr-dev, RAST_OPENEXR)")
check(r.returncode == 0, "rast render -o F.exr ran: " + r.stderr.strip()[-300:])

f = p("frame.exr")
r = rast("render", *scene, "-o", f, "--aov", f"depth={f},primid={f},normals={f}")
check(r.returncode == 0, "colour and three AOVs into one .exr: " + r.stderr.strip()[-300:])
r2 = rast("render", *scene, "-o", p("frame.pfm"), "--aov",
          f"depth={p('d.pfm')},primid={p('ids.bin')},normals={p('n.pfm')}")
check(r2.returncode == 0, "the same render into PFM and ids files")
hdr, ch = read_exr(f)
check(hdr["width"] == 48 and hdr["height"] == 32 and hdr["compression"] == 3, f"48x32, ZIP compressed: {hdr}")
check(sorted(hdr["channels"]) == sorted(["R", "G", "B", "A", "Z", "id", "N.X", "N.Y", "N.Z"]),
      f"channels R G B A Z id N.X N.Y N.Z: {hdr['channels']}")
check(hdr["types"]["id"] == 0 and hdr["types"]["Z"] == 2, "id is UINT, Z is FLOAT")


def top_first(values, w, h, c, k):
    """Channel k of a bottom-first interleaved PFM as rows, top first."""
    return [[values[((h - 1 - y) * w + x) * c + k] for x in range(w)] for y in range(h)]


w, h, c, rgb = rastimg.read_pfm(p("frame.pfm"))
check(all(ch[n] == top_first(rgb, w, h, 3, k) for k, n in enumerate("RGB")), "R, G, B == the PFM's linear colour")
_, _, _, dep = rastimg.read_pfm(p("d.pfm"))
check(ch["Z"] == top_first(dep, w, h, 1, 0), "Z == --aov depth's PFM")
_, _, nrm = rastimg.read_pfm(p("n.pfm"))[0:2] + (rastimg.read_pfm(p("n.pfm"))[3],)
check(all(ch[n] == top_first(nrm, w, h, 3, k) for k, n in enumerate(["N.X", "N.Y", "N.Z"])),
      "N.X N.Y N.Z == --aov normals' PFM")
_, _, ids = rastimg.read_ids(p("ids.bin"))
flat = [v for row in ch["id"] for v in row]
check(flat == list(ids) and any(flat) and not all(flat), "id == --aov primid (index + 1, 0 where empty)")
check(all(0.0 <= a <= 1.0 for row in ch["A"] for a in row) and max(max(row) for row in ch["A"]) == 1.0,
      "A within [0, 1] (clamped), 1 where covered")

z = p("z.exr")
r = rast("render", *scene, "-o", p("c.png"), "--aov", f"depth={z},primid={p('i.npy')}")
hz, cz = read_exr(z)
check(r.returncode == 0 and hz["channels"] == ["Z"] and cz["Z"] == ch["Z"], "an AOV alone in its .exr: channel Z")
check(os.path.getsize(p("i.npy")) > 4 * 48 * 32, "the .npy beside it is written")


# Three layers of alpha 0.5, unlit, no backdrop, each over the whole frame:
# 1 - 0.5^3 of every pixel is covered.
layers = ["builtin:layers?n=3&alpha=0.5&back=0", "--size", "64x48", "--background", "transparent"]
for method in ["exact", "weighted", "sorted", "kbuffer"]:
    e, png = p(f"blend_{method}.exr"), p(f"blend_{method}.png")
    r = rast("render", *layers, "--transparency", method, "-o", e)
    r2 = rast("render", *layers, "--transparency", method, "-o", png)
    check(r.returncode == 0 and r2.returncode == 0, f"{method}: BLEND layers into .exr and .png")
    if r.returncode or r2.returncode:
        continue
    _, ce = read_exr(e)
    pw, ph, px = rastimg.read_png_rgba(png)
    alphas = [a for row in ce["A"] for a in row]
    check(min(alphas) == max(alphas) == 0.875, f"{method}: A is 1 - 0.5^3 at every pixel: {min(alphas)}..{max(alphas)}")
    worst_a = worst = 0.0
    for y in range(ph):
        for x in range(pw):
            a, q = ce["A"][y][x], (y * pw + x) * 4
            worst_a = max(worst_a, abs(a * 255.0 - px[q + 3]))
            for k, n in enumerate("RGB"):
                worst = max(worst, abs(rastimg.srgb(ce[n][y][x] / a) - px[q + k]) if a > 0.0 else 0.0)
    check(worst_a <= 0.5, f"{method}: the PNG's alpha is A (worst {worst_a:.2f} of a byte)")
    check(worst <= 1.0, f"{method}: R, G, B are the PNG's straight colour times A (worst {worst:.2f} of a byte)")

before = open(f, "rb").read()
r = rast("render", *scene, "-o", f, "--aov", f"depth={f}", "--shading", "glossy")
check(r.returncode != 0 and open(f, "rb").read() == before, "a failed run leaves the existing .exr as it was")
sys.exit(1 if check.failed else 0)

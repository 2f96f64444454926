#!/usr/bin/env python3
"""The float film from the command line (docs/post.md):

 - `-o out.pfm` writes the film as linear float RGB: encoded to sRGB here it
   gives the PNG's bytes within 1/255;
 - `--exposure 1` doubles every value of the film exactly (x 2^EV);
 - `--aov ao=F.pfm` (with --ssao) holds AO in [0, 1], below 1 somewhere on the
   default scene (its objects stand on a floor) and 1 on the background;
 - `rast bench` reports no float-film memory without a pass and some with one.
Standard library only."""
import json
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import rastimg  # noqa: E402
from cli_checks import Tally, cli_setup  # noqa: E402

args, env = cli_setup()
check = Tally()  # check(ok, what); check.failed counts the failures


def rast(*a):
    r = subprocess.run([args.rast] + list(a), capture_output=True, text=True, env=env, timeout=600)
    if r.returncode != 0:
        raise SystemExit(f"FAILED: rast {' '.join(a)}: {r.stderr.strip()}")
    return r.stdout


def wd(n):
    return os.path.join(args.workdir, n)


def srgb_byte(v):
    return int(rastimg.srgb(v) + 0.5)


size = ["--size", "96x64"]
rast("render", *size, "-o", wd("plain.png"))
rast("render", *size, "-o", wd("film.pfm"))
rast("render", *size, "--exposure", "1", "-o", wd("film_ev1.pfm"))
w, h, _, png = rastimg.read_png(wd("plain.png"))
pw, ph, ch, pfm = rastimg.read_pfm(wd("film.pfm"))
check((pw, ph, ch) == (w, h, 3), f"film.pfm is {pw}x{ph}x{ch}")
worst = 0
for y in range(h):
    for x in range(w):
        src = ((h - 1 - y) * w + x) * 3  # PFM rows bottom first
        for c in range(3):
            worst = max(worst, abs(srgb_byte(pfm[src + c]) - png[(y * w + x) * 4 + c]))
check(worst <= 1, f"sRGB of the PFM film equals the PNG within 1/255 (max diff {worst})")
check(max(pfm) > 0.1, "the film is not black")
_, _, _, ev1 = rastimg.read_pfm(wd("film_ev1.pfm"))
check(all(b == 2.0 * a for a, b in zip(pfm, ev1)), "--exposure 1 doubles every film value exactly")

rast("render", *size, "--ssao", "--aov", "ao=" + wd("ao.pfm"), "-o", wd("ao.png"))
aw, ah, ach, ao = rastimg.read_pfm(wd("ao.pfm"))
check((aw, ah, ach) == (w, h, 1), "ao.pfm is one channel at the image size")
check(all(0.0 <= v <= 1.0 for v in ao), "AO in [0, 1]")
check(min(ao) < 0.9, f"some occlusion on the default scene (min AO {min(ao):.3f})")
check(ao[0] == 1.0 and ao[-1] == 1.0, "background corners unoccluded")

rows = {}
for name, extra in [("plain", []), ("post", ["--bloom", "--ssao", "--tonemap", "aces"])]:
    rast("bench", *size, "--frames", "1", "--warmup", "1", "--json", wd(name + ".json"), *extra)
    with open(wd(name + ".json")) as f:
        rows[name] = json.load(f)[0]
check(rows["plain"]["film_bytes"] == 0, "bench: no float film without a pass")
check(rows["post"]["film_bytes"] >= 96 * 64 * 16, f"bench: the film's bytes reported ({rows['post']['film_bytes']})")
check(rows["plain"]["total_median_ms"] > 0 and rows["plain"]["staged_total_median_ms"] > 0,
      "bench: the frame timed whole and stage by stage")
stages = rows["post"]["stages_median_ms"]
check(all(p in stages for p in ["ssao", "bloom", "tonemap", "encode"]), f"bench: per-pass times ({', '.join(stages)})")
sys.exit(1 if check.failed else 0)

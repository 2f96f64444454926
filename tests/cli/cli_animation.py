#!/usr/bin/env python3
"""Animation from the command line (#40, docs/animation.md):

 - `rast render --time T` poses the scene: different times give different
   images, the same time the same bytes; `--animation N|NAME` picks one;
 - `--frames START:END:FPS -o out_%03d.png` writes one PNG per frame, each the
   same bytes as `--time` at that frame's time with the same camera flags;
   `--turntable N` orbits the camera in N frames;
 - `-o out.gif|.mp4` goes through ffmpeg (checked when it is installed), and
   without ffmpeg on PATH the run ends in one line naming it;
 - bad requests and the fuzz corpus' broken animation seeds end in one line.
Standard library only."""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from cli_checks import Tally, cli_setup  # noqa: E402

args, env = cli_setup()
check = Tally()  # check(ok, what); check.failed counts the failures
corpus = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fuzz", "corpus")


def run(*a, environment=None):
    return subprocess.run([args.rast] + list(a), capture_output=True, text=True, env=environment or env, timeout=600)


def w(name):
    return os.path.join(args.workdir, name)


def read(p):
    with open(p, "rb") as f:
        return f.read()


scene = w("anim.gltf")
shutil.copy(os.path.join(corpus, "anim_skin_morph.gltf"), scene)
cam = ["--eye", "0.5,0.5,5", "--target", "0.5,0.5,0", "--up", "0,1,0", "--near", "0.1", "--far", "100"]
size = ["--size", "96x72"]

stills = {}
for t in ("0", "0.5", "1"):
    r = run("render", scene, "--time", t, *size, *cam, "-o", w(f"t{t}.png"))
    check(r.returncode == 0, f"--time {t} renders ({r.stderr.strip()})")
    stills[t] = read(w(f"t{t}.png")) if r.returncode == 0 else b""
check(len(set(stills.values())) == 3, "three times give three different images")
r = run("render", scene, "--time", "0.5", *size, *cam, "-o", w("again.png"))
check(r.returncode == 0 and read(w("again.png")) == stills["0.5"], "the same time gives the same bytes")
r1 = run("render", scene, "--time", "1", "--animation", "move", *size, *cam, "-o", w("byname.png"))
r2 = run("render", scene, "--time", "1", "--animation", "0", *size, *cam, "-o", w("byindex.png"))
check(r1.returncode == 0 and r2.returncode == 0 and read(w("byname.png")) == read(w("byindex.png")) == stills["1"],
      "--animation by name and by index pick the same (only) animation")
r = run("render", scene, "--time", "1", *size, "-o", w("framed.png"))
check(r.returncode == 0 and "rast: camera (auto)" in r.stdout, "auto-framing prints the posed scene's camera")

r = run("info", scene)
check(r.returncode == 0 and "animation: 1 animations, 1 skins; 1 skinned and 1 morphed draws" in r.stdout
      and "0 'move': 4 channels, 0 to 1 s" in r.stdout, f"rast info lists the animation ({r.stdout.strip()[-160:]})")

r = run("bench", scene, "--frames", "3", "--warmup", "1", *size)
check(r.returncode == 0 and "animation: " in r.stdout and "ms to send the pose" in r.stdout,
      f"rast bench times posing an animated scene ({r.stdout.strip()[-120:]})")

# A sequence: 5 frames at 4 fps over [0, 1]; frame 2 is t = 0.5.
r = run("render", scene, "--frames", "0:1:4", *size, *cam, "-o", w("seq_%03d.png"))
check(r.returncode == 0 and all(os.path.exists(w(f"seq_{i:03d}.png")) for i in range(5)) and not os.path.exists(w("seq_005.png")),
      f"--frames 0:1:4 writes frames 000..004 ({r.stderr.strip()})")
if r.returncode == 0:
    check(read(w("seq_002.png")) == stills["0.5"] and read(w("seq_004.png")) == stills["1"],
          "sequence frames are the --time stills of their times")
r = run("render", scene, "--turntable", "4", *size, *cam, "-o", w("turn_%d.png"))
check(r.returncode == 0 and [os.path.exists(w(f"turn_{i}.png")) for i in range(5)] == [True] * 4 + [False],
      f"--turntable 4 writes 4 frames ({r.stderr.strip()})")
if r.returncode == 0:
    check(read(w("turn_1.png")) != read(w("turn_0.png")), "the turntable's camera moves")

if shutil.which("ffmpeg"):
    for ext, magic in (("gif", b"GIF8"), ("mp4", b"ftyp")):
        r = run("render", scene, "--frames", "0:1:4", *size, "-o", w(f"clip.{ext}"))
        ok = r.returncode == 0 and os.path.exists(w(f"clip.{ext}")) and magic in read(w(f"clip.{ext}"))[:16]
        check(ok and not os.path.exists(w(f"clip.{ext}.rast-partial")), f"-o clip.{ext} through ffmpeg ({r.stderr.strip()})")
else:
    print("ffmpeg not installed: video output not checked (apt-get install ffmpeg)")
no_ffmpeg = dict(env, PATH="/nonexistent")
r = run("render", scene, "--frames", "0:1:4", *size, "-o", w("none.mp4"), environment=no_ffmpeg)
check(r.returncode == 1 and "needs ffmpeg" in r.stderr and len(r.stderr.strip().splitlines()) == 1 and not os.path.exists(w("none.mp4")),
      f"no ffmpeg on PATH: one line ({r.stderr.strip()})")

for bad, expect in ((["--animation", "3"], "animations 0..0"),
                    (["--animation", "walk"], "no animation named 'walk'"),
                    (["--time", "nan"], "--time"),
                    (["--frames", "1:0:30"], "START <= END"),
                    (["--frames", "0:1"], "START:END:FPS"),
                    (["--frames", "0:1:4", "-o", w("single.png")], "needs a %d"),
                    (["--frames", "0:1:4", "-o", w("two_%d_%d.png")], "one %d")):
    out = [] if "-o" in bad else ["-o", w("bad.png")]
    r = run("render", scene, *size, *bad, *out)
    err = r.stderr.strip()
    check(r.returncode in (1, 2) and expect in err and len(err.splitlines()) == 1, f"{' '.join(bad)}: one line ({err})")
r = run("render", "builtin:default", "--animation", "0", "-o", w("bad.png"))
check(r.returncode == 1 and "has no animations" in r.stderr, "--animation on a scene without animations: one line")

for seed, expect in (("anim_bad_times", "keyframe times must increase"), ("anim_bad_nan", "NaN"),
                     ("anim_bad_count", "keyframes need"), ("anim_bad_joint", "joint 7 out of range"),
                     ("anim_bad_cycle", "node")):
    r = run("render", os.path.join(corpus, seed + ".gltf"), *size, "-o", w("bad.png"))
    err = r.stderr.strip()
    check(r.returncode == 1 and expect in err and len(err.splitlines()) == 1, f"{seed}: one line ({err})")

print(f"{'FAILED' if check.failed else 'all passed'}: {check.failed} failing")
sys.exit(1 if check.failed else 0)

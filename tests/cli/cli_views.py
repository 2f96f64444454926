#!/usr/bin/env python3
"""Many views of one scene (`rast render --cameras FILE -o out_%04d.png`, #41):

 - a JSON list of cameras keyed by rast's flag names renders, view by view,
   the same bytes (image, depth, ids) as one `rast render` per view with
   those flags, the renderer being reused across views;
 - a NeRF transforms.json (camera-to-world matrices, camera_angle_x) gives
   the same view as the equivalent JSON entry;
 - malformed files and output names end in one 'rast: error:' line, exit 1,
   and write nothing.
Standard library only."""
import json
import math
import os
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from cli_checks import one_line_error, Tally, cli_setup  # noqa: E402

args, env = cli_setup()
check = Tally()  # check(ok, what); check.failed counts the failures
W = args.workdir


def run(*a):
    return subprocess.run([args.rast] + [str(x) for x in a], capture_output=True, env=env, timeout=600)


def same(a, b):
    with open(a, "rb") as fa, open(b, "rb") as fb:
        return fa.read() == fb.read()


def p(name):
    return os.path.join(W, name)


SIZE = "96x64"
views = [
    {"eye": [0, 0.5, 4], "target": [0, 0, 0]},
    {"eye": [3, 1, 3], "target": [0, 0.2, 0], "up": [0, 1, 0], "fovy": 35, "near": 0.5, "far": 50},
    {"eye": [-2, 2, 2.5], "target": [0, 0, 0], "fovy": 60},
]
with open(p("cams.json"), "w") as f:
    json.dump(views, f)

r = run("render", "builtin:default", "--size", SIZE, "--cameras", p("cams.json"), "-o", p("v_%03d.png"),
        "--aov", f"depth={p('d_%03d.npy')},primid={p('i_%03d.npy')}")
check(r.returncode == 0, f"--cameras renders a list of 3 views ({r.stderr.decode()[:200]!r})")
for k, v in enumerate(views):
    flags = ["--eye", ",".join(map(str, v["eye"])), "--target", ",".join(map(str, v["target"]))]
    # A key left out keeps the command line's camera: the default scene's own.
    for key, flag in (("up", "--up"), ("fovy", "--fovy"), ("near", "--near"), ("far", "--far")):
        if key in v:
            flags += [flag, str(v[key]) if not isinstance(v[key], list) else ",".join(map(str, v[key]))]
    r1 = run("render", "builtin:default", "--size", SIZE, *flags, "-o", p(f"one_{k}.png"),
             "--aov", f"depth={p(f'od_{k}.npy')},primid={p(f'oi_{k}.npy')}")
    check(r1.returncode == 0 and os.path.exists(p(f"v_{k:03d}.png")) and same(p(f"v_{k:03d}.png"), p(f"one_{k}.png"))
          and same(p(f"d_{k:03d}.npy"), p(f"od_{k}.npy")) and same(p(f"i_{k:03d}.npy"), p(f"oi_{k}.npy")),
          f"view {k}: image, depth and ids equal a single render with its flags")

# NeRF: a camera at (0.3, 0.2, 4) looking down -Z, +Y up, 50 degrees across.
ax = math.radians(50.0)
nerf = {"camera_angle_x": ax, "frames": [{"file_path": "./r_0", "transform_matrix": [
    [1, 0, 0, 0.3], [0, 1, 0, 0.2], [0, 0, 1, 4.0], [0, 0, 0, 1]]}]}
with open(p("transforms.json"), "w") as f:
    json.dump(nerf, f)
w, h = 96, 64
fovy = math.degrees(2.0 * math.atan(math.tan(ax / 2.0) * h / w))
with open(p("nerf_equiv.json"), "w") as f:
    json.dump([{"eye": [0.3, 0.2, 4.0], "target": [0.3, 0.2, 0.0], "up": [0, 1, 0], "fovy": fovy}], f)
r = run("render", "builtin:default", "--size", SIZE, "--cameras", p("transforms.json"), "-o", p("n_%d.png"))
r2 = run("render", "builtin:default", "--size", SIZE, "--cameras", p("nerf_equiv.json"), "-o", p("ne_%d.png"))
check(r.returncode == 0 and r2.returncode == 0 and same(p("n_0.png"), p("ne_0.png")),
      "a NeRF transforms.json frame renders as the equivalent camera entry")

# Refusals: one line, exit 1, no file.
bad = {
    "notjson.json": ("[{", "not valid JSON"),
    "short.json": ('[{"eye": [0, 0]}]', "'eye'"),
    "unknown.json": ('[{"eye": [0, 0, 4], "fov": 3}]', "unknown key"),
    "same.json": ('[{"eye": [0, 0, 0], "target": [0, 0, 0]}]', "must differ"),
    "fovy.json": ('[{"fovy": 180}]', "fovy"),
    "nan.json": ('[{"near": "x"}]', "'near'"),
    "empty.json": ("[]", "no views"),
    "frames.json": ('{"frames": 3}', "'frames'"),
    "noangle.json": ('{"frames": [{"transform_matrix": [[1,0,0,0],[0,1,0,0],[0,0,1,4],[0,0,0,1]]}]}', "camera_angle_x"),
    "matrix.json": ('{"camera_angle_x": 0.8, "frames": [{"transform_matrix": [[1,0,0]]}]}', "transform_matrix"),
    "scalar.json": ("42", "expected a list"),
}
for name, (text, words) in bad.items():
    with open(p(name), "w") as f:
        f.write(text)
    out = p("bad_%d.png")
    r = run("render", "builtin:default", "--size", "8x8", "--cameras", p(name), "-o", out)
    probs = one_line_error(r, ["--cameras", words])
    check(not probs and not os.path.exists(p("bad_0.png")), f"{name}: refused in one line {probs}")
for out, words in ((p("plain.png"), "view number field"), (p("pct_%s.png"), "not a view number field")):
    r = run("render", "builtin:default", "--size", "8x8", "--cameras", p("cams.json"), "-o", out)
    check(not one_line_error(r, words), f"-o {os.path.basename(out)} with --cameras is refused")
r = run("render", "builtin:default", "--size", "8x8", "--cameras", p("missing.json"), "-o", p("m_%d.png"))
check(not one_line_error(r, "not a readable file"), "a missing --cameras file is refused")

sys.exit(1 if check.failed else 0)

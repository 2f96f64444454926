#!/usr/bin/env python3
"""--max-memory bounds peak resident memory (issue 38; docs/security.md,
"Memory budget"): for each case of the issue, rast either renders or refuses
with one line, and its peak RSS (wait4's ru_maxrss, per child) stays within
the budget plus the stated constant of 100 MiB. Cases that fit are run too,
so that the bound is measured on real frames, not only on refusals.
Python standard library only; inputs are generated (nothing large is kept)."""
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import adversarial  # noqa: E402
from script_args import arg_parser  # noqa: E402

args = arg_parser().parse_args()
CONSTANT_MIB = 100  # docs/security.md: peak RSS <= budget + this
TIMEOUT_S = 300
work = os.path.abspath(args.workdir)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
env = dict(os.environ)
env.setdefault("OMP_PROC_BIND", "false")
failed = 0


def run(argv):
    """(returncode or None on timeout, stderr, peak RSS in MiB) of one rast run."""
    p = subprocess.Popen([args.rast] + argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env)
    start = time.time()
    while True:
        pid, status, usage = os.wait4(p.pid, os.WNOHANG)
        if pid:
            break
        if time.time() - start > TIMEOUT_S:
            p.kill()
            pid, status, usage = os.wait4(p.pid, 0)
            return None, b"", usage.ru_maxrss / 1024.0
        time.sleep(0.02)
    err = p.stderr.read()
    p.stderr.close()
    p.returncode = os.waitstatus_to_exitcode(status)
    return p.returncode, err, usage.ru_maxrss / 1024.0


def case(name, argv, budget_mib, expect):
    """expect: 'render', 'refuse' (with words) or 'either'."""
    global failed
    code, err, rss = run(argv + ["--max-memory", f"{budget_mib}M"])
    text = err.decode("utf-8", "replace")
    problems = []
    if code is None:
        problems.append("timed out")
    elif code < 0:
        problems.append(f"killed by signal {-code}")
    elif code == 0 and expect[0] == "refuse":
        problems.append("rendered; expected a refusal")
    elif code != 0 and expect[0] == "render":
        problems.append(f"refused: {text.strip()[:300]!r}")
    elif code != 0:
        lines = text.strip().split("\n")
        if len(lines) != 1 or not lines[0].startswith("rast: error: "):
            problems.append(f"not one error line: {text[:300]!r}")
        for w in expect[1:]:
            if w not in text:
                problems.append(f"stderr lacks {w!r}: {text.strip()[:300]!r}")
    limit = budget_mib + CONSTANT_MIB
    if rss > limit:
        problems.append(f"peak RSS {rss:.0f} MiB > {budget_mib} MiB budget + {CONSTANT_MIB} MiB")
    outcome = "rendered" if code == 0 else "refused"
    if problems:
        failed += 1
        print(f"FAIL    {name}: {'; '.join(problems)} (peak RSS {rss:.0f} MiB)")
    else:
        print(f"ok      {name}: {outcome}, peak RSS {rss:.0f} MiB <= {limit} MiB")


out = os.path.join(work, "out.png")
aovs = ["--aov", ",".join(f"{k}={os.path.join(work, k)}.pfm" for k in ("depth", "primid", "normals", "ao"))]

# The frames: SSAO with four AOVs, a large MSAA frame, SSAA.
case("4096x4096 --ssao, four AOVs, 600M (issue: 1.45 GB)",
     ["render", "-o", out, "--size", "4096x4096", "--ssao"] + aovs, 600, ["refuse", "framebuffer"])
case("1536x1536 --ssao, four AOVs, 600M (fits)",
     ["render", "-o", out, "--size", "1536x1536", "--ssao"] + aovs, 600, ["render"])
case("8192x8192 default scene, 2100M (issue: 5.8 GB)",
     ["render", "-o", out, "--size", "8192x8192"], 2100, ["refuse", "framebuffer"])
case("4096x4096 --aa ssaa4 -o .pfm, 1100M (fits)",
     ["render", "-o", os.path.join(work, "out.pfm"), "--size", "4096x4096", "--aa", "ssaa4"], 1100, ["either"])
case("8192x8192 --aa ssaa4, 1800M (issue: 3.0 GB)",
     ["render", "-o", out, "--size", "8192x8192", "--aa", "ssaa4"], 1800, ["refuse", "framebuffer"])

# One PNG of 4096x4096 (64 MiB decoded) named by six images, all drawn.
scene = os.path.join(work, "six")
os.makedirs(scene)
with open(os.path.join(scene, "big.png"), "wb") as f:
    f.write(adversarial.png(4096, 4096))
six = adversarial.triangle_scene(scene, "six.gltf", image_uris=["big.png"] * 6, image_refs=range(6))
case("one 4096^2 PNG as six images, 400M", ["render", six, "-o", out, "--size", "64x48"], 400, ["refuse", "image"])
case("one 4096^2 PNG as six images, 1500M", ["render", six, "-o", out, "--size", "64x48"], 1500, ["either"])
# Two textures of one image and sampler: decoded once.
two = adversarial.triangle_scene(scene, "two.gltf", image_uris=["big.png"], image_refs=[0, 0])
case("one image used by two textures, 700M", ["render", two, "-o", out, "--size", "64x48"], 700, ["either"])

# A small JSON text that parses into a large tree: 4 MB of "0," in extras is
# 2M values, about 380 MiB resident once parsed (256 bytes a value charged).
import json  # noqa: E402
values = adversarial.triangle_scene(work, "values.gltf")
with open(values) as f:
    doc = json.load(f)
doc["extras"] = {"a": [0] * 2_000_000}
with open(values, "w") as f:
    json.dump(doc, f, separators=(",", ":"))
case("4 MB JSON of 2M values, 300M", ["render", values, "-o", out, "--size", "64x48"], 300,
     ["refuse", "the JSON document (", "values, parsed) needs"])
case("4 MB JSON of 2M values, 600M", ["render", values, "-o", out, "--size", "64x48"], 600, ["render"])

# Files: larger than the budget, refused before reading; zeros refused at the first byte.
zeros = os.path.join(work, "zeros.gltf")
with open(zeros, "wb") as f:
    f.truncate(256 << 20)  # sparse: 256 MiB of zeros that take no disk
case("256 MiB file of zeros, 64M budget", ["render", zeros, "-o", out], 64, ["refuse", "the file", "needs"])
case("256 MiB file of zeros, 1G budget", ["render", zeros, "-o", out], 1024, ["refuse", "invalid JSON at byte 1"])
code, err, rss = run(["render", zeros, "-o", out])
if rss > 100:
    failed += 1
    print(f"FAIL    256 MiB of zeros read whole: peak RSS {rss:.0f} MiB")
else:
    print(f"ok      256 MiB of zeros, default budget: refused at its first byte, peak RSS {rss:.0f} MiB")

print("all passed" if not failed else f"{failed} failed")
sys.exit(1 if failed else 0)

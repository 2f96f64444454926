#!/usr/bin/env python3
"""Security and resource limits at the command line (docs/security.md).

- External files: a texture or buffer URI leading outside the scene's folder
  (../, %2e%2e/, an absolute path, a symlink) is refused with one line naming
  the resolved path, unless --allow-external-files is given; data: URIs work.
- Memory budget: small files claiming huge counts or decoded sizes, and a
  framebuffer of 16384^2 x 8 samples, end in one 'rast: error:' line naming
  what is too big, quickly and without the memory (peak RSS checked).
- Auto-framing a scene beyond float precision is an error, not a blank image.
Python standard library only; the adversarial inputs come from
tests/support/adversarial.py (generated here, nothing large in the repository)."""
import os
import resource
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import adversarial  # noqa: E402
from script_args import arg_parser  # noqa: E402

args = arg_parser().parse_args()
TIMEOUT_S = 60
work = os.path.abspath(args.workdir)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(os.path.join(work, "scene"))
out_png = os.path.join(work, "out.png")
env = dict(os.environ)
env.setdefault("OMP_PROC_BIND", "false")
failed = 0


def run(argv):
    """Runs rast; returns (CompletedProcess or None, peak RSS of the child in MiB)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    try:
        r = subprocess.run([args.rast] + argv, capture_output=True, timeout=TIMEOUT_S, env=env)
    except subprocess.TimeoutExpired:
        r = None
    after = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return r, max(before, after) / 1024.0  # ru_maxrss: KiB; the maximum over children so far


def check(name, problems):
    global failed
    if problems:
        failed += 1
        print(f"FAIL    {name}: {'; '.join(problems)}")
    else:
        print(f"ok      {name}")


def expect_error(name, argv, words, max_rss_mib=None):
    if os.path.exists(out_png):
        os.remove(out_png)
    r, rss = run(argv + ["-o", out_png])
    problems = []
    if r is None:
        check(name, [f"did not finish within {TIMEOUT_S} s"])
        return
    err = r.stderr.decode("utf-8", "replace")
    lines = err.splitlines()
    if r.returncode == 0:
        problems.append("exit status 0")
    if len(lines) != 1 or not lines[0].startswith("rast: error: "):
        problems.append(f"stderr is not one 'rast: error:' line: {err!r}")
    for w in words if isinstance(words, list) else [words]:
        if w not in err:
            problems.append(f"stderr lacks {w!r}: {err.strip()!r}")
    if os.path.exists(out_png):
        problems.append("out.png was written")
    # Peak RSS is the maximum over all children so far; the cases run cheapest first.
    if max_rss_mib is not None and rss > max_rss_mib:
        problems.append(f"peak RSS {rss:.0f} MiB > {max_rss_mib} MiB")
    check(name, problems)


def expect_render(name, argv):
    if os.path.exists(out_png):
        os.remove(out_png)
    r, _ = run(argv + ["-o", out_png])
    problems = []
    if r is None:
        problems.append(f"did not finish within {TIMEOUT_S} s")
    elif r.returncode != 0:
        problems.append(f"exit status {r.returncode}: {r.stderr.decode('utf-8', 'replace').strip()!r}")
    elif not os.path.exists(out_png):
        problems.append("out.png not written")
    check(name, problems)


scene_dir = os.path.join(work, "scene")
small = ["--size", "32x24"]

# ---------------------------------------------------------------- memory (cheapest first: RSS is a running maximum)
tiny = adversarial.tiny_counts(work)
expect_error(f"{os.path.getsize(tiny)}-byte glTF claiming 2^24 vertices", ["render", tiny] + small,
             ["has no bufferView and a count of 16777216", "out of proportion"], max_rss_mib=200)
expect_error("framebuffer 16384x16384 with msaa8 (8 GiB budget)",
             ["render", "--size", "16384x16384", "--aa", "msaa8", "--max-memory", "8G"],
             ["16384x16384 framebuffer with 8 samples per pixel needs 17.0 GiB", "over the memory budget of 8.00 GiB"],
             max_rss_mib=200)
png_scene = adversarial.huge_png(scene_dir)
expect_error(f"{os.path.getsize(os.path.join(scene_dir, 'huge.png')) // 1024} KiB PNG decoding to 16384x16384",
             ["render", png_scene, "--max-memory", "1G"] + small,
             ["image 0 (16384x16384 texels, decoded) needs 3.00 GiB", "--max-memory"], max_rss_mib=200)
strip = adversarial.strip(work, indices=4_000_000)
expect_error("4 MB strip of 4M u8 indices (256 MiB budget)", ["render", strip, "--max-memory", "256M"] + small,
             ["mesh primitive (3 vertices, 3999998 triangles) needs", "256 MiB"], max_rss_mib=200)
expect_error("builtin:tiny?n=1e12", ["render", "builtin:tiny?n=1e12"] + small, "outside 1..134217728", max_rss_mib=200)
expect_error("builtin:grid?n=1e30", ["render", "builtin:grid?n=1e30"] + small, "outside 1..8192", max_rss_mib=200)
expect_error("malformed --max-memory", ["render", "--max-memory", "lots"] + small, "--max-memory: expected a size")

# ---------------------------------------------------------------- external files
secret = os.path.join(work, "secret.png")
with open(secret, "wb") as f:
    f.write(adversarial._png(2, 2))
real_secret = os.path.realpath(secret)
os.symlink(secret, os.path.join(scene_dir, "link.png"))
for label, uri, words in [
    ("../", "../secret.png", "outside the scene's folder"),
    ("%2e%2e/", "%2e%2e/secret.png", "outside the scene's folder"),
    ("absolute path", real_secret, "an absolute path"),
    ("symlink out of the folder", "link.png", "outside the scene's folder"),
]:
    p = adversarial.textured_triangle(scene_dir, f"ext_{len(label)}_{label[0].isalpha()}.gltf", uri)
    expect_error(f"texture URI {label}", ["render", p] + small, [f"refusing to read '{real_secret}'", words])
    expect_render(f"texture URI {label} with --allow-external-files", ["render", p, "--allow-external-files"] + small)
with open(os.path.join(scene_dir, "inside.png"), "wb") as f:
    f.write(adversarial._png(2, 2))
expect_render("texture inside the scene's folder", ["render", adversarial.textured_triangle(scene_dir, "in.gltf", "inside.png")] + small)

# ---------------------------------------------------------------- float range of auto-framing
far = adversarial.far_triangle(work, 1e38)
expect_error("auto-framing vertices near 1e38", ["render", far] + small, "cannot frame the scene within float precision")
expect_render("the same scene with an explicit camera",
              ["render", far, "--eye", "0,0,3e38", "--target", "0,0,0", "--near", "1e37", "--far", "3.3e38"] + small)

print("all passed" if not failed else f"{failed} failed")
sys.exit(1 if failed else 0)

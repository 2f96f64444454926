"""What a new user meets in the first minutes (issue #10): no Kokkos noise,
rast's own help and version, described options, builtin scenes that describe
themselves and print their camera, a default scene that fills the frame, output
paths checked before rendering, progress only on a terminal, `cmake --install`,
ctest failing when no test ran, and skipped tests' reasons reported."""
import os
import pty
import re
import select
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from rastimg import read_png_rgba  # noqa: E402
from script_args import arg_parser  # noqa: E402

args = arg_parser().parse_args()
work = os.path.abspath(args.workdir)
os.makedirs(work, exist_ok=True)
build_dir = os.path.dirname(os.path.abspath(args.rast))
source_dir = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
passed = failed = 0


def check(name, problems):
    global passed, failed
    if problems:
        failed += 1
        print(f"FAIL    {name}: {'; '.join(problems)}")
    else:
        passed += 1
        print(f"ok      {name}")


def env_without_omp(**extra):
    e = {k: v for k, v in os.environ.items() if not k.startswith("OMP_")}
    e.update(extra)
    return e


def rast(*argv, env=None, timeout=300):
    return subprocess.run([args.rast] + list(argv), capture_output=True, text=True, timeout=timeout,
                          env=env if env is not None else env_without_omp())


# ---- no Kokkos warning on ordinary runs, the user's OpenMP settings kept
out = os.path.join(work, "default.png")
r = rast("render", "-o", out, "--size", "320x180")
noise = [l for l in (r.stdout + r.stderr).splitlines() if "OMP_PROC_BIND" in l or "WARNING" in l]
check("render prints no Kokkos warning with OMP_* unset",
      ([f"exit {r.returncode}: {r.stderr.strip()}"] if r.returncode else []) + [f"noise: {l!r}" for l in noise])
r = rast("render", "-o", os.path.join(work, "missing", "x.png"))
check("an error is one line, without Kokkos noise",
      [] if r.returncode != 0 and r.stdout == "" and len(r.stderr.splitlines()) == 1 else
      [f"rc {r.returncode}, stdout {r.stdout!r}, stderr {r.stderr!r}"])
r = rast("info")
m = re.search(r"^OMP_PROC_BIND: (\S+) \((\w+)\)", r.stdout, re.M)
check("rast's OpenMP default is OMP_PROC_BIND=false", [] if m and m.groups() == ("false", "default") else [r.stdout])
r = rast("info", env=env_without_omp(OMP_PROC_BIND="spread", OMP_PLACES="threads"))
m = re.search(r"^OMP_PROC_BIND: (\S+) \((\w+)\)", r.stdout, re.M)
check("the user's OMP_PROC_BIND is kept", [] if m and m.groups() == ("spread", "yours") else [r.stdout])

# ---- help, usage and version
for argv in (["--help"], ["render", "--help"], ["bench", "--help"], ["help"], ["help", "bench"], []):
    r = rast(*argv)
    problems = []
    if r.returncode != 0:
        problems.append(f"exit {r.returncode}: {r.stderr.strip()!r}")
    if "Usage:" not in r.stdout:
        problems.append("no usage")
    if "Kokkos command line arguments" in r.stdout or "--kokkos-numa" in r.stdout:
        problems.append("Kokkos' own help printed")
    if r.stdout.count("--kokkos-help") != 1:
        problems.append("no one-line pointer to --kokkos-help")
    if "subcommand is required" in r.stdout + r.stderr:
        problems.append("'A subcommand is required'")
    check(f"rast {' '.join(argv) or '(alone)'} shows rast's help", problems)
r = rast("--version")
check("rast --version", [] if r.returncode == 0 and re.match(r"rast \d+\.\d+\.\d+ \(Kokkos \d+\.\d+\.\d+, \w+ backend\)",
                                                              r.stdout) else [r.stdout + r.stderr])

# every bench (and render) option has a description: CLI11 prints "  --name TYPE   text"
for cmd in ("bench", "render"):
    text = rast(cmd, "--help").stdout
    undescribed = []
    lines = text.splitlines()
    for i, line in enumerate(lines):
        mo = re.match(r"^  (-[-\w,]+)(.*)$", line)
        if not mo:
            continue
        rest = mo.group(2)
        # the description follows the option after a run of spaces, or on the next, deeper-indented line
        has_text = re.search(r"\S\s{2,}\S", line) or (i + 1 < len(lines) and re.match(r"^ {20,}\S", lines[i + 1]))
        if not has_text:
            undescribed.append(mo.group(1))
    check(f"every {cmd} option has a description", [f"no description: {u}" for u in undescribed])

# ---- builtin scenes: described by rast info, print the camera they carry
info = rast("info").stdout
problems = []
for name in ("default", "bigtri", "tiny", "overdraw", "slivers", "nearplane", "degenerate", "extreme", "zfight", "grid"):
    mo = re.search(rf"^\s+builtin:{name}\s+(.+)$", info, re.M)
    if not mo or len(mo.group(1).split()) < 3:
        problems.append(f"builtin:{name} has no description")
check("rast info describes every builtin scene", problems)
r = rast("render", "builtin:bigtri", "--size", "64x36", "-o", os.path.join(work, "bigtri.png"))
check("a builtin scene prints the camera it carries",
      [] if re.search(r"camera \(scene\) --eye 0,0,5 --target 0,0,0", r.stdout) else [r.stdout + r.stderr])

r2 = rast("render", "builtin:bigtri", "--size", "64x36", "--fovy", "30", "-o", os.path.join(work, "b2.png"))
check("--fovy applies to a builtin scene's camera", [] if "--fovy 30 " in r2.stdout else [r2.stdout + r2.stderr])

# ---- the default scene fills the frame and has a background; tiny is not a flat grey frame
w, h, px = read_png_rgba(out)
bg = px[0:3]
ncov = 0
xs = []
for y in range(h):
    for x in range(w):
        i = 4 * (y * w + x)
        if abs(px[i] - bg[0]) + abs(px[i + 1] - bg[1]) + abs(px[i + 2] - bg[2]) > 12:
            ncov += 1
            xs.append(x)
problems = []
if sum(bg) < 60:
    problems.append(f"background {tuple(bg)} is black")
if ncov < 0.45 * w * h:
    problems.append(f"scene covers {100.0 * ncov / (w * h):.0f}% of the frame (< 45%)")
if xs and max(xs) - min(xs) < 0.9 * w:
    problems.append(f"scene spans {max(xs) - min(xs)} of {w} columns")
check("the default scene fills the frame on a non-black background", problems)
r = rast("render", "-o", os.path.join(work, "d.png"), "--size", "64x36")
check("the default scene's image is anti-aliased by default", [] if "aa msaa4" in r.stdout else [r.stdout])
tiny = os.path.join(work, "tiny.png")
r = rast("render", "builtin:tiny?n=20000", "--size", "160x90", "-o", tiny)
w, h, px = read_png_rgba(tiny)
colours = {tuple(px[i:i + 3]) for i in range(0, len(px), 4)}
hues = {(c[0] > c[2], c[1] > c[2], c[0] > c[1]) for c in colours}
check("builtin:tiny is not an empty grey frame",
      [] if len(colours) > 500 and len(hues) >= 4 else [f"{len(colours)} colours, {len(hues)} hue classes"])

# ---- output paths are checked before anything is loaded or rendered
for bad, why in ((os.path.join(work, "no", "such", "dir", "x.png"), "does not exist"),
                 (work, "is a folder")):
    r = rast("render", "builtin:tiny", "--reference", "-o", bad)
    check(f"-o {why}: refused before rendering",
          [] if r.returncode != 0 and r.stdout == "" and why in r.stderr else [f"rc {r.returncode} {r.stdout!r} {r.stderr!r}"])
r = rast("render", "--size", "32x18", "-o", os.path.join(work, "ok.png"), "--aov", "depth=" + os.path.join(work, "nope", "d.pfm"))
check("--aov path refused before rendering",
      [] if r.returncode != 0 and r.stdout == "" and "--aov" in r.stderr else [r.stdout + r.stderr])


# ---- progress on stderr only when it is a terminal
def run_on_pty(argv):
    pid, fd = pty.fork()
    if pid == 0:
        os.environ.pop("OMP_PROC_BIND", None)
        os.execv(args.rast, [args.rast] + argv)
    chunks = []
    while True:
        try:
            ready, _, _ = select.select([fd], [], [], 120)
            if not ready:
                break
            data = os.read(fd, 4096)
        except OSError:
            break
        if not data:
            break
        chunks.append(data)
    os.waitpid(pid, 0)
    return b"".join(chunks).decode("utf-8", "replace")


tty_out = run_on_pty(["bench", "builtin:grid?n=8", "--size", "64x36", "--frames", "5", "--warmup", "1"])
r = rast("bench", "builtin:grid?n=8", "--size", "64x36", "--frames", "5", "--warmup", "1")
check("bench shows progress on a terminal", [] if "frame 5/5" in tty_out else [tty_out[-300:]])
check("bench shows no progress when stderr is not a terminal",
      [] if r.returncode == 0 and "\r" not in r.stderr and "frame 5/5" not in r.stderr else [r.stderr[-300:]])
tty_out = run_on_pty(["render", "--size", "32x18", "--reference", "--reference-grid", "3", "-o", os.path.join(work, "ref.png")])
check("a reference render shows its passes on a terminal", [] if "passes 9/9" in tty_out else [tty_out[-300:]])

# ---- cmake --install puts the programs in a prefix
prefix = os.path.join(work, "prefix")
shutil.rmtree(prefix, ignore_errors=True)
r = subprocess.run(["cmake", "--install", build_dir, "--prefix", prefix], capture_output=True, text=True)
installed = os.path.join(prefix, "bin", "rast")
problems = [] if r.returncode == 0 else [r.stderr.strip()]
if not os.access(installed, os.X_OK):
    problems.append(f"{installed} missing")
else:
    v = subprocess.run([installed, "--version"], capture_output=True, text=True, env=env_without_omp())
    if not v.stdout.startswith("rast "):
        problems.append(f"installed rast --version: {v.stdout!r}")
if os.path.exists(os.path.join(build_dir, "rast-viewer")) and not os.path.exists(os.path.join(prefix, "bin", "rast-viewer")):
    problems.append("rast-viewer not installed")
check("cmake --install puts rast (and rast-viewer) in PREFIX/bin", problems)

# ---- ctest fails when no test ran; skipped tests' reasons are printed
r = subprocess.run(["ctest", "--test-dir", build_dir, "-R", "^no_such_test_at_all$", "--no-tests=error"],
                   capture_output=True, text=True)
presets = open(os.path.join(source_dir, "CMakePresets.json")).read()
check("ctest (as the presets run it) fails when no test ran",
      [] if r.returncode != 0 and re.search(r'"noTestsAction":\s*"error"', presets) else [f"rc {r.returncode}"])
skipdir = tempfile.mkdtemp(dir=work)
with open(os.path.join(skipdir, "golden_shared_models.txt"), "w") as f:
    f.write("../shared is absent\n")
r = subprocess.run(["cmake", "-DSKIP_DIR=" + skipdir, "-P", os.path.join(source_dir, "tests", "support", "skip_report.cmake")],
                   capture_output=True, text=True)
check("the skip report prints each skipped test with its reason",
      [] if "golden_shared_models: ../shared is absent" in r.stdout + r.stderr else [r.stdout + r.stderr])
custom = os.path.join(build_dir, "CTestCustom.cmake")
check("ctest runs the skip report after the tests",
      [] if os.path.exists(custom) and "skip_report.cmake" in open(custom).read() else [f"{custom} lacks it"])

print(f"{passed} passed, {failed} failed")
sys.exit(1 if failed else 0)

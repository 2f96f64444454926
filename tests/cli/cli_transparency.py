#!/usr/bin/env python3
"""glTF BLEND and MASK from the command line (docs/transparency.md): `exact`
gives the same bytes under every raster method, sample count and backend (the
OpenMP rast and its Serial twin); the unlit arithmetic check (blue at alpha 0.5
over opaque red is (0.5, 0, 0.5) in linear light, sRGB 188) holds under every
method; `--background transparent` writes straight-alpha RGBA; exact's,
sorted's and weighted's films do not depend on the number of threads (their
tile lists' order does); a bad method name is one error line; `sorted` gives the image of
the hardware rasterizer drawing the same glTF files the way engines do (BLEND
draws sorted back to front by their centre, blended premultiplied into an
RGBA32F framebuffer: scripts/measure/glblend, built here from ../shared's glref
sources, or env RAST_GLBLEND), and exact differs from it where layers intersect
or are coplanar. Exit 77 when the Serial twin was not built or glblend could not
be built or run (../shared absent, its Debian packages missing, no EGL context)."""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
import rastimg  # noqa: E402
from skip import skip  # noqa: E402
from script_args import arg_parser  # noqa: E402

ap = arg_parser()
args = ap.parse_args()
os.makedirs(args.workdir, exist_ok=True)
failures = []


def render(exe, scene, tag, *flags):
    out = os.path.join(args.workdir, tag + ".png")
    cmd = [exe, "render", scene, "--size", "160x90", "-o", out] + list(flags)
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=600)
    if r.returncode != 0:
        raise SystemExit(f"FAILED: {' '.join(cmd)}: {r.stderr.strip()}")
    return rastimg.read_png(out)[3]


def pixel(rgba, x, y, w=160):
    i = 4 * (y * w + x)
    return tuple(rgba[i:i + 3])


# The arithmetic check, every method.
for method in ["exact", "sorted", "kbuffer", "weighted", "auto"]:
    rgba = render(args.rast, "builtin:layers?n=1&alpha=0.5&unlit=1", "unlit_" + method, "--transparency", method,
                  "--shading", "pbr")
    if pixel(rgba, 80, 45) != (188, 0, 188):
        failures.append(f"{method}: blue 0.5 over red gave {pixel(rgba, 80, 45)}, expected (188, 0, 188)")

# A transparent background: RGBA, straight alpha. Two blue layers of alpha 0.5
# over nothing cover 0.75: (0, 0, 255) at alpha 191.
out = os.path.join(args.workdir, "rgba.png")
subprocess.run([args.rast, "render", "builtin:layers?n=2&alpha=0.5&back=0", "--shading", "pbr", "--background",
                "transparent", "--size", "160x90", "-o", out], check=True, capture_output=True)
rgba = rastimg.read_png(out)[3]
if tuple(rgba[4 * (45 * 160 + 80):4 * (45 * 160 + 80) + 4]) != (0, 0, 255, 191):
    failures.append(f"transparent background: {tuple(rgba[4 * (45 * 160 + 80):4 * (45 * 160 + 80) + 4])}, "
                    "expected (0, 0, 255, 191)")

# exact: the same bytes under every raster method, sample count and backend.
exes = [("openmp", args.rast)] + ([("serial", args.rast_serial)] if args.rast_serial else [])
scene = "builtin:layers?n=24&mixed=1&cross=1"
for aa in ["none", "msaa4"]:
    first = None
    for name, exe in exes:
        for method in ["naive", "visbuffer", "binned"]:
            img = render(exe, scene, f"exact_{aa}_{name}_{method}", "--transparency", "exact", "--raster", method,
                         "--aa", aa)
            if first is None:
                first = (name, method, img)
            elif img != first[2]:
                failures.append(f"exact {aa}: {name}/{method} differs from {first[0]}/{first[1]}")

# exact, sorted and weighted: the order of a block's tile list follows the
# thread schedule; the film must not (weighted sorts its lists: its sums add
# their terms in raster-index order). 40 mixed, intersecting layers (more
# than the K keys a sample keeps per pass: peeled), under 1, 2 and (where the
# machine has them; rast refuses more threads than hardware threads) 4 OpenMP
# threads.
thread_counts = ["1", "2"] + (["4"] if (os.cpu_count() or 1) >= 4 else [])
for method in ["exact", "sorted", "weighted"]:
    films = {}
    for threads in thread_counts:
        out = os.path.join(args.workdir, f"order_{method}_{threads}.pfm")
        env = dict(os.environ, OMP_NUM_THREADS=threads, OMP_PROC_BIND="false")
        cmd = [args.rast, "render", "builtin:layers?n=40&mixed=1&cross=1", "--size", "160x90", "--transparency",
               method, "-o", out]
        r = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=600)
        if r.returncode != 0:
            raise SystemExit(f"FAILED: {' '.join(cmd)}: {r.stderr.strip()}")
        with open(out, "rb") as f:
            films[threads] = f.read()
    if len(set(films.values())) != 1:
        failures.append(f"{method}: the film depends on the number of threads")

# A bad method: one error line, non-zero exit.
r = subprocess.run([args.rast, "render", scene, "--transparency", "fast", "-o", os.path.join(args.workdir, "x.png")],
                   capture_output=True, text=True)
if r.returncode == 0 or len(r.stderr.strip().splitlines()) != 1 or "transparency" not in r.stderr:
    failures.append(f"--transparency fast: rc {r.returncode}, stderr {r.stderr!r}")



def glblend_exe():
    """glblend from RAST_GLBLEND, else built from scripts/measure/glblend; (exe, None) or (None, why not)."""
    exe = os.environ.get("RAST_GLBLEND", "")
    if exe:
        return (exe, None) if os.access(exe, os.X_OK) else (None, f"RAST_GLBLEND={exe} is not an executable")
    glref_src = os.path.join(args.shared, "tools", "glref", "src") if args.shared else ""
    if not glref_src or not os.path.isfile(os.path.join(glref_src, "scene.cpp")):
        return None, f"no glref sources in {args.shared or '(no shared folder)'}/tools/glref"
    if not shutil.which("cmake") or not shutil.which("pkg-config") or \
            subprocess.run(["pkg-config", "--exists", "epoxy"]).returncode != 0:
        return None, "cmake, pkg-config or libepoxy-dev missing (scripts/setup/bootstrap.sh)"
    build = os.path.join(args.workdir, "glblend-build")
    log = os.path.join(args.workdir, "glblend-build.log")
    with open(log, "w") as lf:
        ok = subprocess.run(["cmake", "-S", os.path.join(REPO, "scripts", "measure", "glblend"), "-B", build,
                             "-DGLREF_SRC=" + glref_src], stdout=lf, stderr=subprocess.STDOUT).returncode == 0
        ok = ok and subprocess.run(["cmake", "--build", build, "-j", str(os.cpu_count() or 1)], stdout=lf,
                                   stderr=subprocess.STDOUT).returncode == 0
    exe = os.path.join(build, "glblend")
    return (exe, None) if ok and os.path.isfile(exe) else (None, f"glblend did not build (log: {log})")


REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(REPO, "scripts", "measure"))
import blend_scenes  # noqa: E402
from blend_vs_gl import camera_flags, errors, pixels_off, read_pfm  # noqa: E402

skipped = []
gl, why = glblend_exe()
if gl:
    files = os.path.join(args.workdir, "gl_scenes")
    subprocess.run([sys.executable, blend_scenes.__file__, files, "--full-screen"], check=True, capture_output=True)
    for name, cam, exact_differs in (("fullscreen_8_mixed", blend_scenes.FULL_SCREEN_CAMERA, False),
                                     ("layers_parallel", None, False), ("layers_intersecting", None, True),
                                     ("layers_coplanar", None, True)):
        path, gl_pfm = os.path.join(files, name + ".gltf"), os.path.join(args.workdir, f"gl_{name}.pfm")
        r = subprocess.run([gl, path, "--size", "160x90", "--frames", "1", "--warmup", "0", "--film", "rgba32f",
                            "--out-pfm", gl_pfm] + (cam or ["--auto-camera"]), capture_output=True, text=True,
                           timeout=300)
        if r.returncode != 0:
            why = f"glblend failed (no EGL/OpenGL context?): {(r.stderr.strip().splitlines() or [''])[-1]}"
            break
        films = {}
        for method in ("sorted", "exact"):
            out = os.path.join(args.workdir, f"gl_{name}_{method}.pfm")
            subprocess.run([args.rast, "render", path, "--size", "160x90", "--shading", "pbr", "--aa", "none",
                            "--transparency", method, "-o", out] + camera_flags(r.stdout), check=True,
                           capture_output=True)
            a, b = read_pfm(gl_pfm), read_pfm(out)
            films[method] = errors(a, b) + (pixels_off(a, b, 1e-5), pixels_off(a, b, 0.01))
        s, e = films["sorted"], films["exact"]
        print(f"glblend {name}: against rast sorted RMSE {s[0]:.2e}, max {s[1]:.2e}, {s[2]} px off by 1e-5; "
              f"against exact RMSE {e[0]:.2e}, {e[3]} px off by 0.01")
        # The same arithmetic in the same order: float rounding at most, except
        # where an edge passes a pixel centre closer than the two rasterizers' sub-pixel
        # precisions tell apart and their coverage parts (a pixel or two).
        if s[2] > 2 or (s[2] == 0 and s[0] > 1e-6):
            failures.append(f"{name}: sorted differs from the hardware's sorted blending: {s[2]} px off by 1e-5, "
                            f"RMSE {s[0]:.2e}")
        if exact_differs and e[3] < 100:
            failures.append(f"{name}: exact differs from sorted blending in only {e[3]} px (expected the order "
                            "error of intersecting or coplanar layers)")
if why:
    skipped.append("hardware blending not compared: " + why)
if not args.rast_serial:
    skipped.append("no Serial twin built: backend parity of exact not checked")

for f in failures:
    print("FAIL:", f)
if failures:
    sys.exit(1)
if skipped:
    skip(args.workdir, "; ".join(skipped) + " (the rest passed)")
print("ok: unlit arithmetic under every method; exact identical across raster methods, MSAA and backends")

#!/usr/bin/env python3
"""rast's primitive ids against the glref OpenGL reference (Mesa llvmpipe through EGL).

Runs scripts/measure/glref_compare.py (docs/glref-agreement.md), which renders every model
with glref at its auto camera, then with rast at exactly that camera, and fails
when fewer than 99.9% of the pixels carry the same primitive id:

  1. every default model (the shared .glb models when <shared>/models exists, and
     the assimp-testmodels glTF 2.0 set) at 640x360;
  2. duck and cow at 1920x1080 (when the shared models exist);
  3. the Serial build (--rast-serial, when given) on duck / box and the strip and
     fan test models at 640x360.

glref: the executable named by env RAST_GLREF, else built from
<shared>/tools/glref into <workdir>/glref-build (needs cmake, pkg-config and the
Debian packages libepoxy-dev libegl-dev libopengl-dev libgl-dev libtinygltf-dev
nlohmann-json3-dev libstb-dev libglm-dev; running it needs libegl-mesa0 and
libgl1-mesa-dri). Exit 77 (skipped) when ../shared is absent and RAST_GLREF is
unset, when glref's build dependencies are missing, or when it cannot create an
EGL/OpenGL context here. Standard library only.
"""
import os
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
COMPARE = os.path.join(REPO, "scripts", "measure", "glref_compare.py")
APT = ("libepoxy-dev libegl-dev libopengl-dev libgl-dev libtinygltf-dev nlohmann-json3-dev "
       "libstb-dev libglm-dev libegl-mesa0 libgl1-mesa-dri")

sys.path.insert(0, os.path.join(HERE, "..", "support"))
from skip import skip as skip_test
from script_args import arg_parser  # noqa: E402

args = arg_parser(assimp_default="/usr/share/assimp/models/glTF2").parse_args()

T0 = time.monotonic()
os.makedirs(args.workdir, exist_ok=True)
env = dict(os.environ)
env.setdefault("OMP_PROC_BIND", "false")


def skip(reason):
    skip_test(args.workdir, reason)


def have_header(name, subdirs=("",)):
    for base in ("/usr/include", "/usr/local/include"):
        for s in subdirs:
            if os.path.isfile(os.path.join(base, s, name)):
                return True
    return False


def build_glref(src, build):
    """Builds glref out of tree; returns the executable or calls skip()."""
    missing = []
    if not shutil.which("cmake"):
        missing.append("cmake")
    if not shutil.which("pkg-config"):
        missing.append("pkg-config")
    elif subprocess.run(["pkg-config", "--exists", "epoxy"]).returncode != 0:
        missing.append("libepoxy-dev (pkg-config epoxy)")
    for header, pkg, subdirs in (("tiny_gltf.h", "libtinygltf-dev", ("",)),
                                 ("stb_image_write.h", "libstb-dev", ("", "stb")),
                                 ("glm/glm.hpp", "libglm-dev", ("",)),
                                 ("nlohmann/json.hpp", "nlohmann-json3-dev", ("",)),
                                 ("EGL/egl.h", "libegl-dev", ("",))):
        if not have_header(header, subdirs):
            missing.append(f"{pkg} ({header})")
    if missing:
        skip(f"cannot build glref, missing: {', '.join(missing)} (apt-get install {APT})")
    exe = os.path.join(build, "glref")
    log = os.path.join(args.workdir, "glref-build.log")
    t = time.monotonic()
    with open(log, "w") as lf:
        ok = subprocess.run(["cmake", "-S", src, "-B", build, "-DCMAKE_BUILD_TYPE=Release"],
                            stdout=lf, stderr=subprocess.STDOUT).returncode == 0
        ok = ok and subprocess.run(["cmake", "--build", build, "--parallel", str(os.cpu_count() or 2)],
                                   stdout=lf, stderr=subprocess.STDOUT).returncode == 0
    if not ok or not os.path.isfile(exe):
        with open(log) as lf:
            tail = lf.read().strip().splitlines()[-15:]
        print("\n".join(tail))
        skip(f"building glref from {src} failed (log: {log})")
    print(f"glref built in {time.monotonic() - t:.1f} s: {exe}")
    return exe


# ------------------------------------------------------------------ find / build glref
shared_models = os.path.join(args.shared, "models") if args.shared else ""
have_shared = bool(args.shared) and os.path.isdir(args.shared)
glref = os.environ.get("RAST_GLREF", "")
if glref:
    if not (os.path.isfile(glref) and os.access(glref, os.X_OK)):
        print(f"FAIL: RAST_GLREF={glref} is not an executable")
        sys.exit(1)
    print(f"glref from RAST_GLREF: {glref}")
else:
    if not have_shared:
        skip(f"no shared folder ({args.shared or 'none given'}) with tools/glref, and RAST_GLREF is unset")
    src = os.path.join(args.shared, "tools", "glref")
    if not os.path.isfile(os.path.join(src, "CMakeLists.txt")):
        skip(f"{src} has no CMakeLists.txt (glref sources absent), and RAST_GLREF is unset")
    glref = build_glref(src, os.path.join(args.workdir, "glref-build"))

# A context must be possible here (Mesa's EGL + llvmpipe): probe on a tiny scene.
probe = os.path.join(args.assimp, "glTF-Asset-Generator", "Mesh_PrimitiveMode", "Mesh_PrimitiveMode_06.gltf")
if not os.path.isfile(probe):
    probe = os.path.join(shared_models, "box.glb")
if not os.path.isfile(probe):
    skip(f"no test models: neither {args.assimp} (Debian assimp-testmodels) nor {shared_models}")
p = subprocess.run([glref, probe, "--size", "16x16", "--frames", "1", "--warmup", "0"],
                   stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env, timeout=120)
out = p.stdout.decode("utf-8", "replace")
if p.returncode != 0:
    print(out.strip()[-2000:])
    skip(f"glref cannot render here (rc {p.returncode}); running it needs libegl-mesa0 libgl1-mesa-dri")
renderer = next((l.split("=", 1)[1] for l in out.splitlines() if l.startswith("glref: GL_RENDERER=")), "?")
print(f"glref renders with: {renderer}")

# ------------------------------------------------------------------ comparisons
failures = []


def compare(label, rast, size, models=None, json_name=None):
    cmd = [sys.executable, COMPARE, "--rast", rast, "--glref", glref, "--size", size,
           "--shared", shared_models if have_shared else "", "--assimp", args.assimp,
           "--out", os.path.join(args.workdir, label), "--min-agreement", "99.9",
           "--json", os.path.join(args.workdir, (json_name or label) + ".json")]
    if models:
        cmd += ["--models"] + models
    print(f"\n=== {label}: {size}, {'models ' + ' '.join(models) if models else 'all default models'}", flush=True)
    t = time.monotonic()
    rc = subprocess.run(cmd, env=env).returncode
    print(f"=== {label}: rc {rc} in {time.monotonic() - t:.1f} s", flush=True)
    if rc != 0:
        failures.append(f"{label} (rc {rc})")


compare("all-640x360", args.rast, "640x360")
if have_shared and os.path.isfile(os.path.join(shared_models, "duck.glb")):
    compare("shared-1920x1080", args.rast, "1920x1080", ["duck", "cow"])
else:
    print("\n(no shared models: the 1920x1080 duck / cow comparison is skipped)")
if args.rast_serial and os.path.isfile(args.rast_serial):
    serial_models = ["Mesh_PrimitiveMode_04", "Mesh_PrimitiveMode_12", "BoxTextured-glTF-Binary/BoxTextured"]
    if have_shared:
        serial_models = ["duck", "box"] + serial_models
    compare("serial-640x360", args.rast_serial, "640x360", serial_models)
else:
    print("\n(no --rast-serial executable: the Serial build is not compared)")

print(f"\ncli_glref_agreement: {time.monotonic() - T0:.1f} s in all")
if failures:
    print("FAIL: " + "; ".join(failures))
    sys.exit(1)
print("ok: every model at >= 99.9% primitive-id agreement with glref")

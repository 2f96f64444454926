#!/usr/bin/env python3
"""Distributed runs under OpenMPI (#41, docs/distributed.md), on oversubscribed
ranks of this machine with one thread each:

 - sort-last (`mpirun -np N rast render SCENE --distribute`): for N = 1..4 the
   image, depth, primitive ids and normals are byte-identical to a single-process render,
   over raster methods, MSAA (mixed pixels included), lines, points, wireframe,
   textured glTF files (Debian's assimp test models),
   post passes (run once, on rank 0's composited film), and builtin:tiny
   generated in part on each rank;
 - many views (`--cameras FILE --distribute`): each view's files equal the
   single-process run's;
 - failure: a rank that fails (a bad file everywhere, an injected failure on
   one rank, an unwritable output on rank 0) ends every rank promptly with one
   'rast: error: rank R:' line from rast; ranks running different builds
   (rast and its Serial twin) are refused at start;
 - transparency: alphaMode BLEND on 2 and 3 ranks is refused with one error
   (not drawn wrongly); on 1 rank it equals the single render; MASK
   (builtin:cutout, MSAA) is byte-identical on 2 and 3 ranks.
Skipped (77) when mpirun is absent or rast was built without MPI."""
import json
import os
import shutil
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from script_args import arg_parser  # noqa: E402
from cli_checks import Tally  # noqa: E402

args = arg_parser().parse_args()
os.makedirs(args.workdir, exist_ok=True)
W = args.workdir
env = dict(os.environ)
env.update({"OMP_PROC_BIND": "false", "OMP_NUM_THREADS": "1", "OMPI_ALLOW_RUN_AS_ROOT": "1",
            "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMPI_MCA_btl": "self,vader,tcp"})
env.pop("RAST_TEST_FAIL_RANK", None)
check = Tally()  # check(ok, what); check.failed counts the failures
started = time.time()
REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def p(name):
    return os.path.join(W, name)


def single(*a):
    return subprocess.run([args.rast] + [str(x) for x in a], capture_output=True, env=env, timeout=300)


def mpi(n, *a, extra_env=None, exe=None):
    e = dict(env)
    e.update(extra_env or {})
    cmd = ["mpirun", "--oversubscribe", "-np", str(n), exe or args.rast] + [str(x) for x in a]
    try:
        return subprocess.run(cmd, capture_output=True, env=e, timeout=120)
    except subprocess.TimeoutExpired:
        return None


def same(a, b):
    if not (os.path.exists(a) and os.path.exists(b)):
        return False
    with open(a, "rb") as fa, open(b, "rb") as fb:
        return fa.read() == fb.read()


mpirun = shutil.which("mpirun")
if not mpirun:
    print("SKIP: mpirun not found (Debian: openmpi-bin)")
    sys.exit(77)
probe = mpi(1, "render", "builtin:default", "--size", "8x8", "-o", p("probe.png"), "--distribute")
if probe is not None and b"built without MPI" in probe.stderr:
    print("SKIP: rast was built without MPI (RAST_MPI)")
    sys.exit(77)
check(probe is not None and probe.returncode == 0, f"mpirun -np 1 rast --distribute runs ({probe and probe.stderr[-300:]!r})")

SIZE = "96x64"


SUFFIXES = (".png", "_d.npy", "_i.npy", "_n.npy")


def outputs(tag):
    return ["-o", p(f"{tag}.png"), "--aov",
            f"depth={p(tag + '_d.npy')},primid={p(tag + '_i.npy')},normals={p(tag + '_n.npy')}"]


def identical(scene, ranks, *flags):
    r = single("render", scene, "--size", SIZE, *outputs("one"), *flags)
    if r.returncode != 0:
        check(False, f"{scene} {' '.join(flags)}: single render failed {r.stderr[-200:]!r}")
        return
    for n in ranks:
        for t in SUFFIXES:
            if os.path.exists(p("many" + t)):
                os.remove(p("many" + t))
        m = mpi(n, "render", scene, "--size", SIZE, *outputs("many"), *flags, "--distribute")
        ok = m is not None and m.returncode == 0 and all(same(p(f"one{s}"), p(f"many{s}")) for s in SUFFIXES)
        check(ok, f"{scene} {' '.join(flags)} on {n} ranks: image, depth, ids, normals byte-identical"
              + ("" if ok or m is None else f" ({m.stderr[-200:]!r})"))


identical("builtin:default", (1, 2, 3, 4), "--aa", "none")
identical("builtin:default", (2, 3), "--aa", "msaa4", "--raster", "naive")
identical("builtin:default", (4,), "--aa", "msaa8", "--raster", "visbuffer")
identical("builtin:default", (3,), "--aa", "none", "--raster", "binned")
identical("builtin:overdraw", (2, 4), "--raster", "visbuffer")
identical("builtin:lines?n=3000", (3,))
identical("builtin:points?n=3000", (2,))
identical("builtin:default", (3,), "--aa", "none", "--wireframe")
identical("builtin:default", (2,), "--aa", "msaa4", "--bloom", "--tonemap", "aces")
# glTF files: textures, many draws, normals output (Debian's assimp test models).
for model in ("BoxTextured-glTF-Binary/BoxTextured.glb", "2CylinderEngine-glTF-Binary/2CylinderEngine.glb"):
    path = os.path.join(args.assimp, model)
    if os.path.exists(path):
        identical(path, (3,), "--aa", "msaa4", "--shading", "blinn-phong")
    else:
        print(f"note: {path} absent (Debian: assimp-testmodels)")
# Generated per rank: each rank makes only the rows of the grid holding its share.
identical("builtin:tiny?n=20000", (3,), "--raster", "visbuffer")

# The float film after the post chain (run once, on rank 0).
r = single("render", "builtin:default", "--size", SIZE, "--aa", "none", "--ssao", "-o", p("film1.pfm"))
m = mpi(3, "render", "builtin:default", "--size", SIZE, "--aa", "none", "--ssao", "-o", p("film3.pfm"), "--distribute")
check(r.returncode == 0 and m is not None and m.returncode == 0 and same(p("film1.pfm"), p("film3.pfm")),
      "--ssao to a .pfm film on 3 ranks equals the single render")

# Many views spread over the ranks: each view's file as a single run writes it.
with open(p("cams.json"), "w") as f:
    json.dump([{"eye": [0, 0.5, 4 + k * 0.3], "target": [0, 0, 0]} for k in range(5)], f)
r = single("render", "builtin:default", "--size", "48x32", "--cameras", p("cams.json"), "-o", p("v1_%02d.png"))
m = mpi(2, "render", "builtin:default", "--size", "48x32", "--cameras", p("cams.json"), "-o", p("v2_%02d.png"),
        "--distribute")
check(r.returncode == 0 and m is not None and m.returncode == 0 and
      all(same(p(f"v1_{k:02d}.png"), p(f"v2_{k:02d}.png")) for k in range(5)),
      "--cameras over 2 ranks: 5 views, each equal to the single run's")


def one_rast_error(res, words):
    """One 'rast: error:' line (mpirun adds its own notice), non-zero exit, no hang."""
    if res is None:
        return ["hung (killed after 120 s)"]
    err = res.stderr.decode("utf-8", "replace")
    lines = [ln for ln in err.split("\n") if ln.startswith("rast: error:")]
    probs = []
    if res.returncode == 0:
        probs.append("exit status 0")
    if len(lines) != 1:
        probs.append(f"{len(lines)} 'rast: error:' lines: {err[:400]!r}")
    for w in words:
        if not any(w in ln for ln in lines):
            probs.append(f"no {w!r} in {lines!r}")
    return probs


t0 = time.time()
res = mpi(3, "render", p("missing.glb"), "-o", p("x.png"), "--distribute")
probs = one_rast_error(res, ["rank 0:", "missing.glb"])
check(not probs, f"a missing scene on every rank: one error naming rank 0 {probs}")
res = mpi(3, "render", "builtin:default", "--size", SIZE, "-o", p("y.png"), "--distribute",
          extra_env={"RAST_TEST_FAIL_RANK": "2"})
probs = one_rast_error(res, ["rank 2:", "injected failure"])
check(not probs and not os.path.exists(p("y.png")), f"rank 2 alone fails: every rank ends, one error naming rank 2 {probs}")
os.makedirs(p("ro"), exist_ok=True)
res = mpi(2, "render", "builtin:default", "--size", SIZE, "-o", p("nodir/z.png"), "--distribute")
probs = one_rast_error(res, ["rank 0:"])
check(not probs, f"an output rank 0 cannot write: every rank ends, one error {probs}")
res = mpi(2, "render", "builtin:default", "--size", "16x16", "-o", p("w.png"), "--distribute",
          extra_env={"RAST_COMPOSITE": "nccl"})
probs = one_rast_error(res, ["RAST_COMPOSITE=nccl", "rank 0:"])
check(not probs, f"RAST_COMPOSITE=nccl where NCCL cannot run: one error naming the rank and the reason {probs}")
check(time.time() - t0 < 60, f"failures end within a minute ({time.time() - t0:.1f} s)")

# alphaMode BLEND is composited on one device only (docs/transparency.md): a
# split run that meets BLEND triangles is refused with one error, not drawn
# wrongly (each rank blended its own share over the pixels it owned). One rank
# splits nothing and renders as one process does.
subprocess.run([sys.executable, os.path.join(REPO, "scripts", "measure", "blend_scenes.py"), p("blend")], check=True,
               capture_output=True)
for scene in ("builtin:layers?n=8&mixed=1", p("blend/layers_intersecting.gltf")):
    for n in (2, 3):
        if os.path.exists(p("blend.png")):
            os.remove(p("blend.png"))
        res = mpi(n, "render", scene, "--size", SIZE, "--shading", "pbr", "-o", p("blend.png"), "--distribute")
        probs = one_rast_error(res, ["BLEND", "--distribute"])
        check(not probs and not os.path.exists(p("blend.png")),
              f"BLEND ({os.path.basename(scene)}) on {n} ranks: refused with one error, nothing written {probs}")
identical("builtin:layers?n=8&mixed=1", (1,), "--shading", "pbr")
# MASK's keys are composited like opaque ones (alpha-to-coverage under MSAA).
identical("builtin:cutout", (2, 3), "--aa", "msaa4")


def knows_distribute(exe):
    h = subprocess.run([exe, "help", "render"], capture_output=True, env=env, timeout=60)
    return b"--distribute" in h.stdout


if args.rast_serial and os.path.exists(args.rast_serial) and knows_distribute(args.rast_serial):
    cmd = ["mpirun", "--oversubscribe", "-np", "1", args.rast, "render", "builtin:default", "--size", "8x8", "-o",
           p("b.png"), "--distribute", ":", "-np", "1", args.rast_serial, "render", "builtin:default", "--size", "8x8",
           "-o", p("b.png"), "--distribute"]
    try:
        res = subprocess.run(cmd, capture_output=True, env=env, timeout=120)
    except subprocess.TimeoutExpired:
        res = None
    probs = one_rast_error(res, ["rank 1", "same build"])
    check(not probs, f"ranks running different builds (rast, rast-serial) are refused at start {probs}")
else:
    print("note: no Serial twin with --distribute; the different-builds check is not run")

print(f"{time.time() - started:.1f} s")
sys.exit(1 if check.failed else 0)

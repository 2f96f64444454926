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
 - transparency: alphaMode BLEND (rank 0 holds every BLEND draw whole and
   composites them over the composited opaque depth) on 1, 2 and 3 ranks:
   exact, sorted and kbuffer (k >= layers) give the single render's image, ids,
   depth, normals and film (PFM) bytes, with and without MSAA, lit and unlit,
   with opaque geometry in front of and between the layers held by the last
   rank, draws cut by the shares, wireframe and line polygon modes; so does
   weighted's film (its sums in raster-index order); MASK (builtin:cutout,
   MSAA) byte-identical.
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
import rastimg  # noqa: E402

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

# alphaMode BLEND (docs/distributed.md, "Transparency"): rank 0 holds every
# BLEND draw whole and composites them after the merge, over the composited
# keys' opaque depth; the others keep theirs marked and run no BLEND pass.
# layers_occluded has an opaque quad through the layers that the last rank
# draws: an opaque depth read from rank 0's own keys would miss it.
subprocess.run([sys.executable, os.path.join(REPO, "scripts", "measure", "blend_scenes.py"), p("blend")], check=True,
               capture_output=True)
OCCLUDED = p("blend/layers_occluded.gltf")


def film_close(scene, ranks, tol, *flags):
    """The linear film (-o F.pfm): byte-identical (tol 0) or within tol per channel."""
    r = single("render", scene, "--size", SIZE, "-o", p("film_one.pfm"), *flags)
    for n in ranks:
        if os.path.exists(p("film_many.pfm")):
            os.remove(p("film_many.pfm"))
        m = mpi(n, "render", scene, "--size", SIZE, "-o", p("film_many.pfm"), *flags, "--distribute")
        ok = r.returncode == 0 and m is not None and m.returncode == 0 and os.path.exists(p("film_many.pfm"))
        what = "byte-identical" if tol == 0 else f"within {tol}"
        if ok and tol == 0:
            ok = same(p("film_one.pfm"), p("film_many.pfm"))
        elif ok:
            a, b = rastimg.read_pfm(p("film_one.pfm")), rastimg.read_pfm(p("film_many.pfm"))
            ok = a[:2] == b[:2] and max(abs(x - y) for x, y in zip(a[3], b[3])) <= tol
        check(ok, f"{os.path.basename(scene)} {' '.join(flags)} on {n} ranks: film {what}"
              + ("" if ok or m is None else f" ({m.stderr[-200:]!r})"))


for scene in ("builtin:layers?n=8&mixed=1", OCCLUDED):
    for method in ("exact", "sorted", "kbuffer"):
        identical(scene, (1, 2, 3) if method == "exact" else (2, 3), "--shading", "pbr", "--transparency", method)
film_close(OCCLUDED, (2, 3), 0, "--shading", "pbr", "--transparency", "exact")
film_close(OCCLUDED, (3,), 0, "--shading", "pbr", "--transparency", "sorted", "--aa", "msaa4")
film_close(OCCLUDED, (2,), 0, "--shading", "pbr", "--transparency", "kbuffer", "--aa", "msaa4")
film_close(OCCLUDED, (2, 3), 0, "--shading", "pbr", "--transparency", "weighted", "--aa", "msaa4")
identical(OCCLUDED, (2, 3), "--shading", "pbr", "--transparency", "exact", "--aa", "msaa4")
# Lit layers that intersect, the draws cut by the shares (16 triangles over 3 ranks).
identical("builtin:layers?n=7&mixed=1&cross=1", (3,), "--transparency", "sorted", "--aa", "msaa4")
identical("builtin:layers?n=7&mixed=1&cross=1", (2,), "--transparency", "exact", "--shading", "blinn-phong")
# A textured glTF file with BLEND and opaque materials (Debian's assimp test models).
clearcoat = os.path.join(args.assimp, "ClearCoat-glTF/ClearCoatTest.gltf")
if os.path.exists(clearcoat):
    identical(clearcoat, (3,), "--shading", "pbr", "--transparency", "exact", "--aa", "msaa4")
else:
    print(f"note: {clearcoat} absent (Debian: assimp-testmodels)")
# Edges of every triangle: rank 0's whole BLEND draws map to global edge items.
identical("builtin:layers?n=7&mixed=1", (2, 3), "--wireframe")
identical("builtin:layers?n=7&mixed=1", (3,), "--polygon", "line")
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

#!/usr/bin/env python3
"""Skinned, animated models written by `rast export` rendered where linear blend skinning puts
them (#40, docs/animation.md):

 - builtin:skin-arm and builtin:skin-tail exported (scripts/measure/skinned_models.py runs
   `rast export`), each at two times, orthographic, cover exactly the box of their vertices
   skinned here, independently of rast, from the script's Python description of the models:
   joint world matrices from the keys (LINEAR with quaternion slerp, CUBICSPLINE with tangents
   scaled by the key interval), Σ w · J · IBM · v, the skinned node's own transform ignored;
   the box in pixels may differ by one at an edge;
 - the same models written by the script with weights that do not sum to 1 (--raw-weights)
   render the same bytes (float weights summing to 2) or the same box (normalised shorts
   summing to 0.5), as rast scales weights to sum 1 at load;
 - round trip: a skinned, morphed, animated glTF (the fuzz seed anim_skin_morph.gltf, and
   simple_skin from assimp-testmodels when installed) exported by rast and read back renders
   the same primitive ids and depth as the original at two times of its animation.
A joint order, a parent applied twice, a tangent unscaled, weights left unnormalised, the
mesh node's translation applied, or a skin, target or channel the exporter drops moves an
edge by many pixels. Standard library only."""
import math
import os
import re
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "support"))
sys.path.insert(0, os.path.join(HERE, "..", "..", "scripts", "measure"))
from cli_checks import Tally, cli_setup  # noqa: E402
from rastimg import read_png_rgba  # noqa: E402
import skinned_models as sm  # noqa: E402

args, env = cli_setup()
check = Tally()  # check(ok, what); check.failed counts the failures


# The view: orthographic, x and y in [-2, 3], 160 x 160 pixels (32 a unit).
SIZE, LO, SPAN = 160, -2.0, 5.0
CAM = ["--ortho", "2.5", "--eye", "0.5,0.5,10", "--target", "0.5,0.5,0", "--up", "0,1,0", "--near", "1",
       "--far", "20", "--size", f"{SIZE}x{SIZE}", "--aa", "none", "--background", "1,0,1"]


# --- skinning, by hand -------------------------------------------------------------------

def mat_mul(a, b):
    return [[sum(a[r][k] * b[k][c] for k in range(4)) for c in range(4)] for r in range(4)]


def trs(t, q, s):
    x, y, z, w = q
    r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    return [[r[i][0] * s[0], r[i][1] * s[1], r[i][2] * s[2], t[i]] for i in range(3)] + [[0, 0, 0, 1]]


def normalised(q):
    n = math.sqrt(sum(c * c for c in q))
    return [c / n for c in q]


def sample(interp, times, values, width, t):
    """glTF 2.0, 3.11: clamped outside the keys; LINEAR (slerp for rotations), CUBICSPLINE."""
    cubic = interp == "CUBICSPLINE"
    stride = 3 * width if cubic else width
    val = lambda k: values[k * stride + (width if cubic else 0):][:width]  # noqa: E731
    if t <= times[0]:
        return val(0)
    if t >= times[-1]:
        return val(len(times) - 1)
    k = max(i for i in range(len(times)) if times[i] <= t)
    dt = times[k + 1] - times[k]
    u = (t - times[k]) / dt
    a, b = val(k), val(k + 1)
    if cubic:
        out_t = values[k * stride + 2 * width:][:width]
        in_t = values[(k + 1) * stride:][:width]
        h00, h10, h01, h11 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u, -2 * u**3 + 3 * u**2, u**3 - u**2
        p = [h00 * a[j] + h10 * dt * out_t[j] + h01 * b[j] + h11 * dt * in_t[j] for j in range(width)]
        return normalised(p) if width == 4 else p
    if width == 4:
        d = sum(x * y for x, y in zip(a, b))
        if d < 0:
            b, d = [-c for c in b], -d
        th = math.acos(min(1.0, d))
        if th < 1e-9:
            return a
        return normalised([(math.sin((1 - u) * th) * x + math.sin(u * th) * y) / math.sin(th) for x, y in zip(a, b)])
    return [x * (1 - u) + y * u for x, y in zip(a, b)]


def skinned_box(kind, t):
    """The box (x0, y0, x1, y1) of the model's vertices posed at t."""
    rest = [list(map(list, j)) for j in sm.JOINTS]  # per joint: T, R, S
    for node, path, interp, times, values in sm.ANIMATIONS[kind]:
        v = sample(interp, times, values, 4 if path == "rotation" else 3, t)
        rest[node - 1][{"translation": 0, "rotation": 1, "scale": 2}[path]] = v
    world, parent = [], None
    for tr, q, s in rest:  # a chain: root, middle, tip
        local = trs(tr, q, s)
        parent = local if parent is None else mat_mul(parent, local)
        world.append(parent)
    # Inverse bind matrices: translations by -k along x (relative to the root).
    joint = [mat_mul(world[k], trs((-float(k), 0, 0), (0, 0, 0, 1), (1, 1, 1))) for k in range(3)]
    pos, _, _, xs = sm.tube()
    pts = []
    for i, x in enumerate(xs):
        v = pos[3 * i:3 * i + 3] + [1.0]
        w = sm.weights(x)
        pts.append([sum(w[k] * sum(joint[k][r][c] * v[c] for c in range(4)) for k in range(3)) for r in range(2)])
    return (min(p[0] for p in pts), min(p[1] for p in pts), max(p[0] for p in pts), max(p[1] for p in pts))


def expected_pixels(box):
    """The pixels (col0, row0, col1, row1) whose centres lie inside the box (rows from the top)."""
    x0, y0, x1, y1 = box
    px = SIZE / SPAN
    col0 = math.floor((x0 - LO) * px - 0.5) + 1
    col1 = math.ceil((x1 - LO) * px - 0.5) - 1
    row0 = math.floor((LO + SPAN - y1) * px - 0.5) + 1
    row1 = math.ceil((LO + SPAN - y0) * px - 0.5) - 1
    return col0, row0, col1, row1


def covered_pixels(path):
    w, h, rgba = read_png_rgba(path)
    cols, rows = [], []
    for y in range(h):
        for x in range(w):
            r, g, b = rgba[4 * (y * w + x):4 * (y * w + x) + 3]
            if (r, g, b) != (255, 0, 255):
                cols.append(x)
                rows.append(y)
    return (min(cols), min(rows), max(cols), max(rows)) if cols else None


def render(scene, t, out):
    r = subprocess.run([args.rast, "render", scene, "--time", str(t), *CAM, "-o", out], capture_output=True, text=True,
                       env=env, timeout=600)
    check(r.returncode == 0, f"{os.path.basename(scene)} --time {t} renders ({r.stderr.strip()})")
    with open(out, "rb") as f:
        return f.read() if r.returncode == 0 else b""


models = dict(zip(("arm", "tail"), sm.write(args.workdir, rast=args.rast, env=env)))
raw = dict(zip(("arm", "tail"), sm.write(args.workdir, raw=True)))
for kind, times in (("arm", (0, 1.5)), ("tail", (0.5, 1.4))):
    for t in times:
        png = os.path.join(args.workdir, f"{kind}_t{t}.png")
        image = render(models[kind], t, png)
        want = expected_pixels(skinned_box(kind, t))
        got = covered_pixels(png) if image else None
        check(got is not None and all(abs(g - e) <= 1 for g, e in zip(got, want)),
              f"{kind} at t={t} covers columns {want[0]}..{want[2]}, rows {want[1]}..{want[3]} (got {got})")
        raw_png = os.path.join(args.workdir, f"{kind}_raw_t{t}.png")
        raw_image = render(raw[kind], t, raw_png)
        if kind == "arm":  # float weights summing to 2: scaled to exactly the written ones
            check(image and raw_image == image, f"arm at t={t}: weights summing to 2 render the same bytes (scaled at load)")
        else:  # normalised shorts summing to 0.5: the same box (their rounding differs)
            got = covered_pixels(raw_png) if raw_image else None
            check(got is not None and all(abs(g - e) <= 1 for g, e in zip(got, want)),
                  f"tail at t={t}: weights summing to 0.5 cover the same box (got {got})")
# The poses differ from the rest pose by far more than the tolerance: the checks above can fail.
rest = expected_pixels(skinned_box("arm", 0))
bent = expected_pixels(skinned_box("arm", 1.5))
check(abs(rest[1] - bent[1]) > 20, f"the arm's top edge moves between t=0 and t=1.5 ({rest[1]} -> {bent[1]})")


# --- round trip: export, read back, the same ids and depth ------------------------------

def render_views(scene, t, tag, cam=None):
    """Primitive ids and depth (bytes) of the scene at t, and the camera flags rast chose."""
    out = os.path.join(args.workdir, tag)
    view = cam or ["--size", "96x96"]
    r = subprocess.run([args.rast, "render", scene, "--time", str(t), "--aa", "none", *view, "-o", out + ".png",
                        "--aov", f"depth={out}.pfm,primid={out}.bin"], capture_output=True, text=True, env=env, timeout=600)
    check(r.returncode == 0, f"{os.path.basename(scene)} --time {t} renders ({r.stderr.strip()[:200]})")
    if r.returncode != 0:
        return None, None, None
    m = re.search(r"(--eye \S+ --target \S+ --up \S+ --fovy \S+ --near \S+ --far \S+)", r.stdout + r.stderr)
    with open(out + ".bin", "rb") as f_ids, open(out + ".pfm", "rb") as f_depth:
        return f_ids.read(), f_depth.read(), (["--size", "96x96"] + m.group(1).split() if m else None)


here = os.path.dirname(os.path.abspath(__file__))
sources = [(os.path.join(here, "..", "fuzz", "corpus", "anim_skin_morph.gltf"), (0.25, 0.8))]
simple_skin = "/usr/share/assimp/models/glTF2/simple_skin/simple_skin.gltf"
if os.path.exists(simple_skin):
    sources.append((simple_skin, (1.0, 2.5)))
else:
    print(f"skip: {simple_skin} is absent (Debian's assimp-testmodels); the round trip of the fuzz seed still runs")
for src, times in sources:
    name = os.path.splitext(os.path.basename(src))[0]
    glb = os.path.join(args.workdir, name + "_export.glb")
    r = subprocess.run([args.rast, "export", src, "-o", glb], capture_output=True, text=True, env=env, timeout=600)
    if not check(r.returncode == 0, f"rast export {name} ({r.stderr.strip()[:200]})"):
        continue
    _, _, cam = render_views(src, times[0], f"{name}_framing")  # one camera, rast's framing at the first time
    if not check(cam is not None, f"{name}: rast printed its camera"):
        continue
    depths = []
    for t in times:
        ids0, depth0, _ = render_views(src, t, f"{name}_src_t{t}", cam)
        ids1, depth1, _ = render_views(glb, t, f"{name}_export_t{t}", cam)
        check(ids0 is not None and ids0 == ids1 and depth0 == depth1,
              f"{name} at t={t}: the export renders the same primitive ids and depth as the original")
        depths.append(depth1)
    # The two times pose the model differently: a pose the export lost would show.
    check(len(depths) == 2 and depths[0] != depths[1], f"{name}: its two times give different depth")
sys.exit(1 if check.failed else 0)

#!/usr/bin/env python3
"""Skinned, animated test models for the accuracy comparison with the Khronos Sample Renderer.

Why: issue #40 asks for silhouettes agreeing with the Sample Renderer on skinned/animated models
built with rast's exporter, with joint hierarchies, scaled joints, non-normalised weights fixed as
the spec says and cubic-spline tangents. The models are rast's built-in scenes builtin:skin-arm
and builtin:skin-tail (scenes/skinned_scenes.cpp), written by `rast export`; this script runs
the export, and describes the same models in Python (tube, joints, keys, weights) so that
tests/cli/cli_skinned_models.py can skin them by hand, independently of rast. docs/animation.md
has the figures.

    skinned_models.py OUT_DIR --rast build/openmp/rast     # skin_arm.glb, skin_tail.glb (rast export)
    skinned_models.py OUT_DIR --raw-weights                # skin_arm_raw.gltf, skin_tail_raw.gltf

Both models are a tube of radius 0.2 along x in [0, 3] (8 sides, a ring every 0.25), skinned to a
chain of three joints: the root (translation (-1.5, -0.5, 0), uniform scale 1.25), a joint at
x = 1 and one at x = 2, with inverse bind matrices relative to the root, so the rest pose is
the root's transform of the tube. The mesh's own node has a translation the spec says to ignore.
Weights come from a falloff around each joint; they do not sum to 1 (they sum to 2) and are
scaled to 1 before writing, as glTF 2.0 (3.7.3.3) requires (rast's exporter writes every
skin's weights so). --raw-weights writes the weights as they are, with this script's own
writer (rast's exporter cannot: it fixes them), for the loader's own fix: float weights
summing to 2, or normalised unsigned shorts summing to 0.5 (they cannot exceed 1).

 - skin_arm: the middle joint rotates about z, LINEAR (0, 90, 30, -45 degrees at t = 0..3);
   the tip joint scales non-uniformly, LINEAR ((1.4, 0.7, 1) at t = 2, 1 at 0, 1 and 3).
 - skin_tail: CUBICSPLINE rotation of the middle joint about z and translation of the tip
   joint, with non-zero tangents, keys at t = 0, 0.8 and 2 (intervals of different lengths, so
   that tangents scaled by the wrong interval show).
The exported files hold unsigned short joints and float weights; the raw files unsigned short
joints with float weights (arm) and unsigned byte joints with normalised unsigned short weights
(tail).
"""
import argparse, base64, json, math, os, struct, subprocess

RADIUS, SIDES, RINGS = 0.2, 8, 13  # rings at x = 0, 0.25, ..., 3
ROOT_T, ROOT_S = (-1.5, -0.5, 0.0), 1.25


def raw_weights(x):
    """Falloff around the joints at x = 0, 1, 2: (j0, j1, j2), summing to 2."""
    if x <= 0.5:
        w = (1.0, 0.0, 0.0)
    elif x < 1.5:
        w = (1.5 - x, x - 0.5, 0.0)
    elif x < 2.5:
        w = (0.0, 2.5 - x, x - 1.5)
    else:
        w = (0.0, 0.0, 1.0)
    return tuple(2.0 * c for c in w)


def quat_z(deg):
    h = math.radians(deg) / 2
    return [0.0, 0.0, math.sin(h), math.cos(h)]


# Per model, its channels: (node, path, interpolation, key times, output values); CUBICSPLINE
# outputs hold in-tangent, value, out-tangent per key (glTF 2.0, 3.11.2). Nodes: 1 root, 2 middle, 3 tip.
ANIMATIONS = {
    'arm': [(2, 'rotation', 'LINEAR', [0, 1, 2, 3], quat_z(0) + quat_z(90) + quat_z(30) + quat_z(-45)),
            (3, 'scale', 'LINEAR', [0, 1, 2, 3], [1, 1, 1, 1, 1, 1, 1.4, 0.7, 1, 1, 1, 1])],
    'tail': [(2, 'rotation', 'CUBICSPLINE', [0, 0.8, 2],
              [0, 0, 0.6, 0] + quat_z(0) + [0, 0, 0.6, 0] +
              [0, 0, -0.4, 0] + quat_z(70) + [0, 0, -0.4, 0] +
              [0, 0, 0.3, 0] + quat_z(-20) + [0, 0, 0.3, 0]),
             (3, 'translation', 'CUBICSPLINE', [0, 0.8, 2],
              [0, 1.5, 0] + [1, 0, 0] + [0, 1.5, 0] +
              [-1, 0, 0] + [1.2, 0.3, 0] + [-1, 0, 0] +
              [0.5, -2, 0] + [1, 0, 0] + [0.5, -2, 0])],
}
# The joints' rest transforms (translation, rotation x y z w, scale), nodes 1 to 3.
JOINTS = [(ROOT_T, (0, 0, 0, 1), (ROOT_S,) * 3), ((1.0, 0, 0), (0, 0, 0, 1), (1, 1, 1)), ((1.0, 0, 0), (0, 0, 0, 1), (1, 1, 1))]


def weights(x, raw=False):
    """A vertex's weights on the three joints, as written (scaled to sum 1 unless raw)."""
    w = raw_weights(x)
    return w if raw else tuple(c / sum(w) for c in w)


def tube():
    pos, nrm, idx, xs = [], [], [], []
    for r in range(RINGS):
        x = r * 0.25
        for s in range(SIDES):
            a = 2 * math.pi * s / SIDES
            pos += [x, RADIUS * math.cos(a), RADIUS * math.sin(a)]
            nrm += [0.0, math.cos(a), math.sin(a)]
            xs.append(x)
    for r in range(RINGS - 1):
        for s in range(SIDES):
            a, b = r * SIDES + s, r * SIDES + (s + 1) % SIDES
            c, d = a + SIDES, b + SIDES
            idx += [a, b, d, a, d, c]
    return pos, nrm, idx, xs


class Doc:
    def __init__(self):
        self.blob, self.views, self.accessors = b'', [], []

    def add(self, data, ctype, count, kind, normalized=False, minmax=None):
        self.views.append({'buffer': 0, 'byteOffset': len(self.blob), 'byteLength': len(data)})
        self.blob += data + b'\0' * (-len(data) % 4)
        acc = {'bufferView': len(self.views) - 1, 'componentType': ctype, 'count': count, 'type': kind}
        if normalized:
            acc['normalized'] = True
        if minmax:
            acc['min'], acc['max'] = minmax
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def floats(self, values, kind, per):
        return self.add(struct.pack(f'<{len(values)}f', *values), 5126, len(values) // per, kind)


def model(kind, raw=False):
    pos, nrm, idx, xs = tube()
    nv = len(xs)
    d = Doc()
    attrs = {'POSITION': d.add(struct.pack(f'<{len(pos)}f', *pos), 5126, nv, 'VEC3',
                               minmax=([0.0, -RADIUS, -RADIUS], [3.0, RADIUS, RADIUS])),
             'NORMAL': d.floats(nrm, 'VEC3', 3)}
    weights_ = [weights(x, raw) + (0.0,) for x in xs]
    joints = [(0, 1, 2, 0)] * nv
    if kind == 'arm':
        attrs['JOINTS_0'] = d.add(b''.join(struct.pack('<4H', *j) for j in joints), 5123, nv, 'VEC4')
        attrs['WEIGHTS_0'] = d.floats([c for w in weights_ for c in w], 'VEC4', 4)
    else:
        attrs['JOINTS_0'] = d.add(b''.join(struct.pack('<4B', *j) for j in joints), 5121, nv, 'VEC4')
        scale = 0.25 if raw else 1.0  # raw: summing to 0.5 (normalised integers stop at 1)
        attrs['WEIGHTS_0'] = d.add(b''.join(struct.pack('<4H', *(round(c * scale * 65535) for c in w))
                                            for w in weights_), 5123, nv, 'VEC4', normalized=True)
    indices = d.add(struct.pack(f'<{len(idx)}H', *idx), 5123, len(idx), 'SCALAR')
    ibm = []
    for k in range(3):  # relative to the root: translation by -k along x
        ibm += [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, -float(k), 0, 0, 1]
    ibm_acc = d.floats(ibm, 'MAT4', 16)
    nodes = [{'name': 'tube', 'mesh': 0, 'skin': 0, 'translation': [5.0, 0.0, 0.0]},  # ignored (3.7.3.3)
             {'name': 'root', 'translation': list(ROOT_T), 'scale': [ROOT_S] * 3, 'children': [2]},
             {'name': 'middle', 'translation': [1.0, 0.0, 0.0], 'children': [3]},
             {'name': 'tip', 'translation': [1.0, 0.0, 0.0]}]
    samplers, channels = [], []
    for node, path, interp, times, values in ANIMATIONS[kind]:
        width = 4 if path == 'rotation' else 3
        samplers.append({'input': d.floats(times, 'SCALAR', 1), 'output': d.floats(values, 'VEC4' if width == 4 else 'VEC3', width),
                         'interpolation': interp})
        channels.append({'sampler': len(samplers) - 1, 'target': {'node': node, 'path': path}})
    return {'asset': {'version': '2.0', 'generator': 'rast scripts/measure/skinned_models.py --raw-weights'},
            'scene': 0, 'scenes': [{'nodes': [0, 1]}], 'nodes': nodes,
            'meshes': [{'primitives': [{'attributes': attrs, 'indices': indices,
                                        'material': 0}]}],
            'materials': [{'pbrMetallicRoughness': {'baseColorFactor': [0.8, 0.8, 0.8, 1], 'metallicFactor': 0.0},
                           'doubleSided': True}],
            'skins': [{'joints': [1, 2, 3], 'inverseBindMatrices': ibm_acc, 'skeleton': 1}],
            'animations': [{'name': kind, 'samplers': samplers, 'channels': channels}],
            'accessors': d.accessors, 'bufferViews': d.views,
            'buffers': [{'byteLength': len(d.blob),
                         'uri': 'data:application/octet-stream;base64,' + base64.b64encode(d.blob).decode()}]}


def write(out_dir, raw=False, rast=None, env=None):
    """Writes the two models; their paths (arm, tail). Exported by rast (skin_arm.glb,
    skin_tail.glb: `rast export builtin:skin-arm`), or with raw weights by this script
    (skin_arm_raw.gltf, skin_tail_raw.gltf)."""
    os.makedirs(out_dir, exist_ok=True)
    paths = []
    for kind in ('arm', 'tail'):
        if raw:
            p = os.path.join(out_dir, f'skin_{kind}_raw.gltf')
            with open(p, 'w') as f:
                json.dump(model(kind, raw), f)
        else:
            if not rast:
                raise SystemExit('skinned_models: --rast is needed to export the models')
            p = os.path.join(out_dir, f'skin_{kind}.glb')
            r = subprocess.run([rast, 'export', f'builtin:skin-{kind}', '-o', p], capture_output=True, text=True, env=env)
            if r.returncode != 0:
                raise SystemExit(f'skinned_models: rast export builtin:skin-{kind} failed: {r.stderr.strip()}')
        paths.append(p)
    return paths


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('out_dir')
    ap.add_argument('--raw-weights', action='store_true', help='weights summing to 2, as they are (this script writes them)')
    ap.add_argument('--rast', help='the rast executable that exports the models')
    a = ap.parse_args()
    for p in write(a.out_dir, a.raw_weights, a.rast):
        print(p)


if __name__ == '__main__':
    main()

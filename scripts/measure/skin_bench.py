#!/usr/bin/env python3
"""What skinning costs the vertex stage: the same grid mesh (N x N vertices) drawn plain and
skinned (4 joints a vertex, weights not all equal), bent and at rest (the same geometry as
the plain mesh, so the frames differ by the skinning alone), timed by `rast bench --json`.

Why: docs/animation.md promises that skinning keeps the vertex stage within 2x of the unskinned
one on the CPU (issue #40) and that scenes without skins pay nothing; this measures both.

    skin_bench.py --rast build/openmp/rast [--n 1000] [--size 1920x1080] [--frames 30] [--out rows.csv]

Writes the two .glb files into a temporary folder; prints the vertex stage and frame medians.
"""
import argparse, csv, json, math, os, struct, subprocess, tempfile


def grid_glb(path, n, skinned, bent=True):
    nv = n * n
    pos = bytearray()
    for y in range(n):
        for x in range(n):
            pos += struct.pack('<3f', x / (n - 1) * 2 - 1, y / (n - 1) * 2 - 1, 0.0)
    idx = bytearray()
    for y in range(n - 1):
        for x in range(n - 1):
            a = y * n + x
            idx += struct.pack('<6I', a, a + 1, a + n + 1, a, a + n + 1, a + n)
    nrm = struct.pack('<3f', 0, 0, 1) * nv
    parts = [bytes(pos), nrm, bytes(idx)]
    attrs = {'POSITION': 0, 'NORMAL': 1}
    acc = [{'bufferView': 0, 'componentType': 5126, 'count': nv, 'type': 'VEC3', 'min': [-1, -1, 0], 'max': [1, 1, 0]},
           {'bufferView': 1, 'componentType': 5126, 'count': nv, 'type': 'VEC3'},
           {'bufferView': 2, 'componentType': 5125, 'count': len(idx) // 4, 'type': 'SCALAR'}]
    doc = {'asset': {'version': '2.0'}, 'scene': 0, 'scenes': [{'nodes': [0]}], 'nodes': [{'mesh': 0}],
           'meshes': [{'primitives': [{'attributes': attrs, 'indices': 2}]}]}
    if skinned:
        joints, weights = bytearray(), bytearray()
        for y in range(n):
            for x in range(n):
                s = x / (n - 1) * 3  # four joints along x, blended
                j0 = min(int(s), 2)
                f = s - j0
                joints += struct.pack('<4H', j0, j0 + 1, (j0 + 2) % 4, (j0 + 3) % 4)
                weights += struct.pack('<4f', 0.7 * (1 - f), 0.7 * f, 0.2, 0.1)
        ibm = b''.join(struct.pack('<16f', 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1 - 2 * k / 3, 0, 0, 1) for k in range(4))
        parts += [bytes(joints), bytes(weights), ibm]
        attrs.update({'JOINTS_0': 3, 'WEIGHTS_0': 4})
        acc += [{'bufferView': 3, 'componentType': 5123, 'count': nv, 'type': 'VEC4'},
                {'bufferView': 4, 'componentType': 5126, 'count': nv, 'type': 'VEC4'},
                {'bufferView': 5, 'componentType': 5126, 'count': 4, 'type': 'MAT4'}]
        # bent=False: the joints at their bind pose, so the skinned mesh lies
        # where the plain one does and the frames differ by the skinning alone.
        c, s = (math.cos(0.15), math.sin(0.15)) if bent else (1.0, 0.0)
        doc['nodes'] = [{'mesh': 0, 'skin': 0}, {'children': [2], 'translation': [-1, 0, 0]},
                        {'children': [3], 'translation': [2 / 3, 0, 0], 'rotation': [0, 0, s, c]},
                        {'children': [4], 'translation': [2 / 3, 0, 0], 'rotation': [0, 0, s, c]},
                        {'translation': [2 / 3, 0, 0], 'rotation': [0, 0, s, c]}]
        doc['scenes'] = [{'nodes': [0, 1]}]
        doc['skins'] = [{'joints': [1, 2, 3, 4], 'inverseBindMatrices': 5}]
    views, blob = [], b''
    for p in parts:
        views.append({'buffer': 0, 'byteOffset': len(blob), 'byteLength': len(p)})
        blob += p + b'\0' * (-len(p) % 4)
    doc.update({'accessors': acc, 'bufferViews': views, 'buffers': [{'byteLength': len(blob)}]})
    js = json.dumps(doc).encode()
    js += b' ' * (-len(js) % 4)
    with open(path, 'wb') as f:
        f.write(struct.pack('<4sII', b'glTF', 2, 12 + 8 + len(js) + 8 + len(blob)))
        f.write(struct.pack('<I4s', len(js), b'JSON') + js + struct.pack('<I4s', len(blob), b'BIN\0') + blob)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--rast', required=True)
    ap.add_argument('--n', type=int, default=1000)
    ap.add_argument('--size', default='1920x1080')
    ap.add_argument('--frames', type=int, default=30)
    ap.add_argument('--out')
    a = ap.parse_args()
    work = tempfile.mkdtemp(prefix='skin_bench_')
    rows = []
    for name, skinned, bent in (('plain', False, False), ('skinned', True, True), ('skinned-rest', True, False)):
        glb = os.path.join(work, f'grid_{name}.glb')
        grid_glb(glb, a.n, skinned, bent)
        js = os.path.join(work, 'rows.json')
        cam = ['--eye', '0,0,3', '--target', '0,0,0', '--up', '0,1,0', '--near', '0.1', '--far', '10']
        subprocess.run([a.rast, 'bench', glb, '--size', a.size, '--frames', str(a.frames), '--warmup', '3', '--json', js,
                        *cam], check=True, capture_output=True)
        row = json.load(open(js))
        row = row[0] if isinstance(row, list) else row
        stages = row['stages_median_ms']
        rows.append({'mesh': name, 'vertices': a.n * a.n,
                     'vertex_ms': stages.get('vertex'), 'frame_ms': row.get('total_median_ms'), 'device': row.get('device')})
        print(rows[-1])
    if rows[0]['vertex_ms'] and rows[1]['vertex_ms']:
        print(f"skinned / plain vertex stage: {rows[1]['vertex_ms'] / rows[0]['vertex_ms']:.2f}x")
    if rows[0]['frame_ms'] and rows[2]['frame_ms']:
        print(f"skinning adds {rows[2]['frame_ms'] - rows[0]['frame_ms']:.4f} ms to the frame (the same geometry, "
              f"at rest; vertex stage +{rows[2]['vertex_ms'] - rows[0]['vertex_ms']:.4f} ms)")
    if a.out:
        with open(a.out, 'w', newline='') as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(rows)


if __name__ == '__main__':
    main()

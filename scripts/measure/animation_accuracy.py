#!/usr/bin/env python3
"""Silhouette agreement of rast's animated poses with the Khronos glTF Sample Renderer.

Why: skins, morph targets and animation sampling are easy to get subtly wrong (a joint
order, a tangent scale, the skinned node's own transform); the Sample Renderer is the
reference implementation, so the same scene at the same time and camera must cover the
same pixels (docs/animation.md records the figures).

    animation_accuracy.py --rast build/openmp/rast [--out rows.csv] [--size 320x240]
                          [SCENE@T1,T2,...] ...

Each scene is rendered by rast at each time (auto-framed at that pose; its camera flags go to
the reference), then all references in one khronos-ref batch, then coverage_iou per pair:
|both covered| / |either covered|, as ../shared/tools/khronos-ref/fidelity.py computes it, but with
each image's background taken from its own corner (the two tools encode a background colour
differently). Without scene arguments: simple_skin and AnimatedMorphCube from Debian's
assimp-testmodels.

khronos-ref's page advances the animations and then renders with GltfView.renderFrame, which
first deactivates every animation not listed in state.animationIndices (empty by default): its
--time has no effect (the rest pose comes out at any time). This script runs a copy of the tool
whose page lists every animation and sets the renderer's animation clock to the time instead.
Times are kept below each animation's end: the Sample Renderer loops (t modulo the last key
time), rast holds the last key.
"""
import argparse, csv, json, os, re, shutil, subprocess, sys, tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
SHARED = os.path.normpath(os.path.join(HERE, '..', '..', '..', 'shared'))
ASSIMP = '/usr/share/assimp/models/glTF2'
CORPUS = os.path.normpath(os.path.join(HERE, '..', '..', 'tests', 'fuzz', 'corpus'))
DEFAULT = [f'{ASSIMP}/simple_skin/simple_skin.gltf@0.3,1,2.5,4,5',
           f'{ASSIMP}/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf@0.3,1,2.2,3.3',
           f'{CORPUS}/anim_skin_morph.gltf@0.1,0.25,0.5,0.8']
BG = '1,0,1'  # magenta: no lit grey surface comes out exactly that


# Coverage agreement with each image's background from its top-left pixel (Debian's numpy and PIL).
IOU = """
import json, sys
import numpy as np
from PIL import Image
def covered(p):
    a = np.asarray(Image.open(p).convert('RGB'), dtype=np.float64)
    return np.any(np.abs(a - a[0, 0]) > 0.5, axis=2)
r, t = covered(sys.argv[1]), covered(sys.argv[2])
print(json.dumps({'iou': float((r & t).sum() / max(1, (r | t).sum())), 'either': int((r | t).sum())}))
"""


def patched_tool(tool, work):
    """A copy of khronos-ref whose --time takes effect (see the docstring)."""
    page = open(os.path.join(tool, 'page.html')).read()
    old = "    for (const a of state.gltf.animations) a.advance(state.gltf, p.time);\n"
    if 'animationIndices' in page or old not in page:
        return tool  # fixed upstream, or changed: use it as it is
    copy = os.path.join(work, 'khronos-ref')
    shutil.copytree(tool, copy)
    page = page.replace(old, old + "    state.animationIndices = state.gltf.animations.map((a, i) => i);\n"
                                   "    state.animationTimer = { elapsedSec: () => p.time };\n")
    open(os.path.join(copy, 'page.html'), 'w').write(page)
    return copy


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--rast', required=True)
    ap.add_argument('--out')
    ap.add_argument('--size', default='320x240')
    ap.add_argument('--shared', default=SHARED)
    ap.add_argument('scenes', nargs='*')
    a = ap.parse_args()
    tool = os.path.join(a.shared, 'tools', 'khronos-ref')
    if not os.path.isdir(tool):
        sys.exit(f'animation_accuracy: no {tool}')
    work = tempfile.mkdtemp(prefix='anim_acc_')
    tool = patched_tool(tool, work)
    jobs, pairs = [], []
    for spec in a.scenes or DEFAULT:
        scene, times = spec.rsplit('@', 1)
        for t in times.split(','):
            base = f'{os.path.splitext(os.path.basename(scene))[0]}_t{t}'
            test = os.path.join(work, base + '_rast.png')
            ref = os.path.join(work, base + '_ref.png')
            out = subprocess.run([a.rast, 'render', scene, '--time', t, '--size', a.size, '--background', BG,
                                  '--aa', 'none', '-o', test], capture_output=True, text=True, check=True).stdout
            flags = re.search(r'camera \([^)]*\) (.*)', out).group(1).split()
            job = {'scene': scene, 'out': ref, 'size': a.size, 'time': t, 'background': BG, 'default-lights': True}
            for k in range(0, len(flags), 2):
                job[flags[k].lstrip('-')] = flags[k + 1]
            jobs.append(job)
            pairs.append((os.path.basename(scene), t, ref, test))
    batch = os.path.join(work, 'jobs.jsonl')
    with open(batch, 'w') as f:
        f.write('\n'.join(json.dumps(j) for j in jobs) + '\n')
    subprocess.run(['node', os.path.join(tool, 'khronos_ref.mjs'), '--batch', batch], check=True)
    rows = []
    for name, t, ref, test in pairs:
        iou = json.loads(subprocess.run(['/usr/bin/python3', '-c', IOU, ref, test], capture_output=True, text=True,
                                        check=True).stdout)
        rows.append({'scene': name, 'time': t, 'coverage_iou': round(iou['iou'], 5), 'pixels': iou['either'], 'images': work})
        print(f'{name:28s} t={t:>5s}  coverage_iou {iou["iou"]:.4f} ({iou["either"]} covered pixels)')
    if a.out:
        with open(a.out, 'w', newline='') as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
            w.writeheader()
            w.writerows(rows)


if __name__ == '__main__':
    main()

#!/usr/bin/env python3
"""The mutation loop of scripts/fuzz/fuzz_cli.sh: mutated scene files and flags
against a sanitizer build of rast, for a bounded time. Python standard library
only; deterministic for a given --seed (apart from timing)."""
import argparse
import json
import os
import random
import shutil
import subprocess
import sys
import time

ap = argparse.ArgumentParser()
ap.add_argument("--rast", required=True)
ap.add_argument("--seconds", type=float, default=600)
ap.add_argument("--seed", type=int, default=1)
ap.add_argument("--out", required=True)
ap.add_argument("--seeds", nargs="+", required=True, help="files or folders of .gltf/.glb seeds")
args = ap.parse_args()
rng = random.Random(args.seed)

seeds = []
for s in args.seeds:
    if os.path.isfile(s):
        seeds.append(s)
    elif os.path.isdir(s):
        for root, _, files in os.walk(s):
            seeds += [os.path.join(root, f) for f in sorted(files) if f.endswith((".gltf", ".glb"))]
seeds = [s for s in seeds if os.path.getsize(s) < 4 << 20]
if not seeds:
    sys.exit("fuzz_cli: no seed files")

work = os.path.join(args.out, "work")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
INTERESTING = [b"0", b"-1", b"1e38", b"-1e38", b"1e-38", b"4294967295", b"2147483648", b"16777216", b"65536",
               b"NaN", b"null", b"[]", b"{}", b'""', b'"../a.png"', b'"/etc/passwd"', b"5", b"6", b"3.5",
               # issue 38: escapes, the folder itself, special files, data: URIs of the wrong length
               b'"%zz"', b'"a%00b"', b'"."', b'"/proc/self/environ"', b'"data:application/octet-stream;base64,AAAA"',
               b'"data:image/png;base64,UDYKNjQgNjQKMjU1Cg=="']


def mutate_json(data):
    """Replaces a number or a value with an interesting one, a few times."""
    for _ in range(rng.randint(1, 4)):
        digits = [i for i, c in enumerate(data) if 48 <= c <= 57]
        if not digits:
            break
        i = rng.choice(digits)
        j = i
        while j < len(data) and (48 <= data[j] <= 57 or data[j] in b".eE-+"):
            j += 1
        data = data[:i] + rng.choice(INTERESTING) + data[j:]
    return data


def mutate_bytes(data):
    data = bytearray(data)
    for _ in range(rng.randint(1, 3)):
        op = rng.randrange(5)
        if not data:
            data += b"{"
        i = rng.randrange(len(data))
        if op == 0:
            data[i] ^= 1 << rng.randrange(8)
        elif op == 1:
            data[i] = rng.choice([0, 0xFF, 0x7F, 0x80, ord("{"), ord("["), ord('"')])
        elif op == 2:
            del data[i:i + rng.randint(1, 16)]
        elif op == 3:
            data[i:i] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
        else:
            del data[i:]
    return bytes(data)


def random_flags():
    f = ["--size", rng.choice(["1x1", "17x9", "64x48", "160x120", "333x1", "1x333", "512x512"])]
    if rng.random() < 0.5:
        f += ["--aa", rng.choice(["none", "msaa2", "msaa4", "msaa8", "ssaa2", "ssaa4"])]
    if rng.random() < 0.5:
        f += ["--raster", rng.choice(["auto", "naive", "visbuffer", "binned"])]
    if rng.random() < 0.4:
        f += ["--shading", rng.choice(["lambert", "blinn-phong", "normals", "depth", "uv", "miplevel"])]
    if rng.random() < 0.3:
        f += ["--filter", rng.choice(["nearest", "bilinear", "trilinear"])]
    if rng.random() < 0.2:
        f += ["--cull", "back"]
    if rng.random() < 0.2:
        v = lambda: rng.choice(["0", "1", "-1", "1e30", "-1e30", "1e-30", "3", "0.5"])
        f += ["--eye", f"{v()},{v()},{v()}", "--target", f"{v()},{v()},{v()}"]
    if rng.random() < 0.2:
        f += ["--near", rng.choice(["1e-30", "0.001", "1", "100"]), "--far", rng.choice(["1e30", "10", "1000"])]
    if rng.random() < 0.1:
        f += ["--fovy", rng.choice(["0.001", "179.9", "90", "1"])]
    if rng.random() < 0.2:
        f += ["--aov", "depth=" + os.path.join(work, "d.pfm") + ",primid=" + os.path.join(work, "i.bin")]
    if rng.random() < 0.2:
        f += ["--max-memory", rng.choice(["1M", "64M", "1G"])]
    if rng.random() < 0.05:  # issue 38: validated before Kokkos sees them
        f += [rng.choice(["--kokkos-threads=0", "--kokkos-threads=1", "--kokkos-threads=100000", "--kokkos-threads=-1"])]
    return f


execs = findings = ok_runs = error_runs = 0
deadline = time.time() + args.seconds
start = time.time()
while time.time() < deadline:
    seed = rng.choice(seeds)
    with open(seed, "rb") as fh:
        data = fh.read()
    ext = ".glb" if data[:4] == b"glTF" else ".gltf"
    # JSON-aware replacements keep most files parseable, so that they reach
    # the renderer; raw byte mutations test the parsers.
    data = mutate_json(data) if (ext == ".gltf" and rng.random() < 0.8) else mutate_bytes(data)
    # Next to the seed's own files (external buffers and images), as a user would.
    folder = os.path.dirname(os.path.abspath(seed))
    scene = os.path.join(work, "input" + ext)
    with open(scene, "wb") as fh:
        fh.write(data)
    for name in os.listdir(folder) if len(os.listdir(folder)) < 50 else []:
        p = os.path.join(folder, name)
        if os.path.isfile(p) and not name.endswith((".gltf", ".glb")) and os.path.getsize(p) < 8 << 20:
            dst = os.path.join(work, name)
            if not os.path.exists(dst):
                shutil.copy(p, dst)
    out_png = os.path.join(work, "out.png")
    # Now and then an output that is an input or another output (issue 38):
    # it must be refused, and the input must be unchanged afterwards.
    target = out_png if rng.random() < 0.9 else rng.choice([scene, os.path.join(work, "a.bin"), os.path.join(work, "a.png")])
    cmd = [args.rast, "render", scene, "-o", target] + random_flags()
    inputs = {p: open(p, "rb").read() for p in [scene, os.path.join(work, "a.bin"), os.path.join(work, "a.png")]
              if os.path.isfile(p)}
    execs += 1
    try:
        r = subprocess.run(cmd, capture_output=True, timeout=60)
        rc, err = r.returncode, r.stderr.decode("utf-8", "replace")
    except subprocess.TimeoutExpired:
        rc, err = None, "timeout after 60 s"
    lines = [l for l in err.splitlines() if l.strip()]
    bad = None
    if rc is None:
        bad = "hang"
    elif "AddressSanitizer" in err or "LeakSanitizer" in err or "runtime error:" in err:
        bad = "sanitizer"
    elif rc < 0:
        bad = f"signal {-rc}"
    elif rc == 0:
        ok_runs += 1
    elif rc in (1, 2) and len(lines) == 1 and lines[0].startswith("rast: error: "):
        error_runs += 1
    else:
        bad = f"exit {rc} with {len(lines)} stderr lines"
    for p, before in inputs.items():
        if not bad and (not os.path.isfile(p) or open(p, "rb").read() != before):
            bad = f"input {os.path.basename(p)} overwritten"
    if not bad and any(".rast-" in f for f in os.listdir(work)):
        bad = "temporary output file left behind"
    if bad:
        findings += 1
        d = os.path.join(args.out, f"finding-{findings:03d}")
        os.makedirs(d, exist_ok=True)
        shutil.copy(scene, os.path.join(d, "input" + ext))
        with open(os.path.join(d, "report.json"), "w") as fh:
            json.dump({"kind": bad, "seed": seed, "cmd": cmd, "rc": rc, "stderr": err[-20000:]}, fh, indent=1)
        print(f"fuzz_cli: FINDING {findings} ({bad}) from {seed}: {' '.join(cmd[2:])}", flush=True)
    for f in os.listdir(work):  # outputs of this run only
        if f.startswith(("out.", "d.", "i.")):
            os.remove(os.path.join(work, f))

elapsed = time.time() - start
print(f"fuzz_cli: {execs} runs in {elapsed:.0f} s ({ok_runs} rendered, {error_runs} one-line errors, "
      f"{findings} findings) from {len(seeds)} seed files, seed {args.seed}")
sys.exit(1 if findings else 0)

#!/usr/bin/env python3
"""Peak memory (RSS) and outcome of `rast render` on the small hostile inputs of
the memory-budget work (docs/security.md), for one or more rast binaries:

  python3 scripts/measure/measure_memory.py --rast build/openmp/rast [--rast OLD/rast] [--extra="--max-memory 1G"]

Inputs (tests/support/adversarial.py, generated in a temporary folder): a ~350-byte
glTF claiming 2^24 vertices drawn 4 times, a ~1 MB PNG decoding to 16384x16384,
a 20 MB strip of 20M u8 indices, and the default scene at 16384x16384 with
msaa8. Each run is capped at --cap-gib of address space (default 3/4 of the
machine's memory) so that an unprotected binary cannot take the machine down;
a capped run shows as its error. Peak RSS comes from wait4's rusage."""
import argparse
import os
import resource
import shlex
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests", "support"))
import adversarial  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--rast", action="append", required=True)
ap.add_argument("--extra", default="", help="extra flags for every run, e.g. '--max-memory 1G'")
ap.add_argument("--cap-gib", type=float,
                default=os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE") * 0.75 / (1 << 30))
args = ap.parse_args()

tmp = tempfile.mkdtemp(prefix="rast_mem_")
cases = [
    ("tiny_counts", [adversarial.tiny_counts(tmp), "--size", "64x48"]),
    ("huge_png", [adversarial.huge_png(tmp), "--size", "64x48"]),
    ("strip_20MB", [adversarial.strip(tmp), "--size", "64x48"]),
    ("16384^2 msaa8", ["--size", "16384x16384", "--aa", "msaa8"]),
]
for name, a in cases:
    size = os.path.getsize(a[0]) if os.path.exists(a[0]) else 0
    extra_file = os.path.join(tmp, "huge.png") if name == "huge_png" else None
    if extra_file:
        size = f"{size} + {os.path.getsize(extra_file)}"
    print(f"# {name}: input {size} bytes")
env = dict(os.environ, OMP_PROC_BIND=os.environ.get("OMP_PROC_BIND", "false"))
cap = int(args.cap_gib * (1 << 30))


def limit():
    resource.setrlimit(resource.RLIMIT_AS, (cap, cap))


print(f"{'binary':40} {'case':14} {'exit':>4} {'peak RSS MiB':>12} {'s':>7}  outcome")
for exe in args.rast:
    for name, a in cases:
        cmd = [exe, "render"] + a + ["-o", os.path.join(tmp, "out.png")] + shlex.split(args.extra)
        t0 = time.time()
        p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env, preexec_fn=limit)
        err = p.stderr.read().decode("utf-8", "replace")
        _, status, ru = os.wait4(p.pid, 0)
        p.returncode = os.waitstatus_to_exitcode(status)
        last = (err.strip().splitlines() or ["(wrote the image)"])[-1]
        print(f"{exe[-40:]:40} {name:14} {p.returncode:>4} {ru.ru_maxrss / 1024:>12.0f} {time.time() - t0:>7.1f}  {last[:160]}",
              flush=True)

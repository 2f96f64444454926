#!/usr/bin/env python3
"""Kokkos' flags and thread counts are checked before Kokkos sees them (issue
38; docs/security.md, "Thread flags"): --kokkos-threads=0 and =1000 crashed
in Kokkos' OpenMP backend (SIGSEGV), OMP_NUM_THREADS=600 too, and -1 printed
five lines. Each now ends in one 'rast: error:' line naming the flag and the
range 1..hardware threads, exit 2; valid counts still render.
Python standard library only."""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from cli_checks import one_line_error  # noqa: E402
from script_args import arg_parser  # noqa: E402

args = arg_parser().parse_args()
work = os.path.abspath(args.workdir)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
env = dict(os.environ)
env.setdefault("OMP_PROC_BIND", "false")
env.pop("OMP_NUM_THREADS", None)
env.pop("KOKKOS_NUM_THREADS", None)
failed = 0
small = ["--size", "64x48"]


def check(name, problems):
    global failed
    if problems:
        failed += 1
        print(f"FAIL    {name}: {'; '.join(problems)}")
    else:
        print(f"ok      {name}")


def run(argv, extra_env=None):
    e = dict(env)
    e.update(extra_env or {})
    try:
        return subprocess.run([args.rast] + argv, capture_output=True, timeout=120, env=e)
    except subprocess.TimeoutExpired:
        return None


ncpu = os.cpu_count() or 1
for flag, words in [("--kokkos-threads=0", "--kokkos-threads=0: expected a count from 1 to"),
                    ("--kokkos-threads=1000000", "--kokkos-threads=1000000: expected a count from 1 to"),
                    (f"--kokkos-threads={max(ncpu * 4, 1000)}", "hardware threads"),
                    ("--kokkos-threads=-1", "--kokkos-threads=-1: expected a count"),
                    ("--kokkos-threads=abc", "--kokkos-threads=abc"),
                    ("--kokkos-threads", "needs a value"),
                    ("--kokkos-numa=0", "--kokkos-numa=0"),
                    ("--kokkos-device-id=-3", "--kokkos-device-id=-3")]:
    r = run(["render", "-o", os.path.join(work, "k.png"), flag] + small)
    check(f"{flag}", one_line_error(r, words))
# (Values libgomp itself finds invalid, 0 or "abc", get its own line first,
# printed while the library loads, before rast runs: not checked here.)
for value in [str(max(600, ncpu + 1)), f"1,{max(600, ncpu + 1)}"]:
    r = run(["render", "-o", os.path.join(work, "k.png")] + small, {"OMP_NUM_THREADS": value})
    check(f"OMP_NUM_THREADS={value}", one_line_error(r, f"OMP_NUM_THREADS={value}: expected thread counts from 1 to"))
r = run(["render", "-o", os.path.join(work, "k.png")] + small, {"KOKKOS_NUM_THREADS": "0"})
check("KOKKOS_NUM_THREADS=0", one_line_error(r, "KOKKOS_NUM_THREADS=0: expected thread counts from 1 to"))
r = run(["render", "-o", os.path.join(work, "k.png"), f"--kokkos-threads={ncpu}"] + small)
check(f"--kokkos-threads={ncpu} (all hardware threads) renders", [] if r is not None and r.returncode == 0 else
      [f"failed: {r and r.stderr[:300]!r}"])
r = run(["render", "-o", os.path.join(work, "k.png"), "--kokkos-threads=1"] + small, {"OMP_NUM_THREADS": "1"})
check("--kokkos-threads=1 with OMP_NUM_THREADS=1 renders", [] if r is not None and r.returncode == 0 else
      [f"failed: {r and r.stderr[:300]!r}"])

print("all passed" if not failed else f"{failed} failed")
sys.exit(1 if failed else 0)

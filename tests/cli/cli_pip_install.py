#!/usr/bin/env python3
"""`pip install .` as a user runs it (docs/python.md): Debian's pip, offline,
without build isolation, into a scratch target folder, reusing this build's
objects (RAST_BUILD_DIR) so the test costs seconds, not a pipeline build.
Then a fresh interpreter that sees only that folder imports rast and renders,
and the installed package holds the module and its Python front and nothing
of the source tree. Skips (77) when pip or setuptools are missing or the
build has no Python module. Standard library only."""
import glob
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from script_args import arg_parser  # noqa: E402
from cli_checks import Tally  # noqa: E402
from skip import skip  # noqa: E402

args = arg_parser().parse_args()
src = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))
build = os.path.dirname(os.path.abspath(args.rast))
work = os.path.abspath(args.workdir)
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
python = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable
if not glob.glob(os.path.join(build, "python", "rast", "_rast*.so")):
    skip(work, "this build has no Python module (RAST_PYTHON=OFF)")
probe = subprocess.run([python, "-c", "import setuptools, wheel, pip"], capture_output=True, text=True)
if probe.returncode != 0:
    skip(work, "pip, setuptools or wheel is missing (Debian: python3-pip python3-setuptools python3-wheel)")

check = Tally()  # check(ok, what); check.failed counts the failures


target = os.path.join(work, "site")
env = dict(os.environ, RAST_BUILD_DIR=build, PIP_NO_CACHE_DIR="1", OMP_PROC_BIND="false")
cmd = [python, "-m", "pip", "install", "--no-build-isolation", "--no-index", "--no-deps", "--target", target, src]
print("+", " ".join(cmd), flush=True)
r = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=850)
check(r.returncode == 0, "pip install . ran" + ("" if r.returncode == 0 else ": " + (r.stdout + r.stderr)[-2000:]))
pkg = os.path.join(target, "rast")
check(os.path.isfile(os.path.join(pkg, "__init__.py")) and bool(glob.glob(os.path.join(pkg, "_rast*.so"))),
      f"the package holds __init__.py and the extension: {sorted(os.listdir(pkg)) if os.path.isdir(pkg) else 'none'}")
code = ("import rast, sys; o = rast.render(size=(64, 48)); "
        "print(rast.__file__, rast.backend, o['color'].shape, int((o['ids'] >= 0).sum()))")
r = subprocess.run([python, "-c", code], capture_output=True, text=True, cwd=work, timeout=300,
                   env=dict(env, PYTHONPATH=target))
print(r.stdout.strip(), r.stderr.strip()[-1000:])
fields = r.stdout.split()
check(r.returncode == 0 and fields and fields[0].startswith(target), "a fresh python imports the installed rast")
check(len(fields) >= 5 and int(fields[-1]) > 0, "and renders the default scene (some pixels covered)")
sys.exit(1 if check.failed else 0)

#!/usr/bin/env python3
"""rast as an installed library (docs/library.md): installs this build into a
scratch prefix (`cmake --install`), then configures, builds and runs
examples/cpp_consumer against that prefix only, with find_package(rast). So the
package (rastConfig.cmake, its version file, rast::rast, the public headers)
is what a consumer outside the tree gets, and its program renders. Also checks
that no internal header or library was installed. Standard library only."""
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
prefix, consumer = os.path.join(work, "prefix"), os.path.join(work, "consumer")
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
if not os.path.isfile(os.path.join(build, "rastConfig.cmake")):
    skip(work, "this build has no rast package (Kokkos built in-tree: cmake/RastLibrary.cmake)")
cmake = shutil.which("cmake") or "cmake"
env = dict(os.environ)
env.setdefault("OMP_PROC_BIND", "false")
env.pop("Kokkos_ROOT", None)  # the package must find its own Kokkos


def run(*cmd):
    print("+", " ".join(cmd), flush=True)
    r = subprocess.run(list(cmd), capture_output=True, text=True, env=env, timeout=850)
    sys.stdout.write(r.stdout[-4000:])
    if r.returncode != 0:
        sys.stdout.write(r.stderr[-4000:])
        raise SystemExit(f"FAILED ({r.returncode}): {' '.join(cmd)}")
    return r.stdout


check = Tally()  # check(ok, what); check.failed counts the failures


run(cmake, "--install", build, "--prefix", prefix)
pkg = os.path.join(prefix, "lib", "cmake", "rast")
for f in ("rastConfig.cmake", "rastConfigVersion.cmake", "rastTargets.cmake"):
    check(os.path.isfile(os.path.join(pkg, f)), f"installed lib/cmake/rast/{f}")
inc = os.path.join(prefix, "include", "rast")
check(sorted(os.listdir(inc)) == ["config.h", "error.h", "rast.h"], f"public headers only: {sorted(os.listdir(inc))}")
check(os.path.isfile(os.path.join(prefix, "lib", "librast.a")), "installed lib/librast.a")
check(not any(n.startswith("librast_") for n in os.listdir(os.path.join(prefix, "lib"))), "no internal library installed")
with open(os.path.join(pkg, "rastConfig.cmake")) as fh:
    cfg = fh.read()
check("rast_KOKKOS_VERSION" in cfg and "find_dependency(Kokkos)" in cfg, "the package records and finds its Kokkos")

gen = ["-G", "Ninja"] if shutil.which("ninja") else []
cxx = os.environ.get("CXX")
run(cmake, "-S", os.path.join(src, "examples", "cpp_consumer"), "-B", consumer, *gen,
    "-DCMAKE_BUILD_TYPE=Release", f"-DCMAKE_PREFIX_PATH={prefix}", *([f"-DCMAKE_CXX_COMPILER={cxx}"] if cxx else []))
run(cmake, "--build", consumer)
exe = os.path.join(consumer, "rast_consumer")
out = run(exe)
check("FAIL" not in out and "ok" in out, "the consumer's own checks pass")
# A consumer asking for a version the package is not: find_package must refuse it.
bad = os.path.join(work, "badver")
os.makedirs(bad)
with open(os.path.join(bad, "CMakeLists.txt"), "w") as fh:
    fh.write("cmake_minimum_required(VERSION 3.21)\nproject(v LANGUAGES CXX)\nfind_package(rast 9.0 REQUIRED)\n")
r = subprocess.run([cmake, "-S", bad, "-B", os.path.join(bad, "b"), f"-DCMAKE_PREFIX_PATH={prefix}"],
                   capture_output=True, text=True, env=env, timeout=300)
check(r.returncode != 0, "find_package(rast 9.0) is refused by the version file")
sys.exit(1 if check.failed else 0)

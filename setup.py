"""`pip install .` for rast's Python module (docs/python.md): setuptools hands
the extension to CMake, which builds the target `_rast` (cmake/RastPython.cmake)
for the Python running pip, in build/python (or RAST_BUILD_DIR, e.g. an
existing build/openmp, to reuse its objects); the package is python/rast with
the built extension beside its __init__.py. Needs cmake, a C++17 compiler,
Kokkos (scripts/setup/bootstrap.sh), pybind11 and numpy."""
import glob
import os
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SRC = os.path.dirname(os.path.abspath(__file__))


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        build = os.path.abspath(os.environ.get("RAST_BUILD_DIR") or os.path.join(SRC, "build", "python"))
        if not os.path.isfile(os.path.join(build, "CMakeCache.txt")):
            gen = ["-G", "Ninja"] if shutil.which("ninja") else []
            subprocess.check_call(["cmake", "-S", SRC, "-B", build, *gen, "-DCMAKE_BUILD_TYPE=Release",
                                   "-DRAST_PYTHON=ON", "-DRAST_BUILD_TESTS=OFF",
                                   f"-DPython_EXECUTABLE={sys.executable}"])
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", str(os.cpu_count() or 2))
        subprocess.check_call(["cmake", "--build", build, "--target", "_rast", "-j", jobs])
        built = glob.glob(os.path.join(build, "python", "rast", "_rast*.so"))
        if not built:
            raise RuntimeError(f"no _rast module in {build}/python/rast after the build")
        dest = self.get_ext_fullpath(ext.name)
        os.makedirs(os.path.dirname(dest), exist_ok=True)
        shutil.copyfile(built[0], dest)


setup(packages=["rast"], package_dir={"": "python"},
      ext_modules=[Extension("rast._rast", sources=[])], cmdclass={"build_ext": CMakeBuild})

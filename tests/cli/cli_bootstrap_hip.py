"""scripts/setup/bootstrap.sh --hip: the architecture names it accepts, and the
patch that teaches Kokkos 3.4.1 gfx90a. Runs only the parts that
install nothing: argument checks, and patch_kokkos_hip_arch on a copy of Kokkos'
kokkos_arch.cmake (the bootstrap's extracted source, or its two anchor lines)."""
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from script_args import arg_parser  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "scripts", "setup", "bootstrap.sh")
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def bootstrap(*args):
    return subprocess.run(["bash", SCRIPT, *args], capture_output=True, text=True, timeout=60)


args = arg_parser().parse_args()
os.makedirs(args.workdir, exist_ok=True)

r = bootstrap("--hip-arch", "gfx999")
check(r.returncode != 0 and "unsupported --hip-arch gfx999" in r.stderr and "[bootstrap] apt" not in r.stdout,
      "an unknown architecture is refused before anything is installed")
r = bootstrap("--hip-arch", "gfx1030")
check(r.returncode != 0 and "64-wide wavefronts" in r.stderr and "Kokkos >= 4" in r.stderr,
      "gfx1030 is refused with the reason (Kokkos 3.4.1 needs 64-wide wavefronts)")
r = bootstrap("--hip-arch")
check(r.returncode != 0 and "--hip-arch needs an architecture" in r.stderr, "--hip-arch without a value is refused")
r = bootstrap("--help")
check(r.returncode == 0 and "--hip-arch" in r.stdout and "gfx90a" in r.stdout, "--help documents --hip-arch")

# patch_kokkos_hip_arch, taken out of the script and run on a copy.
src = os.path.join(args.workdir, "kokkos")
shutil.rmtree(src, ignore_errors=True)
os.makedirs(os.path.join(src, "cmake"))
arch = os.path.join(src, "cmake", "kokkos_arch.cmake")
debian = os.path.join(ROOT, ".deps", "kokkos", "src", "cmake", "kokkos_arch.cmake")
if os.path.exists(debian):
    shutil.copy(debian, arch)
else:
    with open(arch, "w") as f:
        f.write('KOKKOS_ARCH_OPTION(VEGA908         GPU  "AMD GPU MI100 GFX908")\n'
                'CHECK_AMDGPU_ARCH(VEGA908 gfx908)\n')
fn = subprocess.run(["sed", "-n", "/^patch_kokkos_hip_arch() {/,/^}/p", SCRIPT], capture_output=True, text=True).stdout
check("patch_kokkos_hip_arch" in fn, "bootstrap.sh defines patch_kokkos_hip_arch")
run = 'set -euo pipefail; die() { echo "$*" >&2; exit 1; }\n' + fn + '\npatch_kokkos_hip_arch "$1"; patch_kokkos_hip_arch "$1"\n'
r = subprocess.run(["bash", "-c", run, "patch", src], capture_output=True, text=True)
check(r.returncode == 0, "the patch applies (twice: the second time it does nothing) " + r.stderr.strip())
text = open(arch).read()
for line in ("KOKKOS_ARCH_OPTION(VEGA90A ", "CHECK_AMDGPU_ARCH(VEGA90A gfx90a)"):
    check(text.count(line) == 1, f"patched file has exactly one '{line.strip()}'")
lines = text.splitlines()
check(lines.index(next(l for l in lines if l.startswith("CHECK_AMDGPU_ARCH(VEGA90A"))) ==
      lines.index(next(l for l in lines if l.startswith("CHECK_AMDGPU_ARCH(VEGA908"))) + 1,
      "the new architecture checks sit right after VEGA908's")

# Without the anchors (not Kokkos 3.4) it stops with a message instead of building a Kokkos without the architecture.
with open(arch, "w") as f:
    f.write("# nothing here\n")
r = subprocess.run(["bash", "-c", run, "patch", src], capture_output=True, text=True)
check(r.returncode != 0 and "no VEGA908 entries" in r.stderr, "a source without the anchors is refused")

sys.exit(1 if failures else 0)

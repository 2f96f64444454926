"""One way for the tests/cli_*.py scripts to skip: the reason on stdout, one line
in the build's skip folder (printed after ctest's summary, tests/support/skip_report.cmake),
and exit status 77, which ctest counts as skipped."""
import os
import sys


def skip(workdir, reason):
    print(f"SKIPPED: {reason}")
    folder = os.path.join(os.path.dirname(os.path.abspath(workdir)), "skipped")
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, os.path.basename(os.path.abspath(workdir)) + ".txt"), "w") as f:
        f.write(reason + "\n")
    sys.exit(77)

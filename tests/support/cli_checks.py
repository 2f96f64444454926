"""What the CLI tests of bad input (tests/cli/cli_data_safety.py,
cli_kokkos_flags.py) ask of a refused run, in one place: it ended by itself
with a non-zero status, no signal, and exactly one short 'rast: error:' line
that names the problem."""


def one_line_error(r, words):
    """Problems with r as a refusal: non-zero exit (no signal), one 'rast: error:' line with WORDS."""
    if r is None:
        return ["did not finish"]
    problems = []
    err = r.stderr.decode("utf-8", "replace")
    if r.returncode == 0:
        problems.append("exit status 0")
    elif r.returncode < 0:
        problems.append(f"killed by signal {-r.returncode}")
    lines = err.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    if len(lines) != 1 or not lines[0].startswith("rast: error: "):
        problems.append(f"stderr is not one 'rast: error:' line: {err[:300]!r}")
    elif len(lines[0]) > 1100:
        problems.append(f"error line of {len(lines[0])} bytes")
    for w in words if isinstance(words, list) else [words]:
        if w not in err:
            problems.append(f"stderr lacks {w!r}: {err[:300]!r}")
    return problems


class Tally:
    """The checks of a test script, counted: tally(ok, what) prints "ok  " or
    "FAIL" and what was checked, and returns ok; `failed` counts the FAILs.
    One object instead of a global counter and a check() in every script."""

    def __init__(self):
        self.failed = 0

    def __call__(self, ok, what):
        print(f"{'ok  ' if ok else 'FAIL'} {what}", flush=True)
        self.failed += not ok
        return ok


def cli_setup():
    """A CLI test's start: its arguments (tests/support/script_args.py) with
    the work folder made, and the environment to run rast in (OMP_PROC_BIND
    false unless set, as ctest sets it)."""
    import os
    from script_args import arg_parser
    args = arg_parser().parse_args()
    os.makedirs(args.workdir, exist_ok=True)
    env = dict(os.environ)
    env.setdefault("OMP_PROC_BIND", "false")
    return args, env

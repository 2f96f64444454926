"""Progress of the long sweeps on stderr, drawn only when stderr is a terminal
(logs and CI output stay clean)."""
import sys


class Progress:
    def __init__(self, what, total):
        self.what, self.total, self.done = what, total, 0
        self.active = sys.stderr.isatty()

    def step(self, label=""):
        self.done += 1
        if self.active:
            sys.stderr.write(f"\r\033[K{self.what} {self.done}/{self.total} {label}"[:200])
            sys.stderr.flush()

    def close(self):
        if self.active:
            sys.stderr.write("\r\033[K")
            sys.stderr.flush()

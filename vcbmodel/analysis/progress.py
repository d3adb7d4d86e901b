"""Progress lines on stderr (stdout carries only results: CSV or JSON)."""
from __future__ import annotations

import sys
import time


def progress(message):
    print(message, file=sys.stderr, flush=True)


class Progress:
    """Counts finished items; each report gives the rate and an estimate of the time left."""

    def __init__(self, total, label, verbose=True):
        self.total, self.label, self.verbose = total, label, verbose
        self.done, self.start = 0, time.monotonic()

    def step(self, note=""):
        self.done += 1
        if not self.verbose:
            return
        elapsed = time.monotonic() - self.start
        rate = self.done / elapsed if elapsed > 0 else float("inf")
        left = (self.total - self.done) / rate if rate > 0 else float("nan")
        progress(f"{self.label}: {self.done}/{self.total} done, {rate * 60:.1f}/min, about {left:.0f} s left"
                 + (f"; {note}" if note else ""))

"""Progress lines, through :mod:`logging` (logger ``vcbmodel``, level INFO).

The library only logs; whoever runs it decides where lines go: the command line installs a
stderr handler (``--quiet`` raises its level to warnings), a script can call
``logging.basicConfig(level=logging.INFO)`` or silence the ``vcbmodel`` logger. stdout carries
only results (CSV or JSON).
"""
from __future__ import annotations

import logging
import time

log = logging.getLogger("vcbmodel")


def progress(message: str) -> None:
    """One progress line (INFO on the ``vcbmodel`` logger)."""
    log.info(message)


class Progress:
    """Counts finished items; each report gives the rate and an estimate of the time left."""

    def __init__(self, total, label, verbose=True):
        self.total, self.label, self.verbose = total, label, verbose
        self.done, self.start = 0, time.monotonic()

    def step(self, note: str = "") -> None:
        self.done += 1
        if not self.verbose:
            return
        elapsed = time.monotonic() - self.start
        rate = self.done / elapsed if elapsed > 0 else float("inf")
        left = (self.total - self.done) / rate if rate > 0 else float("nan")
        progress(f"{self.label}: {self.done}/{self.total} done, {rate * 60:.1f}/min, about {left:.0f} s left"
                 + (f"; {note}" if note else ""))

"""The ``vcbmodel`` command's entry point.

The command's modules (numpy, scipy, pandas, Exudyn, the laws) take a second or two to load. An
interrupt in that time ends the command with the same line and status as an interrupt during its
work (:func:`vcbmodel.app.cli.main`), not with a traceback from the middle of an import: the import
is deferred into :func:`main` for that reason alone.
"""
from __future__ import annotations

import sys

#: What an interrupted command prints (stderr) and returns; the same as :func:`vcbmodel.app.cli.main`'s
INTERRUPTED, INTERRUPTED_STATUS = "vcbmodel: interrupted", 1


def main(argv: list[str] | None = None) -> int:
    """Load the command line and run it (``argv``: its arguments, default ``sys.argv[1:]``)."""
    try:
        from .cli import main as command  # noqa: PLC0415 (deferred: an interrupt while it loads is one line)
    except KeyboardInterrupt:
        print(INTERRUPTED, file=sys.stderr)
        return INTERRUPTED_STATUS
    return command(argv)

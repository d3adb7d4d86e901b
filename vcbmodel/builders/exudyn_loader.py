"""Exudyn, imported on first use: the package loads without it (the laws, the compiled path and the
reference solves do not need it); only building an Exudyn model does."""
from __future__ import annotations

from ..errors import SimulationError

_EXU = None


def exudyn_modules() -> tuple:
    """(exudyn, exudyn.itemInterface), imported on first use (the package loads without
    Exudyn; only building a model needs it)."""
    global _EXU
    if _EXU is None:
        try:
            import exudyn as exu
            from exudyn import itemInterface as items
        except ImportError as e:  # a headless image without libGL, or no Exudyn at all
            raise SimulationError(
                f"Exudyn cannot be imported on this machine ({e}); a headless node needs libGL "
                "(Debian/Ubuntu: apt install libgl1), or run with --backend fast (a C compiler)") from None
        # Exudyn writes solver warnings and failure banners to stdout, which would corrupt
        # `--json` output and CSV on stdout; failures reach the caller as SimulationError
        exu.config.printToConsole = False
        _EXU = (exu, items)
    return _EXU

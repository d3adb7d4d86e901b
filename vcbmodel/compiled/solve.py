"""Compile a traced system with cffi (a C compiler is needed), cache it, and run it.

Compiled modules are cached twice: in this process ({key: [variants]}) and on disk under
``$VCBMODEL_CACHE`` (default ``~/.cache/vcbmodel``), named by the hash of their C source, so
a model structure is compiled once per machine. A module is reused for new parameter values
only when its guards hold (the same branches of the laws, :mod:`.trace`); otherwise the
system is traced again for them.
"""
from __future__ import annotations

import hashlib
import importlib.util
import logging
import os
import shutil
import sys
import sysconfig
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import SimulationError
from .codegen import CDEF, c_source, trace_system
from .inputs import flatten

log = logging.getLogger("vcbmodel")

#: What results computed here are called (``info["backend"]``)
BACKEND_NAME = "compiled (laws traced to C, cffi, fixed-step RK4)"


class CompilerUnavailable(SimulationError):
    """No working C compiler or cffi: the compiled backend cannot run here (a solver failure to the
    command line: one line, status 1; ``backend="fast"`` falls back to Exudyn instead)."""


@dataclass
class CompiledSystem:
    """One compiled variant: its cffi module, state size, output names and C source hash."""

    lib: object
    ffi: object
    n: int
    outputs: tuple
    digest: str


_VARIANTS: dict = {}


def cache_dir() -> Path:
    base = os.environ.get("VCBMODEL_CACHE") or os.path.join(os.path.expanduser("~"), ".cache", "vcbmodel")
    return Path(base) / "compiled"


def _compile(source, digest, cdef=CDEF):
    """Build (or load from the disk cache) the module of ``source`` declaring ``cdef`` (cffi's
    declarations; ``digest`` must name both); returns (lib, ffi)."""
    try:
        import cffi
    except ImportError as e:  # pragma: no cover - declared in setup.cfg
        raise CompilerUnavailable(f"cffi is missing ({e})") from None
    name = f"_vcb_{digest[:20]}"
    folder = cache_dir()
    suffix = sysconfig.get_config_var("EXT_SUFFIX") or ".so"
    target = folder / (name + suffix)
    if not target.exists():
        try:
            folder.mkdir(parents=True, exist_ok=True)
            work = Path(tempfile.mkdtemp(prefix=name, dir=folder))
        except OSError:
            folder = Path(tempfile.mkdtemp(prefix="vcbmodel-compiled-"))
            target, work = folder / (name + suffix), folder
        ffi = cffi.FFI()
        ffi.cdef(cdef)
        ffi.set_source(name, source, extra_compile_args=["-O2", "-ffp-contract=off"], libraries=["m"])
        try:
            built = ffi.compile(tmpdir=str(work), verbose=False)
        except Exception as e:  # compiler missing or failing: the caller falls back or reports
            raise CompilerUnavailable(f"the compiled backend needs a working C compiler: {str(e).strip().splitlines()[-1][:200]}"
                                  " (use --backend exudyn or fast)") from None
        os.replace(built, target)  # atomic: a parallel process sees the whole file or none
        if work != folder:
            shutil.rmtree(work, ignore_errors=True)
    spec = importlib.util.spec_from_file_location(name, target)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    sys.modules.setdefault(name, module)
    return module.lib, module.ffi


def compiler_problem() -> str | None:
    """Why no C module can be built here (None if one can): a two-line C function compiled with
    cffi into a temporary folder, loaded and called; the disk cache is neither read nor written,
    so a machine whose cache holds modules built elsewhere is still checked. About 0.2 s."""
    try:
        import cffi
    except ImportError as e:
        return f"cffi is missing ({e})"
    name = f"_vcb_compiler_probe_{os.getpid()}"
    ffi = cffi.FFI()
    ffi.cdef("double vcb_probe(double);")
    ffi.set_source(name, "double vcb_probe(double x) { return x + 1.0; }")
    work = tempfile.mkdtemp(prefix="vcbmodel-probe-")
    try:
        built = ffi.compile(tmpdir=work, verbose=False)
        spec = importlib.util.spec_from_file_location(name, built)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        if module.lib.vcb_probe(1.0) != 2.0:
            return "a compiled test function gave a wrong result"
    except Exception as e:  # noqa: BLE001 -- a missing compiler, headers or linker: the reason is the answer
        lines = str(e).strip().splitlines() or [type(e).__name__]
        return f"{type(e).__name__}: {lines[-1][:200]}"
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return None


def compiled_system(kind, equations, prestep, setup) -> tuple:
    """(CompiledSystem, p) for ``setup``'s inputs: a cached variant whose guards hold, or a new one."""
    p, structure = flatten(setup.inputs)
    key = (kind, len(setup.q0), len(setup.memory), structure)
    for variant in _VARIANTS.get(key, []):
        if variant.lib.guards_ok(variant.ffi.from_buffer("double[]", p)):
            return variant, p
    traced = trace_system(equations, prestep, setup)
    source = c_source(traced)
    digest = hashlib.sha256(source.encode()).hexdigest()
    lib, ffi = _compile(source, digest)
    variant = CompiledSystem(lib, ffi, len(setup.q0), tuple(traced.outputs), digest)
    if not lib.guards_ok(ffi.from_buffer("double[]", p)):
        raise RuntimeError("compiled guards reject the parameters they were traced with")
    _VARIANTS.setdefault(key, []).append(variant)
    log.debug("compiled %s variant %s (%d guards)", kind, digest[:12], len(traced.graph.guards))
    return variant, p


def integrate(system: CompiledSystem, p, setup, t_end, step, period=None):
    """Rows (t, q..., v..., outputs...) from t = 0 to t_end every ``period`` (default each
    step) with RK4 at ``step``; a non-finite state raises :class:`SimulationError`."""
    nsteps = max(1, int(round(t_end / step)))
    every = 1 if not period else max(1, int(round(period / step)))
    n_rows = nsteps // every + 1
    width = 1 + 2 * system.n + len(system.outputs)
    rec = np.zeros(n_rows * width)
    x = np.asarray(list(setup.q0) + list(setup.v0), float)
    memory = np.asarray(list(setup.memory) + [0.0], float)  # never empty (a C array)
    ffi = system.ffi
    rows = system.lib.integrate(ffi.from_buffer("double[]", p), ffi.from_buffer("double[]", x),
                                ffi.from_buffer("double[]", memory), float(step), nsteps, every,
                                ffi.from_buffer("double[]", rec))
    if rows < 0:
        raise SimulationError(f"the solution diverged (non-finite state) at t = {-rows * step:.6g} s at the "
                              "experiment's fixed step: a stiffness, mass or contact value far outside its "
                              "documented range is the usual cause (docs/rig-format.md)")
    return rec[: rows * width].reshape(rows, width)

"""One scalar law of state compiled to C, for a Python user function that reads the state itself.

A model whose state lives partly in Exudyn (the ANCF spring's end node) keeps its user function in
Python to read that state, but the law it evaluates from the numbers read is pure: traced once
through ``ops`` (:mod:`.trace`) into ``double value(const double *p, double a0, ...)``, compiled
with cffi and cached like the compiled systems (:mod:`.solve`): in this process by (kind, argument
count, the inputs' structure) and guards, on disk by the C source's hash. The inputs' floats are
the run-time parameters ``p``, so one compiled function serves every parameter value of a fit that
takes the law's same branches.
"""
from __future__ import annotations

import functools
import hashlib
import logging
from collections.abc import Callable, Sequence

from .inputs import flatten, parametrize
from .solve import _compile
from .trace import Graph, TraceOps

log = logging.getLogger("vcbmodel")

#: {(kind, argument count, structure): [(lib, ffi), ...]}: the compiled variants of this process
_FUNCTIONS: dict = {}
#: how many times a function was traced and built (or loaded from the disk cache) in this process
TRACES = {"count": 0}


def function_source(graph: Graph, result, n: int) -> tuple[str, str]:
    """(C source, cffi declarations) of ``result`` (a traced value of ``graph``) as
    ``value(p, a0..a{n-1})`` and of the graph's guards as ``guards_ok(p)``."""
    signature = "double value(const double *p" + "".join(f", double a{i}" for i in range(n)) + ")"
    lines = ["#include <math.h>", "", signature, "{", "    double r;",
             "    (void)p;" + "".join(f" (void)a{i};" for i in range(n))]
    lines += graph.c_statements({"r": result})
    lines += ["    return r;", "}", "", "int guards_ok(const double *p)", "{", "    int ok = 1;"]
    lines += graph.c_guards()
    lines += ["    return ok;", "}"]
    return "\n".join(lines) + "\n", f"int guards_ok(const double *p);\n{signature};\n"


def compiled_function(kind: str, function: Callable, inputs: dict, arguments: Sequence[float]) -> Callable[..., float]:
    """``function(args, inputs, ops) -> float`` as a C function of the ``len(arguments)`` numbers
    ``args`` at ``inputs``' values: returns ``value(*args) -> float``. ``kind`` names ``function``
    (one kind, one function); ``arguments`` are the trace point's values (a law branches on its
    arguments only through ``ops.where``, so they shape nothing). Raises
    :class:`~vcbmodel.compiled.CompilerUnavailable` without a working C compiler."""
    p, structure = flatten(inputs)
    key = (kind, len(arguments), structure)
    for lib, ffi in _FUNCTIONS.get(key, []):
        buffer = ffi.from_buffer("double[]", p)
        if lib.guards_ok(buffer):
            return functools.partial(lib.value, buffer)
    graph = Graph()
    args = [graph.state(f"a{i}", value) for i, value in enumerate(arguments)]
    result = function(args, parametrize(inputs, graph), TraceOps(graph))
    source, cdef = function_source(graph, result, len(arguments))
    lib, ffi = _compile(source, hashlib.sha256(source.encode()).hexdigest(), cdef)
    TRACES["count"] += 1
    buffer = ffi.from_buffer("double[]", p)
    if not lib.guards_ok(buffer):
        raise RuntimeError("compiled guards reject the parameters they were traced with")
    _FUNCTIONS.setdefault(key, []).append((lib, ffi))
    log.debug("compiled function %s (%d guards)", kind, len(graph.guards))
    return functools.partial(lib.value, buffer)

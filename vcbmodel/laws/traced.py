"""The arithmetic a traced value answers: the laws are written once on an ``ops`` namespace, and a
tracer (the compiled path's graph, the lean symbolic builder's fingerprint, Exudyn's symbolic writer)
records each operation a law applies to its values instead of computing it.

:class:`TracedArithmetic` maps Python's binary operators and comparisons onto two methods a tracer
defines: ``_op(name, *others)`` (self first) and ``_rop(name, other)`` (a reflected operator: the other
operand first). The operator names are those the tracers share: add, sub, mul, div, lt, le, gt, ge,
eq, ne. Unary operators and powers differ between tracers and stay with each.
"""
from __future__ import annotations


class TracedArithmetic:
    """Python's binary operators and comparisons, each recorded by ``_op`` / ``_rop`` under its name."""

    __slots__ = ()

    def _op(self, name: str, *others: object) -> TracedArithmetic:  # pragma: no cover - each tracer's own
        raise NotImplementedError

    def _rop(self, name: str, other: object) -> TracedArithmetic:  # pragma: no cover - each tracer's own
        raise NotImplementedError

    def __add__(self, other):
        return self._op("add", other)

    def __radd__(self, other):
        return self._rop("add", other)

    def __sub__(self, other):
        return self._op("sub", other)

    def __rsub__(self, other):
        return self._rop("sub", other)

    def __mul__(self, other):
        return self._op("mul", other)

    def __rmul__(self, other):
        return self._rop("mul", other)

    def __truediv__(self, other):
        return self._op("div", other)

    def __rtruediv__(self, other):
        return self._rop("div", other)

    def __lt__(self, other):
        return self._op("lt", other)

    def __le__(self, other):
        return self._op("le", other)

    def __gt__(self, other):
        return self._op("gt", other)

    def __ge__(self, other):
        return self._op("ge", other)

    def __eq__(self, other):
        return self._op("eq", other)

    def __ne__(self, other):
        return self._op("ne", other)

    __hash__ = object.__hash__  # a traced value is a node, hashed by identity (its == records a node)

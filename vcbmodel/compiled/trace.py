"""Tracing the pure law functions through their ``ops`` argument into straight-line C.

A law in :mod:`vcbmodel.laws` is written once, against an ``ops`` namespace (``where``, ``abs``,
``sqrt``, ``sign``, ``min``, ``sin``, ``cos``) and Python arithmetic. :class:`TraceOps` is one
more such namespace: called with :class:`Expr` values it records every operation once into a
:class:`Graph` (equal operations on equal inputs are shared, so each intermediate is named and
computed once; operations on constants are folded), and :meth:`Graph.c_statements` writes the
graph as C, one ``double`` per intermediate. No equation is copied by hand: the C is what the
law functions computed.

Every :class:`Expr` carries its value at the trace point, computed as the float law would
(``NumericOps`` semantics). A Python ``if`` on a value that depends only on parameters (``if
ws > 0.0``: a branch a law leaves out when its parameter is zero) is taken with that value
and recorded as a *guard*: compiled code is reused only for parameters that take the same
branches (:meth:`Graph.c_guards`). A Python ``if`` on the state raises: a law must branch on
the state with ``ops.where``.
"""
from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

from ..laws.traced import TracedArithmetic

CONST, PARAM, STATE = 0, 1, 2

_C_BINARY = {"add": "+", "sub": "-", "mul": "*", "div": "/"}
_C_COMPARE = {"lt": "<", "le": "<=", "gt": ">", "ge": ">=", "eq": "==", "ne": "!="}
#: C of an operation on its arguments ({0}, {1}, {2}: the names of their values); a comparison gives
#: 1.0 or 0.0; an operation not here is a C function of one argument (sqrt, sin, cos, acos, floor)
_C_FORMS = {**{op: "{0} " + c + " {1}" for op, c in _C_BINARY.items()},
            **{op: "({0} " + c + " {1}) ? 1.0 : 0.0" for op, c in _C_COMPARE.items()},
            "neg": "-{0}", "abs": "fabs({0})", "sign": "({0} > 0.0) ? 1.0 : (({0} < 0.0) ? -1.0 : 0.0)",
            "min": "({0} < {1}) ? {0} : {1}", "max": "({0} > {1}) ? {0} : {1}", "atan2": "atan2({0}, {1})",
            "pow": "pow({0}, {1})", "where": "({0} != 0.0) ? {1} : {2}"}


def _div(a, b):
    try:
        return a / b
    except ZeroDivisionError:
        return math.nan if a == 0 or a != a else math.copysign(math.inf, a) * math.copysign(1.0, b)


def _sqrt(a):
    return math.sqrt(a) if a >= 0 else math.nan


def _sign(a):
    return 1.0 if a > 0 else (-1.0 if a < 0 else 0.0)


def _acos(a):
    return math.acos(a) if -1.0 <= a <= 1.0 else math.nan


def _pow(a, b):
    try:
        return math.pow(a, b)
    except (ValueError, OverflowError):
        return math.nan


_EVAL = {
    "add": lambda a, b: a + b, "sub": lambda a, b: a - b, "mul": lambda a, b: a * b, "div": _div,
    "neg": lambda a: -a, "abs": abs, "sqrt": _sqrt, "sign": _sign, "sin": math.sin, "cos": math.cos,
    "min": lambda a, b: a if a < b else b, "max": lambda a, b: a if a > b else b,
    "atan2": math.atan2, "acos": _acos, "pow": _pow, "floor": lambda a: float(math.floor(a)),
    "lt": lambda a, b: float(a < b), "le": lambda a, b: float(a <= b), "gt": lambda a, b: float(a > b),
    "ge": lambda a, b: float(a >= b), "eq": lambda a, b: float(a == b), "ne": lambda a, b: float(a != b),
    "where": lambda c, a, b: a if c else b,
}


class Graph:
    """The recorded operations: ``nodes[i] = (op, arguments)``; arguments are node indices,
    except for ``const`` (the float), ``param`` (its index in the parameter vector) and ``state``
    (its C expression, e.g. ``x[3]``)."""

    def __init__(self):
        self.nodes = []
        self.values = []
        self.kinds = []
        self._memo = {}
        self.guards = []  # (node index, the branch taken: True/False)
        self.param_names = []

    def _add(self, op, args, value, kind):
        key = (op, args) if op != "const" else ("const", repr(value))
        index = self._memo.get(key)
        if index is None:
            index = len(self.nodes)
            self.nodes.append((op, args))
            self.values.append(value)
            self.kinds.append(kind)
            self._memo[key] = index
        return Expr(self, index)

    def const(self, value) -> Expr:
        return self._add("const", (), float(value), CONST)

    def param(self, name, value) -> Expr:
        """A parameter: read at run time from ``p[i]``; ``value`` is its value at the trace."""
        self.param_names.append(name)
        return self._add("param", (len(self.param_names) - 1,), float(value), PARAM)

    def state(self, c_name, value) -> Expr:
        """A state or time value, read at run time from ``c_name`` (e.g. ``x[2]``, ``t``)."""
        return self._add("state", (c_name,), float(value), STATE)

    def lift(self, x) -> Expr:
        if isinstance(x, Expr):
            if x.graph is not self:
                raise ValueError("an expression of another trace")
            return x
        if isinstance(x, bool):
            return self.const(1.0 if x else 0.0)
        if isinstance(x, (int, float)):
            return self.const(x)
        raise TypeError(f"cannot trace a {type(x).__name__} ({x!r}): the laws take numbers")

    def apply(self, op, *args) -> Expr:
        """Record ``op`` on ``args`` (folded when all are constants, simplified where exact)."""
        xs = [self.lift(a) for a in args]
        idx = tuple(x.index for x in xs)
        vals = [self.values[i] for i in idx]
        value = _EVAL[op](*vals)
        if all(self.kinds[i] == CONST for i in idx):
            return self.const(value)
        simple = self._simplify(op, xs, vals)
        if simple is not None:
            return simple
        kind = max(self.kinds[i] for i in idx)
        return self._add(op, idx, value, kind)

    def take(self, table, index) -> Expr:
        """``table[int(index) mod len]`` for a table of consecutive parameters (``p[base + k]``)."""
        items = [self.lift(x) for x in table]
        base = self.nodes[items[0].index][1][0] if self.nodes[items[0].index][0] == "param" else None
        if base is None or any(self.nodes[x.index] != ("param", (base + k,)) for k, x in enumerate(items)):
            raise TypeError("ops.take needs a table of run-time parameters (a tuple field of the inputs)")
        i = self.lift(index)
        value = self.values[items[int(self.values[i.index]) % len(items)].index]
        return self._add(f"take:{base}:{len(items)}", (i.index,), value, max(STATE, self.kinds[i.index]))

    def _simplify(self, op, xs, vals):
        consts = [self.kinds[x.index] == CONST for x in xs]
        if op == "add":
            if consts[0] and vals[0] == 0.0:
                return xs[1]
            if consts[1] and vals[1] == 0.0:
                return xs[0]
        elif op == "sub" and consts[1] and vals[1] == 0.0:
            return xs[0]
        elif op == "mul":
            for i in (0, 1):
                if consts[i] and vals[i] == 1.0:
                    return xs[1 - i]
                if consts[i] and vals[i] == 0.0:
                    return self.const(0.0)
        elif op == "div" and consts[1] and vals[1] == 1.0:
            return xs[0]
        elif op == "where" and consts[0]:
            return xs[1] if vals[0] else xs[2]
        elif op == "where" and xs[1].index == xs[2].index:
            return xs[1]
        return None

    def used(self, roots: Iterable[int]) -> list[int]:
        """Indices of the nodes the ``roots`` depend on, in order."""
        need = set()
        stack = list(roots)
        while stack:
            i = stack.pop()
            if i in need:
                continue
            need.add(i)
            op, args = self.nodes[i]
            if op not in ("const", "param", "state"):
                stack.extend(args)
        return sorted(need)

    def c_statements(self, outputs: dict[str, Expr | float], prefix: str = "v") -> list[str]:
        """C lines computing the ``outputs`` ({C lvalue: Expr or number}) from ``p``, the state
        names and ``t``."""
        outs = {target: self.lift(e) for target, e in outputs.items()}
        lines = []
        for i in self.used([e.index for e in outs.values()]):
            lines.append(f"    const double {prefix}{i} = {self._c_expr(i, prefix)};")
        for target, e in outs.items():
            lines.append(f"    {target} = {prefix}{e.index};")
        return lines

    def _c_expr(self, i, prefix):
        op, args = self.nodes[i]
        if op == "const":
            v = self.values[i]
            return repr(v) if math.isfinite(v) else ("NAN" if v != v else ("INFINITY" if v > 0 else "-INFINITY"))
        if op == "param":
            return f"p[{args[0]}]"
        if op.startswith("take:"):
            _, base, n = op.split(":")
            return f"p[{base} + ((((long){prefix}{args[0]}) % {n}) + {n}) % {n}]"
        if op == "state":
            return args[0]
        return _C_FORMS.get(op, op + "({0})").format(*(f"{prefix}{j}" for j in args))

    def c_guards(self, prefix: str = "g") -> list[str]:
        """C lines setting ``ok`` to 0 when the parameters ``p`` take another branch than the trace."""
        if not self.guards:
            return ["    (void)p;"]
        roots = [i for i, _ in self.guards]
        lines = [f"    const double {prefix}{i} = {self._c_expr(i, prefix)};" for i in self.used(roots)]
        for i, taken in self.guards:
            lines.append(f"    if (({prefix}{i} != 0.0) != {1 if taken else 0}) ok = 0;")
        return lines


class Expr(TracedArithmetic):
    """A traced value: a node of a :class:`Graph`; arithmetic and comparisons record nodes."""

    __slots__ = ("graph", "index")
    __array_priority__ = 1000  # numpy scalars defer to Expr's reflected operators

    def __init__(self, graph, index):
        self.graph, self.index = graph, index

    @property
    def value(self) -> float:
        """The value at the trace point (float)."""
        return self.graph.values[self.index]

    def _op(self, op, *others):
        return self.graph.apply(op, self, *others)

    def _rop(self, op, other):
        return self.graph.apply(op, other, self)


    def __neg__(self):
        return self._op("neg")

    def __pos__(self):
        return self

    def __abs__(self):
        return self._op("abs")

    def __pow__(self, exponent):
        if exponent == 2:
            return self * self
        if exponent == 0.5:
            return self._op("sqrt")
        raise TypeError(f"trace: power {exponent!r} is not supported (write it as products)")

    def __bool__(self):
        kind = self.graph.kinds[self.index]
        if kind == STATE:
            raise TypeError("a law branches in Python on the state: write the branch with ops.where")
        taken = bool(self.value)
        if kind == PARAM:
            self.graph.guards.append((self.index, taken))
        return taken

    def __float__(self):
        if self.graph.kinds[self.index] != CONST:
            raise TypeError("float() of a traced parameter or state value")
        return self.value


class TraceOps:
    """The ``ops`` namespace of a trace (the operations of ``laws.friction.NumericOps``)."""

    def __init__(self, graph: Graph):
        self.graph = graph

    def where(self, condition: Expr | float, if_true: Expr | float, if_false: Expr | float) -> Expr:
        return self.graph.apply("where", condition, if_true, if_false)

    def abs(self, x: Expr | float) -> Expr:
        return self.graph.apply("abs", x)

    def sqrt(self, x: Expr | float) -> Expr:
        return self.graph.apply("sqrt", x)

    def sign(self, x: Expr | float) -> Expr:
        return self.graph.apply("sign", x)

    def min(self, a: Expr | float, b: Expr | float) -> Expr:
        return self.graph.apply("min", a, b)

    def max(self, a: Expr | float, b: Expr | float) -> Expr:
        return self.graph.apply("max", a, b)

    def atan2(self, y: Expr | float, x: Expr | float) -> Expr:
        return self.graph.apply("atan2", y, x)

    def acos(self, x: Expr | float) -> Expr:
        return self.graph.apply("acos", x)

    def pow(self, a: Expr | float, b: Expr | float) -> Expr:
        return self.graph.apply("pow", a, b)

    def floor(self, x: Expr | float) -> Expr:
        return self.graph.apply("floor", x)

    def take(self, table: Sequence[float], index: Expr | float) -> Expr:
        return self.graph.take(table, index)

    def sin(self, x: Expr | float) -> Expr:
        return self.graph.apply("sin", x)

    def cos(self, x: Expr | float) -> Expr:
        return self.graph.apply("cos", x)

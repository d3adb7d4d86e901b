"""Lean Exudyn symbolic user functions from the pure laws.

Exudyn's symbolic evaluator is a tree interpreter: a value used in several places is computed again
at every use, and of an if-then-else only the branch taken is evaluated (exudyn-notes, "Symbolic
user functions: what they cost"). A law recorded as written (its ``ops`` on Exudyn's symbolic
reals) repeats whole subtrees: the shaft friction's reaction, band and branch coefficients appear
in one another many times over.

Here the law is first traced once through the compiled path's :class:`~vcbmodel.compiled.trace.TraceOps`
(each intermediate recorded once, constants folded: the same law functions, no second copy of an
equation), and the traced graph is then written as an Exudyn expression with its branches chosen
first: the outermost condition of an ``ops.where`` becomes an if-then-else at the top, and each side
is the law with that condition fixed (the other branch and every quantity only it needed drop
out; a product of conditions falls to its remaining factor), recursively, so the expression the
evaluator runs for a state is branch-free arithmetic of the branch that applies, with the decisions
it took. The arithmetic is the traced law's, operation for operation, so the result is the one the
recorded law gives.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence

from ..compiled.trace import CONST, Expr, Graph, TraceOps

#: Comparison operations: their value is exactly 1.0 or 0.0
COMPARISONS = ("lt", "le", "gt", "ge", "eq", "ne")
#: Most branch combinations written out; a law with more is written with its if-then-else in place.
MAX_LEAVES = 256
#: State values at the trace (any: no Python ``if`` may read the state, and nothing is folded with it).
_TRACE_STATE = 0.3


def trace_law(law: Callable, n_args: int) -> tuple[Graph, int, list[int]]:
    """Trace ``law(*args, ops)`` for ``n_args`` state arguments: (graph, root node, argument nodes)."""
    graph = Graph()
    args = [graph.state(f"a{i}", _TRACE_STATE + 0.1 * i) for i in range(n_args)]
    root = graph.lift(law(*args, TraceOps(graph)))
    return graph, root.index, [a.index for a in args]


def lean_expression(law: Callable, args: Sequence) -> object:
    """The Exudyn symbolic expression of ``law(*args, ops)`` (``args``: Exudyn symbolic reals, e.g.
    a user function's arguments), its branches chosen first (module docstring)."""
    from .core import exudyn_modules

    exu, _ = exudyn_modules()
    graph, root, leaves = trace_law(law, len(args))
    writer = _Writer(graph, exu.symbolic, dict(zip(leaves, args)))
    plan = _decisions(graph, root, [MAX_LEAVES])
    return writer.tree(root) if plan is None else writer.decided(plan)


def _decisions(graph: Graph, root: int, budget: list[int]):
    """The branches of ``root`` chosen first: ``root`` (no condition left) or (condition, plan if
    true, plan if false); None when more than ``budget[0]`` branch combinations would be written."""
    conditions = _conditions(graph, root)
    if not conditions:
        budget[0] -= 1
        return root if budget[0] >= 0 else None
    c = _outermost(graph, conditions)
    if_true = _decisions(graph, _fixed(graph, root, c, True), budget)
    if_false = None if if_true is None else _decisions(graph, _fixed(graph, root, c, False), budget)
    return None if if_false is None else (c, if_true, if_false)


def _is_boolean(graph: Graph, i: int) -> bool:
    op, args = graph.nodes[i]
    return op in COMPARISONS or (op == "mul" and all(_is_boolean(graph, a) for a in args))


def _conditions(graph: Graph, root: int) -> list[int]:
    """The conditions the value of ``root`` branches on: each ``where``'s condition, a product of
    comparisons split into its factors."""
    found = set()

    def add(i):
        op, args = graph.nodes[i]
        if op == "mul" and _is_boolean(graph, i):
            for a in args:
                add(a)
        elif graph.kinds[i] != CONST:
            found.add(i)

    for i in graph.used([root]):
        op, args = graph.nodes[i]
        if op == "where" and _min_max(graph, i) is None:
            add(args[0])
    return sorted(found)


def _min_max(graph: Graph, i: int) -> tuple[str, int, int] | None:
    """("max" or "min", a, b) for ``where(a > b, a, b)`` and its kin (written as Exudyn's max or
    min: each operand evaluated once, no decision), else None."""
    op, args = graph.nodes[i]
    if op != "where":
        return None
    cop, cargs = graph.nodes[args[0]]
    if cop not in ("lt", "le", "gt", "ge") or len(cargs) != 2 or set(cargs) != set(args[1:]) or cargs[0] == cargs[1]:
        return None
    larger_if_true = (cop in ("gt", "ge")) == (cargs[0] == args[1])
    return ("max" if larger_if_true else "min", args[1], args[2])


def _outermost(graph: Graph, conditions: list[int]) -> int:
    """The condition to decide first: one that no other condition needs (deciding it may leave the
    conditions inside it unneeded), the earliest recorded of those."""
    inner = set()
    for c in conditions:
        inner.update(i for i in graph.used([c]) if i != c)
    return min(c for c in conditions if c not in inner)


def _fixed(graph: Graph, root: int, condition: int, truth: bool) -> int:
    """``root`` re-recorded with ``condition`` known: a ``where`` on it takes its branch, a
    comparison becomes 1 or 0 (products, ``where`` and arithmetic on it then fold); nodes that do
    not depend on it stay as they are."""
    new = {}
    for i in graph.used([root]):
        op, args = graph.nodes[i]
        if i == condition and op in COMPARISONS:
            new[i] = graph.const(1.0 if truth else 0.0)
        elif op == "where" and args[0] == condition:
            new[i] = new[args[1] if truth else args[2]]
        elif op in ("const", "param", "state") or not any(new[a].index != a for a in args):
            new[i] = Expr(graph, i)
        else:
            new[i] = graph.apply(op, *(new[a] for a in args))
    return new[root].index


class _Writer:
    """Writes graph nodes as Exudyn symbolic expressions."""

    def __init__(self, graph: Graph, es, leaves: dict):
        self.graph, self.es, self.leaves = graph, es, leaves
        self.done = {}

    def decided(self, plan):
        if isinstance(plan, int):
            return self.tree(plan)
        c, if_true, if_false = plan
        return self.es.IfThenElse(self.tree(c), self.decided(if_true), self.decided(if_false))

    def tree(self, i: int):
        if i not in self.done:
            self.done[i] = self._node(i)
        return self.done[i]

    def _node(self, i: int):
        es, (op, args) = self.es, self.graph.nodes[i]
        if op == "const":
            return es.Real(self.graph.values[i])
        if op == "state":
            return self.leaves[i]
        if op in ("param",) or op.startswith("take:"):
            raise TypeError(f"a symbolic user function cannot read {op} (run-time parameters are constants here)")
        pick = _min_max(self.graph, i)
        if pick is not None:
            return _WRITE[pick[0]](es, self.tree(pick[1]), self.tree(pick[2]))
        if op == "mul" and args[0] == args[1] and self.graph.nodes[args[0]][0] not in ("const", "state"):
            return es.pow(self.tree(args[0]), es.Real(2.0))  # a square: its operand evaluated once
        a = [self.tree(j) for j in args]
        return _WRITE[op](es, *a)


_WRITE = {
    "add": lambda es, a, b: a + b, "sub": lambda es, a, b: a - b, "mul": lambda es, a, b: a * b,
    "div": lambda es, a, b: a / b, "neg": lambda es, a: -a,
    "lt": lambda es, a, b: a < b, "le": lambda es, a, b: a <= b, "gt": lambda es, a, b: a > b,
    "ge": lambda es, a, b: a >= b, "eq": lambda es, a, b: a == b, "ne": lambda es, a, b: a != b,
    "where": lambda es, c, a, b: es.IfThenElse(c, a, b),
    "abs": lambda es, a: es.abs(a), "sqrt": lambda es, a: es.sqrt(a), "sign": lambda es, a: es.sign(a),
    "sin": lambda es, a: es.sin(a), "cos": lambda es, a: es.cos(a), "min": lambda es, a, b: es.min(a, b),
    "max": lambda es, a, b: es.max(a, b), "atan2": lambda es, a, b: es.atan2(a, b), "acos": lambda es, a: es.acos(a),
    "pow": lambda es, a, b: es.pow(a, b), "floor": lambda es, a: es.floor(a),
}

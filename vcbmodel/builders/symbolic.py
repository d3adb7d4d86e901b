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
it took. Two more decisions are made where they save work: a comparison with a max or min is
decided by its cheaper half first (``|w| <= max(band(F_n), w0)``: a shaft at rest never computes the
reaction), and in each branch the sign of an argument the branch takes ``sign`` or ``abs`` of is
decided last, so ``sign(w)`` and ``abs(w)`` become 1 and w (or -1 and -w, or 0) and the constants
they multiply fold. The branch-free arithmetic is then written by
:class:`~vcbmodel.builders.symbolic_writer.Writer` in the form that evaluates fewest nodes (normal
forms of sums and products, magnitudes as ``NormL2``, comparisons merged): the decisions are the
law's, the values the law's to rounding.

The written expression is kept as construction steps (:class:`~vcbmodel.builders.symbolic_writer.Tape`),
keyed by the law's fingerprint: the operations it applies to its arguments, in order, with every
number it brings in (the trace is a function of them; recording them costs a quarter of the trace). A
model rebuilt with the same law and numbers (a benchmark's repeats, a fit's runs with the same values)
builds the expression on its own arguments but traces, plans and writes nothing.
"""
from __future__ import annotations

from collections.abc import Callable, Sequence

from ..laws.traced import TracedArithmetic
from ..compiled.trace import CONST, Expr, Graph, TraceOps
from .exudyn_loader import exudyn_modules
from .symbolic_writer import Tape, Writer, min_max, tree_cost

#: Comparison operations: their value is exactly 1.0 or 0.0
COMPARISONS = ("lt", "le", "gt", "ge", "eq", "ne")
#: Most branch combinations written out; a law with more is written with its if-then-else in place.
MAX_LEAVES = 256
#: State values at the trace (any: no Python ``if`` may read the state, and nothing is folded with it).
_TRACE_STATE = 0.3
#: Written laws kept ({fingerprint: Tape}; a model rebuilt with the same law and numbers reuses its tape).
_PLANS_KEPT = 32
_plans: dict = {}


def trace_law(law: Callable, n_args: int) -> tuple[Graph, int, list[int]]:
    """Trace ``law(*args, ops)`` for ``n_args`` state arguments: (graph, root node, argument nodes)."""
    graph = Graph()
    args = [graph.state(f"a{i}", _TRACE_STATE + 0.1 * i) for i in range(n_args)]
    root = graph.lift(law(*args, TraceOps(graph)))
    return graph, root.index, [a.index for a in args]


def lean_expression(law: Callable, args: Sequence) -> object:
    """The Exudyn symbolic expression of ``law(*args, ops)`` (``args``: Exudyn symbolic reals, e.g.
    a user function's arguments), its branches chosen first (module docstring)."""
    exu, _ = exudyn_modules()
    return _planned(law, len(args)).replay(exu.symbolic, args)


def _planned(law: Callable, n_args: int) -> Tape:
    """``law`` traced, planned and written once per distinct sequence of operations (planning and
    writing cost ten times the trace, the trace four times the fingerprint): the written expression
    as a :class:`Tape` to build for any arguments."""
    key = _fingerprint(law, n_args)
    tape = None if key is None else _plans.get(key)
    if tape is not None:
        return tape
    graph, root, leaves = trace_law(law, n_args)
    plan = _decisions(graph, root, [MAX_LEAVES])
    tape = Tape()
    writer = Writer(graph, tape.es, {leaf: tape.argument(k) for k, leaf in enumerate(leaves)})
    tape.root = writer.tree(root) if plan is None else writer.decided(plan)
    if key is not None:
        _plans[key] = tape
        while len(_plans) > _PLANS_KEPT:  # the oldest first (a tape is never changed: threads may share one)
            _plans.pop(next(iter(_plans)), None)
    return tape


def _fingerprint(law: Callable, n_args: int) -> tuple | None:
    """The operations ``law`` applies to its arguments, in order, with every number it brings in
    (its ``repr``): the trace is a function of them, so equal fingerprints trace to one graph. None
    where the law does something the fingerprint does not record (it is then traced every time)."""
    steps: list[tuple] = []
    try:
        result = law(*(_Step(steps, -1 - k) for k in range(n_args)), _FingerprintOps(steps))
    except Exception:  # noqa: BLE001 (the trace then says what is wrong, or plans without a key)
        return None
    return (n_args, tuple(steps), _Step.mark(result))


class _Step(TracedArithmetic):
    """A value in a fingerprint: operations on it record steps."""

    __slots__ = ("steps", "index")

    def __init__(self, steps: list, index: int):
        self.steps, self.index = steps, index

    @staticmethod
    def mark(x: object) -> object:
        return ("step", x.index) if isinstance(x, _Step) else repr(x)

    def _op(self, name: str, *others: object) -> _Step:
        self.steps.append((name, self.index) + tuple(_Step.mark(o) for o in others))
        return _Step(self.steps, len(self.steps) - 1)

    def _rop(self, name: str, other: object) -> _Step:
        self.steps.append((name, _Step.mark(other), self.index))
        return _Step(self.steps, len(self.steps) - 1)

    __pow__ = lambda s, o: s._op("pow", o)  # noqa: E731
    __neg__ = lambda s: s._op("neg")  # noqa: E731
    __pos__ = lambda s: s._op("pos")  # noqa: E731
    __abs__ = lambda s: s._op("abs")  # noqa: E731

    def __bool__(self):
        raise TypeError("a fingerprint cannot branch on the state")


class _FingerprintOps:
    """The ``ops`` of a fingerprint: every operation (any name) is recorded with its arguments."""

    def __init__(self, steps: list):
        self._steps = steps

    def __getattr__(self, name: str) -> Callable:
        steps = self._steps

        def record(*args):
            steps.append((name,) + tuple(_Step.mark(a) for a in args))
            return _Step(steps, len(steps) - 1)
        return record


def _decisions(graph: Graph, root: int, budget: list[int], nonzero: frozenset = frozenset()):
    """The branches of ``root`` chosen first: ``root`` (no condition left) or (condition, plan if
    true, plan if false); None when more than ``budget[0]`` branch combinations would be written.
    ``nonzero``: arguments the decisions taken so far show to be nonzero."""
    conditions = _conditions(graph, root)
    if not conditions:
        return _signs_decided(graph, root, budget, nonzero)
    c = _outermost(graph, conditions)
    known = [nonzero | _nonzero(graph, c, truth) for truth in (True, False)]
    if_true = _decisions(graph, _fixed(graph, root, c, True), budget, known[0])
    if_false = None if if_true is None else _decisions(graph, _fixed(graph, root, c, False), budget, known[1])
    if if_false is None:
        return None
    split = _either(graph, c)
    if split is None:
        return (c, if_true, if_false)
    junction, first, second = split  # the cheaper test first; the other only where it decides
    if junction == "or":
        return (first, if_true, (second, if_true, if_false))
    return (first, (second, if_true, if_false), if_false)


def _signs_decided(graph: Graph, root: int, budget: list[int], nonzero: frozenset = frozenset()):
    """A branch-free ``root`` with the sign of an argument it takes ``sign`` or ``abs`` of decided
    first: ``y > 0``, ``y < 0`` or ``y == 0`` (not the last where ``y`` is in ``nonzero``), and in
    each, ``sign(y)`` and ``abs(y)`` written as what they are there (1 and y, -1 and -y, 0 and 0),
    so the constants they multiply fold."""
    y = next((a[0] for op, a in (graph.nodes[i] for i in graph.used([root]))
              if op in ("sign", "abs") and graph.nodes[a[0]][0] == "state"), None)
    if y is None:
        budget[0] -= 1
        return root if budget[0] >= 0 else None
    Y = Expr(graph, y)
    plans = []
    for s in (1.0, -1.0) if y in nonzero else (1.0, -1.0, 0.0):
        known = {"sign": graph.const(s), "abs": Y if s > 0 else (-Y if s < 0 else graph.const(0.0))}
        plans.append(_decisions(graph, _substituted(graph, root, y, known), budget, nonzero | {y}))
        if plans[-1] is None:
            return None
    if y in nonzero:
        return (graph.apply("gt", Y, 0.0).index, plans[0], plans[1])
    return (graph.apply("gt", Y, 0.0).index, plans[0], (graph.apply("lt", Y, 0.0).index, plans[1], plans[2]))


def _nonzero(graph: Graph, c: int, truth: bool) -> frozenset:
    """{y} where condition ``c`` being ``truth`` shows the argument y to be nonzero: ``|y| > m`` or
    ``|y| >= m`` (and the negations that read so) with m known not below a number >= 0 (> 0 for
    ``>=``); else empty."""
    op, (left, right) = graph.nodes[c][0], (graph.nodes[c][1] + (None, None))[:2]
    if op not in ("lt", "le", "gt", "ge"):
        return frozenset()
    flip = {"lt": "gt", "le": "ge", "gt": "lt", "ge": "le"}
    if graph.nodes[right][0] == "abs":
        op, left, right = flip[op], right, left
    if not truth:
        op = {"lt": "ge", "le": "gt", "gt": "le", "ge": "lt"}[op]
    y = graph.nodes[left][1][0] if graph.nodes[left][0] == "abs" else None
    if y is None or graph.nodes[y][0] != "state" or op not in ("gt", "ge"):
        return frozenset()
    low = _lower_bound(graph, right)
    return frozenset({y}) if low is not None and (low > 0.0 or (low == 0.0 and op == "gt")) else frozenset()


def _lower_bound(graph: Graph, i: int) -> float | None:
    """A number node ``i`` is never below: a constant, or a max with one (else None)."""
    if graph.kinds[i] == CONST:
        return graph.values[i]
    pick = min_max(graph, i)
    if pick is None or pick[0] != "max":
        return None
    bounds = [b for b in (_lower_bound(graph, pick[1]), _lower_bound(graph, pick[2])) if b is not None]
    return max(bounds) if bounds else None


def _substituted(graph: Graph, root: int, y: int, known: dict) -> int:
    """``root`` re-recorded with ``sign(y)`` and ``abs(y)`` replaced by ``known['sign']`` and
    ``known['abs']`` (and ``y`` by 0 where it is 0)."""
    new = {}
    zero = graph.values[known["sign"].index] == 0.0
    for i in graph.used([root]):
        op, args = graph.nodes[i]
        if op in ("sign", "abs") and args[0] == y:
            new[i] = known[op]
        elif i == y and zero:
            new[i] = graph.const(0.0)
        elif op in ("const", "param", "state") or not any(new[a].index != a for a in args):
            new[i] = Expr(graph, i)
        else:
            new[i] = graph.apply(op, *(new[a] for a in args))
    return new[root].index


def _either(graph: Graph, c: int) -> tuple[str, int, int] | None:
    """A comparison with a max or min, ``x <= max(a, b)`` and its kin, as two comparisons
    ("or" or "and", cheaper, other): ``x <= max(a, b)`` is ``x <= a or x <= b`` for every
    number, so where the cheaper one holds the other is not evaluated. None for other conditions."""
    op, args = graph.nodes[c]
    if op not in ("lt", "le", "gt", "ge") or len(args) != 2:
        return None
    if op in ("gt", "ge"):  # a > b is b < a
        op, args = {"gt": "lt", "ge": "le"}[op], (args[1], args[0])
    for side in (1, 0):  # x <= m (side 1) or m <= x (side 0)
        pick = min_max(graph, args[side])
        if pick is None:
            continue
        kind, a, b = pick
        x = args[1 - side]
        tests = [graph.apply(op, *((Expr(graph, x), Expr(graph, m)) if side == 1 else (Expr(graph, m), Expr(graph, x)))).index
                 for m in (a, b)]
        tests.sort(key=lambda i: tree_cost(graph, i))
        return ("or" if (kind == "max") == (side == 1) else "and", tests[0], tests[1])
    return None


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
        if op == "where" and min_max(graph, i) is None:
            add(args[0])
    return sorted(found)


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

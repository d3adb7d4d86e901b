"""Writing a traced law's arithmetic as lean Exudyn symbolic expressions (for
:mod:`vcbmodel.builders.symbolic`, which chooses the branches first).

Exudyn's evaluator is a tree interpreter: every node is a call, a value used twice is computed twice
(no shared values), a leaf or an addition costs about 2 ns, a sin or cos about 6, a pow about 9
(measured in a solve; ``COST``). The writer therefore writes each node of the traced graph in the
form that evaluates fewest nodes, by rules that keep the law's value to rounding:

- **Normal forms of sums and products** (:func:`form`): a node through sums, differences, negation,
  products and division by constants is c0 + sum of coefficient x product of factors; the law's
  constants gather into one coefficient per term (``12.822 * ((-125.784 * sin(x)) / 2.74)`` is one
  coefficient of ``sin(x)``), a sum that multiplies is a factor of its own, scaled to a first
  coefficient of 1 (so a sum and its multiples, and a sum computed by two routes, are one factor:
  the reaction's component entering the root and the linear term is recognised as one), and a factor
  twice is a square (pow of it where evaluating it again would cost more).
- **Magnitudes** (:meth:`Writer._norm`): the square root of a sum of squares with positive
  coefficients (a shaft reaction's magnitude) is Exudyn's ``NormL2`` of the scaled parts: each part
  evaluated once, no pow, a coefficient outside folded in.
- **Comparisons** (:meth:`Writer._comparison`): two varying sides that share a term are compared as
  their merged difference against 0; ``|a| <= k sqrt(q)`` with a one term as ``a^2 <= k^2 q`` (the
  stick test's applied torque then merges into its reaction), a difference of two squares as the
  absolute values of its parts; both sides divided by a positive number where that drops
  multiplications; a cheap side against a magnitude is first compared with the magnitude's bound
  without sin and cos (a sliding shaft is far outside the stick band: the band test reads no trig).

Reassociation changes the last bits of a value (1e-16 relative, tested against the law at every
branch); the decisions are the law's.
"""
from __future__ import annotations

import math
from collections.abc import Sequence

from ..laws.traced import TracedArithmetic
from ..compiled.trace import Graph

def min_max(graph: Graph, i: int) -> tuple[str, int, int] | None:
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


#: Rough cost of evaluating a node of each kind in Exudyn's tree interpreter (ns, measured in a
#: solve: a leaf and an add about 2, a sin 6, a pow 9), to choose between ways of writing a value.
COST = {"const": 1.0, "state": 1.5, "abs": 2.5, "sign": 2.5, "sqrt": 5.0, "sin": 6.0, "cos": 6.0, "pow": 9.0,
         "where": 3.0, "min": 3.0, "max": 3.0, "atan2": 20.0, "acos": 15.0}
COST_OTHER = 2.0


def tree_cost(graph: Graph, i: int, memo: dict | None = None) -> float:
    """Estimated cost of node ``i`` as the writer writes it (a tree: a shared value is paid at every
    use; of an if-then-else the dearer branch)."""
    memo = {} if memo is None else memo
    if i not in memo:
        op, args = graph.nodes[i]
        pick = min_max(graph, i)
        if op in ("const", "param", "state"):
            memo[i] = COST.get(op, COST_OTHER)
        elif pick is not None:
            memo[i] = COST[pick[0]] + tree_cost(graph, pick[1], memo) + tree_cost(graph, pick[2], memo)
        elif op == "where":
            memo[i] = COST["where"] + tree_cost(graph, args[0], memo) + max(tree_cost(graph, a, memo) for a in args[1:])
        elif _is_square(graph, i):
            memo[i] = min(2.0 * tree_cost(graph, args[0], memo) + COST_OTHER,
                          tree_cost(graph, args[0], memo) + COST["pow"] + COST["const"])
        else:
            memo[i] = COST.get(op, COST_OTHER) + sum(tree_cost(graph, a, memo) for a in args)
    return memo[i]


def _is_square(graph: Graph, i: int) -> bool:
    op, args = graph.nodes[i]
    return op == "mul" and args[0] == args[1]


class Writer:
    """Writes graph nodes as Exudyn symbolic expressions (``es``: ``exudyn.symbolic``; ``leaves``:
    {argument node: the user function's symbolic argument}). Each node and each sum is written once
    and shared where it recurs (Exudyn's trees are reference-counted graphs: sharing saves memory and
    writing, not evaluation)."""

    def __init__(self, graph: Graph, es: object, leaves: dict):
        self.graph, self.es, self.leaves = graph, es, leaves
        self.done, self.plans, self.costs, self.forms, self.sums = {}, {}, {}, {}, {}
        self.pretests = {}  # comparison node: (its bound test, the comparison itself)

    def decided(self, plan: int | tuple) -> object:
        """A plan of :func:`vcbmodel.builders.symbolic.lean_expression`: a node, or (condition, plan if
        true, plan if false) as an if-then-else."""
        if isinstance(plan, int):
            return self.tree(plan)
        if id(plan) not in self.plans:  # a plan reached by two decisions is written once (a shared subtree)
            c, if_true, if_false = plan
            condition, if_true, if_false = self.tree(c), self.decided(if_true), self.decided(if_false)
            if c in self.pretests:  # the bound decides false first: no if-then-else inside the condition
                above, compared = self.pretests[c]
                self.plans[id(plan)] = self.es.IfThenElse(above, if_false, self.es.IfThenElse(compared, if_true, if_false))
            else:
                self.plans[id(plan)] = self.es.IfThenElse(condition, if_true, if_false)
        return self.plans[id(plan)]

    def tree(self, i: int) -> object:
        """Node ``i`` as an Exudyn expression."""
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
        pick = min_max(self.graph, i)
        if pick is not None:
            return _WRITE[pick[0]](es, self.tree(pick[1]), self.tree(pick[2]))
        if op in ("add", "sub", "neg", "mul", "div"):
            c0, terms = form(self.graph, i, self.forms)
            if terms and (c0, terms) != (0.0, {(("n", i),): 1.0}):
                return self._sum(c0, terms)
        if self._normable(i):
            return self._norm(i)
        if op in ("lt", "le", "gt", "ge"):
            return self._comparison(op, args, i)
        a = [self.tree(j) for j in args]
        return _WRITE[op](es, *a)

    def _comparison(self, op: str, args: tuple, i: int):
        """A comparison: as a merged difference (:func:`_difference`), or both sides divided by a
        positive number where that saves multiplications, or as it is."""
        es = self.es
        difference = _difference(self.graph, op, args, self.forms)
        if difference is not None:
            cmp, (c0, terms) = difference
            sides = _squares_compared(c0, terms)
            if sides is None:
                return _WRITE[cmp](es, self._sum(c0, terms), es.Real(0.0))
            op = cmp
        else:
            sides = [self._side(j) for j in args]
        if not all(side is not None for side in sides):
            return _WRITE[op](es, self.tree(args[0]), self.tree(args[1]))
        best = min((s for side in sides for s in [1.0] + [abs(v) for v in side[1][1].values()]),
                   key=lambda s: sum(_multiplications(side, s) for side in sides))
        written = [self._side_written(side, best) for side in sides]
        compared = _WRITE[op](es, *written)
        big = 1 if op in ("lt", "le") else 0  # x <= N, or N >= x
        bound = self._norm_bound(sides[big], best) if tree_cost(self.graph, args[1 - big], self.costs) <= 6.0 else None
        if bound is None:
            return compared
        # x above a bound of N that reads no sin or cos (|sin|, |cos| <= 1) decides the comparison false
        above = written[1 - big] > self._sum(*bound)
        self.pretests[i] = (above, compared)
        return es.IfThenElse(above, es.Real(0.0), compared)

    def _norm_bound(self, side: tuple, s: float) -> tuple[float, dict] | None:
        """An upper bound of a norm side divided by ``s`` (the sum of its parts' bounds, each with
        sin and cos at most 1), where it reads no sin or cos; None for other sides."""
        if side[0] != "norm":
            return None
        j, k = side[1][0], side[1][1][()] / s
        c0, terms = form(self.graph, self.graph.nodes[j][1][0], self.forms)
        total, trig = {}, [False]
        const = k * math.sqrt(c0) if c0 > 0.0 else 0.0
        for f, v in terms.items():
            bound = self._bound(f[0], trig)
            if bound is None:
                return None
            const += k * math.sqrt(v) * bound[0]
            for m, c in bound[1].items():
                total[m] = total.get(m, 0.0) + k * math.sqrt(v) * c
        return (const, total) if trig[0] else None

    def _bound(self, key: tuple, trig: list) -> tuple[float, dict] | None:
        """A form not below |factor| with sin and cos replaced by 1 (``trig[0]`` set where one was);
        None where a factor of unknown sign stays."""
        if key[0] == "n":
            return self._bound((None, (0.0, (((key,), 1.0),))), trig)
        c0, terms = key[1]
        total = {}
        for factors, v in terms:
            kept = []
            for f in sorted(set(factors)):
                n = factors.count(f)
                if f[0] == "n" and self.graph.nodes[f[1]][0] in ("sin", "cos"):
                    trig[0] = True
                elif n % 2 == 0 or (f[0] == "n" and self.graph.nodes[f[1]][0] == "abs"):
                    kept += [f] * n
                else:
                    return None
            total[tuple(kept)] = total.get(tuple(kept), 0.0) + abs(v)
        const = abs(c0) + total.pop((), 0.0)
        return const, total

    def _side(self, i: int):
        """A comparison's side as (kind, form): a sum or constant ("sum"), the absolute value of
        one ("abs"), or k sqrt(q) with a NormL2 ("norm"); None for another node."""
        op, args = self.graph.nodes[i]
        if op == "abs":
            return ("abs", form(self.graph, args[0], self.forms))
        c0, terms = form(self.graph, i, self.forms)
        if c0 == 0.0 and len(terms) == 1:
            (f, v), = terms.items()
            if v > 0.0 and len(f) == 1 and f[0][0] == "n" and self._normable(f[0][1]):
                return ("norm", (f[0][1], {(): v}))
        if terms == {(("n", i),): 1.0}:
            return None
        return ("sum", (c0, terms))

    def _side_written(self, side: tuple, s: float):
        kind, (c0, terms) = side
        if kind == "norm":
            return self._norm(c0, terms[()] / s)
        written = self._sum(c0 / s, {k: v / s for k, v in terms.items()}) if terms else self.es.Real(c0 / s)
        return self.es.abs(written) if kind == "abs" else written

    def _sum(self, c0: float, terms: dict):
        """c0 + sum of coefficient x product of factors: a positive term first, the others added or
        subtracted with their coefficient's magnitude."""
        es = self.es
        items = sorted(terms.items(), key=lambda kv: (kv[1] < 0, kv[0]))
        if not items:
            return es.Real(c0)
        total = es.Real(c0) if c0 > 0.0 and items[0][1] < 0 else None
        for factors, coeff in items:
            single = len(factors) == 1 and factors[0][0] == "n" and self._normable(factors[0][1])
            norm = self._norm(factors[0][1], abs(coeff)) if single else None
            m = norm if norm is not None else self._product(factors)
            term = m if abs(coeff) == 1.0 or norm is not None else es.Real(abs(coeff)) * m
            if total is None:
                total = term if coeff > 0 else -term
            else:
                total = total + term if coeff > 0 else total - term
        if c0 != 0.0 and not (c0 > 0.0 and items[0][1] < 0):
            total = total + es.Real(c0) if c0 > 0 else total - es.Real(-c0)
        return total

    def _norm(self, i: int, scale: float = 1.0):
        """``scale * sqrt(q)`` for a node ``i = sqrt(q)`` whose q is a sum of squares with positive
        coefficients (a reaction's magnitude) as Exudyn's NormL2 of the vector of ``scale sqrt(c) f``
        (each component evaluated once: no pow, no sqrt of a sum); None for another node."""
        if not self._normable(i):
            return None
        c0, terms = form(self.graph, self.graph.nodes[i][1][0], self.forms)
        parts = [self._scaled_factor(f[0], scale * math.sqrt(v)) for f, v in sorted(terms.items())]
        if c0 > 0.0:
            parts.append(self.es.Real(scale * math.sqrt(c0)))
        return self.es.Vector(parts).NormL2()

    def _normable(self, i: int) -> bool:
        """Node ``i`` is the square root of a sum of squares with positive coefficients."""
        op, args = self.graph.nodes[i]
        if op != "sqrt":
            return False
        c0, terms = form(self.graph, args[0], self.forms)
        return c0 >= 0.0 and bool(terms) and all(v > 0.0 and len(f) == 2 and f[0] == f[1] for f, v in terms.items())

    def _scaled_factor(self, key: tuple, k: float):
        """``k`` times a factor: a sum's coefficients absorb k."""
        if key[0] == "f":
            c0, terms = key[1]
            return self._sum(c0 * k, {f: v * k for f, v in terms})
        return self._factor(key) if k == 1.0 else self.es.Real(k) * self._factor(key)

    def _product(self, factors: tuple):
        """The product of ``factors`` (repeated as often as they multiply): a factor twice is a
        square, written as pow of it where evaluating it again would cost more."""
        product = None
        for f in sorted(set(factors)):
            n = factors.count(f)
            pieces = [self._square(f)] * (n // 2) + [self._factor(f)] * (n % 2)
            for piece in pieces:
                product = piece if product is None else product * piece
        return product

    def _factor(self, key: tuple):
        """A factor: a node (``("n", i)``) or a sum (``("f", (c0, terms))``), each written once."""
        if key[0] == "n":
            return self.tree(key[1])
        if key not in self.sums:
            self.sums[key] = self._sum(key[1][0], dict(key[1][1]))
        return self.sums[key]

    def _square(self, key: tuple):
        if _factor_cost(self.graph, key, self.costs) > COST["pow"] - 1.0:
            return self.es.pow(self._factor(key), self.es.Real(2.0))  # a dear operand evaluated once
        return self._factor(key) * self._factor(key)


def _squares_compared(c0: float, terms: dict) -> list | None:
    """``p f^2 - q g^2 < 0`` (p, q > 0) as the sides of ``|sqrt(p) f| < |sqrt(q) g|`` (each evaluated
    once); None for another difference."""
    items = sorted(terms.items(), key=lambda kv: kv[1] < 0)
    if c0 != 0.0 or len(items) != 2 or items[0][1] <= 0.0 or items[1][1] >= 0.0:
        return None
    if any(len(f) != 2 or f[0] != f[1] for f, _ in items):
        return None
    sides = []
    for f, c in items:
        k, key = math.sqrt(abs(c)), f[0]
        sides.append(("abs", (key[1][0] * k, {f2: v * k for f2, v in key[1][1]}) if key[0] == "f" else (0.0, {(key,): k})))
    return sides


def _multiplications(side: tuple, s: float) -> int:
    """Coefficients other than +-1 in a comparison's side divided by ``s`` (a norm takes any)."""
    kind, (c0, terms) = side
    return 0 if kind == "norm" else sum(1 for v in terms.values() if abs(v / s) != 1.0)


def _factor_cost(graph: Graph, key: tuple, memo: dict) -> float:
    if key[0] == "n":
        return tree_cost(graph, key[1], memo)
    c0, terms = key[1]
    return (3.0 if c0 else 0.0) + sum(2.0 * len(f) + (1.0 if abs(v) != 1.0 else 0.0)
                                      + sum(_factor_cost(graph, k, memo) for k in f) for f, v in terms)


def form(graph: Graph, i: int, forms: dict) -> tuple[float, dict]:
    """Node ``i`` as c0 + sum of coefficient x product of factors ({sorted factor keys: coefficient};
    a factor is a node, ``("n", i)``, or a sum, ``("f", (c0, terms))``, scaled to a first coefficient
    of 1), through sums, differences, negation, products and division by constants; any other node
    is a factor of its own. The constants of a law's arithmetic gather into one coefficient per term,
    and a value that enters twice (a square, a term in two places) is recognised as one (reassociation:
    the same value to rounding)."""
    if i in forms:
        return forms[i]
    op, args = graph.nodes[i]
    result = (0.0, {(("n", i),): 1.0})
    if op == "const":
        result = (graph.values[i], {})
    elif op in ("add", "sub"):
        (ca, ta), (cb, tb) = form(graph, args[0], forms), form(graph, args[1], forms)
        sign = 1.0 if op == "add" else -1.0
        terms = dict(ta)
        for k, v in tb.items():
            terms[k] = terms.get(k, 0.0) + sign * v
        result = (ca + sign * cb, {k: v for k, v in terms.items() if v != 0.0})
    elif op == "neg":
        result = _scaled(form(graph, args[0], forms), -1.0)
    elif op == "mul":
        result = _times(form(graph, args[0], forms), form(graph, args[1], forms), forms)
    elif op == "div":
        fa, fb = form(graph, args[0], forms), form(graph, args[1], forms)
        if not fb[1] and fb[0] != 0.0 and math.isfinite(fb[0]):
            result = (fa[0] / fb[0], {k: v / fb[0] for k, v in fa[1].items()})
    forms[i] = result
    return result


def _difference(graph: Graph, op: str, args: tuple, forms: dict):
    """A comparison of two state-dependent sides that share a term as (operator, form of left minus
    right) against 0, their terms merged; ``|a| <= k sqrt(q)`` (k > 0, a one term) as
    ``a a - k k q <= 0`` (both sides are not negative, so the squares compare alike, and a's square
    folds into q's terms).
    None when a side is constant or nothing merges (then the comparison is written as it is)."""
    if op in ("gt", "ge"):  # a > b is b < a
        op, args = {"gt": "lt", "ge": "le"}[op], (args[1], args[0])
    a, b = args
    fa, fb = form(graph, a, forms), form(graph, b, forms)
    root = _root_of(graph, fb, forms)
    inner = form(graph, graph.nodes[a][1][0], forms) if graph.nodes[a][0] == "abs" else (1.0, {})
    if root is not None and inner[0] == 0.0 and len(inner[1]) == 1:  # squared, a monomial stays one term
        fa, fb = _times(inner, inner, forms), root
    if not fa[1] or not fb[1]:
        return None
    terms = dict(fa[1])
    for k, v in fb[1].items():
        terms[k] = terms.get(k, 0.0) - v
    terms = {k: v for k, v in terms.items() if v != 0.0}
    merged = len(terms) < len(fa[1]) + len(fb[1])
    return (op, (fa[0] - fb[0], terms)) if terms and merged else None


def _root_of(graph: Graph, side: tuple[float, dict], forms: dict) -> tuple[float, dict] | None:
    """For a form k sqrt(q) with k > 0: the form of k k q; else None."""
    c0, terms = side
    if c0 != 0.0 or len(terms) != 1:
        return None
    (factors, k), = terms.items()
    if k <= 0.0 or len(factors) != 1 or factors[0][0] != "n" or graph.nodes[factors[0][1]][0] != "sqrt":
        return None
    return _scaled(form(graph, graph.nodes[factors[0][1]][1][0], forms), k * k)


def _times(fa: tuple[float, dict], fb: tuple[float, dict], forms: dict) -> tuple[float, dict]:
    """The product of two forms, as one term (a sum that multiplies is a factor of its own)."""
    if not fa[1] or not fb[1]:
        return _scaled(fb, fa[0]) if not fa[1] else _scaled(fa, fb[0])
    canon = forms.setdefault("canon", {})
    (ka, pa), (kb, pb) = _monomial(fa, canon), _monomial(fb, canon)
    return (0.0, {tuple(sorted(pa + pb)): ka * kb})


def _scaled(f: tuple[float, dict], c: float) -> tuple[float, dict]:
    return (f[0] * c, {k: v * c for k, v in f[1].items()})


def _monomial(f: tuple[float, dict], canon: dict) -> tuple[float, tuple]:
    """(coefficient, factors) of a form as one term: itself when it is one, else its first
    coefficient times the sum scaled by it (so a sum and its multiples are the same factor)."""
    c0, terms = f
    if c0 == 0.0 and len(terms) == 1:
        (factors, coeff), = terms.items()
        return coeff, factors
    items = sorted(terms.items())
    s = items[0][1]
    key = ("f", (c0 / s, tuple((k, v / s) for k, v in items)))
    return s, (canon.setdefault(_rounded(key), key),)


def _rounded(key):
    """A factor key with its coefficients to 12 digits: sums equal but for rounding (one law
    computed the same sum by two routes) are the same factor."""
    if isinstance(key, float):
        return float(f"{key:.12g}")
    if isinstance(key, tuple):
        return tuple(_rounded(k) for k in key)
    return key


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


class Tape:
    """The Exudyn expression a :class:`Writer` builds, recorded as construction steps so it can be
    built again for other arguments without writing it again (a model rebuilt with the same law:
    a few hundred Exudyn calls instead of the writer's normal forms). ``Writer(graph, tape.es,
    {node: tape.argument(k)})`` records; :meth:`replay` builds."""

    def __init__(self):
        self.steps: list[tuple] = []  # (kind, name or value, indices of earlier steps)
        self._seen: dict = {}
        self.es = _Recorder(self)
        self.root: _Ref | None = None

    def argument(self, k: int) -> _Ref:
        """The user function's ``k``-th symbolic argument."""
        return self.add("argument", k)

    def add(self, kind: str, name: object, *refs: _Ref) -> _Ref:
        """A step (an equal step recorded before is reused: one Exudyn object, shared)."""
        indices = tuple([r.index for r in refs])
        key = (kind, repr(name) if kind == "real" else name, indices)  # repr: -0.0 is not 0.0
        index = self._seen.get(key)
        if index is None:
            index = self._seen[key] = len(self.steps)
            self.steps.append((kind, name, indices))
        return _Ref(self, index)

    def replay(self, es: object, args: Sequence) -> object:
        """The recorded expression built with Exudyn's symbolic module ``es`` on ``args``."""
        built = []
        for kind, name, refs in self.steps:
            parts = [built[i] for i in refs]
            if kind == "argument":
                built.append(args[name])
            elif kind == "real":
                built.append(es.Real(name))
            elif kind == "operator":
                built.append(_OPERATORS[name](*parts))
            elif kind == "vector":
                built.append(es.Vector(parts))
            elif kind == "norm":
                built.append(parts[0].NormL2())
            else:  # a function of exudyn.symbolic
                built.append(getattr(es, name)(*parts))
        return built[self.root.index]


_OPERATORS = {"add": lambda a, b: a + b, "sub": lambda a, b: a - b, "mul": lambda a, b: a * b,
              "div": lambda a, b: a / b, "neg": lambda a: -a, "lt": lambda a, b: a < b,
              "le": lambda a, b: a <= b, "gt": lambda a, b: a > b, "ge": lambda a, b: a >= b,
              "eq": lambda a, b: a == b, "ne": lambda a, b: a != b}


class _Ref(TracedArithmetic):
    """A recorded value (a step of a :class:`Tape`): arithmetic and comparisons record steps."""

    __slots__ = ("tape", "index")

    def __init__(self, tape: Tape, index: int):
        self.tape, self.index = tape, index

    def _op(self, name, *others):
        return self.tape.add("operator", name, self, *(o if isinstance(o, _Ref) else self.tape.add("real", float(o))
                                                         for o in others))

    def _rop(self, name, other):
        return self.tape.add("operator", name, self.tape.add("real", float(other)), self)


    def __neg__(self):
        return self.tape.add("operator", "neg", self)

    def NormL2(self) -> _Ref:  # noqa: N802 (Exudyn's name)
        return self.tape.add("norm", None, self)


class _Recorder:
    """Stands for ``exudyn.symbolic`` while a :class:`Writer` writes onto a :class:`Tape`."""

    def __init__(self, tape: Tape):
        self._tape = tape

    def Real(self, value: float) -> _Ref:  # noqa: N802 (Exudyn's name)
        return self._tape.add("real", float(value))

    def Vector(self, parts: list) -> _Ref:  # noqa: N802 (Exudyn's name)
        return self._tape.add("vector", None, *parts)

    def __getattr__(self, name):
        tape = self._tape

        def call(*args):
            return tape.add("function", name, *(a if isinstance(a, _Ref) else tape.add("real", float(a)) for a in args))
        return call

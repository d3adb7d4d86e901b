"""The friction connector's lean symbolic user function (vcbmodel.builders.symbolic): the laws traced
once through ``ops`` and written with their branches chosen first give the trajectory of the law
recorded as written (Exudyn symbolic reals through ``symbolic_ops``) to 1e-12, evaluating a fraction
of its nodes for a state; the writer's rules (decisions first, max/min, signs, sums and products
normalised, squares, comparisons merged) keep every value of the law to rounding."""
import math
import re

import numpy as np
import pytest

import vcbmodel.builders.core as core
import vcbmodel.builders.symbolic as symbolic
from vcbmodel.builders.core import exudyn_modules
from vcbmodel.builders.symbolic import lean_expression
from vcbmodel.experiments.simulation import simulate
from vcbmodel.laws.friction import FrictionLaw, NumericOps, shaft_friction, symbolic_ops
from vcbmodel.laws.mechanics import pendulum_loads

FRICTION = {"mu_k": 0.13, "mu_s": 0.20, "stick_velocity": 1e-3, "stribeck_velocity": 0.1, "viscous": 0.6}
HYBRID = ("coulomb_friction", "stribeck", "viscous_friction")


def as_written(law, args):
    """The connector's expression before: the law recorded on Exudyn's symbolic reals as written."""
    return law(*args, symbolic_ops())


@pytest.mark.parametrize("effects", [HYBRID, ("coulomb_friction",)], ids=["hybrid", "coulomb"])
def test_lean_connector_gives_the_recorded_trajectory(pendulum_rig, effects, monkeypatch):
    """6 s of a pendulum that swings, sticks and stays stuck (passive band): angle, speed and friction
    torque at every step."""
    lean = simulate(pendulum_rig, effects, FRICTION, t_end=6.0, user_function="symbolic")
    monkeypatch.setattr(core, "lean_expression", as_written)
    before = simulate(pendulum_rig, effects, FRICTION, t_end=6.0, user_function="symbolic")
    assert lean.measured.shape == before.measured.shape
    assert np.max(np.abs(lean.measured - before.measured)) < 1e-12
    assert np.max(np.abs(lean.channels["shaft_velocity"] - before.channels["shaft_velocity"])) < 1e-12
    assert np.max(np.abs(lean.channels["friction_torque"] - before.channels["friction_torque"])) < 1e-12
    assert np.ptp(lean.measured) > 0.1 and np.abs(lean.channels["shaft_velocity"][-1]) < 1e-3  # it swung, then stopped


def pendulum_friction(law, mass=15.0, length=0.4, inertia=2.74, g=9.81):
    def friction_of_state(t, theta, omega, ops):
        Tc, R0x, R0y, R1x, R1y = pendulum_loads(theta, omega, mass, length, g, ops)
        return shaft_friction(omega, Tc, R0x, R0y, R1x, R1y, inertia, law, ops)[0]
    return friction_of_state


def evaluated_nodes(text: str, values: dict) -> tuple[int, int]:
    """(nodes, sin/cos/sqrt/pow/NormL2) Exudyn's tree interpreter evaluates for an expression printed by
    Exudyn (its ``str``: every use of a shared value printed, as it is evaluated) at ``values``; of
    an if-then-else only the branch taken. A small parser of that print, independent of the writer."""
    tokens = re.findall(r"[A-Za-z_]\w*|\d+\.?\d*(?:e[-+]?\d+)?|<=|>=|==|!=|[-+*/<>(),\[\]]", text)
    at = [0]

    def take():
        at[0] += 1
        return tokens[at[0] - 1]

    def parse():
        tok = take()
        if tok == "(":
            if tokens[at[0]] == "-" and not re.match(r"\d", tokens[at[0] + 1]):
                take()
                node = ("neg", [parse()])
            else:
                left = parse()
                node = (take(), [left, parse()])
            assert take() == ")"
            return node
        if tok == "[":
            items = [parse()]
            while take() == ",":
                items.append(parse())
            return ("vector", items)
        if tok == "-":
            return ("const", -float(take()))
        if re.match(r"\d", tok):
            return ("const", float(tok))
        if tokens[at[0]:at[0] + 1] == ["("]:
            take()
            args = [parse()]
            while take() == ",":
                args.append(parse())
            return (tok, args)
        return ("name", tok)

    ops = {"+": lambda a, b: a + b, "-": lambda a, b: a - b, "*": lambda a, b: a * b, "/": lambda a, b: a / b,
           "<": lambda a, b: a < b, "<=": lambda a, b: a <= b, ">": lambda a, b: a > b, ">=": lambda a, b: a >= b,
           "neg": lambda a: -a, "sin": math.sin, "cos": math.cos, "sqrt": math.sqrt, "abs": abs,
           "sign": lambda a: float(a > 0) - float(a < 0), "pow": math.pow, "max": max, "min": min,
           "vector": lambda *a: a, "NormL2": lambda v: math.hypot(*v)}
    count = [0, 0]

    def value(node):
        count[0] += 1
        op, args = node
        if op == "const":
            return args
        if op == "name":
            return values[args]
        count[1] += op in ("sin", "cos", "sqrt", "pow", "NormL2")
        if op == "IfThenElse":
            return value(args[1]) if value(args[0]) else value(args[2])
        return ops[op](*(value(a) for a in args))

    value(parse())
    return tuple(count)


def test_lean_expression_is_the_law_at_every_branch_and_evaluates_a_fraction_of_it():
    es = exudyn_modules()[0].symbolic
    law = FrictionLaw(mu_s=0.2, mu_k=0.13, stick_velocity=1e-3, stribeck_velocity=0.1, viscous=0.6, step=5e-4)
    f = pendulum_friction(law)
    t, theta, omega = es.Real("t", 0.0), es.Real("theta", 0.0), es.Real("omega", 0.0)
    lean, written = lean_expression(f, (t, theta, omega)), as_written(f, (t, theta, omega))
    assert str(lean).startswith("IfThenElse(")  # a decision first
    # every branch: stuck, breaking away, the band, Stribeck, kinetic, both directions, at rest
    for th in (-1.0, -0.2, 0.0, 0.01, 0.3, 1.2):
        for w in (-2.0, -0.05, -5e-4, -1e-10, 0.0, 1e-10, 5e-4, 0.05, 2.0):
            theta.SetValue(th)
            omega.SetValue(w)
            assert math.isclose(lean.Evaluate(), f(0.0, th, w, NumericOps), rel_tol=1e-14, abs_tol=1e-15), (th, w)
    # what the interpreter evaluates: stuck at rest, sliding in the Stribeck range, kinetic, both ways
    for th, w in ((0.01, 1e-20), (0.3, 0.05), (-0.2, -0.05), (0.1, 0.8), (-0.4, -1.5)):
        (n_lean, dear_lean), (n_written, dear_written) = (evaluated_nodes(str(e), {"theta": th, "omega": w})
                                                          for e in (lean, written))
        assert n_lean < 0.5 * n_written and dear_lean < dear_written, (th, w, n_lean, n_written)
        assert n_lean <= 105 and dear_lean <= 9, (th, w, n_lean, dear_lean)  # 58-100 nodes, 4-8 dear ones


@pytest.mark.parametrize("law", [
    FrictionLaw(mu_s=0.2, mu_k=0.13, stick_velocity=1e-3, stribeck_velocity=0.1, viscous=0.6, sticking="literal"),
    FrictionLaw(mu_s=0.13, mu_k=0.13, stick_velocity=1e-3, stribeck_velocity=0.0, viscous=0.0, step=5e-4),
    FrictionLaw(mu_s=0.2, mu_k=0.13, stick_velocity=2e-3, stribeck_velocity=0.05, viscous=0.0, step=0.0),
    FrictionLaw(mu_s=0.0, mu_k=0.0, stick_velocity=1e-3, stribeck_velocity=0.0, viscous=0.6, step=5e-4)],
    ids=["literal", "coulomb", "no-step", "viscous"])
def test_every_law_variant_keeps_its_values(law):
    """The other shapes of the law (literal band, no Stribeck, no viscous, adaptive step, viscous only)
    written lean: the law's value at states across every branch, both directions, at rest."""
    es = exudyn_modules()[0].symbolic
    f = pendulum_friction(law)
    t, theta, omega = es.Real("t", 0.0), es.Real("theta", 0.0), es.Real("omega", 0.0)
    lean = lean_expression(f, (t, theta, omega))
    for th in (-2.5, -0.2, 0.0, 0.01, 0.3, 1.2, 3.0):
        for w in (-3.0, -0.07, -0.0015, -5e-4, -1e-10, 0.0, 1e-10, 5e-4, 0.0015, 0.07, 3.0):
            theta.SetValue(th)
            omega.SetValue(w)
            assert math.isclose(lean.Evaluate(), f(0.0, th, w, NumericOps), rel_tol=1e-13, abs_tol=1e-14), (th, w)


def test_a_law_is_planned_once_per_distinct_trace(monkeypatch):
    """Rebuilding a model with the same law and numbers reuses the plan (the planning costs ten times
    the trace); other numbers are planned anew."""
    es = exudyn_modules()[0].symbolic
    args = (es.Real("t", 0.0), es.Real("theta", 0.0), es.Real("omega", 0.0))
    law = FrictionLaw(mu_s=0.2, mu_k=0.13, stick_velocity=1e-3, stribeck_velocity=0.1, viscous=0.6, step=5e-4)
    first = str(lean_expression(pendulum_friction(law, mass=11.0), args))
    planned = []
    plan = symbolic._decisions
    monkeypatch.setattr(symbolic, "_decisions", lambda *a: planned.append(1) or plan(*a))
    assert str(lean_expression(pendulum_friction(law, mass=11.0), args)) == first
    assert planned == []
    assert str(lean_expression(pendulum_friction(law, mass=12.0), args)) != first
    assert planned


def test_laws_that_differ_in_one_operation_are_not_confused():
    """The cache's fingerprint tells apart laws whose only difference is an operation or a number
    (a wrong hit would run another law's expression)."""
    es = exudyn_modules()[0].symbolic
    t, x, y = es.Real("t", 0.0), es.Real("x", 0.0), es.Real("y", 0.0)
    laws = [lambda t, x, y, ops: ops.where(x < y, 1.0, 2.0) * x,
            lambda t, x, y, ops: ops.where(x <= y, 1.0, 2.0) * x,
            lambda t, x, y, ops: ops.where(x == y, 1.0, 2.0) * x,
            lambda t, x, y, ops: ops.where(x <= y, 1.0, 2.0000000000000004) * x,
            lambda t, x, y, ops: ops.where(False, 1.0, 2.0) * x]  # what x == y is, were == not recorded
    for xv, yv in ((0.5, 0.5), (0.5, 0.25), (0.5, 0.75)):
        x.SetValue(xv)
        y.SetValue(yv)
        for _ in range(2):  # the second time from the cache
            assert [lean_expression(law, (t, x, y)).Evaluate() for law in laws] == [
                law(0.0, xv, yv, NumericOps) for law in laws], (xv, yv)


def test_writer_rules_keep_the_value():
    """max/min patterns, a square, a product of conditions, the sign of an argument, a magnitude compared
    with a cheap side (bound first), against the law evaluated in Python."""
    es = exudyn_modules()[0].symbolic

    def toy(t, x, y, ops):
        big = ops.where(x * y > x, x * y, x)  # max(x y, x)
        small = ops.where(ops.abs(y) < x, ops.abs(y), x)  # min(|y|, x)
        sq = (ops.sin(x) + y) * (ops.sin(x) + y)
        both = (x > 0.0) * (y < 1.0)
        # a magnitude (NormL2) a cheap side is compared with, its bound without sin and cos a constant
        held = ops.where(ops.abs(y) <= 0.5 * ops.sqrt(ops.cos(x) * ops.cos(x) + 4.0 * ops.sin(x) * ops.sin(x)), 1.0, -1.0)
        return ops.where(both, big + sq, small - sq) + ops.where(y > 2.0, 1.0, ops.sign(y) * 3.0) + held * y

    t, x, y = es.Real("t", 0.0), es.Real("x", 0.0), es.Real("y", 0.0)
    lean = lean_expression(toy, (t, x, y))
    text = str(lean)
    assert "max(" in text and "min(" in text and "pow(" in text and "NormL2(" in text
    for xv in (-1.5, -0.3, 0.0, 0.4, 2.0):
        for yv in (-3.0, -0.5, 0.0, 0.7, 1.0, 2.5):
            x.SetValue(xv)
            y.SetValue(yv)
            want = toy(0.0, xv, yv, NumericOps)
            assert math.isclose(lean.Evaluate(), want, rel_tol=1e-14, abs_tol=1e-14), (xv, yv)

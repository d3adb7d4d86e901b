"""The compiled path (vcbmodel.compiled) against the Exudyn models it stands in for.

The C is traced from the same law functions the Exudyn user functions call, so what the two
share is the laws (friction reading, contact laws, cam profile, latch ramp) and the rig numbers;
what they do not share is the assembly of the equations (Exudyn's bodies, markers, loads, spring
connectors and its pre-step hook there, vcbmodel.compiled.equations here) and the integration
code. These tests check that
assembly and the tracer (sharing, folding, guards) to 1e-9 rad over whole runs."""
import math

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.compiled import BACKEND_NAME, OdeSetup, compiler_works
from vcbmodel.compiled.codegen import trace_system
from vcbmodel.compiled.inputs import flatten
from vcbmodel.compiled.solve import _VARIANTS
from vcbmodel.compiled.trace import Graph, TraceOps
from vcbmodel.experiments import experiment_of
from vcbmodel.experiments.closing_evaluation import latched_impact_speeds
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import simulate
from vcbmodel.laws.breaker import update_impact_speeds
from vcbmodel.laws.friction import FrictionLaw, NumericOps, shaft_friction

from conftest import write_rig

pytestmark = pytest.mark.skipif(not compiler_works(), reason="no working C compiler")

VALUES = {"mu_k": 0.12, "mu_s": 0.18, "stribeck_velocity": 0.5, "viscous": 0.002, "stick_velocity": 1e-3}


def _agree(rig, **options):
    a = simulate(rig, backend="exudyn", values=VALUES, **options)
    b = simulate(rig, backend="compiled", values=VALUES, **options)
    assert b.info["backend"] == BACKEND_NAME and a.info["backend"] == "exudyn"
    assert set(a.channels) == set(b.channels)
    worst = {name: float(np.max(np.abs(a.channels[name] - b.channels[name]))) for name in a.channels}
    return a, b, worst


@pytest.mark.parametrize("sticking", ["passive", "literal"])
def test_pendulum_agrees_with_exudyn(pendulum_rig, sticking):
    a, b, worst = _agree(pendulum_rig, sticking=sticking, t_end=3.0)
    assert worst["pendulum_angle"] < 1e-9
    assert worst["friction_torque"] < 1e-9
    # and the run is not trivial: it swings and friction stops it
    assert np.ptp(a.measured) > 0.2  # released at 10 deg, it swings to the other side


@pytest.mark.parametrize("spring_model", ["massless", "lumped-1", "lumped-2:paper", "lumped-3", "lumped-2:uniform"])
def test_cam_drop_agrees_with_exudyn(cam_rig, spring_model):
    a, b, worst = _agree(cam_rig, spring_model=spring_model)
    assert worst["cam_angle"] < 1e-9, worst
    for name, w in worst.items():
        if name.startswith("spring_mass_"):
            assert w < 1e-9, (name, w)
    assert np.ptp(a.measured) > 1.0  # the cam turned


def test_cam_drop_with_spring_weight_agrees(tmp_path):
    rig_dict = dict(P.REFERENCE_CAM)
    rig_dict["closing_spring"] = dict(rig_dict["closing_spring"], weight=True)
    rig = load_rig(write_rig(tmp_path, rig_dict, "heavy"))
    _, _, worst = _agree(rig, spring_model="lumped-2")
    assert worst["cam_angle"] < 1e-9


def test_sampled_output_matches_exudyn(cam_rig):
    times = np.arange(0, 0.03, 1 / 12000.0)
    a = simulate(cam_rig, values=VALUES, sample_times=times, backend="exudyn")
    b = simulate(cam_rig, values=VALUES, sample_times=times, backend="compiled")
    assert np.allclose(a.t, b.t) and np.max(np.abs(a.measured - b.measured)) < 1e-9


def test_fast_backend_falls_back_for_ancf(cam_rig):
    with pytest.raises(ValueError, match="compiled backend covers"):
        simulate(cam_rig, values=VALUES, spring_model="ancf", backend="compiled", t_end=1e-3)
    r = simulate(cam_rig, values=VALUES, spring_model="ancf", backend="fast", t_end=1e-3)
    assert r.info["backend"] == "exudyn"


def test_guards_pick_a_new_variant_when_a_branch_changes(pendulum_rig):
    """A law leaves a branch out when its parameter is 0 (no Stribeck slope): the code compiled
    for one must not run the other. Variants are keyed by their guards."""
    with_stribeck = simulate(pendulum_rig, values=VALUES, backend="compiled", t_end=2.0)
    no_stribeck = dict(VALUES, stribeck_velocity=0.0)
    compiled = simulate(pendulum_rig, values=no_stribeck, backend="compiled", t_end=2.0)
    exudyn = simulate(pendulum_rig, values=no_stribeck, backend="exudyn", t_end=2.0)
    assert np.max(np.abs(compiled.measured - exudyn.measured)) < 1e-9
    assert np.max(np.abs(compiled.measured - with_stribeck.measured)) > 1e-4
    variants = [v for key, vs in _VARIANTS.items() if key[0] == "pendulum" for v in vs]
    assert len({v.digest for v in variants}) >= 2


def test_trace_shares_and_folds():
    g = Graph()
    ops = TraceOps(g)
    x = g.state("x[0]", 0.3)
    a = ops.sin(x) * ops.sin(x) + 0.0
    assert ops.sin(x).index == ops.sin(x).index  # one node for sin(x)
    assert (2.0 * 3.0 + x * 1.0).index != x.index and (x * 1.0).index == x.index
    assert math.isclose(a.value, math.sin(0.3) ** 2)
    c_lines = g.c_statements({"out[0]": a})
    assert sum("sin(" in line for line in c_lines) == 1


def test_trace_refuses_a_python_branch_on_the_state():
    g = Graph()
    x = g.state("x[0]", 0.3)
    with pytest.raises(TypeError, match="ops.where"):
        bool(x > 0.0)


def test_traced_law_equals_the_float_law():
    """The friction law traced at a point has the float law's value there (every branch)."""
    law = FrictionLaw(mu_s=0.18, mu_k=0.12, stick_velocity=1e-3, stribeck_velocity=0.5, viscous=0.002,
                      radius=0.02, step=1e-4)
    for w, Tc in [(0.0, 0.1), (5e-4, -0.3), (0.2, 0.5), (3.0, -1.0), (-3.0, 40.0)]:
        def eq(t, q, v, memory, inputs, ops):
            Tf = shaft_friction(v[0], Tc, 10.0, 3.0, 0.0, 0.7, 0.05, inputs["law"], ops)[0]
            return [Tf], {}
        traced = trace_system(eq, None, OdeSetup({"law": law}, [0.0], [w], [("x", "v", 1)]))
        expected = shaft_friction(w, Tc, 10.0, 3.0, 0.0, 0.7, 0.05, law, NumericOps)[0]
        assert traced.accelerations[0].value == pytest.approx(expected, rel=1e-15, abs=1e-15)


def test_flatten_orders_parameters_and_structure():
    law = FrictionLaw(mu_s=0.2, mu_k=0.1)
    p, structure = flatten({"law": law, "g": 9.81})
    assert p[0] == 9.81 and 0.2 in p and 0.1 in p  # keys in sorted order: g, then law's fields
    _, other = flatten({"law": FrictionLaw(mu_s=0.2, mu_k=0.1, sticking="literal"), "g": 9.81})
    assert structure != other  # a string option is structure, not a parameter


@pytest.fixture
def breaker_rig(tmp_path):
    return load_rig(write_rig(tmp_path, P.REFERENCE_BREAKER, "breaker"))


@pytest.mark.parametrize("spring_model", ["massless", "lumped-2:exact"])
def test_closing_agrees_with_exudyn(breaker_rig, spring_model):
    """The whole breaker: cam, chain, follower, three poles, contacts with latched impact speeds
    (the pre-step memory), the latch; to 1e-9 rad and 1e-9 m over the closing."""
    a = simulate(breaker_rig, spring_model=spring_model, backend="exudyn")
    b = simulate(breaker_rig, spring_model=spring_model, backend="compiled")
    assert b.info["backend"] == BACKEND_NAME
    assert np.max(np.abs(a.channels["cam_angle"] - b.channels["cam_angle"])) < 1e-9
    assert np.max(np.abs(a.measured - b.measured)) < 1e-9
    for i in range(1, 4):
        assert np.max(np.abs(a.channels[f"pole_{i}_travel"] - b.channels[f"pole_{i}_travel"])) < 1e-9
    # the contacts closed and bounced in both (the comparison covers the impacts)
    assert np.max(b.channels["pole_1_contact_force"]) > 1e3
    fa = experiment_of("vcb_closing").figures_of_merit(a, breaker_rig)
    fb = experiment_of("vcb_closing").figures_of_merit(b, breaker_rig)
    assert fa["closing_time_s"] == pytest.approx(fb["closing_time_s"], abs=1e-9)
    assert fa["bounce_count"] == fb["bounce_count"]


def test_replayed_impact_speeds_match_the_stepwise_latch():
    """The vectorised replay of the contacts' impact speeds equals the law's step-by-step latch."""
    rng = np.random.default_rng(3)
    pen = np.cumsum(rng.normal(0, 1, 400)) * 1e-6
    rate = rng.normal(0, 1, 400)
    latched = latched_impact_speeds(pen, rate)
    impact = [0.0]
    for j in range(400):
        update_impact_speeds(impact, [(pen[j], rate[j])])
        assert latched[j] == impact[0]


def test_without_a_compiler_compiled_is_one_line_and_fast_falls_back(tmp_path):
    """A machine without a C compiler: `--backend compiled` fails with one line (status 1), `fast`
    runs on Exudyn and says so in the file's first line."""
    import os
    import subprocess
    import sys

    rig = write_rig(tmp_path, P.REFERENCE_CAM | {"friction": dict(VALUES)}, "cam")
    env = dict(os.environ, CC=str(tmp_path / "no-such-cc"), VCBMODEL_CACHE=str(tmp_path / "cache"))
    base = [sys.executable, "-m", "vcbmodel", "simulate", str(rig), "-o", str(tmp_path / "out.csv"), "--force"]
    p = subprocess.run(base + ["--backend", "compiled"], env=env, capture_output=True, text=True, timeout=300)
    assert p.returncode == 1 and "Traceback" not in p.stderr and "C compiler" in p.stderr
    assert not (tmp_path / "out.csv").exists()
    p = subprocess.run(base + ["--backend", "fast"], env=env, capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-800:]
    assert "solved by exudyn" in (tmp_path / "out.csv").read_text().splitlines()[0]


@pytest.mark.parametrize("which", ["pendulum", "breaker"])
def test_every_step_and_every_third_step_record_the_same_run(which, pendulum_rig, breaker_rig):
    """A recorded step's end-of-step evaluation is the next step's first stage (codegen's driver): a
    run recorded at every step and one recorded at every third carry the same numbers, bit for bit, at
    the times both record (the pendulum: no memory; the closing: the contacts' latched memory). The poles'
    contact forces are left out: they are evaluated afterwards from the recorded samples, replaying the
    latched impact speeds on the recorded grid (closing_evaluation), so they depend on it."""
    rig, values, t_end = (pendulum_rig, VALUES, 1.0) if which == "pendulum" else (breaker_rig, None, 0.045)
    step = experiment_of(rig.experiment).step(rig)
    every = simulate(rig, values=values, backend="compiled", t_end=t_end)
    third = simulate(rig, values=values, backend="compiled", t_end=t_end, step=step,
                     sample_times=np.arange(int(t_end / step) // 3 + 1) * 3 * step)
    assert every.info["step"] == pytest.approx(step) and len(every.t) > 3 * (len(third.t) - 1)
    replayed = [name for name in third.channels if "_contact_" in name]
    assert len(replayed) == (0 if which == "pendulum" else 6)
    for name, samples in third.channels.items():
        if name in replayed:
            continue
        assert np.array_equal(every.channels[name][: 3 * len(third.t): 3], samples), name

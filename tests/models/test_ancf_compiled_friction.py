"""The ANCF spring's friction callback with its law compiled (vcbmodel.compiled.function): the Python
user function still reads the cable's end node, the law it evaluates runs as C traced from the same
source; trajectories equal the pure-Python callback's, one compiled object serves many parameter
values, and without a C compiler the Python law runs."""
import copy
import math

import numpy as np
import pytest
from conftest import write_rig

import vcbmodel.builders.ancf as ancf
from vcbmodel import parameters as P
from vcbmodel.builders.ancf import AncfOptions
from vcbmodel.compiled import compiler_works
from vcbmodel.compiled.function import TRACES, compiled_function
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import simulate
from vcbmodel.laws.friction import NumericOps

needs_compiler = pytest.mark.skipif(not compiler_works(), reason="no working C compiler")
T = np.arange(421) / 12000.0  # the 35 ms drop filmed at 12 kHz
VALUES = {"mu_k": 0.12, "mu_s": 0.18, "stribeck_velocity": 0.5, "viscous": 0.002, "stick_velocity": 1e-3}
CASES = {
    "coulomb": (("coulomb_friction", "spring_mass"), {}),
    "stribeck_viscous": (("coulomb_friction", "stribeck", "viscous_friction", "spring_mass"), {}),
    "discovered": (("coulomb_friction", "spring_mass", "discovered_torque"),
                   {"discovered:sin_2theta": 20.0, "discovered:w_abs_w": -2e-3, "discovered:time": 300.0}),
}


@pytest.fixture(scope="module")
def heavy_cam(tmp_path_factory):
    d = copy.deepcopy(P.REFERENCE_CAM)
    d["closing_spring"]["mass"] = P.HEAVY_SPRING_MASS
    return load_rig(write_rig(tmp_path_factory.mktemp("ancf_cf"), d, "cam"))


@pytest.fixture
def spy(monkeypatch):
    """The kinds compiled_function was asked for while building ANCF models."""
    calls = []

    def recording(kind, *args):
        calls.append(kind)
        return compiled_function(kind, *args)

    monkeypatch.setattr(ancf, "compiled_function", recording)
    return calls


def drop(rig, case, user_function, values=VALUES):
    effects, extra = CASES[case]
    step = AncfOptions().stable_step(rig.closing_spring)  # the fits' step
    return simulate(rig, effects, {**values, **extra}, spring_model="ancf", sample_times=T, step=step,
                    user_function=user_function)


@needs_compiler
@pytest.mark.parametrize("case", sorted(CASES))
def test_compiled_callback_gives_the_python_callbacks_trajectory(heavy_cam, spy, case):
    python = drop(heavy_cam, case, "python")
    assert spy == []
    compiled = drop(heavy_cam, case, "auto")
    assert spy == ["ancf_tie_friction"]
    assert np.max(np.abs(compiled.measured - python.measured)) <= 1e-10  # rad over 35 ms
    torque = compiled.channels["friction_torque"]
    assert np.max(np.abs(torque - python.channels["friction_torque"])) <= 1e-8 * np.max(np.abs(torque))
    if case != "coulomb":  # the case's extra law acts
        assert np.max(np.abs(drop(heavy_cam, "coulomb", "python").measured - python.measured)) > 1e-3


@needs_compiler
def test_one_compiled_law_serves_a_fits_parameter_values(heavy_cam):
    drop(heavy_cam, "stribeck_viscous", "auto")
    before = TRACES["count"]
    angles = [drop(heavy_cam, "stribeck_viscous", "auto", dict(VALUES, mu_k=mu_k, viscous=c)).measured[-1]
              for mu_k, c in ((0.08, 0.001), (0.16, 0.004))]
    assert TRACES["count"] == before  # no new trace or build: the values are run-time parameters
    assert abs(angles[0] - angles[1]) > 1e-2  # and they act


def test_without_a_compiler_the_python_law_runs(heavy_cam, spy, monkeypatch):
    python = drop(heavy_cam, "coulomb", "python")
    monkeypatch.setattr(ancf, "compiler_works", lambda: False)
    auto = drop(heavy_cam, "coulomb", "auto")
    assert spy == []
    assert np.array_equal(auto.measured, python.measured)


def _guarded(args, inputs, ops):
    x, y = args
    value = inputs["a"] * ops.sin(x) + ops.where(y > 0.0, y * y, -y)
    if inputs["b"]:  # a parameter's branch: a guard
        value = value + inputs["b"] * ops.sqrt(ops.abs(x * y))
    return value


@needs_compiler
def test_compiled_function_is_the_law_and_keeps_its_branches():
    rng = np.random.default_rng(3)
    points = rng.normal(0.0, 2.0, (20, 2))
    for b in (0.0, 1.5, 2.5, 0.0):
        inputs = {"a": 0.7, "b": b}
        value = compiled_function("test_guarded", _guarded, inputs, (0.1, 0.2))
        for x, y in points:
            expected = _guarded((float(x), float(y)), inputs, NumericOps)
            assert value(float(x), float(y)) == pytest.approx(expected, rel=1e-14, abs=1e-300)
    assert math.isclose(value(1.0, -2.0), 0.7 * math.sin(1.0) + 2.0, rel_tol=1e-15)


@needs_compiler
def test_the_breakers_ancf_closing_takes_the_compiled_law_with_its_extra_loads(tmp_path, spy):
    """The whole breaker's cam friction adds the roller's and the latch's loads (Python, read from the
    follower) to the compiled law's arguments: every channel as with the Python law."""
    d = copy.deepcopy(P.REFERENCE_BREAKER)
    d["closing_spring"]["mass"] = P.HEAVY_SPRING_MASS
    rig = load_rig(write_rig(tmp_path, d, "breaker"))
    effects = ("coulomb_friction", "spring_mass")
    runs = {uf: simulate(rig, effects, VALUES, spring_model="ancf", t_end=0.04, user_function=uf)
            for uf in ("python", "auto")}
    assert spy == ["ancf_tie_friction"]
    for name, values in runs["python"].channels.items():
        scale = max(1.0, np.max(np.abs(values)))
        assert np.max(np.abs(runs["auto"].channels[name] - values)) <= 1e-10 * scale, name
    assert np.max(runs["auto"].channels["cam_roller_force"]) > 1e3  # N: the roller's loads act on the cam

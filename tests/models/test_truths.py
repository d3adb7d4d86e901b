"""The friction truths outside the fitted family (vcbmodel/reference/truth_friction.py): each
reduces to its known limit, dissipates, and is not the hybrid law the diagnosis fits."""
import ast
import math
from pathlib import Path

import numpy as np
import pytest

from vcbmodel.experiments.random_rigs import cam_drop_random_rig
from vcbmodel.reference import independent, truth_friction
from vcbmodel.reference.truth_friction import KINDS, truth_cam_drop, truth_pendulum
from vcbmodel.reference.truths import friction_truth_angle, static_load

M, I, L, G, R = 50.0, 2.5, 0.21, 9.81, 0.02
PEND = {"mass": M, "inertia": I, "com_distance": L, "initial_angle": math.radians(15.0)}
#: values in the realism study's ranges (mu_s about 1.9 mu_k, w_s 0.09-0.15 rad/s, Cv 0.5-0.75)
VALUES = {"mu_s": 0.25, "mu_k": 0.13, "stribeck_velocity": 0.12, "viscous": 0.6, "sigma0": 6e4, "sigma1": 80.0,
          "amplitude": 0.3 * 0.13 * R * M * G, "wavenumber": 30.0, "phase": 1.0}
T = np.arange(0.0, 6.0 + 5e-4, 1e-3)


def coulomb_viscous(mu_s, mu_k, cv, t=T):
    """The independent reference's pendulum with Coulomb (static mu_s) and viscous friction only."""
    return independent.pendulum(M, I, L, G, R, {"mu_s": mu_s, "mu_k": mu_k, "viscous": cv}, PEND["initial_angle"],
                                0.0, t)


def energy(out, values=None):
    """Mechanical energy (J) of the pendulum, with the position torque's potential if given."""
    e = 0.5 * I * out["omega"] ** 2 + M * G * L * (1 - np.cos(out["theta"]))
    if values is not None:
        e = e + np.array([truth_friction.position_potential(th, values["amplitude"], values["wavenumber"],
                                                            values["phase"]) for th in out["theta"]])
    return e


def test_tustin_with_equal_levels_is_coulomb():
    v = dict(VALUES, mu_s=0.13)
    out = truth_pendulum("tustin", PEND, G, R, v, T)
    ref = coulomb_viscous(0.13, 0.13, 0.6)
    assert np.max(np.abs(out["theta"] - ref["theta"])) < 1e-7


def test_position_torque_of_zero_amplitude_is_coulomb():
    out = truth_pendulum("position_torque", PEND, G, R, dict(VALUES, amplitude=0.0), T)
    ref = coulomb_viscous(0.25, 0.13, 0.6)
    assert np.max(np.abs(out["theta"] - ref["theta"])) < 1e-7


@pytest.mark.parametrize("kind", ["lugre", "dahl"])
def test_stiff_bristles_approach_coulomb_and_viscous(kind):
    """With mu_s = mu_k and no bristle damping, LuGre and Dahl tend to Coulomb + viscous as the
    bristles stiffen: the gap shrinks with sigma0 and is below the 0.5 mrad noise at 1e7 /m."""
    t = T[T <= 4.0]
    ref = coulomb_viscous(0.13, 0.13, 0.6, t)
    gaps = []
    for s0 in (1e5, 1e7):
        out = truth_pendulum(kind, PEND, G, R, dict(VALUES, mu_s=0.13, sigma0=s0, sigma1=0.0), t)
        gaps.append(np.max(np.abs(out["theta"] - ref["theta"])))
    assert gaps[1] < gaps[0] / 5
    assert gaps[1] < 5e-4


def test_lugre_bristle_deflection_is_micrometres():
    out = truth_pendulum("lugre", PEND, G, R, VALUES, T)
    z = np.abs(out["bristle"])
    assert 0.5e-6 < z.max() < 10e-6  # the steady deflection is about g(w)/sigma0


@pytest.mark.parametrize("kind", ["tustin", "position_torque"])
def test_energy_never_rises(kind):
    out = truth_pendulum(kind, PEND, G, R, VALUES, T)
    e = energy(out, VALUES if kind == "position_torque" else None)
    assert np.max(np.diff(e)) < 1e-8 * e[0]
    assert e[-1] < 0.5 * e[0]


@pytest.mark.parametrize("kind", ["lugre", "dahl"])
def test_bristle_swings_decay(kind):
    """The span of each half swing (between reversals) falls; what is left after the last swing
    is pre-sliding ringing of micro-radians."""
    out = truth_pendulum(kind, PEND, G, R, VALUES, T)
    th, w = out["theta"], out["omega"]
    turns = np.nonzero(np.sign(w[1:]) != np.sign(w[:-1]))[0]
    spans = np.abs(np.diff(np.concatenate([[th[0]], th[turns]])))
    swings = spans[spans > 1e-3]
    assert len(swings) >= 4
    assert np.all(np.diff(swings) < 0)
    last = th[T >= 5.0]
    assert np.ptp(last) < 1e-4


def test_tustin_sticks_for_good():
    out = truth_pendulum("tustin", PEND, G, R, VALUES, T)
    assert out["omega"][-1] == 0.0
    th = out["theta"][-1]
    assert abs(M * G * L * math.sin(th)) <= VALUES["mu_s"] * R * M * G * 1.01


@pytest.mark.parametrize("kind", KINDS)
def test_truth_is_not_the_fitted_hybrid_law(kind):
    """The same values in the model's hybrid law (Karnopp band, linear Stribeck branch, shifted
    viscous term) give a swing more than ten times the pendulum's 0.5 mrad noise away."""
    hybrid = independent.pendulum(M, I, L, G, R, {k: VALUES[k] for k in ("mu_s", "mu_k", "stribeck_velocity", "viscous")}
                                  | {"stick_velocity": 1e-3}, PEND["initial_angle"], 0.0, T)
    out = truth_pendulum(kind, PEND, G, R, VALUES, T)
    assert np.max(np.abs(out["theta"] - hybrid["theta"])) > 5e-3


@pytest.mark.parametrize("kind", KINDS)
def test_cam_drop_truths(kind):
    """Each truth runs the cam drop; the position torque of zero amplitude is the independent
    reference with Coulomb and viscous friction."""
    friction = {"mu_s": 0.25, "mu_k": 0.13, "stribeck_velocity": 0.12}
    rig = cam_drop_random_rig(np.random.default_rng(1), friction, ())
    t = np.arange(0.0, 0.035, 1 / 12000)
    v = dict(VALUES, viscous=friction["viscous"], amplitude=0.0 if kind == "position_torque" else VALUES["amplitude"])
    out = truth_cam_drop(kind, rig["cam"], rig["closing_spring"], G, rig["shaft"]["radius"], v, t)
    assert out["theta"][-1] > rig["cam"]["initial_angle"] + 1.0  # the springs turn the cam
    if kind == "position_torque":
        ref = independent.cam_drop(rig["cam"], dict(rig["closing_spring"], chain=None), G, rig["shaft"]["radius"],
                                   {"mu_s": 0.25, "mu_k": 0.13, "viscous": friction["viscous"]}, t)
        assert np.max(np.abs(out["theta"] - ref["theta"])) < 1e-8


def test_rig_wiring_and_static_load():
    rig = {"experiment": "pendulum", "gravity": G, "shaft": {"radius": R}, "pendulum": PEND}
    assert static_load(rig) == pytest.approx(M * G)
    theta = friction_truth_angle("tustin", rig, VALUES, T)
    assert np.array_equal(theta, truth_pendulum("tustin", PEND, G, R, VALUES, T)["theta"])
    cam = {"pivot": [0.4, 0.0], "arm_length": 0.1, "initial_angle": 0.0}
    spring = {"count": 2, "stiffness": 1000.0, "free_length": 0.2, "anchor": [0.0, 0.0]}
    assert static_load({"experiment": "cam_drop", "cam": cam, "closing_spring": spring}) == pytest.approx(2 * 1000 * 0.3)
    with pytest.raises(ValueError, match="pendulum and cam_drop"):
        friction_truth_angle("tustin", {"experiment": "vcb_closing"}, VALUES, T)


@pytest.mark.parametrize("kind, values, match", [
    ("coulomb", VALUES, "unknown friction truth"),
    ("lugre", {k: v for k, v in VALUES.items() if k != "sigma0"}, "needs sigma0"),
    ("tustin", dict(VALUES, mu_k=-0.1), "mu_k must be"),
])
def test_bad_values_refused(kind, values, match):
    with pytest.raises(ValueError, match=match):
        truth_pendulum(kind, PEND, G, R, values, T)


def test_independent_of_the_model_laws():
    """The truths import nothing from vcbmodel.laws (evidence must not share the fitted law)."""
    for name in ("truth_friction.py", "truths.py"):
        tree = ast.parse((Path(truth_friction.__file__).parent / name).read_text())
        modules = {n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
        modules |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
        assert not any("laws" in m for m in modules), modules

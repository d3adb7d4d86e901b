"""The two effects outside the paper: air drag on the pendulum (``aerodynamic_drag``) and the
closing spring's internal damping (``spring_damping``, Kelvin-Voigt).

Each is checked three ways: the compiled path against the Exudyn model (the same law, assembled
twice, to 1e-9 rad), against an analytic limit (a drag-only swing's amplitude decay; the damped
chain's modal damping ratios from its linearised equations), and, for the spring, the lumped chain
against Exudyn's ANCF cable with its own material damping (an element we did not write)."""
import math

import numpy as np
import pytest
from scipy.signal import find_peaks

from vcbmodel import parameters as P
from vcbmodel.compiled import compiler_works
from vcbmodel.compiled.equations import cam_drop_equations, prepare_cam_drop
from vcbmodel.errors import InputError
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import model_spec, simulate
from vcbmodel.laws.friction import NumericOps
from vcbmodel.laws.mechanics import aerodynamic_drag_torque, paddle_drag_coefficient
from vcbmodel.laws.springs import chain_for, kelvin_voigt_time, modal_damping_ratios

from conftest import write_rig

needs_compiler = pytest.mark.skipif(not compiler_works(), reason="no working C compiler")

FRICTION = {"mu_k": 0.12, "mu_s": 0.18, "stribeck_velocity": 0.5, "viscous": 0.002, "stick_velocity": 1e-3}
PENDULUM_EFFECTS = ("coulomb_friction", "stribeck", "viscous_friction", "aerodynamic_drag")
CAM_EFFECTS = ("coulomb_friction", "stribeck", "viscous_friction", "spring_damping")


def test_drag_law_opposes_the_motion_and_is_quadratic():
    assert aerodynamic_drag_torque(2.0, 0.01) == pytest.approx(-0.04)
    assert aerodynamic_drag_torque(-2.0, 0.01) == pytest.approx(0.04)
    assert aerodynamic_drag_torque(0.0, 0.01) == 0.0
    # a 0.02 m^2 flat plate at 0.3 m: 0.5 * 1.2 * 1.17 * 0.02 * 0.027
    assert paddle_drag_coefficient(0.02, 0.3) == pytest.approx(3.79e-4, rel=1e-3)


@needs_compiler
def test_drag_pendulum_agrees_with_exudyn(pendulum_rig):
    values = dict(FRICTION, drag=0.05)
    a = simulate(pendulum_rig, PENDULUM_EFFECTS, values, backend="exudyn", t_end=3.0)
    b = simulate(pendulum_rig, PENDULUM_EFFECTS, values, backend="compiled", t_end=3.0)
    assert np.max(np.abs(a.measured - b.measured)) < 1e-9
    assert np.max(np.abs(a.channels["friction_torque"] - b.channels["friction_torque"])) < 1e-9
    without = simulate(pendulum_rig, PENDULUM_EFFECTS[:3], values, backend="compiled", t_end=3.0)
    assert np.max(np.abs(without.measured - b.measured)) > 1e-3  # the drag is there


def test_drag_only_swing_decays_as_the_quadratic_damping_law(tmp_path):
    """I th'' + c th'|th'| + M g L th = 0 at small amplitude: averaged over a cycle the amplitude
    follows 1/A = 1/A0 + 4 c w0 t / (3 pi I) (energy loss c <|th'|^3> = c (A w0)^3 4 / (3 pi))."""
    pend = {"mass": 5.0, "inertia": 0.5, "com_distance": 0.3, "initial_angle": 0.05, "initial_velocity": 0.0}
    rig = load_rig(write_rig(tmp_path, {"format": "vcb-rig/1", "name": "drag only", "experiment": "pendulum",
                                        "gravity": 9.81, "shaft": {"radius": 0.02}, "pendulum": pend,
                                        "friction": {"drag": 0.05}, "model": {"effects": ["aerodynamic_drag"]}}))
    r = simulate(rig, t_end=20.0)
    peaks = np.concatenate([find_peaks(r.measured)[0], find_peaks(-r.measured)[0]])
    tp, ap = r.t[peaks], np.abs(r.measured[peaks])
    w0 = math.sqrt(pend["mass"] * 9.81 * pend["com_distance"] / pend["inertia"])
    slope = np.polyfit(tp, 1.0 / ap, 1)[0]
    expected = 4 * 0.05 * w0 / (3 * math.pi * pend["inertia"])
    assert slope == pytest.approx(expected, rel=0.005)
    assert ap[np.argmax(tp)] < 0.85 * pend["initial_angle"]  # it decayed: the check is not vacuous


@needs_compiler
@pytest.mark.parametrize("spring_model", ["massless", "lumped-1", "lumped-3", "lumped-2:paper"])
def test_spring_damping_cam_drop_agrees_with_exudyn(cam_rig, spring_model):
    values = dict(FRICTION, damping_ratio=0.03)
    a = simulate(cam_rig, CAM_EFFECTS, values, spring_model=spring_model, backend="exudyn")
    b = simulate(cam_rig, CAM_EFFECTS, values, spring_model=spring_model, backend="compiled")
    assert np.max(np.abs(a.measured - b.measured)) < 1e-9
    assert np.max(np.abs(a.channels["friction_torque"] - b.channels["friction_torque"])) < 1e-9
    undamped = simulate(cam_rig, CAM_EFFECTS[:3], values, spring_model=spring_model, backend="compiled")
    assert np.max(np.abs(undamped.measured - b.measured)) > 1e-3  # the damping is there


@needs_compiler
def test_spring_damping_closing_agrees_with_exudyn(tmp_path):
    rig = load_rig(write_rig(tmp_path, P.REFERENCE_BREAKER, "breaker"))
    effects = tuple(rig.model.effects) + ("spring_damping",)
    values = {"damping_ratio": 0.03}
    a = simulate(rig, effects, values, spring_model="lumped-2", backend="exudyn")
    b = simulate(rig, effects, values, spring_model="lumped-2", backend="compiled")
    assert np.max(np.abs(a.measured - b.measured)) < 1e-9
    assert np.max(np.abs(a.channels["cam_angle"] - b.channels["cam_angle"])) < 1e-9


def test_damped_chain_modes_have_the_kelvin_voigt_damping_ratios(cam_rig):
    """The chain's equations linearised about its rest with the cam held: each axial mode's damping
    ratio is beta w_n / 2 (stiffness-proportional damping), the first mode of an ``exact`` chain the
    given zeta (its w_1 is the continuum's)."""
    zeta = 0.02
    spec = model_spec(cam_rig, ("coulomb_friction", "spring_mass", "spring_damping"),
                      {"mu_k": 0.0, "damping_ratio": zeta}, "lumped-3")
    chain = chain_for(cam_rig.closing_spring, spec.spring_model)
    setup = prepare_cam_drop(cam_rig, spec, spec.friction_law(cam_rig.shaft_radius), chain)
    q0, n = np.array(setup.q0, float), len(setup.q0) - 1
    v0 = np.zeros(n + 1)

    def acc(q, v):
        return np.array(cam_drop_equations(0.0, list(q), list(v), [], setup.inputs, NumericOps)[0][1:])

    h = 1e-7
    Jq, Jv = np.zeros((n, n)), np.zeros((n, n))
    for j in range(n):
        dq = np.zeros(n + 1)
        dq[1 + j] = h
        Jq[:, j] = (acc(q0 + dq, v0) - acc(q0 - dq, v0)) / (2 * h)
        Jv[:, j] = (acc(q0, v0 + dq) - acc(q0, v0 - dq)) / (2 * h)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [Jq, Jv]])
    lam = np.linalg.eigvals(A)
    lam = lam[lam.imag > 0]
    w, z = np.abs(lam), -lam.real / np.abs(lam)
    axial = np.sort(w[z > 1e-4])  # lateral (string) modes: a link's damper does not stretch to first order
    beta = kelvin_voigt_time(zeta, cam_rig.closing_spring.stiffness, cam_rig.closing_spring.mass)
    expected = np.sort(modal_damping_ratios(chain.masses, chain.stiffnesses, beta))
    assert axial.size == 3
    assert np.allclose(np.sort(z[z > 1e-4]), expected, rtol=1e-4)
    assert z[z > 1e-4].min() == pytest.approx(zeta, rel=1e-4)  # exact chain: w_1 = pi sqrt(k0/m0)


def test_ancf_cable_damping_matches_the_lumped_chains(cam_rig):
    """Exudyn's ANCF cable with Kelvin-Voigt axial damping (its own element code) against the chains:
    what 3 % damping changes in the cam's drop agrees within 5 %."""
    values = {"mu_k": 0.12, "stick_velocity": 1e-3}
    effects = ("coulomb_friction", "spring_damping")
    t = np.arange(0.0, 0.035, 1e-4)
    change = {}
    for model in ("ancf", "lumped-8:uniform"):
        runs = [simulate(cam_rig, effects, dict(values, damping_ratio=z), spring_model=model, sample_times=t).measured
                for z in (0.0, 0.03)]
        change[model] = runs[1] - runs[0]
    rms = {k: float(np.sqrt(np.mean(v**2))) for k, v in change.items()}
    assert rms["ancf"] > 1e-3
    assert np.sqrt(np.mean((change["ancf"] - change["lumped-8:uniform"])**2)) < 0.05 * rms["ancf"]


def test_the_reference_solve_refuses_the_new_effects(pendulum_rig):
    with pytest.raises(ValueError, match="no air drag or spring damping"):
        simulate(pendulum_rig, PENDULUM_EFFECTS, dict(FRICTION, drag=0.01), backend="reference", t_end=0.1)


def test_values_come_from_the_rig_and_are_never_defaulted(tmp_path):
    rig = dict(P.REFERENCE_CAM, model={"effects": ["coulomb_friction", "spring_damping"], "spring_model": "massless"})
    rig["friction"] = {"mu_k": 0.1}
    with pytest.raises(InputError, match="closing_spring.damping_ratio"):
        simulate(load_rig(write_rig(tmp_path, rig, "nodamp")), t_end=1e-3)
    rig["closing_spring"] = dict(rig["closing_spring"], damping_ratio=0.02)
    r = simulate(load_rig(write_rig(tmp_path, rig, "damp")), t_end=1e-3)
    assert r.spec.spring_damping == 0.02
    rig["closing_spring"]["damping_ratio"] = 2.0
    with pytest.raises(InputError, match="closing_spring.damping_ratio"):
        load_rig(write_rig(tmp_path, rig, "overdamped"))

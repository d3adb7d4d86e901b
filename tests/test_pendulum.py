"""Layers 2-3: the Exudyn pendulum (paper eq. 1-6) against analytic limits and an independent solve."""
import itertools
import math

import numpy as np
import pytest
from scipy.special import ellipk

from vcbmodel.errors import SimulationError
from vcbmodel.experiments.simulation import simulate

FRICTION = {"mu_k": 0.13, "mu_s": 0.20, "stick_velocity": 1e-3, "stribeck_velocity": 0.1, "viscous": 0.6}
COMBOS = [c for n in range(4) for c in itertools.combinations(("coulomb_friction", "stribeck", "viscous_friction"), n)]


@pytest.mark.parametrize("effects", COMBOS, ids=lambda c: "+".join(c) or "frictionless")
def test_exudyn_matches_independent_solve_over_6_s(pendulum_rig, effects):
    """(a) Exudyn (closed-form reaction, compiled user function) vs the hand-written
    equations with a fixed-point reaction and a separate RK4 loop: within 1 mrad over 6 s."""
    exu = simulate(pendulum_rig, effects, FRICTION, t_end=6.0)
    ref = simulate(pendulum_rig, effects, FRICTION, t_end=6.0, backend="reference", method="rk4",
                   step=exu.info["step"], sample_times=exu.t)
    assert np.max(np.abs(exu.measured - ref.measured)) < 1e-3
    assert np.max(np.abs(exu.measured - ref.measured)) < 1e-8  # in fact to round-off: same equations


@pytest.mark.parametrize("effects", [(), ("viscous_friction",)])
def test_smooth_cases_match_adaptive_dop853(pendulum_rig, effects):
    exu = simulate(pendulum_rig, effects, FRICTION, t_end=6.0)
    ref = simulate(pendulum_rig, effects, FRICTION, t_end=6.0, backend="reference", sample_times=exu.t)
    assert np.max(np.abs(exu.measured - ref.measured)) < 1e-6


def test_python_and_compiled_user_functions_agree(pendulum_rig):
    effects = ("coulomb_friction", "stribeck", "viscous_friction")
    a = simulate(pendulum_rig, effects, FRICTION, t_end=3.0, user_function="symbolic")
    b = simulate(pendulum_rig, effects, FRICTION, t_end=3.0, user_function="python")
    assert np.max(np.abs(a.measured - b.measured)) < 1e-10
    assert np.max(np.abs(a.channels["friction_torque"] - b.channels["friction_torque"])) < 1e-8


def test_frictionless_energy_and_elliptic_period(pendulum_rig):
    """(b) energy conserved; period = 4 sqrt(I/(M g L)) K(sin^2(theta0/2))."""
    p, g = pendulum_rig.pendulum, pendulum_rig.gravity
    r = simulate(pendulum_rig, (), {}, t_end=6.0)
    th, w = r.measured, r.channels["shaft_velocity"]
    energy = 0.5 * p.inertia * w**2 - p.mass * g * p.com_distance * np.cos(th)
    assert np.ptp(energy) / (p.mass * g * p.com_distance * (1 - math.cos(p.initial_angle))) < 1e-6
    # period from upward zero crossings of the velocity (turning points at +theta0)
    crossings = r.t[1:][(w[:-1] > 0) & (w[1:] <= 0)]
    period = np.mean(np.diff(crossings))
    exact = 4 * math.sqrt(p.inertia / (p.mass * g * p.com_distance)) * ellipk(math.sin(p.initial_angle / 2) ** 2)
    assert period == pytest.approx(exact, rel=1e-4)
    assert period != pytest.approx(2 * math.pi * math.sqrt(p.inertia / (p.mass * g * p.com_distance)), rel=1e-3)


def test_coulomb_amplitude_falls_by_the_analytic_amount(pendulum_rig):
    """(c) Coulomb only: each half swing loses the angle fixed by the energy balance
    M g L (cos A2 - cos A1) = T_f (A1 + A2), T_f = mu_k r F_n with F_n ~ M g (the reaction's
    variation over a 10 deg swing, about 2 %, is the tolerance)."""
    p, g, r_j = pendulum_rig.pendulum, pendulum_rig.gravity, pendulum_rig.shaft_radius
    mu = 0.05
    r = simulate(pendulum_rig, ("coulomb_friction",), {"mu_k": mu}, t_end=2.5)
    th, w = r.measured, r.channels["shaft_velocity"]
    turns = 1 + np.nonzero(np.sign(w[2:]) * np.sign(w[1:-1]) < 0)[0]  # reversals after release
    amps = np.abs(th[turns[:4]])
    assert amps.size == 4
    Tf = mu * r_j * p.mass * g
    for a1, a2 in zip(np.concatenate([[p.initial_angle], amps[:-1]]), amps):
        lhs = p.mass * g * p.com_distance * (math.cos(a2) - math.cos(a1))
        assert lhs == pytest.approx(Tf * (a1 + a2), rel=0.03)
        assert a1 - a2 == pytest.approx(2 * Tf / (p.mass * g * p.com_distance), rel=0.04)


def test_pendulum_with_friction_above_gravity_stays_stuck(pendulum_rig):
    """(d) static friction larger than the gravity torque: no motion at all."""
    p, g = pendulum_rig.pendulum, pendulum_rig.gravity
    needed = p.mass * g * p.com_distance * math.sin(p.initial_angle) / (pendulum_rig.shaft_radius * p.mass * g)
    r = simulate(pendulum_rig, ("coulomb_friction",), {"mu_k": 1.2 * needed}, t_end=1.0)
    assert np.max(np.abs(r.measured - p.initial_angle)) < 1e-12
    r = simulate(pendulum_rig, ("coulomb_friction",), {"mu_k": 0.8 * needed}, t_end=1.0)
    assert np.max(np.abs(r.measured - p.initial_angle)) > 1e-3


def test_step_refinement_converges(pendulum_rig):
    effects = ("coulomb_friction", "viscous_friction")
    runs = [simulate(pendulum_rig, effects, FRICTION, t_end=2.0, step=h) for h in (2e-4, 1e-4, 5e-5)]
    t = runs[-1].t[::20]
    d1 = np.max(np.abs(runs[0].resample(t).measured - runs[2].resample(t).measured))
    d2 = np.max(np.abs(runs[1].resample(t).measured - runs[2].resample(t).measured))
    assert d2 < 1e-4 and d1 < 1e-3


def test_diverged_run_is_reported_not_returned(pendulum_rig):
    # a step far beyond stability for an absurd viscous torque -> NaN -> SimulationError
    with pytest.raises(SimulationError):
        simulate(pendulum_rig, ("viscous_friction",), {"viscous": 1e6}, t_end=0.5, step=1e-2)

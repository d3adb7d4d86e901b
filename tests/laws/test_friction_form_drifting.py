"""The drifting Coulomb level: both levels move by a t, mu_k is the level at the release."""
import numpy as np
import pytest

from vcbmodel.experiments.simulation import simulate
from vcbmodel.laws.friction import NumericOps
from vcbmodel.laws.friction_forms import FormLaw
from vcbmodel.reference.torque_truth import pendulum_with_torque


def test_both_levels_move_linearly_in_time_and_never_below_zero():
    law = FormLaw("drifting", mu_s=0.2, mu_k=0.1, stribeck_velocity=0.1, viscous=0.3, extra=(0.004,))
    at5 = law.at(0.7, 5.0, NumericOps)
    assert at5.mu_k == pytest.approx(0.12) and at5.mu_s == pytest.approx(0.22)
    assert (at5.stribeck_velocity, at5.viscous) == (0.1, 0.3)
    down = FormLaw("drifting", mu_s=0.2, mu_k=0.1, extra=(-0.01,)).at(0.7, 15.0, NumericOps)
    assert down.mu_k == 0.0 and down.mu_s == pytest.approx(0.05)


def test_a_drifting_model_follows_an_independent_pendulum_whose_coulomb_level_drifts(pendulum_rig):
    """Against the torque truth (scipy, its own Coulomb friction) with the drift written as an extra
    torque -a t r F_n sign(w): within 0.1 mrad over 8 s; without the drift, over 3 mrad off."""
    p, r, g = pendulum_rig.pendulum, pendulum_rig.shaft_radius, pendulum_rig.gravity
    mu_k, cv, a = 0.08, 0.3, 0.004
    t = np.arange(0.0, 8.0 + 5e-4, 1e-3)
    pend = {"mass": p.mass, "inertia": p.inertia, "com_distance": p.com_distance, "initial_angle": p.initial_angle}

    def drift_torque(time, th, w):
        acc = -p.mass * g * p.com_distance * np.sin(th) / p.inertia
        fn = p.mass * np.hypot(g * np.cos(th) + p.com_distance * w * w, g * np.sin(th) + p.com_distance * acc)
        return -a * time * r * fn * np.sign(w)

    truth = pendulum_with_torque(pend, g, r, {"mu_k": mu_k, "viscous": cv}, drift_torque, t)
    ok = np.isfinite(truth)
    values = {"mu_k": mu_k, "viscous": cv, "mu_k_drift": a}
    effects = ("coulomb_friction", "viscous_friction")
    model = simulate(pendulum_rig, effects + ("drifting_coulomb_friction",), values, sample_times=t).measured
    still = simulate(pendulum_rig, effects, values, sample_times=t).measured
    assert np.max(np.abs(model - truth)[ok]) < 1e-4
    assert np.max(np.abs(still - truth)[ok]) > 3e-3

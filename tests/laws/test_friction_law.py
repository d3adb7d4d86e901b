"""Layer 1: the friction law and the reaction coupling as pure functions, at fixed numbers."""
import math
from dataclasses import replace

import numpy as np
import pytest

from vcbmodel.laws.friction import (FrictionLaw, NumericOps, consistent_reaction, friction_torque, shaft_friction, stuck_torque,
                               symbolic_ops, viscous_from_zeta, zeta_from_viscous)
from vcbmodel.laws.mechanics import cam_loads, pendulum_loads
from vcbmodel.reference.solve import friction_iterated

LAW = FrictionLaw(mu_s=0.2, mu_k=0.1, stick_velocity=1e-3, stribeck_velocity=0.1, viscous=0.5, radius=0.02)


def test_literal_stick_band_holds_below_static_limit():
    literal = replace(LAW, sticking="literal")
    # |Tc| = 1 < mu_s r Fn = 0.2 * 0.02 * 600 = 2.4: friction balances the torque exactly
    assert friction_torque(5e-4, -1.0, 600.0, literal) == -1.0
    # above the static limit: the static friction torque, with the sign of Tc
    assert friction_torque(-5e-4, 3.0, 600.0, literal) == pytest.approx(2.4)


def test_passive_band_opposes_motion_and_stuck_state_stops_the_shaft():
    # a shaft that cannot stick slips against its motion (never along it), from rest along Tc
    assert friction_torque(5e-4, -3.0, 600.0, LAW) == pytest.approx(2.4)
    assert friction_torque(0.0, -3.0, 600.0, LAW) == pytest.approx(-2.4)
    # stuck: theta'' = (Tc - Tf)/I = -w/tau; never along the motion; capped at mu_s r Fn
    I, tau = 2.74, LAW.stick_time
    Tf, Fn = stuck_torque(5e-4, 1.0, (600.0, 0.0), (0.0, 0.0), I, LAW)
    assert (1.0 - Tf) / I == pytest.approx(-5e-4 / tau) and Fn == 600.0
    assert stuck_torque(1e-5, -1.0, (600.0, 0.0), (0.0, 0.0), I, LAW)[0] == 0.0  # would push it along
    assert stuck_torque(2e-3, 2.0, (600.0, 0.0), (0.0, 0.0), I, LAW)[0] == pytest.approx(2.4)  # capped
    for w in np.linspace(-1e-3, 1e-3, 41):
        for Tc in np.linspace(-2.4, 2.4, 13):
            Tf, _ = shaft_friction(w, Tc, 600.0, 0.0, 0.0, 0.0, I, LAW)
            assert Tf * w >= 0.0  # friction never does positive work


def test_stribeck_branch_falls_linearly():
    # halfway to ws: mu = 0.2 - 0.1 * 0.5 = 0.15 -> 0.15 * 0.02 * 600 = 1.8, opposing w
    assert friction_torque(-0.05, 0.0, 600.0, LAW) == pytest.approx(-1.8)


def test_kinetic_branch_with_viscous_offset_by_ws():
    # mu_k r Fn + Cv (w - ws) = 0.1*0.02*600 + 0.5*(1.0 - 0.1) = 1.2 + 0.45
    assert friction_torque(1.0, 0.0, 600.0, LAW) == pytest.approx(1.65)


def test_law_is_continuous_at_stribeck_velocity_and_odd_in_w():
    for w in (0.1 - 1e-9, 0.1 + 1e-9):
        assert friction_torque(w, 0.0, 600.0, LAW) == pytest.approx(1.2, rel=1e-6)
    for w in (0.01, 0.07, 0.5, 3.0):
        assert friction_torque(-w, 0.0, 600.0, LAW) == pytest.approx(-friction_torque(w, 0.0, 600.0, LAW))


def test_without_stribeck_viscous_starts_from_zero_speed():
    law = FrictionLaw(mu_s=0.1, mu_k=0.1, stick_velocity=1e-3, stribeck_velocity=0.0, viscous=0.5, radius=0.02)
    assert friction_torque(1.0, 0.0, 600.0, law) == pytest.approx(1.2 + 0.5)


def test_zeta_round_trip():
    cv = viscous_from_zeta(0.01, 2.74, 60.0, 9.81, 0.2137)
    assert cv == pytest.approx(2 * 0.01 * math.sqrt(2.74 * 60 * 9.81 * 0.2137))
    assert zeta_from_viscous(cv, 2.74, 60.0, 9.81, 0.2137) == pytest.approx(0.01)


@pytest.mark.parametrize("seed", range(5))
def test_closed_form_reaction_equals_fixed_point_iteration(seed):
    rng = np.random.default_rng(seed)
    for _ in range(50):
        th, w = rng.uniform(-1, 1), rng.choice([rng.uniform(-2, 2), rng.uniform(-1e-3, 1e-3)])
        loads = pendulum_loads(th, w, 60.0, 0.2137, 9.81)
        Tf, Fn = shaft_friction(w, loads[0], *loads[1:], 2.74, LAW)
        Tf2, Fn2 = friction_iterated(w, loads[0], loads[1:3], loads[3:5], 2.74, LAW)
        assert Tf == pytest.approx(Tf2, rel=1e-9, abs=1e-12)
        assert Fn == pytest.approx(Fn2, rel=1e-9)


def test_reaction_satisfies_its_defining_equation_for_cam():
    class Cam:
        mass, com_distance, com_angle, arm_length, inertia_pivot = 6.0, 0.02, 0.5, 0.1032, 0.0524
    Tc, R0x, R0y, R1x, R1y = cam_loads(0.7, 40.0, Cam, -9000.0, -3000.0, 9.81)
    c, d = 0.13 * 0.02, 0.0
    Fn = consistent_reaction(R0x, R0y, R1x, R1y, Tc, Cam.inertia_pivot, c, d)
    acc = (Tc - c * Fn - d) / Cam.inertia_pivot
    assert math.hypot(R0x + R1x * acc, R0y + R1y * acc) == pytest.approx(Fn, rel=1e-12)


def test_pendulum_reaction_matches_paper_eq_6():
    th, w, M, L, g = 0.3, 0.8, 60.0, 0.2137, 9.81
    Tc, R0x, R0y, R1x, R1y = pendulum_loads(th, w, M, L, g)
    acc = -2.0
    assert R0x + R1x * acc == pytest.approx(M * g * math.cos(th) + M * L * w**2)
    assert R0y + R1y * acc == pytest.approx(M * g * math.sin(th) + M * L * acc)
    assert Tc == pytest.approx(-M * g * L * math.sin(th))


def test_symbolic_law_evaluates_like_numeric():
    import exudyn
    es = exudyn.symbolic
    es.SetRecording(True)
    ops = symbolic_ops()
    th, w = es.Real("th", 0.0), es.Real("w", 0.0)
    loads = pendulum_loads(th, w, 60.0, 0.2137, 9.81, ops)
    expr = shaft_friction(w, loads[0], *loads[1:], 2.74, LAW, ops)[0]
    for thv, wv in [(0.1, 0.5), (0.1, -0.05), (-0.2, 5e-4), (0.01, 1e-4), (0.3, -2.0), (0.15, 0.1)]:
        th.SetValue(thv)
        w.SetValue(wv)
        num = pendulum_loads(thv, wv, 60.0, 0.2137, 9.81)
        assert expr.Evaluate() == pytest.approx(shaft_friction(wv, num[0], *num[1:], 2.74, LAW)[0], rel=1e-12)


def test_numeric_ops_sign():
    assert NumericOps.sign(np.float64(-2.0)) == -1.0 and NumericOps.sign(0.0) == 0.0

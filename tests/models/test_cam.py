"""Layers 2-3: the Exudyn cam drop (paper eq. 9-13) against an independent solve and energy."""
import math

import numpy as np
import pytest

from vcbmodel.laws.mechanics import cam_pin
from vcbmodel.experiments.simulation import simulate
from vcbmodel.laws.springs import lumped_chain

FRICTION = {"mu_k": 0.13, "mu_s": 0.2, "stick_velocity": 1e-3, "stribeck_velocity": 0.1, "viscous": 0.05}
MODELS = ["massless", "lumped-1", "lumped-2", "lumped-3"]


def effects_for(model, friction):
    e = ("coulomb_friction", "stribeck", "viscous_friction") if friction else ()
    return e + (("spring_mass",) if model != "massless" else ())


@pytest.mark.parametrize("friction", [False, True], ids=["frictionless", "friction"])
@pytest.mark.parametrize("model", MODELS)
def test_exudyn_matches_independent_solve_over_35_ms(cam_rig, model, friction):
    """(a) within 1 mrad of cam angle: Exudyn (mass points, connectors, marker loads, closed-form
    reaction) vs the hand-written eq. 9-13 for n masses, fixed-point reaction, scipy DOP853."""
    eff = effects_for(model, friction)
    exu = simulate(cam_rig, eff, FRICTION, spring_model=model, t_end=0.035)
    ref = simulate(cam_rig, eff, FRICTION, spring_model=model, t_end=0.035, backend="reference",
                   sample_times=exu.t)
    err = np.max(np.abs(exu.measured - ref.measured))
    assert err < 1e-3
    assert err < 1e-4  # measured about 2e-5 rad: the RK4 step error at h = 1e-5 s
    assert exu.measured[-1] - exu.measured[0] > 2.0  # the cam really closes (about 3 rad in 35 ms)


def _energy(rig, result, model):
    cam, spring, g = rig.cam, rig.closing_spring, rig.gravity
    th, w = result.measured, result.channels["shaft_velocity"]
    c = spring.count
    phi = th - cam.com_angle
    energy = 0.5 * cam.inertia_pivot * w**2 + cam.mass * g * (cam.pivot[1] + cam.com_distance * np.sin(phi))
    bx, by = cam_pin(th, cam, np)
    O = np.array(spring.anchor)
    if model == "massless":
        d = np.hypot(bx - O[0], by - O[1])
        return energy + 0.5 * c * spring.stiffness * (d - spring.free_length) ** 2
    n = int(model.split("-")[1])
    chain = lumped_chain(n, spring.stiffness, spring.mass, spring.free_length)
    energy = energy + 0.5 * c * chain.pin_mass * (w * cam.arm_length) ** 2  # the pin's share rides on B
    pts = [np.stack([np.full_like(th, O[0]), np.full_like(th, O[1])], 1)]
    for i in range(n):
        x, y = result.channels[f"spring_mass_{i + 1}_x"], result.channels[f"spring_mass_{i + 1}_y"]
        pts.append(np.stack([x, y], 1))
        vx, vy = result.channels[f"spring_velocity_{i + 1}_x"], result.channels[f"spring_velocity_{i + 1}_y"]
        energy = energy + 0.5 * c * chain.masses[i] * (vx**2 + vy**2)
    pts.append(np.stack([bx, by], 1))
    for i in range(n + 1):
        d = np.linalg.norm(pts[i + 1] - pts[i], axis=1)
        energy = energy + 0.5 * c * chain.stiffnesses[i] * (d - chain.free_lengths[i]) ** 2
    return energy


@pytest.mark.parametrize("model", MODELS)
def test_frictionless_energy_is_conserved(cam_rig, model):
    """(b) cam, springs, spring masses and gravity: energy constant to 0.1 % of the released spring energy."""
    eff = effects_for(model, False)
    r = simulate(cam_rig, eff, {}, spring_model=model, t_end=0.035)
    e = _energy(cam_rig, r, model)
    released = 0.5 * cam_rig.closing_spring.count * cam_rig.closing_spring.stiffness * (0.2464**2 - 0.05**2)
    assert np.ptp(e) / released < 1e-3
    assert np.ptp(e) / released < 1e-6  # measured: RK4 at 1e-5 s conserves it to 1e-8
    # and friction does take energy out
    rf = simulate(cam_rig, ("coulomb_friction",) + eff, {"mu_k": 0.13}, spring_model=model, t_end=0.035)
    assert _energy(cam_rig, rf, model)[-1] < e[0] - 1.0


@pytest.mark.parametrize("model", ["massless", "lumped-3"])
def test_step_refinement_changes_curve_by_less_than_0_1_mrad(cam_rig, model):
    """(c) the default step against half of it."""
    eff = effects_for(model, True)
    a = simulate(cam_rig, eff, FRICTION, spring_model=model, t_end=0.035)
    b = simulate(cam_rig, eff, FRICTION, spring_model=model, t_end=0.035, step=a.info["step"] / 2, sample_times=a.t)
    assert np.max(np.abs(a.measured - b.measured)) < 1e-4


def test_reference_rig_matches_paper_forces(cam_rig):
    """~6000 N per spring at the start, ~1000 N near the end of the stroke, ~30 ms."""
    cam, s = cam_rig.cam, cam_rig.closing_spring
    def force(th):
        bx, by = cam_pin(th, cam)
        return s.stiffness * (math.hypot(bx - s.anchor[0], by - s.anchor[1]) - s.free_length)
    assert force(cam.initial_angle) == pytest.approx(6000, rel=0.02)
    assert force(math.pi) == pytest.approx(1000, rel=0.02)
    r = simulate(cam_rig, spring_model="lumped-2", t_end=0.035)
    t_pi = np.interp(math.pi, r.measured, r.t)
    assert 0.02 < t_pi < 0.035


def test_spring_mass_slows_the_cam(cam_rig):
    """The paper's finding: the spring's own mass makes the cam turn less and later."""
    light = simulate(cam_rig, ("coulomb_friction",), {"mu_k": 0.13}, spring_model="massless", t_end=0.03)
    heavy = simulate(cam_rig, ("coulomb_friction", "spring_mass"), {"mu_k": 0.13}, spring_model="lumped-2", t_end=0.03)
    assert heavy.measured[-1] < light.measured[-1] - 0.05

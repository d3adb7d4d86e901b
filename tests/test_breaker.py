"""The whole breaker (paper section 4): laws, rest state, independent solve, energy, convergence."""
import copy
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.laws.breaker import (BreakerLaws, cam_roller_contact, cam_roller_loads, kinematic_follower_angle, latch_torque,
                              pitch_radius, polynomial_rise, pressure_angle_curve, push_rod_energy, push_rod_force)
from vcbmodel.analysis.diagnose import diagnose
from vcbmodel.analysis.synthetic import synthetic_measurement
from vcbmodel.errors import InputError
from vcbmodel.experiments.closing_evaluation import energy_balance, figures_of_merit
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import model_spec, simulate
from vcbmodel.records.measurement import write_measurement

T_END = 0.04


def write(tmp_path, rig_dict, name="breaker.rig.json"):
    path = tmp_path / name
    path.write_text(json.dumps(rig_dict))
    return path


@pytest.fixture(scope="module")
def rig(tmp_path_factory):
    return load_rig(write(tmp_path_factory.mktemp("breaker"), P.REFERENCE_BREAKER))


@pytest.fixture(scope="module")
def laws(rig):
    return BreakerLaws.of_rig(rig, model_spec(rig))


# --- pure laws -------------------------------------------------------------------------------

def test_polynomial_rise_is_smooth_and_its_derivative_is_right():
    assert polynomial_rise(0.0) == (0.0, 0.0)
    assert polynomial_rise(1.0)[0] == pytest.approx(1.0, abs=1e-12)
    assert polynomial_rise(1.0)[1] == pytest.approx(0.0, abs=1e-12)
    assert polynomial_rise(0.5)[0] == pytest.approx(0.5, abs=1e-12)
    for x in np.linspace(0.05, 0.95, 7):
        numeric = (polynomial_rise(x + 1e-6)[0] - polynomial_rise(x - 1e-6)[0]) / 2e-6
        assert polynomial_rise(x)[1] == pytest.approx(numeric, rel=1e-6)
    # acceleration zero at both ends: ds/dx ~ x^3 near 0
    assert polynomial_rise(1e-3)[1] < 1e-6


def test_pitch_curve_is_continuous_periodic_and_differentiated_right(rig):
    b = rig.breaker
    u = np.linspace(0.0, 4 * math.pi, 4001)
    rho = np.array([pitch_radius(x, b.profile, b.roller_radius)[0] for x in u])
    assert np.max(np.abs(np.diff(rho))) < 1e-4  # no jump
    assert rho.min() == pytest.approx(b.profile.base_radius + b.roller_radius)
    assert rho.max() == pytest.approx(b.profile.base_radius + b.roller_radius + b.profile.lift)
    for x in (0.9, 2.0, 3.5, 5.9, 6.1):
        numeric = (pitch_radius(x + 1e-7, b.profile, b.roller_radius)[0]
                   - pitch_radius(x - 1e-7, b.profile, b.roller_radius)[0]) / 2e-7
        assert pitch_radius(x, b.profile, b.roller_radius)[1] == pytest.approx(numeric, rel=1e-5, abs=1e-9)
    assert pitch_radius(1.0, b.profile, b.roller_radius) == pytest.approx(
        pitch_radius(1.0 + 2 * math.pi, b.profile, b.roller_radius), rel=1e-12)


def test_penetration_rate_is_the_time_derivative_of_penetration(rig, laws):
    b, g = rig.breaker, laws.geometry
    rng = np.random.default_rng(3)
    for _ in range(10):
        th, w = rng.uniform(0.8, 3.5), rng.uniform(-200, 200)
        # in contact (0.01 mm): the rate is exact to first order in the penetration
        phi, phid = kinematic_follower_angle(th, b, g) - 1e-4, rng.uniform(-30, 30)
        h = 1e-8
        c = cam_roller_contact(th, w, phi, phid, b, g)
        plus = cam_roller_contact(th + w * h, w, phi + phid * h, phid, b, g).penetration
        minus = cam_roller_contact(th - w * h, w, phi - phid * h, phid, b, g).penetration
        assert c.penetration_rate == pytest.approx((plus - minus) / (2 * h), rel=1e-3, abs=1e-6)


def test_contact_torques_do_the_work_of_the_penetration(rig, laws):
    """Virtual work: a normal force F along n does -F d(penetration) on (theta, phi)."""
    b, g = rig.breaker, laws.geometry
    for th in (1.2, 2.0, 2.8):
        phi = kinematic_follower_angle(th, b, g) - 1e-4
        c = cam_roller_contact(th, 0.0, phi, 0.0, b, g)
        t_cam, t_fol, fx, fy = cam_roller_loads(c, 1000.0, b, g)
        h = 1e-7
        d_th = (cam_roller_contact(th + h, 0, phi, 0, b, g).penetration
                - cam_roller_contact(th - h, 0, phi, 0, b, g).penetration) / (2 * h)
        d_phi = (cam_roller_contact(th, 0, phi + h, 0, b, g).penetration
                 - cam_roller_contact(th, 0, phi - h, 0, b, g).penetration) / (2 * h)
        assert t_cam == pytest.approx(-1000.0 * d_th, rel=1e-3, abs=1e-3)
        assert t_fol == pytest.approx(-1000.0 * d_phi, rel=1e-3, abs=1e-3)
        assert math.hypot(fx, fy) == pytest.approx(1000.0)


def test_push_rod_law_is_continuous_and_its_energy_integrates_the_force(rig):
    poles = rig.breaker.poles
    s0 = poles.wipe_preload / poles.rod_stiffness
    assert push_rod_force(s0 - 1e-12, 0, poles) == pytest.approx(push_rod_force(s0 + 1e-12, 0, poles), abs=1e-3)
    assert push_rod_force(s0 + 0.004, 0, poles) == pytest.approx(poles.wipe_preload + poles.wipe_rate * 0.004)
    assert push_rod_force(-1e-5, 0, poles) == pytest.approx(-poles.rod_stiffness * 1e-5)  # holds in tension
    assert push_rod_force(0.001, 0.1, poles) - push_rod_force(0.001, 0.0, poles) == pytest.approx(0.1 * poles.rod_damping)
    for s in (-1e-5, 0.5 * s0, 2 * s0, 0.003):
        numeric = (push_rod_energy(s + 1e-9, poles) - push_rod_energy(s - 1e-9, poles)) / 2e-9
        assert numeric == pytest.approx(push_rod_force(s, 0.0, poles), rel=1e-4)


def test_latch_releases_linearly():
    assert latch_torque(-1.0, 100.0, 0.002) == 100.0
    assert latch_torque(0.001, 100.0, 0.002) == pytest.approx(50.0)
    assert latch_torque(0.003, 100.0, 0.002) == 0.0
    assert latch_torque(0.0, 100.0, 0.0) == 100.0 and latch_torque(1e-9, 100.0, 0.0) == 0.0


def test_cam_profile_pressure_angle_stays_below_30_degrees(rig, laws):
    thetas = np.linspace(rig.cam.initial_angle, rig.cam.initial_angle + 2 * math.pi, 361)
    angle = np.degrees(pressure_angle_curve(rig.breaker, laws.geometry, thetas))
    assert angle.max() < 30.0
    assert angle.max() > 1.0  # the profile does rise


# --- the model -----------------------------------------------------------------------------------

def test_breaker_rests_while_the_latch_holds(tmp_path):
    """The static rest state is an equilibrium of the Exudyn model: nothing moves."""
    d = copy.deepcopy(P.REFERENCE_BREAKER)
    d["breaker"]["latch"]["release_time"] = 1.0
    d["friction"] = {}
    d["model"] = {"effects": ["bellows_force"], "spring_model": "massless"}
    rig = load_rig(write(tmp_path, d))
    # the holding torque only starts falling at t = 0: over 2 ms it falls by 0.2 %
    r = simulate(rig, t_end=0.002)
    assert np.max(np.abs(r.channels["cam_angle"] - rig.cam.initial_angle)) < 1e-5
    assert np.max(np.abs(r.channels["pole_1_velocity"])) < 1e-3
    assert np.max(np.abs(r.channels["follower_velocity"])) < 1e-2


@pytest.mark.parametrize("effects,spring", [
    (("coulomb_friction", "stribeck", "contact_damping", "bellows_force"), "massless"),
    (("coulomb_friction", "contact_damping", "bellows_force", "spring_mass"), "lumped-2"),
])
def test_exudyn_breaker_equals_the_hand_written_equations(rig, effects, spring):
    """Same step, same RK4, equations assembled independently: agreement to round-off."""
    a = simulate(rig, effects, spring_model=spring, t_end=T_END)
    b = simulate(rig, effects, spring_model=spring, t_end=T_END, backend="reference", method="rk4", step=P.BREAKER_STEP)
    for name in ("cam_angle", "follower_displacement", "pole_1_travel", "pole_3_velocity"):
        assert np.max(np.abs(a.channels[name] - np.interp(a.t, b.t, b.channels[name]))) < 1e-8 * max(
            1.0, np.max(np.abs(a.channels[name]))), name


def test_exudyn_breaker_matches_an_adaptive_solve(rig):
    """Elastic contacts (no impact memory): Exudyn's RK4 vs scipy DOP853 at tight tolerance."""
    effects = ("coulomb_friction", "bellows_force")
    a = simulate(rig, effects, spring_model="massless", t_end=T_END)
    b = simulate(rig, effects, spring_model="massless", t_end=T_END, backend="reference", method="DOP853", step=2e-5)
    d = np.interp(b.t, a.t, a.channels["follower_displacement"]) - b.channels["follower_displacement"]
    assert np.max(np.abs(d)) < 2e-6  # m, of a 15 mm stroke


@pytest.mark.parametrize("spring", ["massless", "lumped-2"])
def test_energy_balance_of_the_whole_closing(rig, spring):
    """Released spring energy = kinetic + dissipated (friction, contacts, rods) + stored, to 1 %."""
    r = simulate(rig, spring_model=spring, t_end=T_END,
                 effects=[e for e in rig.model.effects if spring != "massless" or e != "spring_mass"])
    e = energy_balance(r, rig)
    released = np.max(e["spring_energy_released"])
    assert released > 1000.0
    assert np.max(np.abs(e["residual"])) < 0.01 * released
    assert np.max(np.abs(e["residual"])) < 1e-3 * released  # measured: 2e-5
    assert e["dissipated"][-1] > 100.0  # shaft friction dissipates
    assert e["wipe_and_rods"][-1] > 20.0  # the wipe springs are charged


def test_step_refinement_converges(rig):
    a = simulate(rig, t_end=T_END)
    b = simulate(rig, t_end=T_END, step=P.BREAKER_STEP / 2)
    fa, fb = figures_of_merit(a, rig), figures_of_merit(b, rig)
    assert abs(fa["closing_time_s"] - fb["closing_time_s"]) < 1e-6
    d = np.interp(a.t, b.t, b.channels["follower_displacement"]) - a.channels["follower_displacement"]
    assert np.max(np.abs(d)) < 1e-6


def test_figures_of_merit_follow_the_physics(rig):
    full = figures_of_merit(simulate(rig, t_end=T_END), rig)
    frictionless = figures_of_merit(simulate(rig, ["spring_mass", "contact_damping", "bellows_force"], t_end=T_END), rig)
    assert 0.02 < full["closing_time_s"] < 0.04  # "closing in about 30 ms"
    assert frictionless["closing_time_s"] < full["closing_time_s"] - 5e-4  # friction slows the closing
    touches = full["per_pole"]["touch_s"]  # pole 3 has the smallest gap, pole 2 the largest
    assert touches[2] < touches[0] < touches[1]
    assert full["bounce_count"] >= 1 and full["bounce_duration_s"] < 5e-3
    assert 0.5 < full["touch_speed_m_s"] < 4.0
    # wipe: follower travel after the touch = stroke - gap, a few mm
    assert 0.002 < full["overtravel_m"] < 0.006
    elastic = figures_of_merit(simulate(rig, ["coulomb_friction", "stribeck", "spring_mass", "bellows_force"],
                                        t_end=T_END), rig)
    assert elastic["bounce_duration_s"] > full["bounce_duration_s"]  # damping shortens the bouncing


# --- input ---------------------------------------------------------------------------------------

@pytest.mark.parametrize("edit,field", [
    (lambda d: d["breaker"]["poles"].pop("moving_mass"), "breaker.poles.moving_mass"),
    (lambda d: d["breaker"]["poles"].__setitem__("moving_mass", -1.5), "breaker.poles.moving_mass"),
    (lambda d: d["breaker"]["poles"].__setitem__("gap_offsets", [0.0]), "breaker.poles.gap_offsets"),
    (lambda d: d["breaker"]["contact"].__setitem__("restitution", 1.5), "breaker.contact.restitution"),
    (lambda d: d["breaker"]["cam_profile"].__setitem__("rise_end", 0.1), "breaker.cam_profile.rise_start"),
    (lambda d: d.pop("breaker"), "breaker"),
    (lambda d: d["breaker"]["follower"].__setitem__("pivot", [5.0, 5.0]), "breaker.follower.pivot"),
    (lambda d: d["cam"].__setitem__("initial_angle", 2.0), "cam.initial_angle"),
])
def test_bad_breaker_sections_name_the_field(tmp_path, edit, field):
    d = copy.deepcopy(P.REFERENCE_BREAKER)
    edit(d)
    with pytest.raises(InputError) as e:
        load_rig(write(tmp_path, d))
    assert f": {field}: " in str(e.value)


def test_breaker_effects_are_refused_on_a_cam_drop_rig(tmp_path):
    d = copy.deepcopy(P.REFERENCE_CAM)
    d["model"] = {"effects": ["contact_damping"], "spring_model": "massless"}
    with pytest.raises(InputError, match="model.effects"):
        load_rig(write(tmp_path, d))


def test_cli_simulates_a_closing_and_writes_follower_displacement(tmp_path):
    path = write(tmp_path, P.REFERENCE_BREAKER)
    out = tmp_path / "closing.csv"
    p = subprocess.run([sys.executable, "-m", "vcbmodel", "simulate", str(path), "--spring-model", "massless",
                        "--t-end", "0.035", "-o", str(out)], capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    lines = [ln for ln in out.read_text().splitlines() if not ln.startswith("#")]
    assert lines[0] == "t,follower_displacement"
    values = np.array([[float(x) for x in ln.split(",")] for ln in lines[1:]])
    assert values[0, 1] == 0.0 and 0.013 < values[-1, 1] < 0.016  # closed: gap + wipe
    assert np.allclose(np.diff(values[:, 0]), 1 / 12000, atol=1e-7)


# --- diagnosis on a closing ----------------------------------------------------------------------

def hidden_effect_case(tmp_path, starting_effects, truth_values, seed):

    d = copy.deepcopy(P.REFERENCE_BREAKER)
    d["friction"] = {"stick_velocity": 1e-3} if "coulomb_friction" not in starting_effects else {
        "mu_k": truth_values["mu_k"], "stick_velocity": 1e-3}
    d["breaker"]["contact"].pop("restitution")
    d["breaker"]["poles"].pop("bellows_force")
    d["model"] = {"effects": list(starting_effects), "spring_model": "lumped-2", "lumped_convention": "paper"}
    rig = load_rig(write(tmp_path, d, "closing.rig.json"))
    truth = ("coulomb_friction", "spring_mass", "contact_damping", "bellows_force")
    meas = synthetic_measurement(rig, truth, truth_values, seed=seed, t_end=T_END, path=tmp_path / "closing.csv")
    write_measurement(meas, meas.path)
    return rig, meas


@pytest.mark.parametrize("starting,truth,seed,missing,parameter,rel", [
    (("spring_mass", "contact_damping", "bellows_force"),
     {"mu_k": 0.12, "restitution": 0.8, "bellows_force": 150.0}, 5, "coulomb_friction", "mu_k", 0.03),
    pytest.param(("coulomb_friction", "spring_mass", "contact_damping"),
                 {"mu_k": 0.13, "restitution": 0.8, "bellows_force": 300.0}, 6, "bellows_force", "bellows_force", 0.3,
                 marks=pytest.mark.slow),
], ids=["hidden_shaft_friction", "hidden_bellows_force"])
def test_diagnosis_finds_a_hidden_effect_in_a_closing(tmp_path, starting, truth, seed, missing, parameter, rel):
    rig, meas = hidden_effect_case(tmp_path, starting, truth, seed=seed)
    d = diagnose(rig, meas, verbose=False)
    assert d.missing_effect == missing
    assert d.final.values[parameter] == pytest.approx(truth[parameter], rel=rel)
    if missing == "coulomb_friction":
        assert d.baseline.rms > 10 * d.final.rms
        assert d.final.rms < 1.3 * d.noise

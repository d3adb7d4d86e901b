"""The closing end stop and the holding latch (rig sections ``breaker.end_stop``,
``breaker.hold_latch``; laws in vcbmodel.laws.breaker): what stops the cam after the closing.

The test breaker is the reference breaker before issue 19 (FORMER_REFERENCE_BREAKER in
parameters.py, which has neither; the resized REFERENCE_BREAKER has its own) with an end stop at 210 deg and a
holding latch at 205 deg: after the touch (176 deg) and on the cam's rise, so the cam's travel into
the stop shows in the follower's travel. The values are this test's own (a buffer of 8e7 N/m and
2e4 N s/m at 0.1 m: about 0.4 of its critical damping on the cam's inertia), not a design: the
reference breaker's own stop and latch are set with its energy budget (issue 19).
Tolerances are set from measured numbers (given in each test) with a margin."""
import copy
import math
from pathlib import Path

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.compiled import compiler_works
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.closing_evaluation import SPLIT_TERMS, energy_balance, energy_splits, figures_of_merit
from vcbmodel.experiments.simulation import model_spec, simulate
from vcbmodel.laws.breaker import (EndStop, HoldLatch, end_stop_damping, end_stop_force, hold_latch_engagement,
                                   hold_latch_force)
from vcbmodel.laws.friction import ArrayOps
from vcbmodel.records.analyser import figures_of_merit as analyser_figures
from vcbmodel.reference.breaker import solve_closing

from conftest import write_rig

END_STOP = {"angle": math.radians(210.0), "arm": 0.1, "stiffness": 8e7, "damping": 2e4}
HOLD_LATCH = {"angle": math.radians(205.0), "arm": 0.1, "stiffness": 8e7, "damping": 2e4}
T_END = 0.07  # s: the cam hits the stop at 34.9 ms and rests on the latch from about 60 ms

needs_compiler = pytest.mark.skipif(not compiler_works(), reason="no working C compiler")


def stopped(end_stop=None, hold_latch=None):
    d = copy.deepcopy(P.FORMER_REFERENCE_BREAKER)
    d["breaker"]["end_stop"] = dict(END_STOP, **(end_stop or {}))
    d["breaker"]["hold_latch"] = dict(HOLD_LATCH, **(hold_latch or {}))
    return d


@pytest.fixture(scope="module")
def rig(tmp_path_factory):
    return load_rig(write_rig(tmp_path_factory.mktemp("stop"), stopped(), "stopped"))


# --- the laws -----------------------------------------------------------------------------------

def test_end_stop_pushes_only_in_contact_and_never_pulls():
    stop = EndStop(angle=1.0, arm=0.1, stiffness=1e6, damping=1e3)
    assert end_stop_force(0.99, 10.0, stop) == 0.0  # before the stop, even moving towards it
    # 1 mrad in: 0.1 mm at the arm: 100 N, plus the damper 1e3 N s/m x 0.1 m x 2 rad/s
    assert end_stop_force(1.001, 2.0, stop) == pytest.approx(100.0 + 200.0)
    assert end_stop_force(1.001, -10.0, stop) == 0.0  # leaving fast: the damper would pull, clipped
    theta = np.linspace(0.9, 1.1, 11)
    assert np.array_equal(end_stop_force(theta, 1.0, stop, ArrayOps),
                          np.array([end_stop_force(x, 1.0, stop) for x in theta]))


def test_a_buffer_with_a_damping_depth_rises_from_zero_at_contact():
    """With ``damping_depth`` the damping grows as c d / d_r up to c: the force is continuous at
    contact (the plain dashpot jumps to c v there) and equals the plain one beyond the depth."""
    plain = EndStop(angle=1.0, arm=0.1, stiffness=1e6, damping=1e3)
    ramped = EndStop(angle=1.0, arm=0.1, stiffness=1e6, damping=1e3, damping_depth=1e-3)
    just_in = 1.0 + 1e-9  # 0.1 nm in, lever at 5 m/s (50 rad/s x 0.1 m)
    assert end_stop_force(just_in, 50.0, plain) == pytest.approx(5000.0, rel=1e-3)  # the jump: c v
    assert end_stop_force(just_in, 50.0, ramped) < 1.0  # N: c (1e-10 / 1e-3) v + k d
    # 0.5 mm in (5 mrad): half the damping: 500 N + 0.5 x 1e3 x 5 m/s
    assert end_stop_force(1.005, 50.0, ramped) == pytest.approx(500.0 + 2500.0)
    assert end_stop_damping(5e-4, ramped) == pytest.approx(500.0)
    for theta in (1.01, 1.05):  # beyond the depth the two laws are one
        assert end_stop_force(theta, 50.0, ramped) == pytest.approx(end_stop_force(theta, 50.0, plain))
    theta = np.linspace(0.99, 1.02, 31)
    assert np.allclose(end_stop_force(theta, 50.0, ramped, ArrayOps), [end_stop_force(x, 50.0, ramped) for x in theta])


def test_hold_latch_stops_the_cam_turning_back_only_once_engaged():
    latch = HoldLatch(angle=2.0, arm=0.05, stiffness=1e6, damping=0.0)
    assert hold_latch_force(1.99, -1.0, 0.0, latch) == 0.0  # not engaged: the cam passes back freely
    assert hold_latch_force(1.99, -1.0, 1.0, latch) == pytest.approx(1e6 * 0.05 * 0.01)
    assert hold_latch_force(2.01, 1.0, 1.0, latch) == 0.0  # ahead of the pawl: no contact
    engaged = 0.0
    for theta in (1.5, 1.99, 2.0, 1.5):  # engages on reaching the angle and stays engaged
        engaged = hold_latch_engagement(engaged, theta, latch)
    assert engaged == 1.0
    assert hold_latch_engagement(0.0, 1.999, latch) == 0.0


# --- the closing with a stop and a latch ---------------------------------------------------------

@needs_compiler
@pytest.mark.parametrize("spring_model", ["massless", "lumped-2"])
def test_compiled_and_exudyn_agree_with_stop_and_latch(rig, spring_model):
    """Same laws, two assemblies (the Exudyn connector and pre-step memory, the traced C).
    Measured: 1.2e-13 rad, 5e-16 m over 70 ms with the stop's impact and the latch's catch."""
    effects = [e for e in rig.model.effects if spring_model != "massless" or e != "spring_mass"]
    a = simulate(rig, effects, spring_model=spring_model, t_end=T_END, backend="exudyn")
    b = simulate(rig, effects, spring_model=spring_model, t_end=T_END, backend="compiled")
    assert np.max(np.abs(a.channels["cam_angle"] - b.channels["cam_angle"])) < 1e-9
    assert np.max(np.abs(a.measured - b.measured)) < 1e-9
    assert np.max(np.abs(a.channels["pole_2_travel"] - b.channels["pole_2_travel"])) < 1e-9
    # the run covers the stop and the latch: the cam went past the stop's angle and came back below the latch's
    theta = b.channels["cam_angle"]
    assert theta.max() > END_STOP["angle"] and theta[-1] < HOLD_LATCH["angle"]


@pytest.fixture(scope="module")
def ramped_rig(tmp_path_factory):
    """The test rig with a buffer whose damping builds up over its first millimetre."""
    return load_rig(write_rig(tmp_path_factory.mktemp("ramp"), stopped({"damping_depth": 1e-3}), "ramped"))


@needs_compiler
def test_compiled_and_exudyn_agree_with_a_ramped_buffer(ramped_rig):
    """The ramp (ops.min in the law) traced to C and in Exudyn's user function: round-off."""
    a = simulate(ramped_rig, t_end=T_END, backend="exudyn")
    b = simulate(ramped_rig, t_end=T_END, backend="compiled")
    assert np.max(np.abs(a.channels["cam_angle"] - b.channels["cam_angle"])) < 1e-9
    force = b.channels["end_stop_force"]
    first = int(np.argmax(force > 0.0))
    jump = END_STOP["damping"] * END_STOP["arm"] * b.channels["shaft_velocity"][first]  # a plain dashpot's c v
    depth = b.channels["end_stop_penetration"][first]  # the cam turns 0.2 mm (at the arm) per step here
    # continuous at contact: the first sample in contact carries the damping's share d / d_r of c v
    assert depth < 0.3e-3 and force[first] < 0.3 * jump
    assert b.channels["cam_angle"].max() > END_STOP["angle"]


def test_independent_solve_agrees_with_a_ramped_buffer(ramped_rig):
    """The independent solve writes the ramp again (c d / d_r below the depth). Without the damper's
    jump the model's RK4 step meets a kink only: measured 2.0e-4 rad against 1.07e-3 rad with the
    plain dashpot (cam angle), follower 0.76 um against 3.9 um."""
    d, ref = _against_independent(ramped_rig)
    plain, _ = _against_independent(load_rig(write_rig(Path(ramped_rig.path).parent, stopped(), "plain")))
    assert d["cam_angle"] < plain["cam_angle"] / 3
    assert d["follower_displacement"] < 2e-6


def test_reference_wiring_agrees_with_stop_and_latch(rig):
    """The hand-written equations on the model's laws (reference/solve.py, its pre-step memory),
    the same RK4 step: round-off (measured below 1e-12 rad)."""
    effects = ("contact_damping", "bellows_force", "spring_mass")
    a = simulate(rig, effects, t_end=0.05)
    b = simulate(rig, effects, t_end=0.05, backend="reference", method="rk4", step=P.BREAKER_STEP)
    assert np.max(np.abs(a.channels["cam_angle"] - np.interp(a.t, b.t, b.channels["cam_angle"]))) < 1e-8
    assert a.channels["cam_angle"].max() > END_STOP["angle"]


@needs_compiler
def test_the_latch_holds_the_cam_at_rest(rig):
    """The stop turns the cam back at 211.5 deg (1.5 deg into it); the closing springs, past their
    dead centre at 180 deg, pull it back onto the engaged latch, which holds it at 205 deg less
    its spring's give (measured 0.008 deg): the cam rests, the follower's travel settles."""
    r = simulate(rig, t_end=T_END, backend="compiled")
    theta, x = r.channels["cam_angle"], r.measured
    hit = int(np.argmax(theta >= END_STOP["angle"]))
    after = slice(hit, None)
    assert math.degrees(theta.max() - END_STOP["angle"]) == pytest.approx(1.53, abs=0.05)
    # the latch catches the cam coming back (measured 0.50 deg into it, 0.9 mm at its arm) and holds it
    assert math.degrees(HOLD_LATCH["angle"] - np.min(theta[after])) == pytest.approx(0.50, abs=0.05)
    late = r.t > T_END - 0.01
    assert np.max(np.abs(r.channels["shaft_velocity"][late])) < 1.0  # rad/s, from 204 at the stop
    assert np.ptp(x[late]) < 1e-5  # m: the travel has settled (measured 2.2 um, of 0.46 mm overtravel)
    assert theta[-1] == pytest.approx(HOLD_LATCH["angle"], abs=math.radians(0.02))


@needs_compiler
def test_a_stiffer_or_more_damped_stop_gives_less_overtravel(tmp_path):
    """Overtravel as analysers define it (largest travel beyond the final position), from the
    dynamics. Measured: 0.458 mm at 8e7 N/m and 2e4 N s/m; 0.452 mm twice as stiff, 0.438 mm twice
    as damped, 0.526 mm undamped."""
    def overtravel(**stop):
        r = simulate(load_rig(write_rig(tmp_path, stopped(stop), "s")), t_end=T_END, backend="compiled")
        return analyser_figures(r.t, [], r.measured)["overtravel_m"]

    base = overtravel()
    assert base == pytest.approx(0.458e-3, abs=0.01e-3)
    assert overtravel(stiffness=1.6e8) < base - 3e-6
    assert overtravel(damping=4e4) < base - 1e-5
    assert overtravel(damping=0.0) > base + 5e-5


@needs_compiler
def test_a_stop_the_cam_never_reaches_changes_nothing(tmp_path):
    """A stop and latch beyond the cam's turn (the cam turns back at 291.5 deg in 45 ms): the same
    numbers as the rig without them (the forces are exactly zero out of contact)."""
    far = stopped({"angle": math.radians(330.0)}, {"angle": math.radians(320.0)})
    a = simulate(load_rig(write_rig(tmp_path, far, "far")), backend="compiled")
    b = simulate(load_rig(write_rig(tmp_path, P.FORMER_REFERENCE_BREAKER, "plain")), backend="compiled")
    assert np.array_equal(a.channels["cam_angle"], b.channels["cam_angle"])
    assert np.array_equal(a.measured, b.measured)


# --- against the independent solve (vcbmodel/reference/breaker*.py) --------------------------------

def _against_independent(rig, step=None, t_end=0.04):
    """The model (massless springs, the literal stick band) and the independent event-driven solve,
    at 1e-4 s over the stop's impact (33.9 ms) and the latch's catch (36.1 ms)."""
    effects = [e for e in rig.model.effects if e != "spring_mass"]
    a = simulate(rig, effects, spring_model="massless", t_end=t_end, sticking="literal", step=step)
    every = int(round(1e-4 / (step or P.BREAKER_STEP)))
    t = a.t[::every]
    spec = model_spec(rig, effects, spring_model="massless")
    ref = solve_closing(rig, spec, t)
    d = {name: float(np.max(np.abs(a.channels[name][::every] - ref[name])))
         for name in ("cam_angle", "follower_displacement", "pole_1_travel")}
    return d, ref


def test_independent_solve_agrees_with_stop_and_latch(rig):
    """The independent solve writes the stop and the latch again (no law imported) and finds the
    stop's contact, the latch's engagement and the latch's contact as events, exactly; the model
    keeps the engagement as memory from the start of its RK4 step and meets the damper's jump at
    the stop's contact inside a step. What they share: the reading of the rig fields (a linear
    spring and damper at the arm on A->B, perpendicular to it, never pulling; a latch that engages
    on reaching its angle). Measured at the 1e-5 s step: cam angle 1.0e-3 rad (the cam turns
    2e-3 rad per step at the stop), follower 4.5 um, pole travel 1.3 um; 1.3e-6 rad and 0.03 um
    before the stop."""
    d, ref = _against_independent(rig)
    assert d["cam_angle"] < 2.5e-3
    assert d["follower_displacement"] < 1e-5
    assert d["pole_1_travel"] < 3e-6
    kinds = [kind for _, kind in ref["events"] if "stop" in kind or "hold" in kind]
    assert kinds[:4] == ["hold_latch_engages", "end_stop_closes", "end_stop_opens", "hold_latch_closes"]


@pytest.mark.slow
def test_the_difference_to_the_independent_solve_shrinks_with_the_step(rig):
    """The difference is the model's step at the stop's and the latch's contacts: measured 1.0e-3,
    3.8e-4 and 1.3e-4 rad at 1e-5, 5e-6 and 2.5e-6 s."""
    coarse, _ = _against_independent(rig)
    fine, _ = _against_independent(rig, step=P.BREAKER_STEP / 4)
    assert fine["cam_angle"] < coarse["cam_angle"] / 4
    assert fine["follower_displacement"] < coarse["follower_displacement"] / 4


# --- energy and figures of merit ------------------------------------------------------------------

@needs_compiler
def test_energy_balance_closes_with_stop_and_latch(rig):
    """The stop's and the latch's springs and dampers in the balance. The damper's force jumps by
    c a omega (about 400 kN here) when the stop is met inside an RK4 step, so the balance closes to
    first order in the step: measured residual 16.4 J of 1372 J released at 1e-5 s, 4.8 J at
    2.5e-6 s (without the stop's terms it would miss the 870 J its damper takes)."""
    released, residual = [], []
    for step in (P.BREAKER_STEP, P.BREAKER_STEP / 4):
        r = simulate(rig, t_end=T_END, backend="compiled", step=step)
        e = energy_balance(r, rig)
        released.append(np.max(e["spring_energy_released"]))
        residual.append(np.max(np.abs(e["residual"])))
    assert released[0] == pytest.approx(1372.4, abs=1.0)
    assert residual[0] < 0.02 * released[0]
    assert residual[1] < residual[0] / 2.5


@needs_compiler
def test_energy_split_at_touch_and_at_rest(rig):
    """At the first touch the cam holds most of what the springs gave up; at rest (the end of the
    run) the stop's damper has taken most of it (measured 870 J), the latch's 104 J, the shaft
    friction 123 J; the cam, follower and poles hold nothing (the lumped chain's undamped surge
    keeps 7.9 J)."""
    r = simulate(rig, t_end=T_END, backend="compiled")
    s = energy_splits(r, rig)
    touch, end = s["first_touch"], s["end"]
    assert touch["kinetic_cam"] > 0.8 * touch["released"] and touch["dissipated_end_stop"] == 0.0
    assert s["at_rest"] and s["kinetic_J"] < 1e-3 and s["coils_kinetic_J"] == pytest.approx(7.9, abs=0.5)
    assert end["dissipated_end_stop"] == pytest.approx(870.0, abs=10.0)
    assert end["dissipated_hold_latch"] == pytest.approx(104.0, abs=5.0)
    assert end["dissipated_end_stop"] > 0.7 * end["released"]
    for sp in (touch, end):
        assert abs(sp["unaccounted"]) < 0.02 * sp["released"]  # measured 1.3 % at rest (see the balance)
        assert sum(sp[k] for k, _ in SPLIT_TERMS) == pytest.approx(sp["released"] + sp["latch_work"] - sp["unaccounted"])


@needs_compiler
def test_figures_of_merit_are_the_analysers(rig):
    """The closing's overtravel, rebound and wipe are the analysers' (records.analyser) of the
    follower's travel; with the stop they come from the dynamics (measured 0.459 mm overtravel,
    0.057 mm rebound, 2.54 mm wipe, settled at 49 ms)."""
    r = simulate(rig, t_end=T_END, backend="compiled")
    f = figures_of_merit(r, rig)
    a = analyser_figures(r.t, [], r.measured, zone=0.004)
    for key in ("overtravel_m", "rebound_m", "travel_settled_s"):
        assert f[key] == a[key], key
    assert f["overtravel_m"] == pytest.approx(0.459e-3, abs=0.01e-3)
    assert f["rebound_m"] == pytest.approx(0.057e-3, abs=0.01e-3)
    assert f["wipe_m"] == pytest.approx(2.54e-3, abs=0.02e-3)
    assert 0.04 < f["travel_settled_s"] < T_END - 0.005


def test_check_says_whether_the_stop_and_latch_are_modelled(tmp_path, capsys):
    """The model choice is explicit: `vcbmodel check` names both parts, or says they are not modelled."""
    from vcbmodel.app.cli import main

    for rig_dict, expected in ((stopped(), ("end stop: at cam angle 3.66519 rad (210.0 deg)",
                                            "holding latch: at cam angle 3.57792 rad (205.0 deg)")),
                               (P.FORMER_REFERENCE_BREAKER, ("end stop: not modelled (no breaker.end_stop section)",
                                                      "holding latch: not modelled (no breaker.hold_latch section)"))):
        assert main(["check", str(write_rig(tmp_path, rig_dict, "checked"))]) == 0
        out = capsys.readouterr().out
        for line in expected:
            assert line in out, out


@needs_compiler
def test_simulate_summary_says_when_the_cam_meets_the_stop_and_where_it_rests(rig, tmp_path):
    """The summary's stop lines read the cam angle: the stop is met when the cam first passes its
    angle, the latch engages when the cam first passes the latch's (before the stop's), and at the
    end the cam rests on the latch (205 deg); a rig without them has no such lines."""
    from vcbmodel.experiments.summaries import closing_summary

    r = simulate(rig, t_end=T_END, backend="compiled")
    lines = {what: value for what, value, _ in closing_summary(r, rig)}
    theta = r.channels["cam_angle"]
    step = float(r.t[1] - r.t[0])
    assert lines["cam meets the end stop at"] == pytest.approx(r.t[np.argmax(theta > END_STOP["angle"])], abs=step)
    assert lines["holding latch engaged at"] < lines["cam meets the end stop at"]
    into = END_STOP["arm"] * (theta.max() - END_STOP["angle"])
    assert lines["cam's travel into the end stop (at its arm)"] == pytest.approx(into, rel=1e-6)
    assert lines["cam angle at the end of the run"] == pytest.approx(205.0, abs=0.05)
    plain = load_rig(write_rig(tmp_path, P.FORMER_REFERENCE_BREAKER, "plain"))
    short = simulate(plain, t_end=0.005, backend="compiled")
    names = {what for what, _, _ in closing_summary(short, plain)}
    assert not names & {"cam meets the end stop at", "holding latch engaged at", "cam angle at the end of the run"}

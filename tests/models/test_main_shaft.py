"""The main shaft's twist (rig section ``breaker.main_shaft``; laws in vcbmodel.laws.breaker):
pole levers on an elastic shaft, each pole's push rod on its own lever.

The test breaker is the reference breaker (REFERENCE_BREAKER) with MAIN_SHAFT_SECTION
(parameters.py): a 40 mm solid steel shaft, levers 210 mm apart, driven at pole 1. Tolerances are
set from measured numbers (given in each test) with a margin."""
import copy
import math

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.app.cli import main
from vcbmodel.compiled import compiler_works
from vcbmodel.compiled.equations import prepare_closing
from vcbmodel.experiments.closing_evaluation import (SPLIT_TERMS, energy_balance, energy_splits, figures_of_merit,
                                                     lever_channels, main_shaft_twist)
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import model_spec, simulate
from vcbmodel.laws.breaker import BreakerLaws, segment_stiffness, segment_torque, torsional_frequencies
from vcbmodel.laws.friction import ArrayOps, NumericOps
from vcbmodel.laws.mechanics import main_shaft_twist as static_twist, shaft_torsional_stiffness

from conftest import write_rig

needs_compiler = pytest.mark.skipif(not compiler_works(), reason="no working C compiler")


#: The test shaft: the review's 40 mm estimate with its lever inertia and 2 % damping (the measured
#: numbers in the docstrings below are on it); the reference breaker's own shaft (parameters.py) is
#: checked in test_reference_section_numbers_are_as_documented
SHAFT_40 = {"pole_pitch": 0.21, "diameter": 0.04, "bore": 0.0, "shear_modulus": 79.3e9, "damping": 2.6,
            "lever_inertia": 0.0075, "drive_pole": 1}


def with_shaft(**changes):
    d = copy.deepcopy(P.REFERENCE_BREAKER)
    d["breaker"]["main_shaft"] = dict(SHAFT_40, **changes)
    return d


#: The reference breaker on a rigid main shaft (its section removed)
RIGID = copy.deepcopy(P.REFERENCE_BREAKER)
RIGID["breaker"].pop("main_shaft", None)


@pytest.fixture(scope="module")
def rigs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("shaft")
    return {"elastic": load_rig(write_rig(folder, with_shaft(), "elastic")),
            "rigid": load_rig(write_rig(folder, RIGID, "rigid"))}


# --- the laws -----------------------------------------------------------------------------------

def test_segment_torque_and_stiffness(tmp_path):
    """T = k (a_j - a_{j+1}) + c (a_j' - a_{j+1}'); k = G J / pitch."""
    assert segment_torque(0.01, 0.004, 2.0, 1.0, 1e5, 3.0) == pytest.approx(1e5 * 0.006 + 3.0)
    a = np.linspace(-0.01, 0.01, 5)
    assert np.array_equal(segment_torque(a, 0.0, a, 0.0, 1e5, 3.0, ArrayOps), 1e5 * a + 3.0 * a)
    rig = load_rig(write_rig(tmp_path, with_shaft(bore=0.02), "bored"))
    shaft = rig.breaker.main_shaft
    assert segment_stiffness(shaft) == pytest.approx(79.3e9 * math.pi * (0.04**4 - 0.02**4) / 32 / 0.21)


def test_rigid_shaft_is_todays_follower(rigs):
    """Without the section: no lever coordinates, every rod on the follower, and the levers' torque
    is the follower's torque exactly (the same operations: the numbers are bitwise today's)."""
    rig = rigs["rigid"]
    laws = BreakerLaws.of_rig(rig, model_spec(rig))
    assert laws.free_levers == () and laws.follower_inertia == rig.breaker.follower.inertia
    rng = np.random.default_rng(3)
    for _ in range(20):
        theta, omega, phi, phid = rng.uniform(0.2, 3.0), rng.uniform(0, 50), rng.uniform(-0.01, 0.1), rng.uniform(0, 10)
        z, zd = list(rng.uniform(0, 0.012, 3)), list(rng.uniform(0, 1.5, 3))
        t_fol, levers, cam = laws.lever_torques(theta, omega, phi, phid, [], [], z, zd, 0.1)
        assert levers == [] and (t_fol, cam) == laws.follower_torque(theta, omega, phi, phid, z, zd, 0.1)
    setup = prepare_closing(rig, model_spec(rig), None)
    assert not any("lever" in name for name, _, _ in setup.layout)
    assert setup.info["initial"].lever_angles == []
    assert lever_channels(laws, {"follower_angle": 1.0, "follower_velocity": 2.0}) == ([1.0] * 3, [2.0] * 3)


def test_rest_levers_balance(rigs):
    """At the latched start every lever is in torque balance; the levers twist under the rods' rest
    forces (bellows minus weight, 135 N each, pulling the levers towards closing) as the static
    formula (laws.mechanics.main_shaft_twist) says."""
    rig = rigs["elastic"]
    laws = BreakerLaws.of_rig(rig, model_spec(rig))
    setup = prepare_closing(rig, model_spec(rig), None)
    rest = setup.info["initial"]
    phi, psi = rest.follower_angle, rest.lever_angles
    assert len(psi) == 2
    _, torques, _ = laws.rest_torques(rig.cam.initial_angle, phi, psi)
    assert max(abs(t) for t in torques) < 1e-9
    a = laws.lever_angles(phi, psi)
    rods = [laws.rod_loads(a[j], 0.0, rest.pole_travel[j], 0.0)[1] for j in range(3)]
    s = rig.breaker.main_shaft
    expected = static_twist(rods, s.pole_pitch, s.diameter, s.shear_modulus, s.bore)
    assert [x - phi for x in a] == pytest.approx(expected, abs=1e-12)
    assert expected[2] > 4e-4  # rad: 2 x 21.6 N m / 94.9 kN m/rad + 21.6 / 94.9e3


# --- the rig ------------------------------------------------------------------------------------

BAD_SHAFTS = [({"bore": 0.04}, "breaker.main_shaft.bore"), ({"drive_pole": 4}, "breaker.main_shaft.drive_pole"),
              ({"drive_pole": 1.5}, "breaker.main_shaft.drive_pole"), ({"damping": -1.0}, "breaker.main_shaft.damping"),
              ({"lever_inertia": 0.04}, "breaker.main_shaft.lever_inertia"),
              ({"shear_modulus": 0.0}, "breaker.main_shaft.shear_modulus"),
              ({"pitch": 0.2}, "breaker.main_shaft.pitch"), (None, "breaker.main_shaft.diameter")]


@pytest.mark.parametrize("change,field", BAD_SHAFTS, ids=[f for _, f in BAD_SHAFTS])
def test_bad_main_shaft_is_refused(change, field, tmp_path, capsys):
    """One line naming the file and the field, exit 2, nothing written; every field required."""
    d = with_shaft(**(change or {}))
    if change is None:
        del d["breaker"]["main_shaft"]["diameter"]
    rig = write_rig(tmp_path, d, "bad_shaft")
    out_dir = tmp_path / "out"
    out_dir.mkdir()
    assert main(["simulate", str(rig), "-o", str(out_dir / "out.csv")]) == 2
    out, err = capsys.readouterr()
    lines = err.strip().splitlines()
    assert len(lines) == 1 and rig.name in lines[0] and field in lines[0], err
    assert "Traceback" not in err and out == "" and list(out_dir.iterdir()) == []


def test_check_prints_the_shaft_or_says_rigid(tmp_path, capsys):
    """`vcbmodel check` gives the segment stiffness and the first torsional frequency (141 Hz: two
    levers of 0.0075 + 1.5 x 0.16^2 kg m^2 on 94.9 kN m/rad segments, the drive held), or says rigid."""
    assert main(["check", str(write_rig(tmp_path, with_shaft(), "elastic"))]) == 0
    out = capsys.readouterr().out
    k = shaft_torsional_stiffness(0.04, 79.3e9) / 0.21
    assert f"segment stiffness {k:.4g} N m/rad" in out, out
    inertia = 0.0075 + 1.5 * 0.16**2
    first = math.sqrt(k / inertia * (3 - math.sqrt(5)) / 2) / (2 * math.pi)  # the two-mass chain, one end held
    assert f"first torsional frequency about {first:.0f} Hz" in out, out
    assert main(["check", str(write_rig(tmp_path, RIGID, "rigid"))]) == 0
    assert "main shaft: rigid, not modelled" in capsys.readouterr().out


def test_reference_section_numbers_are_as_documented(tmp_path):
    """parameters.py's choice: the segment damping is 2 % of critical for a lever with its pole's
    mass; the fastest new mode (a free lever between its stiff rod and two segments) gets more than
    50 steps per period at BREAKER_STEP."""
    b = load_rig(write_rig(tmp_path, P.REFERENCE_BREAKER, "reference")).breaker
    s, k = b.main_shaft, segment_stiffness(b.main_shaft)
    inertia = s.lever_inertia + b.poles.moving_mass * b.follower.output_arm**2
    assert s.damping / (2 * math.sqrt(k * inertia)) == pytest.approx(0.02, rel=0.02)
    lever_mode = math.sqrt((b.poles.rod_stiffness * b.follower.output_arm**2 + 2 * k) / s.lever_inertia)
    assert 2 * math.pi / lever_mode / P.BREAKER_STEP > 50
    assert torsional_frequencies(s, b.poles, b.follower.output_arm)[-1] < 1000.0
    assert P.REFERENCE_BREAKER["breaker"]["main_shaft"] == P.MAIN_SHAFT_SECTION
    assert "main_shaft" not in P.FORMER_REFERENCE_BREAKER["breaker"]


# --- the backends -------------------------------------------------------------------------------

@needs_compiler
def test_compiled_agrees_with_exudyn_with_the_twist(rigs):
    """The levers in both backends (Exudyn: rotational masses and coordinate spring-dampers; compiled:
    the traced laws): measured 5e-16 rad on the levers, 9e-14 rad on the cam, 2e-9 N on the rods."""
    rig = rigs["elastic"]
    a, b = simulate(rig, backend="exudyn"), simulate(rig, backend="compiled")
    for name in ("cam_angle", "follower_angle", "pole_2_lever_angle", "pole_3_lever_angle"):
        assert np.max(np.abs(a.channels[name] - b.channels[name])) < 1e-9, name
    for i in (1, 2, 3):
        assert np.max(np.abs(a.channels[f"pole_{i}_travel"] - b.channels[f"pole_{i}_travel"])) < 1e-9
    assert np.max(np.abs(a.channels["pole_3_rod_force"] - b.channels["pole_3_rod_force"])) < 1e-5


@needs_compiler
def test_a_very_stiff_shaft_is_the_rigid_model(tmp_path, rigs):
    """100 x the shear modulus (the same damping ratio: 10 x the damping): the twist before touch is a
    hundredth (measured 1.7e-5 rad) and the poles move as on the rigid shaft: touch times within 3.3 us
    (measured), travels within 9.6 um (the elastic shaft's 614 um); so the difference is the twist."""
    s = SHAFT_40
    stiff = load_rig(write_rig(tmp_path, with_shaft(shear_modulus=100 * s["shear_modulus"], damping=10 * s["damping"]),
                               "stiff"))
    runs = {name: simulate(rig, backend="compiled") for name, rig in (("stiff", stiff), ("rigid", rigs["rigid"]),
                                                                        ("elastic", rigs["elastic"]))}
    touches = {name: figures_of_merit(r, rigs["rigid"])["per_pole"]["touch_s"] for name, r in runs.items()}
    assert touches["stiff"] == pytest.approx(touches["rigid"], abs=6e-6)
    assert max(abs(a - b) for a, b in zip(touches["elastic"], touches["rigid"])) > 1e-4  # the twist matters

    def travel_difference(name):
        return max(np.max(np.abs(runs[name].channels[f"pole_{i}_travel"] - runs["rigid"].channels[f"pole_{i}_travel"]))
                   for i in (1, 2, 3))

    assert travel_difference("stiff") < 2e-5
    assert travel_difference("stiff") < 0.05 * travel_difference("elastic")
    assert main_shaft_twist(runs["stiff"], stiff)["before_touch_rad"] < 0.02 * main_shaft_twist(
        runs["elastic"], rigs["elastic"])["before_touch_rad"]


@needs_compiler
def test_closed_rest_twist_is_the_static_formula(rigs):
    """Cam on its holding latch, contacts closed (BREAKER_REST_T_END): the levers rest (measured
    2e-6 rad/s) twisted by the rods' torques as laws.mechanics.main_shaft_twist (the shaft driven at
    pole 1) gives them from those torques: measured 15 mrad at pole 3 (2.4 mm at the pole), agreeing
    to 3e-12 rad. An independent formula: the sum of the torques beyond each segment over G J / pitch."""
    rig = rigs["elastic"]
    r = simulate(rig, backend="compiled", t_end=P.BREAKER_REST_T_END)
    laws = BreakerLaws.of_rig(rig, r.spec)
    a, a_dot = lever_channels(laws, r.channels)
    ch = r.channels
    assert max(abs(x[-1]) for x in a_dot) < 1e-4
    assert all(ch[f"pole_{i}_travel"][-1] > g for i, g in zip((1, 2, 3), laws.gaps))
    rods = [laws.rod_loads(a[j][-1], a_dot[j][-1], ch[f"pole_{j + 1}_travel"][-1], ch[f"pole_{j + 1}_velocity"][-1],
                           NumericOps)[1] for j in range(3)]
    s = rig.breaker.main_shaft
    expected = static_twist(rods, s.pole_pitch, s.diameter, s.shear_modulus, s.bore)
    twist = [x[-1] - a[0][-1] for x in a]
    assert twist == pytest.approx(expected, abs=1e-8)
    assert abs(twist[2]) > 0.01
    summary = main_shaft_twist(r, rig)
    assert summary["end_rad"] == pytest.approx(abs(twist[2]), rel=1e-12)
    assert summary["end_m"] == pytest.approx(abs(twist[2]) * rig.breaker.follower.output_arm, rel=1e-12)


@needs_compiler
def test_energy_balance_closes_with_the_twist(rigs):
    """The levers' kinetic energy, the twist's elastic energy and the segments' damping in the balance:
    residual measured 0.036 J of 354 J released to the rest (the rigid shaft's: 0.30 J); without the
    shaft's terms the balance would miss the 1.3 J (twist, closed) and what the levers carry."""
    rig = rigs["elastic"]
    r = simulate(rig, backend="compiled", t_end=P.BREAKER_REST_T_END)
    e = energy_balance(r, rig)
    released = np.max(e["spring_energy_released"])
    assert np.max(np.abs(e["residual"])) < 1e-3 * released
    s = energy_splits(r, rig)
    end, touch = s["end"], s["first_touch"]
    k = segment_stiffness(rig.breaker.main_shaft)
    a, _ = lever_channels(BreakerLaws.of_rig(rig, r.spec), r.channels)
    closed = sum(0.5 * k * (a[j][-1] - a[j + 1][-1]) ** 2 for j in range(2))
    start = sum(0.5 * k * (a[j][0] - a[j + 1][0]) ** 2 for j in range(2))
    assert end["main_shaft"] == pytest.approx(closed - start, rel=1e-9) and closed > 1.0
    assert touch["kinetic_levers"] > 0.1 and end["dissipated_main_shaft"] > 0.0
    for sp in (touch, end):
        assert sum(sp[k] for k, _ in SPLIT_TERMS) == pytest.approx(sp["released"] + sp["latch_work"] - sp["unaccounted"])
        assert abs(sp["unaccounted"]) < 1e-3 * sp["released"]


@needs_compiler
def test_summary_reports_the_twist_only_with_the_section(rigs):
    from vcbmodel.experiments.summaries import closing_summary

    r = simulate(rigs["elastic"], backend="compiled")
    lines = {what: value for what, value, _ in closing_summary(r, rigs["elastic"])}
    before = lines["main shaft twist, before first touch"]
    assert 1e-3 < before < lines["main shaft twist, largest"]
    assert lines["  as pole travel, before first touch"] == pytest.approx(before * 0.16)
    plain = simulate(rigs["rigid"], backend="compiled", t_end=0.005)
    assert not any("main shaft" in what for what, _, _ in closing_summary(plain, rigs["rigid"]))

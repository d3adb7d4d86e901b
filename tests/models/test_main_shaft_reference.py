"""The independent breaker reference's elastic main shaft (vcbmodel/reference/breaker_shaft.py).

The shaft's section is put on the loaded reference breaker by hand (:func:`with_shaft`: a
``breaker.main_shaft`` with the attributes the rig reader gives), so these tests need nothing of
the model's twist. The shaft is the reference breaker's (40 mm solid steel, G 79.3 GPa, levers
0.21 m apart, driven at pole 1; parameters.MAIN_SHAFT); the lever inertia and segment damping are
this test's own (0.01 kg m^2, a 0.16 m lever of about 1 kg; 2 N m s/rad, about 3 % of a segment's
critical damping), not a design. Tolerances are set from measured numbers (given in each test)
with a margin."""
import copy
import dataclasses
import json
from types import SimpleNamespace

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.experiments.closing_evaluation import figures_of_merit
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import model_spec, simulate
from vcbmodel.laws.mechanics import main_shaft_twist
from vcbmodel.reference.breaker import solve_closing
from vcbmodel.reference.breaker_closing import Closing
from vcbmodel.reference.breaker_integration import rhs

T_END = 0.041  # s: the reference breaker's poles touch at 38.6-39.1 ms
SHAFT = {"pole_pitch": P.MAIN_SHAFT["pole_pitch"], "diameter": 0.04, "bore": 0.0,
         "shear_modulus": P.MAIN_SHAFT["shear_modulus"], "damping": 2.0, "lever_inertia": 0.01, "drive_pole": 1}


def with_shaft(rig, shaft=None, **poles):
    """The rig with ``breaker.main_shaft`` set to ``shaft`` (a dict; None: the rigid shaft) and the
    poles' fields in ``poles`` changed."""
    b = rig.breaker
    parts = {f.name: getattr(b, f.name) for f in dataclasses.fields(b)}
    if poles:
        parts["poles"] = dataclasses.replace(b.poles, **poles)
    parts["main_shaft"] = None if shaft is None else SimpleNamespace(**shaft)
    return dataclasses.replace(rig, sections=dict(rig.sections, breaker=SimpleNamespace(**parts)))


@pytest.fixture(scope="module")
def rig(tmp_path_factory):
    """The reference breaker with a rigid shaft (its own section, once it has one, taken off)."""
    d = copy.deepcopy(P.REFERENCE_BREAKER)
    d["breaker"].pop("main_shaft", None)
    path = tmp_path_factory.mktemp("shaft") / "breaker.rig.json"
    path.write_text(json.dumps(d))
    return load_rig(path)


@pytest.fixture(scope="module")
def spec(rig):
    return model_spec(rig, spring_model="massless")


@pytest.fixture(scope="module")
def times():
    return np.arange(0.0, T_END + 1e-9, 1e-4)


@pytest.fixture(scope="module")
def rigid(rig, spec, times):
    return solve_closing(rig, spec, times)


def twisted(rig, spec, times, scale=1.0):
    """The closing with the shaft's shear modulus times ``scale``."""
    shaft = dict(SHAFT, shear_modulus=SHAFT["shear_modulus"] * scale)
    return solve_closing(with_shaft(rig, shaft), spec, times)


def test_without_the_section_the_reference_is_the_rigid_one(rig, spec, times, rigid):
    """No section, or a section on a one-pole breaker (no segment, the follower keeps its whole
    inertia): the rigid solve to the last bit, with no lever channels."""
    none = solve_closing(with_shaft(rig, None), spec, times)
    assert none.keys() == rigid.keys() and not any("lever" in name for name in rigid)
    for name, value in rigid.items():
        if isinstance(value, np.ndarray):
            assert np.array_equal(none[name], value), name
    one = {"count": 1, "gap_offsets": (0.0,)}
    a = solve_closing(with_shaft(rig, None, **one), spec, times)
    b = solve_closing(with_shaft(rig, dict(SHAFT, lever_inertia=0.07), **one), spec, times)
    for name in ("cam_angle", "follower_angle", "pole_1_travel", "cam_roller_force"):
        assert np.array_equal(a[name], b[name]), name
    assert a["touch_times"] == b["touch_times"]


@pytest.mark.parametrize("drive", [1, 2, 3])
def test_rest_balances_every_lever_and_twists_as_the_static_shaft(rig, spec, drive):
    """At the latch's rest every lever's and the follower's acceleration vanishes (to round-off of
    the rods' 2e7 N/m springs), and the levers' twist against the drive lever is the static
    shaft's under the rods' rest torques (laws.mechanics.main_shaft_twist for the drive at pole 1;
    a drive in the middle twists both ends by one pole's torque over k). Measured: 4.6e-4 and
    6.8e-4 rad at poles 2 and 3 when driven at pole 1."""
    mech = Closing(with_shaft(rig, dict(SHAFT, drive_pole=drive)), spec)
    phi, z, holding, levers = mech.rest()
    y = mech.initial_vector(phi, z, levers)
    dy = rhs(mech, ("stuck",))(0.0, y)
    lever_acc, follower_acc = dy[mech.lev + mech.nl:], dy[2 + 4 * mech.nm + 1 + mech.n]
    assert np.max(np.abs(lever_acc)) < 1e-4 and abs(follower_acc) < 1e-4  # rad/s^2 of 2e3 per rod torque
    a = mech.shaft.angles(phi, levers)
    torques = [mech.rod(x, 0.0, zi, 0.0)[1] for x, zi in zip(a, z)]
    k = mech.shaft.k
    if drive == 1:
        expected = main_shaft_twist(torques, SHAFT["pole_pitch"], SHAFT["diameter"], SHAFT["shear_modulus"])
    elif drive == 2:
        expected = [torques[0] / k, 0.0, torques[2] / k]
    else:
        expected = [(torques[0] + (torques[0] + torques[1])) / k, (torques[0] + torques[1]) / k, 0.0]
    assert np.allclose(np.array(a) - phi, expected, rtol=1e-9, atol=1e-13)
    assert min(abs(x) for i, x in enumerate(expected) if i != drive - 1) > 1e-4  # rad: a twist to see


@pytest.mark.slow  # a convergence sweep (what the slow marker is for)
def test_a_stiff_shaft_tends_to_the_rigid_one(rig, spec, times, rigid):
    """The difference to the rigid shaft falls as 1/k: measured at the real shaft / 100 / 1000 times
    its stiffness (massless springs), touches moved by 245 / 2.4 / 0.28 us (poles 2 and 3 earlier:
    their levers lead under the poles' inertia in the rise's deceleration), pole travel by
    735 / 11 / 1.1 um, the far lever's twist 15.9 / 0.20 / 0.018 mrad."""
    def difference(run):
        touch = np.max(np.abs(np.array(run["touch_times"]) - np.array(rigid["touch_times"])))
        travel = max(np.max(np.abs(run[f"pole_{i}_travel"] - rigid[f"pole_{i}_travel"])) for i in (1, 2, 3))
        return touch, travel, np.max(np.abs(run["pole_3_lever_angle"] - run["follower_angle"]))

    real, stiff, stiffer = (difference(twisted(rig, spec, times, s)) for s in (1.0, 100.0, 1000.0))
    assert real[0] > 1e-4 and real[1] > 3e-4 and real[2] > 1e-2  # the twist matters (s, m, rad)
    for a, b in zip(stiff, stiffer):
        assert b < a / 5
    assert stiff[0] < real[0] / 30


def test_a_shaft_whose_levers_leave_the_follower_no_inertia_is_refused(rig, spec):
    with pytest.raises(ValueError, match="lever_inertia"):
        Closing(with_shaft(rig, dict(SHAFT, lever_inertia=rig.breaker.follower.inertia / 2)), spec)
    with pytest.raises(ValueError, match="drive_pole"):
        Closing(with_shaft(rig, dict(SHAFT, drive_pole=4)), spec)


# --- against the model's twist (vcbmodel.laws.breaker, builders/breaker.py) -------------------------

def elastic(folder, drive: int = 1):
    """The reference breaker with the review's 40 mm main shaft (the softer shaft of the first estimate:
    its lever inertia 0.0075 kg m^2 and 2 % damping 2.6 N m s/rad) driven at pole ``drive``, read by the
    rig reader."""
    d = copy.deepcopy(P.REFERENCE_BREAKER)
    d["breaker"]["main_shaft"] = dict(P.MAIN_SHAFT_SECTION, diameter=0.04, lever_inertia=0.0075, damping=2.6, drive_pole=drive)
    path = folder / f"drive{drive}.rig.json"
    path.write_text(json.dumps(d))
    return load_rig(path)


def against_model(rig, step: float = P.BREAKER_STEP) -> dict:
    """The model (massless springs, the literal stick band, RK4 at ``step``) and the independent
    solve at 1e-4 s: the largest differences of the touch times (s), pole travels (m), free levers'
    angles (rad) and speeds (rad/s), and of the levers' rest angles (rad)."""
    effects = [e for e in rig.model.effects if e != "spring_mass"]
    a = simulate(rig, effects, spring_model="massless", t_end=T_END, sticking="literal", step=step)
    every = int(round(1e-4 / step))
    ref = solve_closing(rig, model_spec(rig, effects, spring_model="massless"), a.t[::every])
    touch = np.array(figures_of_merit(a, rig)["per_pole"]["touch_s"]) - np.array(ref["touch_times"])
    free = [name[:-len("_angle")] for name in ref if name.endswith("_lever_angle")]
    assert sorted(free) == sorted(n[:-len("_angle")] for n in a.channels if n.endswith("_lever_angle"))

    def most(names):
        return max(float(np.max(np.abs(a.channels[n][::every] - ref[n]))) for n in names)
    return {"touch": float(np.max(np.abs(touch))), "travel": most(f"pole_{i + 1}_travel" for i in range(3)),
            "lever": most(f"{n}_angle" for n in free), "lever_velocity": most(f"{n}_velocity" for n in free),
            "rest": max(abs(a.channels[f"{n}_angle"][0] - ref[f"{n}_angle"][0]) for n in free)}


@pytest.mark.parametrize("drive", [1, 2])
def test_the_model_twists_as_the_independent_solve(tmp_path, drive):
    """The model's levers (Exudyn rotational masses, the laws' segment torque, the model's own rest)
    against the reference's (written again, its own static rest, DOP853 at 1e-10), driven at pole 1
    and in the middle. Measured at the 1e-5 s step (drive 1 / 2): touch times 30 / 26 ns apart (the
    model's first-order roller penetration, as on the rigid shaft), pole travel 0.96 / 2.0 um, lever
    angles 3.9 / 4.2e-6 rad (0.7 um at the lever's 0.16 m), lever speeds 0.014 / 0.027 rad/s, rest
    angles 4e-15 / 2e-15 rad."""
    d = against_model(elastic(tmp_path, drive))
    assert d["touch"] < 6e-8
    assert d["travel"] < 4e-6
    assert d["lever"] < 8e-6
    assert d["lever_velocity"] < 0.05
    assert d["rest"] < 1e-12


@pytest.mark.slow
def test_the_levers_difference_shrinks_with_the_step(tmp_path):
    """The lever angles' difference is first order in the model's step (it takes a contact's
    Lankarani-Nikravesh impact speed from the start of its RK4 step): measured 3.9, 1.9 and
    0.94e-6 rad at 1e-5, 5e-6 and 2.5e-6 s, lever speeds 0.014 / 0.010 / 0.0043 rad/s; the touch
    times stay at 30 ns (the first-order penetration)."""
    rig = elastic(tmp_path)
    coarse = against_model(rig)
    fine = against_model(rig, P.BREAKER_STEP / 4)
    assert fine["lever"] < coarse["lever"] / 2.5
    assert fine["lever_velocity"] < coarse["lever_velocity"] / 2
    assert fine["touch"] < 6e-8

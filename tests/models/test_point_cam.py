"""A cam given by points (a CAD or CMM export of the pitch curve), fitted by a periodic spline,
checked (undercut, pressure angle) and refused when the roller cannot follow it."""
import copy
import math

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.compiled import compiler_works
from vcbmodel.errors import InputError
from vcbmodel.experiments import experiment_of
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import simulate
from vcbmodel.laws.cam_follower import pitch_radius

from conftest import write_rig

CLOSING = experiment_of("vcb_closing")


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    return load_rig(write_rig(tmp_path_factory.mktemp("ref"), P.REFERENCE_BREAKER, "ref"))


def point_rig(tmp_path, profile, name="points"):
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    data["breaker"]["cam_profile"] = profile
    return write_rig(tmp_path, data, name)


def sampled(reference, every_deg=1.0, lift=False):
    """The reference cam's pitch curve as points, as a drawing or CMM export would give it."""
    prof, rr = reference.breaker.profile, reference.breaker.roller_radius
    u = np.radians(np.arange(0.0, 360.0, every_deg))
    rho = [pitch_radius(a, prof, rr)[0] for a in u]
    if lift:
        return {"base_radius": prof.base_radius, "points": [[float(a), float(r - prof.base_radius - rr)] for a, r in zip(u, rho)]}
    return {"radius_points": [[float(a), float(r)] for a, r in zip(u, rho)]}


def test_points_of_the_reference_cam_give_its_closing(reference, tmp_path):
    rig = load_rig(point_rig(tmp_path, sampled(reference)))
    u = np.linspace(0, 2 * np.pi, 3001)
    rr = reference.breaker.roller_radius
    worst = max(abs(pitch_radius(a, rig.breaker.profile, rr)[0] - pitch_radius(a, reference.breaker.profile, rr)[0])
                for a in u)
    assert worst < 1e-7  # the spline through 1-degree points: within 0.1 um of the polynomial
    backend = "fast"
    a, b = simulate(reference, backend=backend), simulate(rig, backend=backend)
    fa, fb = CLOSING.figures_of_merit(a, reference), CLOSING.figures_of_merit(b, rig)
    assert fb["closing_time_s"] == pytest.approx(fa["closing_time_s"], abs=1e-7)
    assert fb["per_pole"]["touch_speed_m_s"] == pytest.approx(fa["per_pole"]["touch_speed_m_s"], abs=1e-5)
    assert np.max(np.abs(a.measured - b.measured)) < 1e-7


def test_lift_points_and_radius_points_are_the_same_cam(reference, tmp_path):
    a = load_rig(point_rig(tmp_path, sampled(reference, 2.0), "radius"))
    b = load_rig(point_rig(tmp_path, sampled(reference, 2.0, lift=True), "lift"))
    assert np.allclose(a.breaker.profile.table, b.breaker.profile.table, atol=1e-12)


@pytest.mark.skipif(not compiler_works(), reason="no working C compiler")
def test_point_cam_compiled_agrees_with_exudyn(reference, tmp_path):
    rig = load_rig(point_rig(tmp_path, sampled(reference, 3.0)))
    e, c = simulate(rig, backend="exudyn", t_end=0.036), simulate(rig, backend="compiled", t_end=0.036)
    assert np.max(np.abs(e.channels["cam_angle"] - c.channels["cam_angle"])) < 1e-9
    assert np.max(np.abs(e.measured - c.measured)) < 1e-9


def test_a_profile_the_roller_cannot_follow_is_refused(reference, tmp_path):
    profile = sampled(reference, 2.0)
    # a 1 mm ridge over 4 degrees near 150 deg: a fold far sharper than the 20 mm roller
    for item in profile["radius_points"]:
        if abs(math.degrees(item[0]) - 150.0) < 2.5:
            item[1] += 0.001
    with pytest.raises(InputError, match="cannot follow this profile.*undercut"):
        load_rig(point_rig(tmp_path, profile))


def test_a_steep_rise_is_refused_for_its_pressure_angle(tmp_path):
    """The whole 9.4 mm lift within 8 degrees: with a 2 mm roller the pitch curve is not undercut,
    but the follower would be driven at about 59 deg, past the 45 deg a roller follower can take."""
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    data["breaker"]["roller_radius"] = 0.002
    deg = np.arange(0.0, 360.0, 2.0)

    def smooth(z):
        z = np.clip(z, 0, 1)
        return z**3 * (10 - 15 * z + 6 * z * z)

    rho = 0.065 + 0.0094 * (smooth((deg - 60.0) / 8.0) - smooth((deg - 200.0) / 120.0))
    data["breaker"]["cam_profile"] = {"radius_points": [[float(a), float(r)] for a, r in zip(np.radians(deg), rho)]}
    with pytest.raises(InputError, match="pressure angle 5[0-9].[0-9] deg.*above 45 deg"):
        load_rig(write_rig(tmp_path, data, "steep"))
    # the same rise over 60 degrees is accepted
    rho = 0.065 + 0.0094 * (smooth((deg - 60.0) / 60.0) - smooth((deg - 200.0) / 120.0))
    data["breaker"]["cam_profile"] = {"radius_points": [[float(a), float(r)] for a, r in zip(np.radians(deg), rho)]}
    assert load_rig(write_rig(tmp_path, data, "gentle")).breaker.profile.table


@pytest.mark.parametrize("points, message", [
    ([[0.0, 0.07], [0.1, 0.07]], "at least 8"),
    ([[float(k), 0.07] for k in range(10)], "more than one turn.*in degrees"),  # degrees-like angles over 2 pi
    ([[0.1 * k, 0.07] for k in (0, 1, 2, 4, 3, 5, 6, 7)], r"4: angle 0.3 rad is below point 3's.*sort"),
])
def test_bad_points_are_refused_naming_the_field(tmp_path, points, message):
    with pytest.raises(InputError, match=f"breaker.cam_profile.radius_points.*{message}"):
        load_rig(point_rig(tmp_path, {"radius_points": points}))

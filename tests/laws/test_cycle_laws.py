"""The cycle's laws at fixed numbers and analytic limits: the making current and Holm's repulsion
(vcbmodel.laws.making_current), the trip latch, trip-free link, opening dashpot and open stop
(vcbmodel.laws.opening), the releases' coils (vcbmodel.laws.release)."""
import math
from dataclasses import replace

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.laws.friction import ArrayOps
from vcbmodel.laws.making_current import (MakingCurrent, MakingLaws, ac_peak, current_shape, holm_factor, pole_repulsion,
                                          update_touch_time)
from vcbmodel.laws.opening import (OpeningDashpot, TripLatch, dashpot_force, f_travel, link_factor, link_resets,
                                   open_stop_force, pawl_engagement, pawl_force, travel_rate, trip_holding)
from vcbmodel.laws.release import Release, coil_current, delay_scatter, release_delay
import vcbmodel.laws.release as release_module

MAKING = MakingCurrent(**P.REFERENCE_MAKING_CURRENT)
LATCH = TripLatch(travel=0.0145, stiffness=5e7, damping=5e3, release_time=0.002, reset_travel=0.002)
DASHPOT = OpeningDashpot(stroke=0.006, damping=6000.0, ramp=0.001, stop_stiffness=1e7, stop_damping=2e3)
RELEASE = Release(**dict(P.REFERENCE_CLOSING_RELEASE, voltage_range=(0.85, 1.1), resistance_range=(0.82, 1.08)))


# --- making current ------------------------------------------------------------------------------

def test_current_starts_at_zero_and_is_a_sine_without_offset():
    omega, tau = 2 * math.pi * 50, 0.045
    t = np.linspace(0.0, 0.04, 401)
    assert current_shape(0.0, omega, 1.0, tau) == pytest.approx(0.0, abs=1e-15)
    assert current_shape(-1e-3, omega, 1.0, tau) == 0.0  # before the making instant
    assert np.allclose(current_shape(t, omega, 0.0, tau, ArrayOps), np.sin(omega * t), atol=1e-15)
    # fully asymmetric: exp(-t/tau) - cos(w t), its first peak near half a cycle
    assert np.allclose(current_shape(t, omega, 1.0, tau, ArrayOps), np.exp(-t / tau) - np.cos(omega * t), atol=1e-15)


def test_the_rated_peak_is_the_iec_factor_times_the_ac_component():
    """IEC 62271-100: 2.5 x the rms breaking current at 50 Hz, tau 45 ms, i.e. 1.77 x the AC peak
    (2.5 / sqrt 2); the fully asymmetric first peak is 1.80 x (1 + exp(-0.01 / 0.045) = 1.80 at half a
    cycle, a little more just before it): within 2 %."""
    amplitude = ac_peak(MAKING)
    assert MAKING.peak / amplitude == pytest.approx(2.5 / math.sqrt(2), rel=0.02)
    laws = MakingLaws(MAKING)
    t = np.linspace(0, 0.02, 20001)
    assert np.max(np.abs(laws.current(t, ArrayOps))) == pytest.approx(MAKING.peak, rel=1e-6)


def test_holm_force_at_100_kA():
    """(mu0/4pi) I^2 ln(R/a) / n: 1e-7 x 1e10 x ln(25 / 1.06) = 3.16 kN on one spot, half on two."""
    assert holm_factor(MAKING) * 1e10 == pytest.approx(1e-7 * 1e10 * math.log(0.025 / 0.00106), rel=1e-12)
    assert holm_factor(MAKING) * 1e10 == pytest.approx(3161.0, rel=1e-3)
    assert holm_factor(replace(MAKING, spots=2.0)) == pytest.approx(holm_factor(MAKING) / 2, rel=1e-12)


def test_repulsion_only_after_the_touch_and_while_closed():
    laws = MakingLaws(MAKING)
    args = (laws.amplitude, laws.omega, laws.asymmetry, laws.time_constant, laws.factor)
    assert pole_repulsion(0.05, -1.0, 1e-5, *args) == 0.0  # never touched: no current
    assert pole_repulsion(0.05, 0.04, -1e-6, *args) == 0.0  # open (bouncing): an arc, no constriction
    f = pole_repulsion(0.05, 0.04, 1e-5, *args)
    assert f == pytest.approx(laws.factor * laws.current(0.01) ** 2, rel=1e-12) and f > 1000.0
    touch = -1.0
    for t, pen in ((0.01, -1e-6), (0.02, 1e-6), (0.03, -1e-6), (0.04, 1e-6)):
        touch = update_touch_time(touch, t, pen)
    assert touch == 0.02  # the first touch is kept


# --- trip latch, link, dashpot, stop ---------------------------------------------------------------

def test_pawl_holds_only_once_engaged_and_as_much_as_the_trip_leaves():
    assert pawl_force(0.014, 0.0, 0.0, 1.0, LATCH) == 0.0  # not engaged: F passes freely
    assert pawl_force(0.014, 0.0, 1.0, 1.0, LATCH) == pytest.approx(5e7 * 0.0005)
    assert pawl_force(0.014, 0.0, 1.0, 0.25, LATCH) == pytest.approx(0.25 * 5e7 * 0.0005)
    assert pawl_force(0.0146, -1.0, 1.0, 1.0, LATCH) == 0.0  # above the latch face
    assert pawl_force(0.0144, 10.0, 1.0, 1.0, LATCH) == 0.0  # leaving fast: clipped, never pulls
    engaged = 0.0
    for u in (0.010, 0.0145, 0.012):
        engaged = pawl_engagement(engaged, u, LATCH)
    assert engaged == 1.0 and pawl_engagement(0.0, 0.01449, LATCH) == 0.0


def test_trip_lets_go_linearly_and_the_link_resets():
    assert trip_holding(0.5, -1.0, 0.002) == 1.0  # no trip
    assert trip_holding(0.0105, 0.01, 0.002) == pytest.approx(0.75)
    assert trip_holding(0.009, 0.01, 0.002) == 1.0 and trip_holding(0.013, 0.01, 0.002) == 0.0
    assert link_factor(0.013, 0.01, 1.0, 0.002) == 1.0  # reset: whole again
    # reset needs the pawl gone, F near open and the roller clear of the cam
    assert link_resets(0.0, 0.013, 0.01, 0.001, -1e-4, LATCH) == 1.0
    assert link_resets(0.0, 0.011, 0.01, 0.001, -1e-4, LATCH) == 0.0
    assert link_resets(0.0, 0.013, 0.01, 0.003, -1e-4, LATCH) == 0.0
    assert link_resets(0.0, 0.013, 0.01, 0.001, 1e-4, LATCH) == 0.0  # the cam's lobe still under the roller
    assert link_resets(0.0, 0.013, -1.0, 0.001, -1e-4, LATCH) == 0.0  # no trip


def test_dashpot_damps_the_opening_only_and_starts_from_zero():
    assert dashpot_force(0.0061, -3.0, DASHPOT) == 0.0  # before the piston enters
    assert dashpot_force(0.0059, -3.0, DASHPOT) == pytest.approx(6000.0 * 0.1 * 3.0)  # 0.1 mm into the 1 mm ramp
    assert dashpot_force(0.006, -3.0, DASHPOT) == 0.0  # continuous at entry
    assert dashpot_force(0.002, -3.0, DASHPOT) == pytest.approx(18000.0)
    assert dashpot_force(0.002, 3.0, DASHPOT) == 0.0  # closing: the check valve lets it refill
    assert open_stop_force(0.0, -1.0, DASHPOT) == 0.0 and open_stop_force(1e-4, -1.0, DASHPOT) == 0.0
    assert open_stop_force(-1e-4, -1.0, DASHPOT) == pytest.approx(1e7 * 1e-4 + 2e3)
    assert open_stop_force(-1e-6, 5.0, DASHPOT) == 0.0  # never pulls


def test_travel_rate_is_the_derivative_of_the_travel():
    f = type("F", (), {"pivot": (0.27, 0.065), "output_arm": 0.16, "output_angle": 0.3})()
    for phi in (-0.2, 0.1, 0.6):
        h = 1e-7
        numeric = (f_travel(phi + h, f, 0.1) - f_travel(phi - h, f, 0.1)) / (2 * h)
        assert travel_rate(phi, f) == pytest.approx(numeric, rel=1e-7)


# --- releases ------------------------------------------------------------------------------------

def test_coil_current_rises_with_its_time_constant():
    tau = RELEASE.inductance / RELEASE.resistance
    final = RELEASE.voltage / RELEASE.resistance
    assert coil_current(-1e-3, 110.0, 48.0, 0.48) == 0.0
    assert coil_current(tau, 110.0, 48.0, 0.48) == pytest.approx(final * (1 - math.exp(-1)), rel=1e-12)


def test_release_delay_against_the_constant_pull_limit():
    """With a coil of negligible inductance the pull is k I^2 at once: x = a t^2 / 2, the delay
    sqrt(2 s m / (k I^2 - load)) (an analytic limit the RK4 integration must meet)."""
    fast = replace(RELEASE, inductance=1e-9)
    current = fast.voltage / fast.resistance
    a = (fast.force_constant * current**2 - fast.load) / fast.armature_mass
    assert release_delay(fast) == pytest.approx(math.sqrt(2 * fast.stroke / a), rel=1e-4)


def test_release_delay_converges_and_scatters_the_iec_way(monkeypatch):
    d = release_delay(RELEASE)
    monkeypatch.setattr(release_module, "RELEASE_STEP", release_module.RELEASE_STEP / 4)
    assert release_delay(RELEASE) == pytest.approx(d, abs=1e-6)
    monkeypatch.undo()
    s = delay_scatter(RELEASE)
    assert s["fastest"] < s["nominal"] < s["slowest"]  # high voltage and a cold coil are fastest
    weak = replace(RELEASE, load=RELEASE.force_constant * (RELEASE.voltage / RELEASE.resistance) ** 2 * 1.01)
    assert release_delay(weak) is None  # the pull never beats the load

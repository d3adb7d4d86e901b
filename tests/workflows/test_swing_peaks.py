"""A free swing's extremes read about the angle it turns about, whether or not it has stopped within
the record; a pendulum that is still swinging at the end of a run is not said to have stopped."""
import copy
import math

import numpy as np

from vcbmodel import parameters as P
from vcbmodel.app.cli import main
from vcbmodel.records.signals import first_peak_amplitude, swing_centre, swing_peaks, turning_points

from conftest import write_rig

PERIOD = 1.32


def decaying_swing(t_end, centre=0.02, amplitude=1.5, rate=0.02, sigma=5e-4, seed=1):
    """A viscous-like swing about ``centre`` released at ``amplitude`` (rad), sampled at 1 kHz with noise."""
    t = np.arange(0.0, t_end, 1e-3)
    clean = centre + amplitude * np.exp(-rate * t) * np.cos(2 * math.pi * t / PERIOD)
    return t, clean, clean + np.random.default_rng(seed).normal(0.0, sigma, t.size)


def test_a_swing_cut_off_mid_swing_is_read_about_its_centre():
    # ends 2.4 periods in, at -0.81 of an amplitude: the record's last 5 % lies far from the centre
    t, clean, y = decaying_swing(2.4 * PERIOD)
    assert abs(swing_centre(y, 5e-4) - 0.02) < 5e-3
    times, amps, values = swing_peaks(t, y, signed=True)
    expected = np.arange(times.size) * PERIOD / 2          # release, then every half period
    assert times.size == 5 and np.max(np.abs(times - expected)) < 0.01
    truth = 1.5 * np.exp(-0.02 * expected)
    assert np.max(np.abs(amps - truth)) < 5e-3
    assert np.allclose(np.sign(values - 0.02), [1, -1, 1, -1, 1])
    # the first extreme after the release: half a period in, on the other side
    assert abs(first_peak_amplitude(t, y) - 1.5 * math.exp(-0.02 * PERIOD / 2)) < 5e-3


def test_the_record_edge_is_no_peak():
    t, clean, y = decaying_swing(1.1 * PERIOD, sigma=0.0)
    times, _ = swing_peaks(t, y)
    assert times[-1] < t[-1] - 0.1 and np.allclose(times, [0.0, PERIOD / 2, PERIOD], atol=2e-3)


def test_a_stopped_swing_keeps_the_angle_it_stuck_at():
    # a swing that stops by 3 s and sits at 0.004 rad (inside a friction band) for the rest of the record
    t = np.arange(0.0, 6.0, 1e-3)
    amplitude = np.clip(0.17 - 0.055 * t, 0.0, None)
    y = np.where(t < 3.0, amplitude * np.cos(2 * math.pi * t / 0.93), 0.0) + 0.004 * (t >= 3.0)
    assert swing_centre(y, 1e-9) == 0.004
    times, amps, values = swing_peaks(t, y, signed=True)
    swing = (0.17 - 0.055 * times[:4]) * np.array([1, -1, 1, -1])
    assert np.allclose(values[:4], swing, atol=2e-3) and np.allclose(amps, np.abs(values - 0.004))


def test_turning_points_ignore_noise_below_the_reversal():
    t, clean, y = decaying_swing(3.0, sigma=2e-3)
    points = turning_points(y, 0.05)
    assert np.allclose(t[points], np.arange(points.size) * PERIOD / 2, atol=0.02)


def test_simulate_says_a_frictionless_pendulum_has_not_stopped(tmp_path, capsys):
    rig = copy.deepcopy(P.REFERENCE_PENDULUM)
    rig["pendulum"]["initial_angle"] = 1.5          # a large swing: no small-angle period
    path = write_rig(tmp_path, rig, "swing")
    out = tmp_path / "swing.csv"
    assert main(["simulate", str(path), "--effects", "", "--t-end", "3.3", "-o", str(out), "-q", "--backend", "fast"]) == 0
    text = capsys.readouterr().out
    rows = {line[:28].strip(): line[28:].split() for line in text.splitlines()[1:] if not line.strip().startswith("note")}
    assert rows["stops at"] == ["s", "-"] and "still swinging" in text
    # no friction: every extreme is the release angle, 85.94 deg
    assert abs(float(rows["first peak"][1]) - math.degrees(1.5)) < 0.02
    assert abs(float(rows["amplitude decay (linear)"][1])) < 1e-3


def test_the_diagnosis_signature_has_no_stop_time_for_a_swing_that_goes_on():
    """A swing still going at the end of its record has no stop time (was the record's end, 'stops at
    3.17 s'); one that sticks at 3 s has its stop within a swing of it."""
    from types import SimpleNamespace

    from vcbmodel.experiments.pendulum import signature

    t, clean, y = decaying_swing(2.4 * PERIOD)
    record = SimpleNamespace(t=t, channel=lambda name: y)
    sig = signature(None, record, clean, y - clean, 5e-4)
    assert sig["measured_stop_time_s"] is None and sig["model_stop_time_s"] is None
    t2 = np.arange(0.0, 6.0, 1e-3)
    stuck = np.where(t2 < 3.0, np.clip(0.17 - 0.055 * t2, 0.0, None) * np.cos(2 * math.pi * t2 / 0.93), 0.0)
    sig2 = signature(None, SimpleNamespace(t=t2, channel=lambda name: stuck), stuck, 0 * stuck, 1e-4)
    assert 2.5 < sig2["measured_stop_time_s"] < 3.8

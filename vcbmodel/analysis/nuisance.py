"""The record's nuisance: what ties a record to the model besides the physics.

A record is not the model's output. It starts before the release (a pre-trigger where the shaft
sits still) or while a hand still moves the pendulum; the rig's initial angle is nominal; the
sensor reads with a zero offset and a gain. The diagnosis estimates these with the physics
(they are parameters of every fit), unless the rig pins them in its ``record`` section:

    y(t) = offset + gain * model(t - release_time)      for t >= release_time
    y(t) = offset + gain * model(0)                    before it, when the record starts at rest

``initial_angle`` (the model's state at release) and rig values the rig marks ``uncertain`` need a
new simulation when they change; ``release_time``, ``offset`` and ``gain`` do not (the simulation is
shifted and scaled), so their derivatives are analytic and cost nothing.

This module decides, from the data alone, where the fit starts and the starting values:
:func:`record_setup`. A record that moves from its first sample (a hand-driven start) is fitted
from the free motion's first turning point, with the samples before it left out.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from scipy.optimize import nnls
from scipy.special import ellipk

from ..experiments import experiment_of
from ..rig.paths import loaded_value
from ..records.signals import complete_swing_extremes, motion_onset, swing_peaks

if TYPE_CHECKING:
    from ..rig.data import Rig

#: Prior standard deviation of the initial angle around the rig's nominal value (rad) where the
#: record cannot tell the angle from the sensor offset (cam drop): about a degree.
INITIAL_ANGLE_SD = math.radians(1.0)

#: Release-time search half-width (s) of a camera record found from the model's start of motion.
CAMERA_RELEASE_SPAN = 0.002

RECORD_FIELDS = ("release_time", "initial_angle", "sensor_offset", "sensor_gain")


@dataclass
class RecordSetup:
    """How one record is fitted: the window (record time, s), whether the record rests before
    the release, and starting values of the nuisance."""

    window: tuple
    still_start: bool
    release: float
    release_bounds: tuple
    offset: float
    gain: float
    initial_angle: float | None  # rad (None: the experiment has no initial-angle nuisance)
    initial_angle_prior: tuple | None  # (mean, sd) or None
    pinned: dict = field(default_factory=dict)
    hand_start: bool = False
    level: float = 0.0  # reading before the release
    notes: list = field(default_factory=list)
    channel_rest: dict = field(default_factory=dict)  # model value at rest of extra travel channels
    contact: dict = field(default_factory=dict)  # contact channel -> (gap in m, indicator width in m)

    def to_json(self) -> dict:
        return {"window": [float(self.window[0]), float(self.window[1])], "still_start": self.still_start,
                "hand_start": self.hand_start, "pinned": dict(self.pinned), "notes": list(self.notes)}


def initial_angle_field(experiment: str) -> str | None:
    return experiment_of(experiment).initial_angle_field


def _parabola_release(t, y, level, sigma, lo, hi):
    """Release time of a motion from rest: y = level before t_r, level + a (t - t_r)^2 + b (t - t_r)^3
    after (a constant jerk: the driving torque changes as the shaft turns), fitted on samples in
    [lo, hi] by a grid over t_r (a, b by linear least squares)."""
    sel = (t >= lo) & (t <= hi)
    tt, yy = t[sel], y[sel] - level
    if tt.size < 5:
        return float(lo)
    yy = yy * (1.0 if yy[-1] >= 0 else -1.0)  # departure upwards; a, b >= 0: a motion from rest
    grid = np.linspace(tt[0], tt[-1], min(400, 4 * tt.size))
    best = (math.inf, float(tt[0]))
    for tr in grid:
        tau = np.clip(tt - tr, 0.0, None)
        X = np.column_stack([tau**2, tau**3])
        if not np.any(tau > 0):
            continue
        scale = np.maximum(np.max(X, axis=0), 1e-300)
        coef, _ = nnls(X / scale, yy)
        cost = float(np.sum((yy - (X / scale) @ coef) ** 2))
        if cost < best[0]:
            best = (cost, float(tr))
    return best[1]


def _departure_end(t, y, level, i0, sigma, k=15.0):
    """Index where the departure from ``level`` after sample i0 first exceeds k sigma."""
    beyond = np.nonzero(np.abs(y[i0:] - level) > k * sigma)[0]
    return i0 + int(beyond[0]) if beyond.size else y.size - 1


def record_setup(rig, measurement, sigma) -> RecordSetup:
    """Window and starting values of the nuisance of one record (module docstring)."""
    rec = experiment_of(rig.experiment)
    t = np.asarray(measurement.t, float)
    y = np.asarray(measurement.channel(rec.measured_channel), float)
    pinned = {k: v for k, v in (getattr(rig, "record", None) or {}).items() if k in RECORD_FIELDS}
    gain = float(pinned.get("sensor_gain", 1.0))
    dt = float(np.median(np.diff(t)))
    sigma = max(float(sigma), 1e-12)
    field_name = rec.initial_angle_field
    nominal = loaded_value(rig, field_name) if field_name else None
    notes = []
    onset, level, still = motion_onset(t, y, sigma)
    hand = False
    if rec.free_swing:  # a swing may start by hand; its centre fixes the sensor offset
        p = rig.pendulum
        accel = p.mass * rig.gravity * p.com_distance * abs(math.sin(p.initial_angle)) / p.inertia
        window_start, release, level, hand = _pendulum_start(t, y, sigma, onset, level, still, notes, accel)
        offset = _swing_centre(t, y, release, sigma)
    else:
        window_start = float(t[0])
        j = _departure_end(t, y, level, onset, sigma)
        release = _parabola_release(t, y, level, sigma, float(t[0]), float(t[min(max(j, 3), t.size - 1)]))
        offset = None
    if "release_time" in pinned:
        release = float(pinned["release_time"])
        if rec.free_swing and hand:
            window_start = max(window_start, release)
    span = rec.release_span
    span = max(span, 5 * dt)
    bounds = (release - span, release + span)
    # the initial angle and the offset: the reading before release is offset + gain * angle
    if field_name is None:
        initial, prior = None, None
        offset = level if offset is None else offset
    elif "initial_angle" in pinned:
        initial, prior = float(pinned["initial_angle"]), None
        if offset is None:
            offset = level - gain * initial
    elif rec.free_swing:
        if "sensor_offset" in pinned:
            offset = float(pinned["sensor_offset"])
        initial = (level - offset) / gain
        prior = None  # the swing's centre and amplitude fix it
    else:
        initial = float(nominal)
        offset = level - gain * initial if "sensor_offset" not in pinned else float(pinned["sensor_offset"])
        prior = (float(nominal), INITIAL_ANGLE_SD)
    if "sensor_offset" in pinned:
        offset = float(pinned["sensor_offset"])
    window = (float(window_start), float(t[-1]))
    return RecordSetup(window, not hand, float(release), bounds, float(offset), gain, initial, prior, pinned, hand,
                       float(level), notes)


def _pendulum_start(t, y, sigma, onset, level, still, notes, accel):
    """(window start, release estimate, reading at release, hand start?) of a free swing.

    A pendulum released from rest first moves towards the swing's centre; a hand that brings it
    to the release angle moves it away from the centre (or the record starts while it does).
    So: if the first motion is towards the centre and the record is at rest before it, the
    record starts at rest (a pre-trigger, or none). Otherwise the release is the largest
    excursion before the swing first crosses its centre; if the pendulum was held still there,
    it was let go at the end of the hold."""
    n = y.size
    centre = float(np.median(y[n // 3:]))
    j = _departure_end(t, y, level, onset, sigma)
    towards = np.sign(centre - level) == np.sign(y[j] - level)
    if still and towards:
        release = _parabola_release(t, y, level, sigma, float(t[max(0, onset - 400)]), float(t[min(max(j, 3), t.size - 1)]))
        if release - t[0] > 5 * (t[1] - t[0]):
            notes.append(f"record starts at rest: pre-trigger of about {release - t[0]:.3g} s before the release")
        return float(t[0]), release, level, False
    # the largest excursion before the first crossing of the centre
    z = y - centre
    side = np.sign(z[min(j, n - 1)]) if z[min(j, n - 1)] != 0 else 1.0
    cross = np.nonzero(np.sign(z) == -side)[0]
    end = int(cross[0]) if cross.size else n
    i = int(np.argmax(np.abs(z[:max(end, 2)])))
    vk = float(np.median(y[max(0, i - 2):i + 3]))
    near = np.abs(y - vk) < 4 * sigma
    a = b = i
    while a > 0 and near[a - 1]:
        a -= 1
    while b < n - 1 and near[b + 1]:
        b += 1
    # how long a free turning point stays within 4 sigma (``accel``: the release's angular
    # acceleration by the rig); a longer still stretch is a hold
    natural = 2 * math.sqrt(2 * 4 * sigma / max(accel, 1e-9))
    if t[b] - t[a] > 2.5 * natural:  # held still: let go at the end of the hold
        level = float(np.median(y[a:b + 1]))
        jj = _departure_end(t, y, level, b, sigma)
        release = _parabola_release(t, y, level, sigma, float(t[a]), float(t[max(jj, a + 3)]))
        notes.append(f"record starts moving (hand-driven); held still from {t[a]:.3g} s, released at about "
                     f"{release:.3g} s; fitted from {t[a]:.3g} s")
        return float(t[a]), release, level, True
    tk = float(t[i])
    # the release: where the fall from the largest excursion begins (a quantised sensor holds
    # the top for several samples; the first of them is not the release)
    jj = _departure_end(t, y, vk, i, sigma)
    release = _parabola_release(t, y, vk, sigma, tk, float(t[max(jj, i + 3)]))
    notes.append(f"record starts moving (hand-driven); released at about {release:.3g} s, at the largest "
                 f"excursion; fitted from {tk:.3g} s")
    return tk, release, vk, True


def _first_regular_extreme(tp):
    """Index of the first extreme from which the half periods are regular (within 15 % of the
    median of the following ones), or None."""
    if tp.size < 3:
        return 0 if tp.size else None
    gaps = np.diff(tp)
    for k in range(gaps.size - 1):
        ref = np.median(gaps[k + 1:k + 6]) if gaps[k + 1:].size else gaps[k]
        if abs(gaps[k] - ref) <= 0.15 * ref:
            return k
    return 0


def _swing_centre(t, y, release, sigma):
    """The reading with the pendulum hanging straight down: the mean of the midpoints of an even
    number of successive half swings after the release (Coulomb friction shifts each half swing's
    centre by the same amount, alternately to either side)."""
    sel = t >= release
    tp, _, vals = swing_peaks(t[sel], y[sel], signed=True)
    if vals.size < 3:
        return float(np.median(y[sel][-max(10, sel.sum() // 20):]))
    mids = 0.5 * (vals[1:] + vals[:-1])
    m = mids.size - (mids.size % 2)
    return float(np.mean(mids[:m])) if m else float(mids[0])


def release_from_model(setup: RecordSetup, t: np.ndarray, y: np.ndarray, model_t: np.ndarray, model_y: np.ndarray, sigma: float,
                       span: float | None = None) -> RecordSetup:
    """Re-estimate the release time when the measured channel does not move at the release (a
    closing's follower waits until the cam's rise reaches the roller): the record's departure
    from rest minus the model's (both where they first leave their rest by 15 sigma)."""
    level = setup.level
    k_rec = np.nonzero(np.abs(y - level) > 15 * sigma)[0]
    k_mod = np.nonzero(np.abs(model_y - model_y[0]) > 15 * sigma)[0]
    if not k_rec.size or not k_mod.size:
        return setup
    release = float(t[k_rec[0]] - model_t[k_mod[0]])
    span = span or CAMERA_RELEASE_SPAN
    setup.release = release
    setup.release_bounds = (release - span, release + span)
    setup.notes.append(f"the record leaves rest {model_t[k_mod[0]]:.4g} s after the model's release: released at about "
                       f"{release:.4g} s in the record")
    return setup


def swing_period_mismatch(rig: Rig, t: np.ndarray, y: np.ndarray, window_start: float, sigma: float) -> dict | None:
    """The record's swing period against the rig's, model-free: full periods between every other
    extreme of the free swing (each extreme timed by a parabola through its top) against the
    exact pendulum's at the swing's amplitude, T = 4 sqrt(I/(M g L)) K(sin^2(a/2)) (friction
    changes the period by less than 0.02 %). Returns {"relative", "stderr", "significant", ...} or
    None (fewer than 6 clear extremes)."""
    p = rig.pendulum
    sel = t >= window_start
    ts, ys = t[sel], y[sel]
    tp, amp, vals = complete_swing_extremes(ts, ys)  # a record ending mid-swing: no edge "extreme"
    big = amp > 20 * sigma
    tp, vals = tp[big], vals[big]
    if tp.size < 6:
        return None
    half = float(np.median(np.diff(tp)))
    periods = tp[2:] - tp[:-2]
    keep = np.abs(periods - 2 * half) < 0.3 * half
    centre = np.mean(0.5 * (vals[1:] + vals[:-1]))
    a = np.abs(vals - centre)
    amp_mid = (a[2:] + 2 * a[1:-1] + a[:-2]) / 4
    nominal = 4 * np.sqrt(p.inertia / (p.mass * rig.gravity * p.com_distance)) * ellipk(np.sin(amp_mid / 2) ** 2)
    ratio = periods[keep] / nominal[keep]
    if ratio.size < 3:
        return None
    rel = float(np.median(ratio) - 1.0)
    se = float(1.2533 * np.std(ratio) / np.sqrt(ratio.size))
    return {"relative": rel, "stderr": se, "record_period_s": float(np.median(periods[keep])),
            "model_period_s": float(np.median(nominal[keep])), "periods": int(ratio.size),
            "significant": bool(abs(rel) > 0.002 and abs(rel) > 4 * se), "method": "record extremes vs exact pendulum"}

"""Breaker-analyser channels of a closing record, and the figures of merit analysers compute.

A circuit-breaker analyser (timing and travel test set) records, besides a travel transducer,
one timing channel per pole: the main contact's state, 0 open and 1 closed, sampled at 10-20 kHz.
A ``vcb_closing`` record may carry them as ``pole_1_contact``, ``pole_2_contact``, ... (0/1) and the
moving contacts' travels as ``pole_1_travel``, ... (m, from the open position, towards closing).

Figures of merit, as analysers define them (times from the release; IEC 62271-100 calls the
closing time the interval from energising the closing release to the contacts touching in all
poles; here the reference is the mechanical release, the record's ``release_time``):

- **closing time** per pole: the first 0 -> 1 transition of its contact channel (mid-way between
  the last open and the first closed sample); ``closing_time_s`` is the last pole's;
- **pole spread** (pole discrepancy): last pole's closing time minus the first's;
- **bounce**: every 1 -> 0 transition after a pole's first touch is a bounce (an opening of at
  least ``min_bounce`` s); ``bounce_count`` is the largest count of any pole, ``bounce_duration_s``
  the longest interval from a pole's first touch to its final closing;
- **closing speed** over a zone (``closing_speed_m_s``): the mean speed of the travel channel over
  the last ``zone`` m of travel before the first contact touch (default 4 mm, parameters.SPEED_ZONE: the zone of the
  simulations' closing speed too), distance over time;
- **overtravel**: the largest travel beyond the final resting position (max - final); **rebound**:
  how far the travel comes back below the final position after that peak (final - min after it);
  **wipe**: travel after the first touch (final - travel at touch); the final position is the
  median of the record's last 2 % (:func:`travel_figures`, which simulations use too), and the
  travel has **settled** once it stays within REST_BAND of it.
"""
from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from .. import parameters as P
from ..errors import InputError
from ..laws.breaker import pole_gaps

if TYPE_CHECKING:
    from ..rig.data import Rig
    from .measurement import Measurement

CONTACT = re.compile(r"pole_(\d+)_contact")
TRAVEL = re.compile(r"pole_(\d+)_travel")
#: Travel zone before the first touch over which the closing speed is averaged (m): the closing speed's
#: zone of the simulations (parameters.SPEED_ZONE), so a record and a simulation report one figure.
TOUCH_ZONE = P.SPEED_ZONE[0]
#: Shortest opening counted as a bounce (s): one sample of a 20 kHz analyser.
MIN_BOUNCE = 5e-5
#: Band around the final travel (m) within which the travel counts as settled: half the 0.1 mm a
#: breaker analyser's travel transducer resolves on a 10-20 mm stroke (its figures are read to 0.1 mm).
REST_BAND = 5e-5
#: Weight of a contact channel's residual: one misclassified sample counts as a 2-sigma deviation.
CONTACT_SIGMA = 0.5


def analyser_channels(poles: int) -> tuple[str, ...]:
    """Channel names an analyser record of a breaker with ``poles`` poles may carry."""
    return tuple(f"pole_{i}_{kind}" for i in range(1, poles + 1) for kind in ("contact", "travel"))


def simulated_channels(poles: int) -> tuple[str, ...]:
    """Channels ``vcbmodel simulate`` writes into a closing's record beside the analyser's: each pole's
    speed (m/s), contact force and push-rod force (N), with a making current (``breaker.making_current``)
    its current (A) and Holm repulsion (N), the cam's angle (rad) and speed (rad/s), the cam-roller
    force and the end stop's and holding latch's forces (N). Read back, never fitted."""
    kinds = ("velocity", "contact_force", "rod_force", "making_current", "repulsion_force")
    per_pole = tuple(f"pole_{i}_{kind}" for i in range(1, poles + 1) for kind in kinds)
    return per_pole + ("cam_angle", "shaft_velocity", "cam_roller_force", "end_stop_force", "hold_latch_force")


def check_contacts(measurement: Measurement) -> None:
    """Refuse a contact channel that is not 0/1 (one line naming the channel)."""
    for name, values in measurement.channels.items():
        if CONTACT.fullmatch(name) and not np.all((values == 0) | (values == 1)):
            bad = values[(values != 0) & (values != 1)][0]
            raise InputError(measurement.path, f"column {name!r}", f"a contact channel holds 0 (open) or 1 (closed), got {bad:g}")


def channel_setup(rig: Rig, setup, channels: Iterable[str], channel_sigma: dict[str, float]) -> None:
    """Fill a diagnosis' record setup for the analyser channels: each contact channel's gap (the
    model's pole travel at touch) and indicator width, and the weights."""
    gaps = pole_gaps(rig.breaker.poles)
    for ch in channels:
        m = CONTACT.fullmatch(ch)
        if m:
            i = int(m.group(1)) - 1
            if i >= len(gaps):
                raise InputError(rig.path, "breaker.poles.count", f"the record has {ch} but the breaker has {len(gaps)} poles")
            # the indicator rises over 20 um of travel: well under one sample at 2 m/s and 12 kHz
            setup.contact[ch] = (float(gaps[i]), 2e-5)
            channel_sigma[ch] = CONTACT_SIGMA
        elif TRAVEL.fullmatch(ch):
            channel_sigma[ch] = max(channel_sigma.get(ch, 0.0), 1e-6)


def _transitions(t, c):
    """(times of 0->1, times of 1->0), mid-way between samples."""
    c = np.asarray(c) > 0.5
    d = np.diff(c.astype(int))
    mid = 0.5 * (t[1:] + t[:-1])
    return mid[d == 1], mid[d == -1]


def pole_timing(t: np.ndarray, contact: np.ndarray, release: float = 0.0, min_bounce: float = MIN_BOUNCE) -> dict[str, float | int | None]:
    """One pole: closing time (s from release, None if it never closes), bounces and the bounce
    duration (first touch to final closing)."""
    t = np.asarray(t, float)
    ups, downs = _transitions(t, contact)
    closed0 = bool(np.asarray(contact)[0] > 0.5)
    if not ups.size and not closed0:
        return {"closing_time_s": None, "bounces": 0, "bounce_duration_s": 0.0}
    first = float(ups[0]) if ups.size else float(t[0])
    opens = downs[downs > first]
    bounces = 0
    for o in opens:
        nxt = ups[ups > o]
        width = (float(nxt[0]) if nxt.size else float(t[-1])) - o
        bounces += width >= min_bounce
    final = float(ups[-1]) if ups.size else first
    return {"closing_time_s": first - release, "bounces": int(bounces), "bounce_duration_s": max(0.0, final - first)}


def figures_of_merit(t: np.ndarray, contacts: Sequence[np.ndarray], travel: np.ndarray | None = None, release: float = 0.0,
                     zone: float = TOUCH_ZONE, min_bounce: float = MIN_BOUNCE) -> dict:
    """Analyser figures of merit (module docstring) from contact channels (list of 0/1 arrays,
    pole order) and a travel channel (m, towards closing; the follower displacement or a pole's
    travel). Times in s from ``release``; speeds in m/s; lengths in m."""
    t = np.asarray(t, float)
    poles = [pole_timing(t, c, release, min_bounce) for c in contacts]
    times = [p["closing_time_s"] for p in poles]
    done = [x for x in times if x is not None]
    out = {"per_pole": poles,
           "closing_time_s": max(done) if done and len(done) == len(poles) else None,
           "first_touch_s": min(done) if done else None,
           "pole_spread_s": (max(done) - min(done)) if done and len(done) == len(poles) else None,
           "bounce_count": int(max((p["bounces"] for p in poles), default=0)),
           "bounce_duration_s": float(max((p["bounce_duration_s"] for p in poles), default=0.0))}
    if travel is not None:
        travel = np.asarray(travel, float)
        out.update(travel_figures(t, travel, min(done) + release if done else None, release))
        if done:
            t_touch = min(done) + release
            x_touch = out["travel_at_touch_m"]
            before = np.nonzero((travel <= x_touch - zone) & (t <= t_touch))[0]
            if before.size:
                i = int(before[-1])
                # the crossing of x_touch - zone, interpolated
                t0 = t[i] + (x_touch - zone - travel[i]) / max(travel[i + 1] - travel[i], 1e-300) * (t[i + 1] - t[i])
                out["closing_speed_m_s"] = zone / max(t_touch - t0, 1e-300)
                out["closing_speed_zone_m"] = zone
    return out


def travel_figures(t: np.ndarray, travel: np.ndarray, t_touch: float | None = None, release: float = 0.0) -> dict:
    """The travel's figures (module docstring; lengths in m, times in s from ``release``):
    ``final_travel_m`` (the median of the last 2 % of the samples, at least 3: the resting position),
    ``overtravel_m`` (max - final), ``rebound_m`` (final - the least travel after the max, >= 0),
    ``travel_settled_s`` (when the travel enters REST_BAND of the final travel for good; None if
    only within the last 2 %: not at rest within the record) and, given the first touch
    ``t_touch`` (s, on the record's clock), ``travel_at_touch_m`` and ``wipe_m`` (final - at touch)."""
    t, travel = np.asarray(t, float), np.asarray(travel, float)
    tail = max(3, travel.size // 50)
    final = float(np.median(travel[-tail:]))
    k = int(np.argmax(travel))
    out = {"final_travel_m": final, "overtravel_m": float(travel[k] - final),
           "rebound_m": float(max(0.0, final - np.min(travel[k:])))}
    outside = np.nonzero(np.abs(travel - final) > REST_BAND)[0]
    settled = 0 if not outside.size else int(outside[-1]) + 1
    out["travel_settled_s"] = float(t[settled] - release) if settled < travel.size - tail else None
    if t_touch is not None:
        x_touch = float(np.interp(t_touch, t, travel))
        out["travel_at_touch_m"] = x_touch
        out["wipe_m"] = final - x_touch
    return out


def record_figures(measurement: Measurement, release: float = 0.0, zone: float = TOUCH_ZONE) -> dict:
    """Figures of merit of a measured closing record (the channels it has)."""
    chans = measurement.channels
    contacts = [chans[k] for k in sorted((k for k in chans if CONTACT.fullmatch(k)),
                                         key=lambda k: int(CONTACT.fullmatch(k).group(1)))]
    travel = chans.get("follower_displacement")
    if travel is None:
        travels = [k for k in chans if TRAVEL.fullmatch(k)]
        travel = chans[travels[0]] if travels else None
    return figures_of_merit(measurement.t, contacts, travel, release, zone)

"""A record cut to start at its release: what ``identify`` fits, whose model starts at the rig's
initial angle at t = 0.

The release is found as the diagnosis finds it (:func:`vcbmodel.analysis.nuisance.record_setup`:
a pre-trigger at rest, a logger's clock offset, a hand that brings the pendulum to its angle), so a
record with a pre-trigger, shifted or not, is fitted from its release instead of as another swing.
"""
from __future__ import annotations

import logging
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from ..experiments import experiment_of
from ..experiments.simulation import simulate
from ..records.signals import noise_estimate_floored
from .fit import Parameter, make_parameters
from .nuisance import RecordSetup, record_setup, release_from_model

if TYPE_CHECKING:
    from collections.abc import Sequence

    from ..records.measurement import Measurement
    from ..rig.data import Rig

log = logging.getLogger("vcbmodel")

#: The shortest rest before the release (s) taken as a pre-trigger and cut off: the release estimate
#: from the record alone (its first departure from rest, noise-limited) scatters by about 10 ms on the
#: shipped 1 kHz swings, which start at their release; a shorter "rest" is that scatter, not a
#: pre-trigger, and the record is fitted from its first sample.
MIN_PRE_TRIGGER = 0.05


def from_release(rig: Rig, meas: Measurement) -> Measurement:
    """``meas`` from its release on, the release at t = 0 (the sample nearest it): unchanged when it
    starts at the release already (within a sample, at t = 0). InputError when the release leaves
    too little of the record to fit (a record that never moves, or is cut short)."""
    channel = "pendulum_angle"
    t = np.asarray(meas.t, float)
    dt = float(np.median(np.diff(t)))
    sigma = noise_estimate_floored(meas.channel(channel))
    setup = record_setup(rig, meas, sigma)
    start = max(float(setup.release), float(setup.window[0]))
    if start - t[0] < MIN_PRE_TRIGGER:
        start = float(t[0])
    elif not setup.hand_start:  # at rest before: place the release by the model's own departure from rest
        model_t, model_y = _model_start(rig, meas, start)
        start = float(release_from_model(setup, t, meas.channel(channel), model_t, model_y, sigma).release)
    if abs(t[0]) <= dt and start == t[0]:
        return meas
    k = int(np.argmin(np.abs(t - start)))
    if t.size - k < 20:
        raise InputError(meas.path, "column 't'", f"the release found at {start:g} s leaves {t.size - k} samples: "
                         "too few to fit (does the record show the swing?)")
    log.info("identify: %s: released at %.4g s%s; fitted from there, the release at t = 0", meas.path, start,
             f" ({'; '.join(setup.notes)})" if setup.notes else "")
    shifted = replace(meas, t=t[k:] - t[k], channels={name: v[k:] for name, v in meas.channels.items()},
                      comments=meas.comments + (f"{CUT_NOTE} {start:.6g} s, shifted to t = 0",))
    return shifted


#: The comment :func:`from_release` adds to a record it cut at the release it found.
CUT_NOTE = "vcbmodel: released at"
#: How far (s) a fit may move the release of a record cut at a release found in it: the estimate
#: scatters by about 10 ms on 1 kHz swings (MIN_PRE_TRIGGER's reason), and the cut rounds it to a sample.
RELEASE_REFIT_SPAN = 0.02


def was_cut(meas: Measurement) -> bool:
    """Whether :func:`from_release` cut ``meas`` at a release it found (not at its first sample)."""
    return any(c.startswith(CUT_NOTE) for c in meas.comments)


def release_setup(meas: Measurement) -> RecordSetup:
    """The alignment of a record cut at its found release: the release (t = 0 after the cut) refitted
    within :data:`RELEASE_REFIT_SPAN` as the diagnosis fits it (a ``release`` parameter), the whole
    record fitted; the sensor's offset and gain are not fitted (none is a parameter)."""
    t = np.asarray(meas.t, float)
    return RecordSetup(window=(float(t[0]), float(t[-1])), still_start=True, release=0.0,
                       release_bounds=(-RELEASE_REFIT_SPAN, RELEASE_REFIT_SPAN), offset=0.0, gain=1.0,
                       initial_angle=None, initial_angle_prior=None)


def release_parameter(i: int, setup: RecordSetup) -> Parameter:
    """Dataset ``i``'s release time (s in its record's time) as a fit parameter over ``setup``'s bounds."""
    return Parameter(f"release_time_{i}", setup.release, setup.release_bounds[0], setup.release_bounds[1],
                     unit="s", kind="release", dataset=i)


#: How much of the model's swing from its release is simulated to place the release (s): its departure
#: from rest by 15 sigma comes within the first tenth of a second on the shipped swings.
MODEL_START = 0.3


def _model_start(rig: Rig, meas: Measurement, start: float) -> tuple[np.ndarray, np.ndarray]:
    """(t, angle) of the rig's model from its release, over ``MODEL_START``, with the friction the rig
    gives or, where it gives none, the record's own starting values (its swing's decay)."""
    record = experiment_of(rig.experiment)
    swing = meas.window(start)
    swing = replace(swing, t=swing.t - swing.t[0])
    params = make_parameters(rig, rig.model.effects, initial=record.start_guesses(rig, swing)[0])
    dt = float(np.median(np.diff(meas.t)))
    times = np.arange(int(MODEL_START / dt) + 1) * dt
    result = simulate(rig, rig.model.effects, {k: p.value for k, p in params.items()}, sample_times=times, backend="fast")
    return times, result.measured


def released_pairs(pairs: Sequence[tuple[Rig, Measurement]]) -> list[tuple[Rig, Measurement]]:
    """Each (rig, measurement) pair of pendulum records with the record from its release
    (:func:`from_release`; :func:`was_cut` tells which were cut); InputError for no pairs, or a pair
    that is not a pendulum test."""
    pairs = list(pairs)
    if not pairs:
        raise InputError("identify", "measurements", "no records given: identify needs one pendulum record or more")
    for rig, meas in pairs:
        if rig.experiment != "pendulum" or "pendulum_angle" not in meas.channels:
            raise InputError(meas.path, "experiment", f"identify fits the shaft friction to pendulum records; this is a "
                             f"{rig.experiment} record ({rig.path})")
    return [(rig, from_release(rig, meas)) for rig, meas in pairs]

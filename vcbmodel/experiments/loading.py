"""Loading a rig file: the common sections here, the experiment's own through its record.

Everything is validated on load; any fault raises :class:`~vcbmodel.errors.InputError` naming
the file and the field. Keys starting with ``_`` are free comments.
"""
from __future__ import annotations

import json
import logging
import math
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputError
from ..model.choice import applicable
from ..model.result import unit_of
from ..model.values import rig_values
from ..records.analyser import analyser_channels, check_contacts, simulated_channels
from ..records.integrity import check_held_values, runs_backwards, unwrap_turns
from ..records.measurement import load_measurement, sibling_rig_path
from ..records.signals import noise_estimate_floored
from ..rig.data import Rig
from ..rig.paths import loaded_value
from ..rig.plausibility import check_rig, plausibility, step_limits
from ..rig.reader import Reader, read_json
from ..rig.sections import read_friction, read_record, read_uncertain
from ..rig.spring_model import read_model
from .base import EXPERIMENTS

if TYPE_CHECKING:
    from ..records.measurement import Measurement

log = logging.getLogger("vcbmodel")

FORMAT = "vcb-rig/1"
COMMON_KEYS = ("format", "name", "experiment", "gravity", "shaft", "friction", "model", "record", "uncertain")


def load_rig(path: str | Path) -> Rig:
    """Read and check a ``vcb-rig/1`` file (docs/rig-format.md).

    Parameters
    ----------
    path : the rig file (``NAME.rig.json``).

    Returns
    -------
    Rig
        The checked rig; its values in SI units (m, kg, kg m^2, N/m, N, rad, s; docs/rig-format.md).
    """
    path = str(path)
    rig = rig_from_data(read_json(path), path)
    for line in rig.warnings:  # unusual but possible values: said once, where the file is read
        log.warning("vcbmodel: warning: %s: %s", path, line)
    return rig


def rig_from_data(data: dict, path: str = "(rig)") -> Rig:
    """Check a rig's JSON object (as read from ``path``) and build the :class:`Rig`."""
    rd = Reader(path)
    if not isinstance(data, dict):
        rd.fail("(top level)", "must be a JSON object")
    if data.get("format") != FORMAT:
        rd.fail("format", f"must be {FORMAT!r}, got {json.dumps(data.get('format'))[:40]}")
    name = data.get("experiment")
    if name not in EXPERIMENTS:
        rd.fail("experiment", f"must be one of {', '.join(EXPERIMENTS)}, got {json.dumps(name)[:40]}")
    record = EXPERIMENTS[name]
    rd.known_keys(data, COMMON_KEYS + record.sections)
    gravity = rd.number(data, "gravity", nonnegative=True, default=9.81)
    radius = rd.number(rd.section(data, "shaft", known=("radius",)), "radius", "shaft.", nonnegative=True)
    friction = read_friction(rd, data)
    model = read_model(rd, data, applicable(record), name)
    if not record.has_closing_spring and not model.spring_model.is_massless:
        rd.fail("model.spring_model", f"a {name} test has no closing spring: use 'massless'")
    warnings = plausibility(rd, data)  # a unit slip first: it would mislead the sections' own checks
    sections = record.read_sections(rd, data)
    warnings += check_rig(rd, data, sections)
    title = data.get("name", Path(path).name.replace(".rig.json", ""))
    if not isinstance(title, str):
        rd.fail("name", "must be a string")
    rig = Rig(path=path, name=title, experiment=name, gravity=gravity, shaft_radius=radius, friction=friction,
              model=model, sections=sections, data=data, record=read_record(rd, data),
              uncertain=read_uncertain(rd, data), warnings=warnings, provides=record.provides)
    rig_values(rig)  # the effects check the values the rig gives (e.g. zeta on a pendulum only)
    step_limits(rig, model.spring_model, record.step(rig))  # a spring or damper too stiff for the step
    return rig


def load_record(measurement_path: str | Path, rig: Rig) -> Measurement:
    """A measurement file for ``rig``: it must carry the experiment's channel and a plausible
    time axis (seconds)."""
    record = EXPERIMENTS[rig.experiment]
    known = known_channels(rig)
    meas = load_measurement(measurement_path, record.measured_channel, known, {c: unit_of(c) for c in known},
                            record.channel_hint)
    meas = unwrapped(meas)
    record.check_record(meas.t, meas.channel(record.measured_channel), meas.path,
                        [v for name, v in meas.channels.items() if name != record.measured_channel])
    if record.initial_angle_field is not None:
        check_start_in_degrees(meas, record.measured_channel, rig, record.initial_angle_field)
    check_contacts(meas)
    check_travel_signs(meas)
    check_held_values(meas.t, meas.channel(record.measured_channel), meas.path, record.measured_channel)
    return meas


def require_noise(meas: Measurement, rig: Rig) -> None:
    """Refuse (InputError naming the file and the channel) a record whose measured channel shows no noise
    at all: its third differences mostly exactly zero on no sensor's step, as a noise-free simulation
    written to 9 digits (``vcbmodel simulate``'s output: a pendulum at rest for half of it). A fit weighs
    its residual by the record's noise: with none it divides by zero (the fit failed with 'bad input:
    simulate: values.mu_k: ... got nan', or 'the fitted model's simulation failed')."""
    channel = EXPERIMENTS[rig.experiment].measured_channel
    if noise_estimate_floored(meas.channel(channel)) > 0.0:
        return
    raise InputError(meas.path, channel, "shows no noise at all (a noise-free record, such as vcbmodel simulate "
                     "writes): a fit weighs its residual by the record's noise; add the sensor's noise to it, as "
                     "results/synthetic's records add it to their truth")


def check_travel_signs(meas: Measurement) -> None:
    """Refuse a travel channel (the follower's, a pole's: m, towards closing from rest) that runs mostly
    below zero: a transducer counting the other way (fitted, a mirror image the model cannot follow, which
    a diagnosis would read as a missing effect)."""
    for name, y in meas.channels.items():
        if (name == "follower_displacement" or name.endswith("_travel")) and runs_backwards(y):
            raise InputError(meas.path, f"column {name!r}", f"runs to {float(np.min(y)):.4g} m, more than half its "
                             "span below zero: a travel runs towards closing, from rest; a transducer counting the "
                             "other way? Turn the column's sign")


def unwrapped(meas: Measurement) -> Measurement:
    """``meas`` with each angle channel (rad) that wraps at a full turn (an encoder counting 0..360 deg
    or -180..180 deg) unwrapped, said once as a warning: the record as the shaft turned."""
    channels = dict(meas.channels)
    for name, y in meas.channels.items():
        if unit_of(name) != "rad":
            continue
        channels[name], wraps = unwrap_turns(y)
        if wraps:
            log.warning("vcbmodel: warning: %s: column %r wraps at a full turn %d time(s) (an encoder's count): "
                        "read unwrapped", meas.path, name, wraps)
    return replace(meas, channels=channels)


#: A record whose first sample, less the rig's stated sensor offset and over its gain, reads the record's
#: starting angle (its ``record.initial_angle``, else the rig's) in degrees within this share, and is at
#: least :data:`DEGREES_RATIO_LEAST` times that angle in rad, is a record in degrees without its unit
#: stated (a rad record that far from its rig's start is refused too: the message says both readings).
DEGREES_MATCH = 0.1
DEGREES_RATIO_LEAST = 20.0


def check_start_in_degrees(meas: Measurement, channel: str, rig: Rig, field: str) -> None:
    """Refuse an angle record that starts at its starting angle with its sign turned (a sensor counting
    the other way: fitted, a mirror image the model cannot follow), converted from degrees though it was
    in rad (a column headed ``[deg]`` holding rad), or read in degrees (a 2.5 deg pendulum
    release written as 2.5 stays within pi, so the range check lets it pass, and the fits would take it as
    2.5 rad: a wrong diagnosis, not an error). The starting angle is the rig's ``record.initial_angle``
    when it states one, else ``field``; the first sample is read through the rig's stated
    ``record.sensor_offset`` and ``sensor_gain`` (none: 0 and 1)."""
    stated = rig.record.get("initial_angle")
    initial_angle = float(stated) if stated is not None else loaded_value(rig, field)
    where = "record.initial_angle" if stated is not None else field
    offset, gain = rig.record.get("sensor_offset") or 0.0, rig.record.get("sensor_gain") or 1.0
    first = (float(meas.channel(channel)[0]) - offset) / gain
    degrees = math.degrees(initial_angle)
    if initial_angle == 0.0:
        return
    if abs(first + initial_angle) <= DEGREES_MATCH * abs(initial_angle):
        raise InputError(meas.path, f"column {channel!r}", f"starts at {first:.4g}, the rig's {where} "
                         f"{initial_angle:.4g} rad with its sign turned: a sensor counting the other way? Turn the "
                         f"column's sign; if the test did start there, state it as the rig's {where}")
    if abs(first - math.radians(initial_angle)) <= DEGREES_MATCH * abs(math.radians(initial_angle)):
        raise InputError(meas.path, f"column {channel!r}", f"starts at {first:.4g} rad, the rig's {where} "
                         f"{initial_angle:.4g} rad converted from degrees once too often: values in rad under a "
                         f"stated unit of deg? State the unit the values are in ({channel} [rad])")
    if abs(first) < DEGREES_RATIO_LEAST * abs(initial_angle):
        return
    if abs(first - degrees) <= DEGREES_MATCH * abs(degrees):
        raise InputError(meas.path, f"column {channel!r}", f"starts at {first:.4g}, the rig's {where} "
                         f"{initial_angle:.4g} rad read in degrees ({degrees:.4g}): state the unit ({channel} "
                         f"[deg]) or convert the column to rad; if it is in rad, the rig's {where} is not where "
                         "the record starts")


def known_channels(rig: Rig | None = None) -> tuple[str, ...]:
    """Channel names a measurement file may carry: every experiment's measured channel, and for
    a closing the breaker analyser's ``pole_i_contact`` (0/1) and ``pole_i_travel`` (m), and the
    further channels ``simulate`` writes (speeds, forces; read back, not fitted)."""
    names = tuple(dict.fromkeys(r.measured_channel for r in EXPERIMENTS.values()))
    if rig is not None and rig.breaker is not None:
        names += analyser_channels(rig.breaker.poles.count) + simulated_channels(rig.breaker.poles.count)
    return names


def load_pair(measurement_path: str | Path, rig_path: str | Path | None = None) -> tuple[Rig, Measurement]:
    """(rig, measurement): the rig defaults to the measurement's sibling ``NAME.rig.json``.

    Parameters
    ----------
    measurement_path : the measurement file (``NAME.csv``: ``t`` in s, channels in SI units).
    rig_path : its rig file (default: ``NAME.rig.json`` beside it).

    Returns
    -------
    tuple of (Rig, Measurement)
        The checked rig (SI units) and the record (``t`` in s; channels in rad, m, or 0/1 contacts).
    """
    rig = rig_of(measurement_path, rig_path)
    return rig, load_record(measurement_path, rig)


def rig_of(measurement_path: str | Path, rig_path: str | Path | None = None) -> Rig:
    """The rig of a measurement (``rig_path``, else its sibling ``NAME.rig.json``), read before the
    record so that what is wrong with the rig or the command is said before the record is read."""
    if str(measurement_path).endswith(".rig.json"):
        raise InputError(measurement_path, "file", "is a rig file: give the measurement NAME.csv (its rig "
                         "NAME.rig.json is found beside it, or give it with --rig)")
    return load_rig(rig_path or sibling_rig_path(measurement_path))


def require_experiment(rig: Rig, name: str, command: str) -> None:
    if rig.experiment != name:
        raise InputError(rig.path, "experiment", f"{command} needs a {name} rig, got {rig.experiment}")

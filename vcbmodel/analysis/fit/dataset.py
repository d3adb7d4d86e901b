"""What a fit compares: a record with its rig (:class:`Dataset`), the model on the record's time
axis (:class:`AlignedModel`), and how an analyser's channel is read off the simulation (travel from
rest, a smooth contact indicator, sensor offset and gain names)."""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ... import parameters as P
from ...experiments import experiment_of

#: Channels whose sensor offset and gain carry the short names (``sensor_offset_i``).
MAIN_CHANNELS = ("pendulum_angle", "cam_angle", "follower_displacement")


@dataclass
class Dataset:
    """One record with the rig it was taken on; ``setup`` (:class:`~..nuisance.RecordSetup`):
    how the record is aligned with the model (None: the model starts at t = 0, no nuisance);
    ``channels``: the record's channels that are fitted (default: the experiment's measured one)."""

    rig: object
    measurement: object
    setup: object = None
    channels: tuple = None

    @property
    def t(self) -> np.ndarray:
        """Record times (s)."""
        return self.measurement.t

    @property
    def y(self) -> np.ndarray:
        """The measured channel (rad, or m for a closing)."""
        return self.measurement.channel(experiment_of(self.rig.experiment).measured_channel)

    @property
    def measured_channel(self) -> str:
        return experiment_of(self.rig.experiment).measured_channel

    @property
    def fitted_channels(self) -> tuple:
        return tuple(self.channels) if self.channels else (self.measured_channel,)

    def mask(self) -> np.ndarray:
        """The samples of the fit window (all without a setup)."""
        if self.setup is None:
            return np.ones(self.t.size, bool)
        t0, t1 = self.setup.window
        return (self.t >= t0 - 1e-12) & (self.t <= t1 + 1e-12)

    def with_window(self, t1: float) -> Dataset:
        """The dataset fitted up to record time t1 (s) only (a staged fit's first stage)."""
        if self.setup is None:
            return truncated(self, t1)
        return replace(self, setup=replace(self.setup, window=(self.setup.window[0], min(t1, self.setup.window[1]))))


@dataclass
class AlignedModel:
    """The model on a record's time axis: ``measured`` is the prediction of the measured channel
    at every record time (nan before a hand-driven start), ``channels`` the same for every
    fitted channel."""

    t: np.ndarray
    measured: np.ndarray
    channels: dict
    experiment: str
    spec: object = None


def truncated(dataset: Dataset, t_max: float) -> Dataset:
    """The dataset restricted to t <= t_max (s)."""
    m = dataset.measurement
    keep = m.t <= t_max
    sub = replace(m, t=m.t[keep], channels={k: v[keep] for k, v in m.channels.items()})
    return replace(dataset, measurement=sub)


# --- an analyser's channels from the simulation's --------------------------------------------------

def model_channel(dataset: Dataset, ch: str) -> str:
    """The simulation channel behind a record channel (``pole_i_contact`` is derived from
    ``pole_i_travel``)."""
    if ch.endswith("_contact") and ch.startswith("pole_"):
        return ch.replace("_contact", "_travel")
    return ch


def as_recorded(dataset: Dataset, ch: str, y: np.ndarray, curves=None) -> np.ndarray:
    """Record channel from the simulation channel: travel from rest for pole travels (an
    analyser measures from the open position), a smooth contact indicator for pole contacts
    (1 closed: the pole's travel beyond its gap)."""
    if ch.startswith("pole_") and ch.endswith("_travel") and ch != dataset.measured_channel:
        return y - (curves.data[ch][0] if curves is not None else 0.0)
    if ch.startswith("pole_") and ch.endswith("_contact"):
        gap, width = contact_gap(dataset, ch)
        return 0.5 * (1.0 + np.tanh((y - gap) / width))
    return y


def as_recorded_derivative(dataset: Dataset, ch: str, spline, tau: np.ndarray) -> np.ndarray:
    """Time derivative of :func:`as_recorded` at simulation times ``tau`` (s), from the
    simulation channel's ``spline``."""
    dy = spline(tau, 1)
    if ch.startswith("pole_") and ch.endswith("_contact"):
        gap, width = contact_gap(dataset, ch)
        y = spline(tau)
        return dy * 0.5 / width / np.cosh(np.clip((y - gap) / width, -50, 50)) ** 2
    return dy


def contact_gap(dataset: Dataset, ch: str) -> tuple[float, float]:
    """(gap, width) of a pole's contact indicator (m)."""
    info = dataset.setup.contact if dataset.setup is not None else {}
    return info.get(ch, (0.0, 1e-4))


def has_gain(dataset: Dataset, ch: str) -> bool:
    return dataset.setup is not None and not ch.endswith("_contact")


def has_offset(dataset: Dataset, ch: str) -> bool:
    return dataset.setup is not None and not ch.endswith("_contact")


def offset_name(i: int, ch: str) -> str:
    """Name of the sensor offset parameter of channel ``ch`` of dataset ``i``."""
    return f"sensor_offset_{i}" if ch in MAIN_CHANNELS else f"offset_{ch}_{i}"


def time_scale_name(i: int) -> str:
    """Name of the time-scale parameter of dataset ``i``: seconds that passed per second of the
    record's time stamps (1: the record's clock is right; 1.004: 0.4 % more time passed than the
    stamps say, e.g. a camera whose true frame rate is 0.4 % below the nominal one)."""
    return f"time_scale_{i}"


#: Largest relative error of a record's clock the time-scale nuisance may take (bounds of
#: ``time_scale_i``; the number and its reason live in :mod:`vcbmodel.parameters`).
TIME_SCALE_SPAN = P.TIME_SCALE_SPAN


def model_time(t: np.ndarray, release: float, time_scale: float = 1.0) -> np.ndarray:
    """Model time (s from the release) of record times ``t`` (s): (t - release) * time_scale."""
    return (np.asarray(t, float) - release) * time_scale


def gain_name(i: int, ch: str) -> str:
    """Name of the sensor gain parameter of channel ``ch`` of dataset ``i``."""
    return f"sensor_gain_{i}" if ch in MAIN_CHANNELS else f"gain_{ch}_{i}"

"""The result of one simulation: channels with units, and what it was run with."""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import pandas as pd

    from ..rig.spring_model import SpringModel

#: Unit of each channel name (first matching pattern wins).
CHANNEL_UNITS = (
    (r"(pendulum_angle|cam_angle|follower_angle|pressure_angle)", "rad"),
    (r"(shaft_velocity|follower_velocity|pole_\d+_lever_velocity)", "rad/s"),
    (r"pole_\d+_lever_angle", "rad"),
    (r"(hold_latch_engaged|pole_\d+_contact)", "-"),
    (r"friction_torque", "N m"),
    (r"pole_\d+_making_current", "A"),
    (r".*(force|_N)$", "N"),
    (r".*(penetration_rate|rod_rate|pole_\d+_velocity|spring_velocity_\d+_[xy])$", "m/s"),
    (r".*(displacement|travel|penetration|compression|_x|_y)$", "m"),
)


def unit_of(channel: str) -> str:
    """The SI unit of a channel by its name (``?`` if unknown)."""
    for pattern, unit in CHANNEL_UNITS:
        if re.fullmatch(pattern, channel):
            return unit
    return "?"


@dataclass
class SimulationResult:
    """Channels sampled at ``t`` (s); ``units`` maps each channel to its SI unit.
    ``measured_channel`` is the experiment's measured channel (``pendulum_angle``, ``cam_angle``
    in rad; ``follower_displacement`` in m); ``spec`` holds the effects, parameter values and
    spring model the run used."""

    t: np.ndarray
    channels: dict
    experiment: str
    measured_channel: str
    spec: object  # vcbmodel.model.effects.ModelSpec
    info: dict = field(default_factory=dict)
    units: dict = field(default_factory=dict)

    def __post_init__(self):
        self.units = {name: self.units.get(name) or unit_of(name) for name in self.channels}

    @property
    def measured(self) -> np.ndarray:
        """The measured channel's samples (rad or m)."""
        return self.channels[self.measured_channel]

    @property
    def effects(self) -> tuple:
        return self.spec.effects

    @property
    def spring_model(self) -> SpringModel:
        return self.spec.spring_model

    def resample(self, t: np.ndarray) -> SimulationResult:
        """The channels linearly interpolated at times ``t`` (s)."""
        t = np.asarray(t)
        return SimulationResult(t, {k: np.interp(t, self.t, v) for k, v in self.channels.items()}, self.experiment,
                                self.measured_channel, self.spec, self.info, self.units)

    def to_dataframe(self) -> pd.DataFrame:
        """A pandas DataFrame indexed by ``t`` (s); column names carry their unit: ``cam_angle [rad]``."""
        import pandas as pd  # optional dependency, only for this conversion

        units = self.units
        frame = pd.DataFrame({f"{k} [{units[k]}]": v for k, v in self.channels.items()}, index=self.t)
        frame.index.name = "t [s]"
        return frame

"""The experiment record: everything the layers need to know about one kind of test."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

from ..errors import InputError


def no_guesses(rig, measurement):
    return [{}]


def no_signature(rig, measurement, model_curve, residual, sigma):
    return {}


def whole_record(t, y, sigma):
    return None


@dataclass(frozen=True)
class Experiment:
    """One experiment kind. Callables receive the loaded :class:`vcbmodel.rig.data.Rig`.

    - ``read_sections(reader, data) -> {section name: dataclass}``: the rig sections it needs
      (``sections`` lists their top-level keys);
    - ``build(rig, spec, law, chain, user_function, ancf_elements) -> ExudynModel``;
    - ``channels(data, rig, spec, info) -> {name: array}`` from the sensors' rows (t, values...)
      of either backend (Exudyn or :func:`vcbmodel.reference.solve.simulate_reference`);
    - ``step(rig)``: default fixed RK4 step (s);
    - ``figures_of_merit(result, rig) -> dict`` (SI units; names end in their unit);
    - ``start_guesses(rig, measurement)``: starting-value dicts for fits, from the data;
    - ``swinging_part(t, y, sigma)``: end time (s) of the part a staged fit fits first, or None;
    - ``signature(rig, measurement, model_curve, residual, sigma)``: diagnosis evidence;
    - ``initial_angle_field``: the rig field of the shaft angle at release, which the diagnosis
      estimates as a nuisance (None: the experiment's start is fixed by its geometry);
    - ``period_fields``: rig fields that set a free swing's period (a period mismatch points at them);
    - ``extra_channels``: further record channels the experiment accepts (regular expressions,
      e.g. a breaker analyser's ``pole_1_contact``), fitted when present;
    - ``figure_units``: the figures of merit a sweep tabulates, {column: unit}, in column order;
    - ``run_status(values) -> str``: ``ok``, or why a run's figures of merit are not a result
      (a breaker that never closed: ``not_closed``), counted apart by sweeps and tolerance studies.
    """

    name: str
    description: str
    measured_channel: str
    unit: str  # of the measured channel
    sections: tuple
    read_sections: Callable
    sample_rate: float  # Hz, the usual sensor's
    noise_sigma: float  # the usual sensor's noise, in ``unit``
    default_duration: float  # s
    max_duration: float  # s: a longer record is implausible (a unit slip, e.g. ms written as s)
    build: Callable
    channels: Callable
    step: Callable
    figures_of_merit: Callable
    has_closing_spring: bool = False
    start_guesses: Callable = no_guesses
    swinging_part: Callable = whole_record
    signature: Callable = no_signature
    initial_angle_field: str | None = None
    period_fields: tuple = ()
    extra_channels: tuple = ()
    figure_units: tuple = ()  # ((column, unit), ...): what a sweep tabulates
    missing_means: tuple = ()  # ((column, status), ...): see run_status

    @property
    def figure_columns(self) -> tuple:
        """The sweep's result columns (figures of merit, SI units in their names)."""
        return tuple(c for c, _ in self.figure_units)

    def run_status(self, values) -> str:
        """``ok``; an experiment whose figures can be missing for a physical reason overrides it via
        ``missing_means``: {column: status} (a closing without a closing time: ``not_closed``)."""
        for column, status in self.missing_means:
            v = values.get(column)
            if v is None or (isinstance(v, float) and v != v):
                return status
        return "ok"

    def check_duration(self, duration, source, field):
        """Refuse an implausibly long record or simulation (one line with a hint)."""
        if duration > self.max_duration:
            raise InputError(source, field, f"{duration:g} s is implausible for a {self.name} test (at most "
                             f"{self.max_duration:g} s): is the time in milliseconds? It must be in seconds")


EXPERIMENTS: dict = {}


def register(experiment: Experiment):
    """Add an experiment kind (replacing one of the same name)."""
    EXPERIMENTS[experiment.name] = experiment
    return experiment


def experiment_of(name) -> Experiment:
    try:
        return EXPERIMENTS[name]
    except KeyError:
        raise ValueError(f"unknown experiment {name!r}") from None


def shaft_channels(data, measured_channel):
    """Channels of a shaft experiment from sensor rows: the shaft angle as the measured
    channel (rad), ``shaft_velocity`` (rad/s), ``friction_torque`` (N m, on the shaft,
    opposing motion), spring points ``..._x``/``..._y`` (m) and velocities (m/s)."""
    ch = {measured_channel: data["angle"][:, 1], "shaft_velocity": data["velocity"][:, 1]}
    if "friction_torque" in data:
        ch["friction_torque"] = -data["friction_torque"][:, 1]
    for name, d in data.items():
        if name.startswith(("spring_mass_", "spring_velocity_", "ancf_node_")):
            ch[name + "_x"], ch[name + "_y"] = d[:, 1], d[:, 2]
    return ch

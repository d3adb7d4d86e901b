"""The experiment record: everything the layers need to know about one kind of test."""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Callable

import numpy as np

from ..compiled import OdeModel
from ..errors import InputError

if TYPE_CHECKING:
    from ..records.measurement import Measurement
    from ..model.effects import ModelSpec
    from ..model.result import SimulationResult
    from ..rig.data import Rig

#: Shortest sample interval of any record (s): 10 MHz is beyond any sensor of a mechanism test; a
#: smaller spacing is a time column in the wrong unit, and would make the fits' step (which must
#: divide the spacing) absurdly small.
MIN_SAMPLE_INTERVAL = 1e-7
#: Most samples in a record (two million: 100 s at 20 kHz); a denser record is decimated first.
MAX_SAMPLES = 2_000_000
#: Fewest samples of a record any command reads: the noise comes from the record's third differences
#: (8 samples at least), the residual's whiteness is tested over 20 lags, the release is fitted on
#: the samples before the motion departs (5 at least) and a diagnosis fits up to about ten
#: parameters; 50 leaves each of these samples to spare. An analyser records hundreds (10 kHz over
#: 50 ms: 500), a camera at 12 kHz 300 over a 25 ms drop.
MIN_SAMPLES = 50


def check_samples(t: np.ndarray, source: str) -> None:
    """Refuse (InputError, field ``data``) a record of fewer than MIN_SAMPLES samples."""
    if np.size(t) < MIN_SAMPLES:
        raise InputError(source, "data", f"{np.size(t)} samples: too few to analyse (a record needs at least "
                         f"{MIN_SAMPLES}: its noise, its release and the fitted parameters each take samples)")


def no_guesses(rig: Rig, measurement: Measurement) -> list[dict[str, float]]:
    return [{}]


def no_signature(rig: Rig, measurement: Measurement, model_curve: np.ndarray, residual: np.ndarray, sigma: float) -> dict:
    return {}


def whole_record(t: np.ndarray, y: np.ndarray, sigma: float) -> float | None:
    return None


def default_fit_step(rig: Rig, spring_kind: str) -> float | None:
    """The experiment's own step for fits too (None)."""
    return None


def measured_only(result: SimulationResult, rig: Rig) -> dict[str, tuple[np.ndarray, str]]:
    """{channel: (values, unit)}: the experiment's measured channel (what ``simulate`` writes)."""
    return {result.measured_channel: (result.measured, result.units[result.measured_channel])}


def refuse_discovered_torque(spec: ModelSpec) -> None:
    """The reference solves have no discovered torque: a model that carries one is refused rather than
    solved without it."""
    if spec.discovered:
        raise ValueError("the reference solve has no discovered torque: use backend='exudyn' or 'compiled'")


def figures_summary(result: SimulationResult, rig: Rig) -> list[tuple]:
    """[(what, value, unit)]: the experiment's figures of merit (``simulate``'s one-run summary)."""
    fom = experiment_of(rig.experiment).figures_of_merit(result, rig)
    return [(name, fom.get(name), unit) for name, unit in experiment_of(rig.experiment).figure_units]


@dataclass(frozen=True)
class Experiment:
    """One experiment kind. Callables receive the loaded :class:`vcbmodel.rig.data.Rig`.

    - ``read_sections(reader, data) -> {section name: dataclass}``: the rig sections it needs
      (``sections`` lists their top-level keys);
    - ``provides``: what its model carries that effects act on (each effect says what it needs,
      :class:`vcbmodel.model.effects.Effect`): ``journal`` (a shaft in a journal bearing: the
      friction law), ``swinging_body`` (a body swinging through air), ``closing_spring`` (the closing
      springs as bodies), ``breaker`` (the whole breaker's contacts and poles), ``shaft_torque`` (its
      equations carry a further torque on the shaft: a discovered one); an effect applies to it exactly
      when it provides all the effect needs;
    - ``build(rig, spec, law, chain, user_function, ancf_elements) -> ExudynModel``;
    - ``channels(data, rig, spec, info) -> {name: array}`` from the sensors' rows (t, values...)
      of any backend (Exudyn, compiled, or the record's ``reference`` solve);
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
    - ``fit_step(rig, spring_kind)``, ``scan_step``, ``fit_user_function``: how fits run this experiment
      (each choice measured, with its reasoning at the record);
    - ``summary(result, rig)``: ``simulate``'s one-run summary, [(what, SI value, SI unit[, unit shown])]
      or a :class:`~vcbmodel.experiments.report.Report` (a closing's per-pole table against its limits);
    - ``record_channels(result, rig)``: the channels ``simulate`` writes, as a record file carries them;
    - ``sensor``, ``random_rig``: the usual sensor's kind and randomised rigs of this kind, for
      synthetic records with a known truth (:mod:`.random_rigs`; None: the studies use the
      reference rig);
    - ``reference``: its solve without Exudyn (:mod:`vcbmodel.reference`), the ``reference`` backend;
    - ``ode_model``: the experiment's equations for the compiled backend (:class:`vcbmodel.compiled.OdeModel`);
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
    provides: tuple = ()  # what its model carries that effects act on (above); (): no effect applies
    start_guesses: Callable = no_guesses
    swinging_part: Callable = whole_record
    signature: Callable = no_signature
    initial_angle_field: str | None = None
    period_fields: tuple = ()
    extra_channels: tuple = ()
    min_duration: float = 0.0  # s: a shorter record cannot show the experiment's motion
    max_magnitude: float = math.inf  # largest plausible |measured value| in ``unit``
    unit_hint: str = ""  # what a value beyond max_magnitude suggests ("degrees?")
    min_span: float = 0.0  # smallest plausible span of the measured channel in ``unit`` (a unit slip below it)
    small_hint: str = ""  # what a span below min_span suggests
    channel_hint: str = ""  # what a record without measured_channel should rename (an analyser's export)
    figure_units: tuple = ()  # ((column, unit), ...): what a sweep tabulates
    missing_means: tuple = ()  # ((column, status), ...): see run_status
    free_swing: bool = False  # a free swing: may start by hand, its centre gives the sensor offset, it has a period
    release_span: float = 0.002  # s: half-width of the search for the release time in a record
    staged_fit: bool = False  # fits fit the swinging part first, at twice the step, then the whole record
    release_from_model: bool = False  # the record's release time is found from the model's start of motion
    natural_frequency: Callable | None = None  # (rig) -> Hz of a free swing, diagnosis evidence
    fit_step: Callable = default_fit_step  # (rig, spring kind) -> step (s) of fits, None: ``step(rig)``
    scan_step: float | None = None  # step (s) of the grid scans ranking a fit's starts; None: the fit's
    fit_user_function: str = "python"  # friction connector of fits: python | symbolic | auto (measured per experiment)
    summary: Callable = figures_summary  # (result, rig) -> [(what, value, unit)] or a Report: simulate's summary
    record_channels: Callable = measured_only  # (result, rig) -> {channel: (values, unit)}: simulate's CSV
    ode_model: OdeModel | None = None  # its equations for the compiled backend (vcbmodel.compiled); None: Exudyn only
    reference: Callable | None = None  # (rig, spec, law, chain, t_end, method, step) -> (data, info): the solve without Exudyn
    sensor: str = ""  # the usual sensor's kind: potentiometer | camera (synthetic records' complications follow it)
    random_rig: Callable | None = None  # (rng, friction, start, variant) -> rig JSON: randomised rigs (random_rigs.py)
    #: model-form uncertainty (analysis/model_forms.py): whether its records resolve the friction's shape
    #: (the Stribeck range) so that the friction forms are fitted on them; the registered effects a form
    #: may add beside the selected model's, and those it is also fitted without
    friction_shapes: bool = False
    form_alternatives: tuple = ()
    form_removable: tuple = ()

    @property
    def has_closing_spring(self) -> bool:
        """Whether its model carries the closing springs (``closing_spring`` among ``provides``)."""
        return "closing_spring" in self.provides

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

    def check_record(self, t: np.ndarray, y: np.ndarray, source: str, others: Sequence[np.ndarray] = ()) -> None:
        """Refuse, before any work, a record this experiment cannot have produced: too short or too
        long, sampled implausibly fast or densely, a measured channel beyond its plausible range
        (a unit slip: degrees for rad, mm for m), or with no channel (``y`` and ``others``) that ever
        changes (one line, InputError)."""
        check_samples(t, source)
        steps = np.diff(t)
        if t.size > 2 and float(t[0]).is_integer() and np.all(steps == 1.0):
            raise InputError(source, "column 't'", f"counts in whole steps of 1 ({t[0]:g} to {t[-1]:g}): sample numbers, or "
                             "milliseconds of a 1 kHz record? It must be in seconds: give the time (sample number / "
                             "sample rate), or state its unit (t [ms])")
        self.check_duration(float(t[-1] - t[0]), source, "column 't'")
        spacing = float(np.min(np.diff(t)))
        if spacing < MIN_SAMPLE_INTERVAL:
            raise InputError(source, "column 't'", f"samples {spacing:.3g} s apart: no sensor of a {self.name} test samples "
                             f"faster than {1 / MIN_SAMPLE_INTERVAL:.3g} Hz; is the time column in seconds?"
                             + (" It reads like spreadsheet date-time serial numbers (days since 1900): give the time "
                                "in seconds, or as clock times (2026-11-27 10:00:00.000125)" if 1e4 < t[0] < 1e5 else ""))
        if t[-1] - t[0] < self.min_duration:
            raise InputError(source, "column 't'", f"the record lasts {t[-1] - t[0]:.3g} s: a {self.name} test needs at "
                             f"least {self.min_duration:g} s to show its motion")
        if t.size > MAX_SAMPLES:
            raise InputError(source, "data", f"{t.size} samples: more than {MAX_SAMPLES} (decimate the record to at most "
                             f"a few times {self.sample_rate:g} samples/s)")
        peak = float(np.max(np.abs(y)))
        if peak > self.max_magnitude:
            raise InputError(source, f"column {self.measured_channel!r}", f"reaches {peak:.4g}, implausible in "
                             f"{self.unit} for a {self.name} test (at most {self.max_magnitude:g})"
                             + (self.unit_hint if peak < 1000 * self.max_magnitude else ""))
        if 0.0 < float(np.ptp(y)) < self.min_span:
            raise InputError(source, f"column {self.measured_channel!r}", f"spans only {float(np.ptp(y)):.4g} {self.unit}, "
                             f"implausible for a {self.name} test (at least {self.min_span:g}){self.small_hint}")
        if float(np.ptp(y)) == 0.0 and all(float(np.ptp(v)) == 0.0 for v in others):
            raise InputError(source, f"column {self.measured_channel!r}", "never changes: the record shows no motion to "
                             "fit or compare (a disconnected sensor, or the wrong column?)")

    def check_duration(self, duration: float, source: str, field: str) -> None:
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


def shaft_channels(data: dict[str, np.ndarray], measured_channel: str) -> dict[str, np.ndarray]:
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

"""The one chain every study, fit and sweep calls: rig + options in, a result with units out
(the experiment's record supplies the builder, step, channels and sensor)."""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from .. import parameters as P
from ..builders.ancf import AncfOptions
from ..compiled import BACKEND_NAME, compiler_works, solve_ode_model
from ..laws.springs import chain_for
from ..model.effects import ModelSpec, assemble, consistent_effects
from ..model.result import SimulationResult
from ..model.values import model_values
from ..rig.data import Rig
from .base import experiment_of

if TYPE_CHECKING:
    from ..rig.spring_model import SpringModel
    from .base import Experiment


def model_spec(rig: Rig, effects: Sequence[str] | None = None, values: dict[str, float] | None = None,
               spring_model: str | SpringModel | None = None) -> ModelSpec:
    """The model of a run: the rig's ``model`` unless ``effects`` / ``spring_model`` (text or
    :class:`~vcbmodel.rig.spring_model.SpringModel`) override it; values given > rig; a value
    the effects need that neither gives is refused (:func:`vcbmodel.model.values.model_values`).

    Parameters
    ----------
    rig : the loaded rig.
    effects : effect names (default: the rig's ``model.effects``).
    values : effect parameter values, each in its parameter's unit (``mu_k`` -, ``stick_velocity``
        rad/s, ``viscous`` N m s/rad, ``bellows_force`` N, ...), overriding the rig's.
    spring_model : override of the rig's spring model (text such as ``lumped-2:paper``).

    Returns
    -------
    ModelSpec
        Effects, friction values (SI units, as above) and spring model of the run.
    """
    if spring_model is not None:
        rig = rig.with_model(spring_model=spring_model)
    effects = tuple(rig.model.effects if effects is None else effects)
    if spring_model is not None:
        effects = consistent_effects(effects, rig.model.spring_model)
    return assemble(rig, effects, model_values(rig, effects, values))


def output_times(rig: Rig, t_end: float) -> np.ndarray:
    """Sample times (s) from 0 to t_end at the experiment's sensor rate.

    Parameters
    ----------
    rig : the loaded rig (its experiment's ``sample_rate``, Hz).
    t_end : last time (s).

    Returns
    -------
    numpy.ndarray
        Times (s), 0, 1/rate, ... up to ``t_end``.
    """
    dt = 1.0 / experiment_of(rig.experiment).sample_rate
    n = int(np.floor(t_end / dt + 1e-9))
    return np.arange(n + 1) * dt


def simulate(rig: Rig, effects: Sequence[str] | None = None, values: dict[str, float] | None = None, *, spring_model: str | SpringModel | None = None,
             t_end: float | None = None, sample_times: np.ndarray | None = None, backend: str = "exudyn", user_function: str = "auto",
             step: float | None = None, method: str = "DOP853", ancf_elements: int | None = None, ancf_tie_stiffness: float | None = None,
             ancf: AncfOptions | None = None, sticking: str | None = None) -> SimulationResult:
    """Simulate the rig's experiment.

    Parameters
    ----------
    rig : the loaded rig; its ``model`` is used unless overridden.
    effects : effect names (default: the rig's ``model.effects``).
    values : effect parameter values (mu_k, mu_s, stick_velocity, stribeck_velocity, viscous,
        restitution, bellows_force), overriding the rig's.
    spring_model : override of the rig's spring model (text such as ``lumped-2:paper``).
    t_end : simulated duration (s); default the last sample time or the experiment's.
    sample_times : times (s) at which to return the channels (default: every step).
    backend : ``exudyn`` (the model), ``compiled`` (the same equations traced from the laws to C,
        :mod:`vcbmodel.compiled`: massless or lumped springs), ``fast``
        (compiled where it covers the model and a C compiler works, else exudyn) or ``reference``
        (the scipy solve). The result's ``info["backend"]`` names the one that ran.
    user_function : ``auto``, ``symbolic``, ``python`` (friction connector implementation).
    step : integration step (s), default from the experiment's record.
    method : reference backend only: ``DOP853`` (adaptive; ``step`` caps it) or ``rk4``.
    ancf_elements : elements of the ``ancf`` spring (default parameters.ANCF_ELEMENTS).
    ancf_tie_stiffness : its end ties' stiffness per spring (N/m, default ANCF_PENALTY_STIFFNESS);
        :func:`simulate_rigid_ties` extrapolates to rigid ties.
    ancf : :class:`~vcbmodel.builders.ancf.AncfOptions` (instead of the two above).
    sticking : ``passive`` (default, or the rig's ``friction.sticking``) or ``literal``.

    Returns
    -------
    SimulationResult
        Times ``t`` (s) and channels in SI units (``units`` names each: rad, rad/s, m, m/s, N, N m);
        ``info`` says which backend ran and with which step (s).
    """
    record = experiment_of(rig.experiment)
    spec = model_spec(rig, effects, values, spring_model)
    if sticking is not None:
        spec.sticking = sticking
    if t_end is None:
        t_end = float(sample_times[-1]) if sample_times is not None else record.default_duration
    chain = chain_for(rig.closing_spring, spec.spring_model) if record.has_closing_spring else None
    if ancf is None:
        ancf = AncfOptions(elements=ancf_elements or P.ANCF_ELEMENTS,
                           penalty_stiffness=ancf_tie_stiffness or P.ANCF_PENALTY_STIFFNESS)
    if backend == "fast":
        backend = "compiled" if compiled_covers(record, spec.spring_model) else "exudyn"
    if backend in ("exudyn", "compiled"):
        step, period = _step_and_period(rig, record, spec, ancf, step, sample_times)
        solve = _solve_compiled if backend == "compiled" else _solve_exudyn
        data, info = solve(rig, record, spec, spec.friction_law(rig.shaft_radius, step), chain, t_end, step, period,
                           user_function, ancf)
    elif backend == "reference":
        law = spec.friction_law(rig.shaft_radius, step if method == "rk4" else 0.0)
        if record.reference is None:
            raise ValueError(f"no reference solve for a {record.name} experiment: use backend='exudyn'")
        if spec.drag or spec.spring_damping:  # effects the independent solves do not carry: refused, not left out
            raise ValueError("the reference solve has no air drag or spring damping: use backend='exudyn' or 'compiled'")
        data, info = record.reference(rig, spec, law, chain, t_end, method, step)
    else:
        raise ValueError(f"unknown backend {backend!r}")
    result = SimulationResult(data["angle"][:, 0], record.channels(data, rig, spec, info), record.name,
                              record.measured_channel, spec, info, {record.measured_channel: record.unit})
    if sample_times is not None:
        result = result.resample(sample_times)
    return result


def compiled_path_has(record: Experiment, spring_model: SpringModel) -> bool:
    """Whether the compiled path has this model's equations: the experiment states them, and the
    spring is massless or lumped (the ANCF spring stays on Exudyn)."""
    return record.ode_model is not None and spring_model.kind != "ancf"


def compiled_covers(record: Experiment, spring_model: SpringModel) -> bool:
    """Whether the compiled path has this model (:func:`compiled_path_has`) and runs here (a C
    compiler: checked once, by compiling)."""
    return compiled_path_has(record, spring_model) and compiler_works()


def simulation_backend(record: Experiment, spring_model: SpringModel, backend: str = "fast") -> str:
    """The name of what runs ``backend`` (``fast``: compiled where it covers the model) for this
    experiment and spring model, as results report it."""
    if backend == "fast":
        backend = "compiled" if compiled_covers(record, spring_model) else "exudyn"
    return BACKEND_NAME if backend == "compiled" else backend


def _step_and_period(rig, record, spec, ancf, step, sample_times):
    """The fixed RK4 step (s) and the sensor period (s, None: every step). For uniform samples
    from t = 0 (a sensor's rate) the step shrinks to divide the sample spacing and only the
    sampled steps are stored (no interpolation, less memory)."""
    if step is None:
        step = ancf.step(rig.closing_spring) if spec.spring_model.kind == "ancf" else record.step(rig)
    period = None
    if sample_times is not None and len(sample_times) > 2:
        spacing = (sample_times[-1] - sample_times[0]) / (len(sample_times) - 1)
        uniform = np.max(np.abs(np.diff(sample_times) - spacing)) < 1e-9 * max(1.0, sample_times[-1])
        if uniform and abs(sample_times[0] / spacing - round(sample_times[0] / spacing)) < 1e-6:
            k = math.ceil(spacing / step - 1e-9)
            step, period = spacing / k, spacing
    return step, period


def _solve_exudyn(rig, record, spec, law, chain, t_end, step, period, user_function, ancf):
    """The Exudyn model the experiment's record builds, solved with RK4 at ``step``."""
    model = record.build(rig, spec, law, chain, user_function, ancf)
    data = model.solve(t_end, step, period)
    return data, {"backend": "exudyn", "step": step, "initial": getattr(model, "initial", None)}


def _solve_compiled(rig, record, spec, law, chain, t_end, step, period, user_function=None, ancf=None):
    if not compiled_path_has(record, spec.spring_model):
        raise ValueError(f"the compiled backend covers the pendulum, the cam drop and the closing with a massless "
                         f"or lumped spring, not {record.name} with a {spec.spring_model.kind} spring: use backend='exudyn'")
    data, extra = solve_ode_model(record.ode_model, rig, spec, law, chain, t_end, step, period)
    return data, {"backend": BACKEND_NAME, "step": step, "initial": extra.get("initial")}


def extrapolate_ties(value_1: np.ndarray, value_2: np.ndarray, k1: float, k2: float) -> np.ndarray:
    """Richardson extrapolation to rigid ties, value(k) = value_inf + c / k:
    value_inf = (k2 value_2 - k1 value_1) / (k2 - k1)."""
    return (k2 * np.asarray(value_2) - k1 * np.asarray(value_1)) / (k2 - k1)


def simulate_rigid_ties(rig: Rig, effects: Sequence[str] | None = None, values: dict[str, float] | None = None, *, sample_times: np.ndarray,
                        stiffnesses: tuple[float, float] = (1e8, 1e9), ancf: AncfOptions | None = None, **options) -> SimulationResult:
    """The rig with an ANCF spring whose end ties are extrapolated to infinite stiffness: two
    runs with tie stiffnesses ``stiffnesses`` (N/m per spring) combined channel by channel by
    :func:`extrapolate_ties` (the truth of the spring studies; about 4x one run). ``ancf``:
    :class:`~vcbmodel.builders.ancf.AncfOptions` (elements, EI); ``options`` go to :func:`simulate`."""
    k1, k2 = stiffnesses
    base = ancf or AncfOptions()
    runs = [simulate(rig, effects, values, spring_model="ancf", sample_times=sample_times,
                     ancf=replace(base, penalty_stiffness=k), **options) for k in (k1, k2)]
    a, b = runs
    channels = {name: extrapolate_ties(a.channels[name], b.channels[name], k1, k2) for name in b.channels}
    info = dict(b.info, ties=f"extrapolated to rigid from {k1:g} and {k2:g} N/m")
    return SimulationResult(b.t, channels, b.experiment, b.measured_channel, b.spec, info, b.units)

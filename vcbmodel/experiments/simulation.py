"""The one chain every study, fit and sweep calls: rig + options in, a result with units out
(the experiment's record supplies the builder, step, channels and sensor)."""
from __future__ import annotations

import math

import numpy as np

from .. import parameters as P
from ..laws.springs import chain_for
from ..model.effects import ModelSpec, assemble, consistent_effects
from ..model.result import SimulationResult
from ..model.values import model_values
from ..reference.solve import simulate_reference
from ..rig.data import Rig
from .base import experiment_of


def model_spec(rig: Rig, effects=None, values=None, spring_model=None) -> ModelSpec:
    """The model of a run: the rig's ``model`` unless ``effects`` / ``spring_model`` (text or
    :class:`~vcbmodel.rig.spring_model.SpringModel`) override it; values given > rig; a value
    the effects need that neither gives is refused (:func:`vcbmodel.model.values.model_values`)."""
    if spring_model is not None:
        rig = rig.with_model(spring_model=spring_model)
    effects = tuple(rig.model.effects if effects is None else effects)
    if spring_model is not None:
        effects = consistent_effects(effects, rig.model.spring_model)
    return assemble(rig, effects, model_values(rig, effects, values))


def output_times(rig, t_end):
    """Sample times (s) from 0 to t_end at the experiment's sensor rate."""
    dt = 1.0 / experiment_of(rig.experiment).sample_rate
    n = int(np.floor(t_end / dt + 1e-9))
    return np.arange(n + 1) * dt


def ancf_step(elements=None):
    """RK4 step (s) for the ANCF spring: ANCF_STEP up to ANCF_ELEMENTS elements, shorter in
    proportion above (the fastest element modes scale with the number of elements)."""
    return P.ANCF_STEP * min(1.0, P.ANCF_ELEMENTS / (elements or P.ANCF_ELEMENTS))


def simulate(rig: Rig, effects=None, values=None, *, spring_model=None, t_end=None, sample_times=None,
             backend="exudyn", user_function="auto", step=None, method="DOP853",
             ancf_elements=None, sticking=None) -> SimulationResult:
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
    backend : ``exudyn`` (the model) or ``reference`` (the scipy solve).
    user_function : ``auto``, ``symbolic``, ``python`` (friction connector implementation).
    step : integration step (s), default from the experiment's record.
    method : reference backend only: ``DOP853`` (adaptive; ``step`` caps it) or ``rk4``.
    ancf_elements : elements of the ``ancf`` spring (default parameters.ANCF_ELEMENTS).
    sticking : ``passive`` (default, or the rig's ``friction.sticking``) or ``literal``.
    """
    record = experiment_of(rig.experiment)
    spec = model_spec(rig, effects, values, spring_model)
    if sticking is not None:
        spec.sticking = sticking
    if t_end is None:
        t_end = float(sample_times[-1]) if sample_times is not None else record.default_duration
    chain = chain_for(rig.closing_spring, spec.spring_model) if record.has_closing_spring else None
    if backend == "exudyn":
        if step is None:
            step = ancf_step(ancf_elements) if spec.spring_model.kind == "ancf" else record.step(rig)
        period = None
        if sample_times is not None and len(sample_times) > 2:
            # uniform samples from t = 0 (a sensor's rate): shrink the step to divide the sample
            # spacing and store only the sampled steps (no interpolation, less memory)
            spacing = (sample_times[-1] - sample_times[0]) / (len(sample_times) - 1)
            uniform = np.max(np.abs(np.diff(sample_times) - spacing)) < 1e-9 * max(1.0, sample_times[-1])
            if uniform and abs(sample_times[0] / spacing - round(sample_times[0] / spacing)) < 1e-6:
                k = math.ceil(spacing / step - 1e-9)
                step, period = spacing / k, spacing
        law = spec.friction_law(rig.shaft_radius, step)
        model = record.build(rig, spec, law, chain, user_function, ancf_elements)
        data = model.solve(t_end, step, period)
        info = {"backend": "exudyn", "step": step, "initial": getattr(model, "initial", None)}
    elif backend == "reference":
        law = spec.friction_law(rig.shaft_radius, step if method == "rk4" else 0.0)
        data, info = simulate_reference(rig, spec, law, chain, t_end, method, step)
    else:
        raise ValueError(f"unknown backend {backend!r}")
    result = SimulationResult(data["angle"][:, 0], record.channels(data, rig, spec, info), record.name,
                              record.measured_channel, spec, info, {record.measured_channel: record.unit})
    if sample_times is not None:
        result = result.resample(sample_times)
    return result

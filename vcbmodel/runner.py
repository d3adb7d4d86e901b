"""The one runner every study, fit and sweep calls: rig + options in, named channels out."""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from . import parameters as P
from .effects import ModelSpec, assemble, parameter_specs
from .friction import viscous_from_zeta
from .rig import CHANNEL_OF_EXPERIMENT, Rig, lumped_mass_count
from .springs import lumped_chain


@dataclass
class SimulationResult:
    """Channels sampled at ``t`` (s). Angles in rad, velocities in rad/s, torques in N m,
    positions in m. ``angle`` is the experiment's measured channel (``pendulum_angle`` or
    ``cam_angle``)."""

    t: np.ndarray
    channels: dict
    experiment: str
    spec: ModelSpec
    info: dict = field(default_factory=dict)

    @property
    def angle(self):
        return self.channels[CHANNEL_OF_EXPERIMENT[self.experiment]]

    def resample(self, t):
        """The channels linearly interpolated at times ``t`` (s)."""
        return SimulationResult(np.asarray(t), {k: np.interp(t, self.t, v) for k, v in self.channels.items()},
                                self.experiment, self.spec, self.info)


def rig_values(rig: Rig):
    """Effect parameter values the rig gives: friction (``zeta`` converted to ``viscous`` for
    the pendulum) and, for the whole breaker, ``restitution`` and ``bellows_force``."""
    values = dict(rig.friction)
    if rig.breaker is not None:
        for key, value in (("restitution", rig.breaker.contact.restitution),
                           ("bellows_force", rig.breaker.poles.bellows_force)):
            if value is not None:
                values[key] = value
    if "zeta" in values and "viscous" not in values and rig.pendulum is not None:
        p = rig.pendulum
        values["viscous"] = viscous_from_zeta(values["zeta"], p.inertia, p.mass, rig.gravity, p.com_distance)
    values.pop("zeta", None)
    return values


def model_values(rig: Rig, effects, values=None):
    """All parameter values the effects need: given > rig > the registry's starting guess."""
    out = {p.name: p.initial for p in parameter_specs(effects)}
    out.update(rig_values(rig))
    out.update(values or {})
    return out


def model_spec(rig: Rig, effects=None, values=None, spring_model=None) -> ModelSpec:
    effects = tuple(rig.model.effects if effects is None else effects)
    if spring_model is not None:
        rig = rig.with_model(spring_model=spring_model)
    spec = assemble(rig, effects, model_values(rig, effects, values))
    if spring_model is not None and "spring_mass" not in effects and spring_model != "massless":
        spec.spring_model = spring_model
    return spec


def default_t_end(rig):
    return {"pendulum": P.PENDULUM_T_END, "cam_drop": P.CAM_T_END, "vcb_closing": P.BREAKER_T_END}[rig.experiment]


def default_step(rig, law):
    """Fixed Runge-Kutta step (s). Pendulum: at most PENDULUM_STEP and small enough that one
    step at the release acceleration changes the speed by 1.5 w0, less than the width 2 w0 of
    the stick band, so a reversing shaft cannot jump over it (Karnopp). Cam: CAM_STEP."""
    if rig.experiment == "cam_drop":
        return P.CAM_STEP
    if rig.experiment == "vcb_closing":
        return P.BREAKER_STEP
    p = rig.pendulum
    acc = p.mass * rig.gravity * p.com_distance * max(abs(math.sin(p.initial_angle)), 1e-3) / p.inertia
    acc = max(acc, abs(p.initial_velocity) * 2 * math.pi / 1.0)
    return float(min(P.PENDULUM_STEP, max(1.5 * law.stick_velocity / acc, 1e-5)))


def ancf_step(elements=None):
    """RK4 step (s) for the ANCF spring: ANCF_STEP up to ANCF_ELEMENTS elements, shorter in
    proportion above (the fastest element modes scale with the number of elements)."""
    return P.ANCF_STEP * min(1.0, P.ANCF_ELEMENTS / (elements or P.ANCF_ELEMENTS))


def simulate(rig: Rig, effects=None, values=None, *, spring_model=None, t_end=None, sample_times=None,
             backend="exudyn", user_function="auto", step=None, method="DOP853",
             ancf_elements=None) -> SimulationResult:
    """Simulate the rig's experiment.

    Parameters
    ----------
    rig : the loaded rig; its ``model`` is used unless overridden.
    effects : effect names (default: the rig's ``model.effects``).
    values : friction parameter values (mu_k, mu_s, stick_velocity, stribeck_velocity,
        viscous), overriding the rig's ``friction``.
    spring_model : override of the rig's spring model.
    t_end : simulated duration (s); default the last sample time or 6 s / 35 ms.
    sample_times : times (s) at which to return the channels (default: every step).
    backend : ``exudyn`` (the model) or ``reference`` (the independent scipy solve).
    user_function : ``auto``, ``symbolic``, ``python`` (friction connector implementation).
    step : integration step (s), default from :mod:`vcbmodel.parameters`.
    method : reference backend only: ``DOP853`` (adaptive; ``step`` caps it) or ``rk4``.
    ancf_elements : elements of the ``ancf`` spring (default parameters.ANCF_ELEMENTS).
    """
    spec = model_spec(rig, effects, values, spring_model)
    if t_end is None:
        t_end = float(sample_times[-1]) if sample_times is not None else default_t_end(rig)
    law = spec.friction_law(rig.shaft_radius)
    chain = None
    if rig.experiment in ("cam_drop", "vcb_closing"):
        n = lumped_mass_count(spec.spring_model)
        if n > 0:
            s = rig.closing_spring
            chain = lumped_chain(n, s.stiffness, s.mass, s.free_length, spec.lumped_convention)
    if backend == "exudyn":
        if step is None:
            step = ancf_step(ancf_elements) if spec.spring_model == "ancf" else default_step(rig, law)
        period = None
        if sample_times is not None and len(sample_times) > 2:
            # uniform samples from t = 0 (a sensor's rate): shrink the step to divide the sample
            # spacing and store only the sampled steps (no interpolation, less memory)
            spacing = (sample_times[-1] - sample_times[0]) / (len(sample_times) - 1)
            uniform = np.max(np.abs(np.diff(sample_times) - spacing)) < 1e-9 * max(1.0, sample_times[-1])
            if uniform and abs(sample_times[0] / spacing - round(sample_times[0] / spacing)) < 1e-6:
                k = math.ceil(spacing / step - 1e-9)
                step, period = spacing / k, spacing
        result = _simulate_exudyn(rig, spec, law, chain, t_end, step, user_function, period, ancf_elements)
    elif backend == "reference":
        from .reference import simulate_reference
        result = simulate_reference(rig, spec, law, chain, t_end, method, step)
    else:
        raise ValueError(f"unknown backend {backend!r}")
    if sample_times is not None:
        result = result.resample(sample_times)
    return result


def _simulate_exudyn(rig, spec, law, chain, t_end, step, user_function, sensor_period=None, ancf_elements=None):
    from .exudyn_models import build_cam_drop, build_pendulum
    from .rig import lumped_mass_count

    if rig.experiment == "pendulum":
        uf = "symbolic" if user_function == "auto" else user_function
        model = build_pendulum(rig, law, uf)
    elif rig.experiment == "vcb_closing":
        from .breaker_model import build_vcb_closing, closing_channels
        model = build_vcb_closing(rig, spec, law, chain, user_function, ancf_elements)
        data = model.solve(t_end, step, sensor_period)
        return closing_channels(model, data, rig, spec, step)
    else:
        if lumped_mass_count(spec.spring_model) < 0:
            from .ancf_spring import build_cam_drop_ancf
            model = build_cam_drop_ancf(rig, law, user_function=user_function, elements=ancf_elements)
        else:
            model = build_cam_drop(rig, law, chain, user_function)
    data = model.solve(t_end, step, sensor_period)
    t = data["angle"][:, 0]
    channels = {CHANNEL_OF_EXPERIMENT[rig.experiment]: data["angle"][:, 1],
                "shaft_velocity": data["velocity"][:, 1]}
    if "friction_torque" in data:
        channels["friction_torque"] = -data["friction_torque"][:, 1]
    for name, d in data.items():
        if name.startswith("spring_mass_") or name.startswith("ancf_"):
            channels[name + "_x"] = d[:, 1]
            channels[name + "_y"] = d[:, 2]
    return SimulationResult(t, channels, rig.experiment, spec, {"backend": "exudyn", "step": step})

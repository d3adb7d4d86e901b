"""Checks of a run: what it is asked to do (:func:`check_call`: the Python API's arguments, each fault an
InputError naming it), and what it did: it must not create energy, and its cam (or pendulum) must have
moved.

:func:`audit_energy` balances every kinetic, potential and dissipated term of a run against what it
started with; a run that ends with more than :data:`vcbmodel.parameters.ENERGY_CREATED_FRACTION` of
its starting energy unaccounted for created energy (an unstable step, a stiffness the step cannot
integrate) and is a failed run (SimulationError), never a result. The closing uses its own balance
(:func:`vcbmodel.experiments.closing_evaluation.energy_balance`); the pendulum and the cam drop have
theirs here. :func:`require_motion` says plainly that the cam did not move.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from scipy.integrate import cumulative_trapezoid

from .. import parameters as P
from ..errors import InputError, SimulationError
from ..model.effects import EFFECTS, MACHINERY, parameter_specs
from ..laws.springs import chain_for
from .closing_evaluation import _spring_parts, energy_balance

if TYPE_CHECKING:
    from ..model.result import SimulationResult
    from ..rig.data import Rig


BACKENDS = ("exudyn", "compiled", "fast", "reference")


def check_call(effects: object, values: object, t_end: object, step: object, sample_times: object, backend: object) -> None:
    """Refuse, naming the argument, what :func:`vcbmodel.experiments.simulation.simulate` cannot run
    faithfully: an unknown backend or effect, a value no effect has (a typo such as ``mu_q`` would
    otherwise be ignored), a negative or non-finite value, a duration or step that is not a positive
    number, sample times out of order."""
    if backend not in BACKENDS:
        raise InputError("simulate", "backend", f"must be one of {', '.join(BACKENDS)}, got {backend!r}")
    known = set(EFFECTS) | set(MACHINERY)
    for name in effects or ():
        if name not in known:
            raise InputError("simulate", "effects", f"unknown effect {name!r} (known: {', '.join(known)})")
    names = {p.name for p in parameter_specs(EFFECTS)}
    for name, value in (values or {}).items():
        if any(str(name).startswith(m.prefix) for m in MACHINERY.values()):
            continue
        if name not in names:
            raise InputError("simulate", f"values.{name}", f"no effect has this value (known: {', '.join(sorted(names))})")
        if isinstance(value, bool) or not isinstance(value, (int, float, np.floating)) or not math.isfinite(value) or value < 0:
            raise InputError("simulate", f"values.{name}", f"must be a finite number, not negative, got {value!r}")
    for name, value in (("t_end", t_end), ("step", step)):
        if value is not None and not (isinstance(value, (int, float, np.floating)) and math.isfinite(value) and value > 0):
            raise InputError("simulate", name, f"must be a positive number of seconds, got {value!r}")
    if sample_times is not None:
        times = np.asarray(sample_times, dtype=float)
        if (times.ndim != 1 or times.size < 2 or not np.all(np.isfinite(times)) or times[0] < 0 or times[-1] <= 0
                or np.any(np.diff(times) < 0)):
            raise InputError("simulate", "sample_times", "must be finite times from 0 on, in order, ending after 0 (s)")


def _friction_dissipated(result: SimulationResult) -> np.ndarray:
    """Work (J, cumulative) the shaft friction took from the shaft: -T_friction omega integrated."""
    ch = result.channels
    w = ch["shaft_velocity"]
    power = -ch["friction_torque"] * w if "friction_torque" in ch else np.zeros_like(w)
    return cumulative_trapezoid(power, result.t, initial=0.0)


def pendulum_balance(result: SimulationResult, rig: Rig) -> tuple[np.ndarray, float]:
    """(residual J over time, starting energy J) of a pendulum swing (paper eq. 1): kinetic
    I w^2 / 2 plus the weight's M g L (1 - cos theta), plus what friction dissipated."""
    p, ch = rig.pendulum, result.channels
    theta, w = ch["pendulum_angle"], ch["shaft_velocity"]
    energy = 0.5 * p.inertia * w**2 + p.mass * rig.gravity * p.com_distance * (1.0 - np.cos(theta))
    residual = energy + _friction_dissipated(result) - energy[0]
    return residual, float(energy[0])


def cam_drop_balance(result: SimulationResult, rig: Rig) -> tuple[np.ndarray, float] | None:
    """(residual J, starting energy J) of a cam drop (paper eq. 7-13): the cam's kinetic energy and
    weight, the closing springs' elastic energy and, for a lumped chain, its masses' kinetic energy,
    plus the friction's work. None for the ANCF spring (its energy is Exudyn's own)."""
    if result.spec.spring_model.kind == "ancf":
        return None
    cam, ch = rig.cam, result.channels
    theta, w = ch["cam_angle"], ch["shaft_velocity"]
    parts = _spring_parts(ch, rig, chain_for(rig.closing_spring, result.spec.spring_model))
    energy = (0.5 * cam.inertia_pivot * w**2 + cam.mass * rig.gravity * cam.com_distance * np.sin(theta - cam.com_angle)
              + sum(parts.values()))
    residual = energy + _friction_dissipated(result) - energy[0]
    return residual, float(parts["closing_springs"][0])


def closing_balance(result: SimulationResult, rig: Rig) -> tuple[np.ndarray, float] | None:
    """(residual J, starting energy J: the charged springs' and the latch's work) of a closing, from
    :func:`energy_balance`. None for the ANCF spring (not covered by the balance)."""
    if result.spec.spring_model.kind == "ancf":
        return None
    balance = energy_balance(result, rig)
    start = float(balance["closing_springs"][0]) + float(np.max(np.abs(balance["latch_work"])))
    return balance["residual"], start


BALANCES = {"pendulum": pendulum_balance, "cam_drop": cam_drop_balance, "vcb_closing": closing_balance}


def audit_energy(result: SimulationResult, rig: Rig) -> float | None:
    """Raise SimulationError (one line) when the run created energy: its balance's residual above
    ``ENERGY_CREATED_FRACTION`` of the energy it started with. Returns the largest residual as a
    fraction of that energy (None: no balance for this model)."""
    balance = BALANCES.get(result.experiment)
    out = balance(result, rig) if balance is not None else None
    if out is None:
        return None
    residual, start = out
    if not np.all(np.isfinite(residual)):
        raise SimulationError("the run's energy is not finite: the solve diverged (a stiffness or damper the fixed "
                              "step cannot integrate; vcbmodel check names the unusual values)")
    k = int(np.argmax(residual))
    scale = max(start, 1e-12)
    if residual[k] > P.ENERGY_CREATED_FRACTION * scale:
        w = float(np.max(np.abs(result.channels["shaft_velocity"])))
        raise SimulationError(f"the run created energy: {residual[k]:.3g} J more than the {start:.3g} J it started with "
                              f"by {1e3 * result.t[k]:.4g} ms (shaft up to {w:.3g} rad/s): a numerical instability, not "
                              "a result; a stiffness or damper far above the usual (vcbmodel check names unusual "
                              "values) or a step too long for the model")
    return float(np.max(residual) / scale)


def require_motion(result: SimulationResult, rig: Rig) -> None:
    """Raise SimulationError, said plainly, when the shaft (cam or pendulum) turned less than
    ``CAM_DID_NOT_MOVE`` over the whole run and never left the friction's stick band (at rest: a run
    too short to show motion yet is not judged), after the latch's release: nothing in it is a
    closing, a drop or a swing."""
    channel = "pendulum_angle" if result.experiment == "pendulum" else "cam_angle"
    if channel not in result.channels or "shaft_velocity" not in result.channels:
        return  # an experiment without a shaft (a registered oscillator): nothing to judge
    angle = result.channels[channel]
    turned = float(np.max(np.abs(angle - angle[0])))
    fastest = float(np.max(np.abs(result.channels["shaft_velocity"])))
    at_rest = max(getattr(result.spec, "stick_velocity", 0.0) or 0.0, 1e-6)  # the friction's stick band: at rest
    release = rig.breaker.latch_release_time if rig.breaker is not None else 0.0
    if turned >= P.CAM_DID_NOT_MOVE or fastest > at_rest or result.t[-1] <= release:
        return
    what = "pendulum did not swing" if result.experiment == "pendulum" else "cam did not move"
    held = ("static friction holds it at its initial angle" if result.experiment == "pendulum" else
            "what holds it (the latch, friction, the opening spring, the poles' weight and loads) outweighs the closing "
            "springs' torque")
    raise SimulationError(f"the {what}: it turned {math.degrees(turned):.3g} deg in {1e3 * result.t[-1]:.4g} ms; {held}. "
                          f"Check the rig's values (vcbmodel check {rig.path}); a longer --t-end will not help")

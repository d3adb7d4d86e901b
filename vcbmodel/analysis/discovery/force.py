"""The missing generalized force: what the record's motion needs beyond the fitted model.

The record is read in the model's coordinate with the fit's own alignment (release time, clock scale, sensor
offset and gain; rig values the fit estimated), smoothed with a Savitzky-Golay filter to the
shaft angle theta (rad), speed w (rad/s) and acceleration alpha (rad/s^2) (:func:`measured_state`:
the fitted model's trajectory plus the smoothed difference of the record from it). On that measured
state the model's own equations (the experiment's ``ode_model``, the same law functions the
compiled path and Exudyn run, evaluated through :class:`~vcbmodel.laws.friction.ArrayOps`) give
the acceleration the model would have there; the missing torque is the shaft's inertia times the
difference, ``I (alpha - alpha_model(theta, w))`` in N m. The inertia is read off the equations
too: the change of the acceleration under a unit applied torque.

A lumped closing spring's masses move with states of their own that the record does not hold: their
positions and speeds are taken from the fitted model's own trajectory (the chain as the fitted model
moves it), and the cam's acceleration is read on the measured cam state with that chain. Where the
cam's motion differs from the model's, the chain's does too, so the estimate is a proposal only: the
refit of the whole record decides (:mod:`.refit`). The ANCF spring has no equations outside Exudyn:
it is not read.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from scipy.signal import savgol_filter

from ...experiments import experiment_of
from ...experiments.simulation import model_spec, simulate
from ...laws.friction import ArrayOps
from ...laws.springs import chain_for
from ...rig.paths import loaded_with
from ..fit.dataset import model_time, time_scale_name

if TYPE_CHECKING:
    from ...rig.data import Rig
    from ..fit import FitResult

#: Smoothing window of the Savitzky-Golay filter, as a fraction of the swing period: a cubic over
#: a tenth of a period follows a sine to 0.2 % in its second derivative while averaging over
#: about a hundred samples at 1 kHz (the acceleration's noise falls as the window^2.5).
WINDOW_FRACTION = 0.1
#: The same for a motion without a period (the cam drop, one stroke), as a fraction of the record's
#: window (release to end): a 35 ms drop at 12 kHz is smoothed over 7 ms, 85 samples. A camera's
#: 2 mrad at 12 kHz differentiated twice over a tenth of the stroke leaves an acceleration noise of
#: the order of the cam's whole friction torque; over a fifth it is 5.7 times smaller, and a rub a
#: few ms long is still located to within a window of the library (the refit to the record decides).
STROKE_WINDOW_FRACTION = 0.2
#: Polynomial order of the filter (cubic: the second derivative is a line across the window).
POLYORDER = 3
#: Samples slower than this fraction of the record's peak speed are not used: around a reversal
#: the friction flips sign within the smoothing window, and the model's torque on the smoothed
#: state is wrong there by up to twice the friction.
SLOW_FRACTION = 0.05


@dataclass
class ForceEstimate:
    """The missing torque on the aligned record. Arrays on the record's window samples: ``t``
    model time since release (s), ``theta`` (rad), ``w`` (rad/s), ``alpha`` (rad/s^2), the
    model's acceleration on that state ``alpha_model`` (rad/s^2), ``torque`` the missing torque
    (N m), ``used`` the samples fit for regression (bool); ``inertia`` (kg m^2) and the
    smoothing ``window_s`` (s); ``rig`` the rig with the fit's estimated values; ``chain``: a lumped
    spring's masses as the fitted model moves them, (positions, speeds), each a list of arrays x1, y1,
    x2, ... (m, m/s; empty for massless springs)."""

    t: np.ndarray
    theta: np.ndarray
    w: np.ndarray
    alpha: np.ndarray
    alpha_model: np.ndarray
    torque: np.ndarray
    used: np.ndarray
    inertia: float
    window_s: float
    rig: object
    units: dict
    chain: tuple = ()


def unread(rig: Rig, fit: FitResult) -> str | None:
    """Why the missing torque cannot be read on ``fit``'s model, or None: a massless or lumped spring
    is read (a chain with the fitted model's own chain state, module docstring); an ANCF cable's
    equations are Exudyn's alone."""
    if experiment_of(rig.experiment).has_closing_spring and fit.spring_model.kind not in ("massless", "lumped"):
        return (f"the missing torque is read with massless or lumped closing springs; the {fit.spring_model.label} "
                "spring's equations are Exudyn's alone")
    return None


def fitted_rig(rig: Rig, fit: FitResult) -> Rig:
    """``rig`` with the values ``fit`` estimated for it (an inertia, an initial angle)."""
    overrides = {p.path: p.value for p in fit.parameters.values() if p.kind in ("state", "rig") and p.path
                 and not p.path.startswith("friction.")}
    return loaded_with(rig, overrides)


def model_acceleration(rig, fit, t: np.ndarray, theta: np.ndarray, w: np.ndarray, extra: tuple = (),
                       chain: tuple = ()) -> np.ndarray:
    """The fitted model's shaft acceleration (rad/s^2) at states (t s, theta rad, w rad/s), from the
    experiment's equations through ArrayOps; ``extra``: further discovered terms ((name, coefficient), ...);
    ``chain``: a lumped spring's (positions, speeds) at the same samples (:class:`ForceEstimate`)."""
    rec = experiment_of(rig.experiment)
    values = dict(fit.model_values)
    effects = tuple(fit.effects)
    if extra:
        effects = effects + ("discovered_torque",) if "discovered_torque" not in effects else effects
        values.update({f"discovered:{name}": c for name, c in extra})
    spec = model_spec(rig, effects, values, fit.spring_model)
    lumped = chain_for(rig.closing_spring, spec.spring_model) if rec.has_closing_spring else None
    setup = rec.ode_model.prepare(rig, spec, spec.friction_law(rig.shaft_radius, 0.0), lumped)
    q, v = [theta] + list(chain[0] if chain else ()), [w] + list(chain[1] if chain else ())
    with np.errstate(all="ignore"):
        acc, _ = rec.ode_model.equations(t, q, v, list(setup.memory), setup.inputs, ArrayOps)
    return np.broadcast_to(np.asarray(acc[0], float), np.shape(theta)).copy()


def shaft_inertia(rig, fit, t: np.ndarray, theta: np.ndarray, w: np.ndarray, chain: tuple = ()) -> float:
    """The inertia (kg m^2) the equations divide an applied torque by: 1 / (change of the
    acceleration under a constant 1 N m), at a sample where the shaft moves fastest."""
    i = int(np.argmax(np.abs(w)))
    sl = slice(i, i + 1)
    at = tuple([a[sl] for a in part] for part in chain)
    base = model_acceleration(rig, fit, t[sl], theta[sl], w[sl], chain=at)
    pushed = model_acceleration(rig, fit, t[sl], theta[sl], w[sl], extra=(("constant", 1.0),), chain=at)
    return float(1.0 / (pushed[0] - base[0]))


def smoothing_points(rig, dt: float, duration: float) -> int:
    """Odd number of samples of the filter's window: WINDOW_FRACTION of the swing period, or
    STROKE_WINDOW_FRACTION of ``duration`` (s, the record's window) for a motion without one."""
    rec = experiment_of(rig.experiment)
    span = WINDOW_FRACTION / rec.natural_frequency(rig) if rec.natural_frequency else STROKE_WINDOW_FRACTION * duration
    n = int(round(span / dt)) | 1
    return max(n, 2 * POLYORDER + 3)


def measured_state(rig, dataset, fit) -> tuple:
    """(t model time s, theta rad, w rad/s, alpha rad/s^2, window s, chain) of the record's window,
    aligned with ``fit``: the fitted model's own trajectory plus the smoothed difference of the record
    from it; ``chain``: a lumped spring's state on the model's trajectory (:class:`ForceEstimate`).
    Only the difference is smoothed, so the filter's bias scales with what the model misses, not
    with the swing (smoothing the swing itself biases its acceleration by a percent, which passes for
    a torque in sin(k theta))."""
    values = fit.values
    setup = dataset.setup
    mask = dataset.mask()
    t_rec = dataset.t[mask]
    y = dataset.y[mask]
    release = values.get("release_time_0", setup.release if setup is not None else 0.0)
    offset = values.get("sensor_offset_0", 0.0)
    gain = values.get("sensor_gain_0", 1.0)
    scale = values.get(time_scale_name(0), 1.0)  # a record's clock a fraction of a percent off
    dt = float(np.median(np.diff(t_rec))) * scale
    tau = model_time(t_rec, release, scale)
    n = smoothing_points(rig, dt, float(tau[-1] - max(float(tau[0]), 0.0)))
    if n >= y.size:
        raise ValueError(f"the record's window holds {y.size} samples: too few to smooth over {n}")
    sim = simulate(rig, fit.effects, fit.model_values, spring_model=fit.spring_model,
                   sample_times=np.clip(tau, 0.0, None), backend="fast")
    theta_m, w_m = sim.measured, sim.channels["shaft_velocity"]
    alpha_m = model_acceleration(rig, fit, tau, theta_m, w_m)
    diff = (y - offset) / gain - theta_m
    theta = theta_m + savgol_filter(diff, n, POLYORDER)
    w = w_m + savgol_filter(diff, n, POLYORDER, deriv=1, delta=dt)
    alpha = alpha_m + savgol_filter(diff, n, POLYORDER, deriv=2, delta=dt)
    return tau, theta, w, alpha, n * dt, _chain_state(sim.channels)


def _chain_state(channels: dict) -> tuple:
    """(positions, speeds) of a lumped chain's masses in a simulation's channels ((): none)."""
    count = sum(1 for name in channels if name.startswith("spring_mass_") and name.endswith("_x"))
    if not count:
        return ()
    positions = [channels[f"spring_mass_{k}_{a}"] for k in range(1, count + 1) for a in "xy"]
    speeds = [channels[f"spring_velocity_{k}_{a}"] for k in range(1, count + 1) for a in "xy"]
    return positions, speeds


def missing_torque(rig, dataset, fit) -> ForceEstimate:
    """The missing torque of ``fit`` on ``dataset`` (module docstring)."""
    rig_fit = fitted_rig(rig, fit)
    t, theta, w, alpha, window_s, chain = measured_state(rig_fit, dataset, fit)
    alpha_model = model_acceleration(rig_fit, fit, t, theta, w, chain=chain)
    inertia = shaft_inertia(rig_fit, fit, t, theta, w, chain)
    torque = inertia * (alpha - alpha_model)
    half = int(round(window_s / max(float(np.median(np.diff(t))), 1e-12))) // 2
    used = np.abs(w) > SLOW_FRACTION * float(np.max(np.abs(w)))
    used[:half] = used[-half:] = False  # the filter's ends are extrapolations
    used &= np.isfinite(torque) & (t >= 0.0)
    units = {"t": "s", "theta": "rad", "w": "rad/s", "alpha": "rad/s^2", "torque": "N m", "inertia": "kg m^2"}
    if not math.isfinite(inertia) or inertia <= 0:
        raise ValueError(f"the model's equations give no positive shaft inertia ({inertia!r} kg m^2)")
    return ForceEstimate(t, theta, w, alpha, alpha_model, torque, used, inertia, window_s, rig_fit, units, chain)

"""The pendulum test (paper section 2): a weight on a link swings on the cam shaft."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .. import parameters as P
from ..builders.pendulum import build_pendulum
from ..compiled import OdeModel
from ..reference.solve import reference_pendulum
from ..compiled.equations import pendulum_equations, prepare_pendulum
from ..records.signals import decay_shape, first_peak_amplitude, motion_end_time, swing_peaks, swing_spans
from ..rig.sections import read_pendulum
from .random_rigs import pendulum_random_rig
from .base import Experiment, refuse_discovered_torque, shaft_channels
from .summaries import pendulum_summary

if TYPE_CHECKING:
    from ..builders.ancf import AncfOptions
    from ..builders.core import ExudynModel
    from ..laws.friction import FrictionLaw
    from ..laws.springs import LumpedChain
    from ..model.effects import ModelSpec
    from ..model.result import SimulationResult
    from ..records.measurement import Measurement
    from ..rig.data import Rig


def build(rig: Rig, spec: ModelSpec, law: FrictionLaw, chain: LumpedChain | None, user_function: str,
          ancf_elements: AncfOptions | int | None) -> ExudynModel:
    return build_pendulum(rig, law, user_function, spec.discovered, spec.drag)


def reference(rig: Rig, spec: ModelSpec, law: FrictionLaw, chain: LumpedChain | None, t_end: float,
              method: str = "DOP853", step: float | None = None) -> tuple[dict[str, np.ndarray], dict]:
    """The reference solve (:func:`vcbmodel.reference.solve.reference_pendulum`); it has no
    discovered torque, so a model that carries one is refused rather than solved without it."""
    refuse_discovered_torque(spec)
    return reference_pendulum(rig, spec, law, chain, t_end, method, step)


def channels(data: dict[str, np.ndarray], rig: Rig, spec: ModelSpec, info: dict) -> dict[str, np.ndarray]:
    return shaft_channels(data, "pendulum_angle")


def default_step(rig: Rig) -> float:
    """PENDULUM_STEP: sized for accuracy only; the passive stuck state catches a reversing
    shaft whatever the step (:mod:`vcbmodel.laws.friction`)."""
    return P.PENDULUM_STEP


def swing_frequency(rig: Rig) -> float:
    """Small-angle swing frequency (Hz) of the pendulum of eq. 1: sqrt(M g L / I) / 2 pi."""
    p = rig.pendulum
    return math.sqrt(p.mass * rig.gravity * p.com_distance / p.inertia) / (2 * math.pi)


def figures_of_merit(result: SimulationResult, rig: Rig) -> dict:
    """``first_peak_rad``: amplitude of the first extreme after release; ``stop_time_s``:
    when the shaft last moved faster than the stick band (0 if it never did; None if it still does
    at the end of the run: it has not stopped)."""
    w = result.channels["shaft_velocity"]
    moving = np.nonzero(np.abs(w) > result.spec.stick_velocity)[0]
    still_swinging = moving.size and moving[-1] == w.size - 1
    return {"first_peak_rad": first_peak_amplitude(result.t, result.measured),
            "stop_time_s": None if still_swinging else float(result.t[moving[-1]]) if moving.size else 0.0}


def _span_decay(rig: Rig, measurement: Measurement) -> dict | None:
    """The swing's span decrements (below): the regression's Coulomb rate (rad/s) and viscous
    rate lambda (1/s), the whole decay as a constant rate ``total`` (rad/s) or as an exponential
    ``lam_all`` (1/s), the mean span (rad), and ``to_mu`` (a Coulomb rate -> mu_k); None when the
    record swings fewer than three clear spans."""
    p = rig.pendulum
    mid, spans, gaps = swing_spans(measurement.t, measurement.channel("pendulum_angle"))
    if spans.size < 3:
        return None
    rate_of_change = np.diff(spans) / np.diff(mid)
    s_mid = 0.5 * (spans[1:] + spans[:-1])
    coulomb_rate, lam = (-np.polyfit(s_mid, rate_of_change, 1)[::-1]) if s_mid.size >= 2 else (0.0, 0.0)
    return {"coulomb_rate": max(float(coulomb_rate), 0.0), "lam": max(float(lam), 0.0),
            "total": max(float(-np.polyfit(mid, spans, 1)[0]), 0.0),
            "lam_all": max(float(-np.polyfit(mid, np.log(spans), 1)[0]), 0.0), "mean_span": float(np.mean(spans)),
            "to_mu": float(np.median(gaps)) * p.com_distance / (4 * rig.shaft_radius)}


def start_guesses(rig: Rig, measurement: Measurement) -> list[dict[str, float]]:
    """Starting values from the measured swing.

    While the pendulum swings clearly, the span between successive extremes shrinks at
    ``ds/dt = -4 T_f/(M g L T) - lambda s``: a Coulomb torque T_f ~ mu_k r M g takes a constant
    4 T_f/(M g L) per half period T/2, a viscous torque gives the rate lambda = Cv / (2 I).
    A linear regression of the span decrements on the span separates the two. Starts: the
    regression, all of the decay as Coulomb, all of it as viscous.
    """
    d = _span_decay(rig, measurement)
    if d is None:
        return [{}]
    inertia = rig.pendulum.inertia
    both = {"mu_k": d["coulomb_rate"] * d["to_mu"], "viscous": 2 * d["lam"] * inertia}
    both["mu_s"] = 1.5 * both["mu_k"]
    return [both,
            {"mu_k": d["total"] * d["to_mu"], "viscous": 0.0, "mu_s": 1.5 * d["total"] * d["to_mu"]},
            {"mu_k": 0.0, "viscous": 2 * d["lam_all"] * inertia, "mu_s": 0.0}]


def decay_split_guesses(rig: Rig, measurement: Measurement, coulomb_shares: tuple[float, ...]) -> list[dict[str, float]]:
    """Starts spread along the Coulomb-viscous valley: the swing's mean decay rate (rad/s) shared
    between a Coulomb part (share f: mu_k) and a viscous one (1 - f, at the mean span: Cv in
    N m s/rad), one start per share. The regression of :func:`start_guesses` reads a few noisy
    span decrements and, for friction of another shape than the law's, often puts all of the
    decay in Coulomb friction (viscous 0), a local optimum of the fit; the valley's other end
    (all viscous) is too far to reach the right basin from. [] when the record barely swings."""
    d = _span_decay(rig, measurement)
    if d is None or d["mean_span"] <= 0:
        return []
    out = []
    for f in coulomb_shares:
        mu_k = f * d["total"] * d["to_mu"]
        out.append({"mu_k": mu_k, "viscous": 2 * rig.pendulum.inertia * (1 - f) * d["total"] / d["mean_span"],
                    "mu_s": 1.5 * mu_k})
    return out


def swinging_part(t: np.ndarray, y: np.ndarray, sigma: float) -> float | None:
    """After a free swing sticks, the stuck angle depends discontinuously on the friction:
    fits take the swinging part first (None when the swing never stops within the record)."""
    t_stop = motion_end_time(t, y, sigma)
    return t_stop if t_stop < 0.9 * t[-1] else None


def signature(rig: Rig, measurement: Measurement, model_curve: np.ndarray, residual: np.ndarray, sigma: float) -> dict:
    """How the measured amplitude decays and when the swing stops (s), measured vs model; None for
    a swing that does not stop within the record."""
    t, y = measurement.t, measurement.channel("pendulum_angle")
    tp, ap = swing_peaks(t, y)

    def stop(curve):
        end = motion_end_time(t, curve, sigma)
        return None if end >= t[-1] else end

    return {"amplitude_decay": decay_shape(tp, ap), "measured_stop_time_s": stop(y), "model_stop_time_s": stop(model_curve)}


PENDULUM = Experiment(
    name="pendulum", description="pendulum free swing on the cam shaft (paper section 2, eq. 1-6)",
    measured_channel="pendulum_angle", unit="rad", sections=("pendulum",), read_sections=read_pendulum,
    # the body swings on the cam shaft's journal through air; its equation carries a further shaft torque
    provides=("journal", "swinging_body", "shaft_torque"),
    # potentiometer at 1 kHz, sigma 0.5 mrad (the example data's sensor)
    sample_rate=1000.0, noise_sigma=0.5e-3, default_duration=P.PENDULUM_T_END, max_duration=600.0,
    # a swing is at least a quarter period (about 0.25 s); a pendulum angle beyond half a turn is degrees
    min_duration=0.2, max_magnitude=math.pi, unit_hint=": is it in degrees? pendulum_angle must be in rad",
    build=build, channels=channels, step=default_step, figures_of_merit=figures_of_merit,
    start_guesses=start_guesses, swinging_part=swinging_part, signature=signature,
    initial_angle_field="pendulum.initial_angle", period_fields=("pendulum.inertia", "pendulum.com_distance"),
    figure_units=(("first_peak_rad", "rad"), ("stop_time_s", "s")), summary=pendulum_summary,
    # fits run the compiled path (ode_model) where a C compiler works; on Exudyn (no compiler) they use its
    # symbolic friction function, 6x faster than the Python one here
    fit_user_function="symbolic", staged_fit=True, natural_frequency=swing_frequency,
    # a swing starts within tens of ms of where it is first seen to move (a hand release is slower)
    free_swing=True, release_span=0.06,
    # a swing's decay is shared between Coulomb friction, viscous friction and air drag: a record can hold
    # any of them beside or instead of another; it sweeps through the Stribeck range at every turn
    friction_shapes=True, form_alternatives=("coulomb_friction", "viscous_friction", "aerodynamic_drag"),
    form_removable=("stribeck", "aerodynamic_drag", "viscous_friction"),
    ode_model=OdeModel("pendulum", prepare_pendulum, pendulum_equations), reference=reference,
    sensor="potentiometer", random_rig=pendulum_random_rig)

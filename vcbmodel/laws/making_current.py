"""Closing onto a fault: the making current and the contacts' electrodynamic repulsion.

A breaker that closes onto a short circuit makes the current at contact touch. In an inductive
circuit the current starts from zero and carries a decaying DC offset (IEC 62271-100, sec. 4.103:
the rated short-circuit making current is the peak of the first major loop, 2.5 times the rated
short-circuit breaking current at 50 Hz with the standard time constant of 45 ms):

    i(t) = I_ac [sin(w t - beta) + sin(beta) exp(-t / tau)],   t >= 0 from the making instant,

with w = 2 pi f, tau the DC time constant (s) and sin(beta) the asymmetry (0: symmetric, the
current starts at a voltage peak; 1: fully asymmetric, at a voltage zero). ``I_ac`` (A, the AC
component's peak) follows from the stated making peak (the largest |i| of the first cycle).

Current through a butt contact flows through small conducting spots (a-spots): the current lines
bend into each spot and push the contacts apart. Holm's constriction force (R. Holm, Electric
Contacts, 4th ed., 1967, sec. 5; Slade, Electrical Contacts, 2nd ed., 2014, ch. 1) for a circular
contact face of radius R carrying i through n equal spots of radius a:

    F = (mu0 / 4 pi) i^2 ln(R / a) / n      (N; mu0 / 4 pi = 1e-7 N/A^2)

(each spot carries i / n and pushes (mu0 / 4 pi) (i / n)^2 ln(R / a)). It acts on each pole's moving
contact, against its closing, while the pole is closed (penetration > 0) from its own first touch
(each pole's current starts at its own touch: a single-phase making test, or a three-phase fault to
earth with an earthed neutral). While a pole bounces open an arc carries the current: no
constriction, no force (the arc's own pressure is left out). A prestrike before touch is left out:
the current is taken to start at the touch.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .friction import NumericOps
from .types import Ops, Scalar

#: mu0 / (4 pi) in N/A^2 (the magnetic constant's conventional value)
MU0_OVER_4PI = 1e-7
#: A pole's touch time before it touches (memory value): any negative number means "not yet"
NOT_YET = -1.0


@dataclass(frozen=True)
class MakingCurrent:
    """The making current and the contacts' repulsion (rig section ``breaker.making_current``):
    ``peak`` (A, the making current's first major peak, IEC's rated short-circuit making current),
    ``frequency`` (Hz), ``time_constant`` (s, the DC component's decay, IEC's standard 45 ms),
    ``asymmetry`` (-, 0..1: sin(beta), the DC offset as a fraction of the AC peak at the making
    instant), ``contact_radius`` (m, R: the contact face carrying the current), ``spot_radius`` (m,
    a: each conducting spot) and ``spots`` (-, n equal spots sharing the current)."""

    peak: float  # A
    frequency: float  # Hz
    time_constant: float  # s
    asymmetry: float  # -
    contact_radius: float  # m
    spot_radius: float  # m
    spots: float  # -


def current_shape(t: Scalar, omega: Scalar, asymmetry: Scalar, time_constant: Scalar, ops: Ops = NumericOps) -> Scalar:
    """The making current per unit AC peak (-) at ``t`` (s) after the making instant:
    sin(w t - beta) + sin(beta) exp(-t / tau), sin(beta) = ``asymmetry``, w in rad/s, tau in s;
    zero before the making instant (t < 0)."""
    cos_beta = ops.sqrt(ops.max(1.0 - asymmetry * asymmetry, 0.0))
    tt = ops.max(t, 0.0)
    shape = (ops.sin(omega * tt) * cos_beta - ops.cos(omega * tt) * asymmetry
             + asymmetry * ops.pow(math.e, -tt / time_constant))
    return ops.where(t < 0.0, 0.0, shape)


def ac_peak(making: MakingCurrent) -> float:
    """The AC component's peak I_ac (A) whose current (:func:`current_shape`) reaches
    ``making.peak`` as its largest |i| within the first cycle (with an offset, the first major
    loop's peak, about half a cycle after the making instant)."""
    omega = 2.0 * math.pi * making.frequency
    t = np.linspace(0.0, 1.0 / making.frequency, 20001)
    shape = np.abs(np.sin(omega * t - math.asin(making.asymmetry)) + making.asymmetry * np.exp(-t / making.time_constant))
    return making.peak / float(np.max(shape))


def holm_factor(making: MakingCurrent) -> float:
    """(mu0 / 4 pi) ln(R / a) / n in N/A^2: Holm's constriction force per ampere squared."""
    return MU0_OVER_4PI * math.log(making.contact_radius / making.spot_radius) / making.spots


def holm_force(current: Scalar, factor: Scalar) -> Scalar:
    """Holm's repulsion (N) of a contact carrying ``current`` (A): ``factor`` i^2 with
    ``factor`` = :func:`holm_factor` (N/A^2)."""
    return factor * current * current


def pole_repulsion(t: Scalar, touch_time: Scalar, penetration: Scalar, amplitude: Scalar, omega: Scalar,
                   asymmetry: Scalar, time_constant: Scalar, factor: Scalar, ops: Ops = NumericOps) -> Scalar:
    """Repulsion (N, along opening) on a pole's moving contact at time ``t`` (s): Holm's force of
    the making current ``amplitude`` x :func:`current_shape` (A; ``amplitude`` I_ac in A, ``omega``
    rad/s, ``time_constant`` s) from the pole's first touch ``touch_time`` (s; negative: it has not
    touched, no current), while the pole is closed (``penetration`` m > 0)."""
    current = amplitude * current_shape(t - touch_time, omega, asymmetry, time_constant, ops)
    force = holm_force(current, factor)
    return ops.where(touch_time < 0.0, 0.0, ops.where(penetration > 0.0, force, 0.0))


def update_touch_time(touch_time: Scalar, t: Scalar, penetration: Scalar, ops: Ops = NumericOps) -> Scalar:
    """A pole's first-touch time (s) after a state at time ``t`` (s) with contact ``penetration``
    (m): the first ``t`` at which it penetrates, kept from then on (``NOT_YET`` before)."""
    return ops.where(touch_time < 0.0, ops.where(penetration > 0.0, t, NOT_YET), touch_time)


class MakingLaws:
    """The making current's derived numbers (floats, so the compiled path traces them as
    parameters): ``amplitude`` I_ac (A, :func:`ac_peak`), ``omega`` (rad/s), ``asymmetry``,
    ``time_constant`` (s) and Holm's ``factor`` (N/A^2, :func:`holm_factor`)."""

    def __init__(self, making: MakingCurrent) -> None:
        self.amplitude = ac_peak(making)
        self.omega = 2.0 * math.pi * making.frequency
        self.asymmetry = making.asymmetry
        self.time_constant = making.time_constant
        self.factor = holm_factor(making)

    def current(self, t_since_touch: Scalar, ops: Ops = NumericOps) -> Scalar:
        """The making current (A) ``t_since_touch`` s after the touch."""
        return self.amplitude * current_shape(t_since_touch, self.omega, self.asymmetry, self.time_constant, ops)

    def repulsion(self, t: Scalar, touch_time: Scalar, penetration: Scalar, ops: Ops = NumericOps) -> Scalar:
        """:func:`pole_repulsion` with these numbers (N, along opening)."""
        return pole_repulsion(t, touch_time, penetration, self.amplitude, self.omega, self.asymmetry,
                              self.time_constant, self.factor, ops)

"""The hybrid shaft friction law (paper eq. 2-6 and 13, typos resolved as in the spec).

All functions here are pure: they take numbers (or Exudyn symbolic reals, through the
``ops`` argument) and return numbers. Units: torques in N m, forces in N, angular
velocities in rad/s, lengths in m, inertia in kg m^2.

The law (spec "The shaft friction law", paper eq. 2-4 with eq. 3 read as T_f = T_s):

- stick band ``|w| <= w0``:  ``T_f = min(|T_c|, mu_s r F_n) sign(T_c)`` (read literally)
- Stribeck branch ``w0 < |w| < ws``:  ``T_f = (mu_s - (mu_s - mu_k)|w|/ws) r F_n sign(w)``
- otherwise:  ``T_f = mu_k r F_n sign(w) + C_v (w - ws' sign(w))``

``F_n`` is the magnitude of the shaft reaction force. It depends on the angular
acceleration (eq. 5-6, eq. 13), which depends on ``T_f``: the two are solved together.
Writing the reaction as ``R = R0 + R1 * theta''`` (both 2-vectors, linear in the
acceleration) and ``theta'' = (T_c - T_f) / I`` with ``T_f = c F_n + d`` on each branch,
``|R| = F_n`` is a quadratic in ``F_n`` with the closed-form positive root used in
:func:`consistent_reaction`. No iteration and no lag: the result is exact for the branch.

Passive sticking (spec, revised). Read literally, the stick band lets a shaft that enters it
with a small speed keep that speed: it creeps at up to w0 forever, uphill, with friction doing
positive work. The default ``sticking="passive"`` completes the band with a stuck state
realised as a velocity-restoring torque (Karnopp with a restoring term): inside the band,
where static friction can hold the applied torque (``|T_c| <= mu_s r F_n`` at rest), the
friction is the torque that brings the shaft to rest with time constant ``stick_time`` tau,

    T_f = T_c + I w / tau   (so theta'' = -w / tau),

limited to the static capacity mu_s r F_n, and set to zero where it would push the shaft
along (``T_f w < 0``: friction never does positive work; below :data:`REST_SPEED`, round-off,
the shaft counts as at rest). A shaft that enters the band stops
within a few tau and then stays: its angle moves by at most w0 tau. Outside the band, or when
static friction cannot hold T_c, the slip branches apply, with the band's friction opposing
the motion (``mu_s r F_n sign(w)``, breaking away in the direction of T_c from rest).
``sticking="literal"`` keeps the band as written, for comparison. With an explicit fixed step
h the passive band is widened to ``max(w0, 2 h mu_s r F_n / I)``: near rest the shaft's speed
changes by at most (|T_c| + mu_s r F_n) h / I per step, so a reversing shaft always lands in the
band instead of jumping over it, whatever the step (the stuck state then moves the angle by at
most that speed times tau). The step must stay below about 2.8 tau (stability of the restoring
term).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..parameters import STICK_TIME
from .types import Ops, Scalar


class NumericOps:
    """Scalar float operations (the pure-Python evaluation of the laws). Every ``ops`` namespace
    offers these: ``where``, ``abs``, ``sqrt``, ``sign``, ``min``, ``max``, ``sin``, ``cos``,
    ``atan2``, ``acos``, ``pow``, ``floor``, ``take`` (an item of a table by a computed index; Exudyn's
    symbolic one: the first eight, what the friction law needs, and ``pow``, what a discovered
    torque needs)."""

    @staticmethod
    def where(condition: bool, if_true: float, if_false: float) -> float:
        return if_true if condition else if_false

    abs = staticmethod(abs)
    sqrt = staticmethod(math.sqrt)

    @staticmethod
    def sign(x: float) -> float:
        return 1.0 if x > 0 else (-1.0 if x < 0 else 0.0)

    @staticmethod
    def min(a: float, b: float) -> float:
        return a if a < b else b

    sin = staticmethod(math.sin)
    cos = staticmethod(math.cos)

    @staticmethod
    def max(a: float, b: float) -> float:
        return a if a > b else b

    atan2 = staticmethod(math.atan2)
    acos = staticmethod(math.acos)

    @staticmethod
    def pow(a: float, b: float) -> float:
        return math.pow(a, b)

    @staticmethod
    def floor(a: float) -> float:
        return float(math.floor(a))

    @staticmethod
    def take(table: Sequence[float], index: float) -> float:
        return table[int(index) % len(table)]


class ArrayOps:
    """The same operations on numpy arrays, elementwise (a law evaluated over a whole record at
    once; every branch is computed and the one that applies chosen, so call it inside
    ``numpy.errstate(all="ignore")`` where an unchosen branch may divide by zero)."""

    where = staticmethod(np.where)
    abs = staticmethod(np.abs)
    sqrt = staticmethod(np.sqrt)
    sign = staticmethod(np.sign)
    min = staticmethod(np.minimum)
    max = staticmethod(np.maximum)
    sin = staticmethod(np.sin)
    cos = staticmethod(np.cos)
    atan2 = staticmethod(np.arctan2)
    acos = staticmethod(np.arccos)
    pow = staticmethod(np.power)
    floor = staticmethod(np.floor)

    @staticmethod
    def take(table: Sequence[float] | np.ndarray, index: np.ndarray | float) -> np.ndarray:
        return np.asarray(table)[np.asarray(index).astype(int) % len(table)]


def symbolic_ops() -> type:
    """The same operations on Exudyn symbolic reals (compiled user functions)."""
    import exudyn

    es = exudyn.symbolic

    def real(x):
        return x if isinstance(x, es.Real) else es.Real(float(x))

    class SymbolicOps:
        @staticmethod
        def where(condition, if_true, if_false):
            return es.IfThenElse(real(condition), real(if_true), real(if_false))

        abs = staticmethod(es.abs)
        sqrt = staticmethod(es.sqrt)
        sign = staticmethod(es.sign)
        min = staticmethod(es.min)
        max = staticmethod(es.max)
        sin = staticmethod(es.sin)
        cos = staticmethod(es.cos)

        @staticmethod
        def pow(a, b):
            return es.pow(real(a), real(b))

    return SymbolicOps


@dataclass(frozen=True)
class FrictionLaw:
    """Parameters of the shaft friction law, with the effects already folded in.

    Attributes
    ----------
    mu_s : static friction coefficient (-); equals ``mu_k`` without ``stribeck``.
    mu_k : kinetic friction coefficient (-); 0 without ``coulomb_friction``.
    stick_velocity : half-width w0 of the Karnopp stick band (rad/s).
    stribeck_velocity : ws (rad/s); 0 without ``stribeck`` (the branch never applies).
    viscous : Cv (N m s/rad); 0 without ``viscous_friction``.
    radius : journal radius r (m).
    sticking : ``passive`` (a stuck shaft stays at rest; default) or ``literal`` (the band as written).
    stick_time : tau (s), time constant of the passive stuck state's restoring torque.
    step : the explicit integrator's fixed step (s), 0 for an adaptive one: a passive band catches
        a reversing shaft whose speed changes by up to 2 h mu_s r F_n / I in one step (module
        docstring), so the step need not be sized to the band.
    """

    mu_s: float = 0.0
    mu_k: float = 0.0
    stick_velocity: float = 1e-3
    stribeck_velocity: float = 0.0
    viscous: float = 0.0
    radius: float = 0.02
    sticking: str = "passive"
    stick_time: float = STICK_TIME
    step: float = 0.0

    def __post_init__(self):
        # the static coefficient is never below the kinetic one (spec: without stribeck, mu_s = mu_k)
        object.__setattr__(self, "mu_s", effective_static(self.mu_s, self.mu_k))


#: Speed (rad/s) below which a stuck shaft counts as at rest: round-off between the applied
#: torque in the model and in the law (1e-15 relative) leaves |w| ~ 1e-17; treating it as motion
#: would switch the holding torque off. Friction power there is below |T_c| x 1e-9 W.
REST_SPEED = 1e-9


def effective_static(mu_s: Scalar, mu_k: Scalar) -> Scalar:
    """The static coefficient the law uses: mu_s, but never below mu_k (-)."""
    return mu_s if mu_s > mu_k else mu_k


def viscous_from_zeta(zeta: float, inertia: float, mass: float, gravity: float, com_distance: float) -> float:
    """Pendulum viscous coefficient Cv = 2 zeta sqrt(I M g L) (paper eq. 4), in N m s/rad."""
    return 2.0 * zeta * math.sqrt(inertia * mass * gravity * com_distance)


def zeta_from_viscous(viscous: float, inertia: float, mass: float, gravity: float, com_distance: float) -> float:
    """Inverse of :func:`viscous_from_zeta` (dimensionless damping ratio)."""
    return viscous / (2.0 * math.sqrt(inertia * mass * gravity * com_distance))


def consistent_reaction(R0x: Scalar, R0y: Scalar, R1x: Scalar, R1y: Scalar, applied_torque: Scalar, inertia: Scalar, c: Scalar, d: Scalar,
                        ops: Ops = NumericOps) -> Scalar:
    """Shaft reaction magnitude F_n (N) solved together with the acceleration.

    The reaction is ``R = R0 + R1 theta''`` with ``theta'' = (T_c - c F_n - d) / I``, i.e.
    ``R = P - Q F_n`` with ``P = R0 + R1 (T_c - d)/I`` and ``Q = R1 c / I``. Setting
    ``|R| = F_n`` gives ``(1 - Q.Q) F_n^2 + 2 (P.Q) F_n - P.P = 0``; the positive root is
    returned (``|Q| < 1`` holds for any physical journal: ``|Q| ~ m L mu r / I``).
    Written with ``k = c/I``, ``u = P.R1`` and ``v = R1.R1`` so each input appears few times
    (Exudyn's symbolic trees do not share common subexpressions).
    """
    a = (applied_torque - d) / inertia
    Px = R0x if _is_zero(R1x) else R0x + R1x * a
    Py = R0y if _is_zero(R1y) else R0y + R1y * a
    u = (0.0 if _is_zero(R1x) else Px * R1x) + (0.0 if _is_zero(R1y) else Py * R1y)
    v = R1x * R1x + R1y * R1y
    k = c / inertia
    kv = 1.0 - k * k * v
    return (ops.sqrt(k * k * u * u + kv * (Px * Px + Py * Py)) - k * u) / kv


def _is_zero(x):
    return isinstance(x, (int, float)) and x == 0.0


def shaft_friction(w: Scalar, applied_torque: Scalar, R0x: Scalar, R0y: Scalar, R1x: Scalar, R1y: Scalar, inertia: Scalar, law: FrictionLaw,
                   ops: Ops = NumericOps, t: Scalar = 0.0) -> tuple[Scalar, Scalar]:
    """Friction torque T_f (N m, opposing motion) and shaft reaction F_n (N).

    Parameters
    ----------
    w : shaft angular velocity (rad/s).
    applied_torque : T_c, the torque on the shaft without friction (N m) (eq. 12's right side).
    R0x, R0y : shaft reaction force at zero angular acceleration (N) (eq. 5-6, eq. 13).
    R1x, R1y : change of the reaction per unit angular acceleration (N s^2/rad).
    inertia : the inertia that multiplies theta'' in the equation of motion (kg m^2).
    law : :class:`FrictionLaw` (``sticking``: passive or literal, module docstring).
    ops : :class:`NumericOps` or :func:`symbolic_ops` (same formula compiled by Exudyn).
    t : model time (s); a friction form (:mod:`vcbmodel.laws.friction_forms`) in place of ``law``
        gives the hybrid law that holds at this speed and time.

    Returns ``(T_f, F_n)``; the equation of motion is ``I theta'' = T_c - T_f``.
    """
    if not isinstance(law, FrictionLaw):  # a friction form: its law at this instant
        law = law.at(w, t, ops)
    r = law.radius
    absw = ops.abs(w)
    Fn_rest = ops.sqrt(R0x * R0x + R0y * R0y)  # the reaction with the shaft at rest (theta'' = 0)
    band_width = law.stick_velocity
    if law.sticking != "literal" and law.step > 0.0:  # catch a reversal within one step (docstring)
        caught = 2.0 * law.step * law.mu_s * r * Fn_rest / inertia
        band_width = ops.where(caught > band_width, caught, band_width)
    in_band = absw <= band_width
    c, d = slip_branch(law, w, absw, applied_torque, in_band, ops)
    Fn_slip = consistent_reaction(R0x, R0y, R1x, R1y, applied_torque, inertia, c, d, ops)
    # stick band: can static friction hold T_c with the shaft at rest (theta'' = 0, F_n = |R0|)?
    holds = in_band * (ops.abs(applied_torque) <= law.mu_s * r * Fn_rest)
    if law.sticking == "literal":
        Tf = ops.where(holds, applied_torque, c * Fn_slip + d)
        return Tf, ops.where(holds, Fn_rest, Fn_slip)
    stuck, Fn_stop = passive_stuck_torque(w, absw, applied_torque, (R0x, R0y, R1x, R1y), inertia, law, ops)
    Tf = ops.where(holds, stuck, c * Fn_slip + d)
    return Tf, ops.where(holds, Fn_stop, Fn_slip)


def slip_branch(law: FrictionLaw, w: Scalar, absw: Scalar, applied_torque: Scalar, in_band: Scalar,
                ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
    """The friction torque's branch as ``T_f = c F_n + d`` (eq. 12's friction term): ``c`` (m), the
    radius times the friction coefficient in force (Coulomb mu_k, the Stribeck branch below w_s, mu_s
    in the band), and ``d`` (N m), the viscous torque (``law.viscous`` in N m s/rad), so that F_n can
    be solved once (:func:`consistent_reaction`). ``w`` in rad/s and ``absw`` its magnitude (passed in,
    so that a symbolic expression holds it once), ``applied_torque`` T_c in N m; ``in_band``: whether
    |w| is within the stick band.

    Branches whose parameters are zero are left out here, in Python, so the compiled expression stays
    small (the law is unchanged: they would contribute nothing)."""
    s, ws = ops.sign(w), law.stribeck_velocity
    in_strib = absw < ws
    outside = law.mu_k * s
    if ws > 0.0:
        mu_stribeck = law.mu_s - (law.mu_s - law.mu_k) * absw / ws
        outside = ops.where(in_strib, mu_stribeck * s, outside)
    if law.sticking == "literal":
        band = law.mu_s * ops.sign(applied_torque)
    else:  # oppose the motion; from rest, break away in the direction of T_c
        band = law.mu_s * ops.where(absw > REST_SPEED, s, ops.sign(applied_torque))
    c = law.radius * ops.where(in_band, band, outside)
    if law.viscous == 0.0:
        d = 0.0
    elif ws > 0.0:
        d = ops.where(in_band, 0.0, ops.where(in_strib, 0.0, law.viscous * (w - ws * s)))
    else:
        d = ops.where(in_band, 0.0, law.viscous * w)
    return c, d


def passive_stuck_torque(w: Scalar, absw: Scalar, applied_torque: Scalar, reaction: tuple[Scalar, Scalar, Scalar, Scalar],
                         inertia: Scalar, law: FrictionLaw, ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
    """The passive stuck state's friction torque (N m) and shaft reaction (N): the torque that stops the
    shaft within ``law.stick_time`` (theta'' = -w/tau), within the static capacity mu_s r F_n at that
    acceleration (eq. 5-6's reaction, ``reaction`` = (R0x, R0y, R1x, R1y)), and never along the motion.
    Units as :func:`shaft_friction`; ``absw`` = |w|."""
    R0x, R0y, R1x, R1y = reaction
    tau = law.stick_time
    restoring = applied_torque + inertia * w / tau
    Rx, Ry = R0x - R1x * w / tau, R0y - R1y * w / tau
    Fn_stop = ops.sqrt(Rx * Rx + Ry * Ry)
    capacity = law.mu_s * law.radius * Fn_stop
    stuck = ops.where(ops.abs(restoring) <= capacity, restoring, capacity * ops.sign(restoring))
    stuck = ops.where((restoring * w < 0.0) * (absw > REST_SPEED), 0.0, stuck)
    return stuck, Fn_stop


def band_width(law: FrictionLaw, Fn_rest: float, inertia: float) -> float:
    """Half-width (rad/s) of the stick band: w0, widened for the passive law with a fixed step
    to the speed change one step can make near rest (module docstring)."""
    if law.sticking == "literal" or law.step <= 0.0:
        return law.stick_velocity
    return max(law.stick_velocity, 2.0 * law.step * law.mu_s * law.radius * Fn_rest / inertia)


def friction_torque(w: float, applied_torque: float, reaction: float, law: FrictionLaw, band: float | None = None) -> float:
    """The spec's slip law at a *given* shaft reaction F_n (N): T_f in N m.

    This is the law as written (paper eq. 2-4, eq. 3 read as T_f = T_s), without the coupling
    of F_n to the acceleration and without the passive stuck state (:func:`shaft_friction`
    solves the coupling in closed form; the reference solvers by iteration or root finding).
    ``band``: the stick band's half-width (rad/s), default w0. Inside it the literal law gives
    min(|T_c|, mu_s r F_n) sign(T_c); the passive law, for a shaft that cannot stick there,
    mu_s r F_n opposing the motion (from rest: in the direction of T_c).
    """
    r, absw = law.radius, abs(w)
    s = NumericOps.sign(w)
    if absw <= (law.stick_velocity if band is None else band):
        if law.sticking == "literal":
            return min(abs(applied_torque), law.mu_s * r * reaction) * NumericOps.sign(applied_torque)
        return law.mu_s * r * reaction * (s if absw > REST_SPEED else NumericOps.sign(applied_torque))
    ws = law.stribeck_velocity
    if absw < ws:
        return (law.mu_s - (law.mu_s - law.mu_k) * absw / ws) * r * reaction * s
    return law.mu_k * r * reaction * s + law.viscous * (w - ws * s)


def stuck_torque(w: float, applied_torque: float, R0: tuple[float, float], R1: tuple[float, float], inertia: float,
                 law: FrictionLaw) -> tuple[float, float]:
    """The passive stuck state (module docstring): (T_f in N m, F_n in N) for a shaft in the
    band whose applied torque static friction can hold; written out plainly (no ``ops``)."""
    tau = law.stick_time
    acc = -w / tau
    Fn = math.hypot(R0[0] + R1[0] * acc, R0[1] + R1[1] * acc)
    restoring = applied_torque + inertia * w / tau
    if restoring * w < 0.0 and abs(w) > REST_SPEED:
        return 0.0, Fn
    capacity = law.mu_s * law.radius * Fn
    return max(-capacity, min(capacity, restoring)), Fn

"""The hybrid shaft friction law (paper eq. 2-6 and 13, typos resolved as in the spec).

All functions here are pure: they take numbers (or Exudyn symbolic reals, through the
``ops`` argument) and return numbers. Units: torques in N m, forces in N, angular
velocities in rad/s, lengths in m, inertia in kg m^2.

The law (spec "The shaft friction law", paper eq. 2-4 with eq. 3 read as T_f = T_s):

- stick band ``|w| <= w0``:  ``T_f = min(|T_c|, mu_s r F_n) sign(T_c)``
- Stribeck branch ``w0 < |w| < ws``:  ``T_f = (mu_s - (mu_s - mu_k)|w|/ws) r F_n sign(w)``
- otherwise:  ``T_f = mu_k r F_n sign(w) + C_v (w - ws' sign(w))``

``F_n`` is the magnitude of the shaft reaction force. It depends on the angular
acceleration (eq. 5-6, eq. 13), which depends on ``T_f``: the two are solved together.
Writing the reaction as ``R = R0 + R1 * theta''`` (both 2-vectors, linear in the
acceleration) and ``theta'' = (T_c - T_f) / I`` with ``T_f = c F_n + d`` on each branch,
``|R| = F_n`` is a quadratic in ``F_n`` with the closed-form positive root used in
:func:`consistent_reaction`. No iteration and no lag: the result is exact for the branch.
"""
from __future__ import annotations

import math
from dataclasses import dataclass


class NumericOps:
    """Scalar float operations (the pure-Python evaluation of the law)."""

    @staticmethod
    def where(condition, if_true, if_false):
        return if_true if condition else if_false

    abs = staticmethod(abs)
    sqrt = staticmethod(math.sqrt)

    @staticmethod
    def sign(x):
        return 1.0 if x > 0 else (-1.0 if x < 0 else 0.0)

    @staticmethod
    def min(a, b):
        return a if a < b else b

    sin = staticmethod(math.sin)
    cos = staticmethod(math.cos)


def symbolic_ops():
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
        sin = staticmethod(es.sin)
        cos = staticmethod(es.cos)

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
    """

    mu_s: float = 0.0
    mu_k: float = 0.0
    stick_velocity: float = 1e-3
    stribeck_velocity: float = 0.0
    viscous: float = 0.0
    radius: float = 0.02


def viscous_from_zeta(zeta, inertia, mass, gravity, com_distance):
    """Pendulum viscous coefficient Cv = 2 zeta sqrt(I M g L) (paper eq. 4), in N m s/rad."""
    return 2.0 * zeta * math.sqrt(inertia * mass * gravity * com_distance)


def zeta_from_viscous(viscous, inertia, mass, gravity, com_distance):
    """Inverse of :func:`viscous_from_zeta` (dimensionless damping ratio)."""
    return viscous / (2.0 * math.sqrt(inertia * mass * gravity * com_distance))


def consistent_reaction(R0x, R0y, R1x, R1y, applied_torque, inertia, c, d, ops=NumericOps):
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


def shaft_friction(w, applied_torque, R0x, R0y, R1x, R1y, inertia, law: FrictionLaw, ops=NumericOps):
    """Friction torque T_f (N m, opposing motion) and shaft reaction F_n (N).

    Parameters
    ----------
    w : shaft angular velocity (rad/s).
    applied_torque : T_c, the torque on the shaft without friction (N m) (eq. 12's right side).
    R0x, R0y : shaft reaction force at zero angular acceleration (N) (eq. 5-6, eq. 13).
    R1x, R1y : change of the reaction per unit angular acceleration (N s^2/rad).
    inertia : the inertia that multiplies theta'' in the equation of motion (kg m^2).
    law : :class:`FrictionLaw`.
    ops : :class:`NumericOps` or :func:`symbolic_ops` (same formula compiled by Exudyn).

    Returns ``(T_f, F_n)``; the equation of motion is ``I theta'' = T_c - T_f``.
    """
    r = law.radius
    s = ops.sign(w)
    absw = ops.abs(w)
    ws = law.stribeck_velocity
    in_band = absw <= law.stick_velocity
    in_strib = absw < ws
    # Each branch is T_f = c F_n + d; pick (c, d) first so F_n is solved once.
    # Branches whose parameters are zero are left out here, in Python, so the compiled
    # expression stays small (the law is unchanged: they would contribute nothing).
    sTc = ops.sign(applied_torque)
    outside = law.mu_k * s
    if ws > 0.0:
        mu_stribeck = law.mu_s - (law.mu_s - law.mu_k) * absw / ws
        outside = ops.where(in_strib, mu_stribeck * s, outside)
    c = r * ops.where(in_band, law.mu_s * sTc, outside)
    if law.viscous == 0.0:
        d = 0.0
    elif ws > 0.0:
        d = ops.where(in_band, 0.0, ops.where(in_strib, 0.0, law.viscous * (w - ws * s)))
    else:
        d = ops.where(in_band, 0.0, law.viscous * w)
    Fn_slip = consistent_reaction(R0x, R0y, R1x, R1y, applied_torque, inertia, c, d, ops)
    # stick band: the shaft holds (theta'' = 0, F_n = |R0|) if static friction can take T_c
    Fn_stick = ops.sqrt(R0x * R0x + R0y * R0y)
    holds = in_band * (ops.abs(applied_torque) <= law.mu_s * r * Fn_stick)
    Tf = ops.where(holds, applied_torque, c * Fn_slip + d)
    Fn = ops.where(holds, Fn_stick, Fn_slip)
    return Tf, Fn


def friction_torque(w, applied_torque, reaction, law: FrictionLaw):
    """The spec's friction law at a *given* shaft reaction F_n (N): T_f in N m.

    This is the law as written (paper eq. 2-4, eq. 3 read as T_f = T_s), without the
    coupling of F_n to the acceleration; :func:`shaft_friction` solves that coupling in
    closed form, the reference solver (:mod:`vcbmodel.reference.solve`) by fixed-point iteration.
    """
    r, absw = law.radius, abs(w)
    s = NumericOps.sign(w)
    if absw <= law.stick_velocity:
        return min(abs(applied_torque), law.mu_s * r * reaction) * NumericOps.sign(applied_torque)
    ws = law.stribeck_velocity
    if absw < ws:
        return (law.mu_s - (law.mu_s - law.mu_k) * absw / ws) * r * reaction * s
    return law.mu_k * r * reaction * s + law.viscous * (w - ws * s)

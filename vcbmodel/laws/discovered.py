"""A discovered generalized torque: a sum of named library terms with fitted coefficients.

Discovery (:mod:`vcbmodel.analysis.discovery`) finds a torque no registered effect describes by
sparse regression over the candidate terms below; the model then carries it as
``T_d = sum_k c_k f_k(t, theta, w)`` (N m) on the shaft coordinate, added to the applied torque
T_c of paper eq. 1 / eq. 12 before the shaft friction (eq. 2-6) is evaluated, so a stuck shaft
holds it like any other applied torque. Each term is a pure function of the model time t (s),
the shaft angle theta (rad) and speed w (rad/s) taking an ``ops`` namespace, so Python, numpy
arrays, Exudyn's symbolic user functions and the compiled path evaluate the same source.

A term's coefficient carries the unit that makes c f a torque (N m): ``N m s^2/rad^2`` for w|w|.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

from .types import Ops, Scalar

#: Speeds v (rad/s) of the library's ``sign(w) exp(-|w|/v)`` terms: a friction falling from
#: breakaway over v, from a sharp (0.05 rad/s) to a broad (0.5 rad/s) Stribeck-like curve; a
#: pendulum swings at 0.5-5 rad/s, so slower curves are confined to the reversals (where the
#: estimate is not used) and faster ones look like Coulomb friction.
SIGN_EXP_SPEEDS = (0.05, 0.15, 0.5)
#: Harmonics k of the ``sin(k theta)``, ``cos(k theta)`` terms: a torque periodic in the angle
#: (k = 1 is the weight's own moment), up to the third harmonic.
HARMONICS = (1, 2, 3)
#: Centres (degrees) of the ``rub_<c>deg`` position windows, sign(w) exp(kappa (cos(theta - c) - 1)):
#: a friction confined to part of a turn (a tight spot of the bearing, a part touching the cam). Every
#: 30 degrees around the turn; a window is periodic in the angle, so it serves whatever turn the
#: cam is released in.
WINDOW_CENTRES_DEG = tuple(range(0, 360, 30))
#: Concentration kappa of the windows: their half-width at half height is acos(1 - ln 2 / kappa) =
#: 18.1 degrees (0.32 rad); a neighbour 30 degrees away stands at 0.15 of the peak, and the sum of
#: all windows varies by 3 % around the turn, so one to three of them follow a rub of any centre
#: that is at least about 0.4 rad wide.
WINDOW_KAPPA = 14.0


#: Physical tiers of the terms: how directly a torque of the term's form follows from a known
#: mechanism on a turning shaft. Where a record cannot tell two forms apart (their BICs within the
#: evidence margin), discovery keeps the lower tier and reports the tie.
#: 0: the form of a known law: air drag (w|w| above Reynolds numbers of about 1e3, where Cd is
#: constant), a Tustin/Stribeck friction curve, the weight's moment (sin/cos theta), a tilt (a constant);
#: 1: the form of a plausible part: a torsional spring (theta), a cam or detent (higher harmonics), a
#: localized rub (a position window), a drift (time);
#: 2: a shape with no common mechanism on a shaft: a speed-cubed damper (w^3), a stiffening spring (theta^3).
TIERS = {0: "the form of a known law", 1: "the form of a plausible part", 2: "a shape with no common mechanism"}


@dataclass(frozen=True)
class Term:
    """One candidate term: ``value(t, theta, w, ops)``; ``unit``: its coefficient's unit (so that
    coefficient times value is N m); ``reading``: what a torque of this form usually is; ``tier``:
    its physical tier (:data:`TIERS`)."""

    name: str
    value: Callable[[Scalar, Scalar, Scalar, Ops], Scalar]
    unit: str
    reading: str
    tier: int = 1


def _sign_exp(v: float) -> Callable:
    def value(t, theta, w, ops):
        return ops.sign(w) * ops.pow(math.e, -ops.abs(w) / v)
    return value


def _window(centre_deg: int) -> Callable:
    c = math.radians(centre_deg)

    def value(t, theta, w, ops):
        return ops.sign(w) * ops.pow(math.e, WINDOW_KAPPA * (ops.cos(theta - c) - 1.0))
    return value


def _sin(k: int) -> Callable:
    return lambda t, theta, w, ops: ops.sin(k * theta)


def _cos(k: int) -> Callable:
    return lambda t, theta, w, ops: ops.cos(k * theta)


def _terms() -> dict[str, Term]:
    terms = [
        Term("w_abs_w", lambda t, theta, w, ops: w * ops.abs(w), "N m s^2/rad^2",
             "torque proportional to w|w|: aerodynamic (speed-squared) drag", 0),
        Term("w3", lambda t, theta, w, ops: w * w * w, "N m s^3/rad^3",
             "torque proportional to w^3: a speed-hardening damper", 2),
        Term("theta", lambda t, theta, w, ops: theta, "N m/rad",
             "torque proportional to the angle: a torsional spring (a cable, a sensor's return spring)"),
        Term("theta3", lambda t, theta, w, ops: theta * theta * theta, "N m/rad^3",
             "torque proportional to theta^3: a stiffening spring", 2),
        Term("time", lambda t, theta, w, ops: t, "N m/s",
             "torque growing in time: a drift (heating, a slipping clamp)"),
        Term("constant", lambda t, theta, w, ops: 1.0 + 0.0 * t, "N m",
             "a constant torque: a tilted rig or a cable's pull", 0),
    ]
    terms += [Term(f"sign_exp_{v:g}", _sign_exp(v), "N m",
                   f"friction falling from breakaway over {v:g} rad/s: a Stribeck (Tustin) curve the registry's "
                   "linear one does not follow", 0) for v in SIGN_EXP_SPEEDS]
    terms += [Term(f"sin_{k}theta", _sin(k), "N m",
                   "torque in sin(theta): the weight's moment M g L is off (mass or centre of gravity)" if k == 1 else
                   f"torque periodic in the angle, sin({k} theta): a cam, detent or unbalance on the shaft",
                   0 if k == 1 else 1) for k in HARMONICS]
    terms += [Term(f"cos_{k}theta", _cos(k), "N m",
                   "torque in cos(theta): the centre of gravity off the link's line (a sideways unbalance)" if k == 1
                   else f"torque periodic in the angle, cos({k} theta): a cam, detent or unbalance on the shaft",
                   0 if k == 1 else 1) for k in HARMONICS]
    terms += [Term(f"rub_{c}deg", _window(c), "N m",
                   f"friction confined to angles near {c} degrees (a window about 36 degrees wide): a tight spot of "
                   "the bearing or a part rubbing the cam there") for c in WINDOW_CENTRES_DEG]
    return {term.name: term for term in terms}


#: The library, by name.
TERMS = _terms()


def term(name: str) -> Term:
    """The library term ``name`` (ValueError naming the known ones otherwise)."""
    try:
        return TERMS[name]
    except KeyError:
        raise ValueError(f"unknown discovered term {name!r} (known: {', '.join(TERMS)})") from None


def discovered_torque(t: Scalar, theta: Scalar, w: Scalar, terms: Sequence[tuple[str, Scalar]], ops: Ops) -> Scalar:
    """T_d = sum of coefficient x term over ``terms`` ((name, coefficient) pairs), in N m.

    Parameters
    ----------
    t : model time since release (s).
    theta : shaft angle (rad).
    w : shaft speed (rad/s).
    terms : ((term name, coefficient in the term's unit), ...); empty: no torque (0.0).
    ops : an ``ops`` namespace (:class:`vcbmodel.laws.friction.NumericOps`, ``ArrayOps``, symbolic, traced).
    """
    total = 0.0
    for name, coefficient in terms:
        total = total + coefficient * term(name).value(t, theta, w, ops)
    return total

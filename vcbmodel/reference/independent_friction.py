"""The shaft friction law of the independent reference (:mod:`.independent`), written again from the spec.

Holds the spec's friction law ("The shaft friction law": Karnopp band, Stribeck branch, kinetic
Coulomb with a viscous term) split into speed regimes with a smooth torque in each, and the
friction/acceleration coupling solved as a scalar root (Brent). Shares with the model only the
reading of the spec's law and its values (``mu_s``, ``mu_k``, ``stick_velocity``,
``stribeck_velocity``, ``viscous``); no code.

Units: SI. Torques in N m, forces in N, speeds in rad/s, accelerations in rad/s^2, radius in m.
"""
from __future__ import annotations

import math
from typing import Callable, Mapping, Sequence

from scipy.optimize import brentq

from vcbmodel.errors import SimulationError

FRICTION_KEYS = ("mu_s", "mu_k", "stick_velocity", "stribeck_velocity", "viscous")


# ----------------------------------------------------------------------------------------------
# friction law
# ----------------------------------------------------------------------------------------------
class FrictionLaw:
    """The spec's shaft friction law on journal radius ``r`` (m), split into speed regimes.

    Regime ``i`` covers speeds ``bounds[i] < |w| < bounds[i+1]`` (rad/s); within a regime the
    torque is smooth: ``Tf = k(|w|) * Fn + v(w)`` with ``k`` in m (coefficient times radius, with
    the sign of w) and ``v`` in N m.
    """

    def __init__(self, friction: Mapping[str, float] | None, radius: float,
                 zeta_to_viscous: Callable[[float], float] | None = None):
        friction = dict(friction or {})
        allowed = set(FRICTION_KEYS) | ({"zeta"} if zeta_to_viscous is not None else set())
        unknown = sorted(set(friction) - allowed)
        if unknown:
            raise ValueError(f"independent reference: unknown friction key(s) {unknown}; allowed {sorted(allowed)}")
        self.mu_k = float(friction.get("mu_k", 0.0))
        self.mu_s = float(friction.get("mu_s", self.mu_k))
        self.w0 = float(friction.get("stick_velocity", 0.0))
        self.ws = float(friction.get("stribeck_velocity", 0.0))
        if "viscous" in friction:
            self.cv = float(friction["viscous"])
        elif "zeta" in friction:
            self.cv = zeta_to_viscous(float(friction["zeta"]))
        else:
            self.cv = 0.0
        self.r = float(radius)
        for name, value in (("mu_s", self.mu_s), ("mu_k", self.mu_k), ("stick_velocity", self.w0),
                            ("stribeck_velocity", self.ws), ("viscous", self.cv), ("radius", self.r)):
            if not (math.isfinite(value) and value >= 0.0):
                raise ValueError(f"independent reference: {name} must be finite and >= 0, got {value!r}")
        self.ws_shift = self.ws if self.ws > 0.0 else 0.0
        bounds = [0.0]
        if self.w0 > 0.0:
            bounds.append(self.w0)
        if self.ws > max(self.w0, 0.0):
            bounds.append(self.ws)
        bounds.append(math.inf)
        self.bounds = bounds
        self.kinds = []
        for lo, hi in zip(bounds[:-1], bounds[1:]):
            self.kinds.append(self.kind(0.5 * (lo + hi) if math.isfinite(hi) else lo + 1.0))

    def kind(self, speed: float) -> str:
        if speed <= self.w0:
            return "band"
        if self.ws > 0.0 and speed < self.ws:
            return "stribeck"
        return "kinetic"

    def regime_of(self, speed: float) -> int:
        """Index of the regime with bounds[i] <= speed < bounds[i+1]."""
        for i in range(len(self.bounds) - 1):
            if self.bounds[i] <= speed < self.bounds[i + 1]:
                return i
        raise SimulationError(f"independent reference: non-finite shaft speed {speed!r}")

    def split(self, regime: int, w: float, s: float) -> tuple[float, float]:
        """(k, v): Tf = k * Fn + v in the given regime, shaft speed w, direction s = +-1."""
        kind = self.kinds[regime]
        if kind == "band":
            return self.mu_s * self.r * s, 0.0
        if kind == "stribeck":
            return (self.mu_s - (self.mu_s - self.mu_k) * abs(w) / self.ws) * self.r * s, 0.0
        return self.mu_k * self.r * s, self.cv * (w - self.ws_shift * s)

    def holds(self, torque: float, fn0: float) -> bool:
        """Static friction can carry ``torque`` with the shaft at rest (reaction ``fn0``)."""
        return abs(torque) <= self.mu_s * self.r * fn0


def coupled_acceleration(a_free: float, b0: float, k: float, v: float, R0: Sequence[float],
                         R1: Sequence[float]) -> float:
    """Solve theta'' = a_free - b0 * (k |R0 + R1 theta''| + v) for theta'' (Brent's method).

    g(a) = a - a_free + b0 (k |R0 + R1 a| + v) is strictly increasing (g' >= 1 - |b0 k| |R1| > 0),
    so the root is unique; the bracket a_c +- D below follows from |R0 + R1 a| <= |R0| + |R1| |a|.
    """
    a_c = a_free - b0 * v
    if k == 0.0:
        return a_c
    ck = abs(b0 * k)
    r1 = math.hypot(R1[0], R1[1])
    c = ck * r1
    if not c < 1.0:
        raise SimulationError("independent reference: friction/reaction coupling is ill-posed (|b mu r R1| >= 1)")
    D = ck * (math.hypot(R0[0], R0[1]) + r1 * abs(a_c)) / (1.0 - c)
    if not math.isfinite(D):
        raise SimulationError("independent reference: non-finite reaction force")
    if D == 0.0:
        return a_c
    D = D * (1.0 + 1e-9) + 1e-300

    def g(a):
        return a - a_free + b0 * (k * math.hypot(R0[0] + R1[0] * a, R0[1] + R1[1] * a) + v)

    lo, hi = a_c - D, a_c + D
    for _ in range(60):  # round-off can leave the analytic bracket a hair too tight: widen it
        if g(lo) <= 0.0 <= g(hi):
            break
        D *= 2.0
        lo, hi = a_c - D, a_c + D
    return brentq(g, lo, hi, xtol=1e-15 * (abs(a_c) + D), rtol=1e-15, maxiter=200)

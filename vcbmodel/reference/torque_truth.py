"""A pendulum with an extra torque no registered effect describes, for synthetic records that test
discovery (:mod:`vcbmodel.analysis.discovery`): an independent solve, like the others in this folder,
sharing no law with the model (its friction is written out here; sticking by events)."""
from __future__ import annotations

import math
from collections.abc import Callable, Mapping

import numpy as np
from scipy.integrate import solve_ivp


def _reaction(M: float, I: float, L: float, g: float, th: float, w: float) -> float:
    """Shaft reaction (N) of eq. 5-6 with the frictionless acceleration (the coupling is second order)."""
    acc = -M * g * L * math.sin(th) / I
    return M * math.hypot(g * math.cos(th) + L * w * w, g * math.sin(th) + L * acc)


def pendulum_with_torque(p: Mapping[str, float], gravity: float, radius: float, friction: Mapping[str, float],
                         extra: Callable[[float, float, float], float], t_eval: np.ndarray) -> np.ndarray:
    """Shaft angle (rad) at ``t_eval`` (s) of I th'' = -M g L sin th - T_f + T_x(t, th, w), released from
    rest at ``p["initial_angle"]``: T_f = mu_k r F_n sign(w) + Cv w (``friction``: mu_k, viscous in
    N m s/rad), T_x = ``extra(t s, th rad, w rad/s)`` in N m. The shaft sticks for good when it stops
    where static friction (mu_k r F_n) holds the weight's and the extra torque."""
    M, I, L, g = p["mass"], p["inertia"], p["com_distance"], gravity
    mu_k, cv = friction["mu_k"], friction.get("viscous", 0.0)

    def rhs(s):
        def f(t, y):
            th, w = y
            tf = mu_k * radius * _reaction(M, I, L, g, th, w) * s + cv * w
            return [w, (-M * g * L * math.sin(th) - tf + extra(t, th, w)) / I]
        return f

    def stops(t, y):
        return y[1]
    stops.terminal = True

    t_eval = np.asarray(t_eval, float)
    theta = np.full(t_eval.size, np.nan)
    t0, y0 = 0.0, [p["initial_angle"], 0.0]
    while True:
        th = y0[0]
        torque = -M * g * L * math.sin(th) + extra(t0, th, 0.0)
        if abs(torque) <= mu_k * radius * _reaction(M, I, L, g, th, 0.0):
            theta[np.isnan(theta) & (t_eval >= t0 - 1e-12)] = th
            return theta
        s = math.copysign(1.0, torque) if abs(y0[1]) < 1e-12 else math.copysign(1.0, y0[1])
        stops.direction = -s
        sol = solve_ivp(rhs(s), (t0, t_eval[-1] + 1e-9), y0, method="DOP853", rtol=1e-10, atol=1e-12,
                        events=stops, dense_output=True)
        t1 = sol.t[-1]
        sel = (t_eval >= t0 - 1e-12) & (t_eval <= t1 + 1e-12)
        theta[sel] = sol.sol(t_eval[sel])[0]
        if t1 >= t_eval[-1] or not sol.t_events[0].size:
            return theta
        t0, y0 = t1, [float(sol.y[0, -1]), 0.0]

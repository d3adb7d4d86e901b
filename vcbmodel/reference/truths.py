"""Truth models outside the model's families, for synthetic records whose cause no registered
effect describes (the diagnosis' "not explained" checks): independent solves, like the others in
this folder, sharing no law with the model.

Here: the position-dependent journal friction, and :func:`friction_truth_angle`, which runs a
rig file's pendulum or cam drop under one of :mod:`.truth_friction`'s laws (Tustin, LuGre, Dahl,
a position-dependent torque).
"""
from __future__ import annotations

import math
from typing import Mapping

import numpy as np
from scipy.integrate import solve_ivp

from .truth_friction import KINDS as FRICTION_TRUTHS
from .truth_friction import truth_cam_drop, truth_pendulum

__all__ = ["FRICTION_TRUTHS", "friction_truth_angle", "static_load", "position_dependent_pendulum"]


def static_load(rig: Mapping) -> float:
    """The journal's load at the start (N) of a rig file's (JSON) pendulum (its weight M g) or
    cam drop (the closing springs' initial pull, count k (|B0 - O| - l0))."""
    if rig["experiment"] == "pendulum":
        return float(rig["pendulum"]["mass"] * rig["gravity"])
    cam, spring = rig["cam"], rig["closing_spring"]
    bx = cam["pivot"][0] + cam["arm_length"] * math.cos(cam["initial_angle"]) - spring["anchor"][0]
    by = cam["pivot"][1] + cam["arm_length"] * math.sin(cam["initial_angle"]) - spring["anchor"][1]
    return float(spring["count"] * spring["stiffness"] * (math.hypot(bx, by) - spring["free_length"]))


def friction_truth_angle(kind: str, rig: Mapping, values: Mapping[str, float], t_eval: np.ndarray) -> np.ndarray:
    """The shaft angle (rad) over ``t_eval`` (s) of a rig file's (JSON) pendulum or cam drop
    (massless springs) under friction truth ``kind`` (:data:`FRICTION_TRUTHS`) with ``values``
    (:data:`.truth_friction.NEEDS`)."""
    if rig["experiment"] == "pendulum":
        out = truth_pendulum(kind, rig["pendulum"], rig["gravity"], rig["shaft"]["radius"], values, t_eval)
    elif rig["experiment"] == "cam_drop":
        out = truth_cam_drop(kind, rig["cam"], rig["closing_spring"], rig["gravity"], rig["shaft"]["radius"],
                             values, t_eval)
    else:
        raise ValueError(f"no {kind} friction truth for a {rig['experiment']} rig (pendulum and cam_drop only)")
    return out["theta"]


def position_dependent_pendulum(p: Mapping[str, float], gravity: float, radius: float, friction: Mapping[str, float], amplitude: float,
                                wavelength: float, phase: float, t_eval: np.ndarray) -> np.ndarray:
    """A pendulum whose journal friction depends on the shaft angle (no registered effect):
    T_f = mu_k (1 + a sin(2 pi theta / lambda + phase)) r F_n sign(w) + Cv w, static friction 1.5x
    that; sticking by events (stuck for good once static friction holds the weight's torque).
    The reaction uses eq. 5-6 with the frictionless acceleration (the coupling is second order)."""
    M, I, L, g = p["mass"], p["inertia"], p["com_distance"], gravity
    mu_k, cv = friction["mu_k"], friction.get("viscous", 0.0)

    def mu(th):
        return mu_k * (1 + amplitude * math.sin(2 * math.pi * th / wavelength + phase))

    def reaction(th, w):
        acc = -M * g * L * math.sin(th) / I
        return M * math.hypot(g * math.cos(th) + L * w * w, g * math.sin(th) + L * acc)

    def rhs(s):
        def f(t, y):
            th, w = y
            tf = mu(th) * radius * reaction(th, w) * s + cv * w
            return [w, (-M * g * L * math.sin(th) - tf) / I]
        return f

    def zero(t, y):
        return y[1]
    zero.terminal = True

    t_eval = np.asarray(t_eval, float)
    theta = np.full(t_eval.size, np.nan)
    t0, y0 = 0.0, [p["initial_angle"], 0.0]
    while True:
        th = y0[0]
        torque = -M * g * L * math.sin(th)
        if abs(y0[1]) < 1e-12 and abs(torque) <= 1.5 * mu(th) * radius * reaction(th, 0.0):
            theta[t_eval >= t0 - 1e-12] = np.where(np.isnan(theta[t_eval >= t0 - 1e-12]), th,
                                                   theta[t_eval >= t0 - 1e-12])
            break
        s = math.copysign(1.0, y0[1]) if abs(y0[1]) > 1e-12 else math.copysign(1.0, torque)
        zero.direction = -s
        sol = solve_ivp(rhs(s), (t0, t_eval[-1] + 1e-9), y0, method="DOP853", rtol=1e-10, atol=1e-12,
                        events=zero, dense_output=True)
        t1 = sol.t[-1]
        sel = (t_eval >= t0 - 1e-12) & (t_eval <= t1 + 1e-12)
        theta[sel] = sol.sol(t_eval[sel])[0]
        if t1 >= t_eval[-1] or not sol.t_events[0].size:
            break
        t0, y0 = t1, [float(sol.y[0, -1]), 0.0]
    return theta

"""Independent solve of the paper's equations without Exudyn (verification reference).

The equations of motion are written out by hand (eq. 1 and 5-6 for the pendulum, eq. 9-13
generalised to n spring masses for the cam) and integrated either with scipy's adaptive
``solve_ivp`` (DOP853) or with a plain fixed-step classical Runge-Kutta loop. The friction
law is the spec's law at a given reaction (:func:`vcbmodel.friction.friction_torque`) and
the reaction/acceleration coupling is solved by fixed-point iteration, not by the closed
form the Exudyn models use, so agreement checks that closed form as well.

Why a fixed-step option: with Karnopp's stick band a stuck shaft keeps the (tiny) speed
it had when it entered the band (|w| <= w0) and drifts at that speed; where it lands in the
band depends on the integrator's step, so sticking trajectories are compared with the same
step scheme, and smooth ones (no friction, viscous only, cam drop) with DOP853.
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING, Callable

import numpy as np
from scipy.integrate import solve_ivp

from ..errors import SimulationError
from ..laws.breaker import BreakerLaws, massless_pull
from ..laws.friction import band_width, friction_torque, stuck_torque
from ..laws.mechanics import cam_inertia, cam_loads, cam_pin, pendulum_loads
from . import independent

if TYPE_CHECKING:
    from ..laws.friction import FrictionLaw
    from ..laws.springs import LumpedChain
    from ..model.effects import ModelSpec
    from ..rig.data import Rig


def friction_iterated(w: float, applied_torque: float, R0: tuple[float, float], R1: tuple[float, float], inertia: float, law: FrictionLaw,
                      tol: float = 1e-12, max_iter: int = 100) -> tuple[float, float]:
    """(T_f, F_n): the stick test at rest, the passive stuck state, or the slip law with the
    reaction found by fixed-point iteration F_n -> T_f -> theta'' -> R -> F_n."""
    Fn = math.hypot(*R0)
    band = band_width(law, Fn, inertia)
    if abs(w) <= band and abs(applied_torque) <= law.mu_s * law.radius * Fn:
        if law.sticking == "literal":
            return applied_torque, Fn
        return stuck_torque(w, applied_torque, R0, R1, inertia, law)
    for _ in range(max_iter):
        Tf = friction_torque(w, applied_torque, Fn, law, band)
        acc = (applied_torque - Tf) / inertia
        Fn_new = math.hypot(R0[0] + R1[0] * acc, R0[1] + R1[1] * acc)
        if abs(Fn_new - Fn) <= tol * max(1.0, Fn):
            return friction_torque(w, applied_torque, Fn_new, law, band), Fn_new
        Fn = Fn_new
    raise SimulationError("reference: the reaction-force iteration did not converge")


def pendulum_rhs(rig: Rig, law: FrictionLaw) -> tuple[Callable[[float, np.ndarray], np.ndarray], np.ndarray]:
    p, g = rig.pendulum, rig.gravity

    def rhs(t, y):
        th, w = y
        Tc, R0x, R0y, R1x, R1y = pendulum_loads(th, w, p.mass, p.com_distance, g)
        Tf, _ = friction_iterated(w, Tc, (R0x, R0y), (R1x, R1y), p.inertia, law)
        return np.array([w, (Tc - Tf) / p.inertia])

    return rhs, np.array([p.initial_angle, p.initial_velocity])


def cam_rhs(rig: Rig, law: FrictionLaw, chain: LumpedChain | None = None,
            extension: BreakerExtension | None = None) -> tuple[Callable[[float, np.ndarray], np.ndarray], np.ndarray]:
    """State: theta, omega, then x_i, y_i of each spring mass, then their velocities, then
    the ``extension``'s states (the whole breaker: :class:`BreakerExtension`)."""
    cam, spring, g = rig.cam, rig.closing_spring, rig.gravity
    c = spring.count
    O = np.array(spring.anchor, float)
    if chain is None:
        n, masses, ks, ls = 0, np.zeros(0), np.array([spring.stiffness]), np.array([spring.free_length])
    else:
        n, masses, ks, ls = len(chain.masses), chain.masses, chain.stiffnesses, chain.free_lengths
    masses, ks = c * masses, c * ks
    B0 = np.array(cam_pin(cam.initial_angle, cam))
    fractions = chain.equilibrium_fractions() if chain is not None else np.zeros(0)
    pos0 = O[None, :] + fractions[:, None] * (B0 - O)[None, :]
    y0 = np.concatenate([[cam.initial_angle, cam.initial_velocity], pos0.ravel(), np.zeros(2 * n)])
    weight = spring.weight
    pin = c * chain.pin_mass if chain is not None else 0.0
    inertia = cam_inertia(cam, pin)
    n_cam = len(y0)
    if extension is not None:
        y0 = np.concatenate([y0, extension.y0])

    def rhs(t, y):
        th, w = y[0], y[1]
        pts = y[2:2 + 2 * n].reshape(n, 2)
        B = np.array(cam_pin(th, cam))
        chain_pts = np.vstack([O[None, :], pts, B[None, :]])
        seg = np.diff(chain_pts, axis=0)
        length = np.linalg.norm(seg, axis=1)
        tension = ks * (length - ls)
        f_seg = tension[:, None] * seg / length[:, None]  # force pulling segment's start forward
        acc_pts = (f_seg[1:] - f_seg[:-1]) / masses[:, None] if n else np.zeros((0, 2))
        if weight and n:
            acc_pts[:, 1] -= g
        fx, fy = -f_seg[-1]  # pull of the last segment on B
        Tc, R0x, R0y, R1x, R1y = cam_loads(th, w, cam, fx, fy, g, pin_mass=pin, pin_weight=weight)
        tail = []
        if extension is not None:
            (torque, ex, ey), tail = extension.loads_and_rates(t, th, w, y[n_cam:])
            Tc, R0x, R0y = Tc + torque, R0x - ex, R0y - ey
        Tf, _ = friction_iterated(w, Tc, (R0x, R0y), (R1x, R1y), inertia, law)
        vel = y[2 + 2 * n:n_cam]
        return np.concatenate([[w, (Tc - Tf) / inertia], vel, acc_pts.ravel(), tail])

    return rhs, y0


class BreakerExtension:
    """The whole breaker's follower and poles appended to the cam's equations: state
    (phi, z_1..z_n, phi', z_1'..z_n'); the equations written from the laws directly
    (follower: I_f phi'' = torques; pole: m z'' = rod push - contact + bellows - weight)."""

    def __init__(self, rig, spec):
        self.laws = BreakerLaws.of_rig(rig, spec)
        self.n = rig.breaker.poles.count
        self.initial = self.laws.initial_state(massless_pull(rig.cam, rig.closing_spring))
        self.y0 = np.array([self.initial.follower_angle, *self.initial.pole_travel, 0.0, *([0.0] * self.n)])
        self.impact = np.zeros(self.n + 1)
        self.engaged = 0.0  # the holding latch's memory (breaker.hold_latch)
        self.offset = None  # index of the extension in the full state (set by reference_closing)

    def loads_and_rates(self, t: float, th: float, w: float, y: np.ndarray) -> tuple:
        laws, n, b = self.laws, self.n, self.laws.b
        phi, z, phid, zd = y[0], y[1:1 + n], y[1 + n], y[2 + n:]
        t_fol, _ = laws.follower_torque(th, w, phi, phid, z, zd, self.impact[0])
        acc = [(laws.rod_loads(phi, phid, z[i], zd[i])[0] - laws.pole_contact(i, z[i], zd[i], self.impact[i + 1])
                + laws.pole_load) / b.poles.moving_mass for i in range(n)]
        rates = np.concatenate([[phid], zd, [t_fol / b.follower.inertia], acc])
        # the roller's and the latch's loads on the cam (torque, and force into the journal)
        return laws.cam_loads(t, th, w, phi, phid, self.initial.holding_torque, self.impact[0], self.engaged), rates

    def pre_step(self, t: float, y_full: np.ndarray) -> None:
        y, n = y_full[self.offset:], self.n
        self.laws.latch_impact_speeds(self.impact, y_full[0], y_full[1], y[0], y[1 + n], y[1:1 + n], y[2 + n:])
        self.engaged = self.laws.engage(self.engaged, y_full[0])


def rk4(rhs: Callable[[float, np.ndarray], np.ndarray], y0: np.ndarray, t_end: float, step: float,
        pre_step: Callable[[float, np.ndarray], None] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Classical fixed-step Runge-Kutta (returns t, Y); ``pre_step(t, y)`` runs before each step."""
    n = max(1, int(round(t_end / step)))
    h = t_end / n
    Y = np.empty((n + 1, len(y0)))
    Y[0] = y = np.array(y0, float)
    t = 0.0
    for i in range(n):
        if pre_step is not None:
            pre_step(t, y)
        k1 = rhs(t, y)
        k2 = rhs(t + h / 2, y + h / 2 * k1)
        k3 = rhs(t + h / 2, y + h / 2 * k2)
        k4 = rhs(t + h, y + h * k3)
        y = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        t += h
        Y[i + 1] = y
    return np.linspace(0.0, t_end, n + 1), Y


def friction_values(law: FrictionLaw) -> dict[str, float]:
    """The friction law's values as the independent reference takes them."""
    return {"mu_s": law.mu_s, "mu_k": law.mu_k, "stick_velocity": law.stick_velocity,
            "stribeck_velocity": law.stribeck_velocity, "viscous": law.viscous}


def reference_pendulum(rig: Rig, spec: ModelSpec, law: FrictionLaw, chain: LumpedChain | None, t_end: float, method: str = "DOP853",
                       step: float | None = None) -> tuple[dict[str, np.ndarray], dict]:
    """The pendulum from :mod:`vcbmodel.reference.independent` (shares no law with the model;
    event-driven sticking), as sensor rows sampled every ``step`` (default 1e-4 s)."""
    t = _sample_times(t_end, step)
    p = rig.pendulum
    out = independent.pendulum(p.mass, p.inertia, p.com_distance, rig.gravity, rig.shaft_radius, friction_values(law),
                               p.initial_angle, p.initial_velocity, t)
    return _shaft_rows(t, out)


def reference_cam_drop(rig: Rig, spec: ModelSpec, law: FrictionLaw, chain: LumpedChain | None, t_end: float, method: str = "DOP853",
                       step: float | None = None) -> tuple[dict[str, np.ndarray], dict]:
    """The cam drop from :mod:`vcbmodel.reference.independent`, as :func:`reference_pendulum`."""
    t = _sample_times(t_end, step)
    cam, spring = rig.cam, rig.closing_spring
    chain_data = None
    if chain is not None:
        O, B = np.array(spring.anchor), np.array(cam_pin(cam.initial_angle, cam))
        positions = O[None, :] + chain.equilibrium_fractions()[:, None] * (B - O)[None, :]
        chain_data = {"masses": list(chain.masses), "stiffnesses": list(chain.stiffnesses),
                      "free_lengths": list(chain.free_lengths), "positions": positions, "pin_mass": chain.pin_mass}
    out = independent.cam_drop(
        {"mass": cam.mass, "inertia_com": cam.inertia_com, "com_distance": cam.com_distance,
         "com_angle": cam.com_angle, "pivot": tuple(cam.pivot), "arm_length": cam.arm_length,
         "initial_angle": cam.initial_angle, "initial_velocity": cam.initial_velocity},
        {"count": spring.count, "anchor": tuple(spring.anchor), "stiffness": spring.stiffness,
         "free_length": spring.free_length, "chain": chain_data, "weight": spring.weight},
        rig.gravity, rig.shaft_radius, friction_values(law), t)
    return _shaft_rows(t, out)


def _sample_times(t_end, step):
    return np.linspace(0.0, t_end, int(round(t_end / (step or 1e-4))) + 1)


def _shaft_rows(t, out):
    def rows(*columns):
        return np.column_stack([t, *columns])

    data = {"angle": rows(out["theta"]), "velocity": rows(out["omega"]),
            "friction_torque": rows(-out["friction_torque"])}
    for i in range(out["mass_positions"].shape[1] if "mass_positions" in out else 0):
        data[f"spring_mass_{i + 1}"] = rows(out["mass_positions"][:, i, 0], out["mass_positions"][:, i, 1])
        data[f"spring_velocity_{i + 1}"] = rows(out["mass_velocities"][:, i, 0], out["mass_velocities"][:, i, 1])
    return data, {"backend": "reference", "method": "independent (sympy Lagrange, event-driven sticking)",
                  "stuck": out["stuck"]}


def reference_closing(rig: Rig, spec: ModelSpec, law: FrictionLaw, chain: LumpedChain | None, t_end: float, method: str = "DOP853",
                      step: float | None = None) -> tuple[dict[str, np.ndarray], dict]:
    """The whole breaker without Exudyn: the hand-written equations above with the model's laws
    (a wiring check), adaptive or fixed-step RK4.

    Every ``reference_*`` solve returns (data, info): ``data`` maps the Exudyn builders' sensor
    names (``angle``, ``velocity``, ``spring_mass_k``, ``spring_velocity_k``, ``follower_angle``,
    ``pole_i_travel``, ...) to arrays of rows (t, values...), so the experiments assemble
    channels from either backend the same way; ``info`` holds the breaker's initial state. For the
    pendulum and the cam drop ``method`` and ``step`` only set the output sampling. Each
    experiment's record names its solve (``Experiment.reference``).
    """
    extension = BreakerExtension(rig, spec)
    rhs, y0 = cam_rhs(rig, law, chain, extension)
    extension.offset = len(y0) - len(extension.y0)
    if method != "rk4" and spec.restitution < 1.0:
        raise ValueError("the breaker's contact damping needs the fixed-step reference (method='rk4')")
    if method != "rk4" and rig.breaker.hold_latch is not None:
        raise ValueError("the breaker's holding latch (its engagement is pre-step memory) needs the fixed-step "
                         "reference (method='rk4')")
    if method == "rk4":
        t, Y = rk4(rhs, y0, t_end, step, extension.pre_step)
    else:
        sol = solve_ivp(rhs, (0.0, t_end), y0, method=method, rtol=1e-10, atol=1e-12,
                        max_step=step or np.inf, dense_output=True)
        if not sol.success:
            raise SimulationError(f"reference solver failed: {sol.message}")
        t = np.linspace(0.0, t_end, int(round(t_end / 1e-4)) + 1)
        Y = sol.sol(t).T
    if not np.all(np.isfinite(Y)):
        raise SimulationError("reference solution is not finite")

    def rows(*columns):
        return np.column_stack([t, *columns])

    data = {"angle": rows(Y[:, 0]), "velocity": rows(Y[:, 1])}
    n_cam = len(y0) - len(extension.y0)
    n = (n_cam - 2) // 4
    for i in range(n):
        data[f"spring_mass_{i + 1}"] = rows(Y[:, 2 + 2 * i], Y[:, 3 + 2 * i])
        data[f"spring_velocity_{i + 1}"] = rows(Y[:, 2 + 2 * n + 2 * i], Y[:, 3 + 2 * n + 2 * i])
    o, poles = extension.offset, extension.n
    data["follower_angle"], data["follower_velocity"] = rows(Y[:, o]), rows(Y[:, o + 1 + poles])
    for i in range(poles):
        data[f"pole_{i + 1}_travel"] = rows(Y[:, o + 1 + i])
        data[f"pole_{i + 1}_travel_velocity"] = rows(Y[:, o + 2 + poles + i])
    return data, {"backend": "reference", "method": method, "initial": extension.initial}

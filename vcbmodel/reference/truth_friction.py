"""Friction truths from outside the fitted family: Tustin, LuGre, Dahl, and a position-dependent torque.

The diagnosis fits the spec's hybrid law (Karnopp band, linear Stribeck branch, Coulomb, a
viscous term shifted by the Stribeck velocity). Synthetic records whose friction *is* that law
make agreement nearly certain; these truths make records whose friction is not in the family:

=================== ==========================================================================
``tustin``          Tustin's exponential Stribeck curve (Tustin 1947; survey: Armstrong-
                    Helouvry, Dupont & Canudas de Wit, Automatica 30, 1994):
                    T_f = [mu_k + (mu_s - mu_k) exp(-|w|/w_s)] r F_n sign(w) + C_v w,
                    with exact sticking (stuck while |T_c| <= mu_s r F_n).
``power``           a Stribeck fall with an exponent d (Armstrong-Helouvry et al. 1994, eq. 5):
                    T_f = [mu_k + (mu_s - mu_k) exp(-(|w|/w_s)^d)] r F_n sign(w) + C_v w,
                    sticking as Tustin's (d = 1 is Tustin's curve).
``lugre``           the LuGre bristle model (Canudas de Wit, Olsson, Astrom & Lischinsky, IEEE
                    TAC 40, 1995), per unit normal force, with the slip speed v = r w (m/s):
                    dz/dt = v - sigma0 |v| z / g(w), g(w) = mu_k + (mu_s - mu_k) exp(-(w/w_s)^2),
                    T_f = [sigma0 z + sigma1 exp(-(w/w_s)^2) dz/dt] r F_n + C_v w: micrometres
                    of pre-sliding (z ~ g/sigma0), no true sticking. The damping sigma1 fades
                    with speed (Olsson et al., Eur. J. Control 4, 1998) so that it acts in
                    pre-sliding only.
``dahl``            Dahl's model (Dahl, Aerospace Corp. TOR-0158, 1968) with exponent 1:
                    dz/dt = v - sigma0 |v| z / mu_k, T_f = sigma0 z r F_n + C_v w: pre-sliding
                    hysteresis, no static peak, no Stribeck fall.
``position_torque`` Coulomb (static mu_s, kinetic mu_k) and viscous friction with exact
                    sticking, plus a position-dependent torque on the shaft, a cogging or
                    defect torque T_p = a sin(k theta + p) (N m); no registered effect has it.
=================== ==========================================================================

What they share with the model (and so cannot test): the mechanism (the independent Lagrange
equations and Newton-Euler reactions of :mod:`.independent_lagrange`, paper eq. 1, 5-6 and
9-13), friction proportional to the journal reaction on radius r, the meaning of ``mu_k`` as
the kinetic level at speeds well above the Stribeck range, of ``mu_s`` as the level at rest and
of ``viscous`` as a torque C_v w. What they do not share: every law's form between rest and
sliding (and the position torque). No import from :mod:`vcbmodel.laws`; the integration is
scipy's (event-driven DOP853 for the sticking laws, LSODA for the stiff bristle state).

Units: SI. Angles in rad, speeds in rad/s, torques in N m, forces in N, radius and bristle
deflection z in m, sigma0 in 1/m, sigma1 in s/m, C_v in N m s/rad, a in N m, k in 1/rad.
"""
from __future__ import annotations

import math
from typing import Any, Callable, Mapping

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import solve_ivp

from vcbmodel.errors import SimulationError

from .independent_friction import FrictionLaw, coupled_acceleration
from .independent_hybrid import Hybrid
from .independent_lagrange import CamMechanism, PendulumMechanism

KINDS = ("tustin", "lugre", "dahl", "position_torque")
#: Truths beside :data:`KINDS` (which the realism study draws, seed for seed): not drawn there.
FURTHER_KINDS = ("power",)
#: The values each truth needs (besides the mechanism).
NEEDS = {"tustin": ("mu_s", "mu_k", "stribeck_velocity", "viscous"),
         "power": ("mu_s", "mu_k", "stribeck_velocity", "viscous", "stribeck_exponent"),
         "lugre": ("mu_s", "mu_k", "stribeck_velocity", "viscous", "sigma0", "sigma1"),
         "dahl": ("mu_k", "viscous", "sigma0"),
         "position_torque": ("mu_s", "mu_k", "viscous", "amplitude", "wavenumber", "phase")}
#: Tolerances: DOP853 (relative, absolute) for the sticking laws; LSODA relative, and absolute
#: per state kind (rad, rad/s, m of bristle deflection) for the bristle laws.
RTOL, ATOL = 1e-10, 1e-12
BRISTLE_RTOL, BRISTLE_ATOL = 1e-8, (1e-10, 1e-9, 1e-13)


# ----------------------------------------------------------------------------------------------
# the laws (pure)
# ----------------------------------------------------------------------------------------------
def tustin_coefficient(w: float, mu_s: float, mu_k: float, decay_velocity: float) -> float:
    """Tustin's friction coefficient (-) at shaft speed ``w`` (rad/s): mu_k + (mu_s - mu_k)
    exp(-|w| / w_s), ``decay_velocity`` w_s in rad/s."""
    return mu_k + (mu_s - mu_k) * math.exp(-abs(w) / decay_velocity)


def power_coefficient(w: float, mu_s: float, mu_k: float, decay_velocity: float, exponent: float) -> float:
    """The generalised Stribeck coefficient (-) at shaft speed ``w`` (rad/s): mu_k + (mu_s - mu_k)
    exp(-(|w| / w_s)^d), ``decay_velocity`` w_s in rad/s, ``exponent`` d (-)."""
    return mu_k + (mu_s - mu_k) * math.exp(-((abs(w) / decay_velocity) ** exponent))


def lugre_level(w: float, mu_s: float, mu_k: float, stribeck_velocity: float) -> float:
    """LuGre's steady-state coefficient g(w) (-): mu_k + (mu_s - mu_k) exp(-(w / w_s)^2)."""
    return mu_k + (mu_s - mu_k) * math.exp(-(w / stribeck_velocity) ** 2)


def bristle_rate(z: float, slip_speed: float, level: float, sigma0: float) -> float:
    """dz/dt (m/s) of the bristle deflection ``z`` (m) at slip speed v = r w (m/s): v - sigma0
    |v| z / g, with steady level g (-) and stiffness sigma0 (1/m, per unit normal force). LuGre
    with g = g(w); Dahl (exponent 1) with g = mu_k."""
    return slip_speed - sigma0 * abs(slip_speed) * z / level


def bristle_coefficient(z: float, z_rate: float, sigma0: float, sigma1: float) -> float:
    """The bristles' friction coefficient (-): sigma0 z + sigma1 dz/dt (z in m, dz/dt in m/s)."""
    return sigma0 * z + sigma1 * z_rate


def position_torque(theta: float, amplitude: float, wavenumber: float, phase: float) -> float:
    """A cogging or defect torque on the shaft (N m): a sin(k theta + p); a in N m, k in 1/rad.
    It is conservative, with potential (a / k) cos(k theta + p)."""
    return amplitude * math.sin(wavenumber * theta + phase)


def position_potential(theta: float, amplitude: float, wavenumber: float, phase: float) -> float:
    """The potential (J) of :func:`position_torque`: T_p = -dV/dtheta."""
    return amplitude / wavenumber * math.cos(wavenumber * theta + phase)


# ----------------------------------------------------------------------------------------------
# laws and mechanisms for the event-driven integration (independent_hybrid.Hybrid)
# ----------------------------------------------------------------------------------------------
class TustinLaw:
    """Tustin's law on journal radius ``r`` (m) in the form :class:`.independent_hybrid.Hybrid`
    integrates: one smooth slip regime, T_f = k F_n + v, sticking while |T_c| <= mu_s r F_n; with a
    ``stribeck_exponent`` d among ``values``, the generalised curve (:func:`power_coefficient`)."""

    kinds = ("tustin", "power")
    bounds = (0.0, math.inf)

    def __init__(self, values: Mapping[str, float], radius: float):
        self.mu_s, self.mu_k = float(values["mu_s"]), float(values["mu_k"])
        self.ws, self.cv, self.r = float(values["stribeck_velocity"]), float(values["viscous"]), float(radius)
        self.d = float(values.get("stribeck_exponent", 1.0))

    def regime_of(self, speed: float) -> int:
        if not math.isfinite(speed):
            raise SimulationError(f"Tustin truth: non-finite shaft speed {speed!r}")
        return 0

    def split(self, regime: int, w: float, s: float) -> tuple[float, float]:
        """(k in m, v in N m): T_f = k F_n + v at shaft speed w, direction s."""
        return power_coefficient(w, self.mu_s, self.mu_k, self.ws, self.d) * self.r * s, self.cv * w

    def holds(self, torque: float, fn0: float) -> bool:
        return abs(torque) <= self.mu_s * self.r * fn0


class WithPositionTorque:
    """A mechanism (q[0] the shaft angle) with :func:`position_torque` added on the shaft."""

    def __init__(self, mech, amplitude: float, wavenumber: float, phase: float):
        self.mech, self.nq = mech, mech.nq
        self.shape = (float(amplitude), float(wavenumber), float(phase))

    def mass(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return self.mech.mass(q)

    def forces(self, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        h = np.array(self.mech.forces(q, qd), float)
        h[0] -= position_torque(q[0], *self.shape)  # M q'' + h = Q: an applied torque lowers h
        return h

    def reaction(self, q: np.ndarray, qd: np.ndarray):
        return self.mech.reaction(q, qd)  # a pure torque: the bearing force is unchanged


# ----------------------------------------------------------------------------------------------
# integration
# ----------------------------------------------------------------------------------------------
def _sticking_run(mech, law, q0, qd0, t_eval: np.ndarray) -> dict[str, np.ndarray]:
    hybrid = Hybrid(mech, law, RTOL, ATOL)
    try:
        segments, _ = hybrid.run(q0, qd0, float(t_eval[-1]))
        out, Q, QD = hybrid.sample(segments, t_eval)
    except (ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
        raise SimulationError(f"friction truth: {type(exc).__name__}: {exc}") from exc
    return {"t": t_eval, "theta": out["theta"], "omega": out["omega"], "friction_torque": out["friction_torque"],
            "q": Q, "qd": QD}


def _bristle_law(kind: str, values: Mapping[str, float], radius: float) -> Callable[[float, float], tuple[float, float]]:
    """(z, w) -> (dz/dt m/s, friction coefficient -) of the LuGre or Dahl truth."""
    s0 = float(values["sigma0"])
    if kind == "dahl":
        mu_k = float(values["mu_k"])

        def dahl(z, w):
            rate = bristle_rate(z, radius * w, mu_k, s0)
            return rate, bristle_coefficient(z, rate, s0, 0.0)
        return dahl
    mu_s, mu_k, ws, s1 = (float(values[k]) for k in ("mu_s", "mu_k", "stribeck_velocity", "sigma1"))

    def lugre(z, w):
        rate = bristle_rate(z, radius * w, lugre_level(w, mu_s, mu_k, ws), s0)
        return rate, bristle_coefficient(z, rate, s0, s1 * math.exp(-(w / ws) ** 2))
    return lugre


def _bristle_run(mech, bristles, radius: float, viscous: float, q0, qd0, t_eval: np.ndarray) -> dict[str, np.ndarray]:
    """Integrate (q, q', z) with LSODA; the friction/reaction coupling solved at each call."""
    nq = mech.nq

    def accelerations(y):
        q, qd, z = y[:nq], y[nq:2 * nq], y[-1]
        _, Minv = mech.mass(q)
        a_free, b = -Minv @ mech.forces(q, qd), Minv[:, 0]
        rate, mu = bristles(z, qd[0])
        k, v = mu * radius, viscous * qd[0]
        R0, R1 = mech.reaction(q, qd)
        a = coupled_acceleration(a_free[0], b[0], k, v, R0, R1)
        tf = k * math.hypot(R0[0] + R1[0] * a, R0[1] + R1[1] * a) + v
        return a_free - b * tf, rate, tf

    def rhs(t, y):
        if not np.all(np.isfinite(y)):
            raise SimulationError(f"friction truth: non-finite state at t = {t:.6g} s")
        qdd, rate, _ = accelerations(y)
        return np.concatenate([y[nq:2 * nq], qdd, [rate]])

    y0 = np.concatenate([np.asarray(q0, float), np.asarray(qd0, float), [0.0]])
    atol = np.array([BRISTLE_ATOL[0]] * nq + [BRISTLE_ATOL[1]] * nq + [BRISTLE_ATOL[2]])
    sol = solve_ivp(rhs, (0.0, float(t_eval[-1])), y0, method="LSODA", t_eval=t_eval, rtol=BRISTLE_RTOL, atol=atol)
    if not sol.success:
        raise SimulationError(f"friction truth: the bristle solve failed: {sol.message}")
    Y = sol.y.T
    tf = np.array([accelerations(y)[2] for y in Y])
    return {"t": t_eval, "theta": Y[:, 0], "omega": Y[:, nq], "friction_torque": tf, "bristle": Y[:, -1],
            "q": Y[:, :nq], "qd": Y[:, nq:2 * nq]}


def _check(kind: str, values: Mapping[str, float], t_eval: ArrayLike) -> np.ndarray:
    if kind not in KINDS + FURTHER_KINDS:
        raise ValueError(f"unknown friction truth {kind!r} (known: {', '.join(KINDS + FURTHER_KINDS)})")
    missing = [k for k in NEEDS[kind] if k not in values]
    if missing:
        raise ValueError(f"{kind} friction truth needs {', '.join(missing)}")
    bad = [k for k in NEEDS[kind] if not math.isfinite(float(values[k])) or (k != "phase" and float(values[k]) < 0.0)]
    if bad:
        raise ValueError(f"{kind} friction truth: {', '.join(bad)} must be finite and >= 0")
    t = np.asarray(t_eval, float).ravel()
    if t.size == 0 or t[0] < 0.0 or np.any(np.diff(t) < 0.0) or not np.all(np.isfinite(t)):
        raise ValueError("friction truth: t_eval must be non-empty, finite, non-decreasing and >= 0")
    return t


def _solve(kind: str, mech, radius: float, values: Mapping[str, float], q0, qd0, t: np.ndarray) -> dict[str, np.ndarray]:
    if kind in ("tustin", "power"):
        return _sticking_run(mech, TustinLaw(values, radius), q0, qd0, t)
    if kind == "position_torque":
        law = FrictionLaw({k: float(values[k]) for k in ("mu_s", "mu_k", "viscous")}, radius)
        shaped = WithPositionTorque(mech, values["amplitude"], values["wavenumber"], values["phase"])
        return _sticking_run(shaped, law, q0, qd0, t)
    return _bristle_run(mech, _bristle_law(kind, values, radius), radius, float(values["viscous"]), q0, qd0, t)


# ----------------------------------------------------------------------------------------------
# public API
# ----------------------------------------------------------------------------------------------
def truth_pendulum(kind: str, pendulum: Mapping[str, float], gravity: float, radius: float,
                   values: Mapping[str, float], t_eval: ArrayLike) -> dict[str, np.ndarray]:
    """The pendulum test (paper eq. 1, 5-6) under friction truth ``kind`` (:data:`KINDS`).

    ``pendulum``: ``mass`` (kg), ``inertia`` (kg m^2), ``com_distance`` (m), ``initial_angle``
    (rad), ``initial_velocity`` (rad/s, default 0), as in a rig file; ``values``: the truth's
    values (:data:`NEEDS`). Returns arrays over ``t`` (s): ``theta`` (rad), ``omega`` (rad/s),
    ``friction_torque`` (N m, opposing the motion), and ``bristle`` z (m) for LuGre and Dahl.
    """
    t = _check(kind, values, t_eval)
    mech = PendulumMechanism(pendulum["mass"], pendulum["inertia"], pendulum["com_distance"], gravity)
    return _solve(kind, mech, float(radius), values, [float(pendulum["initial_angle"])],
                  [float(pendulum.get("initial_velocity", 0.0))], t)


def truth_cam_drop(kind: str, cam: Mapping[str, Any], spring: Mapping[str, Any], gravity: float, radius: float,
                   values: Mapping[str, float], t_eval: ArrayLike) -> dict[str, np.ndarray]:
    """The cam drop (paper eq. 9-13) with massless closing springs under friction truth ``kind``.

    ``cam`` and ``spring`` as a rig file's ``cam`` and ``closing_spring`` (count, stiffness,
    free_length, anchor; the spring's mass is not used); returns as :func:`truth_pendulum`."""
    t = _check(kind, values, t_eval)
    spring = {"count": spring["count"], "anchor": tuple(spring["anchor"]), "stiffness": spring["stiffness"],
              "free_length": spring["free_length"], "chain": None}
    try:
        mech = CamMechanism(cam, spring, gravity)
    except KeyError as exc:
        raise ValueError(f"friction truth: the cam or spring lacks {exc}") from None
    return _solve(kind, mech, float(radius), values, [float(cam["initial_angle"])],
                  [float(cam.get("initial_velocity", 0.0))], t)

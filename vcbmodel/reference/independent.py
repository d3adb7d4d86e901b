"""A reference solve of the pendulum and cam-drop experiments that shares no code with the model.

Why this exists
---------------
The Exudyn model (and the older ``reference`` solve, which reuses the model's loads and friction
law) must be checked against something written separately from the equations. This module
imports nothing from :mod:`vcbmodel` except :class:`vcbmodel.errors.SimulationError`; it depends
only on numpy, scipy and sympy.

Units: SI throughout. Lengths in m, masses in kg, inertias in kg m^2, times in s, angles in rad
(counter-clockwise positive), angular velocities in rad/s, torques in N m, forces in N,
stiffnesses in N/m, viscous coefficients in N m s/rad, gravity in m/s^2 (acting along -y).

Method
------
* Equations of motion: Lagrange's equations, derived once per model structure with sympy from the
  kinetic and potential energies in the generalised coordinates (theta, x_1, y_1, ..., x_n, y_n),
  with the shaft friction torque as the generalised force -Tf on theta, then lambdified.
  ``M(q) q'' + h(q, q') = Q`` with ``Q = (-Tf, 0, ..., 0)``.
* Shaft reaction: Newton-Euler on the rotating body, written separately from the Lagrangian
  (pendulum: paper eq. 5-6; cam: sum of forces on cam + pin mass = m_c a_G + m_pin a_B, with the
  spring pull on B, the weights and the bearing force at A). The reaction is linear in theta'':
  F = R0 + R1 theta''.
* Friction/acceleration coupling: Fn = |R0 + R1 theta''| and theta'' depends on Tf(Fn); the scalar
  equation theta'' = a_free - b Tf(Fn(theta'')) is solved with Brent's method on a bracket that is
  guaranteed to contain the unique root when |b mu r R1| < 1 (otherwise the problem is ill-posed
  and SimulationError is raised).
* Friction law (spec "The shaft friction law", passive sticking): an event-driven hybrid
  integration with scipy's DOP853 at tight tolerances.
    - slip mode, sign s = sign(w), in a speed regime: band (|w| <= w0): Tf = mu_s r Fn s;
      Stribeck (w0 < |w| < ws): Tf = (mu_s - (mu_s - mu_k)|w|/ws) r Fn s; kinetic (otherwise):
      Tf = mu_k r Fn s + Cv (w - ws' s), ws' = ws if a Stribeck velocity is given, else 0.
      Regime boundaries are terminal events, so each integration segment has a smooth right-hand
      side (no discontinuity inside a DOP853 step).
    - w reaching 0: the shaft sticks if |Tc| <= mu_s r Fn0 (Fn0: the reaction with w = 0 and
      theta'' = 0); otherwise it continues slipping in the direction of Tc.
    - stuck mode: theta frozen, w = 0 exactly, Tf = Tc (the torque needed to hold it); the spring
      masses (if any) keep moving, and the event |Tc| = mu_s r Fn0 (rising) breaks the shaft away
      in the direction of Tc.
    - starting from rest: stuck if static friction can hold, else break away.
  With this, a stuck shaft does not creep at all and friction never does positive work.

Public API: :func:`pendulum`, :func:`cam_drop`; both return a dict of numpy arrays.
"""
from __future__ import annotations

import functools
import math

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from vcbmodel.errors import SimulationError

#: Default DOP853 tolerances (relative, absolute). Absolute tolerance applies to every state
#: component (rad, rad/s, m, m/s).
RTOL = 1e-11
ATOL = 1e-12
#: Guard against Zeno behaviour (endless stick/slip or regime switching).
MAX_SEGMENTS = 200_000

FRICTION_KEYS = ("mu_s", "mu_k", "stick_velocity", "stribeck_velocity", "viscous")


# ----------------------------------------------------------------------------------------------
# friction law
# ----------------------------------------------------------------------------------------------
class _FrictionLaw:
    """The spec's shaft friction law on journal radius ``r`` (m), split into speed regimes.

    Regime ``i`` covers speeds ``bounds[i] < |w| < bounds[i+1]`` (rad/s); within a regime the
    torque is smooth: ``Tf = k(|w|) * Fn + v(w)`` with ``k`` in m (coefficient times radius, with
    the sign of w) and ``v`` in N m.
    """

    def __init__(self, friction, radius, zeta_to_viscous=None):
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

    def kind(self, speed):
        if speed <= self.w0:
            return "band"
        if self.ws > 0.0 and speed < self.ws:
            return "stribeck"
        return "kinetic"

    def regime_of(self, speed):
        """Index of the regime with bounds[i] <= speed < bounds[i+1]."""
        for i in range(len(self.bounds) - 1):
            if self.bounds[i] <= speed < self.bounds[i + 1]:
                return i
        raise SimulationError(f"independent reference: non-finite shaft speed {speed!r}")

    def split(self, regime, w, s):
        """(k, v): Tf = k * Fn + v in the given regime, shaft speed w, direction s = +-1."""
        kind = self.kinds[regime]
        if kind == "band":
            return self.mu_s * self.r * s, 0.0
        if kind == "stribeck":
            return (self.mu_s - (self.mu_s - self.mu_k) * abs(w) / self.ws) * self.r * s, 0.0
        return self.mu_k * self.r * s, self.cv * (w - self.ws_shift * s)

    def holds(self, torque, fn0):
        """Static friction can carry ``torque`` with the shaft at rest (reaction ``fn0``)."""
        return abs(torque) <= self.mu_s * self.r * fn0


def _coupled_acceleration(a_free, b0, k, v, R0, R1):
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


# ----------------------------------------------------------------------------------------------
# equations of motion (Lagrange, sympy)
# ----------------------------------------------------------------------------------------------
def _lagrange(T, V, coords, t):
    """Lagrange's equations d/dt dL/dq' - dL/dq = Q as M(q) q'' + h(q, q') (sympy)."""
    L = T - V
    eqs = [sp.diff(sp.diff(L, sp.diff(q, t)), t) - sp.diff(L, q) for q in coords]
    nq = len(coords)
    qs = sp.symbols(f"q0:{nq}")
    qds = sp.symbols(f"qd0:{nq}")
    qdds = sp.symbols(f"qdd0:{nq}")
    sub2 = {sp.diff(q, t, 2): s for q, s in zip(coords, qdds)}
    sub1 = {sp.diff(q, t): s for q, s in zip(coords, qds)}
    sub0 = {q: s for q, s in zip(coords, qs)}
    eqs = [e.subs(sub2).subs(sub1).subs(sub0) for e in eqs]
    E = sp.Matrix(eqs)
    M = E.jacobian(sp.Matrix(qdds)).applyfunc(lambda e: sp.trigsimp(sp.simplify(e)))
    h = E.subs({s: 0 for s in qdds})
    return qs, qds, M, h


class _Equations:
    """Lambdified M(q, p) and h(q, q', p) with the symbol lists they take."""

    def __init__(self, qs, qds, params, M, h):
        self.nq = len(qs)
        self.constant_mass = not (M.free_symbols & (set(qs) | set(qds)))
        self._M = sp.lambdify([qs, params], M, modules="numpy")
        self._h = sp.lambdify([qs, qds, params], list(h), modules="numpy", cse=True)

    def mass(self, q, p):
        return np.array(self._M(q, p), dtype=float)

    def forces(self, q, qd, p):
        return np.array(self._h(q, qd, p), dtype=float)


@functools.lru_cache(maxsize=None)
def _pendulum_equations():
    t = sp.Symbol("t")
    th = sp.Function("theta")(t)
    I, M, g, L = sp.symbols("I M g L", positive=True)
    T = I * sp.diff(th, t) ** 2 / 2
    V = -M * g * L * sp.cos(th)  # centre of mass at L (sin th, -cos th)
    qs, qds, Mm, h = _lagrange(T, V, [th], t)
    return _Equations(qs, qds, [I, M, g, L], Mm, h)


@functools.lru_cache(maxsize=None)
def _cam_equations(n):
    """Cam + pin mass rotating about A, n spring point masses in the plane, n+1 axial springs.

    Parameters (all totals over the ``count`` springs): Ic, mc, lg, psi, Ax, Ay, lAB, Ox, Oy,
    g (gravity on the cam), gw (gravity on spring and pin masses: g or 0), mpin, m_1..m_n,
    k_1..k_{n+1}, l_1..l_{n+1}.
    """
    t = sp.Symbol("t")
    th = sp.Function("theta")(t)
    xs = [sp.Function(f"x{i + 1}")(t) for i in range(n)]
    ys = [sp.Function(f"y{i + 1}")(t) for i in range(n)]
    Ic, mc, lg, psi, Ax, Ay, lAB, Ox, Oy, g, gw, mpin = sp.symbols("Ic mc lg psi Ax Ay lAB Ox Oy g gw mpin", real=True)
    ms = sp.symbols(f"m1:{n + 1}", positive=True) if n else ()
    ks = sp.symbols(f"k1:{n + 2}", positive=True)
    ls = sp.symbols(f"l1:{n + 2}", positive=True)
    G = (Ax + lg * sp.cos(th - psi), Ay + lg * sp.sin(th - psi))
    B = (Ax + lAB * sp.cos(th), Ay + lAB * sp.sin(th))

    def speed2(P):
        return sp.diff(P[0], t) ** 2 + sp.diff(P[1], t) ** 2

    T = mc / 2 * speed2(G) + Ic / 2 * sp.diff(th, t) ** 2 + mpin / 2 * speed2(B)
    T += sum(m / 2 * speed2((x, y)) for m, x, y in zip(ms, xs, ys))
    T = sp.trigsimp(sp.expand(T))
    pts = [(Ox, Oy)] + list(zip(xs, ys)) + [B]
    V = mc * g * G[1] + gw * (mpin * B[1] + sum(m * y for m, y in zip(ms, ys)))
    for k, l0, P, Q in zip(ks, ls, pts[:-1], pts[1:]):
        length = sp.sqrt((Q[0] - P[0]) ** 2 + (Q[1] - P[1]) ** 2)
        V += k / 2 * (length - l0) ** 2
    coords = [th] + [c for xy in zip(xs, ys) for c in xy]
    qs, qds, Mm, h = _lagrange(T, V, coords, t)
    params = [Ic, mc, lg, psi, Ax, Ay, lAB, Ox, Oy, g, gw, mpin, *ms, *ks, *ls]
    return _Equations(qs, qds, params, Mm, h)


# ----------------------------------------------------------------------------------------------
# mechanisms: equations + Newton-Euler reaction
# ----------------------------------------------------------------------------------------------
class _Mechanism:
    """q[0] is the shaft angle; M, h from the Lagrangian; reaction(q, qd) -> (R0, R1)."""

    def __init__(self, eqs, params):
        self.eqs = eqs
        self.p = [float(v) for v in params]
        self.nq = eqs.nq
        self._M = self._Minv = None
        if eqs.constant_mass:
            M = eqs.mass(np.zeros(self.nq), self.p)
            self._M, self._Minv = M, np.linalg.inv(M)

    def mass(self, q):
        if self._M is not None:
            return self._M, self._Minv
        M = self.eqs.mass(q, self.p)
        return M, np.linalg.inv(M)

    def forces(self, q, qd):
        return self.eqs.forces(q, qd, self.p)


class _PendulumMechanism(_Mechanism):
    def __init__(self, mass, inertia, com_distance, gravity):
        self.M_, self.L_, self.g_ = float(mass), float(com_distance), float(gravity)
        super().__init__(_pendulum_equations(), [inertia, mass, gravity, com_distance])

    def reaction(self, q, qd):
        """Paper eq. 6 in the pendulum's frame: (F_om, F_ot) = R0 + R1 theta''."""
        th, w = q[0], qd[0]
        M, L, g = self.M_, self.L_, self.g_
        return (M * g * math.cos(th) + M * L * w * w, M * g * math.sin(th)), (0.0, M * L)


class _CamMechanism(_Mechanism):
    def __init__(self, cam, spring, gravity):
        c = int(spring["count"])
        if c < 1:
            raise ValueError("independent reference: spring count must be >= 1")
        self.A = np.array(cam["pivot"], float)
        self.O = np.array(spring["anchor"], float)
        self.mc, self.Ic = float(cam["mass"]), float(cam["inertia_com"])
        self.lg, self.psi, self.lAB = float(cam["com_distance"]), float(cam["com_angle"]), float(cam["arm_length"])
        self.g = float(gravity)
        self.gw = self.g if spring.get("weight", False) else 0.0
        chain = spring.get("chain")
        if chain is None:
            n = 0
            masses, ks, ls = [], [c * float(spring["stiffness"])], [float(spring["free_length"])]
            self.mpin = 0.0
            pos = np.zeros((0, 2))
        else:
            masses = [c * float(m) for m in chain["masses"]]
            n = len(masses)
            ks = [c * float(k) for k in chain["stiffnesses"]]
            ls = [float(l) for l in chain["free_lengths"]]
            self.mpin = c * float(chain.get("pin_mass", 0.0))
            pos = np.array(chain["positions"], float).reshape(-1, 2) if n else np.zeros((0, 2))
            if len(ks) != n + 1 or len(ls) != n + 1 or pos.shape != (n, 2):
                raise ValueError("independent reference: a chain of n masses needs n+1 stiffnesses and free "
                                 "lengths and n x 2 positions")
        values = [self.mc, self.Ic, self.lAB, *masses, *ks, *ls]
        if not all(math.isfinite(v) for v in values) or min(values) <= 0.0 or self.mpin < 0.0 or self.lg < 0.0:
            raise ValueError("independent reference: masses, inertia, lengths and stiffnesses must be positive")
        self.n, self.masses, self.ks, self.ls = n, np.array(masses), np.array(ks), np.array(ls)
        self.initial_positions = pos
        params = [self.Ic, self.mc, self.lg, self.psi, *self.A, self.lAB, *self.O, self.g, self.gw, self.mpin,
                  *masses, *ks, *ls]
        super().__init__(_cam_equations(n), params)

    def pin(self, th):
        return self.A + self.lAB * np.array([math.cos(th), math.sin(th)])

    def spring_pull_on_pin(self, q):
        """Force (N) of the last axial spring on pin B (all springs together)."""
        B = self.pin(q[0])
        P = q[2 * self.n - 1:2 * self.n + 1] if self.n else self.O
        d = np.asarray(P, float) - B
        length = math.hypot(d[0], d[1])
        if not length > 0.0:
            raise SimulationError("independent reference: a spring segment collapsed to zero length")
        return self.ks[-1] * (length - self.ls[-1]) * d / length

    def reaction(self, q, qd):
        """Bearing force at A on the cam body (cam + pin mass), Newton-Euler:
        F_A = m_c a_G + m_pin a_B - F_spring_on_B - W_cam - W_pin, a linear in theta''."""
        th, w = q[0], qd[0]
        phi = th - self.psi
        eG, nG = np.array([math.cos(phi), math.sin(phi)]), np.array([-math.sin(phi), math.cos(phi)])
        eB, nB = np.array([math.cos(th), math.sin(th)]), np.array([-math.sin(th), math.cos(th)])
        F = self.spring_pull_on_pin(q)
        weight = np.array([0.0, -self.mc * self.g - self.mpin * self.gw])
        R0 = -self.mc * self.lg * w * w * eG - self.mpin * self.lAB * w * w * eB - F - weight
        R1 = self.mc * self.lg * nG + self.mpin * self.lAB * nB
        return R0, R1


# ----------------------------------------------------------------------------------------------
# hybrid (event-driven) integration
# ----------------------------------------------------------------------------------------------
class _Segment:
    __slots__ = ("t0", "t1", "mode", "s", "regime", "sol", "theta")

    def __init__(self, t0, mode, s=0, regime=0, sol=None, theta=None):
        self.t0, self.t1, self.mode, self.s, self.regime, self.sol, self.theta = t0, None, mode, s, regime, sol, theta


class _Hybrid:
    def __init__(self, mech, law, rtol, atol):
        self.mech, self.law, self.rtol, self.atol = mech, law, rtol, atol
        self.nq = mech.nq

    # -- accelerations ------------------------------------------------------------------------
    def slip(self, q, qd, s, regime):
        """(q'', Tf, Fn, Tc) in slip mode."""
        M, Minv = self.mech.mass(q)
        h = self.mech.forces(q, qd)
        a_free = -Minv @ h
        b = Minv[:, 0]
        k, v = self.law.split(regime, qd[0], s)
        R0, R1 = self.mech.reaction(q, qd)
        a = _coupled_acceleration(a_free[0], b[0], k, v, R0, R1)
        fn = math.hypot(R0[0] + R1[0] * a, R0[1] + R1[1] * a)
        tf = k * fn + v
        qdd = a_free - b * tf
        return qdd, tf, fn, a_free[0] / b[0]

    def stuck(self, q, qd):
        """(q'' with theta'' = 0, Tf holding the shaft, Fn0, Tc); qd[0] must be 0."""
        M, _ = self.mech.mass(q)
        h = self.mech.forces(q, qd)
        qdd = np.zeros(self.nq)
        if self.nq > 1:
            qdd[1:] = np.linalg.solve(M[1:, 1:], -h[1:])
        tc = -h[0] - M[0, 1:] @ qdd[1:]
        R0, _ = self.mech.reaction(q, qd)
        return qdd, tc, math.hypot(R0[0], R0[1]), tc

    # -- right-hand sides ---------------------------------------------------------------------
    def _check(self, t, y):
        if not np.all(np.isfinite(y)):
            raise SimulationError(f"independent reference: non-finite state at t = {t:.6g} s")

    def slip_rhs(self, s, regime):
        nq = self.nq

        def rhs(t, y):
            self._check(t, y)
            qdd = self.slip(y[:nq], y[nq:], s, regime)[0]
            return np.concatenate([y[nq:], qdd])

        return rhs

    def stuck_rhs(self, theta):
        nq = self.nq

        def rhs(t, z):
            self._check(t, z)
            q, qd = self.full(theta, z)
            qdd = self.stuck(q, qd)[0]
            return np.concatenate([z[nq - 1:], qdd[1:]])

        return rhs

    def full(self, theta, z):
        nq = self.nq
        q = np.concatenate([[theta], z[:nq - 1]])
        qd = np.concatenate([[0.0], z[nq - 1:]])
        return q, qd

    # -- driver -------------------------------------------------------------------------------
    def _start_at_rest(self, t, y, segments, events, kind):
        """Shaft at rest at time t: stuck or break away. Returns the new mode tuple."""
        nq = self.nq
        y = y.copy()
        y[nq] = 0.0
        _, tc, fn0, _ = self.stuck(y[:nq], y[nq:])
        if self.law.holds(tc, fn0):
            events.append({"t": t, "kind": "stick" if kind != "start" else "start_stuck", "theta": y[0]})
            return ("stuck", 0, 0), y
        s = 1 if tc > 0 else -1
        events.append({"t": t, "kind": kind, "theta": y[0], "direction": s})
        self._check_entry(t, y, s, 0, outward=True)
        return ("slip", s, 0), y

    def _check_entry(self, t, y, s, regime, outward):
        """Entering a slip regime at its boundary, the speed must move into it; if it points back
        out, both sides drive the speed onto the boundary (a sliding mode the law does not define,
        e.g. mu_k > mu_s): report it instead of chattering."""
        nq = self.nq
        rate = s * self.slip(y[:nq], y[nq:], s, regime)[0][0]  # d|w|/dt in the new regime
        if (rate < 0.0) if outward else (rate > 0.0):
            law = self.law
            raise SimulationError(
                f"independent reference: friction law has no consistent motion at t = {t:.6g} s, |w| = "
                f"{abs(y[nq]):.3g} rad/s ({law.kinds[regime]} branch drives the speed back; mu_s = {law.mu_s:g}, "
                f"mu_k = {law.mu_k:g})")

    def run(self, q0, qd0, t_end):
        nq, law = self.nq, self.law
        y = np.concatenate([np.asarray(q0, float), np.asarray(qd0, float)])
        self._check(0.0, y)
        t = 0.0
        segments, events = [], []
        if y[nq] == 0.0:
            mode, y = self._start_at_rest(t, y, segments, events, "start")
        else:
            s = 1 if y[nq] > 0 else -1
            mode = ("slip", s, law.regime_of(abs(y[nq])))
        opts = dict(method="DOP853", rtol=self.rtol, atol=self.atol, dense_output=True)
        while True:
            if len(segments) > MAX_SEGMENTS:
                raise SimulationError(f"independent reference: more than {MAX_SEGMENTS} stick/slip segments "
                                      f"before t = {t:.6g} s (Zeno behaviour)")
            if mode[0] == "stuck":
                seg = _Segment(t, "stuck", theta=y[0])
                segments.append(seg)
                if nq == 1 or t >= t_end:  # nothing else moves (or no time left): stuck to the end
                    seg.t1 = t_end
                    seg.sol = _ConstantSol(np.concatenate([y[1:nq], y[nq + 1:]]))
                    break
                theta = y[0]

                def breakaway(tt, z, theta=theta):
                    q, qd = self.full(theta, z)
                    _, tc, fn0, _ = self.stuck(q, qd)
                    return abs(tc) - law.mu_s * law.r * fn0

                breakaway.terminal, breakaway.direction = True, 1.0
                sol = solve_ivp(self.stuck_rhs(theta), (t, t_end), y[1:nq].tolist() + y[nq + 1:].tolist(),
                                events=[breakaway], **opts)
                if sol.status < 0:
                    raise SimulationError(f"independent reference: solver failed at t = {sol.t[-1]:.6g} s: {sol.message}")
                seg.sol, seg.t1 = sol.sol, sol.t[-1]
                if sol.status == 0:
                    break
                t = float(sol.t_events[0][0])
                seg.t1 = t
                q, qd = self.full(theta, sol.y_events[0][0])
                y = np.concatenate([q, qd])
                _, tc, _, _ = self.stuck(q, qd)
                s = 1 if tc > 0 else -1
                events.append({"t": t, "kind": "breakaway", "theta": theta, "direction": s})
                self._check_entry(t, y, s, 0, outward=True)
                mode = ("slip", s, 0)
                continue
            _, s, regime = mode
            seg = _Segment(t, "slip", s=s, regime=regime)
            segments.append(seg)
            if t >= t_end:
                seg.t1 = t_end
                seg.sol = _ConstantSol(y)
                break
            lo, hi = law.bounds[regime], law.bounds[regime + 1]

            def leave_low(tt, yy, s=s, lo=lo):
                return s * yy[nq] - lo

            leave_low.terminal, leave_low.direction = True, -1.0
            evs = [leave_low]
            if math.isfinite(hi):
                def leave_high(tt, yy, s=s, hi=hi):
                    return s * yy[nq] - hi

                leave_high.terminal, leave_high.direction = True, 1.0
                evs.append(leave_high)
            sol = solve_ivp(self.slip_rhs(s, regime), (t, t_end), y, events=evs, **opts)
            if sol.status < 0:
                raise SimulationError(f"independent reference: solver failed at t = {sol.t[-1]:.6g} s: {sol.message}")
            seg.sol, seg.t1 = sol.sol, sol.t[-1]
            if sol.status == 0:
                break
            which = 0 if len(sol.t_events[0]) else 1
            t = float(sol.t_events[which][0])
            y = np.array(sol.y_events[which][0], float)
            self._check(t, y)
            seg.t1 = t
            if which == 1:
                y[nq] = s * hi
                self._check_entry(t, y, s, regime + 1, outward=True)
                mode = ("slip", s, regime + 1)
            elif regime > 0:
                y[nq] = s * lo
                self._check_entry(t, y, s, regime - 1, outward=False)
                mode = ("slip", s, regime - 1)
            else:  # w reached zero: stick, or slip on in the direction of Tc
                mode, y = self._start_at_rest(t, y, segments, events, "reversal")
                if mode[0] == "slip" and mode[1] == s:
                    events[-1]["kind"] = "restart"
        segments[-1].t1 = t_end
        return segments, events

    # -- output -------------------------------------------------------------------------------
    def sample(self, segments, t_eval):
        nq = self.nq
        starts = np.array([seg.t0 for seg in segments])
        idx = np.clip(np.searchsorted(starts, t_eval, side="right") - 1, 0, len(segments) - 1)
        N = len(t_eval)
        Q, QD = np.empty((N, nq)), np.empty((N, nq))
        tf, fn, tc, acc = np.empty(N), np.empty(N), np.empty(N), np.empty(N)
        stuck = np.zeros(N, bool)
        for j in np.unique(idx):
            seg = segments[j]
            sel = np.nonzero(idx == j)[0]
            ts = np.clip(t_eval[sel], seg.t0, seg.t1)
            if seg.mode == "stuck":
                stuck[sel] = True
                Z = seg.sol(ts).T
                for i, z in zip(sel, Z):
                    q, qd = self.full(seg.theta, z)
                    Q[i], QD[i] = q, qd
                    qdd, tc_i, fn0, _ = self.stuck(q, qd)
                    tf[i], fn[i], tc[i], acc[i] = tc_i, fn0, tc_i, 0.0
            else:
                Y = seg.sol(ts).T
                for i, yy in zip(sel, Y):
                    q, qd = yy[:nq], yy[nq:]
                    Q[i], QD[i] = q, qd
                    qdd, tf[i], fn[i], tc[i] = self.slip(q, qd, seg.s, seg.regime)
                    acc[i] = qdd[0]
        out = {"t": np.asarray(t_eval, float), "theta": Q[:, 0].copy(), "omega": QD[:, 0].copy(),
               "friction_torque": tf, "stuck": stuck, "alpha": acc, "normal_force": fn, "applied_torque": tc}
        if not all(np.all(np.isfinite(v)) for v in (Q, QD, tf, fn)):
            raise SimulationError("independent reference: non-finite values in the sampled output")
        return out, Q, QD


class _ConstantSol:
    def __init__(self, y):
        self.y = np.asarray(y, float)

    def __call__(self, t):
        return np.repeat(self.y[:, None], np.size(t), axis=1)


def _times(t_eval):
    t_eval = np.asarray(t_eval, float).ravel()
    if t_eval.size == 0 or not np.all(np.isfinite(t_eval)) or t_eval[0] < 0.0 or np.any(np.diff(t_eval) < 0.0):
        raise ValueError("independent reference: t_eval must be a non-empty, finite, non-decreasing array of times >= 0")
    return t_eval


def _run(mech, law, q0, qd0, t_eval, rtol, atol):
    t_eval = _times(t_eval)
    hybrid = _Hybrid(mech, law, rtol, atol)
    try:
        segments, events = hybrid.run(q0, qd0, float(t_eval[-1]))
        out, Q, QD = hybrid.sample(segments, t_eval)
    except (ArithmeticError, np.linalg.LinAlgError) as exc:
        raise SimulationError(f"independent reference: {type(exc).__name__}: {exc}") from exc
    except ValueError as exc:  # brentq bracket failure (no sign change) from a non-finite state
        raise SimulationError(f"independent reference: {exc}") from exc
    out["events"] = events
    out["segments"] = [(seg.t0, seg.t1, seg.mode if seg.mode == "stuck" else f"slip{seg.s:+d}:{law.kinds[seg.regime]}")
                       for seg in segments]
    return out, Q, QD


# ----------------------------------------------------------------------------------------------
# public API
# ----------------------------------------------------------------------------------------------
def pendulum(mass, inertia, com_distance, gravity, radius, friction, theta0, omega0, t_eval, *,
             rtol=RTOL, atol=ATOL):
    """Pendulum test (paper eq. 1, 5, 6): I th'' + M g L sin th + Tf = 0.

    Parameters
    ----------
    mass : M (kg), the swinging mass.
    inertia : I (kg m^2) about the shaft axis.
    com_distance : L (m), shaft axis to centre of mass.
    gravity : g (m/s^2).
    radius : journal radius r (m).
    friction : dict with any of ``mu_s``, ``mu_k`` (-), ``stick_velocity`` w0 (rad/s),
        ``stribeck_velocity`` ws (rad/s), ``viscous`` Cv (N m s/rad) or ``zeta`` (damping ratio,
        Cv = 2 zeta sqrt(I M g L)); missing keys are 0, ``mu_s`` defaults to ``mu_k``.
    theta0, omega0 : initial angle from hanging straight down (rad) and angular velocity (rad/s).
    t_eval : output times (s), non-decreasing, >= 0; the solve starts at t = 0.
    rtol, atol : DOP853 tolerances.

    Returns
    -------
    dict with arrays over ``t`` (s): ``theta`` (rad), ``omega`` (rad/s), ``friction_torque`` Tf
    (N m, the torque in eq. 1, opposing motion), ``stuck`` (bool), ``alpha`` (rad/s^2),
    ``normal_force`` Fn (N), ``applied_torque`` Tc = -M g L sin th (N m); and ``events`` (list of
    dicts: t, kind in start_stuck/start/stick/reversal/restart/breakaway, theta) and ``segments``
    (t0, t1, mode).
    """
    M, I, L, g = float(mass), float(inertia), float(com_distance), float(gravity)
    if not all(math.isfinite(v) and v > 0.0 for v in (M, I, L, g)):
        raise ValueError("independent reference: pendulum mass, inertia, com_distance and gravity must be > 0")
    law = _FrictionLaw(friction, radius, zeta_to_viscous=lambda z: 2.0 * z * math.sqrt(I * M * g * L))
    mech = _PendulumMechanism(M, I, L, g)
    out, _, _ = _run(mech, law, [float(theta0)], [float(omega0)], t_eval, rtol, atol)
    return out


def cam_drop(cam, spring, gravity, radius, friction, t_eval, *, rtol=RTOL, atol=ATOL):
    """Cam drop (paper eq. 9-13, generalised to n spring masses and a pin mass).

    Parameters
    ----------
    cam : dict ``mass`` m_c (kg), ``inertia_com`` I_c (kg m^2, about the centre of mass),
        ``com_distance`` l_g (m), ``com_angle`` psi (rad; centre of mass at A + l_g (cos(th - psi),
        sin(th - psi))), ``pivot`` A (m, (x, y)), ``arm_length`` l_AB (m; pin B = A + l_AB (cos th,
        sin th)), ``initial_angle`` (rad, A->B from +x), ``initial_velocity`` (rad/s, default 0).
    spring : dict ``count`` (identical springs acting in the plane, lumped as one with count times
        stiffnesses and masses), ``anchor`` O (m), ``stiffness`` k0 (N/m) and ``free_length`` (m) of
        each spring for the massless model, ``chain``: None (massless) or a dict ``masses`` (kg, n
        per spring), ``stiffnesses`` (N/m, n+1 per spring, O side first), ``free_lengths`` (m, n+1),
        ``positions`` (n x 2 initial positions, m; masses start at rest), ``pin_mass`` (kg per
        spring, rides on B); ``weight`` (bool, default False): spring and pin masses carry weight.
    gravity : g (m/s^2), along -y.
    radius : journal radius r (m).
    friction : as for :func:`pendulum` (``zeta`` not accepted).
    t_eval : output times (s), non-decreasing, >= 0; the solve starts at t = 0.

    Returns
    -------
    dict as for :func:`pendulum` (``applied_torque`` Tc: spring + gravity torque about A, N m;
    ``normal_force``: bearing force at A, N), plus ``mass_positions`` and ``mass_velocities``
    (len(t) x n x 2; m, m/s).
    """
    try:
        mech = _CamMechanism(cam, spring, gravity)
    except KeyError as exc:
        raise ValueError(f"independent reference: cam or spring dict lacks the key {exc}") from None
    law = _FrictionLaw(friction, radius)
    n = mech.n
    q0 = [float(cam["initial_angle"])] + mech.initial_positions.ravel().tolist()
    qd0 = [float(cam.get("initial_velocity", 0.0))] + [0.0] * (2 * n)
    out, Q, QD = _run(mech, law, q0, qd0, t_eval, rtol, atol)
    out["mass_positions"] = Q[:, 1:].reshape(len(Q), n, 2)
    out["mass_velocities"] = QD[:, 1:].reshape(len(Q), n, 2)
    return out

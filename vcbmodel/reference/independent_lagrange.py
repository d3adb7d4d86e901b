"""The independent reference's equations of motion: Lagrange's equations derived with sympy, and
the mechanisms (pendulum, cam with a spring chain) with their Newton-Euler shaft reactions.

Holds :func:`lagrange` (``M(q) q'' + h(q, q') = Q`` from the kinetic and potential energies),
the lambdified :class:`Equations` of the pendulum (paper eq. 1) and of the cam drop (paper eq.
9-13, generalised to n spring point masses and a pin mass), and the mechanisms that evaluate
them and the shaft reaction ``F = R0 + R1 theta''`` (pendulum: paper eq. 5-6; cam: sum of
forces on cam + pin mass = m_c a_G + m_pin a_B). Shares no code with the model; it shares the
planar layout (cam pivot A, pin B = A + l_AB (cos th, sin th), spring anchor O, gravity along -y)
and the lumped chain's numbers (``count`` identical springs lumped as one with ``count`` times
the masses and stiffnesses).

Units: SI. Lengths in m, masses in kg, inertias in kg m^2, angles in rad (counter-clockwise),
forces in N, stiffnesses in N/m, gravity in m/s^2.
"""
from __future__ import annotations

import functools
import math
from typing import Any, Mapping, Sequence

import numpy as np
import sympy as sp

from vcbmodel.errors import SimulationError

# ----------------------------------------------------------------------------------------------
# equations of motion (Lagrange, sympy)
# ----------------------------------------------------------------------------------------------
def lagrange(T: sp.Expr, V: sp.Expr, coords: list, t: sp.Symbol) -> tuple:
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


class Equations:
    """Lambdified M(q, p) and h(q, q', p) with the symbol lists they take."""

    def __init__(self, qs, qds, params, M, h):
        self.nq = len(qs)
        self.constant_mass = not (M.free_symbols & (set(qs) | set(qds)))
        self._M = sp.lambdify([qs, params], M, modules="numpy")
        self._h = sp.lambdify([qs, qds, params], list(h), modules="numpy", cse=True)

    def mass(self, q: Sequence[float], p: Sequence[float]) -> np.ndarray:
        return np.array(self._M(q, p), dtype=float)

    def forces(self, q: Sequence[float], qd: Sequence[float], p: Sequence[float]) -> np.ndarray:
        return np.array(self._h(q, qd, p), dtype=float)


@functools.lru_cache(maxsize=None)
def pendulum_equations() -> Equations:
    t = sp.Symbol("t")
    th = sp.Function("theta")(t)
    I, M, g, L = sp.symbols("I M g L", positive=True)
    T = I * sp.diff(th, t) ** 2 / 2
    V = -M * g * L * sp.cos(th)  # centre of mass at L (sin th, -cos th)
    qs, qds, Mm, h = lagrange(T, V, [th], t)
    return Equations(qs, qds, [I, M, g, L], Mm, h)


@functools.lru_cache(maxsize=None)
def cam_equations(n: int) -> Equations:
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
    qs, qds, Mm, h = lagrange(T, V, coords, t)
    params = [Ic, mc, lg, psi, Ax, Ay, lAB, Ox, Oy, g, gw, mpin, *ms, *ks, *ls]
    return Equations(qs, qds, params, Mm, h)


# ----------------------------------------------------------------------------------------------
# mechanisms: equations + Newton-Euler reaction
# ----------------------------------------------------------------------------------------------
class Mechanism:
    """q[0] is the shaft angle; M, h from the Lagrangian; reaction(q, qd) -> (R0, R1)."""

    def __init__(self, eqs, params):
        self.eqs = eqs
        self.p = [float(v) for v in params]
        self.nq = eqs.nq
        self._M = self._Minv = None
        if eqs.constant_mass:
            M = eqs.mass(np.zeros(self.nq), self.p)
            self._M, self._Minv = M, np.linalg.inv(M)

    def mass(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        if self._M is not None:
            return self._M, self._Minv
        M = self.eqs.mass(q, self.p)
        return M, np.linalg.inv(M)

    def forces(self, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        return self.eqs.forces(q, qd, self.p)


class PendulumMechanism(Mechanism):
    def __init__(self, mass: float, inertia: float, com_distance: float, gravity: float):
        self.M_, self.L_, self.g_ = float(mass), float(com_distance), float(gravity)
        super().__init__(pendulum_equations(), [inertia, mass, gravity, com_distance])

    def reaction(self, q: np.ndarray, qd: np.ndarray) -> tuple[tuple[float, float], tuple[float, float]]:
        """Paper eq. 6 in the pendulum's frame: (F_om, F_ot) = R0 + R1 theta''."""
        th, w = q[0], qd[0]
        M, L, g = self.M_, self.L_, self.g_
        return (M * g * math.cos(th) + M * L * w * w, M * g * math.sin(th)), (0.0, M * L)


class CamMechanism(Mechanism):
    def __init__(self, cam: Mapping[str, Any], spring: Mapping[str, Any], gravity: float):
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
        super().__init__(cam_equations(n), params)

    def pin(self, th: float) -> np.ndarray:
        return self.A + self.lAB * np.array([math.cos(th), math.sin(th)])

    def spring_pull_on_pin(self, q: np.ndarray) -> np.ndarray:
        """Force (N) of the last axial spring on pin B (all springs together)."""
        B = self.pin(q[0])
        P = q[2 * self.n - 1:2 * self.n + 1] if self.n else self.O
        d = np.asarray(P, float) - B
        length = math.hypot(d[0], d[1])
        if not length > 0.0:
            raise SimulationError("independent reference: a spring segment collapsed to zero length")
        return self.ks[-1] * (length - self.ls[-1]) * d / length

    def reaction(self, q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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

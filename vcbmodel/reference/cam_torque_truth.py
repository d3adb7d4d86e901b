"""A cam drop with an extra torque no registered effect describes, for synthetic records that test
discovery on the cam (:mod:`vcbmodel.analysis.discovery`): an independent solve, like the others in
this folder, sharing no code with the model.

The cam (mass m, inertia I_G about its centre of mass G at distance l_g from the pivot A, at the
angle theta - psi) turns about A, pulled at its pin B = A + l_AB (cos theta, sin theta) by n
massless tension springs anchored at O (Hooke's law along B -> O), under gravity along -y. The
shaft friction is Coulomb's, mu_k r |F_A| with F_A the bearing's force on the cam (Newton's second
law for the cam: F_A = m a_G - F_spring - m g), plus a viscous Cv w; an optional point mass
("eccentric") rides on the cam and adds its inertia, weight and share of F_A. Written in complex
numbers (a point is x + i y) from the mechanics, not from the model's laws; what it shares with the
model is the reading of the rig (the layout, the massless spring, Coulomb friction on the bearing
force), the paper's section-3 set-up. The shaft sticks for good when it stops where Coulomb
friction holds the applied torque.

Units: SI; angles in rad, speeds in rad/s, torques in N m, forces in N.
"""
from __future__ import annotations

import cmath
import math
from collections.abc import Callable, Mapping

import numpy as np
from scipy.integrate import solve_ivp

#: Fixed-point sweeps of the friction / acceleration coupling (|F_A| depends on theta''); each
#: sweep shrinks the error by mu r m l_g / I, below 0.01 for a cam.
COUPLING_SWEEPS = 8


class _Cam:
    """The rigid cam with its springs and an optional point mass, in complex coordinates."""

    def __init__(self, cam: Mapping, spring: Mapping, gravity: float, eccentric: Mapping | None):
        self.A = complex(*cam["pivot"])
        self.O = complex(*spring["anchor"])
        self.l_ab, self.g = float(cam["arm_length"]), float(gravity)
        self.k = spring["count"] * float(spring["stiffness"])
        self.L0 = float(spring["free_length"])
        # bodies riding on the cam: (mass kg, distance from A m, angle behind A->B rad)
        self.bodies = [(float(cam["mass"]), float(cam["com_distance"]), float(cam["com_angle"]))]
        self.inertia = float(cam["inertia_com"]) + cam["mass"] * cam["com_distance"] ** 2
        if eccentric:
            self.bodies.append((float(eccentric["mass"]), float(eccentric["distance"]), float(eccentric["angle"])))
            self.inertia += eccentric["mass"] * eccentric["distance"] ** 2

    def loads(self, th: float, w: float) -> tuple[float, complex, complex]:
        """(applied torque about A N m, bearing force on the cam at zero theta'' N, its change per unit theta'')."""
        B = self.A + self.l_ab * cmath.exp(1j * th)
        d = B - self.O
        F = -self.k * (abs(d) - self.L0) * d / abs(d)  # the springs' pull on B
        torque = ((B - self.A).conjugate() * F).imag  # r x F
        force0, force1 = -F, 0j
        for m, dist, ang in self.bodies:
            r = dist * cmath.exp(1j * (th - ang))
            torque += (r.conjugate() * complex(0.0, -m * self.g)).imag
            force0 += m * (-w * w * r) - complex(0.0, -m * self.g)  # F_A = m a - (the other forces)
            force1 += m * 1j * r
        return torque, force0, force1


def cam_drop_with_torque(cam: Mapping, spring: Mapping, gravity: float, radius: float, friction: Mapping[str, float],
                         extra: Callable[[float, float, float], float], t_eval: np.ndarray,
                         eccentric: Mapping | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(cam angle rad, speed rad/s) at ``t_eval`` (s) of I_A th'' = T_springs + T_weights + T_x - T_f,
    released at ``cam["initial_angle"]`` with ``cam["initial_velocity"]``. ``cam``: mass (kg),
    inertia_com (kg m^2), com_distance l_g (m), com_angle psi (rad), pivot A (m), arm_length l_AB
    (m); ``spring``: count, stiffness (N/m each), free_length (m), anchor O (m); ``friction``:
    mu_k (-), viscous Cv (N m s/rad, optional); ``extra(t s, th rad, w rad/s)``: T_x (N m);
    ``eccentric``: an optional point mass {mass kg, distance m from A, angle rad behind A -> B}."""
    body = _Cam(cam, spring, gravity, eccentric)
    mu_r, cv = friction["mu_k"] * radius, friction.get("viscous", 0.0)

    def rhs(s):
        def f(t, y):
            th, w = y
            torque, f0, f1 = body.loads(th, w)
            drive = torque + extra(t, th, w) - cv * w
            acc = drive / body.inertia
            for _ in range(COUPLING_SWEEPS):
                acc = (drive - s * mu_r * abs(f0 + f1 * acc)) / body.inertia
            return [w, acc]
        return f

    def stops(t, y):
        return y[1]
    stops.terminal = True

    t_eval = np.asarray(t_eval, float)
    theta, omega = np.full(t_eval.size, np.nan), np.zeros(t_eval.size)
    t0, y0 = 0.0, [float(cam["initial_angle"]), float(cam.get("initial_velocity", 0.0))]
    while True:
        if abs(y0[1]) < 1e-12:
            torque, f0, _ = body.loads(y0[0], 0.0)
            torque += extra(t0, y0[0], 0.0)
            if abs(torque) <= mu_r * abs(f0):
                theta[np.isnan(theta) & (t_eval >= t0 - 1e-12)] = y0[0]
                return theta, omega
            s = math.copysign(1.0, torque)
        else:
            s = math.copysign(1.0, y0[1])
        stops.direction = -s
        sol = solve_ivp(rhs(s), (t0, t_eval[-1] + 1e-9), y0, method="DOP853", rtol=1e-11, atol=1e-12,
                        events=stops, dense_output=True)
        t1 = sol.t[-1]
        sel = (t_eval >= t0 - 1e-12) & (t_eval <= t1 + 1e-12)
        theta[sel], omega[sel] = sol.sol(t_eval[sel])
        if t1 >= t_eval[-1] or not sol.t_events[0].size:
            return theta, omega
        t0, y0 = t1, [float(sol.y[0, -1]), 0.0]

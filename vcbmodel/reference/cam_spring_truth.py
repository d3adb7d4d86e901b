"""A cam drop whose closing springs are a damped continuum, for synthetic records that test whether
damping inside a spring is read as what it is (the ``spring_damping`` effect), not as shaft friction:
an independent solve, like the others in this folder, sharing no code with the model.

The cam (mass m_c, inertia I_G about its centre of mass G at l_g from the pivot A, at the angle
theta - psi) turns about A. Its pin B = A + l_AB e^{i theta} is pulled by ``count`` tension springs
anchored at O, taken together as one continuum of stiffness count k0, mass count m0 and free length
L0, cut into S equal segments: S - 1 point masses count m0 / S inside, half a segment's mass at each
end (the anchor's stays put, the pin's rides on B), each segment a Kelvin-Voigt element of stiffness
S count k0, free length L0 / S and damper beta S count k0, beta = 2 zeta / (pi sqrt(k0 / m0)) (zeta:
the continuum's first fixed-fixed mode's damping ratio; the material's damping is proportional to
its stiffness). Masses carry no weight (the paper's eq. 9-10); the cam does. Shaft friction: Coulomb's
mu_k r |F_A| with F_A the bearing's force on the cam and the pin's mass (Newton's second law for
them), and a viscous Cv w. Written in complex numbers (a point is x + i y) from the mechanics.

What it shares with the model: the reading of the rig (layout, springs side by side as one), the
Kelvin-Voigt law and its zeta (the ``spring_damping`` effect's definition), Coulomb friction on the
bearing force. Not the chain: 16 uniform segments here against the model's few masses of the
``exact`` convention. The drop must turn one way (a reversal is refused). Units: SI.
"""
from __future__ import annotations

import cmath
import math
from collections.abc import Mapping

import numpy as np
from scipy.integrate import solve_ivp

#: Segments of the continuum: its first three fixed-fixed modes within 0.5 % (a uniform chain of S
#: segments has w_n = 2 S sqrt(k0/m0) sin(n pi / 2S)).
SEGMENTS = 16
#: Fixed-point sweeps of the friction / acceleration coupling (|F_A| depends on theta'').
COUPLING_SWEEPS = 8


class _Drop:
    """The cam and the damped chain in complex coordinates (module docstring)."""

    def __init__(self, cam: Mapping, spring: Mapping, gravity: float, damping_ratio: float, segments: int):
        self.A, self.O = complex(*cam["pivot"]), complex(*spring["anchor"])
        self.l_ab, self.g = float(cam["arm_length"]), float(gravity)
        self.m_c, self.l_g, self.psi = float(cam["mass"]), float(cam["com_distance"]), float(cam["com_angle"])
        k0, m0, n = float(spring["stiffness"]), float(spring["mass"]), float(spring["count"])
        self.S = segments
        self.k = segments * n * k0  # each segment (N/m)
        self.c = 2.0 * damping_ratio / (math.pi * math.sqrt(k0 / m0)) * self.k  # its damper (N s/m)
        self.L0 = float(spring["free_length"]) / segments
        self.m = n * m0 / segments  # an interior mass (kg)
        self.m_pin = self.m / 2.0
        self.inertia = float(cam["inertia_com"]) + self.m_c * self.l_g**2 + self.m_pin * self.l_ab**2

    def tension(self, p0: complex, p1: complex, v0: complex, v1: complex) -> complex:
        """Force (N) of the segment p0 -> p1 on p1 (towards p0): k (L - L0) + c dL/dt along it."""
        d = p1 - p0
        length = abs(d)
        rate = (d.conjugate() * (v1 - v0)).real / length
        return -(self.k * (length - self.L0) + self.c * rate) * d / length

    def rhs(self, s: float, mu_r: float, cv: float):
        def f(t, y):
            th, w = y[0], y[1]
            n = self.S - 1
            z = y[2:2 + n] + 1j * y[2 + n:2 + 2 * n]
            v = y[2 + 2 * n:2 + 3 * n] + 1j * y[2 + 3 * n:2 + 4 * n]
            rb = self.l_ab * cmath.exp(1j * th)
            points = [self.O, *z, self.A + rb]
            speeds = [0j, *v, 1j * w * rb]
            pulls = [self.tension(points[i], points[i + 1], speeds[i], speeds[i + 1]) for i in range(self.S)]
            acc_chain = [(pulls[i] - pulls[i + 1]) / self.m for i in range(n)]
            rg = self.l_g * cmath.exp(1j * (th - self.psi))
            torque = (rb.conjugate() * pulls[-1]).imag + (rg.conjugate() * complex(0.0, -self.m_c * self.g)).imag
            moment = self.m_c * rg + self.m_pin * rb
            force0 = -w * w * moment - pulls[-1] + 1j * self.m_c * self.g  # F_A = m a - (the other forces)
            force1 = 1j * moment
            drive = torque - cv * w
            alpha = drive / self.inertia
            for _ in range(COUPLING_SWEEPS):
                alpha = (drive - s * mu_r * abs(force0 + force1 * alpha)) / self.inertia
            a = np.array(acc_chain, complex)
            return np.concatenate([[w, alpha], v.real, v.imag, a.real, a.imag])
        return f

    def start(self, theta0: float, omega0: float) -> np.ndarray:
        """The released state: the chain at rest, its masses evenly along O -> B (equal segments)."""
        b = self.A + self.l_ab * cmath.exp(1j * theta0)
        z = np.array([self.O + (b - self.O) * i / self.S for i in range(1, self.S)])
        n = self.S - 1
        return np.concatenate([[theta0, omega0], z.real, z.imag, np.zeros(2 * n)])


def cam_drop_with_damped_spring(cam: Mapping, spring: Mapping, gravity: float, radius: float,
                                friction: Mapping[str, float], damping_ratio: float, t_eval: np.ndarray,
                                segments: int = SEGMENTS) -> tuple[np.ndarray, np.ndarray]:
    """(cam angle rad, speed rad/s) at ``t_eval`` (s) of the drop of the module docstring, released at
    ``cam["initial_angle"]``. ``cam``: mass (kg), inertia_com (kg m^2), com_distance (m), com_angle
    (rad), pivot (m), arm_length (m); ``spring``: count, stiffness (N/m each), mass (kg each),
    free_length (m), anchor (m); ``friction``: mu_k (-), viscous (N m s/rad, optional);
    ``damping_ratio``: zeta (-); ``radius``: the journal's r (m)."""
    drop = _Drop(cam, spring, gravity, damping_ratio, segments)
    y0 = drop.start(float(cam["initial_angle"]), float(cam.get("initial_velocity", 0.0)))
    mu_r, cv = friction["mu_k"] * radius, friction.get("viscous", 0.0)
    probe = drop.rhs(1.0, 0.0, 0.0)(0.0, y0)[1]  # the springs' push at release sets the direction
    s = math.copysign(1.0, probe)

    def reverses(t, y):
        return y[1] if t > 0 else s
    reverses.terminal = True
    t_eval = np.asarray(t_eval, float)
    sol = solve_ivp(drop.rhs(s, mu_r, cv), (0.0, t_eval[-1]), y0, method="DOP853", rtol=1e-10, atol=1e-12,
                    t_eval=t_eval, events=reverses)
    if sol.status != 0 or sol.t.size != t_eval.size:
        raise ValueError("the damped-spring cam drop stopped or reversed before the record's end: this truth "
                         "covers one-way drops only")
    return sol.y[0], sol.y[1]

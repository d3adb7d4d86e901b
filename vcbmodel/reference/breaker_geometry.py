"""The independent breaker reference's geometry: the cam profile, the follower and the rest geometry.

Holds :class:`Profile` (the pitch radius rho(u) = r_b + r_r + lift s on the cam's polynomial
rise and return) and :class:`Geometry` (cam pivot A and arm l_AB, follower pivot, roller and
output arms, the rest angle with the roller on the base circle, and the kinematics: roller
centre, output point F, pin B, points of the pitch curve). Written again from the rig's numbers
for :mod:`.breaker`; it shares with the model the cam profile's definition (the 4-5-6-7
polynomial rise and return, spec "Cam profile") and the planar layout read from the loaded rig,
no code.

Units: SI. Lengths in m, angles in rad (counter-clockwise from +x), u the cam-fixed profile angle.
"""
from __future__ import annotations

import math
from typing import Any

from ..errors import SimulationError

TWO_PI = 2.0 * math.pi


class Profile:
    """Pitch radius rho(u) (m) with its first and second derivatives in u (m/rad, m/rad^2)."""

    def __init__(self, profile: Any, roller_radius: float):
        self.base = profile.base_radius + roller_radius
        self.lift = profile.lift
        self.r0, self.r1 = profile.rise_start, profile.rise_end
        self.d0, self.d1 = profile.return_start, profile.return_end

    @staticmethod
    def _poly(x):
        """The 4-5-6-7 polynomial s(x) = 35x^4 - 84x^5 + 70x^6 - 20x^7 with s' and s'' (x in [0, 1])."""
        if x <= 0.0:
            return 0.0, 0.0, 0.0
        if x >= 1.0:
            return 1.0, 0.0, 0.0
        s = 35 * x**4 - 84 * x**5 + 70 * x**6 - 20 * x**7
        ds = 140 * x**3 - 420 * x**4 + 420 * x**5 - 140 * x**6
        dds = 420 * x**2 - 1680 * x**3 + 2100 * x**4 - 840 * x**5
        return s, ds, dds

    def __call__(self, u: float) -> tuple[float, float, float]:
        u = self.r0 + math.fmod(u - self.r0, TWO_PI)
        if u < self.r0:
            u += TWO_PI
        if u <= self.r1:
            w = self.r1 - self.r0
            s, ds, dds = self._poly((u - self.r0) / w)
            return self.base + self.lift * s, self.lift * ds / w, self.lift * dds / (w * w)
        if u < self.d0:
            return self.base + self.lift, 0.0, 0.0
        w = self.d1 - self.d0
        s, ds, dds = self._poly((u - self.d0) / w)
        return self.base + self.lift * (1.0 - s), -self.lift * ds / w, -self.lift * dds / (w * w)


class Geometry:
    """The mechanism's plane geometry from a loaded ``vcb_closing`` rig, at rest and in motion.

    Attributes: ``A`` cam pivot, ``lab`` arm A->B (m); ``P`` follower pivot, ``ar`` roller arm,
    ``ao`` output arm (m), ``alpha_o`` output angle (rad); ``profile``; ``phi_geo`` follower angle
    with the roller on the base circle, ``beta_rest`` the roller's polar angle from A there (rad);
    ``F0`` the output point at rest (m).
    """

    def __init__(self, rig: Any):
        cam, b = rig.cam, rig.breaker
        self.A = (float(cam.pivot[0]), float(cam.pivot[1]))
        self.lab = cam.arm_length
        f = b.follower
        self.P = (float(f.pivot[0]), float(f.pivot[1]))
        self.ar, self.ao, self.alpha_o = f.roller_arm, f.output_arm, f.output_angle
        self.profile = Profile(b.profile, b.roller_radius)
        self.phi_geo = self._base_circle_angle(b.profile.base_radius + b.roller_radius, f.rest_angle)
        C = self.roller_centre(self.phi_geo)
        self.beta_rest = math.atan2(C[1] - self.A[1], C[0] - self.A[0])
        self.F0 = self.output_point(self.phi_geo)

    def _base_circle_angle(self, rho0: float, rest_angle: float) -> float:
        """Follower angle (rad) with the roller centre at distance rho0 (m) from A: of the two, the
        one nearer the rig's rest angle."""
        dx, dy = self.A[0] - self.P[0], self.A[1] - self.P[1]
        d = math.hypot(dx, dy)
        cos_a = (self.ar**2 + d * d - rho0**2) / (2 * self.ar * d)
        if abs(cos_a) > 1:
            raise SimulationError("independent breaker reference: the roller cannot reach the base circle")
        base, a = math.atan2(dy, dx), math.acos(cos_a)
        return min((base + a, base - a), key=lambda x: abs(math.remainder(x - rest_angle, TWO_PI)))

    def roller_centre(self, phi: float) -> tuple[float, float]:
        return self.P[0] + self.ar * math.cos(phi), self.P[1] + self.ar * math.sin(phi)

    def output_point(self, phi: float) -> tuple[float, float]:
        a = phi + self.alpha_o
        return self.P[0] + self.ao * math.cos(a), self.P[1] + self.ao * math.sin(a)

    def pin(self, theta: float) -> tuple[float, float]:
        return self.A[0] + self.lab * math.cos(theta), self.A[1] + self.lab * math.sin(theta)

    def pitch_point(self, beta: float, theta: float):
        """Pitch curve at polar angle beta: (P, dP/dbeta, d2P/dbeta2, rho, drho/dbeta)."""
        rho, d1, d2 = self.profile(theta - (beta - self.beta_rest))
        rb, rbb = -d1, d2  # u = theta - beta + beta_rest
        c, s = math.cos(beta), math.sin(beta)
        P = (self.A[0] + rho * c, self.A[1] + rho * s)
        dP = (rb * c - rho * s, rb * s + rho * c)
        ddP = (rbb * c - 2 * rb * s - rho * c, rbb * s + 2 * rb * c - rho * s)
        return P, dP, ddP, rho, rb

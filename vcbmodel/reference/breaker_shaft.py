"""The independent breaker reference's main shaft: the elastic segments between the pole levers.

Holds :class:`Shaft`, read from the rig's ``breaker.main_shaft`` section (None: the rigid main
shaft, every push rod on the follower's output point, and no :class:`Shaft` at all). Pole levers
1..n sit along the shaft in pole order, ``pole_pitch`` apart; the drive pole's lever is rigid with
the follower (angle phi), every other lever j has its own angle psi_j and inertia
``lever_inertia``; the follower keeps ``follower.inertia - (n - 1) lever_inertia``, so that the
whole assembly's inertia is the rigid shaft's. Each segment between lever j and lever j + 1
(angles a_j, a_{j+1}) is a linear torsion spring and damper,
T = k (a_j - a_{j+1}) + c (a_j' - a_{j+1}'), acting +T on lever j + 1 and -T on lever j, with
k = G pi (d^4 - d_i^4) / 32 / pole_pitch (a hollow circular shaft, d_i the bore; Saint-Venant
torsion without warping) and c the rig's ``damping`` per segment.

Written again from the interface's text (docs/rig-format.md, ``breaker.main_shaft``); shares no
code with the model (it imports nothing from ``vcbmodel.laws``). Shared with the model: this
reading of the section (linear segments k = G J / pitch with J of the hollow circle, the damping
per segment, the drive lever rigid with the follower, the inertia split) and nothing else.

Units: SI. Angles in rad, angular speeds in rad/s, torques in N m, stiffness in N m/rad,
damping in N m s/rad, inertias in kg m^2, lengths in m, the shear modulus in Pa.
"""
from __future__ import annotations

import math
from typing import Any, Callable, Sequence

from ..errors import SimulationError

#: The rest's fixed point stops when no lever angle moves by more than this (rad): above the
#: round-off of a rod's torque (its 2e7 N/m spring on an ulp of its 0.25 m length: about 1e-10 N m,
#: 1e-15 rad on a segment), far below the rest's twist (about 5e-4 rad on the reference breaker).
REST_TOLERANCE = 1e-12
#: ... or fails after this many sweeps (each contracts by the loads' change with the twist over k).
REST_SWEEPS = 100


class Shaft:
    """The elastic main shaft of a breaker with ``count`` poles (see the module docstring).

    Attributes: ``k`` (N m/rad) and ``c`` (N m s/rad) per segment, ``lever_inertia`` and
    ``follower_inertia`` (kg m^2), ``drive`` (0-based index of the drive pole), ``free`` (0-based
    indices of the poles with their own lever, in pole order), ``count``.
    """

    def __init__(self, section: Any, count: int, follower_inertia: float):
        drive = int(section.drive_pole)
        if drive != section.drive_pole or not 1 <= drive <= count:
            raise ValueError(f"breaker.main_shaft.drive_pole must be a pole 1..{count}, got {section.drive_pole}")
        d, bore = float(section.diameter), float(section.bore)
        if not (d > 0.0 and 0.0 <= bore < d and section.shear_modulus > 0.0 and section.pole_pitch > 0.0):
            raise ValueError("breaker.main_shaft: diameter, bore, shear_modulus or pole_pitch out of range")
        if not (section.lever_inertia > 0.0 and section.damping >= 0.0):
            raise ValueError("breaker.main_shaft: lever_inertia must be > 0 and damping >= 0")
        self.count, self.drive = count, drive - 1
        self.free = [i for i in range(count) if i != self.drive]
        polar = math.pi * (d**4 - bore**4) / 32.0  # m^4
        self.k = float(section.shear_modulus) * polar / float(section.pole_pitch)
        self.c = float(section.damping)
        self.lever_inertia = float(section.lever_inertia)
        self.follower_inertia = follower_inertia - (count - 1) * self.lever_inertia
        if self.follower_inertia <= 0.0:
            raise ValueError("breaker.main_shaft.lever_inertia: (poles - 1) levers leave the follower no inertia "
                             f"of follower.inertia {follower_inertia} kg m^2")

    def period(self) -> float:
        """A bound (s) from below on the period of the levers' fastest twisting mode, 2 pi over
        2 sqrt(k / I_min) (a segment's stiffness can at most double on a lever with two)."""
        smallest = min(self.lever_inertia, self.follower_inertia)
        return 2.0 * math.pi / (2.0 * math.sqrt(self.k / smallest))

    @classmethod
    def of(cls, breaker: Any, count: int, follower_inertia: float) -> "Shaft | None":
        """The rig's shaft, None when the breaker has no ``main_shaft`` section (rigid)."""
        section = getattr(breaker, "main_shaft", None)
        return None if section is None else cls(section, count, follower_inertia)

    def angles(self, phi: float, levers: Sequence[float]) -> list[float]:
        """Every pole's lever angle (rad): phi at the drive pole, ``levers`` (the free ones in pole
        order) elsewhere; the same for speeds."""
        out = [phi] * self.count
        for i, value in zip(self.free, levers):
            out[i] = value
        return out

    def torques(self, a: Sequence[float], w: Sequence[float]) -> list[float]:
        """The segments' torque on each lever (N m) at lever angles a (rad) and speeds w (rad/s)."""
        out = [0.0] * self.count
        for j in range(self.count - 1):
            t = self.k * (a[j] - a[j + 1]) + self.c * (w[j] - w[j + 1])
            out[j] -= t
            out[j + 1] += t
        return out

    def rest_angles(self, phi: float, load: Callable[[float], float]) -> list[float]:
        """Every lever's angle (rad) at rest with the follower at phi: each free lever in balance
        between its load ``load(a)`` (N m, the push rod's torque at lever angle a) and the
        segments. Statically a segment carries the loads of every lever beyond it (seen from the
        drive), so a_j = a_{j-1} + (sum of loads at j and beyond) / k towards the far end, and
        likewise towards pole 1; solved by fixed-point sweeps (the loads change little with the
        twist)."""
        a, d, n = [phi] * self.count, self.drive, self.count
        for _ in range(REST_SWEEPS):
            t = [load(x) for x in a]
            new = [phi] * n
            for j in range(d + 1, n):
                new[j] = new[j - 1] + sum(t[j:]) / self.k
            for j in range(d - 1, -1, -1):
                new[j] = new[j + 1] + sum(t[:j + 1]) / self.k
            moved = max(abs(x - y) for x, y in zip(new, a))
            a = new
            if moved <= REST_TOLERANCE:
                return a
        raise SimulationError("independent breaker reference: the levers' rest did not converge "
                         f"(last sweep moved {moved:.3g} rad)")

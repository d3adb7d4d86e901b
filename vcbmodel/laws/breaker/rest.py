"""The breaker at rest before the release, held by the closing latch: the follower's angle, the
poles' travels and the free pole levers' angles in torque balance, and the latch's holding torque.
:class:`AtRest` is the part of :class:`~.forces.BreakerLaws` that finds it (from the forces'
own torques, so the rest is the model's)."""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from ...errors import SimulationError
from ..cam_follower import output_point
from ..mechanics import cam_pin, cam_weight_torque


@dataclass
class InitialState:
    """Static rest held by the latch: follower angle (rad), pole travels (m), the latch's
    holding torque on the cam (N m) and, with a main shaft (``breaker.main_shaft``), the free pole
    levers' angles (rad, in pole order without the drive pole's; empty for a rigid shaft)."""

    follower_angle: float
    pole_travel: list
    holding_torque: float
    lever_angles: list = field(default_factory=list)


class AtRest:
    """The rest state of :class:`~.forces.BreakerLaws`, a part of it: it reads the laws' ``b``,
    ``cam``, ``gravity``, ``geometry``, ``pole_load``, ``pin_rest`` and ``free_levers`` and balances
    their own torques (:meth:`~.forces.BreakerLaws.lever_torques`, ``lever_angles``)."""

    def rod_rest_compression(self) -> float:
        """Compression (m) of a rod holding its pole at rest: force m g - bellows."""
        force, p = -self.pole_load, self.b.poles
        s0 = p.wipe_preload / p.rod_stiffness
        return force / p.rod_stiffness if force <= p.wipe_preload else s0 + (force - p.wipe_preload) / p.wipe_rate

    def rest_pole_travel(self, phi: float) -> float:
        """Pole travel z (m) with the rod at its rest compression for follower angle phi."""
        fx, fy = output_point(phi, self.b.follower)
        length = self.b.poles.push_rod_length - self.rod_rest_compression()
        return fy + math.sqrt(length * length - (self.pin_rest[0] - fx) ** 2) - self.pin_rest[1]

    def rest_torques(self, theta: float, phi: float, psi: Sequence) -> tuple[float, list, tuple]:
        """:meth:`lever_torques` at rest (every speed zero), each pole at its rod's rest compression
        on its own lever (:meth:`rest_pole_travel`)."""
        n = self.b.poles.count
        z = [self.rest_pole_travel(a) for a in self.lever_angles(phi, psi)] if self.free_levers else \
            [self.rest_pole_travel(phi)] * n  # one value for every pole (as before the main shaft)
        return self.lever_torques(theta, 0.0, phi, 0.0, psi, [0.0] * len(psi), z, [0.0] * n)

    def rest_levers(self, theta: float, phi: float) -> list:
        """The free pole levers' angles (rad) in torque balance (rods at rest, the segments twisted
        by them) with the follower at ``phi``: Newton's method on the levers' torques, the Jacobian
        by differences (the rods' torques change little with the angle; the segments dominate)."""
        psi = np.full(len(self.free_levers), float(phi))
        if not psi.size:
            return []
        h = 1e-7
        for _ in range(30):
            r = np.array(self.rest_torques(theta, phi, psi)[1])
            jac = np.empty((psi.size, psi.size))
            for k in range(psi.size):
                d = psi.copy()
                d[k] += h
                jac[:, k] = (np.array(self.rest_torques(theta, phi, d)[1]) - r) / h
            step = np.linalg.solve(jac, r)
            psi = psi - step
            if np.max(np.abs(step)) <= 1e-15:
                break
        return [float(x) for x in psi]

    def initial_state(self, spring_pull, pin_weight_torque=0.0) -> InitialState:
        """Static rest at the cam's initial angle; ``spring_pull`` (N, N) is the closing
        springs' pull on pin B there, ``pin_weight_torque`` (N m) the weight of the springs'
        pin mass about A when the springs carry weight. With a main shaft every pole lever is in
        torque balance too (:meth:`rest_levers`): the follower's balance takes the whole shaft's."""
        cam = self.cam
        theta = cam.initial_angle

        def torque(phi):
            return self.rest_torques(theta, phi, self.rest_levers(theta, phi))[0]

        phi_rest = self.geometry.follower_angle
        span = 1e-3
        lo, hi = phi_rest - span, phi_rest + span
        if torque(lo) * torque(hi) > 0:
            raise SimulationError("breaker: no static rest of the follower on the cam at the initial angle (the "
                                  "torques on it do not balance within 1 mrad of its geometric rest): check the "
                                  "opening spring's preload against the poles' bellows and push-rod forces, and the "
                                  "contact values (stiffness, exponent)")
        phi = brentq(torque, lo, hi, xtol=1e-15)
        psi = self.rest_levers(theta, phi)
        _, _, (t_cam, _, _) = self.rest_torques(theta, phi, psi)
        z = [self.rest_pole_travel(a) for a in self.lever_angles(phi, psi)]
        bx, by = cam_pin(theta, cam)
        fx, fy = spring_pull
        spring_and_weight = ((bx - cam.pivot[0]) * fy - (by - cam.pivot[1]) * fx
                             + cam_weight_torque(theta, cam, self.gravity) + pin_weight_torque)
        return InitialState(phi, z, -(spring_and_weight + t_cam), psi)

"""The independent breaker reference's equations: parameters, forces, friction and rest of the closing.

Holds :class:`Closing`, the closing's mechanism as :mod:`.breaker` integrates it: the parameters
read from the loaded rig and the model spec (cam and lumped closing-spring chain, shaft friction,
follower, poles and push rods, opening spring, contacts, latch, and the elastic main shaft of
:mod:`.breaker_shaft` when the rig has one: each push rod then acts on its own pole lever), the forces (chain, cam-roller
and pole contacts, push rods, opening spring, latch ramp, and when the rig has them the closing end
stop and the holding latch), everything on the cam but friction as
T_c and the shaft reaction R = R0 + R1 theta'', the friction law in speed regimes with the
friction/reaction coupling solved for theta'' (Brent), and the static rest held by the latch.
The roller's penetration comes from :mod:`.breaker_distance`, the geometry from
:mod:`.breaker_geometry`.

Shares no code with the model. It shares the reading of the spec and rig: the friction law and
its values (``mu_s`` taken as at least ``mu_k``), the lumped chain's conventions (it solves the chain
itself from k0, m0 and n, :mod:`.breaker_chain`; ``count`` identical springs lumped as one chain of
``count`` times the masses and stiffnesses), the contact constants
(Hertz or Palmgren line stiffness, Lankarani-Nikravesh or Hunt-Crossley damping, the impact-speed
floor), the latch ramp T_h (1 - t / t_r) and the planar layout; for the end stop and the holding
latch, the reading of their rig fields: a linear spring and damper at ``arm`` on A->B,
perpendicular to it, never pulling, and a latch that engages on reaching its angle; for the main
shaft, the reading of ``breaker.main_shaft`` (linear segments k = G J / pitch, damping per segment,
the drive pole's lever rigid with the follower, the inertia split I_f - (n-1) I_l and I_l).

Units: SI. Lengths in m, masses in kg, inertias in kg m^2, angles in rad (counter-clockwise),
forces in N, torques in N m, stiffnesses in N/m (N/m^n for a Hertz law), gravity in m/s^2 along -y.
"""
from __future__ import annotations

import math
from typing import Any, Sequence

import numpy as np
from scipy.optimize import brentq

from ..errors import SimulationError
from .breaker_chain import chain_of
from .breaker_distance import DISTANCES, roller_contact
from .breaker_geometry import Geometry
from .breaker_shaft import Shaft

#: Palmgren's steel-on-steel line-contact compliance, delta (mm) = C Q^0.9 / l^0.8 (N, mm).
PALMGREN = 3.84e-5


class Closing(Geometry):
    """Parameters, the rest state and the forces of the closing (:mod:`.breaker`'s docstring).

    State vector y: theta, theta', the chain points (x, y) and their velocities, phi, the pole
    travels z_i, phi', z_i', and with an elastic main shaft (``shaft``, :mod:`.breaker_shaft`)
    the free pole levers' angles psi_j and speeds psi_j' in pole order (rad, rad/s, m, m/s).
    """

    def __init__(self, rig: Any, spec: Any, distance: str = "exact"):
        if distance not in DISTANCES:
            raise ValueError("distance must be 'exact' or 'first_order'")
        self.distance = distance
        super().__init__(rig)
        self.g = rig.gravity
        self._cam_and_spring(rig.cam, rig.closing_spring, spec.spring_model)
        self._friction(spec, rig.shaft_radius)
        self.If = rig.breaker.follower.inertia
        self._poles_and_springs(rig.breaker, spec)
        self.shaft = Shaft.of(rig.breaker, self.n, self.If)
        self.nl = len(self.shaft.free) if self.shaft else 0  # free pole levers
        self.lev = 2 + 4 * self.nm + 2 + 2 * self.n  # their first index in y
        self._contacts(rig.breaker, spec)
        self._latch(rig.breaker)
        self._stops(rig.breaker)

    # -- parameters ---------------------------------------------------------------------------
    def _cam_and_spring(self, cam, spring, spring_model):
        """The cam's mass and the closing spring, lumped: ``count`` springs as one chain, the chain
        solved here from the spring's k0, m0 and the spec's n and convention (:mod:`.breaker_chain`)."""
        self.mc, self.lg, self.psi = cam.mass, cam.com_distance, cam.com_angle
        c = spring.count
        self.O = (float(spring.anchor[0]), float(spring.anchor[1]))
        self.weight = bool(spring.weight)
        if spring_model.kind == "massless":
            self.masses, self.ks, self.ls, self.mpin = [], [c * spring.stiffness], [spring.free_length], 0.0
        elif spring_model.kind == "lumped":
            chain = chain_of(spring.stiffness, spring.mass, spring.free_length, spring_model.masses, spring_model.convention)
            self.masses = [c * m for m in chain.masses]
            self.ks = [c * k for k in chain.stiffnesses]
            self.ls = list(chain.free_lengths)
            self.mpin = c * chain.pin_mass
        else:
            raise ValueError(f"the independent breaker reference has massless and lumped springs only, not {spring_model.kind}")
        self.nm = len(self.masses)
        self.IA = cam.inertia_com + self.mc * self.lg**2 + self.mpin * self.lab**2
        self.theta0 = cam.initial_angle

    def _friction(self, spec, radius):
        """Shaft friction (spec values; without an effect its value is off in the spec already)."""
        self.mu_k = spec.mu_k
        self.mu_s = max(spec.mu_s, spec.mu_k)
        self.w0, self.ws, self.cv, self.r = spec.stick_velocity, spec.stribeck_velocity, spec.viscous, radius
        bounds = [0.0] + ([self.w0] if self.w0 > 0 else []) + ([self.ws] if self.ws > self.w0 else []) + [math.inf]
        self.bounds = bounds

    def _poles_and_springs(self, b, spec):
        """Poles, push rods (wipe spring above the preload) and the opening spring."""
        po = b.poles
        self.n = po.count
        self.mp = po.moving_mass
        self.gaps = [po.contact_gap + o for o in po.gap_offsets]
        self.Lrod, self.krod, self.pre, self.kwipe, self.crod = (po.push_rod_length, po.rod_stiffness, po.wipe_preload,
                                                                  po.wipe_rate, po.rod_damping)
        self.s0 = self.pre / self.krod
        self.pin_x, self.pin_y0 = self.F0[0], self.F0[1] + self.Lrod
        self.pole_push = spec.bellows_force - self.mp * self.g  # N along closing
        o = b.opening_spring
        self.anchor = (self.F0[0], self.F0[1] - o.length)
        self.k_open, self.l_open = o.stiffness, o.length - o.preload / o.stiffness

    def _contacts(self, b, spec):
        """Cam-roller (Hertz point or Palmgren line) and pole contacts with their damping."""
        con = b.contact
        roller = b.cam_roller
        if roller.law == "line":
            width_mm = 1000.0 * roller.roller_width
            self.K_roller = (1000.0 * width_mm**0.8 / PALMGREN) ** (1.0 / 0.9)  # Q = (delta_mm l^0.8 / C)^(1/0.9)
            self.n_roller = 1.0 / 0.9
        else:
            self.K_roller, self.n_roller = con.cam_roller_stiffness, con.exponent
        damped = "contact_damping" in spec.effects
        self.e = spec.restitution if damped else 1.0
        self.hunt_crossley = roller.damping == "hunt_crossley"
        self.alpha = roller.damping_factor if damped else 0.0
        self.K_pole, self.n_pole, self.v_floor = con.pole_stiffness, con.exponent, con.min_impact_speed
        self.impact = [0.0] * (self.n + 1)  # LN impact speeds [cam-roller, poles]

    def _latch(self, b):
        """The latch point (arm, angle from A->B) and its release ramp; holding torque set by :meth:`rest`."""
        lp = b.latch_point
        self.latch_arm = self.lab if lp.arm is None else lp.arm
        self.latch_angle = lp.angle
        self.t_release = b.latch_release_time
        self.holding = 0.0

    def _stops(self, b):
        """The closing end stop and the holding latch (rig sections ``breaker.end_stop`` and
        ``breaker.hold_latch``; None: not modelled) as (angle rad, arm m, stiffness N/m, damping
        N s/m); whether the latch has engaged is set by the integration's events."""
        self.stop = self._stop_values(getattr(b, "end_stop", None))
        self.hold = self._stop_values(getattr(b, "hold_latch", None))
        self.engaged = False

    @staticmethod
    def _stop_values(part):
        """(angle, arm, stiffness, damping, depth over which the damping builds up: 0 at once)."""
        if part is None:
            return None
        return (float(part.angle), float(part.arm), float(part.stiffness), float(part.damping),
                float(getattr(part, "damping_depth", 0.0)))

    # -- contact distance ---------------------------------------------------------------------
    def roller_contact(self, theta: float, omega: float, phi: float, phid: float):
        """(penetration m, rate m/s, outward normal, roller centre C) (:mod:`.breaker_distance`)."""
        return roller_contact(self, theta, omega, phi, phid, self.distance)

    # -- forces -------------------------------------------------------------------------------
    def roller_force(self, pen: float, rate: float) -> float:
        if pen <= 0.0:
            return 0.0
        elastic = self.K_roller * pen**self.n_roller
        if self.hunt_crossley:
            return max(0.0, elastic * (1.0 + self.alpha * rate))
        v = max(self.impact[0], self.v_floor)
        return max(0.0, elastic * (1.0 + 0.75 * (1.0 - self.e**2) * rate / v))

    def pole_force(self, i: int, z: float, zd: float) -> float:
        pen = z - self.gaps[i]
        if pen <= 0.0:
            return 0.0
        v = max(self.impact[i + 1], self.v_floor)
        return max(0.0, self.K_pole * pen**self.n_pole * (1.0 + 0.75 * (1.0 - self.e**2) * zd / v))

    def rod(self, phi: float, phid: float, z: float, zd: float) -> tuple[float, float, float]:
        """(force on the pole along +y, torque on the follower, compression)."""
        F = self.output_point(phi)
        vF = (-phid * (F[1] - self.P[1]), phid * (F[0] - self.P[0]))
        dx, dy = self.pin_x - F[0], self.pin_y0 + z - F[1]
        L = math.hypot(dx, dy)
        ex, ey = dx / L, dy / L
        comp = self.Lrod - L
        rate = -(ex * (0.0 - vF[0]) + ey * (zd - vF[1]))
        force = self.krod * comp if comp <= self.s0 else self.pre + self.kwipe * (comp - self.s0)
        force += self.crod * rate
        # the rod pushes the pin along +e, the follower at F along -e
        torque = (F[0] - self.P[0]) * (-force * ey) - (F[1] - self.P[1]) * (-force * ex)
        return force * ey, torque, comp

    def opening_torque(self, phi: float) -> float:
        F = self.output_point(phi)
        dx, dy = F[0] - self.anchor[0], F[1] - self.anchor[1]
        L = math.hypot(dx, dy)
        tension = self.k_open * (L - self.l_open)
        gx, gy = -tension * dx / L, -tension * dy / L
        return (F[0] - self.P[0]) * gy - (F[1] - self.P[1]) * gx

    def latch(self, t: float, theta: float) -> tuple[float, float, float]:
        """(torque, Fx, Fy) of the latch on the cam."""
        if t <= 0.0:
            torque = self.holding
        elif t >= self.t_release:
            torque = 0.0
        else:
            torque = self.holding * (1.0 - t / self.t_release)
        a = theta + self.latch_angle
        f = torque / self.latch_arm
        return torque, -f * math.sin(a), f * math.cos(a)

    def stop_penetrations(self, theta: float) -> tuple[float, float]:
        """(end stop, holding latch) penetrations (m) at cam angle theta: the stop lever's travel
        past the stop, arm (theta - angle), and the latch face's travel back past the pawl,
        arm (angle - theta) (whether or not the pawl has dropped); -inf without the part."""
        stop = self.stop[1] * (theta - self.stop[0]) if self.stop else -math.inf
        hold = self.hold[1] * (self.hold[0] - theta) if self.hold else -math.inf
        return stop, hold

    def stops(self, theta: float, omega: float) -> tuple[float, float, float, float, float]:
        """(torque N m, Fx N, Fy N, end stop force N, latch force N) of the end stop and, once
        engaged, the holding latch on the cam. Each is a buffer: stiffness times penetration plus
        damping times its rate while in contact, never pulling, acting at its arm on A->B and
        perpendicular to it (the stop against the forward turn, the latch with it); the end stop's
        damping grows in proportion to the penetration up to its damping depth, when it has one."""
        d_stop, d_hold = self.stop_penetrations(theta)
        f_stop = f_hold = 0.0
        if d_stop > 0.0:
            _, arm, k, c, depth = self.stop
            if depth > 0.0 and d_stop < depth:  # the buffer's damping builds up over its first `depth`
                c = c * d_stop / depth
            f_stop = max(0.0, k * d_stop + c * arm * omega)
        if self.engaged and d_hold > 0.0:
            _, arm, k, c, _ = self.hold
            f_hold = max(0.0, k * d_hold - c * arm * omega)
        push = (f_hold * self.hold[1] if f_hold else 0.0) - (f_stop * self.stop[1] if f_stop else 0.0)
        net = f_hold - f_stop  # along the forward direction (-sin theta, cos theta) of a point on A->B
        return push, -net * math.sin(theta), net * math.cos(theta), f_stop, f_hold

    def chain_forces(self, theta: float, pts: list[tuple[float, float]]) -> tuple[list[tuple[float, float]], tuple[float, float]]:
        """(accelerations of the chain points, pull on pin B)."""
        B = self.pin(theta)
        nodes = [self.O] + pts + [B]
        pulls = []
        for k, l0, p, q in zip(self.ks, self.ls, nodes[:-1], nodes[1:]):
            dx, dy = q[0] - p[0], q[1] - p[1]
            L = math.hypot(dx, dy)
            tension = k * (L - l0)
            pulls.append((tension * dx / L, tension * dy / L))  # pulls q towards p: -this on q
        acc = []
        for i, m in enumerate(self.masses):
            fx = pulls[i + 1][0] - pulls[i][0]
            fy = pulls[i + 1][1] - pulls[i][1] - (m * self.g if self.weight else 0.0)
            acc.append((fx / m, fy / m))
        return acc, (-pulls[-1][0], -pulls[-1][1])

    def cam_applied(self, t: float, y: np.ndarray) -> tuple[float, tuple[float, float], tuple[float, float], tuple]:
        """Everything on the cam but friction: (T_c, R0, R1, roller state) at state y."""
        theta, omega = y[0], y[1]
        pts = [(y[2 + 2 * k], y[3 + 2 * k]) for k in range(self.nm)]
        _, (sx, sy) = self.chain_forces(theta, pts)
        j = 2 + 4 * self.nm
        phi, phid = y[j], y[j + 1 + self.n]
        pen, rate, (nx, ny), C = self.roller_contact(theta, omega, phi, phid)
        f = self.roller_force(pen, rate)
        cfx, cfy = -f * nx, -f * ny  # on the cam
        tl, lx, ly = self.latch(t, theta)
        if self.stop or self.hold:
            ts, stop_x, stop_y, _, _ = self.stops(theta, omega)
            tl, lx, ly = tl + ts, lx + stop_x, ly + stop_y
        rb = (self.lab * math.cos(theta), self.lab * math.sin(theta))
        rg = (self.lg * math.cos(theta - self.psi), self.lg * math.sin(theta - self.psi))
        rc = (C[0] - self.A[0], C[1] - self.A[1])
        pin_w = self.mpin * self.g if self.weight else 0.0
        Tc = (rb[0] * sy - rb[1] * sx) - self.mc * self.g * rg[0] - pin_w * rb[0] + (rc[0] * cfy - rc[1] * cfx) + tl
        # R = m_c a_G + m_pin a_B - (spring + roller + latch + weights)
        w2 = omega * omega
        R0 = (-self.mc * w2 * rg[0] - self.mpin * w2 * rb[0] - sx - cfx - lx,
              -self.mc * w2 * rg[1] - self.mpin * w2 * rb[1] - sy - cfy - ly + self.mc * self.g + pin_w)
        R1 = (-self.mc * rg[1] - self.mpin * rb[1], self.mc * rg[0] + self.mpin * rb[0])
        return Tc, R0, R1, (pen, rate, f, (nx, ny), C)

    def lever_state(self, y: np.ndarray) -> tuple[list[float], list[float]]:
        """Every pole lever's angle (rad) and speed (rad/s): the follower's with a rigid shaft."""
        j, n, lev, nl = 2 + 4 * self.nm, self.n, self.lev, self.nl
        phi, phid = y[j], y[j + 1 + n]
        if self.shaft is None:
            return [phi] * n, [phid] * n
        return self.shaft.angles(phi, y[lev:lev + nl]), self.shaft.angles(phid, y[lev + nl:lev + 2 * nl])

    def others(self, t: float, y: np.ndarray, roller: tuple) -> tuple[list[tuple[float, float]], float, list[float], list[float]]:
        """Rates of the chain, follower, poles and free pole levers at state y (roller: its contact
        state). Pole i's push rod acts on its own lever (the follower with a rigid shaft)."""
        nm, n = self.nm, self.n
        pts = [(y[2 + 2 * k], y[3 + 2 * k]) for k in range(nm)]
        acc, _ = self.chain_forces(y[0], pts)
        j = 2 + 4 * nm
        z, zd = y[j + 1:j + 1 + n], y[j + 2 + n:j + 2 + 2 * n]
        a, w = self.lever_state(y)
        _, _, f, (nx, ny), C = roller
        t_fol = (C[0] - self.P[0]) * (f * ny) - (C[1] - self.P[1]) * (f * nx) + self.opening_torque(y[j])
        zacc, rods = [], []
        for i in range(n):
            push, torque, _ = self.rod(a[i], w[i], z[i], zd[i])
            rods.append(torque)
            zacc.append((push - self.pole_force(i, z[i], zd[i]) + self.pole_push) / self.mp)
        if self.shaft is None:
            for torque in rods:
                t_fol += torque
            return acc, t_fol / self.If, zacc, []
        on_lever = [r + s for r, s in zip(rods, self.shaft.torques(a, w))]
        t_fol += on_lever[self.shaft.drive]
        return (acc, t_fol / self.shaft.follower_inertia, zacc,
                [on_lever[i] / self.shaft.lever_inertia for i in self.shaft.free])

    # -- friction -----------------------------------------------------------------------------
    def regime_split(self, regime: int, w: float, s: float) -> tuple[float, float]:
        """(k, v): T_f = k F_n + v in speed regime ``regime`` (bounds index), direction s."""
        lo, hi = self.bounds[regime], self.bounds[regime + 1]
        mid = 0.5 * (lo + hi) if math.isfinite(hi) else lo + 1.0
        if mid <= self.w0:
            return self.mu_s * self.r * s, 0.0
        if self.ws > 0.0 and mid < self.ws:
            # |w| clipped to the regime: a Runge-Kutta stage may look beyond the regime's end
            # (the event then ends the segment there), where the branch would extrapolate
            speed = min(max(abs(w), lo), hi)
            return (self.mu_s - (self.mu_s - self.mu_k) * speed / self.ws) * self.r * s, 0.0
        return self.mu_k * self.r * s, self.cv * (w - (self.ws if self.ws > 0 else 0.0) * s)

    def slip_acceleration(self, Tc: float, R0: tuple[float, float], R1: tuple[float, float], k: float, v: float) -> tuple[float, float]:
        """theta'' with T_f = k |R0 + R1 theta''| + v (Brent on a monotonic function)."""
        I = self.IA
        a_c = (Tc - v) / I
        if k == 0.0:
            return a_c, math.hypot(*R0)

        def g(a):
            return a - a_c + k / I * math.hypot(R0[0] + R1[0] * a, R0[1] + R1[1] * a)

        if abs(k / I) * math.hypot(*R1) >= 1.0:
            raise SimulationError("independent breaker reference: friction/reaction coupling is ill-posed")
        D = abs(k / I) * (math.hypot(*R0) + math.hypot(*R1) * abs(a_c)) / (1.0 - abs(k / I) * math.hypot(*R1))
        D = D * (1.0 + 1e-9) + 1e-12
        lo, hi = a_c - D, a_c + D
        while g(lo) > 0.0:
            lo -= D
        while g(hi) < 0.0:
            hi += D
        a = brentq(g, lo, hi, xtol=1e-14 * (abs(a_c) + D), rtol=4 * np.finfo(float).eps, maxiter=200)
        return a, math.hypot(R0[0] + R1[0] * a, R0[1] + R1[1] * a)

    # -- rest state ---------------------------------------------------------------------------
    def rest(self) -> tuple[float, list[float], float, list[float]]:
        """Static rest held by the latch: (follower angle, pole travels, holding torque, free lever
        angles). Each rod carries its pole's rest force; with an elastic shaft every free lever is
        in balance between its rod and the segments (they twist under the rods' torques), and the
        follower's balance includes the shaft's torque on the drive lever."""
        n = self.n
        force = -self.pole_push  # the rod holds the pole's weight minus the bellows force
        comp = force / self.krod if force <= self.pre else self.s0 + (force - self.pre) / self.kwipe

        def travel(a):
            F = self.output_point(a)
            L = self.Lrod - comp
            return F[1] + math.sqrt(L * L - (self.pin_x - F[0]) ** 2) - self.pin_y0

        def load(a):  # the rod's torque on a lever at angle a, its pole at rest
            return self.rod(a, 0.0, travel(a), 0.0)[1]

        def torque(phi):
            pen, rate, (nx, ny), C = self.roller_contact(self.theta0, 0.0, phi, 0.0)
            f = self.roller_force(pen, 0.0)
            t = (C[0] - self.P[0]) * (f * ny) - (C[1] - self.P[1]) * (f * nx) + self.opening_torque(phi)
            if self.shaft is None:
                return t + n * self.rod(phi, 0.0, travel(phi), 0.0)[1]
            a = self.shaft.rest_angles(phi, load)
            return t + load(phi) + self.shaft.torques(a, [0.0] * n)[self.shaft.drive]

        phi = brentq(torque, self.phi_geo - 1e-3, self.phi_geo + 1e-3, xtol=1e-15)
        a = [phi] * n if self.shaft is None else self.shaft.rest_angles(phi, load)
        z = [travel(x) for x in a]
        levers = [a[i] for i in self.shaft.free] if self.shaft else []
        y = self.initial_vector(phi, z, levers)
        self.holding = 0.0
        Tc, _, _, _ = self.cam_applied(-1.0, y)  # with holding = 0: the torque the latch must balance
        self.holding = -Tc
        return phi, z, -Tc, levers

    def initial_vector(self, phi: float, z: Sequence[float], levers: Sequence[float] = ()) -> np.ndarray:
        B = self.pin(self.theta0)
        compliance = [1.0 / k for k in self.ks]
        total, acc, pts = sum(compliance), 0.0, []
        for k in range(self.nm):
            acc += compliance[k]
            f = acc / total
            pts += [self.O[0] + f * (B[0] - self.O[0]), self.O[1] + f * (B[1] - self.O[1])]
        return np.array([self.theta0, 0.0] + pts + [0.0] * (2 * self.nm) + [phi] + list(z) + [0.0] + [0.0] * self.n
                        + list(levers) + [0.0] * len(levers))

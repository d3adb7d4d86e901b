"""Every force of the whole breaker at a state (:class:`BreakerLaws`), gathered from the laws of its
parts: the cam-roller contact (:mod:`..cam_follower`, :mod:`..contact`), the push rods and poles
(:mod:`.poles`), the opening spring, the pole levers on the main shaft (:mod:`.main_shaft`), the
closing latch (:mod:`.latch`), the end stop and holding latch (:mod:`.stops`); its rest state is
:mod:`.rest`'s. The Exudyn builder (:mod:`vcbmodel.builders.breaker`), the compiled path, the reference
solve and the evaluation (:mod:`vcbmodel.experiments.closing_evaluation`) all ask it.

Contacts: the cam-roller contact is a Hertz point contact or a line contact (a cylindrical
roller on a cam, :func:`vcbmodel.laws.contact.palmgren_line_stiffness`), damped by
Lankarani-Nikravesh (impact speed) or Hunt-Crossley (fixed factor, for a contact preloaded
throughout), as the rig's :class:`~vcbmodel.laws.cam_follower.CamRollerLaw` says; the pole contacts are Hertz point contacts
with Lankarani-Nikravesh damping (impacts). The latch holds the cam with a force at a latch point
(:class:`~.latch.LatchPoint`), so it loads the shaft's journal like any other force on the cam.
"""
from __future__ import annotations

import math
from collections.abc import Sequence

from ..cam_follower import CamRollerContact, cam_roller_contact, cam_roller_loads, output_point, rest_geometry
from ..contact import LINE_EXPONENT, contact_energy, contact_force, hunt_crossley_force, palmgren_line_stiffness, update_impact_speeds
from ..friction import NumericOps
from ..mechanics import cam_pin, massless_spring_force
from ..types import Ops, Scalar
from .latch import latch_force, latch_torque
from .main_shaft import segment_stiffness, segment_torque
from .poles import pole_gaps, push_rod_force
from .rest import AtRest
from .stops import end_stop_force, hold_latch_engagement, hold_latch_force


class BreakerLaws(AtRest):
    """Every force of the breaker at a state, from the laws of its parts (module docstring).

    One object serves the Exudyn user functions, the reference solve and the evaluation
    (forces and energies from the recorded states). ``breaker``: the rig's breaker data (its
    ``cam_roller`` :class:`CamRollerLaw` and ``latch_point`` :class:`LatchPoint`, read by
    :func:`vcbmodel.rig.sections.read_breaker`); ``cam``: the rig's cam (its
    axis A and the start angle); ``gravity`` (m/s^2); ``restitution`` of the Lankarani-Nikravesh
    contacts (1 = elastic) and ``bellows_force`` per pole (N) are the effect-dependent values
    (effects ``contact_damping`` and ``bellows_force``); ``damped``: whether contact damping is
    on at all (effect ``contact_damping``; default: restitution < 1), which switches the
    Hunt-Crossley cam-roller damping too.
    """

    def __init__(self, breaker, cam, gravity, restitution=1.0, bellows_force=0.0, damped=None):
        self.b, self.cam, self.gravity = breaker, cam, gravity
        self.geometry = rest_geometry(breaker, cam.pivot)
        self.gaps = pole_gaps(breaker.poles)
        self.restitution = restitution
        self.damped = restitution < 1.0 if damped is None else bool(damped)
        self.pole_load = bellows_force - breaker.poles.moving_mass * gravity  # N, along closing
        fx, fy = self.geometry.output_point
        self.pin_rest = (fx, fy + breaker.poles.push_rod_length)
        self.opening_anchor = (fx, fy - breaker.opening_spring.length)
        o = breaker.opening_spring
        self.opening_free_length = o.length - o.preload / o.stiffness
        # the cam-roller contact's law
        self.roller_law = breaker.cam_roller
        law = breaker.contact
        if self.roller_law.law == "line":
            self.roller_stiffness = palmgren_line_stiffness(self.roller_law.roller_width)
            self.roller_exponent = LINE_EXPONENT
        else:
            self.roller_stiffness, self.roller_exponent = law.cam_roller_stiffness, law.exponent
        self.roller_hunt_crossley = self.roller_law.damping == "hunt_crossley"
        self.roller_alpha = self.roller_law.damping_factor if self.damped else 0.0
        latch = breaker.latch_point
        self.latch_arm = cam.arm_length if latch.arm is None else latch.arm
        self.latch_angle = latch.angle
        self._main_shaft(breaker)

    def _main_shaft(self, breaker) -> None:
        """The pole levers on the main shaft (``breaker.main_shaft``): ``drive`` (the drive pole's
        index, 0-based), ``free_levers`` (the other poles' indices, each its own coordinate), the
        segments' stiffness (N m/rad) and damping (N m s/rad), and the inertia (kg m^2) left on the
        follower's coordinate: the whole ``follower.inertia`` without the free levers'."""
        shaft, f = breaker.main_shaft, breaker.follower
        if shaft is None:
            self.drive, self.free_levers = 0, ()
            self.segment_stiffness = self.segment_damping = self.lever_inertia = 0.0
            self.follower_inertia = f.inertia
            return
        self.drive = shaft.drive_pole - 1
        self.free_levers = tuple(j for j in range(breaker.poles.count) if j != self.drive)
        self.segment_stiffness, self.segment_damping = segment_stiffness(shaft), shaft.damping
        self.lever_inertia = shaft.lever_inertia
        self.follower_inertia = f.inertia - len(self.free_levers) * shaft.lever_inertia

    @classmethod
    def of_rig(cls, rig, spec) -> BreakerLaws:
        """For a rig (its breaker, cam, gravity) and a model spec (restitution, bellows force,
        whether ``contact_damping`` is on)."""
        return cls(rig.breaker, rig.cam, rig.gravity, spec.restitution, spec.bellows_force,
                   damped="contact_damping" in spec.effects)

    # -- cam-roller contact
    def roller_force(self, penetration: Scalar, rate: Scalar, impact_speed: Scalar = 0.0, ops: Ops = NumericOps) -> Scalar:
        """Normal force (N) of the cam-roller contact at a penetration (m) and its rate (m/s)."""
        if self.roller_hunt_crossley:
            return hunt_crossley_force(penetration, rate, self.roller_stiffness, self.roller_exponent,
                                       self.roller_alpha, ops)
        return contact_force(penetration, rate, self.roller_stiffness, self.roller_exponent, self.restitution,
                             impact_speed, self.b.contact.min_impact_speed, ops)

    def roller_elastic(self, penetration: float) -> float:
        """Elastic part (N) of the cam-roller force."""
        return self.roller_stiffness * max(penetration, 0.0) ** self.roller_exponent

    def roller_energy(self, penetration: Scalar, ops: Ops = NumericOps) -> Scalar:
        """Elastic energy (J) stored in the cam-roller contact."""
        return contact_energy(penetration, self.roller_stiffness, self.roller_exponent, ops)

    def roller(self, theta: Scalar, omega: Scalar, phi: Scalar, phi_dot: Scalar, impact_speed: Scalar = 0.0,
               ops: Ops = NumericOps) -> tuple[CamRollerContact, Scalar]:
        """(CamRollerContact, normal force in N)."""
        c = cam_roller_contact(theta, omega, phi, phi_dot, self.b, self.geometry, ops)
        return c, self.roller_force(c.penetration, c.penetration_rate, impact_speed, ops)

    def roller_loads(self, theta: Scalar, omega: Scalar, phi: Scalar, phi_dot: Scalar, impact_speed: Scalar = 0.0,
                     ops: Ops = NumericOps) -> tuple[Scalar, Scalar, Scalar, Scalar]:
        """(torque on cam N m, torque on follower N m, force on cam Fx, Fy in N)."""
        c, force = self.roller(theta, omega, phi, phi_dot, impact_speed, ops)
        return cam_roller_loads(c, force, self.b, self.geometry)

    # -- push rods and poles
    def pin(self, z: Scalar) -> tuple[Scalar, Scalar]:
        return self.pin_rest[0], self.pin_rest[1] + z

    def rod(self, phi: Scalar, phi_dot: Scalar, z: Scalar, z_dot: Scalar,
            ops: Ops = NumericOps) -> tuple[Scalar, Scalar, tuple[Scalar, Scalar], Scalar]:
        """(compression m, its rate m/s, unit vector F -> pin, compressive force N)."""
        f = self.b.follower
        fx, fy = output_point(phi, f, ops)
        vx = -phi_dot * (fy - f.pivot[1])
        vy = phi_dot * (fx - f.pivot[0])
        px, py = self.pin(z)
        dx, dy = px - fx, py - fy
        length = ops.sqrt(dx * dx + dy * dy)
        ex, ey = dx / length, dy / length
        rate = -(ex * (0.0 - vx) + ey * (z_dot - vy))
        compression = self.b.poles.push_rod_length - length
        return compression, rate, (ex, ey), push_rod_force(compression, rate, self.b.poles, ops)

    def rod_loads(self, phi: Scalar, phi_dot: Scalar, z: Scalar, z_dot: Scalar, ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
        """(force on the pole along closing N, torque on the follower N m)."""
        _, _, (ex, ey), force = self.rod(phi, phi_dot, z, z_dot, ops)
        fx, fy = output_point(phi, self.b.follower, ops)
        pv = self.b.follower.pivot
        # the rod pushes the pin along +e and F along -e
        return force * ey, (fx - pv[0]) * (-force * ey) - (fy - pv[1]) * (-force * ex)

    def pole_contact(self, i: int, z: Scalar, z_dot: Scalar, impact_speed: Scalar = 0.0, ops: Ops = NumericOps) -> Scalar:
        """Force (N, opening direction) of pole i's fixed contact (Hertz point contact with
        Lankarani-Nikravesh damping: an impact contact)."""
        law = self.b.contact
        return contact_force(z - self.gaps[i], z_dot, law.pole_stiffness, law.exponent, self.restitution,
                             impact_speed, law.min_impact_speed, ops)

    def pole_elastic(self, penetration: float) -> float:
        law = self.b.contact
        return law.pole_stiffness * max(penetration, 0.0) ** law.exponent

    def pole_energy(self, penetration: Scalar, ops: Ops = NumericOps) -> Scalar:
        law = self.b.contact
        return contact_energy(penetration, law.pole_stiffness, law.exponent, ops)

    # -- opening spring
    def opening(self, phi: Scalar, ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
        """(tension N, torque on the follower N m)."""
        f = self.b.follower
        fx, fy = output_point(phi, f, ops)
        ox, oy = self.opening_anchor
        L = ops.sqrt((fx - ox) * (fx - ox) + (fy - oy) * (fy - oy))
        tension = self.b.opening_spring.stiffness * (L - self.opening_free_length)
        gx, gy = -tension * (fx - ox) / L, -tension * (fy - oy) / L
        return tension, (fx - f.pivot[0]) * gy - (fy - f.pivot[1]) * gx

    # -- the pole levers on the main shaft (breaker.main_shaft)
    def lever_angles(self, phi: Scalar, psi: Sequence) -> list:
        """Every pole lever's angle (or speed), in pole order: the follower's ``phi`` for the drive
        pole's lever, ``psi`` (the free levers', in pole order) for the others; ``phi`` for every
        pole on a rigid shaft."""
        if not self.free_levers:
            return [phi] * self.b.poles.count
        a = list(psi)
        a.insert(self.drive, phi)
        return a

    def shaft_torques(self, a: Sequence, a_dot: Sequence, ops: Ops = NumericOps) -> list:
        """The segments' torques (N m) on every pole lever (angles rad, speeds rad/s, pole order):
        :func:`segment_torque` of each segment, +T on lever j+1 and -T on lever j."""
        out = [0.0] * len(a)
        for j in range(len(a) - 1):
            torque = segment_torque(a[j], a[j + 1], a_dot[j], a_dot[j + 1], self.segment_stiffness,
                                    self.segment_damping, ops)
            out[j], out[j + 1] = out[j] - torque, out[j + 1] + torque
        return out

    def lever_torques(self, theta: Scalar, omega: Scalar, phi: Scalar, phi_dot: Scalar, psi: Sequence, psi_dot: Sequence,
                      z: Sequence, z_dot: Sequence, impact_speed: Scalar = 0.0,
                      ops: Ops = NumericOps) -> tuple[Scalar, list, tuple[Scalar, Scalar, Scalar]]:
        """(torque N m on the follower's coordinate, torques N m on the free pole levers, the
        roller's loads on the cam as :meth:`follower_torque`'s). Each push rod acts on its own
        lever, the segments between the levers, the roller and the opening spring on the follower
        (which carries the drive pole's lever). A rigid shaft: :meth:`follower_torque`, no levers."""
        if not self.free_levers:
            t_fol, cam = self.follower_torque(theta, omega, phi, phi_dot, z, z_dot, impact_speed, ops)
            return t_fol, [], cam
        a, a_dot = self.lever_angles(phi, psi), self.lever_angles(phi_dot, psi_dot)
        t_cam, t_fol, fx, fy = self.roller_loads(theta, omega, phi, phi_dot, impact_speed, ops)
        t_fol += self.opening(phi, ops)[1]
        shaft = self.shaft_torques(a, a_dot, ops)
        levers = [self.rod_loads(a[j], a_dot[j], z[j], z_dot[j], ops)[1] + shaft[j] for j in range(len(a))]
        return t_fol + levers[self.drive], [levers[j] for j in self.free_levers], (t_cam, fx, fy)

    def follower_torque(self, theta: Scalar, omega: Scalar, phi: Scalar, phi_dot: Scalar, z: Scalar, z_dot: Scalar, impact_speed: Scalar = 0.0,
                        ops: Ops = NumericOps) -> tuple[Scalar, tuple[Scalar, Scalar, Scalar]]:
        """Total torque (N m) on the follower and the roller's loads on the cam."""
        t_cam, t_fol, fx, fy = self.roller_loads(theta, omega, phi, phi_dot, impact_speed, ops)
        t_fol += self.opening(phi, ops)[1]
        for zi, zi_dot in zip(z, z_dot):
            t_fol += self.rod_loads(phi, phi_dot, zi, zi_dot, ops)[1]
        return t_fol, (t_cam, fx, fy)

    def latch_impact_speeds(self, impact: list, theta: Scalar, omega: Scalar, phi: Scalar, phi_dot: Scalar, z: Scalar, z_dot: Scalar,
                            ops: Ops = NumericOps) -> CamRollerContact:
        """Update ``impact`` ([cam-roller, pole 1..n], m/s) from a state by
        :func:`update_impact_speeds`; returns the cam-roller contact at that state."""
        roller = cam_roller_contact(theta, omega, phi, phi_dot, self.b, self.geometry, ops)
        state = [(roller.penetration, roller.penetration_rate)]
        state += [(zi - gap, zi_dot) for zi, zi_dot, gap in zip(z, z_dot, self.gaps)]
        update_impact_speeds(impact, state, ops)
        return roller

    # -- the closing latch
    def latch(self, t: Scalar, holding: Scalar, ops: Ops = NumericOps) -> Scalar:
        """The latch's torque (N m) on the cam at time t (s)."""
        return latch_torque(t, holding, self.b.latch_release_time, ops)

    def latch_loads(self, t: Scalar, theta: Scalar, holding: Scalar, ops: Ops = NumericOps) -> tuple[Scalar, Scalar, Scalar]:
        """(torque N m, Fx N, Fy N) of the latch on the cam: the force at the latch point that
        exerts :meth:`latch`'s torque, so that it also loads the shaft's journal."""
        torque = self.latch(t, holding, ops)
        fx, fy = latch_force(torque, theta, self.latch_arm, self.latch_angle, ops)
        return torque, fx, fy

    # -- the closing end stop and the holding latch (optional: breaker.end_stop, breaker.hold_latch)
    @property
    def has_stops(self) -> bool:
        """Whether the rig models an end stop or a holding latch (each section is optional)."""
        return self.b.end_stop is not None or self.b.hold_latch is not None

    def end_stop(self, theta: Scalar, omega: Scalar, ops: Ops = NumericOps) -> Scalar:
        """The end stop's force (N) on the cam's stop lever (0 without an end stop)."""
        stop = self.b.end_stop
        return 0.0 if stop is None else end_stop_force(theta, omega, stop, ops)

    def hold_latch(self, theta: Scalar, omega: Scalar, engaged: Scalar, ops: Ops = NumericOps) -> Scalar:
        """The holding latch's force (N) on the cam's latch face (0 without a holding latch)."""
        latch = self.b.hold_latch
        return 0.0 if latch is None else hold_latch_force(theta, omega, engaged, latch, ops)

    def engage(self, engaged: Scalar, theta: Scalar, ops: Ops = NumericOps) -> Scalar:
        """The holding latch's memory after a state at cam angle ``theta`` (rad)
        (:func:`hold_latch_engagement`); 0 without a holding latch."""
        latch = self.b.hold_latch
        return 0.0 if latch is None else hold_latch_engagement(engaged, theta, latch, ops)

    def stop_loads(self, theta: Scalar, omega: Scalar, engaged: Scalar, ops: Ops = NumericOps) -> tuple[Scalar, Scalar, Scalar]:
        """(torque about A N m, Fx N, Fy N) of the end stop and the holding latch on the cam: each
        force acts at its arm on A->B, perpendicular to it (the stop's against the forward turn,
        the latch's with it), so it loads the shaft's journal like the roller's and the latch's."""
        torque, fx, fy = 0.0, 0.0, 0.0
        for part, force, sign in ((self.b.end_stop, self.end_stop(theta, omega, ops), -1.0),
                                  (self.b.hold_latch, self.hold_latch(theta, omega, engaged, ops), 1.0)):
            if part is not None:
                f = sign * force
                torque, fx, fy = torque + part.arm * f, fx - f * ops.sin(theta), fy + f * ops.cos(theta)
        return torque, fx, fy

    def cam_loads(self, t: Scalar, theta: Scalar, omega: Scalar, phi: Scalar, phi_dot: Scalar, holding: Scalar, impact_speed: Scalar = 0.0,
                  engaged: Scalar = 0.0, ops: Ops = NumericOps) -> tuple[Scalar, Scalar, Scalar]:
        """(torque about A N m, Fx N, Fy N): the roller's and the latch's loads on the cam and,
        when the rig has them, the end stop's and the holding latch's (``engaged``: the holding
        latch's memory), the breaker's share of the cam's applied torque and shaft reaction."""
        t_cam, _, fx, fy = self.roller_loads(theta, omega, phi, phi_dot, impact_speed, ops)
        t_latch, lx, ly = self.latch_loads(t, theta, holding, ops)
        loads = (t_cam + t_latch, fx + lx, fy + ly)
        return self.with_stops(loads, theta, omega, engaged, ops)

    def with_stops(self, loads: tuple, theta: Scalar, omega: Scalar, engaged: Scalar, ops: Ops = NumericOps) -> tuple:
        """``loads`` (torque N m, Fx N, Fy N on the cam) plus :meth:`stop_loads`; unchanged (the
        same numbers, no operation) when the rig has neither an end stop nor a holding latch."""
        if not self.has_stops:
            return loads
        ts, sx, sy = self.stop_loads(theta, omega, engaged, ops)
        return loads[0] + ts, loads[1] + sx, loads[2] + sy


def pin_weight_torque(cam, spring, pin_mass: float, gravity: float) -> float:
    """Torque (N m) about A at the start of the weight of the springs' pin mass (``pin_mass`` kg per
    spring, riding on B), when the springs carry weight (``spring.weight``); 0 otherwise."""
    if not (pin_mass and spring.weight):
        return 0.0
    return -spring.count * pin_mass * gravity * cam.arm_length * math.cos(cam.initial_angle)


def massless_pull(cam, spring) -> tuple[float, float]:
    """Pull (N, N) of massless closing springs on pin B at the cam's initial angle."""
    return massless_spring_force(*cam_pin(cam.initial_angle, cam), spring)

"""The whole breaker's closing (paper section 4, Fig. 11-12): laws and geometry.

Planar model with separate pole bodies (see README "The whole breaker"): the cam of the
cam-drop test (eq. 9-13, closing springs and shaft friction unchanged) drives an oscillating
roller follower pivoted on the frame at ``follower.pivot``; the follower's output point F
pushes ``poles.count`` insulating push rods, each through its wipe (contact-pressure) spring,
into a moving contact that slides on a straight vertical guide (the translational joint) and
closes on its fixed contact after ``contact_gap``. An opening spring pulls F down (it is
charged by the closing). The closing latch holds the cam at rest until it is released.

Everything here is a pure function of numbers (units in each docstring), testable without
Exudyn. The breaker's data (:class:`vcbmodel.rig.data.Breaker` and its parts) come in as
arguments. :class:`BreakerLaws` gathers every force of the breaker at a state: the Exudyn
builder (:mod:`vcbmodel.builders.breaker`), the reference solve and the evaluation
(:mod:`vcbmodel.experiments.closing_evaluation`) all ask it.

Contacts: the cam-roller contact is a Hertz point contact or a line contact (a cylindrical
roller on a cam, :func:`vcbmodel.laws.contact.palmgren_line_stiffness`), damped by
Lankarani-Nikravesh (impact speed) or Hunt-Crossley (fixed factor, for a contact preloaded
throughout), as the rig's :class:`CamRollerLaw` says; the pole contacts are Hertz point contacts
with Lankarani-Nikravesh damping (impacts). The latch holds the cam with a force at a latch point
(:class:`LatchPoint`), so it loads the shaft's journal like any other force on the cam.

The cam profile, the follower's kinematics and the cam-roller contact's geometry are in
:mod:`.cam_follower` (re-exported here).
"""
from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from ..errors import SimulationError
from .contact import LINE_EXPONENT, hertz_contact_force, hunt_crossley_force, palmgren_line_stiffness
from .cam_follower import (  # noqa: F401 -- re-exported: the breaker's laws are read from here too
    TWO_PI, polynomial_rise, pitch_radius, follower_point, roller_centre, output_point, angle_on_circle, Geometry,
    rest_geometry, CamRollerContact, cam_roller_contact, cam_roller_loads, kinematic_follower_angle, pressure_angle_curve, follower_displacement)
from .friction import NumericOps
from .mechanics import cam_pin, cam_weight_torque, massless_spring_force, shaft_torsional_stiffness
from .types import Ops, Scalar


# --- contact laws ---------------------------------------------------------------------------------

def contact_force(penetration: Scalar, rate: Scalar, stiffness: Scalar, exponent: Scalar, restitution: Scalar, impact_speed: Scalar,
                  min_impact_speed: Scalar, ops: Ops = NumericOps) -> Scalar:
    """Hertz force with Lankarani-Nikravesh damping (N); the impact speed (m/s) is the approach
    speed at the start of the contact, floored at ``min_impact_speed`` for resting contacts."""
    return hertz_contact_force(penetration, rate, stiffness, restitution, ops.max(impact_speed, min_impact_speed),
                               exponent, ops)


def contact_energy(penetration: Scalar, stiffness: float, exponent: float, ops: Ops = NumericOps) -> Scalar:
    """Elastic energy (J) stored in a Hertz contact: K delta^(n+1) / (n+1)."""
    return stiffness * ops.max(penetration, 0.0) ** (exponent + 1.0) / (exponent + 1.0)


@dataclass(frozen=True)
class CamRollerLaw:
    """How the cam-roller contact is modelled (rig fields ``breaker.contact.cam_roller_law``,
    ``roller_width``, ``cam_roller_damping``, ``cam_roller_damping_factor``; see
    :mod:`vcbmodel.laws.contact`). The defaults are the original model: Hertz point contact with
    ``cam_roller_stiffness`` and ``exponent``, Lankarani-Nikravesh damping."""

    law: str = "hertz_point"  # hertz_point | line (Palmgren, exponent 10/9, K from roller_width)
    roller_width: float | None = None  # m, the roller's effective contact length (line law)
    damping: str = "lankarani_nikravesh"  # lankarani_nikravesh | hunt_crossley
    damping_factor: float = 0.0  # s/m, Hunt-Crossley alpha


@dataclass(frozen=True)
class LatchPoint:
    """Where the closing latch holds the cam (rig fields ``breaker.latch.arm``, ``angle``): a
    point on the cam at ``arm`` (m) from A, at ``angle`` (rad) from A->B, pushed perpendicular
    to A->point. None for ``arm``: at the spring pin B (arm l_AB, angle 0)."""

    arm: float | None = None
    angle: float = 0.0


@dataclass(frozen=True)
class EndStop:
    """The closing end stop (rig section ``breaker.end_stop``): a buffer on the frame (a stop
    with a shock absorber) that a stop lever of the cam meets at cam angle ``angle`` (rad, the
    cam angle A->B from +x, counted on from the start and not wrapped: 5.0 rad is 286 deg of the
    first turn). The lever's contact point is at ``arm`` (m) from A along A->B; the buffer pushes
    it back perpendicular to A->B with ``stiffness`` (N/m) times its penetration plus a damping
    coefficient times the penetration's rate, only while in contact and never pulling
    (:func:`end_stop_force`). The damping coefficient rises from zero at contact in proportion to
    the penetration and reaches ``damping`` (N s/m) at ``damping_depth`` (m), so the buffer's force
    rises from zero as a real buffer's does (a Hunt-Crossley-type damping, c d/d_r v, saturated);
    ``damping_depth`` 0: the plain dashpot, full ``damping`` from the first contact (its force
    jumps to damping x speed). Absent (None): not modelled, the cam turns on."""

    angle: float  # rad
    arm: float  # m
    stiffness: float  # N/m
    damping: float  # N s/m
    damping_depth: float = 0.0  # m; 0: the damping acts in full from the first contact


@dataclass(frozen=True)
class HoldLatch:
    """The holding (closing) latch (rig section ``breaker.hold_latch``): a pawl that drops behind
    the cam's latch face once the cam has passed ``angle`` (rad, as :class:`EndStop`'s) going
    forward, and from then on stops it turning back: a one-way stop at ``angle``, acting at
    ``arm`` (m) from A along A->B, with ``stiffness`` (N/m) and ``damping`` (N s/m) like the end
    stop's (:func:`hold_latch_force`). Whether it has engaged is memory kept from step to step
    (:func:`hold_latch_engagement`), as the contacts' impact speeds are. Absent (None): not
    modelled."""

    angle: float  # rad
    arm: float  # m
    stiffness: float  # N/m
    damping: float  # N s/m


@dataclass(frozen=True)
class MainShaft:
    """The main shaft that carries the pole levers (rig section ``breaker.main_shaft``): pole
    levers 1..n along it in pole order, ``pole_pitch`` (m) apart; a round shaft of ``diameter``
    (m) with a ``bore`` (m, 0: solid) and ``shear_modulus`` (Pa), so each segment between two
    levers has the torsional stiffness :func:`segment_stiffness` (N m/rad) and the torsional
    ``damping`` (N m s/rad); each pole lever has ``lever_inertia`` (kg m^2, its share of the
    follower's inertia); the lever of pole ``drive_pole`` (1..n) sits at the drive, rigid with the
    roller's follower lever. Absent (None): a rigid shaft, every rod on the follower."""

    pole_pitch: float  # m
    diameter: float  # m
    bore: float  # m
    shear_modulus: float  # Pa
    damping: float  # N m s/rad per segment
    lever_inertia: float  # kg m^2 per pole lever
    drive_pole: int  # 1..poles.count


def segment_stiffness(shaft: MainShaft) -> float:
    """Torsional stiffness (N m/rad) of one shaft segment between adjacent pole levers:
    G pi (d^4 - d_i^4) / 32 / pole_pitch (:func:`vcbmodel.laws.mechanics.shaft_torsional_stiffness`)."""
    return shaft_torsional_stiffness(shaft.diameter, shaft.shear_modulus, shaft.bore) / shaft.pole_pitch


def segment_torque(a_j: Scalar, a_next: Scalar, rate_j: Scalar, rate_next: Scalar, stiffness: Scalar, damping: Scalar,
                   ops: Ops = NumericOps) -> Scalar:
    """Torque (N m) of the shaft segment between lever j and lever j+1 (angles rad, speeds rad/s):
    T = k (a_j - a_{j+1}) + c (a_j' - a_{j+1}') with the segment's stiffness k (N m/rad) and
    damping c (N m s/rad); it acts +T on lever j+1 and -T on lever j. Linear: ``ops`` is not
    needed, kept for the laws' signature."""
    return stiffness * (a_j - a_next) + damping * (rate_j - rate_next)


def torsional_frequencies(shaft: MainShaft, poles, output_arm: float) -> np.ndarray:
    """Natural frequencies (Hz, ascending) of the pole levers twisting the shaft with the drive
    lever held (the cam, the springs and the roller hold it): each free lever with its inertia and
    its pole's mass reflected through a stiff rod (moving_mass output_arm^2), the segments'
    stiffness between them. An estimate: the rods' and wipe springs' own compliance is left out."""
    n, drive = poles.count, shaft.drive_pole - 1
    k = segment_stiffness(shaft)
    stiff = np.zeros((n, n))
    for j in range(n - 1):
        stiff[j:j + 2, j:j + 2] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    free = [j for j in range(n) if j != drive]
    if not free:
        return np.zeros(0)
    inertia = shaft.lever_inertia + poles.moving_mass * output_arm**2
    w2 = np.linalg.eigvalsh(stiff[np.ix_(free, free)] / inertia)
    return np.sqrt(np.maximum(w2, 0.0)) / (2.0 * math.pi)


def end_stop_damping(penetration: Scalar, stop: EndStop, ops: Ops = NumericOps) -> Scalar:
    """The end stop's damping coefficient (N s/m) at a penetration d (m, > 0): c min(d / d_r, 1)
    with c = ``damping`` and d_r = ``damping_depth``; c throughout when d_r is 0."""
    if stop.damping_depth <= 0.0:
        return stop.damping
    return stop.damping * ops.min(penetration / stop.damping_depth, 1.0)


def end_stop_force(theta: Scalar, omega: Scalar, stop: EndStop, ops: Ops = NumericOps) -> Scalar:
    """Force (N, >= 0) of the end stop on the cam's stop lever at cam angle ``theta`` (rad) and
    speed ``omega`` (rad/s): penetration d = arm (theta - angle) (m), rate arm omega (m/s);
    k d + c(d) d' while d > 0 (:func:`end_stop_damping`: zero at contact, rising to ``damping``
    at ``damping_depth``), clipped at zero (the buffer never pulls the lever back). Continuous at
    contact when ``damping_depth`` > 0."""
    d = stop.arm * (theta - stop.angle)
    force = stop.stiffness * d + end_stop_damping(d, stop, ops) * stop.arm * omega
    return ops.where(d <= 0.0, 0.0, ops.max(0.0, force))


def hold_latch_force(theta: Scalar, omega: Scalar, engaged: Scalar, latch: HoldLatch, ops: Ops = NumericOps) -> Scalar:
    """Force (N, >= 0) of the engaged holding latch on the cam's latch face: penetration
    d = arm (angle - theta) (m) once the cam turns back below ``angle``, rate -arm omega (m/s);
    k d + c d' while d > 0 and ``engaged`` (1: the pawl has dropped, 0: not yet), clipped at zero."""
    d = latch.arm * (latch.angle - theta)
    force = ops.where(d <= 0.0, 0.0, ops.max(0.0, latch.stiffness * d - latch.damping * latch.arm * omega))
    return ops.where(engaged <= 0.5, 0.0, force)


def hold_latch_engagement(engaged: Scalar, theta: Scalar, latch: HoldLatch, ops: Ops = NumericOps) -> Scalar:
    """The latch's memory (1 engaged, 0 not) after a state at cam angle ``theta`` (rad): it
    engages once the cam has reached ``angle`` and stays engaged."""
    return ops.where(theta >= latch.angle, 1.0, engaged)


def one_way_stop_energy(penetration: float | np.ndarray, stiffness: float) -> float | np.ndarray:
    """Elastic energy (J) of a stop's spring at a penetration (m): k d^2 / 2 for d > 0."""
    d = np.maximum(penetration, 0.0)
    return 0.5 * stiffness * d * d


def latch_force(torque: Scalar, theta: Scalar, arm: Scalar, angle: Scalar, ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
    """Force (N, N) on the cam at the latch point that exerts ``torque`` (N m) about A:
    perpendicular to A->point, magnitude torque / arm."""
    a = theta + angle
    f = torque / arm
    return -f * ops.sin(a), f * ops.cos(a)


def push_rod_force(compression: Scalar, rate: Scalar, poles, ops: Ops = NumericOps) -> Scalar:
    """Compressive force (N) of one push rod with its wipe spring: stiff (rod_stiffness) until
    the wipe spring's preload is reached, then the wipe spring's rate; structural damping.
    ``compression`` (m) is rod length at rest minus current length (negative: tension)."""
    s0 = poles.wipe_preload / poles.rod_stiffness
    elastic = ops.where(compression <= s0, poles.rod_stiffness * compression,
                        poles.wipe_preload + poles.wipe_rate * (compression - s0))
    return elastic + poles.rod_damping * rate


def push_rod_energy(compression: Scalar, poles, ops: Ops = NumericOps) -> Scalar:
    """Elastic energy (J) of :func:`push_rod_force`'s spring part."""
    s0 = poles.wipe_preload / poles.rod_stiffness
    x = compression - s0
    return ops.where(compression <= s0, 0.5 * poles.rod_stiffness * compression * compression,
                     0.5 * poles.wipe_preload * s0 + poles.wipe_preload * x + 0.5 * poles.wipe_rate * x * x)


def latch_torque(t: Scalar, holding_torque: Scalar, release_time: Scalar, ops: Ops = NumericOps) -> Scalar:
    """Torque (N m) of the closing latch on the cam: the holding torque until t = 0, then
    falling linearly to zero over ``release_time`` (s)."""
    return ops.where(t <= 0.0, holding_torque,
                     ops.where(t >= release_time, 0.0, holding_torque * (1.0 - t / ops.max(release_time, 1e-300))))


def pole_gaps(poles) -> list[float]:
    return [poles.contact_gap + o for o in poles.gap_offsets]


def update_impact_speeds(impact: list, state: Iterable[tuple[Scalar, Scalar]], ops: Ops = NumericOps) -> None:
    """While contact k is open (penetration <= 0) its impact speed follows the approach speed
    (m/s); once it penetrates, the last open value is kept: the speed at impact."""
    for k, (penetration, rate) in enumerate(state):
        impact[k] = ops.where(penetration <= 0.0, ops.max(rate, 0.0), impact[k])


@dataclass
class InitialState:
    """Static rest held by the latch: follower angle (rad), pole travels (m), the latch's
    holding torque on the cam (N m) and, with a main shaft (``breaker.main_shaft``), the free pole
    levers' angles (rad, in pole order without the drive pole's; empty for a rigid shaft)."""

    follower_angle: float
    pole_travel: list
    holding_torque: float
    lever_angles: list = field(default_factory=list)


class BreakerLaws:
    """Every force of the breaker at a state, from the laws above.

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

    # -- rest state
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

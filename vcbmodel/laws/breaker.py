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

Cam profile: the roller centre runs on the pitch curve ``rho(u) = base_radius + roller_radius
+ lift * s(u)`` about the cam axis A, where u is the cam's rotation measured so that the
roller, on its rest line, sees ``u = theta`` (the cam angle of A->B). ``s`` is the 4-5-6-7
polynomial rise ``35x^4 - 84x^5 + 70x^6 - 20x^7`` (zero speed, acceleration at both ends),
a dwell at full lift and the mirrored return.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..errors import SimulationError
from .contact import LINE_EXPONENT, hertz_contact_force, hunt_crossley_force, palmgren_line_stiffness
from .friction import NumericOps
from .mechanics import cam_pin, cam_weight_torque, massless_spring_force

TWO_PI = 2.0 * math.pi


# --- cam profile -------------------------------------------------------------------------------

def polynomial_rise(x, ops=NumericOps):
    """4-5-6-7 rise s(x) and ds/dx for x in [0, 1] (clipped outside); s(0)=0, s(1)=1."""
    x = ops.min(ops.max(x, 0.0), 1.0)
    x3 = x * x * x
    s = x3 * x * (35.0 + x * (-84.0 + x * (70.0 - 20.0 * x)))
    ds = x3 * (140.0 + x * (-420.0 + x * (420.0 - 140.0 * x)))
    return s, ds


def pitch_radius(u, profile, roller_radius, ops=NumericOps):
    """Distance rho (m) of the roller centre from the cam axis on the pitch curve, and
    d rho / d u (m/rad), at cam rotation u (rad) relative to the roller: the rise, the dwell at
    full lift, the return and the base circle (each piece evaluated, the one that applies chosen)."""
    p = profile
    turns = (u - p.rise_start) / TWO_PI
    u = p.rise_start + (u - p.rise_start) - TWO_PI * ops.floor(turns)  # into [rise_start, rise_start + 2 pi)
    base = p.base_radius + roller_radius
    w_rise, w_return = p.rise_end - p.rise_start, p.return_end - p.return_start
    s_rise, ds_rise = polynomial_rise((u - p.rise_start) / w_rise, ops)
    s_return, ds_return = polynomial_rise((u - p.return_start) / w_return, ops)
    rising, dwelling = u <= p.rise_end, u < p.return_start
    rho = ops.where(rising, base + p.lift * s_rise, ops.where(dwelling, base + p.lift, base + p.lift * (1.0 - s_return)))
    drho = ops.where(rising, p.lift * ds_rise / w_rise, ops.where(dwelling, 0.0, -p.lift * ds_return / w_return))
    return rho, drho


# --- follower kinematics -----------------------------------------------------------------------

def follower_point(phi, follower, arm, angle=0.0, ops=NumericOps):
    """Point on the follower at ``arm`` (m) and ``angle`` (rad) from the roller direction."""
    return (follower.pivot[0] + arm * ops.cos(phi + angle), follower.pivot[1] + arm * ops.sin(phi + angle))


def roller_centre(phi, follower, ops=NumericOps):
    return follower_point(phi, follower, follower.roller_arm, 0.0, ops)


def output_point(phi, follower, ops=NumericOps):
    """The follower's output point F (m) driving the push rods."""
    return follower_point(phi, follower, follower.output_arm, follower.output_angle, ops)


def angle_on_circle(pivot, arm, centre, radius, near):
    """Angle phi (rad) with |pivot + arm (cos phi, sin phi) - centre| = radius, closest to
    ``near`` (the intersection of two circles)."""
    dx, dy = centre[0] - pivot[0], centre[1] - pivot[1]
    d = math.hypot(dx, dy)
    cos_a = (arm * arm + d * d - radius * radius) / (2.0 * arm * d)
    if abs(cos_a) > 1.0:
        raise ValueError("the roller cannot reach the cam's pitch curve: check follower pivot and arm")
    base, a = math.atan2(dy, dx), math.acos(cos_a)
    candidates = (base + a, base - a)
    return min(candidates, key=lambda c: abs(math.remainder(c - near, TWO_PI)))


@dataclass(frozen=True)
class Geometry:
    """Derived rest geometry: cam axis A (m), roller direction from A (rad), open follower
    angle (rad), output point F0 (m)."""

    cam_axis: tuple
    roller_direction: float
    follower_angle: float
    output_point: tuple


def rest_geometry(breaker, cam_axis) -> Geometry:
    """The follower angle that puts the roller on the base circle (open position)."""
    f = breaker.follower
    rho0 = breaker.profile.base_radius + breaker.roller_radius
    phi = angle_on_circle(f.pivot, f.roller_arm, cam_axis, rho0, f.rest_angle)
    cx, cy = roller_centre(phi, f)
    return Geometry(tuple(cam_axis), math.atan2(cy - cam_axis[1], cx - cam_axis[0]), phi, output_point(phi, f))


# --- contact laws ---------------------------------------------------------------------------------

@dataclass
class CamRollerContact:
    """State of the cam-roller contact. Lengths m, speeds m/s, force N, torques N m."""

    penetration: float  # normal overlap of roller and cam surface (> 0: in contact)
    penetration_rate: float
    normal: tuple  # unit normal of the cam surface at the contact, pointing to the roller
    centre: tuple  # roller centre C (the force acts along the normal through C)
    pressure_angle: float  # rad, between the normal and the roller centre's path


def cam_roller_contact(theta, omega, phi, phi_dot, breaker, geometry: Geometry, ops=NumericOps) -> CamRollerContact:
    """Normal penetration of the roller into the cam (cam angle theta, follower angle phi, rad).

    With rho_C = |C - A| and beta the direction of C from A, the roller sees the cam
    rotation u = theta - (beta - beta_rest); the pitch curve's outward normal is
    n = (e_r - q e_beta) / sqrt(1 + q^2) with q = (d rho / d beta) / rho = -(d rho/du) / rho,
    and the penetration (rho(u) - rho_C) cos(gamma), cos(gamma) = 1 / sqrt(1 + q^2), exact to
    first order in the penetration. Against the exact minimum distance to the pitch curve
    (:mod:`vcbmodel.reference.breaker`) this costs 0.4 nm of penetration and 0.01 um of follower
    displacement over the reference closing.
    """
    f, A = breaker.follower, geometry.cam_axis
    cx, cy = roller_centre(phi, f, ops)
    vx, vy = -phi_dot * (cy - f.pivot[1]), phi_dot * (cx - f.pivot[0])
    dx, dy = cx - A[0], cy - A[1]
    rho_c = ops.sqrt(dx * dx + dy * dy)
    erx, ery = dx / rho_c, dy / rho_c
    ebx, eby = -ery, erx
    beta = ops.atan2(dy, dx)
    u = theta - (beta - geometry.roller_direction)
    rho, drho_du = pitch_radius(u, breaker.profile, breaker.roller_radius, ops)
    q = -drho_du / rho
    cos_g = 1.0 / ops.sqrt(1.0 + q * q)
    nx, ny = (erx - q * ebx) * cos_g, (ery - q * eby) * cos_g
    beta_dot = (ebx * vx + eby * vy) / rho_c
    rate = (drho_du * (omega - beta_dot) - (erx * vx + ery * vy)) * cos_g
    # pressure angle: normal vs the roller centre's direction of motion (perpendicular to the arm)
    tx, ty = -(cy - f.pivot[1]) / f.roller_arm, (cx - f.pivot[0]) / f.roller_arm
    pressure = ops.acos(ops.min(1.0, ops.abs(nx * tx + ny * ty)))
    return CamRollerContact((rho - rho_c) * cos_g, rate, (nx, ny), (cx, cy), pressure)


def cam_roller_loads(contact: CamRollerContact, force, breaker, geometry: Geometry):
    """Torques (N m) of a normal contact force (N, pushing the roller out) on the cam about A
    and on the follower about its pivot, and the force (N) on the cam: (T_cam, T_follower, Fx, Fy)."""
    (cx, cy), (nx, ny) = contact.centre, contact.normal
    A, Bf = geometry.cam_axis, breaker.follower.pivot
    fx, fy = force * nx, force * ny
    t_cam = -((cx - A[0]) * fy - (cy - A[1]) * fx)
    t_follower = (cx - Bf[0]) * fy - (cy - Bf[1]) * fx
    return t_cam, t_follower, -fx, -fy


def contact_force(penetration, rate, stiffness, exponent, restitution, impact_speed, min_impact_speed, ops=NumericOps):
    """Hertz force with Lankarani-Nikravesh damping (N); the impact speed (m/s) is the approach
    speed at the start of the contact, floored at ``min_impact_speed`` for resting contacts."""
    return hertz_contact_force(penetration, rate, stiffness, restitution, ops.max(impact_speed, min_impact_speed),
                               exponent, ops)


def contact_energy(penetration, stiffness, exponent):
    """Elastic energy (J) stored in a Hertz contact: K delta^(n+1) / (n+1)."""
    return stiffness * max(penetration, 0.0) ** (exponent + 1.0) / (exponent + 1.0)


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


def latch_force(torque, theta, arm, angle, ops=NumericOps):
    """Force (N, N) on the cam at the latch point that exerts ``torque`` (N m) about A:
    perpendicular to A->point, magnitude torque / arm."""
    a = theta + angle
    f = torque / arm
    return -f * ops.sin(a), f * ops.cos(a)


def push_rod_force(compression, rate, poles, ops=NumericOps):
    """Compressive force (N) of one push rod with its wipe spring: stiff (rod_stiffness) until
    the wipe spring's preload is reached, then the wipe spring's rate; structural damping.
    ``compression`` (m) is rod length at rest minus current length (negative: tension)."""
    s0 = poles.wipe_preload / poles.rod_stiffness
    elastic = ops.where(compression <= s0, poles.rod_stiffness * compression,
                        poles.wipe_preload + poles.wipe_rate * (compression - s0))
    return elastic + poles.rod_damping * rate


def push_rod_energy(compression, poles):
    """Elastic energy (J) of :func:`push_rod_force`'s spring part."""
    s0 = poles.wipe_preload / poles.rod_stiffness
    if compression <= s0:
        return 0.5 * poles.rod_stiffness * compression * compression
    x = compression - s0
    return 0.5 * poles.wipe_preload * s0 + poles.wipe_preload * x + 0.5 * poles.wipe_rate * x * x


def latch_torque(t, holding_torque, release_time, ops=NumericOps):
    """Torque (N m) of the closing latch on the cam: the holding torque until t = 0, then
    falling linearly to zero over ``release_time`` (s)."""
    return ops.where(t <= 0.0, holding_torque,
                     ops.where(t >= release_time, 0.0, holding_torque * (1.0 - t / ops.max(release_time, 1e-300))))


def pole_gaps(poles):
    return [poles.contact_gap + o for o in poles.gap_offsets]


def kinematic_follower_angle(theta, breaker, geometry: Geometry, near=None):
    """Follower angle (rad) that puts the roller centre exactly on the pitch curve at cam
    angle theta (fixed-point iteration; the pitch radius depends weakly on phi)."""
    f = breaker.follower
    phi = geometry.follower_angle if near is None else near
    for _ in range(100):
        cx, cy = roller_centre(phi, f)
        beta = math.atan2(cy - geometry.cam_axis[1], cx - geometry.cam_axis[0])
        rho = pitch_radius(theta - (beta - geometry.roller_direction), breaker.profile, breaker.roller_radius)[0]
        new = angle_on_circle(f.pivot, f.roller_arm, geometry.cam_axis, rho, phi)
        if abs(new - phi) < 1e-14:
            break
        phi = new
    return phi


def pressure_angle_curve(breaker, geometry: Geometry, thetas):
    """Pressure angle (rad) along the cam rotation with the roller on the pitch curve."""
    out, phi = [], geometry.follower_angle
    for th in thetas:
        phi = kinematic_follower_angle(th, breaker, geometry, phi)
        out.append(cam_roller_contact(th, 0.0, phi, 0.0, breaker, geometry).pressure_angle)
    return np.array(out)


def update_impact_speeds(impact, state, ops=NumericOps):
    """While contact k is open (penetration <= 0) its impact speed follows the approach speed
    (m/s); once it penetrates, the last open value is kept: the speed at impact."""
    for k, (penetration, rate) in enumerate(state):
        impact[k] = ops.where(penetration <= 0.0, ops.max(rate, 0.0), impact[k])


def follower_displacement(phi, follower, phi0):
    """Travel (m) of the output point F along the poles' closing direction (+y) from rest."""
    return np.array([output_point(p, follower)[1] for p in np.atleast_1d(phi)]) - output_point(phi0, follower)[1]


@dataclass
class InitialState:
    """Static rest held by the latch: follower angle (rad), pole travels (m) and the latch's
    holding torque on the cam (N m)."""

    follower_angle: float
    pole_travel: list
    holding_torque: float


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

    @classmethod
    def of_rig(cls, rig, spec):
        """For a rig (its breaker, cam, gravity) and a model spec (restitution, bellows force,
        whether ``contact_damping`` is on)."""
        return cls(rig.breaker, rig.cam, rig.gravity, spec.restitution, spec.bellows_force,
                   damped="contact_damping" in spec.effects)

    # -- cam-roller contact
    def roller_force(self, penetration, rate, impact_speed=0.0, ops=NumericOps):
        """Normal force (N) of the cam-roller contact at a penetration (m) and its rate (m/s)."""
        if self.roller_hunt_crossley:
            return hunt_crossley_force(penetration, rate, self.roller_stiffness, self.roller_exponent,
                                       self.roller_alpha, ops)
        return contact_force(penetration, rate, self.roller_stiffness, self.roller_exponent, self.restitution,
                             impact_speed, self.b.contact.min_impact_speed, ops)

    def roller_elastic(self, penetration):
        """Elastic part (N) of the cam-roller force."""
        return self.roller_stiffness * max(penetration, 0.0) ** self.roller_exponent

    def roller_energy(self, penetration):
        """Elastic energy (J) stored in the cam-roller contact."""
        return contact_energy(penetration, self.roller_stiffness, self.roller_exponent)

    def roller(self, theta, omega, phi, phi_dot, impact_speed=0.0, ops=NumericOps):
        """(CamRollerContact, normal force in N)."""
        c = cam_roller_contact(theta, omega, phi, phi_dot, self.b, self.geometry, ops)
        return c, self.roller_force(c.penetration, c.penetration_rate, impact_speed, ops)

    def roller_loads(self, theta, omega, phi, phi_dot, impact_speed=0.0, ops=NumericOps):
        """(torque on cam N m, torque on follower N m, force on cam Fx, Fy in N)."""
        c, force = self.roller(theta, omega, phi, phi_dot, impact_speed, ops)
        return cam_roller_loads(c, force, self.b, self.geometry)

    # -- push rods and poles
    def pin(self, z):
        return self.pin_rest[0], self.pin_rest[1] + z

    def rod(self, phi, phi_dot, z, z_dot, ops=NumericOps):
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

    def rod_loads(self, phi, phi_dot, z, z_dot, ops=NumericOps):
        """(force on the pole along closing N, torque on the follower N m)."""
        _, _, (ex, ey), force = self.rod(phi, phi_dot, z, z_dot, ops)
        fx, fy = output_point(phi, self.b.follower, ops)
        pv = self.b.follower.pivot
        # the rod pushes the pin along +e and F along -e
        return force * ey, (fx - pv[0]) * (-force * ey) - (fy - pv[1]) * (-force * ex)

    def pole_contact(self, i, z, z_dot, impact_speed=0.0, ops=NumericOps):
        """Force (N, opening direction) of pole i's fixed contact (Hertz point contact with
        Lankarani-Nikravesh damping: an impact contact)."""
        law = self.b.contact
        return contact_force(z - self.gaps[i], z_dot, law.pole_stiffness, law.exponent, self.restitution,
                             impact_speed, law.min_impact_speed, ops)

    def pole_elastic(self, penetration):
        law = self.b.contact
        return law.pole_stiffness * max(penetration, 0.0) ** law.exponent

    def pole_energy(self, penetration):
        law = self.b.contact
        return contact_energy(penetration, law.pole_stiffness, law.exponent)

    # -- opening spring
    def opening(self, phi, ops=NumericOps):
        """(tension N, torque on the follower N m)."""
        f = self.b.follower
        fx, fy = output_point(phi, f, ops)
        ox, oy = self.opening_anchor
        L = ops.sqrt((fx - ox) * (fx - ox) + (fy - oy) * (fy - oy))
        tension = self.b.opening_spring.stiffness * (L - self.opening_free_length)
        gx, gy = -tension * (fx - ox) / L, -tension * (fy - oy) / L
        return tension, (fx - f.pivot[0]) * gy - (fy - f.pivot[1]) * gx

    # -- rest state
    def rod_rest_compression(self):
        """Compression (m) of a rod holding its pole at rest: force m g - bellows."""
        force, p = -self.pole_load, self.b.poles
        s0 = p.wipe_preload / p.rod_stiffness
        return force / p.rod_stiffness if force <= p.wipe_preload else s0 + (force - p.wipe_preload) / p.wipe_rate

    def rest_pole_travel(self, phi):
        """Pole travel z (m) with the rod at its rest compression for follower angle phi."""
        fx, fy = output_point(phi, self.b.follower)
        length = self.b.poles.push_rod_length - self.rod_rest_compression()
        return fy + math.sqrt(length * length - (self.pin_rest[0] - fx) ** 2) - self.pin_rest[1]

    def follower_torque(self, theta, omega, phi, phi_dot, z, z_dot, impact_speed=0.0, ops=NumericOps):
        """Total torque (N m) on the follower and the roller's loads on the cam."""
        t_cam, t_fol, fx, fy = self.roller_loads(theta, omega, phi, phi_dot, impact_speed, ops)
        t_fol += self.opening(phi, ops)[1]
        for zi, zi_dot in zip(z, z_dot):
            t_fol += self.rod_loads(phi, phi_dot, zi, zi_dot, ops)[1]
        return t_fol, (t_cam, fx, fy)

    def initial_state(self, spring_pull, pin_weight_torque=0.0) -> InitialState:
        """Static rest at the cam's initial angle; ``spring_pull`` (N, N) is the closing
        springs' pull on pin B there, ``pin_weight_torque`` (N m) the weight of the springs'
        pin mass about A when the springs carry weight."""
        cam = self.cam
        theta = cam.initial_angle
        n = self.b.poles.count

        def torque(phi):
            z = [self.rest_pole_travel(phi)] * n
            return self.follower_torque(theta, 0.0, phi, 0.0, z, [0.0] * n)[0]

        phi_rest = self.geometry.follower_angle
        span = 1e-3
        lo, hi = phi_rest - span, phi_rest + span
        if torque(lo) * torque(hi) > 0:
            raise SimulationError("breaker: no static rest of the follower on the cam at the initial angle (the "
                                  "torques on it do not balance within 1 mrad of its geometric rest): check the "
                                  "opening spring's preload against the poles' bellows and push-rod forces, and the "
                                  "contact values (stiffness, exponent)")
        phi = brentq(torque, lo, hi, xtol=1e-15)
        z = [self.rest_pole_travel(phi)] * n
        _, (t_cam, _, _) = self.follower_torque(theta, 0.0, phi, 0.0, z, [0.0] * n)
        bx, by = cam_pin(theta, cam)
        fx, fy = spring_pull
        spring_and_weight = ((bx - cam.pivot[0]) * fy - (by - cam.pivot[1]) * fx
                             + cam_weight_torque(theta, cam, self.gravity) + pin_weight_torque)
        return InitialState(phi, z, -(spring_and_weight + t_cam))

    def latch_impact_speeds(self, impact, theta, omega, phi, phi_dot, z, z_dot, ops=NumericOps):
        """Update ``impact`` ([cam-roller, pole 1..n], m/s) from a state by
        :func:`update_impact_speeds`; returns the cam-roller contact at that state."""
        roller = cam_roller_contact(theta, omega, phi, phi_dot, self.b, self.geometry, ops)
        state = [(roller.penetration, roller.penetration_rate)]
        state += [(zi - gap, zi_dot) for zi, zi_dot, gap in zip(z, z_dot, self.gaps)]
        update_impact_speeds(impact, state, ops)
        return roller

    # -- the closing latch
    def latch(self, t, holding, ops=NumericOps):
        """The latch's torque (N m) on the cam at time t (s)."""
        return latch_torque(t, holding, self.b.latch_release_time, ops)

    def latch_loads(self, t, theta, holding, ops=NumericOps):
        """(torque N m, Fx N, Fy N) of the latch on the cam: the force at the latch point that
        exerts :meth:`latch`'s torque, so that it also loads the shaft's journal."""
        torque = self.latch(t, holding, ops)
        fx, fy = latch_force(torque, theta, self.latch_arm, self.latch_angle, ops)
        return torque, fx, fy

    def cam_loads(self, t, theta, omega, phi, phi_dot, holding, impact_speed=0.0, ops=NumericOps):
        """(torque about A N m, Fx N, Fy N): the roller's and the latch's loads on the cam, the
        breaker's share of the cam's applied torque and shaft reaction."""
        t_cam, _, fx, fy = self.roller_loads(theta, omega, phi, phi_dot, impact_speed, ops)
        t_latch, lx, ly = self.latch_loads(t, theta, holding, ops)
        return t_cam + t_latch, fx + lx, fy + ly


def massless_pull(cam, spring):
    """Pull (N, N) of massless closing springs on pin B at the cam's initial angle."""
    return massless_spring_force(*cam_pin(cam.initial_angle, cam), spring)

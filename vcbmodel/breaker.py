"""The whole breaker's closing (paper section 4, Fig. 11-12): data, laws and geometry.

Planar model with separate pole bodies (see README "The whole breaker"): the cam of the
cam-drop test (eq. 9-13, closing springs and shaft friction unchanged) drives an oscillating
roller follower pivoted on the frame at ``follower.pivot``; the follower's output point F
pushes ``poles.count`` insulating push rods, each through its wipe (contact-pressure) spring,
into a moving contact that slides on a straight vertical guide (the translational joint) and
closes on its fixed contact after ``contact_gap``. An opening spring pulls F down (it is
charged by the closing). The closing latch holds the cam at rest until it is released.

Everything here is a pure function of numbers (units in each docstring): the Exudyn builder
(:mod:`vcbmodel.breaker_model`) and the independent reference solve call the same laws.

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

from .contact import hertz_contact_force

TWO_PI = 2.0 * math.pi


@dataclass(frozen=True)
class CamProfile:
    """Closing cam (pitch curve above). Lengths in m, angles in rad of cam rotation."""

    base_radius: float  # base circle of the cam surface (m)
    lift: float  # rise of the roller centre (m)
    rise_start: float
    rise_end: float
    return_start: float
    return_end: float


@dataclass(frozen=True)
class Follower:
    """Oscillating roller follower (the paper's revolute joint B to ground)."""

    pivot: tuple  # (m) follower's fixed pivot
    inertia: float  # kg m^2 about the pivot (follower, main shaft and pole levers)
    roller_arm: float  # m, pivot to roller centre
    output_arm: float  # m, pivot to the output point F that drives the push rods
    output_angle: float  # rad, angle of pivot->F relative to pivot->roller
    rest_angle: float  # rad, about the angle of pivot->roller when open (picks the branch)


@dataclass(frozen=True)
class Poles:
    """The moving contacts, one body per pole, each on its own push rod and wipe spring."""

    count: int
    moving_mass: float  # kg per pole (moving contact, stem, terminal, push rod share)
    contact_gap: float  # m, open gap of the vacuum interrupter
    gap_offsets: tuple  # m per pole, assembly spread added to contact_gap
    push_rod_length: float  # m, F to the moving contact's pin at rest
    wipe_preload: float  # N, wipe spring preload against its stop
    wipe_rate: float  # N/m, wipe spring rate
    rod_stiffness: float  # N/m, push rod and stop below the preload
    rod_damping: float  # N s/m, structural damping along the rod
    bellows_force: float | None  # N, atmospheric pressure on the bellows (effect `bellows_force`)


@dataclass(frozen=True)
class OpeningSpring:
    """Tension spring pulling F straight down (towards open); charged while closing."""

    stiffness: float  # N/m
    preload: float  # N in the open position
    length: float  # m, anchor (below F) to F in the open position


@dataclass(frozen=True)
class ContactLaw:
    """Hertz contacts with Lankarani-Nikravesh damping (:mod:`vcbmodel.contact`)."""

    cam_roller_stiffness: float  # N/m^exponent
    pole_stiffness: float  # N/m^exponent, moving on fixed contact
    exponent: float  # Hertz exponent (1.5)
    restitution: float | None  # e of both contacts (effect `contact_damping`); None: not given
    min_impact_speed: float  # m/s, floor of the impact speed in the damping term


@dataclass(frozen=True)
class Breaker:
    profile: CamProfile
    roller_radius: float  # m
    follower: Follower
    poles: Poles
    opening_spring: OpeningSpring
    contact: ContactLaw
    latch_release_time: float  # s: the latch's holding torque falls linearly to 0 over it


# --- reading the rig's "breaker" section ------------------------------------------------------

def read_breaker(rd, data) -> Breaker:
    """Parse and check the ``breaker`` section of a ``vcb_closing`` rig (``rd``: rig reader)."""
    b = rd.section(data, "breaker")
    pre = "breaker."
    cp = rd.section(b, "cam_profile", pre)
    p = "breaker.cam_profile."
    profile = CamProfile(
        base_radius=rd.number(cp, "base_radius", p, positive=True), lift=rd.number(cp, "lift", p, positive=True),
        rise_start=rd.number(cp, "rise_start", p), rise_end=rd.number(cp, "rise_end", p),
        return_start=rd.number(cp, "return_start", p), return_end=rd.number(cp, "return_end", p))
    angles = (profile.rise_start, profile.rise_end, profile.return_start, profile.return_end)
    if not all(a < b_ for a, b_ in zip(angles, angles[1:])) or angles[3] > angles[0] + TWO_PI:
        rd.fail(p + "rise_start", "need rise_start < rise_end < return_start < return_end <= rise_start + 2 pi")
    fo = rd.section(b, "follower", pre)
    p = "breaker.follower."
    follower = Follower(pivot=rd.point(fo, "pivot", p), inertia=rd.number(fo, "inertia", p, positive=True),
                        roller_arm=rd.number(fo, "roller_arm", p, positive=True),
                        output_arm=rd.number(fo, "output_arm", p, positive=True),
                        output_angle=rd.number(fo, "output_angle", p, default=0.0),
                        rest_angle=rd.number(fo, "rest_angle", p))
    po = rd.section(b, "poles", pre)
    p = "breaker.poles."
    count = rd.number(po, "count", p, positive=True, default=3.0)
    if count != int(count):
        rd.fail(p + "count", "must be a whole number")
    offsets = po.get("gap_offsets", [0.0] * int(count))
    if (not isinstance(offsets, list) or len(offsets) != int(count)
            or any(isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x) for x in offsets)):
        rd.fail(p + "gap_offsets", f"must be a list of {int(count)} finite numbers (m), one per pole")
    poles = Poles(count=int(count), moving_mass=rd.number(po, "moving_mass", p, positive=True),
                  contact_gap=rd.number(po, "contact_gap", p, positive=True), gap_offsets=tuple(map(float, offsets)),
                  push_rod_length=rd.number(po, "push_rod_length", p, positive=True),
                  wipe_preload=rd.number(po, "wipe_preload", p, nonnegative=True),
                  wipe_rate=rd.number(po, "wipe_rate", p, positive=True),
                  rod_stiffness=rd.number(po, "rod_stiffness", p, positive=True),
                  rod_damping=rd.number(po, "rod_damping", p, nonnegative=True),
                  bellows_force=rd.number(po, "bellows_force", p, nonnegative=True) if "bellows_force" in po else None)
    if min(poles.contact_gap + o for o in poles.gap_offsets) <= 0:
        rd.fail(p + "gap_offsets", "make a pole's gap zero or negative")
    os_ = rd.section(b, "opening_spring", pre)
    p = "breaker.opening_spring."
    opening = OpeningSpring(stiffness=rd.number(os_, "stiffness", p, positive=True),
                            preload=rd.number(os_, "preload", p, nonnegative=True),
                            length=rd.number(os_, "length", p, positive=True))
    if opening.preload / opening.stiffness >= opening.length:
        rd.fail(p + "preload", "stretches the spring beyond twice its length: free length would be <= 0")
    co = rd.section(b, "contact", pre)
    p = "breaker.contact."
    contact = ContactLaw(cam_roller_stiffness=rd.number(co, "cam_roller_stiffness", p, positive=True),
                         pole_stiffness=rd.number(co, "pole_stiffness", p, positive=True),
                         exponent=rd.number(co, "exponent", p, positive=True, default=1.5),
                         restitution=rd.number(co, "restitution", p, positive=True) if "restitution" in co else None,
                         min_impact_speed=rd.number(co, "min_impact_speed", p, positive=True, default=0.05))
    if contact.restitution is not None and contact.restitution > 1.0:
        rd.fail(p + "restitution", f"must be in (0, 1], got {contact.restitution:g}")
    latch = b.get("latch", {})
    if not isinstance(latch, dict):
        rd.fail(pre + "latch", "must be an object")
    release = rd.number(latch, "release_time", "breaker.latch.", nonnegative=True, default=0.0)
    return Breaker(profile, rd.number(b, "roller_radius", pre, positive=True), follower, poles, opening, contact,
                   release)


# --- cam profile -------------------------------------------------------------------------------

def polynomial_rise(x):
    """4-5-6-7 rise s(x) and ds/dx for x in [0, 1] (clipped outside); s(0)=0, s(1)=1."""
    x = min(max(x, 0.0), 1.0)
    x3 = x * x * x
    s = x3 * x * (35.0 + x * (-84.0 + x * (70.0 - 20.0 * x)))
    ds = x3 * (140.0 + x * (-420.0 + x * (420.0 - 140.0 * x)))
    return s, ds


def pitch_radius(u, profile: CamProfile, roller_radius):
    """Distance rho (m) of the roller centre from the cam axis on the pitch curve, and
    d rho / d u (m/rad), at cam rotation u (rad) relative to the roller."""
    p = profile
    u = p.rise_start + (u - p.rise_start) % TWO_PI
    base = p.base_radius + roller_radius
    if u <= p.rise_end:
        w = p.rise_end - p.rise_start
        s, ds = polynomial_rise((u - p.rise_start) / w)
        return base + p.lift * s, p.lift * ds / w
    if u < p.return_start:
        return base + p.lift, 0.0
    w = p.return_end - p.return_start
    s, ds = polynomial_rise((u - p.return_start) / w)
    return base + p.lift * (1.0 - s), -p.lift * ds / w


# --- follower kinematics -----------------------------------------------------------------------

def follower_point(phi, follower: Follower, arm, angle=0.0):
    """Point on the follower at ``arm`` (m) and ``angle`` (rad) from the roller direction."""
    return (follower.pivot[0] + arm * math.cos(phi + angle), follower.pivot[1] + arm * math.sin(phi + angle))


def roller_centre(phi, follower: Follower):
    return follower_point(phi, follower, follower.roller_arm)


def output_point(phi, follower: Follower):
    """The follower's output point F (m) driving the push rods."""
    return follower_point(phi, follower, follower.output_arm, follower.output_angle)


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


def rest_geometry(breaker: Breaker, cam_axis) -> Geometry:
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


def cam_roller_contact(theta, omega, phi, phi_dot, breaker: Breaker, geometry: Geometry) -> CamRollerContact:
    """Normal penetration of the roller into the cam (cam angle theta, follower angle phi, rad).

    With rho_C = |C - A| and beta the direction of C from A, the roller sees the cam
    rotation u = theta - (beta - beta_rest); the pitch curve's outward normal is
    n = (e_r - q e_beta) / sqrt(1 + q^2) with q = (d rho / d beta) / rho = -(d rho/du) / rho,
    and the penetration (rho(u) - rho_C) cos(gamma), cos(gamma) = 1 / sqrt(1 + q^2), exact to
    first order in the penetration.
    """
    f, A = breaker.follower, geometry.cam_axis
    cx, cy = roller_centre(phi, f)
    vx, vy = -phi_dot * (cy - f.pivot[1]), phi_dot * (cx - f.pivot[0])
    dx, dy = cx - A[0], cy - A[1]
    rho_c = math.hypot(dx, dy)
    erx, ery = dx / rho_c, dy / rho_c
    ebx, eby = -ery, erx
    beta = math.atan2(dy, dx)
    u = theta - (beta - geometry.roller_direction)
    rho, drho_du = pitch_radius(u, breaker.profile, breaker.roller_radius)
    q = -drho_du / rho
    cos_g = 1.0 / math.sqrt(1.0 + q * q)
    nx, ny = (erx - q * ebx) * cos_g, (ery - q * eby) * cos_g
    beta_dot = (ebx * vx + eby * vy) / rho_c
    rate = (drho_du * (omega - beta_dot) - (erx * vx + ery * vy)) * cos_g
    # pressure angle: normal vs the roller centre's direction of motion (perpendicular to the arm)
    tx, ty = -(cy - f.pivot[1]) / f.roller_arm, (cx - f.pivot[0]) / f.roller_arm
    pressure = math.acos(min(1.0, abs(nx * tx + ny * ty)))
    return CamRollerContact((rho - rho_c) * cos_g, rate, (nx, ny), (cx, cy), pressure)


def cam_roller_loads(contact: CamRollerContact, force, breaker: Breaker, geometry: Geometry):
    """Torques (N m) of a normal contact force (N, pushing the roller out) on the cam about A
    and on the follower about its pivot, and the force (N) on the cam: (T_cam, T_follower, Fx, Fy)."""
    (cx, cy), (nx, ny) = contact.centre, contact.normal
    A, Bf = geometry.cam_axis, breaker.follower.pivot
    fx, fy = force * nx, force * ny
    t_cam = -((cx - A[0]) * fy - (cy - A[1]) * fx)
    t_follower = (cx - Bf[0]) * fy - (cy - Bf[1]) * fx
    return t_cam, t_follower, -fx, -fy


def contact_force(penetration, rate, stiffness, exponent, restitution, impact_speed, min_impact_speed):
    """Hertz force with Lankarani-Nikravesh damping (N); the impact speed (m/s) is the approach
    speed at the start of the contact, floored at ``min_impact_speed`` for resting contacts."""
    return hertz_contact_force(penetration, rate, stiffness, restitution, max(impact_speed, min_impact_speed),
                               exponent)


def contact_energy(penetration, stiffness, exponent):
    """Elastic energy (J) stored in a Hertz contact: K delta^(n+1) / (n+1)."""
    return stiffness * max(penetration, 0.0) ** (exponent + 1.0) / (exponent + 1.0)


def push_rod_force(compression, rate, poles: Poles):
    """Compressive force (N) of one push rod with its wipe spring: stiff (rod_stiffness) until
    the wipe spring's preload is reached, then the wipe spring's rate; structural damping.
    ``compression`` (m) is rod length at rest minus current length (negative: tension)."""
    s0 = poles.wipe_preload / poles.rod_stiffness
    if compression <= s0:
        elastic = poles.rod_stiffness * compression
    else:
        elastic = poles.wipe_preload + poles.wipe_rate * (compression - s0)
    return elastic + poles.rod_damping * rate


def push_rod_energy(compression, poles: Poles):
    """Elastic energy (J) of :func:`push_rod_force`'s spring part."""
    s0 = poles.wipe_preload / poles.rod_stiffness
    if compression <= s0:
        return 0.5 * poles.rod_stiffness * compression * compression
    x = compression - s0
    return 0.5 * poles.wipe_preload * s0 + poles.wipe_preload * x + 0.5 * poles.wipe_rate * x * x


def latch_torque(t, holding_torque, release_time):
    """Torque (N m) of the closing latch on the cam: the holding torque until t = 0, then
    falling linearly to zero over ``release_time`` (s)."""
    if t <= 0.0:
        return holding_torque
    if t >= release_time:
        return 0.0
    return holding_torque * (1.0 - t / release_time)


def pole_gaps(poles: Poles):
    return [poles.contact_gap + o for o in poles.gap_offsets]


def kinematic_follower_angle(theta, breaker: Breaker, geometry: Geometry, near=None):
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


def pressure_angle_curve(breaker: Breaker, geometry: Geometry, thetas):
    """Pressure angle (rad) along the cam rotation with the roller on the pitch curve."""
    out, phi = [], geometry.follower_angle
    for th in thetas:
        phi = kinematic_follower_angle(th, breaker, geometry, phi)
        out.append(cam_roller_contact(th, 0.0, phi, 0.0, breaker, geometry).pressure_angle)
    return np.array(out)

"""The cam and its roller follower (paper section 4, Fig. 11): the cam profile, the follower's
kinematics, the rest geometry and the cam-roller contact's geometry, as pure functions.

Cam profile: the roller centre runs on the pitch curve ``rho(u) = base_radius + roller_radius
+ lift * s(u)`` about the cam axis A, where u is the cam's rotation measured so that the
roller, on its rest line, sees ``u = theta`` (the cam angle of A->B). ``s`` is the 4-5-6-7
polynomial rise ``35x^4 - 84x^5 + 70x^6 - 20x^7`` (zero speed, acceleration at both ends),
a dwell at full lift and the mirrored return. Units: lengths m, angles rad, speeds m/s and
rad/s. Functions with an ``ops`` argument serve floats, arrays, and the compiled path alike.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from .friction import ArrayOps, NumericOps
from .types import Ops, Scalar

if TYPE_CHECKING:
    from scipy.interpolate import CubicSpline

TWO_PI = 2.0 * math.pi


# --- cam profile -------------------------------------------------------------------------------

def polynomial_rise(x: Scalar, ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
    """4-5-6-7 rise s(x) and ds/dx for x in [0, 1] (clipped outside); s(0)=0, s(1)=1."""
    x = ops.min(ops.max(x, 0.0), 1.0)
    x3 = x * x * x
    s = x3 * x * (35.0 + x * (-84.0 + x * (70.0 - 20.0 * x)))
    ds = x3 * (140.0 + x * (-420.0 + x * (420.0 - 140.0 * x)))
    return s, ds


def pitch_radius(u: Scalar, profile, roller_radius: Scalar, ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
    """Distance rho (m) of the roller centre from the cam axis on the pitch curve, and
    d rho / d u (m/rad), at cam rotation u (rad) relative to the roller: the rise, the dwell at
    full lift, the return and the base circle (each piece evaluated, the one that applies chosen);
    or, for a profile given by points, its table (:func:`table_radius`)."""
    p = profile
    if p.table:
        return table_radius(u, p.table, ops)
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


# --- a cam given by points ---------------------------------------------------------------------

#: Samples per turn of the table of a cam given by points (0.25 deg; cubic Hermite between them:
#: within 1e-9 m of the spline for a profile whose lift changes over a few degrees or more)
PROFILE_SAMPLES = 1440
#: Largest pressure angle a roller follower is driven through (rad): above it the cam jams the
#: roller rather than lifting it (the usual design limit is 30 deg)
MAX_PRESSURE_ANGLE = math.radians(45.0)


def profile_spline(angles: ArrayLike, radii: ArrayLike) -> CubicSpline:
    """The periodic cubic spline rho(u) (m) through points of the pitch curve: cam angles (rad,
    increasing, within one turn) and the roller centre's distance from the cam axis (m)."""
    from scipy.interpolate import CubicSpline

    a = np.asarray(angles, float)
    r = np.asarray(radii, float)
    return CubicSpline(np.append(a, a[0] + TWO_PI), np.append(r, r[0]), bc_type="periodic")


def profile_table(spline: CubicSpline, samples: int = PROFILE_SAMPLES) -> tuple[float, ...]:
    """(rho_0, drho_0, rho_1, drho_1, ...): the spline's value (m) and slope (m/rad) at ``samples``
    angles k 2 pi / samples, the table :func:`table_radius` reads."""
    start = spline.x[0]
    u = start + (np.arange(samples) * TWO_PI / samples - start) % TWO_PI
    return tuple(np.column_stack([spline(u), spline(u, 1)]).ravel().tolist())


def table_radius(u: Scalar, table: Sequence[float], ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
    """Pitch radius (m) and its slope (m/rad) at cam rotation u (rad) from a profile table
    (:func:`profile_table`): cubic Hermite between the samples."""
    n = len(table) // 2
    h = TWO_PI / n
    x = u - TWO_PI * ops.floor(u / TWO_PI)
    s = x / h
    i = ops.floor(s)
    t = s - i
    y0, d0 = ops.take(table, 2.0 * i), ops.take(table, 2.0 * i + 1.0)
    y1, d1 = ops.take(table, 2.0 * i + 2.0), ops.take(table, 2.0 * i + 3.0)
    t2 = t * t
    t3 = t2 * t
    rho = (2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * h * d0 + (3 * t2 - 2 * t3) * y1 + (t3 - t2) * h * d1
    slope = ((6 * t2 - 6 * t) * y0 + (3 * t2 - 4 * t + 1) * h * d0 + (6 * t - 6 * t2) * y1
             + (3 * t2 - 2 * t) * h * d1) / h
    return rho, slope


def pitch_curvature_radius(spline: CubicSpline, u: float | np.ndarray) -> float | np.ndarray:
    """Signed radius of curvature (m) of the pitch curve rho(u) at u: positive where it is convex
    (centre of curvature towards the cam axis): (rho^2 + rho'^2)^(3/2) / (rho^2 + 2 rho'^2 - rho rho'')."""
    r, r1, r2 = spline(u), spline(u, 1), spline(u, 2)
    return (r * r + r1 * r1) ** 1.5 / (r * r + 2 * r1 * r1 - r * r2)


def undercut(spline: CubicSpline, roller_radius: float, samples: int = PROFILE_SAMPLES * 4) -> tuple[float, float] | None:
    """Where the roller cannot follow the pitch curve: (angle in rad, convex radius of curvature in
    m) of the sharpest convex point if it is below the roller radius (the cam surface, the pitch
    curve offset by the roller radius, would loop: undercut), else None."""
    u = spline.x[0] + np.arange(samples) * TWO_PI / samples
    radius = pitch_curvature_radius(spline, u)
    convex = radius > 0
    if not np.any(convex):
        return None
    k = int(np.argmin(np.where(convex, radius, np.inf)))
    return (float(u[k]), float(radius[k])) if radius[k] <= roller_radius else None


# --- follower kinematics -----------------------------------------------------------------------

def follower_point(phi: Scalar, follower, arm: Scalar, angle: Scalar = 0.0, ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
    """Point on the follower at ``arm`` (m) and ``angle`` (rad) from the roller direction."""
    return (follower.pivot[0] + arm * ops.cos(phi + angle), follower.pivot[1] + arm * ops.sin(phi + angle))


def roller_centre(phi: Scalar, follower, ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
    return follower_point(phi, follower, follower.roller_arm, 0.0, ops)


def output_point(phi: Scalar, follower, ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
    """The follower's output point F (m) driving the push rods."""
    return follower_point(phi, follower, follower.output_arm, follower.output_angle, ops)


def angle_on_circle(pivot: tuple[float, float], arm: float, centre: tuple[float, float], radius: float, near: float) -> float:
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


def follower_displacement(phi: float | np.ndarray, follower, phi0: float) -> np.ndarray:
    """Travel (m) of the output point F along the poles' closing direction (+y) from rest (the samples of
    ``phi`` at once: :class:`~.friction.ArrayOps`, elementwise the same arithmetic as one at a time)."""
    return np.asarray(output_point(np.atleast_1d(np.asarray(phi, float)), follower, ArrayOps)[1], float) \
        - output_point(phi0, follower)[1]


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

"""The independent breaker reference's roller-to-profile distance: the cam-roller penetration.

Holds :func:`roller_contact`, the penetration of the roller into the cam, its rate and the
contact normal, in two readings:

* ``exact`` (the reference's own): the signed minimum distance from the roller centre C to the
  cam's pitch curve (the locus of roller centres at zero penetration), found by Newton's method
  on the stationarity condition (P - C) . dP/dbeta = 0 (:func:`closest_pitch_angle`); the force
  acts along the pitch curve's normal at the closest point, and the rate is the relative
  velocity of the closest point and C along that normal.
* ``first_order`` (the model's formula, written again here): the pitch curve's normal offset at
  the roller's own polar angle, (rho(u) - rho_C) cos(gamma), and its rate
  (:func:`first_order_rate`), to measure what the first-order offset costs.

Shares with the model the cam profile and the planar layout (:mod:`.breaker_geometry`), no code.

Units: SI. Lengths in m, speeds in m/s, angles in rad, angular velocities in rad/s.
"""
from __future__ import annotations

import math

from ..errors import SimulationError
from .breaker_geometry import Geometry

DISTANCES = ("exact", "first_order")


def closest_pitch_angle(geo: Geometry, theta: float, C: tuple[float, float]) -> float:
    """Polar angle beta (rad, from A) of the pitch curve's point closest to C at cam angle theta:
    Newton on (P - C) . dP/dbeta = 0 from C's own polar angle, steps clipped to 0.05 rad. Where
    that start lies on a stretch that Newton leaves (a trial state of the solver far off the
    cam, or near a flank's turning point), Newton starts again from the closest of 720 points
    around the whole pitch curve; a point that still does not converge is an error."""
    start = math.atan2(C[1] - geo.A[1], C[0] - geo.A[0])
    beta, step = _newton_closest(geo, theta, C, start)
    if abs(step) > 1e-11:
        samples = [start + 2.0 * math.pi * k / 720 for k in range(720)]
        nearest = min(samples, key=lambda b: _distance_squared(geo, theta, C, b))
        beta, step = _newton_closest(geo, theta, C, nearest)
    if abs(step) > 1e-11:
        raise SimulationError("independent breaker reference: the closest point on the cam did not "
                              f"converge (theta = {theta:.6g} rad, last step {step:.3g} rad)")
    return beta


def _distance_squared(geo: Geometry, theta: float, C: tuple[float, float], beta: float) -> float:
    """Squared distance (m^2) from C to the pitch curve's point at polar angle beta."""
    P = geo.pitch_point(beta, theta)[0]
    return (P[0] - C[0]) ** 2 + (P[1] - C[1]) ** 2


def _newton_closest(geo: Geometry, theta: float, C: tuple[float, float], beta: float) -> tuple[float, float]:
    """Newton on (P - C) . dP/dbeta = 0 from beta (steps clipped to 0.05 rad): (beta, last step)."""
    step = 0.0
    for _ in range(60):
        P, dP, ddP, rho, rb = geo.pitch_point(beta, theta)
        dx, dy = P[0] - C[0], P[1] - C[1]
        fval = dx * dP[0] + dy * dP[1]
        fder = dP[0] ** 2 + dP[1] ** 2 + dx * ddP[0] + dy * ddP[1]
        step = max(-0.05, min(0.05, fval / fder))
        beta -= step
        if abs(step) < 1e-14:
            break
    return beta, step


def roller_contact(geo: Geometry, theta: float, omega: float, phi: float, phid: float, distance: str = "exact"):
    """(penetration m, rate m/s, outward normal, roller centre C) at cam angle theta (rad), shaft
    speed omega (rad/s), follower angle phi (rad) and speed phid (rad/s)."""
    C = geo.roller_centre(phi)
    vC = (-phid * (C[1] - geo.P[1]), phid * (C[0] - geo.P[0]))
    if distance == "exact":
        beta = closest_pitch_angle(geo, theta, C)
    else:
        beta = math.atan2(C[1] - geo.A[1], C[0] - geo.A[0])
    P, dP, _, rho, rb = geo.pitch_point(beta, theta)
    c, s = math.cos(beta), math.sin(beta)
    nx, ny = rho * c + rb * s, rho * s - rb * c  # rho e_r - rho_beta e_beta
    norm = math.hypot(nx, ny)
    nx, ny = nx / norm, ny / norm
    if distance == "exact":
        pen = (P[0] - C[0]) * nx + (P[1] - C[1]) * ny
    else:  # the model's first-order offset along the normal at the roller's own polar angle
        pen = (rho - math.hypot(C[0] - geo.A[0], C[1] - geo.A[1])) * rho / norm
    vP = (-omega * (P[1] - geo.A[1]), omega * (P[0] - geo.A[0]))
    rate = (vP[0] - vC[0]) * nx + (vP[1] - vC[1]) * ny
    if distance == "first_order":  # the rate of the first-order penetration
        rate = first_order_rate(geo, theta, omega, C, vC)
    return pen, rate, (nx, ny), C


def first_order_rate(geo: Geometry, theta: float, omega: float, C: tuple[float, float],
                     vC: tuple[float, float]) -> float:
    """Rate (m/s) of the first-order penetration (rho(u) - rho_C) cos(gamma), roller centre C
    moving at vC (m/s): (rho_u (omega - beta') - rho_C') cos(gamma)."""
    dx, dy = C[0] - geo.A[0], C[1] - geo.A[1]
    rho_c = math.hypot(dx, dy)
    er = (dx / rho_c, dy / rho_c)
    eb = (-er[1], er[0])
    beta = math.atan2(dy, dx)
    rho, drho_du, _ = geo.profile(theta - (beta - geo.beta_rest))
    beta_dot = (eb[0] * vC[0] + eb[1] * vC[1]) / rho_c
    cos_g = 1.0 / math.sqrt(1.0 + (drho_du / rho) ** 2)
    return (drho_du * (omega - beta_dot) - (er[0] * vC[0] + er[1] * vC[1])) * cos_g

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
    Newton on (P - C) . dP/dbeta = 0 from C's own polar angle, steps clipped to 0.05 rad."""
    beta = math.atan2(C[1] - geo.A[1], C[0] - geo.A[0])
    for _ in range(60):  # Newton on (P - C) . dP/dbeta = 0
        P, dP, ddP, rho, rb = geo.pitch_point(beta, theta)
        dx, dy = P[0] - C[0], P[1] - C[1]
        fval = dx * dP[0] + dy * dP[1]
        fder = dP[0] ** 2 + dP[1] ** 2 + dx * ddP[0] + dy * ddP[1]
        step = max(-0.05, min(0.05, fval / fder))
        beta -= step
        if abs(step) < 1e-14:
            break
    else:
        if abs(step) > 1e-11:
            raise SimulationError("independent breaker reference: the closest point on the cam did not "
                                  f"converge (theta = {theta:.6g} rad, last step {step:.3g} rad)")
    return beta


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

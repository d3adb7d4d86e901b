"""Contact laws of the whole-breaker model (paper section 4), as pure functions.

Elastic part (force ``K delta^n`` for penetration ``delta > 0``, m):

- **Hertz point contact**, n = 1.5 (spheres, crowned rollers; the paper's Lankarani-Nikravesh
  model uses it for every contact). K in N/m^1.5.
- **Line contact** of a cylindrical roller on a cam or raceway: the Hertz 2-D solution has no
  closed force-approach law (the approach depends on the bodies' size through a logarithm);
  the standard engineering law is Palmgren's for steel rollers on steel raceways,
  ``delta = 3.84e-5 Q^0.9 / l^0.8`` (mm, N, l the roller's effective length in mm; Palmgren,
  *Ball and Roller Bearing Engineering*, 3rd ed., 1959; Harris & Kotzalas, *Rolling Bearing
  Analysis*, 5th ed., 2007, vol. 1, ch. 6), i.e. ``Q = K_L delta^(10/9)`` with K_L from
  :func:`palmgren_line_stiffness`. :func:`johnson_line_approach` is Johnson's 2-D formula for
  two elastic cylinders (*Contact Mechanics*, 1985, sec. 5.6), the check of Palmgren's law for a
  given geometry (tested: Johnson's approach is 8-13 % larger over 1-40 kN for the reference
  roller on the base circle).

Damping part (both clipped so that the contact never pulls):

- **Lankarani-Nikravesh** (J. Mech. Des. 112, 1990), for impacts:
  ``F = K delta^n (1 + 3 (1 - e^2) / 4 * delta_dot / v_impact)``, e the coefficient of
  restitution, v_impact the approach speed at first contact. The dissipated energy matches e
  for e near 1 (measured here: rebound ratio 0.954 / 0.913 / 0.847 for e = 0.95 / 0.9 / 0.8). It
  needs the impact speed, which a persistent (preloaded) contact does not have: a floor speed
  then sets an arbitrary, large dashpot.
- **Hunt-Crossley with a fixed damping factor** (Hunt & Crossley, J. Appl. Mech. 42, 1975;
  Marhefka & Orin, IEEE Trans. SMC-A 29, 1999): ``F = K delta^n (1 + alpha delta_dot)`` with
  alpha in s/m a property of the contact, not of an impact, so it serves persistent contacts
  and new impacts alike; an impact at speed v then rebounds with e = 1 - 2/3 alpha v to first
  order (measured here: 0.9375 for alpha v = 0.1, 0.862 for 0.24, for any stiffness, exponent
  and mass). Hunt and Crossley's and Goldsmith's data give alpha = 0.08 to 0.32 s/m for steel,
  bronze and ivory.
"""
from __future__ import annotations

import math
from collections.abc import Iterable

from .friction import NumericOps
from .types import Ops, Scalar

#: Exponent of the line-contact law (Palmgren): Q ~ delta^(10/9).
LINE_EXPONENT = 10.0 / 9.0
#: Palmgren's constant: delta (mm) = PALMGREN_COMPLIANCE * Q(N)^0.9 / l(mm)^0.8, steel on steel.
PALMGREN_COMPLIANCE = 3.84e-5
#: Contact laws of the cam-roller contact (rig field ``breaker.contact.cam_roller_law``).
CAM_ROLLER_LAWS = ("hertz_point", "line")
#: Damping laws of the cam-roller contact (rig field ``breaker.contact.cam_roller_damping``).
DAMPING_LAWS = ("lankarani_nikravesh", "hunt_crossley")


def hertz_contact_force(penetration: Scalar, penetration_rate: Scalar, stiffness: Scalar, restitution: Scalar, impact_velocity: Scalar,
                        exponent: Scalar = 1.5, ops: Ops = NumericOps) -> Scalar:
    """Normal contact force (N, pushing the bodies apart) of the Lankarani-Nikravesh law."""
    v0 = ops.max(ops.abs(impact_velocity), 1e-9)
    damping = 3.0 * (1.0 - restitution * restitution) / 4.0 * penetration_rate / v0
    elastic = stiffness * ops.pow(ops.max(penetration, 0.0), exponent)
    return ops.where(penetration <= 0.0, 0.0, ops.max(0.0, elastic * (1.0 + damping)))


def hunt_crossley_force(penetration: Scalar, penetration_rate: Scalar, stiffness: Scalar, exponent: Scalar, damping_factor: Scalar,
                        ops: Ops = NumericOps) -> Scalar:
    """Normal contact force (N) of the Hunt-Crossley law with a fixed damping factor alpha (s/m)."""
    elastic = stiffness * ops.pow(ops.max(penetration, 0.0), exponent)
    return ops.where(penetration <= 0.0, 0.0, ops.max(0.0, elastic * (1.0 + damping_factor * penetration_rate)))


def palmgren_line_stiffness(length: float) -> float:
    """K_L (N/m^(10/9)) of a steel roller of effective contact length ``length`` (m) on steel:
    Palmgren's delta = 3.84e-5 Q^0.9 / l^0.8 (mm, N) solved for Q and converted to SI."""
    length_mm = 1000.0 * length
    # Q = (delta_mm l^0.8 / c)^(1/0.9), delta_mm = 1000 delta
    return (1000.0 * length_mm**0.8 / PALMGREN_COMPLIANCE) ** (1.0 / 0.9)


def johnson_line_approach(force: float, length: float, radius_1: float, radius_2: float, youngs_modulus: float = 206e9,
                          poisson: float = 0.3) -> float:
    """Approach (m) of two parallel elastic cylinders of the same material pressed together by
    ``force`` (N) over ``length`` (m): Johnson (1985) sec. 5.6,
    delta = P (1 - nu^2) / (pi E) (2 ln(4 R1 / a) - 1 + 2 ln(4 R2 / a) - 1), P = force / length,
    a = sqrt(4 P R / (pi E*)) the contact half-width, 1/R = 1/R1 + 1/R2, E* = E / (2 (1 - nu^2))."""
    p = force / length
    r = 1.0 / (1.0 / radius_1 + 1.0 / radius_2)
    e_star = youngs_modulus / (2.0 * (1.0 - poisson**2))
    a = math.sqrt(4.0 * p * r / (math.pi * e_star))
    return p * (1.0 - poisson**2) / (math.pi * youngs_modulus) * (
        2.0 * math.log(4.0 * radius_1 / a) - 1.0 + 2.0 * math.log(4.0 * radius_2 / a) - 1.0)


# --- a contact's force and energy at a state, and its impact speed ------------------------------------

def contact_force(penetration: Scalar, rate: Scalar, stiffness: Scalar, exponent: Scalar, restitution: Scalar, impact_speed: Scalar,
                  min_impact_speed: Scalar, ops: Ops = NumericOps) -> Scalar:
    """Hertz force with Lankarani-Nikravesh damping (N); the impact speed (m/s) is the approach
    speed at the start of the contact, floored at ``min_impact_speed`` for resting contacts."""
    return hertz_contact_force(penetration, rate, stiffness, restitution, ops.max(impact_speed, min_impact_speed),
                               exponent, ops)


def contact_energy(penetration: Scalar, stiffness: float, exponent: float, ops: Ops = NumericOps) -> Scalar:
    """Elastic energy (J) stored in a Hertz contact: K delta^(n+1) / (n+1)."""
    return stiffness * ops.max(penetration, 0.0) ** (exponent + 1.0) / (exponent + 1.0)


def update_impact_speeds(impact: list, state: Iterable[tuple[Scalar, Scalar]], ops: Ops = NumericOps) -> None:
    """While contact k is open (penetration <= 0) its impact speed follows the approach speed
    (m/s); once it penetrates, the last open value is kept: the speed at impact."""
    for k, (penetration, rate) in enumerate(state):
        impact[k] = ops.where(penetration <= 0.0, ops.max(rate, 0.0), impact[k])

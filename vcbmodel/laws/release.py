"""The closing and opening releases: a shunt coil, its armature and the latch it trips.

IEC 62271-100 times a closing from energising the closing release to the contacts' touch, and an
opening from energising the opening release to the contacts' parting; the mechanism starts only
when the release's armature has tripped its latch. The release here (rig sections
``breaker.closing_release``, ``breaker.opening_release``; :class:`Release`):

- the coil, resistance R (ohm) and inductance L (H), switched onto its supply U (V) at t = 0:
  i(t) = (U / R) (1 - exp(-t R / L)) (the armature's motion changes L little before it trips:
  its back-EMF is left out);
- its armature (mass m, kg) pulled by k i^2 (N; k = dL/dx / 2 in N/A^2, taken constant over the
  short stroke) against ``load`` (N: its return spring and the latch's friction), moving once the
  pull exceeds the load; it trips the latch when it has travelled ``stroke`` (m):
  m x'' = max(k i^2 - load, 0) (:func:`release_delay`, integrated with RK4).

The release's delay scatters with its supply voltage and its coil's temperature: IEC 62271-1
(sec. 5.8) requires a shunt closing release to operate between 85 % and 110 % of its rated supply
voltage, a shunt opening release between 70 % (DC) and 110 %; the coil's copper resistance rises
0.393 %/K (``resistance_range``: the rig's coldest and hottest coil as factors on R).
:func:`delay_scatter` gives the delay at the fastest (highest voltage, coldest coil) and slowest
(lowest voltage, hottest coil) corners.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .friction import NumericOps
from .types import Ops, Scalar

#: Integration step (s) of the armature's motion: the coils' time constants are milliseconds and
#: the strokes a few: 2 us resolves the delay to well under 0.01 ms (halving it changes the
#: reference release's delay by less than 1e-6 s, tests/laws/test_release.py)
RELEASE_STEP = 2e-6
#: Longest delay integrated (s): a release that has not tripped by then never will at that voltage
RELEASE_LONGEST = 1.0


@dataclass(frozen=True)
class Release:
    """A shunt release (rig sections ``breaker.closing_release``, ``breaker.opening_release``):
    ``voltage`` (V, rated supply), ``resistance`` (ohm, the coil's at 20 degC), ``inductance`` (H),
    ``force_constant`` (N/A^2, the armature's pull per ampere squared), ``armature_mass`` (kg),
    ``stroke`` (m, travel to trip the latch), ``load`` (N, the return spring and the latch's
    friction), ``voltage_range`` (lowest, highest supply as fractions of rated) and
    ``resistance_range`` (coldest, hottest coil as factors on ``resistance``)."""

    voltage: float  # V
    resistance: float  # ohm
    inductance: float  # H
    force_constant: float  # N/A^2
    armature_mass: float  # kg
    stroke: float  # m
    load: float  # N
    voltage_range: tuple  # (-, -)
    resistance_range: tuple  # (-, -)


def coil_current(t: Scalar, voltage: Scalar, resistance: Scalar, inductance: Scalar, ops: Ops = NumericOps) -> Scalar:
    """Current (A) of a coil (``resistance`` ohm, ``inductance`` H) ``t`` s after it is switched
    onto ``voltage`` V: (U / R) (1 - exp(-t R / L)); 0 before."""
    rise = 1.0 - ops.pow(math.e, -ops.max(t, 0.0) * resistance / inductance)
    return ops.where(t < 0.0, 0.0, voltage / resistance * rise)


def armature_acceleration(t: Scalar, release: Release, voltage: Scalar, resistance: Scalar, ops: Ops = NumericOps) -> Scalar:
    """The armature's acceleration (m/s^2) at ``t`` (s): max(k i^2 - load, 0) / m, with the coil's
    current at ``voltage`` (V) and ``resistance`` (ohm)."""
    i = coil_current(t, voltage, resistance, release.inductance, ops)
    return ops.max(release.force_constant * i * i - release.load, 0.0) / release.armature_mass


def picks_up(release: Release, voltage_factor: float, resistance_factor: float) -> bool:
    """Whether the armature's full pull k (U / R)^2 exceeds its load at this supply (a fraction of
    rated) and coil resistance (a factor on R): if not, it never moves."""
    current = release.voltage * voltage_factor / (release.resistance * resistance_factor)
    return release.force_constant * current * current > release.load


def release_delay(release: Release, voltage_factor: float = 1.0, resistance_factor: float = 1.0) -> float | None:
    """Time (s) from energising the release to its armature tripping the latch (travel ``stroke``),
    at ``voltage_factor`` x rated supply and ``resistance_factor`` x the coil's resistance; None if
    it never trips (:func:`picks_up`) or not within RELEASE_LONGEST. RK4 on (x, x') with step
    RELEASE_STEP, the crossing of ``stroke`` interpolated."""
    if not picks_up(release, voltage_factor, resistance_factor):
        return None
    u, r, h = release.voltage * voltage_factor, release.resistance * resistance_factor, RELEASE_STEP
    t, x, v = 0.0, 0.0, 0.0
    while t < RELEASE_LONGEST:
        a1 = armature_acceleration(t, release, u, r)
        a2 = armature_acceleration(t + h / 2, release, u, r)
        a4 = armature_acceleration(t + h, release, u, r)
        x_new = x + h * v + h * h / 6.0 * (a1 + 2.0 * a2)
        v_new = v + h / 6.0 * (a1 + 4.0 * a2 + a4)
        if x_new >= release.stroke:
            return t + h * (release.stroke - x) / (x_new - x)
        t, x, v = t + h, x_new, v_new
    return None


def delay_scatter(release: Release) -> dict:
    """The release's delay (s) at its rated supply and 20 degC coil (``nominal``), at its fastest
    corner (highest voltage, coldest coil: ``fastest``) and its slowest (lowest voltage, hottest
    coil: ``slowest``); a corner at which it never trips is None."""
    (v_lo, v_hi), (r_lo, r_hi) = release.voltage_range, release.resistance_range
    return {"nominal": release_delay(release), "fastest": release_delay(release, v_hi, r_lo),
            "slowest": release_delay(release, v_lo, r_hi)}

"""Physical plausibility of fitted values: each quantity's documented range (the numbers and their
sources in :mod:`vcbmodel.parameters`) and the laws' own constraints.

A value outside its range, one that breaks its law's constraint (a static coefficient below the
kinetic one by more than their combined 95 % error), or a stated error wider than the whole plausible range (the fit does not determine the
value: a flat direction) is an *implausible* finding. The reports say each plainly, and a verdict
of ``explained`` must not stand with one (:func:`implausible`: a diagnosis's verdict calls it with
the final fit's values and errors and sets ``explained`` false when it returns any finding).

Ranges (``plausible_range``): mu_k and mu_s of a steel journal, the Stribeck velocity from the
sliding speeds of lubricated metal contacts, viscous friction from Petroff's film torque with the
rig's journal radius, air drag from 0.5 rho Cd A R^3 with the rig's centre-of-mass distance, the
friction levels' drift, the contacts' restitution and the bellows' force. A quantity without a
documented range (a discovered torque's coefficient) is checked only for its error.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass

from .. import parameters as P

#: The 95 % interval's half-width in standard deviations (normal).
Z95 = 1.959964


def _viscous_range(rig) -> tuple[float, float]:
    """(0, Petroff's largest C_v) in N m s/rad for the rig's journal radius (m)."""
    r = rig.shaft_radius
    mu, length, clearance = P.PETROFF_VISCOSITY[1], P.PETROFF_LENGTH_RATIO[1] * 2 * r, P.PETROFF_CLEARANCE_RATIO[0] * r
    return 0.0, 2 * math.pi * mu * r**3 * length / clearance


def _drag_range(rig) -> tuple[float, float] | None:
    """(0, the largest 0.5 rho Cd A R^3) in N m s^2/rad^2 for the rig's pendulum (None otherwise)."""
    if rig.pendulum is None:
        return None
    radius = P.DRAG_MAX_RADIUS_OVER_COM * rig.pendulum.com_distance
    return 0.0, 0.5 * P.AIR_DENSITY * P.DRAG_MAX_CD * P.DRAG_MAX_AREA * radius**3


def _stribeck_range(rig) -> tuple[float, float]:
    lo, hi = P.PLAUSIBLE_STRIBECK_SLIDING_SPEED
    return lo / rig.shaft_radius, hi / rig.shaft_radius


RANGES = {"mu_k": lambda rig: P.PLAUSIBLE_MU_K, "mu_s": lambda rig: P.PLAUSIBLE_MU_S,
          "stribeck_velocity": _stribeck_range, "viscous": _viscous_range, "drag": _drag_range,
          "mu_k_drift": lambda rig: P.PLAUSIBLE_MU_K_DRIFT, "restitution": lambda rig: P.PLAUSIBLE_RESTITUTION,
          "bellows_force": lambda rig: P.PLAUSIBLE_BELLOWS_FORCE}
#: Where each range comes from, for the reports.
SOURCES = {"mu_k": "a steel journal: greased bushing to dry steel (Rabinowicz 1995; Marks' Table 3.2.1)",
           "mu_s": "up to dry steel on steel's static level (Marks' Table 3.2.1)",
           "stribeck_velocity": "sliding speeds 1e-5-0.1 m/s of lubricated metal contacts (Armstrong-Helouvry 1994)",
           "viscous": "0 (dry) to Petroff's film torque 2 pi mu r^3 L / c with a grease's apparent viscosity",
           "drag": "0 to 0.5 rho Cd A R^3 for a 0.1 m^2 bluff paddle at twice the centre-of-mass distance",
           "mu_k_drift": "a bearing warming during a test: at most 0.05 over 10 s",
           "restitution": "steel and copper contacts at 0.1-1 m/s (Goldsmith 1960)",
           "bellows_force": "medium-voltage vacuum interrupters' bellows"}


def plausible_range(name: str, rig) -> tuple[float, float] | None:
    """(low, high) of quantity ``name`` for ``rig`` in its unit, or None when none is documented."""
    rule = RANGES.get(name)
    return None if rule is None else rule(rig)


@dataclass(frozen=True)
class Finding:
    """An implausible value: the quantity, its value, what is wrong (``outside`` its range, breaks
    the law's ``constraint``, or its ``stderr`` says it is not determined) and the sentence."""

    name: str
    value: float
    kind: str
    message: str

    def to_json(self) -> dict:
        return {"parameter": self.name, "value": self.value, "kind": self.kind, "message": self.message}


def implausible(rig, values: Mapping[str, float], stderr: Mapping[str, float | None]) -> list[Finding]:
    """The findings on fitted ``values`` ({name: value}, the fit's raw values) with their stated
    errors ``stderr`` (None or missing: not varied or not computed): each outside its plausible
    range, mu_s below mu_k, or a stated error non-finite or wider than the plausible range. An empty
    list: nothing implausible. This is the check a verdict of ``explained`` must pass."""
    out = []
    if "mu_s" in values and "mu_k" in values and "mu_s" in stderr and _below(values, stderr):
        out.append(Finding("mu_s", float(values["mu_s"]), "constraint",
                           f"mu_s {values['mu_s']:.3g} is below mu_k {values['mu_k']:.3g}: the law requires the static "
                           "level at or above the kinetic one (the fit put the Stribeck fall where it has no meaning)"))
    for name, value in values.items():
        bounds = plausible_range(name, rig)
        if bounds is not None and not bounds[0] <= value <= bounds[1]:
            out.append(Finding(name, float(value), "outside",
                               f"{name} {value:.3g} is outside its plausible range [{bounds[0]:.3g}, {bounds[1]:.3g}] "
                               f"({SOURCES[name]})"))
        se = stderr.get(name, 0.0)
        if name in stderr and (se is None or not math.isfinite(se)):
            out.append(Finding(name, float(value), "stderr", f"{name} has no finite stated error: the record does "
                               "not determine it"))
        elif se and bounds is not None and se > P.IMPLAUSIBLE_STDERR_OVER_RANGE * (bounds[1] - bounds[0]):
            out.append(Finding(name, float(value), "stderr", f"{name}'s stated error {se:.2g} is wider than its "
                               f"whole plausible range: the record does not determine it"))
    return out


def _below(values: Mapping[str, float], stderr: Mapping[str, float | None]) -> bool:
    """Whether mu_s lies below mu_k by more than their combined 95 % error (a finite one; a fall
    whose error is unbounded is reported as not determined instead)."""
    se = math.hypot(stderr.get("mu_s") or 0.0, stderr.get("mu_k") or 0.0)
    return bool(math.isfinite(se) and values["mu_k"] - values["mu_s"] > Z95 * se)


def findings_of(rig, values: Mapping[str, float], stderr: Mapping[str, float | None],
                quantities: Mapping | None = None) -> list[Finding]:
    """:func:`implausible` on a fit's values, and on the model-form estimates of ``quantities``
    ({name: Quantity}) that are determined (an average over the forms outside its range)."""
    out = implausible(rig, values, stderr)
    seen = {(f.name, f.kind) for f in out}
    for name, q in (quantities or {}).items():
        bounds = plausible_range(name, rig)
        if q.determined and bounds is not None and not bounds[0] <= q.estimate <= bounds[1] \
                and (name, "outside") not in seen:
            out.append(Finding(name, float(q.estimate), "outside",
                               f"{name}'s estimate over the forms {q.estimate:.3g} is outside its plausible range "
                               f"[{bounds[0]:.3g}, {bounds[1]:.3g}] ({SOURCES[name]})"))
    return out

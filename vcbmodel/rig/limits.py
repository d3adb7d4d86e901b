"""A breaker's acceptance limits (rig section ``breaker.limits``), as a breaker analyser checks a
closing against them: each figure with a lowest and/or highest value, the unit they are stated in
and where they come from.

``"limits": {"closing_speed": {"min": 1.0, "max": 1.3, "unit": "m/s", "source": "..."},
"pole_spread": {"max": 2, "unit": "ms"}, ...}``. The unit is required (no unit is assumed); it must
be one of the figure's quantity (``ms`` or ``s`` for a time, ``mm`` or ``m`` for a travel, ``kN`` or
``N`` for a force). A rig without the section has no limits: the report says "no limit given".
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .. import parameters as P
from .units import to_si
from .reader import Reader

#: The figures a limit may bound: {name: (SI unit, what it is)}; the name is the figure's without its
#: unit (``closing_time`` bounds ``closing_time_s``), checked per pole where the report has the figure
#: per pole, else for the whole breaker.
LIMITED_FIGURES = {
    "closing_time": ("s", "latch release to the contacts touching (per pole; the breaker's: the last pole)"),
    "pole_spread": ("s", "first to last pole touching"),
    "closing_speed": ("m/s", "mean speed over breaker.speed_zone before the touch"),
    "touch_speed": ("m/s", "contact speed at the touch"),
    "bounce_duration": ("s", "first touch to the last re-closing"),
    "bounce_count": ("-", "separations after the first touch"),
    "wipe": ("m", "travel after the touch, to the final position"),
    "overtravel": ("m", "largest travel beyond the final position"),
    "rebound": ("m", "travel back below the final position after the peak"),
    "contact_force_closed": ("N", "contact force at the end of the run"),
    "peak_cam_roller_force": ("N", "largest cam-roller force"),
    "travel_settled": ("s", "travel within 0.05 mm of its final position"),
    "closing_time_from_coil": ("s", "energising the closing coil to the last pole's touch, at rated supply "
                               "(IEC 62271-100's closing time; needs breaker.closing_release)"),
    "kinetic_margin": ("J", "the cam's least kinetic energy from the first touch to its latch"),
    "opening_time": ("s", "the pawl letting go to the last pole's parting (an O, a CO's opening; needs "
                     "breaker.trip_latch and breaker.opening_dashpot)"),
    "opening_time_from_coil": ("s", "energising the opening coil to the last pole's parting, at rated supply "
                               "(IEC 62271-100's opening time; needs breaker.opening_release)"),
    "opening_speed": ("m/s", "mean speed over breaker.opening_speed_zone after the parting (every pole)"),
}
#: The limits on an opening: judged by ``simulate --sequence`` on each O and each CO's opening, not by
#: a closing's report (a plain closing does not open).
OPENING_LIMITS = ("opening_time", "opening_time_from_coil", "opening_speed")
LIMIT_KEYS = ("min", "max", "unit", "source")


@dataclass(frozen=True)
class Limit:
    """One figure's limit: ``low``/``high`` in SI units (None: no bound on that side), the ``unit``
    the rig states them in (the report prints them so) and their ``source`` (free text)."""

    figure: str
    low: float | None
    high: float | None
    unit: str
    source: str = ""

    def holds(self, value: float | None) -> bool | None:
        """Whether an SI value is within the limit; None if there is no value (the run did not show it)."""
        if value is None or (isinstance(value, float) and not math.isfinite(value)):
            return None
        return (self.low is None or value >= self.low) and (self.high is None or value <= self.high)

    def text(self) -> str:
        """The limit as the rig states it: ``1-1.3 m/s``, ``<= 2 ms``, ``>= 3 kN``."""
        factor = to_si(self.unit)[1]
        lo, hi = (None if v is None else f"{v / factor:.4g}" for v in (self.low, self.high))
        unit = "" if self.unit == "-" else f" {self.unit}"
        if lo is not None and hi is not None:
            return f"{lo}-{hi}{unit}"
        return f"<= {hi}{unit}" if hi is not None else f">= {lo}{unit}"


def read_limits(rd: Reader, b: dict, poles: int) -> tuple[Limit, ...]:
    """``breaker.limits`` (optional): {figure: {min, max, unit, source}}; () when absent. ``poles``:
    the breaker's pole count (a single pole has no pole spread to limit)."""
    if "limits" not in b:
        return ()
    section = rd.optional_section(b, "limits", "breaker.", tuple(LIMITED_FIGURES))
    limits = []
    for name, entry in section.items():
        if name.startswith("_"):
            continue
        p = f"breaker.limits.{name}."
        entry = rd.optional_section(section, name, "breaker.limits.", LIMIT_KEYS)
        check_judgeable(rd, b, name, poles)
        si_unit = LIMITED_FIGURES[name][0]
        unit = entry.get("unit")
        if not isinstance(unit, str):
            rd.fail(p + "unit", f"missing: say the unit the limits are stated in ({si_unit} or a multiple)")
        known = to_si(unit)
        if known is None or known[0] != si_unit:
            rd.fail(p + "unit", f"{unit!r} is not a unit of {name} ({si_unit}, or a multiple such as "
                    f"{ {'s': 'ms', 'm': 'mm', 'N': 'kN', 'm/s': 'mm/ms', 'J': 'kJ'}.get(si_unit, si_unit)})")
        low, high = (rd.number(entry, key, p) * known[1] if key in entry else None for key in ("min", "max"))
        if low is None and high is None:
            rd.fail(p + "min", "give min, max or both")
        if low is not None and high is not None and low > high:
            rd.fail(p + "max", "is below min")
        check_plausible(rd, name, low, high, unit.strip(), known[1])
        source = entry.get("source", "")
        if not isinstance(source, str):
            rd.fail(p + "source", "must be text")
        limits.append(Limit(name, low, high, unit.strip(), source))
    return tuple(limits)


def check_judgeable(rd: Reader, b: dict, name: str, poles: int) -> None:
    """Refuse a limit the rig can never judge: a single pole's spread, a time from a coil without its
    release, an opening's figure on a breaker without the parts that open it (``breaker.trip_latch``,
    ``breaker.opening_dashpot``)."""
    p = f"breaker.limits.{name}"
    if name == "pole_spread" and poles == 1:
        rd.fail(p, "a single-pole breaker (breaker.poles.count 1) has no pole spread: delete this limit")
    if name == "closing_time_from_coil" and "closing_release" not in b:
        rd.fail(p, "needs breaker.closing_release, the coil this closing time is counted from "
                "(without it, closing_time bounds the time from the latch release)")
    if name in OPENING_LIMITS and not ("trip_latch" in b and "opening_dashpot" in b):
        rd.fail(p, "bounds an opening: needs breaker.trip_latch and breaker.opening_dashpot (docs/rig-format.md), "
                "without which the breaker does not open")
    if name == "opening_time_from_coil" and "opening_release" not in b:
        rd.fail(p, "needs breaker.opening_release, the coil this opening time is counted from "
                "(without it, opening_time bounds the time from the pawl)")


def check_plausible(rd: Reader, name: str, low: float | None, high: float | None, unit: str, factor: float) -> None:
    """Refuse a nonzero bound (SI) no breaker's limit has (:data:`vcbmodel.parameters.LIMIT_PLAUSIBLE`):
    a unit slip, ``0.08`` under ``ms`` or ``1.0-1.5`` under ``mm/s``, that would fail every run."""
    span = P.LIMIT_PLAUSIBLE.get(name)
    if span is None:
        return
    for key, value in (("min", low), ("max", high)):
        if value is not None and value != 0.0 and not span[0] <= value <= span[1]:
            si = LIMITED_FIGURES[name][0]
            rd.fail(f"breaker.limits.{name}.{key}", f"{value / factor:g} {unit} ({value:g} {si}) is no limit a breaker's "
                    f"{name.replace('_', ' ')} has ({span[0]:g} to {span[1]:g} {si}): is the unit right?")

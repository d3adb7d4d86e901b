"""Units: what a record's header may state, and how a figure is shown to an engineer.

Reading: a column's stated unit (``t [ms]``, ``pole_1_travel [mm]``, a units row under the header)
is converted to the channel's SI unit by a factor (:func:`to_si`); a unit of another quantity (``m``
for a time) is refused by the reader, naming both.

Showing: a figure of merit's name ends in its SI unit (``closing_time_s``, ``wipe_m``,
``closing_speed_m_s``, ``peak_cam_roller_force_N``); :func:`display` gives the unit a breaker
engineer reads it in (ms, mm, m/s, kN), its factor and the finest step worth printing, and
:func:`format_value` prints 4 significant figures, never finer than that step (a travel to the
micrometre, a time to the microsecond).
"""
from __future__ import annotations

import math
from typing import NamedTuple

#: Units a record's header may state: {unit: (SI unit, factor to SI)}. Spellings of one unit share
#: their entry (``us`` and ``µs``; ``-`` and ``1`` for 0/1 or dimensionless channels).
TO_SI = {
    "s": ("s", 1.0), "ms": ("s", 1e-3), "us": ("s", 1e-6), "µs": ("s", 1e-6), "min": ("s", 60.0),
    "second": ("s", 1.0), "seconds": ("s", 1.0), "sec": ("s", 1.0),  # a Keysight scope's units row: second,Volt
    "m": ("m", 1.0), "mm": ("m", 1e-3), "cm": ("m", 1e-2), "um": ("m", 1e-6), "µm": ("m", 1e-6),
    "rad": ("rad", 1.0), "mrad": ("rad", 1e-3), "deg": ("rad", math.pi / 180), "°": ("rad", math.pi / 180),
    "m/s": ("m/s", 1.0), "mm/ms": ("m/s", 1.0), "mm/s": ("m/s", 1e-3),
    "rad/s": ("rad/s", 1.0), "deg/s": ("rad/s", math.pi / 180), "rpm": ("rad/s", 2 * math.pi / 60),
    "N": ("N", 1.0), "kN": ("N", 1e3), "N m": ("N m", 1.0), "Nm": ("N m", 1.0), "J": ("J", 1.0), "kJ": ("J", 1e3), "A": ("A", 1.0), "kA": ("A", 1e3),
    "-": ("-", 1.0), "1": ("-", 1.0),
}


def to_si(unit: str) -> tuple[str, float] | None:
    """(SI unit, factor) of a stated unit (``ms`` -> (``s``, 1e-3)); None if unknown."""
    return TO_SI.get(unit.strip().replace("\u03bc", "\u00b5"))  # the Greek mu typed for the micro sign


class Display(NamedTuple):
    """How one SI quantity is shown: ``unit`` (what is printed), ``factor`` (SI -> shown) and
    ``step`` (the finest resolution worth printing, in the shown unit)."""

    unit: str
    factor: float
    step: float


#: SI unit -> how a breaker analyser's report shows it: times in ms to the microsecond, travels in
#: mm to the micrometre (an analyser's transducer resolves 0.1 mm; a model resolves more), speeds in
#: m/s, forces in kN to the newton, angles in degrees.
DISPLAY = {
    "s": Display("ms", 1e3, 1e-3), "m": Display("mm", 1e3, 1e-3), "m/s": Display("m/s", 1.0, 1e-3),
    "N": Display("kN", 1e-3, 1e-3), "J": Display("J", 1.0, 0.1), "rad": Display("deg", 180 / math.pi, 0.001),
    "deg": Display("deg", 1.0, 0.01), "rad/s": Display("rad/s", 1.0, 0.01), "N m": Display("N m", 1.0, 0.01),
    "A": Display("kA", 1e-3, 1e-3), "W": Display("W", 1.0, 0.1), "1/s": Display("1/s", 1.0, 1e-4),
    "-": Display("", 1.0, 1.0), "Hz": Display("Hz", 1.0, 0.01), "kg": Display("kg", 1.0, 1e-4),
}
#: A figure's name suffix -> its SI unit (longest suffix first: ``_m_s`` before ``_s``)
SUFFIX_UNITS = (("_rad_s", "rad/s"), ("_m_s", "m/s"), ("_N_m", "N m"), ("_deg", "deg"), ("_rad", "rad"),
                ("_s", "s"), ("_m", "m"), ("_N", "N"), ("_J", "J"), ("_A", "A"), ("_W", "W"), ("_Hz", "Hz"),
                ("_kg", "kg"))


def unit_of_name(name: str) -> str | None:
    """The SI unit a figure's name ends in (``closing_time_s`` -> ``s``); None if it names none."""
    for suffix, unit in SUFFIX_UNITS:
        if name.endswith(suffix):
            return unit
    return None


def display(si_unit: str | None) -> Display:
    """How a quantity in ``si_unit`` is shown (unknown units as they are, to 4 significant figures)."""
    if si_unit is None:
        return Display("", 1.0, 1.0)
    return DISPLAY.get(si_unit, Display(si_unit, 1.0, 0.0))


def format_value(value: float | int | None, step: float = 0.0, figures: int = 4) -> str:
    """``value`` to ``figures`` significant figures, never finer than ``step`` (0: no floor, and a
    value below 1e-3 or from 1e6 up in powers of ten, ``-3.038e-06``); ``-`` for None or NaN.
    Integers (counts) as they are."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    if isinstance(value, (bool, int)) or (step >= 1.0 and float(value).is_integer()):
        return str(int(value))
    v = float(value)
    magnitude = math.floor(math.log10(abs(v))) if v != 0.0 else 0
    if step == 0.0 and not -3 <= magnitude < 6:
        return f"{v:.{figures - 1}e}"
    decimals = max(0, figures - 1 - magnitude)
    if step > 0.0:
        decimals = min(decimals, max(0, -math.floor(math.log10(step) + 1e-9)))
    text = f"{v:.{decimals}f}"
    return "0" + text[2:] if text.startswith("-0") and float(text) == 0.0 else text


def shown(value: float | int | None, si_unit: str | None) -> tuple[float | int | None, str, str]:
    """(value in the shown unit, the shown unit, the value as printed) of an SI value."""
    d = display(si_unit)
    if value is None or isinstance(value, bool) or (isinstance(value, float) and not math.isfinite(value)):
        return None, d.unit, "-"
    v = value if isinstance(value, int) and d.factor == 1.0 else float(value) * d.factor
    return v, d.unit, format_value(v, d.step)

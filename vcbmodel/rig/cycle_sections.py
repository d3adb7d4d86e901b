"""Readers of the breaker's cycle sections: closing onto a fault, the trip latch, the opening
dashpot and the releases (rig sections ``breaker.making_current``, ``breaker.trip_latch``,
``breaker.opening_dashpot``, ``breaker.closing_release``, ``breaker.opening_release``,
``breaker.opening_speed_zone``; docs/rig-format.md). Each section is optional (absent: not
modelled); when present every field is required and checked, and a bad one is refused with one
line naming it.
"""
from __future__ import annotations

import numpy as np

from ..laws.cam_follower import TWO_PI, kinematic_follower_angle, output_point, rest_geometry
from ..laws.making_current import MakingCurrent
from ..laws.opening import OpeningDashpot, TripLatch
from ..laws.release import Release, picks_up
from .reader import Reader

#: Every field of each cycle section with its unit (the one-line error for a missing field lists them)
CYCLE_KEYS = {
    "making_current": (("peak", "A"), ("frequency", "Hz"), ("time_constant", "s"), ("asymmetry", "-"),
                       ("contact_radius", "m"), ("spot_radius", "m"), ("spots", "-")),
    "trip_latch": (("travel", "m"), ("stiffness", "N/m"), ("damping", "N s/m"), ("release_time", "s"),
                   ("reset_travel", "m")),
    "opening_dashpot": (("stroke", "m"), ("damping", "N s/m"), ("ramp", "m"), ("stop_stiffness", "N/m"),
                        ("stop_damping", "N s/m")),
    "closing_release": (("voltage", "V"), ("resistance", "ohm"), ("inductance", "H"), ("force_constant", "N/A^2"),
                        ("armature_mass", "kg"), ("stroke", "m"), ("load", "N"), ("voltage_range", "-"),
                        ("resistance_range", "-")),
}
CYCLE_KEYS["opening_release"] = CYCLE_KEYS["closing_release"]
#: The cycle's keys of the ``breaker`` section (sections, and the opening speed's zone)
CYCLE_BREAKER_KEYS = tuple(CYCLE_KEYS) + ("opening_speed_zone",)


def _fields(rd: Reader, b: dict, key: str) -> tuple[dict, str] | tuple[None, str]:
    """The section ``breaker.key`` with every field present (None if the section is absent)."""
    p = f"breaker.{key}."
    if key not in b:
        return None, p
    names = [name for name, _ in CYCLE_KEYS[key]]
    s = {k: v for k, v in rd.optional_section(b, key, "breaker.", names).items() if not k.startswith("_")}
    for name in names:
        if name not in s:
            listing = ", ".join(f"{n} ({u})" for n, u in CYCLE_KEYS[key])
            rd.fail(p + name, f"missing: breaker.{key} needs {listing}; leave out the whole section to leave it "
                    "out of the model")
    return s, p


def read_making_current(rd: Reader, b: dict) -> MakingCurrent | None:
    """``breaker.making_current`` (:class:`vcbmodel.laws.making_current.MakingCurrent`)."""
    s, p = _fields(rd, b, "making_current")
    if s is None:
        return None
    m = MakingCurrent(peak=rd.number(s, "peak", p, positive=True), frequency=rd.number(s, "frequency", p, positive=True),
                      time_constant=rd.number(s, "time_constant", p, positive=True),
                      asymmetry=rd.number(s, "asymmetry", p, nonnegative=True),
                      contact_radius=rd.number(s, "contact_radius", p, positive=True),
                      spot_radius=rd.number(s, "spot_radius", p, positive=True), spots=float(rd.count(s, "spots", p)))
    if m.peak < 1000.0:
        rd.fail(p + "peak", f"{m.peak:g} A is not a fault current (in kA? the peak is in A: 100 kA is 100000)")
    if not 10.0 <= m.frequency <= 1000.0:
        rd.fail(p + "frequency", f"{m.frequency:g} Hz is not a power frequency (50 or 60 Hz)")
    if m.time_constant > 1.0:
        rd.fail(p + "time_constant", f"{m.time_constant:g} s: the DC time constant is milliseconds (IEC's standard "
                "45 ms is 0.045; in ms?)")
    if m.asymmetry > 1.0:
        rd.fail(p + "asymmetry", f"must be between 0 (symmetric) and 1 (fully asymmetric), got {m.asymmetry:g}")
    if m.spot_radius >= m.contact_radius:
        rd.fail(p + "spot_radius", f"{m.spot_radius:g} m is not smaller than the contact radius "
                f"({m.contact_radius:g} m): the current constricts into spots smaller than the face")
    return m


def largest_f_travel(breaker, cam) -> float:
    """The largest travel (m) of the follower's output point F from its open rest over the cam's
    first turn (the roller on the pitch curve): how far the cam can lift F."""
    geometry = rest_geometry(breaker, cam.pivot)
    y0 = geometry.output_point[1]
    phi, best = geometry.follower_angle, 0.0
    for theta in cam.initial_angle + np.linspace(0.0, TWO_PI, 181):
        phi = kinematic_follower_angle(theta, breaker, geometry, phi)
        best = max(best, output_point(phi, breaker.follower)[1] - y0)
    return best


def read_trip_latch(rd: Reader, b: dict, breaker, cam) -> TripLatch | None:
    """``breaker.trip_latch`` (:class:`vcbmodel.laws.opening.TripLatch`): the pawl's travel must
    be within what the cam lifts F (else it never engages), the reset travel below it."""
    s, p = _fields(rd, b, "trip_latch")
    if s is None:
        return None
    latch = TripLatch(travel=rd.number(s, "travel", p, positive=True), stiffness=rd.number(s, "stiffness", p, positive=True),
                      damping=rd.number(s, "damping", p, nonnegative=True),
                      release_time=rd.number(s, "release_time", p, positive=True),
                      reset_travel=rd.number(s, "reset_travel", p, positive=True))
    reach = largest_f_travel(breaker, cam)
    if latch.travel >= reach:
        rd.fail(p + "travel", f"{latch.travel:g} m: the cam lifts F at most {reach:.6g} m, so the pawl would never "
                "engage (in mm? travels are in m)")
    if latch.reset_travel >= latch.travel:
        rd.fail(p + "reset_travel", f"{latch.reset_travel:g} m is not below the pawl's travel ({latch.travel:g} m): "
                "the link resets near the open position")
    if latch.release_time > 0.1:
        rd.fail(p + "release_time", f"{latch.release_time:g} s: a pawl lets go in milliseconds (in ms?)")
    return latch


def read_opening_dashpot(rd: Reader, b: dict, trip_latch: TripLatch | None) -> OpeningDashpot | None:
    """``breaker.opening_dashpot`` (:class:`vcbmodel.laws.opening.OpeningDashpot`): needs the trip
    latch (without it nothing opens the breaker); ramp within the stroke, stroke within the travel."""
    s, p = _fields(rd, b, "opening_dashpot")
    if s is None:
        return None
    if trip_latch is None:
        rd.fail("breaker.opening_dashpot", "needs breaker.trip_latch (without a trip latch the breaker never opens)")
    d = OpeningDashpot(stroke=rd.number(s, "stroke", p, positive=True), damping=rd.number(s, "damping", p, nonnegative=True),
                       ramp=rd.number(s, "ramp", p, positive=True),
                       stop_stiffness=rd.number(s, "stop_stiffness", p, positive=True),
                       stop_damping=rd.number(s, "stop_damping", p, nonnegative=True))
    if d.stroke >= trip_latch.travel:
        rd.fail(p + "stroke", f"{d.stroke:g} m reaches the pawl's travel ({trip_latch.travel:g} m): the dashpot "
                "damps the end of the opening stroke (in mm? travels are in m)")
    if d.ramp > d.stroke:
        rd.fail(p + "ramp", f"{d.ramp:g} m is longer than the stroke ({d.stroke:g} m)")
    return d


def read_release(rd: Reader, b: dict, key: str) -> Release | None:
    """``breaker.closing_release`` or ``breaker.opening_release`` (:class:`vcbmodel.laws.release.Release`):
    ranges as [lowest, highest] around 1; the armature must pick up at the slowest corner."""
    s, p = _fields(rd, b, key)
    if s is None:
        return None
    ranges = {}
    for name, what in (("voltage_range", "supply as fractions of rated (IEC 62271-1: closing 0.85-1.1)"),
                       ("resistance_range", "coil resistance as factors (coldest, hottest)")):
        lo, hi = rd.numbers(s, name, p, 2, None)
        if not 0.0 < lo <= 1.0 <= hi <= 2.0:
            rd.fail(p + name, f"must be [lowest, highest] {what}, with 0 < lowest <= 1 <= highest <= 2; got [{lo:g}, {hi:g}]")
        ranges[name] = (lo, hi)
    r = Release(voltage=rd.number(s, "voltage", p, positive=True), resistance=rd.number(s, "resistance", p, positive=True),
                inductance=rd.number(s, "inductance", p, positive=True),
                force_constant=rd.number(s, "force_constant", p, positive=True),
                armature_mass=rd.number(s, "armature_mass", p, positive=True), stroke=rd.number(s, "stroke", p, positive=True),
                load=rd.number(s, "load", p, nonnegative=True), **ranges)
    if r.stroke > 0.05:
        rd.fail(p + "stroke", f"{r.stroke:g} m: a release's armature moves millimetres (in mm? lengths are in m)")
    if not picks_up(r, r.voltage_range[0], r.resistance_range[1]):
        current = r.voltage * r.voltage_range[0] / (r.resistance * r.resistance_range[1])
        rd.fail(p + "force_constant", f"the armature never moves at {100 * r.voltage_range[0]:g} % supply with the "
                f"hottest coil: k (U/R)^2 = {r.force_constant * current ** 2:.4g} N is not above its load ({r.load:g} N)")
    return r


def read_opening_speed_zone(rd: Reader, b: dict, poles, closing_zone: tuple) -> tuple:
    """``breaker.opening_speed_zone``: [start, end] in m of travel after each pole's parting,
    0 <= start < end, within the smallest gap; default the closing zone's length from the
    parting (analysers' opening speed: over a zone the user programs after the contacts part)."""
    if "opening_speed_zone" not in b:
        return (0.0, closing_zone[0] - closing_zone[1])
    zone = tuple(rd.numbers(b, "opening_speed_zone", "breaker.", 2, None))
    if not 0.0 <= zone[0] < zone[1]:
        rd.fail("breaker.opening_speed_zone", "must be [start, end] in m after the parting, 0 <= start < end")
    if zone[1] > min(poles.contact_gap + o for o in poles.gap_offsets):
        rd.fail("breaker.opening_speed_zone", "ends beyond the open position: it must lie within the smallest pole gap")
    return zone


def read_cycle(rd: Reader, b: dict, breaker, cam) -> dict:
    """Every cycle part of the ``breaker`` section, as the :class:`vcbmodel.rig.data.Breaker`
    fields of the same names (each None when absent)."""
    trip = read_trip_latch(rd, b, breaker, cam)
    return {"making_current": read_making_current(rd, b), "trip_latch": trip,
            "opening_dashpot": read_opening_dashpot(rd, b, trip),
            "closing_release": read_release(rd, b, "closing_release"),
            "opening_release": read_release(rd, b, "opening_release"),
            "opening_speed_zone": read_opening_speed_zone(rd, b, breaker.poles, breaker.speed_zone)}

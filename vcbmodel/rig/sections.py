"""Readers of a rig file's sections: JSON object in, checked dataclass out.

Each reader takes the public :class:`vcbmodel.rig.reader.Reader` (errors name the dotted
field) and the file's JSON object. The experiment records (:mod:`vcbmodel.experiments`) say
which readers their rig needs. Keys starting with ``_`` are free comments and are ignored.
"""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .. import parameters as P

from ..laws.breaker import CamRollerLaw, EndStop, HoldLatch, LatchPoint, MainShaft
from ..laws.cam_follower import (MAX_PRESSURE_ANGLE, TWO_PI, pitch_radius, pressure_angle_curve, profile_spline,
                                 profile_table, rest_geometry, undercut)
from ..laws.contact import CAM_ROLLER_LAWS, DAMPING_LAWS
from ..laws.coil import coil_mass, coil_stiffness
from ..laws.mechanics import cam_pin
from .cycle_sections import CYCLE_BREAKER_KEYS, read_cycle
from .cam_points import check_point_pairs, read_points_file, settle_scatter
from .datasheet import check_datasheet
from .limits import read_limits
from .paths import numeric_at
from .reader import Reader
from .data import (Breaker, Cam, CamProfile, ClosingSpring, ContactLaw, Follower, OpeningSpring, Pendulum,
                   Poles)

FRICTION_KEYS = ("mu_s", "mu_k", "stick_velocity", "stribeck_velocity", "viscous", "zeta", "sticking", "drag")
STICKING = ("passive", "literal")
PENDULUM_KEYS = ("mass", "inertia", "com_distance", "initial_angle", "initial_velocity")
CAM_KEYS = ("mass", "inertia_com", "com_distance", "com_angle", "pivot", "arm_length", "initial_angle",
            "initial_velocity")
SPRING_KEYS = ("count", "stiffness", "mass", "free_length", "anchor", "wire_diameter", "coil_diameter",
               "active_coils", "shear_modulus", "weight", "density", "damping_ratio", "ends")
#: How a closing spring's ends are made: standard hooks (bent from the wire: their bending and torsion
#: are checked) or screwed-in plugs / swivel inserts (no hook stress: the body alone is checked)
SPRING_ENDS = ("hooks", "plugs")
#: Relative difference allowed between a given k0 or m0 and the datasheet's (catalogue rounding)
DATASHEET_TOLERANCE = 0.05


def without_comments(obj: dict) -> dict:
    return {k: v for k, v in obj.items() if not k.startswith("_")}


def read_friction(rd: Reader, data: dict) -> dict[str, float]:
    """The friction values the rig gives (subset of FRICTION_KEYS), checked."""
    f = without_comments(rd.optional_section(data, "friction"))
    rd.known_keys(f, FRICTION_KEYS, "friction.")
    friction = {key: rd.number(f, key, "friction.", nonnegative=True) for key in f if key != "sticking"}
    if "sticking" in f:
        friction["sticking"] = rd.choice(f, "sticking", "friction.", STICKING)
    if "mu_s" in friction and "mu_k" in friction and friction["mu_s"] < friction["mu_k"]:
        rd.fail("friction.mu_s", "must not be smaller than friction.mu_k")
    return friction


RECORD_KEYS = ("release_time", "initial_angle", "sensor_offset", "sensor_gain", "sensor_noise")
#: Record values that may be marked uncertain without a rig field of their own: the sensor's gain
#: and the record's time base (relative sd of its clock).
UNCERTAIN_RECORD = ("record.sensor_gain", "record.time_base")


def read_record(rd: Reader, data: dict) -> dict[str, float]:
    """The optional ``record`` section: facts about the measurement that the diagnosis would
    otherwise estimate (release time in the record, initial angle, sensor offset and gain), and
    the sensor's noise level (``sensor_noise``, the record's unit: a witness of the verdict)."""
    r = without_comments(rd.optional_section(data, "record", known=RECORD_KEYS))
    out = {}
    for key in r:
        out[key] = rd.number(r, key, "record.", positive=key in ("sensor_gain", "sensor_noise"))
    return out


def read_uncertain(rd: Reader, data: dict) -> dict[str, float]:
    """The optional ``uncertain`` section: dotted path of a numeric rig field -> its relative
    standard deviation (0.05: known to +-5 %). The field must be in the rig and non-zero."""
    u = without_comments(rd.optional_section(data, "uncertain"))
    out = {}
    for path in u:
        value = rd.number(u, path, "uncertain.", positive=True)
        if value >= 1.0:
            rd.fail(f"uncertain.{path}", f"a relative standard deviation below 1 (0.05 for +-5 %), got {value:g}")
        if path == "record.time_base" and value > P.TIME_SCALE_SPAN / 2:
            rd.fail(f"uncertain.{path}", f"at most {P.TIME_SCALE_SPAN / 2:g} (the fit bounds a record's clock error "
                    f"to +-{100 * P.TIME_SCALE_SPAN:g} %), got {value:g}")
        if path in UNCERTAIN_RECORD:  # the sensor's gain, the record's clock: estimated with this uncertainty
            out[path] = value
            continue
        nominal = numeric_at(data, path)
        if nominal is None or nominal == 0:
            rd.fail(f"uncertain.{path}", "must name a numeric, non-zero field of this rig (e.g. pendulum.inertia)")
        if path.split(".")[0] in ("format", "name", "experiment", "model", "record", "uncertain"):
            rd.fail(f"uncertain.{path}", "must name a physical value of the rig")
        out[path] = value
    return out


def read_pendulum(rd: Reader, data: dict) -> dict[str, Pendulum]:
    p = without_comments(rd.section(data, "pendulum", known=PENDULUM_KEYS))
    pre = "pendulum."
    pendulum = Pendulum(
        mass=rd.number(p, "mass", pre, positive=True), inertia=rd.number(p, "inertia", pre, positive=True),
        com_distance=rd.number(p, "com_distance", pre, positive=True),
        initial_angle=rd.number(p, "initial_angle", pre), initial_velocity=rd.number(p, "initial_velocity", pre, default=0.0))
    if pendulum.inertia < 0.99 * pendulum.mass * pendulum.com_distance**2:  # 1 %: rounded data
        rd.fail("pendulum.inertia", "smaller than mass * com_distance^2: not a physical body")
    if abs(pendulum.initial_angle) >= math.pi:
        rd.fail("pendulum.initial_angle", "must lie within (-pi, pi) rad of hanging straight down")
    return {"pendulum": pendulum}


def read_cam(rd: Reader, data: dict) -> dict[str, Cam]:
    c = without_comments(rd.section(data, "cam", known=CAM_KEYS))
    pre = "cam."
    cam = Cam(
        mass=rd.number(c, "mass", pre, positive=True), inertia_com=rd.number(c, "inertia_com", pre, nonnegative=True),
        com_distance=rd.number(c, "com_distance", pre, nonnegative=True),
        com_angle=rd.number(c, "com_angle", pre, default=0.0), pivot=rd.point(c, "pivot", pre),
        arm_length=rd.number(c, "arm_length", pre, positive=True), initial_angle=rd.number(c, "initial_angle", pre),
        initial_velocity=rd.number(c, "initial_velocity", pre, default=0.0))
    if cam.inertia_pivot <= 0:
        rd.fail("cam.inertia_com", "the cam has no inertia about its shaft")
    for key in ("initial_angle", "com_angle"):
        if abs(getattr(cam, key)) > TWO_PI:
            rd.fail(pre + key, f"{getattr(cam, key):g} rad is more than a turn: in degrees? angles are in rad")
    return {"cam": cam}


def read_closing_spring(rd: Reader, data: dict, cam: Cam) -> dict[str, ClosingSpring]:
    s = without_comments(rd.section(data, "closing_spring", known=SPRING_KEYS))
    pre = "closing_spring."
    optional = {k: rd.number(s, k, pre, positive=True)
                for k in ("wire_diameter", "coil_diameter", "active_coils", "shear_modulus", "density") if k in s}
    stiffness, mass, derived = spring_rate_and_mass(rd, s, optional)
    if "damping_ratio" in s:
        optional["damping_ratio"] = rd.number(s, "damping_ratio", pre, nonnegative=True)
        if optional["damping_ratio"] >= 1.0:
            rd.fail(pre + "damping_ratio", f"a damping ratio below 1 (0.01 for 1 %), got {optional['damping_ratio']:g}")
    if "ends" in s:
        optional["ends"] = rd.choice(s, "ends", pre, SPRING_ENDS)
    spring = ClosingSpring(
        count=rd.count(s, "count", pre, default=2.0), stiffness=stiffness, mass=mass,
        free_length=rd.number(s, "free_length", pre, positive=True), anchor=rd.point(s, "anchor", pre),
        weight=rd.boolean(s, "weight", pre), from_datasheet=derived, **optional)
    bx, by = cam_pin(cam.initial_angle, cam)
    if math.hypot(bx - spring.anchor[0], by - spring.anchor[1]) <= spring.free_length:
        rd.fail("closing_spring.free_length", "the spring is not stretched at the start: a tension spring must be charged")
    return {"closing_spring": spring}


def spring_rate_and_mass(rd: Reader, s: dict, coil: dict) -> tuple[float, float, tuple[str, ...]]:
    """k0 (N/m) and m0 (kg) of a closing spring: as given, or from its datasheet (wire and mean
    coil diameter, active coils, shear modulus; the wire's density, steel's 7850 kg/m^3 unless
    given: :mod:`vcbmodel.laws.coil`). Given and datasheet values must agree within
    DATASHEET_TOLERANCE. Returns (k0, m0, the names derived from the datasheet)."""
    pre = "closing_spring."
    check_datasheet(rd, coil)
    geometry = all(k in coil for k in ("wire_diameter", "coil_diameter", "active_coils"))
    sheet = {}
    if geometry and "shear_modulus" in coil:
        sheet["stiffness"] = coil_stiffness(coil["wire_diameter"], coil["coil_diameter"], coil["active_coils"],
                                            coil["shear_modulus"])
    if geometry:
        sheet["mass"] = coil_mass(coil["wire_diameter"], coil["coil_diameter"], coil["active_coils"],
                                  coil.get("density", P.STEEL_DENSITY))
    values, derived = {}, []
    for key, unit, need in (("stiffness", "N/m", "wire_diameter, coil_diameter, active_coils and shear_modulus"),
                            ("mass", "kg", "wire_diameter, coil_diameter and active_coils")):
        if key in s:
            values[key] = rd.number(s, key, pre, positive=True)
            if key in sheet and abs(values[key] / sheet[key] - 1) > DATASHEET_TOLERANCE:
                rd.fail(pre + key, f"{values[key]:.6g} {unit}, but the datasheet fields give {sheet[key]:.6g} {unit} "
                        f"(more than {100 * DATASHEET_TOLERANCE:g} % apart): correct one, or leave {key} out")
        elif key in sheet:
            values[key] = sheet[key]
            derived.append(key)
        else:
            rd.fail(pre + key, f"missing: give it, or the spring's datasheet ({need})")
    return values["stiffness"], values["mass"], tuple(derived)


def read_cam_and_spring(rd: Reader, data: dict) -> dict:
    """``cam`` and ``closing_spring`` (cam drop; the whole breaker's cam too)."""
    sections = read_cam(rd, data)
    sections.update(read_closing_spring(rd, data, sections["cam"]))
    return sections


BREAKER_KEYS = {
    "": ("cam_profile", "roller_radius", "follower", "poles", "opening_spring", "contact", "latch", "speed_zone",
         "end_stop", "hold_latch", "main_shaft", "limits") + CYCLE_BREAKER_KEYS,
    "cam_profile": ("base_radius", "lift", "rise_start", "rise_end", "return_start", "return_end", "points",
                    "radius_points", "points_file", "smoothing"),
    "follower": ("pivot", "inertia", "roller_arm", "output_arm", "output_angle", "rest_angle"),
    "poles": ("count", "moving_mass", "contact_gap", "gap_offsets", "push_rod_length", "wipe_preload", "wipe_rate",
              "rod_stiffness", "rod_damping", "bellows_force"),
    "opening_spring": ("stiffness", "preload", "length"),
    "contact": ("cam_roller_stiffness", "pole_stiffness", "exponent", "restitution", "min_impact_speed",
                "cam_roller_law", "roller_width", "cam_roller_damping", "cam_roller_damping_factor"),
    "latch": ("release_time", "arm", "angle"),
    "end_stop": ("angle", "arm", "stiffness", "damping", "damping_depth"),
    "hold_latch": ("angle", "arm", "stiffness", "damping"),
    "main_shaft": ("pole_pitch", "diameter", "bore", "shear_modulus", "damping", "lever_inertia", "drive_pole"),
}


def read_breaker(rd, data, cam) -> Breaker:
    """Parse and check the ``breaker`` section of a ``vcb_closing`` rig, and that the roller
    rests on the cam's base circle at ``cam.initial_angle``."""
    b = without_comments(rd.section(data, "breaker", known=BREAKER_KEYS[""]))

    def part(key, optional=False):
        known = BREAKER_KEYS[key]
        section = rd.optional_section(b, key, "breaker.", known) if optional else rd.section(b, key, "breaker.", known)
        return without_comments(section), f"breaker.{key}."

    roller_radius = rd.number(b, "roller_radius", "breaker.", positive=True)
    cp, p = part("cam_profile")
    profile = read_cam_profile(rd, cp, p, roller_radius)
    fo, p = part("follower")
    follower = Follower(pivot=rd.point(fo, "pivot", p), inertia=rd.number(fo, "inertia", p, positive=True),
                        roller_arm=rd.number(fo, "roller_arm", p, positive=True),
                        output_arm=rd.number(fo, "output_arm", p, positive=True),
                        output_angle=rd.number(fo, "output_angle", p, default=0.0),
                        rest_angle=rd.number(fo, "rest_angle", p))
    po, p = part("poles")
    count = rd.count(po, "count", p, default=3.0)
    offsets = rd.numbers(po, "gap_offsets", p, count, [0.0] * count)
    poles = Poles(count=count, moving_mass=rd.number(po, "moving_mass", p, positive=True),
                  contact_gap=rd.number(po, "contact_gap", p, positive=True), gap_offsets=offsets,
                  push_rod_length=rd.number(po, "push_rod_length", p, positive=True),
                  wipe_preload=rd.number(po, "wipe_preload", p, nonnegative=True),
                  wipe_rate=rd.number(po, "wipe_rate", p, positive=True),
                  rod_stiffness=rd.number(po, "rod_stiffness", p, positive=True),
                  rod_damping=rd.number(po, "rod_damping", p, nonnegative=True),
                  bellows_force=rd.number(po, "bellows_force", p, nonnegative=True) if "bellows_force" in po else None)
    if min(poles.contact_gap + o for o in poles.gap_offsets) <= 0:
        rd.fail(p + "gap_offsets", "make a pole's gap zero or negative")
    os_, p = part("opening_spring")
    opening = OpeningSpring(stiffness=rd.number(os_, "stiffness", p, positive=True),
                            preload=rd.number(os_, "preload", p, nonnegative=True),
                            length=rd.number(os_, "length", p, positive=True))
    if opening.preload / opening.stiffness >= opening.length:
        rd.fail(p + "preload", "stretches the spring beyond twice its length: free length would be <= 0")
    contact, roller_law = read_contact(rd, *part("contact"))
    latch, p = part("latch", optional=True)
    release = rd.number(latch, "release_time", p, nonnegative=True, default=0.0)
    latch_point = LatchPoint(rd.number(latch, "arm", p, positive=True) if "arm" in latch else None,
                             rd.number(latch, "angle", p, default=0.0))
    end_stop, hold_latch = read_stops(rd, b, cam)
    breaker = Breaker(profile, roller_radius, follower, poles, opening,
                      contact, release, roller_law, latch_point,
                      read_speed_zone(rd, b, poles), end_stop, hold_latch, read_main_shaft(rd, b, follower, poles),
                      read_limits(rd, b, poles.count))
    try:
        rest_geometry(breaker, cam.pivot)
    except ValueError as e:
        rd.fail("breaker.follower.pivot", str(e))
    # a profile from points may ripple by micrometres between them (its spline): 10 um is still "on"
    on_base = 1e-5 if profile.table else 1e-9
    if pitch_radius(cam.initial_angle, profile, breaker.roller_radius)[0] > profile.base_radius + breaker.roller_radius + on_base:
        rd.fail("cam.initial_angle", "the roller is not on the cam's base circle at the start (breaker open)")
    if profile.table:
        check_pressure_angle(rd, breaker, cam)
    return replace(breaker, **read_cycle(rd, b, breaker, cam))


def read_contact(rd, co: dict, p: str) -> tuple[ContactLaw, CamRollerLaw]:
    """``breaker.contact``: the contact law (stiffnesses, exponent, restitution, impact-speed floor)
    and the cam-roller contact's law (point or line, Lankarani-Nikravesh or Hunt-Crossley damping)."""
    contact = ContactLaw(cam_roller_stiffness=rd.number(co, "cam_roller_stiffness", p, positive=True),
                         pole_stiffness=rd.number(co, "pole_stiffness", p, positive=True),
                         exponent=rd.number(co, "exponent", p, positive=True, default=1.5),
                         restitution=rd.number(co, "restitution", p, positive=True) if "restitution" in co else None,
                         min_impact_speed=rd.number(co, "min_impact_speed", p, positive=True, default=0.05))
    if not 1.0 <= contact.exponent <= 2.0:
        rd.fail(p + "exponent", f"must be between 1 (line contact) and 2; Hertz's point contact is 1.5, got "
                f"{contact.exponent:g}")
    if contact.restitution is not None and contact.restitution > 1.0:
        rd.fail(p + "restitution", f"must be in (0, 1], got {contact.restitution:g}")
    law = rd.choice(co, "cam_roller_law", p, CAM_ROLLER_LAWS, "hertz_point")
    damping = rd.choice(co, "cam_roller_damping", p, DAMPING_LAWS, "lankarani_nikravesh")
    width = rd.number(co, "roller_width", p, positive=True) if "roller_width" in co or law == "line" else None
    factor = (rd.number(co, "cam_roller_damping_factor", p, nonnegative=True)
              if "cam_roller_damping_factor" in co or damping == "hunt_crossley" else 0.0)
    return contact, CamRollerLaw(law, width, damping, factor)


#: Fields of a stop section that may be left out: the end stop's ``damping_depth`` (m), the penetration
#: over which its damping rises from zero to ``damping`` (left out or 0: a plain dashpot, the whole
#: damping from the first contact; :func:`vcbmodel.laws.breaker.end_stop_damping`).
OPTIONAL_STOP_KEYS = ("damping_depth",)


def read_stops(rd: Reader, b: dict, cam: Cam) -> tuple[EndStop | None, HoldLatch | None]:
    """``breaker.end_stop`` and ``breaker.hold_latch``: each optional (absent: not modelled), and
    when present every field is required: ``angle`` (rad, the cam angle where it acts, after the
    start), ``arm`` (m, > 0), ``stiffness`` (N/m, > 0), ``damping`` (N s/m, >= 0), except the end
    stop's ``damping_depth`` (m, >= 0, :data:`OPTIONAL_STOP_KEYS`). A holding
    latch beyond the end stop could only engage with the cam pressed into the stop: refused."""
    parts = {}
    for key, kind, what in (("end_stop", EndStop, "an end stop"), ("hold_latch", HoldLatch, "a holding latch")):
        if key not in b:
            parts[key] = None
            continue
        p = f"breaker.{key}."
        s = without_comments(rd.optional_section(b, key, "breaker.", BREAKER_KEYS[key]))
        for name in BREAKER_KEYS[key]:
            if name not in s and name not in OPTIONAL_STOP_KEYS:
                rd.fail(p + name, f"missing: {what} needs angle (rad), arm (m), stiffness (N/m) and "
                        f"damping (N s/m); leave out the whole breaker.{key} section to leave it out of the model")
        ramp = {"damping_depth": rd.number(s, "damping_depth", p, nonnegative=True)} if "damping_depth" in s else {}
        parts[key] = kind(angle=rd.number(s, "angle", p), arm=rd.number(s, "arm", p, positive=True),
                          stiffness=rd.number(s, "stiffness", p, positive=True),
                          damping=rd.number(s, "damping", p, nonnegative=True), **ramp)
        if parts[key].angle <= cam.initial_angle:
            rd.fail(p + "angle", f"{parts[key].angle:g} rad is not after the cam's initial angle ({cam.initial_angle:g} "
                    "rad): the cam angle counts on from the start (not wrapped), and the part must act after it")
        if parts[key].angle > cam.initial_angle + TWO_PI:
            rd.fail(p + "angle", f"{parts[key].angle:g} rad is more than a turn after the cam's initial angle: a closing "
                    "cam turns less than a turn, so it would never act (in degrees? angles are in rad)")
    stop, latch = parts["end_stop"], parts["hold_latch"]
    if stop is not None and latch is not None and latch.angle > stop.angle:
        rd.fail("breaker.hold_latch.angle", f"{latch.angle:g} rad is beyond the end stop's {stop.angle:g} rad: the "
                "pawl could only engage with the cam pressed into the stop; put it at or before the stop's angle")
    return stop, latch


def read_main_shaft(rd: Reader, b: dict, follower: Follower, poles: Poles) -> MainShaft | None:
    """``breaker.main_shaft``: optional (absent: a rigid shaft, not modelled); when present every
    field is required: ``pole_pitch``, ``diameter`` (m, > 0), ``bore`` (m, 0 <= bore < diameter),
    ``shear_modulus`` (Pa, > 0), ``damping`` (N m s/rad, >= 0), ``lever_inertia`` (kg m^2, > 0;
    the follower keeps ``follower.inertia`` less the other poles' levers, which must stay > 0) and
    ``drive_pole`` (whole number 1..poles.count)."""
    if "main_shaft" not in b:
        return None
    p = "breaker.main_shaft."
    s = without_comments(rd.optional_section(b, "main_shaft", "breaker.", BREAKER_KEYS["main_shaft"]))
    for name in BREAKER_KEYS["main_shaft"]:
        if name not in s:
            rd.fail(p + name, "missing: a main shaft needs pole_pitch (m), diameter (m), bore (m, 0: solid), "
                    "shear_modulus (Pa), damping (N m s/rad), lever_inertia (kg m^2) and drive_pole; leave out the "
                    "whole breaker.main_shaft section for a rigid shaft")
    shaft = MainShaft(pole_pitch=rd.number(s, "pole_pitch", p, positive=True),
                      diameter=rd.number(s, "diameter", p, positive=True),
                      bore=rd.number(s, "bore", p, nonnegative=True),
                      shear_modulus=rd.number(s, "shear_modulus", p, positive=True),
                      damping=rd.number(s, "damping", p, nonnegative=True),
                      lever_inertia=rd.number(s, "lever_inertia", p, positive=True),
                      drive_pole=rd.count(s, "drive_pole", p))
    if shaft.bore >= shaft.diameter:
        rd.fail(p + "bore", f"{shaft.bore:g} m is not smaller than the diameter ({shaft.diameter:g} m)")
    if shaft.drive_pole > poles.count:
        rd.fail(p + "drive_pole", f"{shaft.drive_pole} is not a pole: the breaker has {poles.count} (1..{poles.count})")
    rest = follower.inertia - (poles.count - 1) * shaft.lever_inertia
    if rest <= 0.0:
        rd.fail(p + "lever_inertia", f"{poles.count - 1} levers of {shaft.lever_inertia:g} kg m^2 take all of "
                f"follower.inertia ({follower.inertia:g} kg m^2, the whole assembly): nothing left for the follower")
    return shaft


#: The closing speed's default zone (m before each pole's touch): parameters.SPEED_ZONE, the records'
#: analyser's too.
DEFAULT_SPEED_ZONE = P.SPEED_ZONE


def read_speed_zone(rd: Reader, b: dict, poles: Poles) -> tuple[float, float]:
    """``breaker.speed_zone``: [start, end] in m before the touch, start > end >= 0, within the gap."""
    if "speed_zone" not in b:
        return DEFAULT_SPEED_ZONE
    zone = tuple(rd.numbers(b, "speed_zone", "breaker.", 2, None))
    if not (zone[0] > zone[1] >= 0.0):
        rd.fail("breaker.speed_zone", "must be [start, end] in m before the touch, start > end >= 0")
    if zone[0] > min(poles.contact_gap + o for o in poles.gap_offsets):
        rd.fail("breaker.speed_zone", "starts before the contacts move: it must lie within the smallest pole gap")
    return zone


def read_cam_profile(rd, cp, p, roller_radius) -> CamProfile:
    """The 4-5-6-7 profile of ``base_radius``, ``lift`` and its four angles, or a profile given by
    points of the pitch curve (``points``: [cam angle rad, roller-centre lift m] with
    ``base_radius``; or ``radius_points``: [cam angle rad, pitch radius m]), fitted by a periodic
    cubic spline and checked: a profile the roller cannot follow (undercut) is refused."""
    if "points" in cp or "radius_points" in cp or "points_file" in cp:
        return read_point_profile(rd, cp, p, roller_radius)
    profile = CamProfile(
        base_radius=rd.number(cp, "base_radius", p, positive=True), lift=rd.number(cp, "lift", p, positive=True),
        rise_start=rd.number(cp, "rise_start", p), rise_end=rd.number(cp, "rise_end", p),
        return_start=rd.number(cp, "return_start", p), return_end=rd.number(cp, "return_end", p))
    angles = (profile.rise_start, profile.rise_end, profile.return_start, profile.return_end)
    if not all(a < b_ for a, b_ in zip(angles, angles[1:])) or angles[3] > angles[0] + TWO_PI:
        rd.fail(p + "rise_start", "need rise_start < rise_end < return_start < return_end <= rise_start + 2 pi")
    return profile


#: The fields of a polynomial profile, which a profile from points takes from its points instead
POLYNOMIAL_FIELDS = ("lift", "rise_start", "rise_end", "return_start", "return_end")


def read_point_profile(rd, cp, p, roller_radius) -> CamProfile:
    key = "points" if "points" in cp else "radius_points"
    if sum(k in cp for k in ("points", "radius_points", "points_file")) > 1:
        rd.fail(p + key, "give one of points (lift), radius_points (pitch radius) or points_file, not several")
    given = "points_file" if "points_file" in cp else key
    for name in POLYNOMIAL_FIELDS:
        if name in cp:
            rd.fail(p + name, f"conflicts with {p}{given}: a profile from points takes its lift and angles from the "
                    f"points, so {name} would be ignored; leave out {', '.join(POLYNOMIAL_FIELDS)} (or the points)")
    raw = cp[key] if key in cp else None
    if "points_file" in cp:
        key, raw = read_points_file(rd, cp, p)
    field = p + ("points_file" if "points_file" in cp else key)
    pairs = check_point_pairs(rd, _point_pairs(rd, raw, field), field)
    angles = [a for a, _ in pairs]
    if key == "points":
        base = rd.number(cp, "base_radius", p, positive=True)
        radii = [base + roller_radius + v for _, v in pairs]
    else:
        radii = [v for _, v in pairs]
        if min(radii) <= roller_radius:
            rd.fail(field, f"a pitch radius at or below the roller radius ({roller_radius:g} m): the roller "
                    "centre runs outside the cam, so the pitch radius is the cam's radius plus the roller's")
    radii = settle_scatter(rd, cp, angles, radii, field)
    if key == "radius_points":
        base = min(radii) - roller_radius
        if "base_radius" in cp and abs(rd.number(cp, "base_radius", p, positive=True) - base) > 1e-5:
            rd.fail(p + "base_radius", f"{cp['base_radius']:g} m conflicts with {field}, whose smallest pitch radius "
                    f"less the roller's gives {base:.6g} m: leave base_radius out (the points give it) or correct one")
    elif min(v for _, v in pairs) < -(3.0 * rd.number(cp, "smoothing", p) if "smoothing" in cp else 1e-9):
        rd.fail(field, "a lift below the base circle (negative, beyond 3 x smoothing): lifts are measured from the base circle")
    spline = profile_spline(angles, radii)
    _refuse_undercut(rd, spline, roller_radius, field)
    lift = max(radii) - min(radii)
    return CamProfile(base_radius=base, lift=lift, rise_start=math.nan, rise_end=math.nan, return_start=math.nan,
                      return_end=math.nan, table=profile_table(spline))


def _point_pairs(rd: Reader, raw: object, field: str) -> list[tuple[float, float]]:
    """A profile's points as (angle rad, value m) pairs: a list of at least 8 [angle, value]."""
    if not isinstance(raw, list) or len(raw) < 8:
        rd.fail(field, "must be a list of at least 8 [angle, value] pairs")
    pairs = []
    for i, item in enumerate(raw):
        if not isinstance(item, list) or len(item) != 2:
            rd.fail(f"{field}.{i}", "must be a pair [angle in rad, value in m]")
        pairs.append((rd.value(item[0], f"{field}.{i}.0"), rd.value(item[1], f"{field}.{i}.1")))
    return pairs


def _refuse_undercut(rd: Reader, spline: object, roller_radius: float, field: str) -> None:
    """Refuse a pitch curve that bends tighter than the roller (m) anywhere: the cam surface would undercut."""
    cut = undercut(spline, roller_radius)
    if cut is not None:
        rd.fail(field, f"the roller cannot follow this profile: at {math.degrees(cut[0]):.1f} deg the pitch curve "
                f"bends with a radius of {1e3 * cut[1]:.2f} mm, below the {1e3 * roller_radius:g} mm roller (the cam "
                "surface would undercut); smooth the profile there or use a smaller roller")


def check_pressure_angle(rd: Reader, breaker: Breaker, cam: Cam) -> None:
    """Refuse a profile that drives the roller at a pressure angle above MAX_PRESSURE_ANGLE over
    the turn after the start (the cam would jam the follower instead of lifting it)."""
    geometry = rest_geometry(breaker, cam.pivot)
    thetas = cam.initial_angle + np.linspace(0.0, TWO_PI, 721)
    try:
        pressure = pressure_angle_curve(breaker, geometry, thetas)
    except ValueError as e:
        rd.fail("breaker.cam_profile", f"the follower cannot stay on this profile: {e}")
    k = int(np.argmax(pressure))
    if pressure[k] > MAX_PRESSURE_ANGLE:
        rd.fail("breaker.cam_profile", f"pressure angle {math.degrees(pressure[k]):.1f} deg at cam angle "
                f"{math.degrees(thetas[k]):.1f} deg, above {math.degrees(MAX_PRESSURE_ANGLE):g} deg: the cam would "
                "jam the roller rather than lift it (a longer rise or a larger base circle lowers it)")


def read_closing(rd: Reader, data: dict) -> dict:
    """``cam``, ``closing_spring`` and ``breaker`` of a ``vcb_closing`` rig."""
    sections = read_cam_and_spring(rd, data)
    sections["breaker"] = read_breaker(rd, data, sections["cam"])
    return sections

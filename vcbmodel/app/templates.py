"""``vcbmodel init KIND``: a rig file to start from, commented, that simulates as written, and
``vcbmodel check RIG``: what a rig would simulate, explained, without solving it.

JSON has no comments; keys starting with ``_`` are free comments wherever they appear in a rig
(docs/rig-format.md), so the templates carry their explanations as ``_about`` and ``_units`` keys.
"""
from __future__ import annotations

import copy
import json
import math
from typing import TYPE_CHECKING

import numpy as np

from .. import parameters as P
from ..experiments.cycle_evaluation import cycle_check_lines
from ..experiments import experiment_of
from ..experiments.simulation import model_spec
from ..rig.limits import OPENING_LIMITS
from ..rig.plausibility import reachable_travel, travel_curve
from ..model.effects import EFFECTS, parameter_specs
from ..model.values import rig_values
from ..laws.breaker import segment_stiffness, torsional_frequencies
from ..laws.cam_follower import pressure_angle_curve, rest_geometry
from ..laws.coil import spring_check
from ..laws.spring_strength import closing_pulls, compression_reading, extension_checks, wire_for_index
from ..laws.mechanics import cam_pin

if TYPE_CHECKING:
    from ..rig.data import Rig

#: What each section's numbers mean (units), written into the templates as ``_units``.
SECTION_UNITS = {
    "shaft": "radius: m (journal radius of the cam shaft, where the friction acts)",
    "pendulum": "mass: kg; inertia: kg m^2 about the shaft; com_distance: m; initial_angle: rad from hanging; "
                "initial_velocity: rad/s",
    "cam": "mass: kg; inertia_com: kg m^2 about its centre of mass; com_distance: m; com_angle: rad; pivot: [x, y] m "
           "of the cam shaft's axis; arm_length: m, axis to the closing spring's pin; initial_angle: rad of the arm "
           "from +x; initial_velocity: rad/s",
    "closing_spring": "count: springs acting together; stiffness: N/m each; mass: kg each (active coils); "
                      "free_length: m; anchor: [x, y] m; or the datasheet instead of stiffness and mass: "
                      "wire_diameter, coil_diameter (mean): m; active_coils; shear_modulus: Pa; density: kg/m^3; "
                      "ends: hooks or plugs (screwed-in plug ends: no hook to check)",
    "friction": "mu_k, mu_s: -; stick_velocity, stribeck_velocity: rad/s; viscous: N m s/rad",
    "model": "effects: names (docs/rig-format.md section 4); spring_model: massless | lumped-N | ancf",
    "breaker": "roller_radius: m; speed_zone: [start, end] m before each pole's touch; the subsections below say "
               "their own units (docs/rig-format.md section 3.8)",
    "cam_profile": "base_radius: m (the cam's base circle); lift: m (the roller centre's rise); rise_start, rise_end, "
                   "return_start, return_end: rad of cam turn (a profile from points instead: points_file)",
    "follower": "pivot: [x, y] m; inertia: kg m^2 about the pivot (follower, main shaft and pole levers); roller_arm, "
                "output_arm: m; output_angle, rest_angle: rad",
    "poles": "count; moving_mass: kg per pole; contact_gap: m; gap_offsets: m per pole; push_rod_length: m; "
             "wipe_preload: N; wipe_rate: N/m; rod_stiffness: N/m; rod_damping: N s/m; bellows_force: N",
    "opening_spring": "stiffness: N/m; preload: N when open; length: m, its anchor to the output point when open",
    "contact": "cam_roller_stiffness, pole_stiffness: N/m^exponent (Hertz); exponent: -; restitution: -; "
               "min_impact_speed: m/s; roller_width: m; cam_roller_law: point | line; cam_roller_damping: "
               "lankarani_nikravesh | hunt_crossley; cam_roller_damping_factor: s/m",
    "latch": "release_time: s; arm: m; angle: rad",
    "end_stop": "angle: rad of cam turn, counted on from the start (not wrapped); arm: m; stiffness: N/m; "
                "damping: N s/m",
    "hold_latch": "angle: rad of cam turn, counted on from the start (not wrapped); arm: m; stiffness: N/m; "
                  "damping: N s/m",
    "main_shaft": "pole_pitch, diameter, bore: m; shear_modulus: Pa (steel 79.3e9); damping: N m s/rad per "
                  "segment; lever_inertia: kg m^2 per pole lever; drive_pole: 1..count",
    "limits": "acceptance limits, one per figure (docs/rig-format.md section 3.8): each states its own unit",
}
#: The ``_units`` comment of each limit in ``breaker.limits``.
LIMIT_UNITS = "min, max: in the unit named by unit (required); source: where the limit comes from"
#: Fields that hold angles (rad): each gets a comment with its value in degrees in the templates
ANGLE_FIELDS = ("initial_angle", "com_angle", "rise_start", "rise_end", "return_start", "return_end",
                "output_angle", "rest_angle", "angle")


def _template_cam(reference: dict) -> dict:
    """A template's cam and closing spring: the breaker's cam with the template spring, whose datasheet
    passes the strength checks (``parameters.TEMPLATE_CLOSING_SPRING``)."""
    return dict(reference, cam=copy.deepcopy(P.REFERENCE_BREAKER["cam"]),
                closing_spring=copy.deepcopy(P.TEMPLATE_CLOSING_SPRING))


TEMPLATES = {
    "pendulum": lambda: dict(copy.deepcopy(P.REFERENCE_PENDULUM), friction=dict(P.REFERENCE_PENDULUM_TRUTH),
                             name="my pendulum test"),
    "cam_drop": lambda: dict(_template_cam(copy.deepcopy(P.REFERENCE_CAM)), name="my cam drop"),
    "vcb_closing": lambda: dict(_template_cam(copy.deepcopy(P.REFERENCE_BREAKER)), name="my breaker's closing"),
}


def commented(key: str, value: object, parent: str = "") -> object:
    """A section with its ``_units`` comment first and a degree hint (``_FIELD``: "... = N deg") after each
    angle, its subsections (``breaker``'s, each limit) commented alike; other values as they are."""
    if not isinstance(value, dict):
        return value
    units = LIMIT_UNITS if parent == "limits" else SECTION_UNITS.get(key)
    out = {"_units": units} if units else {}
    for name, v in value.items():
        out[name] = commented(name, v, key)
        if name in ANGLE_FIELDS and isinstance(v, (int, float)):
            out[f"_{name}"] = f"{v:.6g} rad = {math.degrees(v):.2f} deg (angles are in rad)"
    return out


def template(kind: str) -> str:
    """The commented template of an experiment kind, as JSON text."""
    data = TEMPLATES[kind]()
    record = experiment_of(kind)
    out = {"_about": f"vcbmodel rig file: {record.description}. Every number is in SI units; keys starting with _ are "
                     "comments. Edit the values for your machine; docs/rig-format.md describes every field. "
                     "The values here are the documented reference ones (vcbmodel/parameters.py); the closing "
                     "spring is given by its datasheet (parameters.TEMPLATE_CLOSING_SPRING), within its allowables."
                     if record.has_closing_spring else
                     f"vcbmodel rig file: {record.description}. Every number is in SI units; keys starting with _ are "
                     "comments. Edit the values for your machine; docs/rig-format.md describes every field. "
                     "The values here are the documented reference ones (vcbmodel/parameters.py)."}
    for key, value in data.items():
        out[key] = commented(key, value)
    return json.dumps(out, indent=2) + "\n"


def closing_stroke(b, cam) -> tuple[float, str]:
    """The cam angle (rad) where the closing stroke ends, and why: the end stop's angle, or (without
    one) where the poles' travel peaks over the turn from the start."""
    if b.end_stop is not None:
        return b.end_stop.angle, "to the end stop"
    thetas = cam.initial_angle + np.linspace(0.0, 2 * np.pi, 361)
    return float(thetas[int(np.argmax(travel_curve(b, cam, thetas)))]), "to the largest lift"


def pressure_lines(rig: Rig) -> list[str]:
    """The largest pressure angle over the closing stroke (what the closing runs: from the start to the
    end stop, or to the largest lift), against the usual 30 deg, and over the rest of the turn, which
    a closing never runs (a return flank)."""
    b, cam = rig.breaker, rig.cam
    end, why = closing_stroke(b, cam)
    geometry = rest_geometry(b, cam.pivot)
    stroke = cam.initial_angle + np.linspace(0.0, end - cam.initial_angle, 361)
    rest = np.linspace(end, cam.initial_angle + 2 * np.pi, 361)
    lines = []
    for thetas, what in ((stroke, f"over the closing stroke (cam angle {np.degrees(stroke[0]):.1f} to "
                                  f"{np.degrees(end):.1f} deg, {why})"), (rest, "over the rest of the turn (not run "
                                                                               "in a closing)")):
        pressure = np.degrees(pressure_angle_curve(b, geometry, thetas))
        k = int(np.argmax(pressure))
        verdict = "" if pressure[k] <= P.USUAL_PRESSURE_ANGLE or what.startswith("over the rest") else (
            f": ABOVE the usual {P.USUAL_PRESSURE_ANGLE:g} deg (a longer rise or a larger base circle lowers it)")
        lines.append(f"    largest pressure angle {what}: {pressure[k]:.1f} deg at cam angle "
                     f"{np.degrees(thetas[k]):.1f} deg{verdict}")
    return lines


def cam_lines(rig: Rig) -> list[str]:
    """The cam as a designer checks it: where its profile comes from, the largest pressure angle over
    the closing stroke (usual limit 30 deg) and over the rest of the turn (above 45 deg a profile from
    points is refused), the speed zone, the stops and the main shaft."""
    b = rig.breaker
    smoothing = rig.data["breaker"]["cam_profile"].get("smoothing")
    points = rig.data["breaker"]["cam_profile"].get("points_file")
    through = (f"a smoothing spline (within about {1e6 * smoothing:g} um, breaker.cam_profile.smoothing) of"
               if smoothing else "a spline through")
    where = f"the points in {points}" if points else "the rig's points"
    source = (f"{len(b.profile.table) // 2}-sample table of {through} {where}" if b.profile.table
              else "4-5-6-7 polynomial rise, dwell and return")
    return ([f"  cam profile: {source}; lift {1e3 * b.profile.lift:.2f} mm, base circle {1e3 * b.profile.base_radius:.1f} "
             f"mm, roller {1e3 * b.roller_radius:g} mm; the poles travel up to {1e3 * reachable_travel(b, rig.cam):.2f} mm "
             f"(gap {1e3 * b.poles.contact_gap:g} mm)"]
            + pressure_lines(rig)
            + [f"  closing speed: mean pole speed from {1e3 * b.speed_zone[0]:g} to {1e3 * b.speed_zone[1]:g} mm before "
               "each pole's touch (breaker.speed_zone)"] + stop_lines(b) + shaft_lines(b) + cycle_check_lines(b)
            + limit_lines(b))


def limit_lines(b) -> list[str]:
    """The acceptance limits ``simulate`` will judge (``breaker.limits``), each as stated with its unit:
    a closing's, then an opening's (judged by ``simulate --sequence``)."""
    if not b.limits:
        return ["  limits: none given (breaker.limits): simulate judges no figure"]
    closing = [lim for lim in b.limits if lim.figure not in OPENING_LIMITS]
    opening = [lim for lim in b.limits if lim.figure in OPENING_LIMITS]
    return ([f"  limits simulate judges (breaker.limits): {_stated(closing)}"] if closing else []) + \
        ([f"  limits on the opening, judged by simulate --sequence on each O and CO (breaker.limits): {_stated(opening)}"]
         if opening else [])


def _stated(limits: list) -> str:
    return "; ".join(f"{lim.figure.replace('_', ' ')} {lim.text()}" for lim in limits)


def shaft_lines(b) -> list[str]:
    """The main shaft (``breaker.main_shaft``): each segment's torsional stiffness and the first
    torsional frequency estimate (:func:`vcbmodel.laws.breaker.torsional_frequencies`), or that the
    shaft is rigid."""
    shaft = b.main_shaft
    if shaft is None:
        return ["  main shaft: rigid, not modelled (no breaker.main_shaft section): every push rod on the follower"]
    freqs = torsional_frequencies(shaft, b.poles, b.follower.output_arm)
    first = (f"first torsional frequency about {freqs[0]:.0f} Hz (the pole levers with their poles' mass, the drive "
             "lever held)" if freqs.size else "one pole: no segment twists")
    return [f"  main shaft: {1e3 * shaft.diameter:g} mm (bore {1e3 * shaft.bore:g} mm), pole levers "
            f"{1e3 * shaft.pole_pitch:g} mm apart, driven at pole {shaft.drive_pole}; segment stiffness "
            f"{segment_stiffness(shaft):.4g} N m/rad, damping {shaft.damping:g} N m s/rad; {first}"]


def stop_lines(b) -> list[str]:
    """What stops the cam after the closing: the end stop and the holding latch, or that the rig
    leaves them out (then nothing stops the cam, and overtravel and rebound are not dynamics)."""
    lines = []
    for part, key, what in ((b.end_stop, "end_stop", "end stop"), (b.hold_latch, "hold_latch", "holding latch")):
        if part is None:
            lines.append(f"  {what}: not modelled (no breaker.{key} section): "
                         + ("nothing stops the cam after the closing; it turns on until the springs turn it back"
                            if key == "end_stop" else "nothing holds the cam from turning back"))
        else:
            ramp = getattr(part, "damping_depth", 0.0)
            lines.append(f"  {what}: at cam angle {part.angle:g} rad ({math.degrees(part.angle):.1f} deg), arm "
                         f"{1e3 * part.arm:g} mm, {part.stiffness:.4g} N/m, {part.damping:.4g} N s/m (breaker.{key})"
                         + ("; it engages once the cam passes that angle and then stops it turning back"
                            if key == "hold_latch" else
                            f"; its damping builds up over the first {1e3 * ramp:g} mm" if ramp > 0 else
                            "; its damping acts in full from the first contact"))
    return lines


def spring_lines(rig: Rig) -> list[str]:
    """The closing spring as a designer checks it: rate, mass and surge frequency (with their source),
    the charged pull and the coil, then the spring maker's checks (:func:`strength_lines`)."""
    s = rig.closing_spring
    bx, by = cam_pin(rig.cam.initial_angle, rig.cam)
    pull = s.stiffness * (math.hypot(bx - s.anchor[0], by - s.anchor[1]) - s.free_length)
    c = spring_check(s, pull)

    def source(key):
        if key not in s.from_datasheet:
            return "given"
        if key == "mass" and s.density is None:  # say the density the mass rests on: the rig did not give it
            return f"from the datasheet, at steel's {P.STEEL_DENSITY:g} kg/m^3: no density given"
        return "from the datasheet"

    coil = (f"wire {1e3 * c['wire_diameter_m']:.2f} mm on a {1e3 * c['coil_diameter_m']:.1f} mm mean diameter "
            f"(index {c['coil_diameter_m'] / c['wire_diameter_m']:.3g})"
            if c["coil_given"] else
            f"no coil given: the lightest coil of this k0 and m0 at index {c['coil_diameter_m'] / c['wire_diameter_m']:g}, "
            f"wire {1e3 * c['wire_diameter_m']:.2f} mm")
    # the body's stress is judged once, in the spring maker's checks below (Bergstrasser's factor)
    return [f"  closing spring ({s.count} alike): k0 {s.stiffness:.6g} N/m ({source('stiffness')}), active mass "
            f"{s.mass:.4g} kg ({source('mass')}), surge frequency {c['surge_frequency_hz']:.1f} Hz",
            f"    charged pull {pull:.0f} N each; {coil}"] + strength_lines(rig, c) + ([
            "    (the rig's coil fields size the stress check and an ANCF spring only: with stiffness and mass given, "
            "they do not change k0 or the mass)"] if c["coil_given"] and not s.from_datasheet else [])


def strength_lines(rig: Rig, c: dict) -> list[str]:
    """The closing spring as an extension spring with standard hooks (``closing_spring.ends`` "plugs":
    screwed-in plug ends, the body alone), checked as a spring maker would
    (laws.spring_strength: body, hooks, fatigue over the rated operations, initial tension) over one
    closing's pulls, each with its allowable; then what the lightest spring of this rate that passes
    would weigh."""
    s = rig.closing_spring
    high, low = closing_pulls(s, rig.cam)
    d, D = c["wire_diameter_m"], c["coil_diameter_m"]
    plugs = s.ends == "plugs"  # no bent hook: its stresses are not there to check
    checks = extension_checks(d, D, high, low, hooks=not plugs)
    failed = [k.name for k in checks if k.fails]
    strength = sum(not k.advisory for k in checks)
    ends = "screwed-in plug ends" if plugs else "standard hooks"
    lines = [f"    as an extension spring ({ends}, Cr-Si wire) cycling {low:.0f}-{high:.0f} N "
             f"{P.RATED_OPERATIONS} times (IEC 62271-100 class M2): "
             + (f"FAILS {len(failed)} of {strength} strength checks" if failed else f"passes all {strength} strength checks")
             + ("" if all(k.passes for k in checks if k.advisory) else " (and asks for a specified initial tension)")]
    for k in checks:
        value = (f"{k.value / 1e6:.0f} MPa against {k.allowable / 1e6:.0f} MPa" if k.unit == "Pa" else
                 f"factor of safety {k.value:.2f} (at least 1)" if k.unit == "-" else
                 f"{k.value:.0f} N at most {k.allowable:.0f} N")
        verdict = "ok" if k.passes else "FAILS" if k.fails else "SPECIFY an initial tension below the smallest pull"
        lines.append(f"      {k.name}: {value} ({k.source}) {verdict}")
    if failed:
        index = min(max(D / d, 4.0), 12.0)
        found = [(what, wire_for_index(index, s.stiffness, high, low, hooks=hooks))
                 for what, hooks in (("standard hooks", True), ("screwed-in plug ends (no hook stress)", False))]
        lines.append(f"      the thinnest wire that passes at this k0 and index {index:.3g}: "
                     + "; ".join(f"{what} {1e3 * b['wire_diameter_m']:.2f} mm on {1e3 * b['coil_diameter_m']:.1f} mm, "
                                 f"{b['active_coils']:.1f} active coils, {b['mass_kg']:.2f} kg active mass"
                                 for what, b in found))
    return lines + [compression_line(c, high, s.shear_modulus or P.DEFAULT_SHEAR_MODULUS)]


def compression_line(c: dict, high: float, shear_modulus: float) -> str:
    """The same coil read as a compression spring (laws.spring_strength.compression_reading): its body
    against 0.65 S_ut, and where it buckles unguided; a guide holds it, and with it the lateral motion.
    Its active coils are those of its rate k0 in the wire's ``shear_modulus`` (Pa; the rig's, as for
    the stress check)."""
    d, D = c["wire_diameter_m"], c["coil_diameter_m"]
    n_a = shear_modulus * d**4 / (8.0 * D**3 * c["stiffness_N_m"])
    r = compression_reading(d, D, n_a, c["stiffness_N_m"], high)
    ends = ", ".join(f"{end} ends {'never' if math.isinf(y) else f'at {1e3 * y:.0f} mm'}"
                     for end, y in ((e, r[f"buckles_at_{e}_m"]) for e in P.BUCKLING_END_CONSTANTS))
    guided = any(r[f"buckles_at_{e}_m"] < r["deflection_m"] for e in P.BUCKLING_END_CONSTANTS)
    return (f"    read as a compression spring instead: body {r['body_stress_Pa'] / 1e6:.0f} MPa against 0.65 S_ut = "
            f"{r['allowable_Pa'] / 1e6:.0f} MPa; free length {1e3 * r['free_length_m']:.0f} mm, compressed "
            f"{1e3 * r['deflection_m']:.0f} mm (y/L0 {r['deflection_ratio']:.2f}); unguided it buckles ({ends}, "
            "Shigley eq. 10-10)" + ("; it needs a guide rod or tube, which also holds the coil's lateral motion"
                                    if guided else ""))


def value_lines(rig: Rig) -> list[str]:
    """What the plausibility check (:mod:`vcbmodel.rig.plausibility`) says of the rig's values: each
    unusual value (its unit to check), or that all lie in their usual ranges; and that every run's
    energy balance is checked."""
    head = (f"  values: {len(rig.warnings)} unusual (possible, but check the unit):" if rig.warnings else
            "  values: every one within its usual range (docs/rig-format.md 3.11)")
    return ([head] + [f"    {w}" for w in rig.warnings]
            + ["  every run's energy balance is checked: a run that creates energy fails (exit 1)"])


def explain(rig: Rig) -> list[str]:
    """Lines saying what ``simulate`` would run for ``rig``, where each value comes from, and what
    it reports; a value the model needs but the rig lacks raises InputError, as simulate would."""
    record = experiment_of(rig.experiment)
    spec = model_spec(rig)
    from_rig = rig_values(rig)
    lines = [f"{rig.path}: a valid {rig.experiment} rig ({rig.name!r})", f"  {record.description}",
             f"  model: {', '.join(spec.effects) or 'no effects'}; spring {spec.spring_model.label}"]
    for p in parameter_specs(spec.effects):
        source = "rig" if p.name in from_rig else "documented default"
        lines.append(f"    {p.name} = {getattr(spec, p.name, from_rig.get(p.name, p.default))!s} {p.unit} "
                     f"({source}; effect {next(e for e in EFFECTS if p in EFFECTS[e].parameters)})")
    off = [name for name, e in EFFECTS.items() if e.acts_on(rig.provides) and name not in spec.effects]
    if off:
        lines.append(f"  effects left out (candidates for vcbmodel diagnose): {', '.join(off)}")
    if record.has_closing_spring:
        lines += spring_lines(rig)
    if rig.breaker is not None:
        lines += cam_lines(rig)
    lines += value_lines(rig)
    lines.append(f"  simulate runs {record.default_duration:g} s at a fixed step of {record.step(rig):g} s and "
                 f"writes {record.measured_channel} ({record.unit}) at {record.sample_rate:g} samples/s")
    lines.append(f"  it reports: {', '.join(name for name, _ in record.figure_units)}")
    return lines

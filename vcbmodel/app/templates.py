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
from ..experiments import experiment_of
from ..experiments.simulation import model_spec
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
           "of the closing spring's lever pivot; arm_length: m; initial_angle: rad; initial_velocity: rad/s",
    "closing_spring": "count: springs acting together; stiffness: N/m each; mass: kg each; free_length: m; "
                      "anchor: [x, y] m",
    "friction": "mu_k, mu_s: -; stick_velocity, stribeck_velocity: rad/s; viscous: N m s/rad",
    "model": "effects: names (docs/rig-format.md section 4); spring_model: massless | lumped-N | ancf",
    "breaker": "SI units throughout (m, kg, N, N/m, rad, s); every field in docs/rig-format.md section 3.8",
}
TEMPLATES = {
    "pendulum": lambda: dict(copy.deepcopy(P.REFERENCE_PENDULUM), friction=dict(P.REFERENCE_PENDULUM_TRUTH),
                             name="my pendulum test"),
    "cam_drop": lambda: dict(copy.deepcopy(P.REFERENCE_CAM), name="my cam drop"),
    "vcb_closing": lambda: dict(copy.deepcopy(P.REFERENCE_BREAKER), name="my breaker's closing"),
}


def template(kind: str) -> str:
    """The commented template of an experiment kind, as JSON text."""
    data = TEMPLATES[kind]()
    record = experiment_of(kind)
    out = {"_about": f"vcbmodel rig file: {record.description}. Every number is in SI units; keys starting with _ are "
                     "comments. Edit the values for your machine; docs/rig-format.md describes every field. "
                     "The values here are the documented reference ones (vcbmodel/parameters.py)."}
    for key, value in data.items():
        if isinstance(value, dict) and key in SECTION_UNITS:
            value = {"_units": SECTION_UNITS[key], **value}
        out[key] = value
    return json.dumps(out, indent=2) + "\n"


def cam_lines(rig: Rig) -> list[str]:
    """The cam as a designer checks it: where its profile comes from, the largest pressure angle over
    the turn from the start (limit 30 deg usual, 45 deg refused) and the roller's clearance."""
    b, cam = rig.breaker, rig.cam
    thetas = cam.initial_angle + np.linspace(0.0, 2 * np.pi, 721)
    pressure = pressure_angle_curve(b, rest_geometry(b, cam.pivot), thetas)
    k = int(np.argmax(pressure))
    smoothing = rig.data["breaker"]["cam_profile"].get("smoothing")
    points = rig.data["breaker"]["cam_profile"].get("points_file")
    through = (f"a smoothing spline (within about {1e6 * smoothing:g} um, breaker.cam_profile.smoothing) of"
               if smoothing else "a spline through")
    where = f"the points in {points}" if points else "the rig's points"
    source = (f"{len(b.profile.table) // 2}-sample table of {through} {where}" if b.profile.table
              else "4-5-6-7 polynomial rise, dwell and return")
    return [f"  cam profile: {source}; lift {1e3 * b.profile.lift:.2f} mm, base circle {1e3 * b.profile.base_radius:.1f} mm, "
            f"roller {1e3 * b.roller_radius:g} mm",
            f"    largest pressure angle {np.degrees(pressure[k]):.1f} deg at cam angle {np.degrees(thetas[k]):.1f} deg "
            f"(usual limit 30 deg; above 45 deg a profile is refused)",
            f"  closing speed: mean pole speed from {1e3 * b.speed_zone[0]:g} to {1e3 * b.speed_zone[1]:g} mm before each "
            "pole's touch (breaker.speed_zone)"] + stop_lines(b) + shaft_lines(b)


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
        return "from the datasheet" if key in s.from_datasheet else "given"

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
    """The closing spring as an extension spring with standard hooks, checked as a spring maker would
    (laws.spring_strength: body, hooks, fatigue over the rated operations, initial tension) over one
    closing's pulls, each with its allowable; then what the lightest spring of this rate that passes
    would weigh."""
    s = rig.closing_spring
    high, low = closing_pulls(s, rig.cam)
    d, D = c["wire_diameter_m"], c["coil_diameter_m"]
    checks = extension_checks(d, D, high, low)
    failed = [k.name for k in checks if not k.passes]
    lines = [f"    as an extension spring (standard hooks, Cr-Si wire) cycling {low:.0f}-{high:.0f} N "
             f"{P.RATED_OPERATIONS} times (IEC 62271-100 class M2): "
             + (f"FAILS {len(failed)} of {len(checks)} checks" if failed else f"passes all {len(checks)} checks")]
    for k in checks:
        value = (f"{k.value / 1e6:.0f} MPa against {k.allowable / 1e6:.0f} MPa" if k.unit == "Pa" else
                 f"factor of safety {k.value:.2f} (at least 1)" if k.unit == "-" else
                 f"{k.value:.0f} N at most {k.allowable:.0f} N")
        lines.append(f"      {k.name}: {value} ({k.source}) {'ok' if k.passes else 'FAILS'}")
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
    off = [name for name, e in EFFECTS.items() if rig.experiment in e.experiments and name not in spec.effects]
    if off:
        lines.append(f"  effects left out (candidates for vcbmodel diagnose): {', '.join(off)}")
    if record.has_closing_spring:
        lines += spring_lines(rig)
    if rig.breaker is not None:
        lines += cam_lines(rig)
    lines.append(f"  simulate runs {record.default_duration:g} s at a fixed step of {record.step(rig):g} s and "
                 f"writes {record.measured_channel} ({record.unit}) at {record.sample_rate:g} samples/s")
    lines.append(f"  it reports: {', '.join(name for name, _ in record.figure_units)}")
    return lines

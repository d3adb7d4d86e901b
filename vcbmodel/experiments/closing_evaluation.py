"""Evaluation of a whole-breaker closing from its recorded states: the channels (forces,
penetrations, pressure angle replayed from the states), the figures of merit and the energy
balance. Pure numpy on a :class:`vcbmodel.model.result.SimulationResult`; the forces come
from :class:`vcbmodel.laws.breaker.BreakerLaws`, as in the Exudyn model.
"""
from __future__ import annotations

from typing import TYPE_CHECKING
import numpy as np
from scipy.integrate import cumulative_trapezoid

from .. import parameters as P
from ..laws.breaker import (BreakerLaws, cam_roller_contact, follower_displacement, one_way_stop_energy, pole_gaps,
                            push_rod_energy)
from ..laws.cam_follower import pitch_radius, rest_geometry, roller_centre
from ..laws.cycle import NEVER, open_angle
from ..laws.friction import ArrayOps
from ..laws.mechanics import cam_pin
from ..laws.springs import chain_for
from ..records.analyser import travel_figures
from .cycle_evaluation import cycle_channels, kinetic_margin, opening_figures, release_figures, trip_instant

if TYPE_CHECKING:
    from ..model.effects import ModelSpec
    from ..model.result import SimulationResult
    from ..rig.data import Rig


def closing_channels(data: dict[str, np.ndarray], rig: Rig, spec: ModelSpec, info: dict) -> dict[str, np.ndarray]:
    """Channels of a closing from sensor rows (either backend): cam and follower angles (rad)
    and speeds (rad/s), ``follower_displacement`` (m, the measured channel), pole travels (m)
    and speeds (m/s), spring points, shaft friction, and the contact forces of
    :func:`contact_channels`."""
    b = rig.breaker
    ch = {"cam_angle": data["angle"][:, 1], "shaft_velocity": data["velocity"][:, 1],
          "follower_angle": data["follower_angle"][:, 1], "follower_velocity": data["follower_velocity"][:, 1]}
    if "friction_torque" in data:
        ch["friction_torque"] = -data["friction_torque"][:, 1]
    ch["follower_displacement"] = follower_displacement(ch["follower_angle"], b.follower, open_angle(info["initial"]))
    n = b.poles.count
    for i in range(n):
        ch[f"pole_{i + 1}_travel"] = data[f"pole_{i + 1}_travel"][:, 1]
        if f"pole_{i + 1}_lever_angle" in data:
            ch[f"pole_{i + 1}_lever_angle"] = data[f"pole_{i + 1}_lever_angle"][:, 1]
            ch[f"pole_{i + 1}_lever_velocity"] = data[f"pole_{i + 1}_lever_velocity"][:, 1]
        ch[f"pole_{i + 1}_velocity"] = data[f"pole_{i + 1}_travel_velocity"][:, 1]
    for name, d in data.items():
        if name.startswith(("spring_mass_", "spring_velocity_", "ancf_node_")):
            ch[name + "_x"], ch[name + "_y"] = d[:, 1], d[:, 2]
    laws = BreakerLaws.of_rig(rig, spec)
    ch.update(contact_channels(laws, ch, n))
    ch.update(cycle_channels(laws, ch, data["angle"][:, 0], open_angle(info["initial"])))
    return ch


def lever_channels(laws: BreakerLaws, ch: dict[str, np.ndarray]) -> tuple[list, list]:
    """Every pole lever's angle (rad) and speed (rad/s) over the record, in pole order: the
    follower's for the drive pole's lever (and for every pole on a rigid shaft), the recorded
    ``pole_{j}_lever_angle`` and ``_velocity`` for the others (``breaker.main_shaft``)."""
    psi = [ch[f"pole_{j + 1}_lever_angle"] for j in laws.free_levers]
    psi_dot = [ch[f"pole_{j + 1}_lever_velocity"] for j in laws.free_levers]
    return laws.lever_angles(ch["follower_angle"], psi), laws.lever_angles(ch["follower_velocity"], psi_dot)


def contact_channels(laws: BreakerLaws, ch: dict[str, np.ndarray], n: int) -> dict[str, np.ndarray]:
    """Cam-roller force, pole contact forces and rod forces (N), penetrations (m), with the
    impact speeds replayed over the samples (exact when sampled at every step): the laws
    evaluated on the whole record at once (``ArrayOps``)."""
    ops = ArrayOps
    th, w, phi, phid = ch["cam_angle"], ch["shaft_velocity"], ch["follower_angle"], ch["follower_velocity"]
    with np.errstate(all="ignore"):
        c = cam_roller_contact(th, w, phi, phid, laws.b, laws.geometry, ops)
        impact = latched_impact_speeds(c.penetration, c.penetration_rate)
        force = laws.roller_force(c.penetration, c.penetration_rate, impact, ops)
        elastic = laws.roller_stiffness * np.power(np.maximum(c.penetration, 0.0), laws.roller_exponent)
        out = {"cam_roller_force": force, "cam_roller_penetration": c.penetration,
               "cam_roller_penetration_rate": c.penetration_rate, "pressure_angle": c.pressure_angle,
               # damping force = total - elastic (with the clip at zero: -elastic while the roller leaves)
               "cam_roller_damping_force": np.where(c.penetration > 0, force - elastic, 0.0)}
        contact = laws.b.contact
        lever, lever_dot = lever_channels(laws, ch)
        for i in range(n):
            z, zd = ch[f"pole_{i + 1}_travel"], ch[f"pole_{i + 1}_velocity"]
            pen = z - laws.gaps[i]
            f = laws.pole_contact(i, z, zd, latched_impact_speeds(pen, zd), ops)
            pole_elastic = contact.pole_stiffness * np.power(np.maximum(pen, 0.0), contact.exponent)
            s, rate, _, rod = laws.rod(lever[i], lever_dot[i], z, zd, ops)
            out.update({f"pole_{i + 1}_contact_force": f,
                        f"pole_{i + 1}_contact_damping_force": np.where(pen > 0, f - pole_elastic, 0.0),
                        f"pole_{i + 1}_rod_force": rod, f"pole_{i + 1}_rod_compression": s,
                        f"pole_{i + 1}_rod_rate": rate})
        out.update(stop_channels(laws, th, w))
    return {name: np.asarray(v, float) * np.ones(len(th)) for name, v in out.items()}


def stop_channels(laws: BreakerLaws, theta: np.ndarray, omega: np.ndarray) -> dict[str, np.ndarray]:
    """The end stop's and the holding latch's channels, for the parts the rig has: force (N) and
    penetration (m, at the arm) of each, and the latch's engagement (0/1) replayed over the
    samples (:func:`vcbmodel.laws.breaker.hold_latch_engagement`: engaged from the first sample
    at or past its angle)."""
    out = {}
    stop, latch = laws.b.end_stop, laws.b.hold_latch
    if stop is not None:
        out["end_stop_penetration"] = stop.arm * (theta - stop.angle)
        out["end_stop_force"] = laws.end_stop(theta, omega, ArrayOps)
    if latch is not None:
        engaged = np.maximum.accumulate(theta >= latch.angle).astype(float)
        out["hold_latch_engaged"] = engaged
        out["hold_latch_penetration"] = np.where(engaged > 0.5, latch.arm * (latch.angle - theta), 0.0)
        out["hold_latch_force"] = laws.hold_latch(theta, omega, engaged, ArrayOps)
    return out


def latched_impact_speeds(penetration: np.ndarray, rate: np.ndarray) -> np.ndarray:
    """The impact speed (m/s) a contact's damping uses at each sample: the approach speed
    max(rate, 0) at the last sample, up to this one, where the contact was open
    (:func:`vcbmodel.laws.breaker.update_impact_speeds` replayed over a record); 0 before any."""
    open_at = np.where(penetration <= 0.0, np.arange(len(penetration)), -1)
    last_open = np.maximum.accumulate(open_at)
    return np.where(last_open >= 0, np.maximum(rate[np.maximum(last_open, 0)], 0.0), 0.0)


def energy_parts(result: SimulationResult, rig: Rig) -> dict:
    """Every term of a closing's energy (J) as a time series, by where it sits: kinetic energy of
    the cam (with the springs' pin mass), the closing springs' chain, the follower and the poles;
    potential energy of the closing springs, the cam's weight, the springs' weight, the opening
    spring, the push rods and wipe springs, the contacts and the poles' loads (bellows minus
    weight), the end stop and the holding latch (their springs); dissipated (cumulative) in the
    shaft friction, the contacts' damping and the rods' damping, and the end stop's and the holding
    latch's dampers; and the latch's work. The stop and latch terms are zero when the rig leaves
    them out. Massless or lumped springs (ANCF: not covered)."""
    ch, t = result.channels, result.t
    laws = BreakerLaws.of_rig(rig, result.spec)
    chain = chain_for(rig.closing_spring, result.spec.spring_model)
    b, cam = rig.breaker, rig.cam
    th, w, phid = ch["cam_angle"], ch["shaft_velocity"], ch["follower_velocity"]
    parts = {"kinetic_cam": 0.5 * cam.inertia_pivot * w**2, "kinetic_follower": 0.5 * laws.follower_inertia * phid**2}
    parts.update(_shaft_parts(ch, laws, t))
    parts.update(_spring_parts(ch, rig, chain))
    parts["cam_weight"] = cam.mass * rig.gravity * cam.com_distance * np.sin(th - cam.com_angle)
    parts["opening_spring"] = 0.5 * b.opening_spring.stiffness * (laws.opening(ch["follower_angle"], ArrayOps)[0]
                                                                  / b.opening_spring.stiffness) ** 2
    parts.update(_pole_parts(ch, laws, b))
    friction = -ch["friction_torque"] * w if "friction_torque" in ch else np.zeros_like(th)
    parts["dissipated_friction"] = cumulative_trapezoid(friction, t, initial=0.0)
    damping = parts.pop("contact_damping_rate") + parts.pop("rod_damping_rate")
    parts["dissipated_damping"] = cumulative_trapezoid(damping, t, initial=0.0)
    parts.update(_stop_parts(ch, b, t))
    holding = result.info["initial"].holding_torque
    shift = NEVER if b.commands is not None and not b.commands.close else 0.0  # an O's closing latch holds
    with np.errstate(all="ignore"):  # the latch law's unchosen branch
        latch = laws.latch(t - shift, holding, ArrayOps)
    parts["latch_work"] = cumulative_trapezoid(latch * w, t, initial=0.0)
    power = ch.get("cycle_power")
    parts["cycle_work"] = cumulative_trapezoid(power, t, initial=0.0) if power is not None else np.zeros_like(t)
    return parts


def _spring_parts(ch, rig, chain):
    """The closing springs' elastic energy, the chain's kinetic energy (the pin's share rides on the
    cam) and, with ``closing_spring.weight``, their weight's potential energy (J)."""
    cam, spring, g = rig.cam, rig.closing_spring, rig.gravity
    c, th, w = spring.count, ch["cam_angle"], ch["shaft_velocity"]
    bx, by = cam_pin(th, cam, ArrayOps)
    zero = np.zeros_like(th)
    if chain is None:
        length = np.hypot(bx - spring.anchor[0], by - spring.anchor[1])
        return {"closing_springs": 0.5 * c * spring.stiffness * (length - spring.free_length) ** 2,
                "kinetic_spring": zero, "pin_on_cam": zero, "spring_weight": zero}
    pin_mass = getattr(chain, "pin_mass", 0.0)
    pin_kinetic = 0.5 * c * pin_mass * (w * cam.arm_length) ** 2
    weights = c * pin_mass * g * by if spring.weight else zero
    kinetic = zero
    pts = [np.stack([np.full_like(th, spring.anchor[0]), np.full_like(th, spring.anchor[1])])]
    for k, m in enumerate(chain.masses, start=1):
        pts.append(np.stack([ch[f"spring_mass_{k}_x"], ch[f"spring_mass_{k}_y"]]))
        kinetic = kinetic + 0.5 * c * m * (ch[f"spring_velocity_{k}_x"] ** 2 + ch[f"spring_velocity_{k}_y"] ** 2)
        if spring.weight:
            weights = weights + c * m * g * ch[f"spring_mass_{k}_y"]
    pts.append(np.stack([bx, by]))
    springs = sum(0.5 * c * k * (np.hypot(*(p1 - p0)) - l0) ** 2
                  for p0, p1, k, l0 in zip(pts[:-1], pts[1:], chain.stiffnesses, chain.free_lengths))
    return {"closing_springs": springs, "kinetic_spring": kinetic, "pin_on_cam": pin_kinetic, "spring_weight": weights}


def _pole_parts(ch, laws, b):
    """The poles' kinetic energy, the rods' and wipe springs', the contacts' and the pole loads'
    potential energy (J), and the power the contacts' and rods' damping dissipate (W); with a trip
    latch the roller is left out of the contacts (its work through the link is ``cycle_work``)."""
    t = ch["cam_angle"] * 0.0
    kinetic, rods, poles = t.copy(), t.copy(), t.copy()
    contacts = laws.roller_energy(ch["cam_roller_penetration"], ArrayOps)
    contact_damping = ch["cam_roller_damping_force"] * ch["cam_roller_penetration_rate"]
    if b.trip_latch is not None:  # the roller's work goes through the trip-free link: cycle_work counts it
        contacts, contact_damping = contacts * 0.0, contact_damping * 0.0
    rod_damping = t.copy()
    for i in range(b.poles.count):
        z, zd = ch[f"pole_{i + 1}_travel"], ch[f"pole_{i + 1}_velocity"]
        kinetic += 0.5 * b.poles.moving_mass * zd**2
        rods += push_rod_energy(ch[f"pole_{i + 1}_rod_compression"], b.poles, ArrayOps)
        contacts += laws.pole_energy(z - laws.gaps[i], ArrayOps)
        poles -= laws.pole_load * z
        contact_damping = contact_damping + ch[f"pole_{i + 1}_contact_damping_force"] * zd
        rod_damping = rod_damping + b.poles.rod_damping * ch[f"pole_{i + 1}_rod_rate"] ** 2
    return {"kinetic_poles": kinetic, "wipe_and_rods": rods, "contacts": contacts, "pole_loads": poles,
            "contact_damping_rate": contact_damping, "rod_damping_rate": rod_damping}


def _shaft_parts(ch, laws, t):
    """The main shaft's (``breaker.main_shaft``) terms: the free pole levers' kinetic energy, the
    segments' elastic energy k (a_j - a_{j+1})^2 / 2 and what their damping dissipated (J,
    cumulative: c (a_j' - a_{j+1}')^2 integrated). Zero for a rigid shaft."""
    zero = np.zeros_like(t)
    out = {"kinetic_levers": zero, "main_shaft": zero, "dissipated_main_shaft": zero}
    if not laws.free_levers:
        return out
    a, a_dot = lever_channels(laws, ch)
    out["kinetic_levers"] = sum(0.5 * laws.lever_inertia * ch[f"pole_{j + 1}_lever_velocity"] ** 2
                                for j in laws.free_levers)
    out["main_shaft"] = sum(0.5 * laws.segment_stiffness * (a[j] - a[j + 1]) ** 2 for j in range(len(a) - 1))
    rate = sum(laws.segment_damping * (a_dot[j] - a_dot[j + 1]) ** 2 for j in range(len(a) - 1))
    out["dissipated_main_shaft"] = cumulative_trapezoid(rate, t, initial=0.0)
    return out


def _stop_parts(ch, b, t):
    """The end stop's and the holding latch's elastic energy (J) and what their dampers dissipated
    (J, cumulative): the damper's share of a stop's force (force - spring, clipped with it) times
    the penetration's rate. Zero for a part the rig leaves out."""
    zero = np.zeros_like(t)
    out = {"end_stop": zero, "hold_latch": zero, "dissipated_end_stop": zero, "dissipated_hold_latch": zero}
    w = ch["shaft_velocity"]
    for key, part, sign in (("end_stop", b.end_stop, 1.0), ("hold_latch", b.hold_latch, -1.0)):
        if part is None:
            continue
        d, force = ch[f"{key}_penetration"], ch[f"{key}_force"]
        contact = (d > 0.0) & (force >= 0.0) if key == "end_stop" else (d > 0.0) & (ch["hold_latch_engaged"] > 0.5)
        out[key] = np.where(contact, one_way_stop_energy(d, part.stiffness), 0.0)
        damper = np.where(contact, force - part.stiffness * d, 0.0)
        out[f"dissipated_{key}"] = jump_integral(damper * sign * part.arm * w, t, d, contact)
    return out


def jump_integral(power: np.ndarray, t: np.ndarray, penetration: np.ndarray, contact: np.ndarray) -> np.ndarray:
    """Cumulative integral (J) of a damper's power (W) that jumps from zero when its contact
    begins (a linear damper meets the stop at speed): the trapezoid rule, except over a step in
    which a contact begins, where the power is taken from the contact's start (the penetration's
    zero, interpolated) at its value at the step's end, not spread over the whole step."""
    steps = 0.5 * (power[1:] + power[:-1]) * np.diff(t)
    begins = np.nonzero(~contact[:-1] & contact[1:])[0]
    d0, d1 = penetration[begins], penetration[begins + 1]
    inside = np.clip(d1 / np.where(d1 > d0, d1 - d0, 1.0), 0.0, 1.0)  # the step's share after the start
    steps[begins] = power[begins + 1] * inside * (t[begins + 1] - t[begins])
    return np.concatenate([[0.0], np.cumsum(steps)])


KINETIC = ("kinetic_cam", "pin_on_cam", "kinetic_spring", "kinetic_follower", "kinetic_levers", "kinetic_poles")
POTENTIAL = ("closing_springs", "cam_weight", "spring_weight", "opening_spring", "wipe_and_rods", "contacts", "pole_loads",
             "end_stop", "hold_latch", "main_shaft")
DISSIPATED = ("dissipated_friction", "dissipated_damping", "dissipated_end_stop", "dissipated_hold_latch",
              "dissipated_main_shaft")


def energy_balance(result: SimulationResult, rig: Rig) -> dict:
    """Energy bookkeeping of a closing (J), from the recorded states (massless or lumped spring;
    the terms: :func:`energy_parts`). Returns time series: ``kinetic``, ``potential``,
    ``closing_springs``, ``opening_spring``, ``wipe_and_rods``, ``contacts``, ``dissipated``
    (shaft friction, contact damping, rod damping, the end stop's and holding latch's dampers),
    ``latch_work``, ``cycle_work`` (the work of the cycle parts, :func:`.cycle_evaluation.cycle_channels`'s
    ``cycle_power``; zero without them), ``spring_energy_released`` and
    ``residual`` = E(t) + dissipated - latch_work - cycle_work - E(0), which is zero for an exact solution."""
    p = energy_parts(result, rig)
    t = result.t
    kinetic = sum(p[k] for k in KINETIC)
    potential = sum(p[k] for k in POTENTIAL)
    dissipated = sum(p[k] for k in DISSIPATED)
    total = kinetic + potential
    return {"t": t, "kinetic": kinetic, "potential": potential, "closing_springs": p["closing_springs"],
            "opening_spring": p["opening_spring"], "wipe_and_rods": p["wipe_and_rods"], "contacts": p["contacts"],
            "dissipated": dissipated, "latch_work": p["latch_work"], "cycle_work": p["cycle_work"],
            "residual": total + dissipated - p["latch_work"] - p["cycle_work"] - total[0],
            "spring_energy_released": p["closing_springs"][0] - p["closing_springs"]}


#: Where the springs' energy can go, in order, with readable names
SPLIT_TERMS = (("kinetic_cam", "cam (kinetic)"), ("pin_on_cam", "springs' pin mass on the cam (kinetic)"),
               ("kinetic_spring", "spring coils (kinetic)"), ("kinetic_follower", "follower (kinetic)"),
               ("kinetic_levers", "pole levers on the main shaft (kinetic)"),
               ("kinetic_poles", "poles (kinetic)"), ("opening_spring", "opening spring (charged)"),
               ("wipe_and_rods", "wipe springs and push rods"), ("contacts", "contacts (elastic)"),
               ("cam_weight", "cam's weight (raised)"), ("spring_weight", "springs' weight (raised)"),
               ("pole_loads", "bellows and pole weights"), ("dissipated_friction", "shaft friction (dissipated)"),
               ("dissipated_damping", "contact and rod damping (dissipated)"),
               ("end_stop", "end stop (elastic)"), ("hold_latch", "holding latch (elastic)"),
               ("dissipated_end_stop", "end stop's damper (dissipated)"),
               ("dissipated_hold_latch", "holding latch's damper (dissipated)"),
               ("main_shaft", "main shaft's twist (elastic)"),
               ("dissipated_main_shaft", "main shaft's torsional damping (dissipated)"))


def energy_split(result: SimulationResult, rig: Rig, at: float, parts: dict | None = None) -> dict:
    """Where the energy the closing springs gave up by time ``at`` (s) has gone (J): each term of
    :func:`energy_parts` as its change since the release (kinetic energies, the charge of the
    opening and wipe springs, the contacts, raised weights, dissipation), with ``released`` (the
    springs' energy drop), ``latch_work`` and ``unaccounted`` (the balance's residual). ``parts``:
    :func:`energy_parts` when already computed."""
    p = energy_parts(result, rig) if parts is None else parts
    t = result.t
    k = int(min(np.searchsorted(t, at), t.size - 1))
    out = {name: float(p[name][k] - p[name][0]) for name, _ in SPLIT_TERMS}
    out["released"] = float(p["closing_springs"][0] - p["closing_springs"][k])
    out["latch_work"] = float(p["latch_work"][k])
    out["cycle_work"] = float(p["cycle_work"][k])
    out["unaccounted"] = (out["released"] + out["latch_work"] + out["cycle_work"]
                          - sum(out[name] for name, _ in SPLIT_TERMS))
    out["t_s"] = float(t[k])
    return out


def energy_splits(result: SimulationResult, rig: Rig) -> dict:
    """:func:`energy_split` at the first touch (``first_touch``; None if no pole touches) and at
    the end of the run (``end``), with ``at_rest``: whether the mechanism has come to rest by then
    (the kinetic energy of the cam, follower and poles below 0.1 % of the energy the springs gave
    up, and the travel settled, :func:`vcbmodel.records.analyser.travel_figures`), that kinetic
    energy (``kinetic_J``) and the spring coils' (``coils_kinetic_J``: a lumped chain has no
    damping of its own, so its surge rings on after the mechanism rests)."""
    fom = figures_of_merit(result, rig)
    parts = energy_parts(result, rig)
    end = energy_split(result, rig, float(result.t[-1]), parts)
    kinetic = float(sum(parts[k][-1] for k in KINETIC if k != "kinetic_spring"))
    touch = fom["first_touch_s"]
    return {"first_touch": energy_split(result, rig, touch, parts) if touch is not None else None, "end": end,
            "kinetic_J": kinetic, "coils_kinetic_J": float(parts["kinetic_spring"][-1]),
            "at_rest": bool(kinetic < 1e-3 * abs(end["released"]) and fom["travel_settled_s"] is not None)}


def crossing_time(t: np.ndarray, z: np.ndarray, level: float) -> float | None:
    """First time (s) the travel z reaches ``level`` (m), interpolated; None if it never does."""
    above = z >= level
    if not above.any():
        return None
    k = int(np.argmax(above))
    if k == 0:
        return float(t[0])
    return float(t[k - 1] + (level - z[k - 1]) / (z[k] - z[k - 1]) * (t[k] - t[k - 1]))


def zone_speed(t: np.ndarray, z: np.ndarray, gap: float, zone: tuple[float, float]) -> float | None:
    """Mean closing speed (m/s) of a pole over the travel zone ``zone`` = (start, end) in m before
    its touch (at travel ``gap``): the zone's length over the time the pole takes to cross it."""
    start, end = crossing_time(t, z, gap - zone[0]), crossing_time(t, z, gap - zone[1])
    if start is None or end is None or end <= start:
        return None
    return (zone[0] - zone[1]) / (end - start)



def pole_touch(t: np.ndarray, z: np.ndarray, zd: np.ndarray, gap: float) -> tuple:
    """One pole's (touch time s, speed at touch m/s, bounces: separations after the first touch that
    reclose, first touch to the last re-closing s) from its travel z (m) and speed zd (m/s); (None,
    None, 0, 0.0) if it never touches. A pole open at the end of the run has reopened (or the run
    ends inside a bounce): that last separation is not counted, and the time is to its last re-closing."""
    closed = z > gap
    if not closed.any():
        return None, None, 0, 0.0
    k = int(np.argmax(closed))
    frac = (gap - z[k - 1]) / (z[k] - z[k - 1]) if k > 0 else 0.0
    touch = float(t[k - 1] + frac * (t[k] - t[k - 1])) if k > 0 else float(t[0])
    speed = float(zd[k - 1] + frac * (zd[k] - zd[k - 1])) if k > 0 else float(zd[0])
    recloses = np.nonzero(~closed[k:-1] & closed[k + 1:])[0]  # separations after the first touch that reclose
    if not recloses.size:
        return touch, speed, 0, 0.0
    return touch, speed, int(recloses.size), float(t[k + recloses[-1] + 1] - touch)


def lift_under_roller(theta: np.ndarray, phi: np.ndarray, rig: Rig) -> np.ndarray:
    """The cam's lift (m, above the base circle) at the angle it presents to the roller, at cam
    angles theta and follower angles phi (rad): the profile read where the roller sits, whether or
    not the roller touches it."""
    b = rig.breaker
    geometry = rest_geometry(b, rig.cam.pivot)
    cx, cy = roller_centre(phi, b.follower, ArrayOps)
    beta = np.arctan2(cy - geometry.cam_axis[1], cx - geometry.cam_axis[0])
    rho, _ = pitch_radius(theta - (beta - geometry.roller_direction), b.profile, b.roller_radius, ArrayOps)
    return np.asarray(rho, float) - (b.profile.base_radius + b.roller_radius)


def run_events(result: SimulationResult, rig: Rig, touches: list) -> dict:
    """What happened after the closing, and how the run ends (SI units, times from the release):

    - ``contacts_reopen_s``: the earliest time a pole that had touched opens again and stays open to
      the end of the run (a bounce recloses; this does not), ``reopened_poles`` (1-based); None, [];
    - ``cam_falls_back_s``: when the lift under the roller first falls more than
      ``CAM_FALL_BACK_FRACTION`` of the cam's lift below its peak so far (None: never), and
      ``cam_falls_back_turning``: ``back`` (the cam turns back down its rise) or ``forward`` (it
      runs on into its return); ``lift_lost_m``: how far below its peak the lift is at the end;
    - ``end_s``, ``shaft_velocity_end_rad_s``, ``cam_angle_end_deg``, and ``moving_at_end``: the
      shaft still turns faster than ``MOVING_AT_END_FRACTION`` of its peak speed; ``end_stop_met``:
      whether the cam met the rig's end stop (None: the rig has none)."""
    ch, t = result.channels, result.t
    reopened = []
    for i, (touch, gap) in enumerate(zip(touches, pole_gaps(rig.breaker.poles)), start=1):
        closed = ch[f"pole_{i}_travel"] > gap
        if touch is not None and not closed[-1]:
            last_closed = int(np.nonzero(closed)[0][-1])
            reopened.append((float(t[last_closed + 1]), i))
    w = ch["shaft_velocity"]
    lift = lift_under_roller(ch["cam_angle"], ch["follower_angle"], rig)
    lost = np.maximum.accumulate(lift) - lift
    fell = lost > P.CAM_FALL_BACK_FRACTION * rig.breaker.profile.lift
    k = int(np.argmax(fell))
    return {"contacts_reopen_s": min(reopened)[0] if reopened else None, "reopened_poles": sorted(i for _, i in reopened),
            "cam_falls_back_s": float(t[k]) if fell.any() else None,
            "cam_falls_back_turning": ("back" if w[k] < 0 else "forward") if fell.any() else None,
            "lift_lost_m": float(lost[-1]), "end_s": float(t[-1]), "shaft_velocity_end_rad_s": float(w[-1]),
            "cam_angle_end_deg": float(np.degrees(ch["cam_angle"][-1])),
            "end_stop_met": bool(np.any(ch["end_stop_force"] > 0.0)) if "end_stop_force" in ch else None,
            "moving_at_end": bool(abs(w[-1]) > P.MOVING_AT_END_FRACTION * np.max(np.abs(w)))}


def figures_of_merit(result: SimulationResult, rig: Rig) -> dict:
    """Closing figures of merit from a result (SI units; times from the latch release).

    Among them: ``roller_lift_off_s``, the total time the roller is off the cam (no contact
    force); ``roller_first_lift_off_s``, when it first leaves, relative to the first pole's
    touch (negative: a follower jump before the contacts touch; absolute time if no pole
    touches; None if it never leaves); ``min_cam_roller_force_before_touch_N``, the smallest
    roller force from the release to the first touch (the margin against a jump); and what
    happened after the closing and how the run ends (:func:`run_events`)."""
    ch, t = result.channels, result.t
    b = rig.breaker
    gaps = pole_gaps(b.poles)
    poles = [pole_touch(t, ch[f"pole_{i + 1}_travel"], ch[f"pole_{i + 1}_velocity"], gap) for i, gap in enumerate(gaps)]
    touches, speeds, bounces, bounce_times = (list(column) for column in zip(*poles))
    travel = ch["follower_displacement"]
    zone_speeds = [zone_speed(t, ch[f"pole_{i + 1}_travel"], gap, b.speed_zone) for i, gap in enumerate(gaps)]
    done = [x for x in touches if x is not None]
    figures = travel_figures(t, travel, min(done) if done else None)
    force = ch["cam_roller_force"]
    off = force <= 0.0
    first_off = None  # first sample at which the roller has left the cam, interpolated like the touches
    if off.any():
        k = int(np.argmax(off))
        first_off = float(t[k]) if k == 0 else float(t[k - 1] + force[k - 1] / (force[k - 1] - force[k]) * (t[k] - t[k - 1]))
    before = t <= min(done) if done else np.ones_like(t, bool)
    return run_events(result, rig, touches) | {
        "closing_time_s": max(done) if len(done) == len(gaps) else None,
        "first_touch_s": min(done) if done else None,
        "pole_spread_s": (max(done) - min(done)) if len(done) == len(gaps) else None,
        # an analyser's closing speed: the mean speed over the rig's zone before each pole's touch;
        # the spec's window holds for every pole, so the slowest and fastest pole's are figures too
        "closing_speed_m_s": (float(np.mean([v for v in zone_speeds if v is not None]))
                              if any(v is not None for v in zone_speeds) else None),
        **zone_extremes(zone_speeds),
        "bounce_count": int(max(bounces)),
        "bounce_duration_s": float(max(bounce_times)),
        # the follower's travel as analysers read it (records.analyser.travel_figures): overtravel
        # beyond the final position, rebound below it after the peak, wipe after the first touch
        "final_travel_m": float(travel[-1]),
        "overtravel_m": figures["overtravel_m"], "rebound_m": figures["rebound_m"],
        "wipe_m": figures.get("wipe_m"), "travel_settled_s": figures["travel_settled_s"],
        "peak_cam_roller_force_N": float(np.max(ch["cam_roller_force"])),
        "roller_lift_off_s": float(np.sum(np.diff(t) * off[1:])),  # total time off the cam
        # when the roller first leaves the cam, relative to the first touch (negative: a follower
        # jump before the contacts touch); None: it never leaves
        "roller_first_lift_off_s": (first_off - min(done) if done else first_off) if first_off is not None else None,
        # the smallest roller force from the latch release to the first touch: the margin against a jump
        "min_cam_roller_force_before_touch_N": float(np.min(force[before])),
        "max_pressure_angle_deg": float(np.degrees(np.max(ch["pressure_angle"]))),
        "per_pole": {"touch_s": touches, "touch_speed_m_s": speeds, "closing_speed_m_s": zone_speeds, "bounces": bounces,
                     "bounce_duration_s": bounce_times},
    } | cycle_figures(result, rig, min(done) if done else None, max(done) if len(done) == len(gaps) else None)


def zone_extremes(zone_speeds: list) -> dict:
    """The slowest and fastest pole's closing speed over the analyser's zone (m/s):
    ``zone_speed_min_m_s``, ``zone_speed_max_m_s``; None when a pole has none (it did not touch)."""
    if not zone_speeds or any(v is None for v in zone_speeds):
        return {"zone_speed_min_m_s": None, "zone_speed_max_m_s": None}
    return {"zone_speed_min_m_s": float(min(zone_speeds)), "zone_speed_max_m_s": float(max(zone_speeds))}


def cycle_figures(result: SimulationResult, rig: Rig, first_touch: float | None, closing_time: float | None) -> dict:
    """The figures of the cycle (:mod:`.cycle_evaluation`): the kinetic margin after the touch (every
    closing with a holding latch or end stop; a CO's judged up to its trip), the opening's figures when the run trips (an O, a
    CO: ``opening``), the close-open time of a CO (first touch to the last pole's parting), and the
    IEC times from the releases' coils when the rig has them."""
    trip = trip_instant(result, rig, first_touch)
    out = kinetic_margin(result, rig, first_touch, trip)
    opening = opening_figures(result, rig, trip) if trip is not None else None
    out["opening"] = opening
    opening_time = opening["opening_time_s"] if opening is not None else None
    out["close_open_time_s"] = (trip + opening_time - first_touch
                                if opening_time is not None and first_touch is not None else None)
    return out | release_figures(rig, closing_time, opening_time)


def main_shaft_twist(result: SimulationResult, rig: Rig) -> dict | None:
    """The main shaft's twist over a closing (``breaker.main_shaft``; None for a rigid shaft): the
    largest angle (rad) between any two pole levers before the first touch (``before_touch_rad``; the
    whole run if no pole touches), over the run (``largest_rad``) and at its end (``end_rad``, the
    closed rest when the run reaches it), each also as travel at the pole (m: twist times
    ``follower.output_arm``)."""
    laws = BreakerLaws.of_rig(rig, result.spec)
    if not laws.free_levers:
        return None
    angles, _ = lever_channels(laws, result.channels)
    spread = np.ptp(np.stack(angles), axis=0)
    touch = figures_of_merit(result, rig)["first_touch_s"]
    before = result.t <= touch if touch is not None else np.ones_like(result.t, bool)
    out = {"before_touch_rad": float(np.max(spread[before])), "largest_rad": float(np.max(spread)),
           "end_rad": float(spread[-1])}
    arm = rig.breaker.follower.output_arm
    out.update({key.replace("_rad", "_m"): value * arm for key, value in list(out.items())})
    return out

"""Evaluation of the breaker's cycle from a run's recorded states: the kinetic margin after the
touch, the making current and the contacts' repulsion, the opening's figures (parting, opening
time and speed, rebound) and the IEC times from the releases' coils. Pure numpy on a
:class:`vcbmodel.model.result.SimulationResult`; the forces come from
:class:`vcbmodel.laws.cycle.CycleLaws`, as in the models.

**Kinetic margin.** The closing springs give most of their energy to the cam before the first
touch; the wipe, the opening spring's last charge, friction and the springs' recharge past their
dead centre are then paid from the cam's kinetic energy. If it runs short the cam stops and turns
back before its holding latch engages, and the contacts reopen. The margin is the smallest kinetic
energy of the cam (with the springs' pin mass on it) from the first touch until the cam reaches its
holding latch's angle (the end stop's without a holding latch): what was left when it was least.
``kinetic_margin_J`` is None when the cam does not get there: ``latched`` False once it has turned
back short of it (run back from its farthest angle by more than ``parameters.CAM_TURN_BACK_ANGLE``,
0.1 deg: a negative speed at the solver's resolution is no turn-back) or has come to rest short of it
(its angle within that 0.1 deg over the run's last ``parameters.CAM_REST_TIME``: held by friction or
in balance, it will not latch), None when the run ends with the cam still on its way or stopped for
less time (a longer run tells); ``latch_short_deg``: how far short its farthest angle after the touch
stays, for a closing that fails (``latched`` False; 0 when latched, None when not judged).

**A closing tripped before it latched (a CO).** The trip lets the trip-free link collapse: the roller's
load no longer reaches the cam, so what the cam does after the trip is not the closing's own motion.
The closing is judged by whether it would have completed without the trip: latched (True) only when
the cam reaches its latch angle before the trip; after it, the freed cam has gone at least as far as
the loaded one would (the link passed the roller's load, which resists the cam on its rise, and the
shaft's friction under it), so a freed cam that turns back or comes to rest short of its latch fails
the closing (False), while one that reaches its latch only after the trip leaves it unjudged (None,
``latch_short_deg`` None: the loaded cam might have stopped short).
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .. import parameters as P
from ..laws.breaker import BreakerLaws, pole_gaps
from ..laws.cam_follower import cam_roller_contact
from ..laws.cycle import CycleLaws, open_angle
from ..laws.friction import ArrayOps
from ..laws.opening import NO_TRIP, travel_rate
from ..laws.making_current import holm_factor
from ..laws.release import delay_scatter
from ..laws.springs import chain_for

if TYPE_CHECKING:
    from ..model.result import SimulationResult
    from ..rig.data import Rig


def cam_kinetic(result: SimulationResult, rig: Rig) -> np.ndarray:
    """The cam's kinetic energy (J) over the run, with the closing springs' pin mass riding on B."""
    chain = chain_for(rig.closing_spring, result.spec.spring_model)
    pin = rig.closing_spring.count * getattr(chain, "pin_mass", 0.0) * rig.cam.arm_length ** 2 if chain is not None else 0.0
    return 0.5 * (rig.cam.inertia_pivot + pin) * result.channels["shaft_velocity"] ** 2


def latch_angle(rig: Rig) -> float | None:
    """The cam angle (rad) at which the closing counts as latched: the holding latch's, else the end
    stop's; None when the rig has neither."""
    b = rig.breaker
    part = b.hold_latch if b.hold_latch is not None else b.end_stop
    return None if part is None else part.angle


def kinetic_margin(result: SimulationResult, rig: Rig, first_touch: float | None, trip: float | None = None) -> dict:
    """The kinetic margin after the touch (module docstring): ``kinetic_at_touch_J``,
    ``kinetic_margin_J`` (None if not latched), ``kinetic_margin_fraction`` (of the energy at
    touch), ``latched`` (True: the cam reached its latch angle after the touch, and before ``trip``,
    s, when the run trips; False: it turned back or came to rest short of it; None: the run ended
    first, or the cam reached it only after the trip), ``latched_s`` and ``latch_short_deg``; all None
    without a touch or a latch angle."""
    target = latch_angle(rig)
    empty = {"kinetic_at_touch_J": None, "kinetic_margin_J": None, "kinetic_margin_fraction": None, "latched": None,
             "latched_s": None, "latch_short_deg": None}
    if first_touch is None or target is None:
        return empty
    t, theta = result.t, result.channels["cam_angle"]
    ke = cam_kinetic(result, rig)
    k0 = int(min(np.searchsorted(t, first_touch), t.size - 1))
    at_touch = float(np.interp(first_touch, t, ke))
    reached = np.nonzero(theta[k0:] >= target)[0]
    if not reached.size:
        # short of its latch: a failure once the cam has turned back or come to rest, else the run ended first
        stopped = turned_back_angle(theta[k0:]) > P.CAM_TURN_BACK_ANGLE or at_rest(t[k0:], theta[k0:])
        # how far short it stops: a cam still on its way has not stopped short (None, as latching is unjudged)
        short = float(np.degrees(target - np.max(theta[k0:]))) if stopped else None
        return empty | {"kinetic_at_touch_J": at_touch, "latched": False if stopped else None, "latch_short_deg": short}
    k1 = k0 + int(reached[0])
    if trip is not None and t[k1] > trip:  # reached by the cam the trip had freed: the closing's own is not shown
        return empty | {"kinetic_at_touch_J": at_touch}
    margin = float(min(at_touch, np.min(ke[k0:k1 + 1])))
    return {"kinetic_at_touch_J": at_touch, "kinetic_margin_J": margin,
            "kinetic_margin_fraction": margin / at_touch if at_touch > 0 else None, "latched": True,
            "latched_s": float(t[k1]), "latch_short_deg": 0.0}


def turned_back_angle(theta: np.ndarray) -> float:
    """How far (rad) the cam angle ``theta`` (rad, over time) has run back from its farthest angle so far,
    at most: 0 for a cam that never turns back; a wiggle at the solver's resolution gives about nothing
    (the closing counts as turned back beyond ``parameters.CAM_TURN_BACK_ANGLE``)."""
    if not theta.size:
        return 0.0
    return float(np.max(np.maximum.accumulate(theta) - theta))


def at_rest(t: np.ndarray, theta: np.ndarray) -> bool:
    """Whether the cam angle ``theta`` (rad, over the times ``t``, s) has stayed within
    ``parameters.CAM_TURN_BACK_ANGLE`` of its last value for the last ``parameters.CAM_REST_TIME`` of
    the run (False when the run is shorter than that)."""
    if not t.size or t[-1] - t[0] < P.CAM_REST_TIME:
        return False
    tail = t >= t[-1] - P.CAM_REST_TIME
    return bool(np.max(np.abs(theta[tail] - theta[-1])) <= P.CAM_TURN_BACK_ANGLE)


def replay_memory(laws: BreakerLaws, cycle: CycleLaws, ch: dict[str, np.ndarray], t: np.ndarray) -> np.ndarray:
    """The cycle parts' memory at each sample (rows), replayed from the recorded states with
    :meth:`CycleLaws.update` (exact when sampled at every step, as the figures of merit are)."""
    n = laws.b.poles.count
    memory = cycle.initial_memory()
    rows = np.empty((t.size, len(memory)))
    for k in range(t.size):
        z = [ch[f"pole_{i + 1}_travel"][k] for i in range(n)]
        roller = cam_roller_contact(ch["cam_angle"][k], 0.0, ch["follower_angle"][k], 0.0, laws.b, laws.geometry)
        memory = cycle.update(memory, t[k], ch["follower_angle"][k], z, roller.penetration)
        rows[k] = memory
    return rows


def cycle_channels(laws: BreakerLaws, ch: dict[str, np.ndarray], t: np.ndarray, open_angle: float) -> dict[str, np.ndarray]:
    """The cycle parts' channels (none without them): each pole's making current (A) and Holm
    repulsion (N), the trip-free link's share (-), the pawl's, dashpot's and open stop's force on F
    (N, ``follower_cycle_force``), F's travel (m, ``f_travel``, from the open rest at the
    follower's ``open_angle``, rad), with a trip latch the roller's forces as the link transmits them
    (:func:`linked_roller`), and ``cycle_power`` (W): the power these parts put into the mechanism
    (the pawl's, dashpot's and stop's force times F's speed, the repulsions times the poles' opening
    speed and, with a trip latch, the roller's transmitted force times the contact's opening rate),
    which the energy balance counts as work done on it."""
    cycle = CycleLaws(laws, open_angle)
    if not cycle.active:
        return {}
    rows = replay_memory(laws, cycle, ch, t)
    out = {"f_travel": np.array([cycle.travel(p) for p in ch["follower_angle"]])}
    forces, links = np.zeros(t.size), np.ones(t.size)
    for k in range(t.size):
        _, trip = cycle.split(rows[k])
        forces[k] = cycle.follower_force(t[k], ch["follower_angle"][k], ch["follower_velocity"][k], trip)
        links[k] = cycle.link(t[k], trip)
    out["follower_cycle_force"], out["trip_link"] = forces, links
    u_dot = ch["follower_velocity"] * travel_rate(ch["follower_angle"], laws.b.follower, ArrayOps)
    power = forces * u_dot
    if cycle.making is not None:
        for i in range(cycle.n):
            touch = rows[:, i]
            z = ch[f"pole_{i + 1}_travel"]
            out[f"pole_{i + 1}_making_current"] = np.where(touch < 0, 0.0, cycle.making.current(t - touch, ArrayOps))
            out[f"pole_{i + 1}_repulsion_force"] = np.array([cycle.repulsion(i, t[k], rows[k, :cycle.n], z[k])
                                                             for k in range(t.size)])
            power = power - out[f"pole_{i + 1}_repulsion_force"] * ch[f"pole_{i + 1}_velocity"]
    if cycle.trip_latch is not None:
        # the roller's contact as the link passes it on: its work on the cam and follower is counted here
        # (energy_parts leaves the roller out of the contacts' energy and damping then)
        power = power - links * ch["cam_roller_force"] * ch["cam_roller_penetration_rate"]
        out.update(linked_roller(ch, links))
    out["cycle_power"] = power
    return out


def linked_roller(ch: dict[str, np.ndarray], links: np.ndarray) -> dict[str, np.ndarray]:
    """The roller's force and damping force (N) as the trip-free link transmits them (times its share)."""
    return {"cam_roller_force": links * ch["cam_roller_force"], "cam_roller_damping_force": links * ch["cam_roller_damping_force"]}


def trip_instant(result: SimulationResult, rig: Rig, first_touch: float | None) -> float | None:
    """When the run's trip lets the pawl go (s): the commands' trip time (an O), or the first touch
    plus the commanded delay (a CO); None without a trip."""
    commands = rig.breaker.commands
    if commands is None or rig.breaker.trip_latch is None:
        return None
    if commands.trip_time != NO_TRIP:
        return float(commands.trip_time)
    if commands.trip_after_touch != NO_TRIP and first_touch is not None:
        return float(first_touch + commands.trip_after_touch)
    return None


def _parting(t: np.ndarray, z: np.ndarray, gap: float, after: float) -> float | None:
    """The last time (s) after ``after`` that a pole's travel z (m) falls through its gap and stays
    open to the end of the run, interpolated; None if it ends closed or never parts."""
    closed = z > gap
    if closed[-1]:
        return None
    k = np.nonzero(closed[:-1] & ~closed[1:] & (t[1:] >= after))[0]
    if not k.size:
        return None
    j = int(k[-1])
    return float(t[j] + (z[j] - gap) / (z[j] - z[j + 1]) * (t[j + 1] - t[j]))


def _fall_time(t: np.ndarray, z: np.ndarray, level: float, after: float) -> float | None:
    """The first time (s) after ``after`` that z (m) falls to ``level``, interpolated."""
    k = np.nonzero((z[:-1] > level) & (z[1:] <= level) & (t[1:] >= after))[0]
    if not k.size:
        return None
    j = int(k[0])
    return float(t[j] + (z[j] - level) / (z[j] - z[j + 1]) * (t[j + 1] - t[j]))


def opening_figures(result: SimulationResult, rig: Rig, trip: float) -> dict:
    """An opening's figures (SI units; times from the trip, when the pawl starts letting go):
    each pole's parting (the last time its contacts separate for good), ``opening_time_s`` (the last
    pole's: IEC's contacts separated in all poles), ``opening_speed_m_s`` (the poles' mean speed over
    ``breaker.opening_speed_zone`` after their parting), and F's travel at the open end as an
    analyser reads it: ``opening_overtravel_m`` (beyond the final open position), ``opening_rebound_m``
    (back towards closed after it) and ``open_settled_s``."""
    ch, t, b = result.channels, result.t, rig.breaker
    start, end = b.opening_speed_zone
    partings, speeds = [], []
    for i, gap in enumerate(pole_gaps(b.poles)):
        z = ch[f"pole_{i + 1}_travel"]
        part = _parting(t, z, gap, trip)
        partings.append(None if part is None else part - trip)
        a, e = (_fall_time(t, z, gap - x, part) if part is not None else None for x in (start, end))
        speeds.append((end - start) / (e - a) if a is not None and e is not None and e > a else None)
    done = [x for x in partings if x is not None]
    u = CycleLaws(BreakerLaws.of_rig(rig, result.spec), open_angle(result.info["initial"])).travel(ch["follower_angle"], ArrayOps)
    after = t >= trip
    tail = max(3, u.size // 50)
    final = float(np.median(u[-tail:]))
    k = int(np.argmin(np.where(after, u, np.inf)))
    settled = np.nonzero(np.abs(u - final) > 5e-5)[0]
    return {"trip_s": trip, "parting_s": partings,
            "opening_time_s": max(done) if done and len(done) == len(partings) else None,
            "opening_speed_m_s": float(np.mean([s for s in speeds if s is not None])) if any(s is not None for s in speeds) else None,
            "opening_speeds_m_s": speeds, "open_final_travel_m": final,
            "opening_overtravel_m": float(final - u[k]), "opening_rebound_m": float(max(0.0, np.max(u[k:]) - final)),
            "open_settled_s": float(t[settled[-1] + 1] - trip) if settled.size and settled[-1] + 1 < u.size - tail else None}


def release_figures(rig: Rig, closing_time: float | None, opening_time: float | None) -> dict:
    """IEC 62271-100's times from the releases' coils (rig sections ``breaker.closing_release``,
    ``breaker.opening_release``; each None without its release): the release's delay (s) at rated
    supply and its scatter (fastest and slowest corners, :func:`vcbmodel.laws.release.delay_scatter`),
    and the closing time from energising the closing coil to the last pole's touch and the opening
    time from energising the opening coil to the last pole's parting, each as [fastest, nominal,
    slowest]."""
    out = {}
    for key, release, mechanical in (("closing", rig.breaker.closing_release, closing_time),
                                     ("opening", rig.breaker.opening_release, opening_time)):
        if release is None:
            continue
        d = delay_scatter(release)
        out[f"{key}_release_delay_s"] = d["nominal"]
        out[f"{key}_release_delay_range_s"] = [d["fastest"], d["slowest"]]
        out[f"{key}_time_from_coil_s"] = None if mechanical is None else [
            None if d[c] is None else d[c] + mechanical for c in ("fastest", "nominal", "slowest")]
    return out


def cycle_check_lines(b) -> list[str]:
    """What ``vcbmodel check`` says of a breaker's operating-cycle parts (docs/rig-format.md): each
    section's key numbers, or that it is not modelled."""
    lines = []
    m = b.making_current
    if m is None:
        lines.append("  making current: not modelled (no breaker.making_current): every closing carries no current")
    else:
        force = holm_factor(m) * m.peak ** 2
        lines.append(f"  making current: {m.peak / 1e3:g} kA peak, {m.frequency:g} Hz, DC time constant "
                     f"{1e3 * m.time_constant:g} ms, asymmetry {m.asymmetry:g}; Holm's repulsion at the peak "
                     f"{force / 1e3:.3g} kN per pole (R {1e3 * m.contact_radius:g} mm, a {1e3 * m.spot_radius:g} mm, "
                     f"{m.spots:g} spot(s))")
    t, d = b.trip_latch, b.opening_dashpot
    if t is None:
        lines.append("  trip latch: not modelled (no breaker.trip_latch): the closed breaker rests on the cam; no opening")
    else:
        lines.append(f"  trip latch: the pawl holds F at {1e3 * t.travel:g} mm of travel, {t.stiffness:.4g} N/m, lets go "
                     f"over {1e3 * t.release_time:g} ms; trip-free link resets within {1e3 * t.reset_travel:g} mm of open")
    if d is not None:
        lines.append(f"  opening dashpot: from {1e3 * d.stroke:g} mm before open, {d.damping:g} N s/m after a "
                     f"{1e3 * d.ramp:g} mm ramp; open stop {d.stop_stiffness:.4g} N/m")
    for key, release in (("closing", b.closing_release), ("opening", b.opening_release)):
        if release is None:
            lines.append(f"  {key} release: not modelled (no breaker.{key}_release): {key} times run from the latch")
            continue
        s = delay_scatter(release)
        lines.append(f"  {key} release: coil L/R {1e3 * release.inductance / release.resistance:.3g} ms; trips "
                     f"{1e3 * s['nominal']:.2f} ms after energising ({1e3 * s['fastest']:.2f}-{1e3 * s['slowest']:.2f} ms "
                     f"over {100 * release.voltage_range[0]:g}-{100 * release.voltage_range[1]:g} % supply and the coil's "
                     "temperature)")
    return lines

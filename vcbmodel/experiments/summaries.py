"""What ``vcbmodel simulate`` says about one run, and which channels it writes, per experiment.

Each function takes a :class:`~vcbmodel.model.result.SimulationResult` and the loaded rig; the
experiment records (``summary``, ``record_channels``) point at them, so the command line asks the
record and compares no experiment names.
"""
from __future__ import annotations

from typing import TYPE_CHECKING
import numpy as np

from .. import parameters as P
from ..laws.breaker import pole_gaps
from ..laws.cam_follower import follower_displacement
from ..records.analyser import simulated_channels, travel_figures
from ..records.signals import decay_shape, swing_peaks
from ..rig.limits import OPENING_LIMITS
from ..rig.units import unit_of_name
from .base import experiment_of, measured_only
from .closing_evaluation import main_shaft_twist
from .cycle_evaluation import at_rest
from .report import Report, Row, label

if TYPE_CHECKING:
    from ..model.result import SimulationResult
    from ..rig.data import Rig


def closing_record_channels(result: SimulationResult, rig: Rig) -> dict[str, tuple[np.ndarray, str]]:
    """What a closing's CSV holds, each channel with its SI unit: the follower's travel (the measured
    channel); per pole, as a breaker analyser records them, travel (m), speed (m/s) and contact (0
    open, 1 closed: travel beyond the pole's gap), then its contact force and push-rod force (N), with
    a making current its current (A) and Holm repulsion (N); the
    cam's angle (rad) and speed (rad/s), the cam-roller force (N) and the end stop's and holding
    latch's forces (N) where the rig has them. A file ``vcbmodel diagnose`` reads (the analyser's
    channels are fitted, the others ignored)."""
    out = measured_only(result, rig)
    ch = result.channels
    for i, gap in enumerate(pole_gaps(rig.breaker.poles), start=1):
        travel = ch[f"pole_{i}_travel"]
        out[f"pole_{i}_travel"] = (travel, "m")
        out[f"pole_{i}_velocity"] = (ch[f"pole_{i}_velocity"], "m/s")
        out[f"pole_{i}_contact"] = ((travel > gap).astype(float), "-")
    for name in simulated_channels(rig.breaker.poles.count):
        if name in ch and name not in out:
            out[name] = (ch[name], result.units[name])
    return out


def pendulum_summary(result: SimulationResult, rig: Rig) -> list[tuple]:
    """[(what, value, SI unit, unit shown)]: swing period, first peak, how the amplitude decays, when it stops."""
    t, y = result.t, result.measured
    times, amps = swing_peaks(t, y)
    period = 2 * float(np.mean(np.diff(times))) if times.size >= 2 else float("nan")
    decay = decay_shape(times, amps)
    fom = result_figures(result, rig)
    lines = [("swing period", period, "s", "s"), ("first peak", fom["first_peak_rad"], "rad", "deg"),
             ("stops at", fom["stop_time_s"], "s", "s"), ("peaks", times.size, "-")]
    if decay["shape"] != "unknown":
        lines.append((f"amplitude decay ({decay['shape']})",
                      decay["linear_slope"] if decay["shape"] == "linear" else decay["exponential_rate"],
                      "rad/s" if decay["shape"] == "linear" else "1/s", "deg/s" if decay["shape"] == "linear" else None))
    if fom["stop_time_s"] is None:
        w = float(result.channels["shaft_velocity"][-1])
        lines.append(("note", f"the run ends at {float(t[-1]):.4g} s with the pendulum still swinging ({w:.3g} rad/s "
                              f"at {np.degrees(y[-1]):.1f} deg): it has not stopped; a longer --t-end shows where it does", None))
    return lines


def cam_drop_summary(result: SimulationResult, rig: Rig) -> list[tuple]:
    fom = result_figures(result, rig)
    return [("end time", float(result.t[-1]), "s"), ("cam angle at the end", fom["cam_angle_end_rad"], "rad"),
            ("peak shaft speed", fom["peak_shaft_velocity_rad_s"], "rad/s")]


def breaker_figures(fom: dict, rig: Rig) -> list[tuple]:
    """[(figure, what, SI value, SI unit)]: the whole breaker's figures of a closing (the per-pole
    ones are :func:`pole_rows`'); the follower's travel is the mechanism's, as an analyser's
    transducer on the operating rod reads it."""
    geometric = "" if rig.breaker.end_stop is not None else " (no end stop: cam geometry)"
    return [("closing_time_s", "closing time (last pole)", fom["closing_time_s"], "s"),
            ("pole_spread_s", "pole spread", fom["pole_spread_s"], "s"),
            ("wipe_m", "mechanism wipe (after first touch)", fom["wipe_m"], "m"),
            ("overtravel_m", "mechanism overtravel" + geometric, fom["overtravel_m"], "m"),
            ("rebound_m", "mechanism rebound", fom["rebound_m"], "m"),
            ("travel_settled_s", "travel settled (within 0.05 mm)", fom["travel_settled_s"], "s"),
            ("peak_cam_roller_force_N", "peak cam-roller force", fom["peak_cam_roller_force_N"], "N"),
            ("min_cam_roller_force_before_touch_N", "least cam-roller force before touch",
             fom["min_cam_roller_force_before_touch_N"], "N"),
            ("roller_lift_off_s", "roller off the cam (in all)", fom["roller_lift_off_s"], "s"),
            ("kinetic_at_touch_J", "cam's kinetic energy at the first touch", fom["kinetic_at_touch_J"], "J"),
            ("kinetic_margin_J", "kinetic margin (cam's least, touch to latch)", fom["kinetic_margin_J"], "J")] + coil_figures(fom)


def coil_figures(fom: dict) -> list[tuple]:
    """IEC 62271-100's closing time, from energising the closing coil (rated supply, fastest, slowest
    corner), where the rig has a closing release (``breaker.closing_release``); else nothing."""
    coil = fom.get("closing_time_from_coil_s")
    if coil is None:
        return []
    return [("closing_time_from_coil_s", "closing time from the closing coil (IEC 62271-100, rated supply)", coil[1], "s"),
            ("", "  fastest (highest supply, cold coil)", coil[0], "s"),
            ("", "  slowest (lowest supply, hot coil)", coil[2], "s")]


def closing_summary(result: SimulationResult, rig: Rig) -> list[tuple]:
    """[(what, SI value, SI unit)]: the whole breaker's figures, the end stop's, the main shaft's twist,
    and notes (``("note", text, None)``); each pole's figures: :func:`closing_report`."""
    fom = result_figures(result, rig)
    lines = [(what, value, unit) for _, what, value, unit in breaker_figures(fom, rig)]
    return (lines + stop_summary(result, rig) + twist_summary(result, rig)
            + closing_notes(fom, rig, stops_untouched(result, fom)))


def stops_untouched(result: SimulationResult, fom: dict) -> bool:
    """Whether the cam has come to rest with no pole touched: it moved (more than
    ``parameters.CAM_TURN_BACK_ANGLE`` from its start) and has stood within that angle over the run's
    last ``parameters.CAM_REST_TIME`` (:func:`~vcbmodel.experiments.cycle_evaluation.at_rest`): the
    breaker will not close however long the run, where a run cut short before the touch is not judged."""
    if fom.get("first_touch_s") is not None:
        return False
    t, theta = result.t, result.channels["cam_angle"]
    return bool(theta.size) and float(np.max(theta) - theta[0]) > P.CAM_TURN_BACK_ANGLE and at_rest(t, theta)


def closing_notes(fom: dict, rig: Rig, untouched: bool = False) -> list[tuple]:
    """[("note", text, None)]: what a reader of the figures must not miss, said plainly: a run that
    ends before every pole touches, before the cam meets its end stop, or with the cam still
    turning (a truncated run, not a complete closing); a cam at rest before any pole touches
    (``untouched``: :func:`stops_untouched`, the closing fails); contacts that reopen after closing; a
    cam that runs back down its profile (turned back by its springs, or on into its return)."""
    end_ms = 1e3 * fom["end_s"]
    notes = []
    touches = fom["per_pole"]["touch_s"]
    missing = [str(i) for i, x in enumerate(touches, start=1) if x is None]
    if untouched:
        notes.append(f"no pole touches: the cam comes to rest at {fom['cam_angle_end_deg']:.1f} deg before the contacts "
                     "close (the closing fails)")
    elif missing:
        notes.append(f"the run ends at {end_ms:.4g} ms before pole {', '.join(missing)} "
                     f"{'touches' if len(missing) == 1 else 'touch'}: not a complete closing (a longer --t-end)")
    if fom["contacts_reopen_s"] is not None:
        poles = fom["reopened_poles"]
        notes.append(f"CONTACTS REOPEN after closing: pole {', '.join(map(str, poles))} "
                     f"{'opens' if len(poles) == 1 else 'open'} again from {1e3 * fom['contacts_reopen_s']:.4g} ms "
                     f"and {'is' if len(poles) == 1 else 'are'} open at the end of the run")
    if fom["cam_falls_back_s"] is not None:
        how = ("turns back down its rise" if fom["cam_falls_back_turning"] == "back"
               else "runs on into its return")
        hint = "" if rig.breaker.end_stop is not None else " (the rig has no breaker.end_stop or hold_latch to hold it)"
        notes.append(f"the cam {how} at {1e3 * fom['cam_falls_back_s']:.4g} ms: the lift under the roller falls, "
                     f"{1e3 * fom['lift_lost_m']:.3g} mm below its peak at the end{hint}")
    if fom["latched"] is False:
        notes.append(f"the cam stops {fom['latch_short_deg']:.3g} deg short of its latch after the touch: its kinetic "
                     "margin is used up (the closing fails)")
    if fom["latched"] is None and fom["kinetic_at_touch_J"] is not None:
        notes.append(f"the run ends at {end_ms:.4g} ms before the cam reaches its latch: no kinetic margin yet (a longer --t-end)")
    opening = [lim.figure.replace("_", " ") for lim in rig.breaker.limits if lim.figure in OPENING_LIMITS]
    if opening and fom.get("opening") is None:
        notes.append(f"the limits on the opening ({', '.join(opening)}) are judged by simulate --sequence, on each "
                     "O and CO: a closing does not open")
    if rig.breaker.end_stop is not None and fom["end_stop_met"] is False and fom["latched"] is not False \
            and not untouched:
        # a cam that has stopped short of its latch will not meet its stop either: no longer run shows it
        notes.append(f"the run ends at {end_ms:.4g} ms before the cam meets its end stop (a longer --t-end shows it)")
    if fom["moving_at_end"]:
        notes.append(f"the run ends at {end_ms:.4g} ms with the cam still turning ({fom['shaft_velocity_end_rad_s']:.3g} "
                     f"rad/s at {fom['cam_angle_end_deg']:.1f} deg): not at rest; a longer --t-end shows where it stops")
    return [("note", text, None) for text in notes]


def twist_summary(result: SimulationResult, rig: Rig) -> list[tuple]:
    """[(what, value, unit)] of the main shaft's twist (``breaker.main_shaft``; none for a rigid
    shaft): the largest angle between two pole levers before the first touch, over the run and at
    its end, in rad and as travel at the pole (m: the twist times the follower's output arm)."""
    twist = main_shaft_twist(result, rig)
    if twist is None:
        return []
    lines = []
    for key, what in (("before_touch", "before first touch"), ("largest", "largest"), ("end", "at the end")):
        lines += [(f"main shaft twist, {what}", twist[f"{key}_rad"], "rad"),
                  (f"  as pole travel, {what}", twist[f"{key}_m"], "m")]
    return lines


def stop_summary(result: SimulationResult, rig: Rig) -> list[tuple]:
    """[(what, value, unit)] for the rig's end stop and holding latch (none without them): when the
    cam first meets the stop (its force first positive) and how far it goes into it (m at the
    stop's arm), when the latch engages, and the cam angle at the end of the run (deg); ``never``
    when the run ends first (a longer ``--t-end`` shows it)."""
    ch, t, b = result.channels, result.t, rig.breaker
    lines = []
    if b.end_stop is not None:
        hit = ch["end_stop_force"] > 0.0
        lines += [("cam meets the end stop at", float(t[np.argmax(hit)]) if hit.any() else None, "s"),
                  ("cam's travel into the end stop (at its arm)",
                   float(np.max(ch["end_stop_penetration"])) if hit.any() else None, "m")]
    if b.hold_latch is not None:
        engaged = ch["hold_latch_engaged"] > 0.5
        lines.append(("holding latch engaged at", float(t[np.argmax(engaged)]) if engaged.any() else None, "s"))
    if lines:
        lines.append(("cam angle at the end of the run", float(np.degrees(ch["cam_angle"][-1])), "deg"))
    return lines


def result_figures(result: SimulationResult, rig: Rig) -> dict:
    return experiment_of(rig.experiment).figures_of_merit(result, rig)


#: The per-pole rows, in order: {key in the report: (key in figures_of_merit()["per_pole"], label)};
#: the pole's travel figures and its contact force closed come from :func:`pole_travel_figures`. A
#: per-pole figure the evaluation adds that is not listed gets a row after these, named from its key.
POLE_ROWS = {"closing_time_s": ("touch_s", "closing time (touch)"),
             "closing_speed_m_s": ("closing_speed_m_s", "closing speed over the zone"),
             "touch_speed_m_s": ("touch_speed_m_s", "speed at touch"),
             "bounce_count": ("bounces", "bounces"),
             "bounce_duration_s": ("bounce_duration_s", "bounce duration"),
             "overtravel_m": ("overtravel_m", "overtravel"),
             "rebound_m": ("rebound_m", "rebound"),
             "wipe_m": ("wipe_m", "wipe (travel after touch)"),
             "contact_force_closed_N": ("contact_force_closed_N", "contact force closed")}


def pole_drive_travel(result: SimulationResult, rig: Rig, pole: int) -> np.ndarray:
    """The travel (m) that drives pole ``pole`` (1-based): the output point F's travel at the pole's
    lever angle (``pole_{i}_lever_angle`` on an elastic main shaft, else the follower's), as a
    transducer on that pole's operating rod reads it; the moving contact's own travel stops at the touch."""
    ch = result.channels
    angle = ch.get(f"pole_{pole}_lever_angle", ch["follower_angle"])
    return follower_displacement(angle, rig.breaker.follower, result.info["initial"].follower_angle)


def pole_travel_figures(result: SimulationResult, rig: Rig, touches: list) -> list[dict]:
    """Per pole, from the travel that drives it (:func:`pole_drive_travel`), as analysers define them
    (:func:`vcbmodel.records.analyser.travel_figures`): ``overtravel_m`` beyond the final position,
    ``rebound_m`` below it after the peak, ``wipe_m`` from the pole's touch to the final position (None
    if it never touches); and ``contact_force_closed_N``: the contact force at rest, the median of the
    run's last 2 % (0 for a pole that touched and is open at the end; None for one that has not touched
    yet: a run too short to show its closed force, as its closing time)."""
    out = []
    for i, touch in enumerate(touches, start=1):
        figures = travel_figures(result.t, pole_drive_travel(result, rig, i), touch)
        force = result.channels[f"pole_{i}_contact_force"]
        out.append({"overtravel_m": figures["overtravel_m"], "rebound_m": figures["rebound_m"],
                    "wipe_m": figures.get("wipe_m"),
                    "contact_force_closed_N": None if touch is None else float(np.median(force[-max(3, force.size // 50):]))})
    return out


def pole_rows(fom: dict, extra: list[dict], rig: Rig) -> list[Row]:
    """The per-pole table's rows: :data:`POLE_ROWS`, then any other per-pole figure of the evaluation."""
    per_pole = {**fom["per_pole"], **{k: [e[k] for e in extra] for k in extra[0]}} if extra else dict(fom["per_pole"])
    zone = rig.breaker.speed_zone
    untouched = [t is None for t in fom["per_pole"]["touch_s"]]
    rows = []
    for key, (source, what) in POLE_ROWS.items():
        if source in per_pole:
            if key == "closing_speed_m_s":
                what = f"closing speed, {1e3 * zone[0]:g}-{1e3 * zone[1]:g} mm before touch"
            values = list(per_pole[source])
            if key in ("bounce_count", "bounce_duration_s"):  # a pole not touched has no bounce yet: no value
                values = [None if u else v for u, v in zip(untouched, values)]
            rows.append(Row(key, what, values, unit_of_name(key)))
    listed = {source for source, _ in POLE_ROWS.values()}
    for key, values in per_pole.items():
        if key not in listed and isinstance(values, (list, tuple)):
            rows.append(Row(key, label(key), list(values), unit_of_name(key)))
    return rows


#: Whole-run figures the report shows elsewhere (per pole, in the notes) or leaves out: the poles'
#: mean, slowest and fastest zone speed are in the per-pole table's row.
NOT_BREAKER_ROWS = {"closing_speed_m_s", "zone_speed_min_m_s", "zone_speed_max_m_s", "first_touch_s", "bounce_count", "bounce_duration_s",
                    "final_travel_m", "end_s", "contacts_reopen_s", "cam_falls_back_s", "lift_lost_m",
                    "shaft_velocity_end_rad_s", "cam_angle_end_deg", "roller_first_lift_off_s", "max_pressure_angle_deg"}
#: Whole-run figures of an opening, shown only for a run that trips (an O, a CO: its ``opening`` figures
#: are there); a plain closing has no close-open time or opening time from the coil to show, not an empty one.
OPENING_ONLY_ROWS = {"close_open_time_s", "opening_time_from_coil_s"}


def closing_report(result: SimulationResult, rig: Rig) -> Report:
    """``simulate``'s report of a closing: each pole's figures in a column against ``breaker.limits``,
    then the whole breaker's (:func:`breaker_figures`, then any other figure of the evaluation whose
    name ends in its unit), the end stop's and the main shaft's, and the notes."""
    fom = result_figures(result, rig)
    single = rig.breaker.poles.count == 1  # one pole has no spread: said, not printed as 0.000 ms
    rows = [Row(key, what, [value], unit, absent="one pole" if single and key == "pole_spread_s" else "")
            for key, what, value, unit in breaker_figures(fom, rig)]
    shown = {key for key, *_ in breaker_figures(fom, rig)} | NOT_BREAKER_ROWS
    if fom.get("opening") is None:  # the run does not trip
        shown |= OPENING_ONLY_ROWS
    rows += [Row(key, label(key), [value], unit_of_name(key)) for key, value in fom.items()
             if key not in shown and unit_of_name(key) and isinstance(value, (int, float, type(None)))
             and not isinstance(value, bool)]
    rows += [Row("", what, [value], unit) for what, value, unit in stop_summary(result, rig) + twist_summary(result, rig)]
    extra = pole_travel_figures(result, rig, fom["per_pole"]["touch_s"])
    untouched = stops_untouched(result, fom)
    return Report(f"{rig.name}: {rig.experiment}", rows, pole_rows(fom, extra, rig), rig.breaker.poles.count,
                  [text for _, text, _ in closing_notes(fom, rig, untouched)], rig.breaker.limits,
                  latching_verdict(fom, untouched))


def latching_verdict(fom: dict, untouched: bool = False) -> tuple[str, str, bool] | None:
    """(text, brief text, whether the closing fails) for the verdict on the limits: a cam that stops
    short of its latch, or at rest before any pole touches (``untouched``: :func:`stops_untouched`),
    fails the closing whatever the limits say; a run that ends before the cam reaches its latch leaves
    that unjudged (None: it latched, or no pole touched in a run that ends first)."""
    if untouched:
        return (f"THE CLOSING FAILS: no pole touches, the cam comes to rest at {fom['cam_angle_end_deg']:.1f} deg",
                "CLOSING FAILS (no pole touches)", True)
    if fom["latched"] is False:
        return (f"THE CLOSING FAILS: the cam stops {fom['latch_short_deg']:.3g} deg short of its latch",
                "CLOSING FAILS (latch not reached)", True)
    if fom["latched"] is None and fom["kinetic_at_touch_J"] is not None:
        return (f"latching not judged: the run ends at {1e3 * fom['end_s']:.4g} ms before the cam reaches its latch "
                "(a longer --t-end)", "latching not judged", False)
    return None

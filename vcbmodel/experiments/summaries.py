"""What ``vcbmodel simulate`` says about one run, and which channels it writes, per experiment.

Each function takes a :class:`~vcbmodel.model.result.SimulationResult` and the loaded rig; the
experiment records (``summary``, ``record_channels``) point at them, so the command line asks the
record and compares no experiment names.
"""
from __future__ import annotations

from typing import TYPE_CHECKING
import numpy as np

from ..laws.breaker import pole_gaps
from ..records.signals import decay_shape, swing_peaks
from .base import experiment_of, measured_only
from .closing_evaluation import main_shaft_twist

if TYPE_CHECKING:
    from ..model.result import SimulationResult
    from ..rig.data import Rig


def closing_record_channels(result: SimulationResult, rig: Rig) -> dict[str, tuple[np.ndarray, str]]:
    """The follower's travel and, as a breaker analyser records them, each pole's travel (m) and
    contact (0 open, 1 closed: travel beyond the pole's gap); a file ``vcbmodel diagnose`` reads."""
    out = measured_only(result, rig)
    for i, gap in enumerate(pole_gaps(rig.breaker.poles), start=1):
        travel = result.channels[f"pole_{i}_travel"]
        out[f"pole_{i}_travel"] = (travel, "m")
        out[f"pole_{i}_contact"] = ((travel > gap).astype(float), "-")
    return out


def pendulum_summary(result: SimulationResult, rig: Rig) -> list[tuple]:
    """[(what, value, unit)]: swing period, first peak, how the amplitude decays, when it stops."""
    t, y = result.t, result.measured
    times, amps = swing_peaks(t, y)
    period = 2 * float(np.mean(np.diff(times))) if times.size >= 2 else float("nan")
    decay = decay_shape(times, amps)
    fom = result_figures(result, rig)
    lines = [("swing period", period, "s"), ("first peak", fom["first_peak_rad"], "rad"),
             ("stops at", fom["stop_time_s"], "s"), ("peaks", float(times.size), "-")]
    if decay["shape"] != "unknown":
        lines.append((f"amplitude decay ({decay['shape']})",
                      decay["linear_slope"] if decay["shape"] == "linear" else decay["exponential_rate"],
                      "rad/s" if decay["shape"] == "linear" else "1/s"))
    return lines


def cam_drop_summary(result: SimulationResult, rig: Rig) -> list[tuple]:
    fom = result_figures(result, rig)
    return [("end time", float(result.t[-1]), "s"), ("cam angle at the end", fom["cam_angle_end_rad"], "rad"),
            ("peak shaft speed", fom["peak_shaft_velocity_rad_s"], "rad/s")]


def closing_summary(result: SimulationResult, rig: Rig) -> list[tuple]:
    fom = result_figures(result, rig)
    per_pole = fom["per_pole"]
    geometric = ")" if rig.breaker.end_stop is not None else "; no end stop in the rig: the cam's geometry, not dynamics)"
    lines = [(f"pole {i} closes at", v, "s") for i, v in enumerate(per_pole["touch_s"], start=1)]
    lines += [("closing time (last pole)", fom["closing_time_s"], "s"),
              ("touch speed (mean of poles)", fom["touch_speed_m_s"], "m/s"),
              (f"closing speed ({1e3 * rig.breaker.speed_zone[0]:g} to {1e3 * rig.breaker.speed_zone[1]:g} mm "
               "before touch)", fom["closing_speed_m_s"], "m/s"),
              ("pole spread", fom["pole_spread_s"], "s"), ("bounces (worst pole)", float(fom["bounce_count"]), "-"),
              ("bounce duration (worst pole)", fom["bounce_duration_s"], "s"),
              ("wipe (follower travel after the first touch, to its final position)", fom["wipe_m"], "m"),
              ("overtravel (follower travel beyond its final position" + geometric, fom["overtravel_m"], "m"),
              ("rebound (follower travel back below its final position after the peak)", fom["rebound_m"], "m"),
              ("follower travel settled (within 0.05 mm of its final position)", fom["travel_settled_s"], "s"),
              ("peak cam-roller force", fom["peak_cam_roller_force_N"], "N"),
              ("cam's kinetic energy at the first touch", fom["kinetic_at_touch_J"], "J"),
              ("kinetic margin (the cam's least kinetic energy from the touch to its latch)", fom["kinetic_margin_J"], "J")]
    coil = fom.get("closing_time_from_coil_s")
    if coil is not None:  # the rig has a closing release: IEC's closing time, from energising its coil
        lines += [("closing time from the closing coil (IEC 62271-100, rated supply)", coil[1], "s"),
                  ("  fastest (highest supply, cold coil)", coil[0], "s"), ("  slowest (lowest supply, hot coil)", coil[2], "s")]
    return lines + stop_summary(result, rig) + twist_summary(result, rig) + closing_notes(fom, rig)


def closing_notes(fom: dict, rig: Rig) -> list[tuple]:
    """[("note", text, None)]: what a reader of the figures must not miss, said plainly: a run that
    ends before every pole touches, before the cam meets its end stop, or with the cam still
    turning (a truncated run, not a complete closing); contacts that reopen after closing; a cam
    that runs back down its profile (turned back by its springs, or on into its return)."""
    end_ms = 1e3 * fom["end_s"]
    notes = []
    touches = fom["per_pole"]["touch_s"]
    missing = [str(i) for i, x in enumerate(touches, start=1) if x is None]
    if missing:
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
    if rig.breaker.end_stop is not None and fom["end_stop_met"] is False:
        notes.append(f"the run ends at {end_ms:.4g} ms before the cam meets its end stop (a longer --t-end shows it)")
    if fom["moving_at_end"]:
        notes.append(f"the run ends at {end_ms:.4g} ms with the cam still turning ({fom['shaft_velocity_end_rad_s']:.3g} "
                     f"rad/s at {fom['cam_angle_end_deg']:.1f} deg): not at rest; a longer --t-end shows where it stops")
    return [("note", text, None) for text in notes]


def twist_summary(result: SimulationResult, rig: Rig) -> list[tuple]:
    """[(what, value, unit)] of the main shaft's twist (``breaker.main_shaft``; none for a rigid
    shaft): the largest angle between two pole levers before the first touch, over the run and at
    its end, in rad and as travel at the pole (m)."""
    twist = main_shaft_twist(result, rig)
    if twist is None:
        return []
    lines = []
    for key, what in (("before_touch", "before the first touch"), ("largest", "over the run"),
                      ("end", "at the end of the run")):
        lines += [(f"main shaft's largest twist {what}", twist[f"{key}_rad"], "rad"),
                  (f"  as travel at the pole (twist x output arm) {what}", twist[f"{key}_m"], "m")]
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

"""An operating sequence drawn as a breaker analyser shows each operation (``simulate --sequence
... --plot``): one row of panels per operation, time in ms from that operation's latch or pawl
letting go, each pole in one colour throughout (:data:`.closing_plot.POLE_COLOURS`).

- a closing (C, and the closing of a CO): the closing's own panels (:mod:`.closing_plot`): travel per
  pole with the speed zone shaded and each touch marked, speed per pole with each pole's closing
  speed over the zone, contact timing, the bounces' close-up; a CO's trip and partings marked on them;
- an opening (O): travel per pole with the opening zone (``breaker.opening_speed_zone``, after the
  parting) shaded and each parting marked, the speed towards open per pole with each pole's opening
  speed over that zone, contact timing with the partings, and the mechanism's travel at the open end
  (overtravel and rebound, as analysers read them).

The figures come from the same runs as the sequence's report, at the solver's step.
"""
from __future__ import annotations

import os
import textwrap
from typing import TYPE_CHECKING

import numpy as np
import matplotlib.pyplot as plt

from ..experiments.closing_evaluation import figures_of_merit
from ..experiments.sequence import commands_for, margin_text, with_commands
from ..laws.breaker import pole_gaps
from .closing_plot import MECHANISM, ZONE, bounce_closeup, contact_bars, pole_colour, speed_panel, travel_panel
from .plots import fitted_title, save

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..model.result import SimulationResult
    from ..rig.data import Rig

TRIP = "crimson"  # the trip instant (the pawl starts letting go): a vertical line
HEADLINE_PT = 44.0  # an operation's headline above its row (pt): clear of three lines of panel titles


def plot_sequence(report: dict, results: list[SimulationResult], rig: Rig, path: str | os.PathLike, title: str) -> None:
    """The analyser's view of every operation of a sequence (:func:`sequence_figure`), written to ``path``."""
    save(sequence_figure(report, results, rig, title), path, tight=False)


def sequence_figure(report: dict, results: list[SimulationResult], rig: Rig, title: str) -> Figure:
    """One row of four panels per operation (module docstring): ``report`` is
    :func:`~vcbmodel.experiments.sequence.run_sequence`'s, ``results`` its runs in order."""
    rows = len(results)
    fig, axes = plt.subplots(rows, 4, figsize=(20.0, 4.3 * rows + 1.0), squeeze=False,
                             gridspec_kw={"width_ratios": [1.3, 1.3, 1.0, 1.0]})
    for row, entry, result in zip(axes, report["operations"], results):
        op_rig = with_commands(rig, commands_for(rig, entry["op"]))
        fom = figures_of_merit(result, op_rig)
        t_ms = 1e3 * result.t
        if entry["op"] == "O":
            opening_row(row, result, op_rig, fom, t_ms)
        else:
            closing_row(row, result, op_rig, fom, t_ms)
        # the operation's headline above its row, the panels' own titles under it
        row[0].annotate(f"{entry['op']} at {entry['command_s']:g} s (sequence clock): {operation_text(entry)}",
                        xy=(0.0, 1.0), xycoords="axes fraction", xytext=(0.0, HEADLINE_PT), textcoords="offset points",
                        fontsize=10, fontweight="bold", va="bottom")
    wrap_titles(fig)
    text = fitted_title(fig, f"{title}: sequence {report['sequence']}\nSIMULATED, not measured", 10)
    # the figure's title, then the first row's headline and its panels' titles (up to three lines)
    top = 1.0 - ((text.count("\n") + 1) * 10 * 1.3 + HEADLINE_PT + 22) / 72 / fig.get_figheight()
    fig.subplots_adjust(top=top, bottom=0.6 / fig.get_figheight(), left=0.05, right=0.99, hspace=0.75, wspace=0.25)
    fig.suptitle(text, fontsize=10, y=0.995, va="top")
    return fig


def wrap_titles(fig: Figure, fontsize: float = 9) -> None:
    """Break each panel's (left) title into lines that fit the panel's width: the closing's panels
    were written for a figure one panel wide."""
    for ax in fig.axes:
        text = ax.get_title(loc="left")
        if text:
            chars = max(20, int(ax.get_position().width * fig.get_figwidth() * 72 / (0.55 * fontsize)))
            ax.set_title(textwrap.fill(" ".join(text.split()), chars), fontsize=fontsize, loc="left")


def operation_text(entry: dict) -> str:
    """The operation's headline figures for its row's title (ms, m/s, J)."""
    def ms(x: float | None) -> str:
        return "-" if x is None else f"{1e3 * x:.2f} ms"

    parts = []
    if "closing_time_from_latch_s" in entry:
        parts.append(f"closing {ms(entry['closing_time_from_latch_s'])} from the latch "
                     f"({ms(entry['closing_time_from_coil_s'])} from the coil), kinetic margin"
                     + margin_text(entry, brief=True))
    if "opening_time_from_pawl_s" in entry:
        speed = entry["opening_speed_m_s"]
        parts.append(f"opening {ms(entry['opening_time_from_pawl_s'])} from the pawl "
                     f"({ms(entry['opening_time_from_coil_s'])} from the coil), "
                     + ("-" if speed is None else f"{speed:.2f} m/s"))
    return "; ".join(parts)


def closing_row(row: np.ndarray, result: SimulationResult, rig: Rig, fom: dict, t_ms: np.ndarray) -> None:
    """A closing's panels (:mod:`.closing_plot`); a CO's trip and each pole's parting marked."""
    travel_panel(row[0], result, rig, fom, t_ms)
    speed_panel(row[1], result, rig, fom, t_ms)
    contact_bars(row[2], result, rig, t_ms)
    row[2].set_title("contact timing (bar: closed)", fontsize=9, loc="left")
    bounce_closeup(row[3], result, rig, fom, t_ms)
    opening = fom.get("opening")
    if opening is not None:
        for ax in row[:3]:
            ax.axvline(1e3 * opening["trip_s"], color=TRIP, lw=1.0, ls="--")
        row[0].plot([], [], "--", color=TRIP, label="trip (the pawl lets go)")
        partings(row[0], rig, opening, mark_label="parting")
        row[0].legend(fontsize=7, loc="upper left", ncol=2)
    for ax in row[:3]:
        ax.set_xlim(float(t_ms[0]), float(t_ms[-1]))
    for ax in row:
        ax.set_xlabel("t (ms from the closing latch letting go)")


def partings(ax: Axes, rig: Rig, opening: dict, mark_label: str = "") -> None:
    """Each pole's parting (the last separation, from the trip) as a cross at its gap."""
    for i, (gap, part) in enumerate(zip(pole_gaps(rig.breaker.poles), opening["parting_s"]), start=1):
        if part is not None:
            ax.plot(1e3 * (opening["trip_s"] + part), 1e3 * gap, "X", color=pole_colour(i), ms=8, mec="k", mew=0.6)
    if mark_label:
        ax.plot([], [], "X", color="w", mec="k", label=mark_label)


def opening_row(row: np.ndarray, result: SimulationResult, rig: Rig, fom: dict, t_ms: np.ndarray) -> None:
    """An opening's panels (module docstring)."""
    opening = fom["opening"]
    windows = opening_windows(result, rig, opening)
    opening_travel_panel(row[0], result, rig, opening, t_ms)
    opening_speed_panel(row[1], result, rig, opening, windows, t_ms)
    contact_bars(row[2], result, rig, t_ms)
    times = " / ".join("-" if p is None else f"{1e3 * p:.2f}" for p in opening["parting_s"])
    n = len(opening["parting_s"])
    poles = "pole 1" if n == 1 else "poles " + "/".join(str(i) for i in range(1, n + 1))
    row[2].set_title(f"contact timing (bar: closed); partings, {poles}: {times} ms after the trip", fontsize=9,
                     loc="left")
    open_end_panel(row[3], result, opening, t_ms)
    for ax in row[:3]:
        ax.axvline(1e3 * opening["trip_s"], color=TRIP, lw=1.0, ls="--")
        ax.set_xlim(float(t_ms[0]), float(t_ms[-1]))
        ax.set_xlabel("t (ms from the trip)")


def opening_travel_panel(ax: Axes, result: SimulationResult, rig: Rig, opening: dict, t_ms: np.ndarray) -> None:
    """Each pole's contact travel (mm), the mechanism's (F's, from its open rest), the opening zone
    after the parting (shaded, below the nominal gap) and each parting (cross)."""
    ch, b = result.channels, rig.breaker
    start, end = b.opening_speed_zone
    gap = 1e3 * b.poles.contact_gap
    ax.axhspan(gap - 1e3 * end, gap - 1e3 * start, color=ZONE, lw=0,
               label=f"opening zone, {1e3 * start:g}-{1e3 * end:g} mm after parting")
    ax.plot(t_ms, 1e3 * ch["f_travel"], "--", color=MECHANISM, lw=1.2, label="mechanism (F)")
    for i in range(1, b.poles.count + 1):
        ax.plot(t_ms, 1e3 * ch[f"pole_{i}_travel"], color=pole_colour(i), lw=1.4, label=f"pole {i}")
    partings(ax, rig, opening, mark_label="parting")
    ax.plot([], [], "--", color=TRIP, label="trip (the pawl lets go)")
    ax.set_ylabel("travel (mm)")
    ax.set_title("travel: contacts per pole, mechanism dashed; crosses: parting", fontsize=9, loc="left")
    ax.legend(fontsize=7, loc="upper right", ncol=2)
    ax.grid(alpha=0.3)


def opening_windows(result: SimulationResult, rig: Rig, opening: dict) -> list[tuple[float, float] | None]:
    """Per pole, the times (ms) its travel enters and leaves the opening zone after its parting (None
    where it parts not, or does not cross the zone within the run)."""
    start, end = rig.breaker.opening_speed_zone
    out = []
    for i, (gap, part) in enumerate(zip(pole_gaps(rig.breaker.poles), opening["parting_s"]), start=1):
        z, t = result.channels[f"pole_{i}_travel"], result.t
        after = t >= opening["trip_s"] + (part or 0.0)
        into, out_of = (np.nonzero(after & (z <= gap - d))[0] for d in (start, end))
        out.append((1e3 * float(t[into[0]]), 1e3 * float(t[out_of[0]]))
                   if part is not None and into.size and out_of.size else None)
    return out


def opening_speed_panel(ax: Axes, result: SimulationResult, rig: Rig, opening: dict, windows: list,
                        t_ms: np.ndarray) -> None:
    """Each pole's speed towards open (m/s), the window in which the poles cross the opening zone
    (shaded) and each pole's opening speed over it (a bar over its crossing)."""
    crossed = [w for w in windows if w is not None]
    if crossed:
        ax.axvspan(min(a for a, _ in crossed), max(e for _, e in crossed), color=ZONE, lw=0, label="opening zone crossed")
    for i in range(1, rig.breaker.poles.count + 1):
        ax.plot(t_ms, -result.channels[f"pole_{i}_velocity"], color=pole_colour(i), lw=1.2, label=f"pole {i}")
        speed, window = opening["opening_speeds_m_s"][i - 1], windows[i - 1]
        if speed is not None and window is not None:
            ax.hlines(speed, *window, color=pole_colour(i), lw=3.0, alpha=0.8)
    ax.plot([], [], "-", color="0.3", lw=3.0, label="opening speed over the zone")
    ax.set_ylabel("speed towards open (m/s)")
    ax.set_title("contact speed per pole, opening positive", fontsize=9, loc="left")
    ax.legend(fontsize=7, loc="upper right", ncol=2)
    ax.grid(alpha=0.3)


def open_end_panel(ax: Axes, result: SimulationResult, opening: dict, t_ms: np.ndarray) -> None:
    """The mechanism's travel (F's, mm) from the last parting to the end of the run, around its final
    open position: the overtravel beyond it and the rebound back towards closed."""
    done = [p for p in opening["parting_s"] if p is not None]
    first = 1e3 * (opening["trip_s"] + (max(done) if done else 0.0))
    u = 1e3 * result.channels["f_travel"]
    final = 1e3 * opening["open_final_travel_m"]
    after = t_ms >= first
    ax.plot(t_ms[after], u[after], color=MECHANISM, lw=1.4, label="mechanism (F)")
    ax.axhline(final, color="k", lw=0.8, ls=":", label="final open position")
    span = max(1e3 * (opening["opening_overtravel_m"] + opening["opening_rebound_m"]), 0.05)
    ax.set_ylim(final - 4.0 * span, final + 4.0 * span)
    ax.set_xlim(first, float(t_ms[-1]))
    ax.set_title(f"open end close-up: overtravel {1e3 * opening['opening_overtravel_m']:.3f} mm, rebound "
                 f"{1e3 * opening['opening_rebound_m']:.3f} mm", fontsize=9, loc="left")
    ax.set_ylabel("travel (mm)")
    ax.set_xlabel("t (ms from the trip)")
    ax.legend(fontsize=7, loc="upper right")
    ax.grid(alpha=0.3)

"""A closing drawn as a breaker analyser shows it (``simulate --plot`` of a ``vcb_closing`` rig).

Five panels, time in ms, each pole in one colour throughout: travel per pole (mm) with the
mechanism's travel, the speed zone shaded and each touch marked; speed per pole (m/s) over the same
time with the zone's window and the closing-speed limits; contact timing bars (closed = bar); a
close-up of the bounces; the energy the springs release, the kinetic energy and what is dissipated
(J). The figures of the report (:func:`vcbmodel.experiments.summaries.closing_report`) come from the
same run, at the solver's step.
"""
from __future__ import annotations

import os
from typing import TYPE_CHECKING

import numpy as np
import matplotlib.pyplot as plt

from ..experiments.closing_evaluation import energy_balance
from ..experiments.summaries import result_figures
from ..laws.breaker import pole_gaps
from ..rig.units import format_value
from .plots import fitted_title, save

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

    from ..experiments.report import Report
    from ..model.result import SimulationResult
    from ..rig.data import Rig

#: One colour per pole, the same in every panel (matplotlib's first three: blue, orange, green)
POLE_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown")
MECHANISM = "0.35"  # the mechanism's (follower's) travel: grey, dashed
ZONE = "#ffe9a8"  # the speed zone's shading


def pole_colour(i: int) -> str:
    """The colour of pole ``i`` (1-based) in every panel."""
    return POLE_COLOURS[(i - 1) % len(POLE_COLOURS)]


def plot_closing(result: SimulationResult, rig: Rig, path: str | os.PathLike, title: str, report: Report | None = None) -> None:
    """The analyser's view of one closing (:func:`closing_figure`), written to ``path``."""
    save(closing_figure(result, rig, title, report), path, tight=False)


def closing_figure(result: SimulationResult, rig: Rig, title: str, report: Report | None = None) -> Figure:
    """The analyser's view of one closing (module docstring); ``report``'s verdict on the limits in
    the title."""
    fom = result_figures(result, rig)
    fig = plt.figure(figsize=(9.5, 13.0))
    grid = fig.add_gridspec(5, 1, height_ratios=[2.2, 1.6, 0.9, 1.3, 1.3], hspace=0.45)
    travel = fig.add_subplot(grid[0])
    axes = [travel] + [fig.add_subplot(grid[k], sharex=travel) for k in (1, 2)]
    closeup, energy = fig.add_subplot(grid[3]), fig.add_subplot(grid[4], sharex=travel)
    t_ms = 1e3 * result.t
    travel_panel(axes[0], result, rig, fom, t_ms)
    speed_panel(axes[1], result, rig, fom, t_ms)
    timing_panel(axes[2], result, rig, t_ms)
    bounce_closeup(closeup, result, rig, fom, t_ms)
    energy_panel(energy, result, rig, t_ms)
    axes[0].set_xlim(float(t_ms[0]), float(t_ms[-1]))
    verdict = report.verdict(brief=True) if report is not None else ""
    text = fitted_title(fig, f"{title}\nSIMULATED, not measured" + (f"; {verdict}" if verdict else ""), 9)
    # the title's lines (9 pt, 1.3 line spacing) and a third of an inch above the first panel's own title
    top = 1.0 - ((text.count("\n") + 1) * 9 * 1.3 / 72 + 0.35) / fig.get_figheight()
    fig.subplots_adjust(top=top, bottom=0.04, left=0.1, right=0.97)
    fig.suptitle(text, fontsize=9, y=0.995, va="top")
    return fig


def travel_panel(ax: Axes, result: SimulationResult, rig: Rig, fom: dict, t_ms: np.ndarray) -> None:
    """Each pole's contact travel (mm), the mechanism's (the follower's output point), the zone over
    which the closing speed is measured (shaded, before the nominal gap) and each touch (dot)."""
    ch, b = result.channels, rig.breaker
    zone = b.speed_zone
    gap = 1e3 * b.poles.contact_gap
    ax.axhspan(gap - 1e3 * zone[0], gap - 1e3 * zone[1], color=ZONE, lw=0,
               label=f"speed zone, {1e3 * zone[0]:g}-{1e3 * zone[1]:g} mm before touch")
    ax.plot(t_ms, 1e3 * ch["follower_displacement"], "--", color=MECHANISM, lw=1.2, label="mechanism (follower output)")
    for i, (gap_i, touch) in enumerate(zip(pole_gaps(b.poles), fom["per_pole"]["touch_s"]), start=1):
        ax.plot(t_ms, 1e3 * ch[f"pole_{i}_travel"], color=pole_colour(i), lw=1.4, label=f"pole {i}")
        if touch is not None:
            ax.plot(1e3 * touch, 1e3 * gap_i, "o", color=pole_colour(i), ms=6, mec="k", mew=0.6)
    ax.plot([], [], "o", color="w", mec="k", label="touch")
    ax.set_ylabel("travel (mm)")
    ax.set_title("travel: contacts per pole, mechanism dashed", fontsize=9, loc="left")
    ax.legend(fontsize=7, loc="upper left", ncol=2)
    ax.grid(alpha=0.3)


def speed_panel(ax: Axes, result: SimulationResult, rig: Rig, fom: dict, t_ms: np.ndarray) -> None:
    """Each pole's contact speed (m/s), the window in which the poles cross the speed zone (shaded),
    each pole's closing speed over the zone (a bar over its crossing) and the rig's limits on it."""
    ch, b = result.channels, rig.breaker
    spans = zone_windows(result, rig)
    if spans:
        ax.axvspan(min(s for s, _ in spans), max(e for _, e in spans), color=ZONE, lw=0, label="speed zone crossed")
    for i, touch in enumerate(fom["per_pole"]["touch_s"], start=1):
        ax.plot(t_ms, ch[f"pole_{i}_velocity"], color=pole_colour(i), lw=1.2, label=f"pole {i}")
        speed = fom["per_pole"]["closing_speed_m_s"][i - 1]
        if speed is not None and i - 1 < len(spans):
            ax.hlines(speed, *spans[i - 1], color=pole_colour(i), lw=3.0, alpha=0.8)
        if touch is not None:
            ax.plot(1e3 * touch, fom["per_pole"]["touch_speed_m_s"][i - 1], "o", color=pole_colour(i), ms=5, mec="k", mew=0.6)
    for limit in b.limits:
        if limit.figure == "closing_speed":
            for v in (limit.low, limit.high):
                if v is not None:
                    ax.axhline(v, color="crimson", ls=":", lw=1.0)
            ax.plot([], [], ":", color="crimson", label=f"closing speed limit {limit.text()}")
    ax.plot([], [], "-", color="0.3", lw=3.0, label="closing speed over the zone")
    ax.set_ylabel("speed (m/s)")
    ax.set_title("contact speed per pole; dots: touch", fontsize=9, loc="left")
    ax.legend(fontsize=7, loc="best", ncol=2)
    ax.grid(alpha=0.3)


def zone_windows(result: SimulationResult, rig: Rig) -> list[tuple[float, float]]:
    """Per pole (in order, while each has one), the times (ms) its travel enters and leaves the speed zone."""
    out = []
    zone = rig.breaker.speed_zone
    for i, gap in enumerate(pole_gaps(rig.breaker.poles), start=1):
        z = result.channels[f"pole_{i}_travel"]
        enter, leave = (np.argmax(z >= gap - d) if np.any(z >= gap - d) else None for d in zone)
        if enter is None or leave is None:
            break
        out.append((1e3 * float(result.t[enter]), 1e3 * float(result.t[leave])))
    return out


def contact_bars(ax: Axes, result: SimulationResult, rig: Rig, t_ms: np.ndarray) -> None:
    """One row per pole (pole 1 on top): a bar where its contacts are closed."""
    n = rig.breaker.poles.count
    for i, gap in enumerate(pole_gaps(rig.breaker.poles), start=1):
        closed = (result.channels[f"pole_{i}_travel"] > gap).astype(int)
        edges = np.flatnonzero(np.diff(np.concatenate([[0], closed, [0]])))
        spans = [(t_ms[a], t_ms[min(b, len(t_ms) - 1)] - t_ms[a]) for a, b in zip(edges[::2], edges[1::2])]
        ax.broken_barh(spans, (n - i - 0.35, 0.7), color=pole_colour(i))
    ax.set_yticks(range(n), [f"pole {n - k}" for k in range(n)])
    ax.set_ylim(-0.6, n - 0.4)
    ax.grid(alpha=0.3, axis="x")


def timing_panel(ax: Axes, result: SimulationResult, rig: Rig, t_ms: np.ndarray) -> None:
    contact_bars(ax, result, rig, t_ms)
    ax.set_title("contact timing (bar: closed)", fontsize=9, loc="left")
    ax.set_xlabel("t (ms from the latch release)")


def bounce_closeup(ax: Axes, result: SimulationResult, rig: Rig, fom: dict, t_ms: np.ndarray) -> None:
    """The contact timing from the first touch to the last re-closing (the bounces), each pole's
    bounce count and duration (first touch to the last re-closing) in the title."""
    contact_bars(ax, result, rig, t_ms)
    pp = fom["per_pole"]
    touches = [x for x in pp["touch_s"] if x is not None]
    if touches:
        first = 1e3 * min(touches)
        last = max(1e3 * (t + d) for t, d in zip(pp["touch_s"], pp["bounce_duration_s"]) if t is not None)
        pad = max(0.15 * (last - first), 0.2)
        ax.set_xlim(first - pad, last + pad)
    else:
        ax.set_xlim(float(t_ms[0]), float(t_ms[-1]))
    counts = ", ".join(f"pole {i} {count} ({format_value(1e3 * duration, 1e-3)} ms)" for i, (count, duration)
                       in enumerate(zip(pp["bounces"], pp["bounce_duration_s"]), start=1))
    ax.set_title(f"bounce close-up; bounces (touch to last re-closing): {counts}" if touches else
                 "bounce close-up: no pole touches before the run ends", fontsize=9, loc="left")
    ax.set_xlabel("t (ms from the latch release)")


def energy_panel(ax: Axes, result: SimulationResult, rig: Rig, t_ms: np.ndarray) -> None:
    """The energy the closing springs have released, the kinetic energy of every moving part and the
    energy dissipated so far (J); an ANCF spring has no energy bookkeeping (said in the panel)."""
    if result.spec.spring_model.kind == "ancf":
        ax.text(0.5, 0.5, "energy: not computed for the ANCF spring", ha="center", va="center", transform=ax.transAxes)
    else:
        e = energy_balance(result, rig)
        ax.plot(t_ms, e["spring_energy_released"], color="k", lw=1.4, label="released by the closing springs")
        ax.plot(t_ms, e["kinetic"], color="tab:purple", lw=1.2, label="kinetic (all moving parts)")
        ax.plot(t_ms, e["dissipated"], color="tab:brown", lw=1.2, label="dissipated (friction, dampers)")
        ax.plot(t_ms, e["potential"] - e["potential"][0] + e["spring_energy_released"], color="tab:cyan", lw=1.0,
                label="stored elsewhere (opening and wipe springs, contacts, weights)")
        # headroom above the curves for the legend, which then covers none of them
        low, high = ax.get_ylim()
        ax.set_ylim(low, high + 0.45 * (high - low))
        ax.legend(fontsize=7, loc="upper center", ncol=2)
    ax.set_ylabel("energy (J)")
    ax.set_xlabel("t (ms from the latch release)")
    ax.set_title("energy", fontsize=9, loc="left")
    ax.grid(alpha=0.3)

"""Figures (matplotlib, Agg backend). Synthetic measurements are labelled as such."""
from __future__ import annotations

import io
import os
import textwrap
from typing import TYPE_CHECKING

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.backend_bases import FigureCanvasBase  # noqa: E402

from ..experiments import experiment_of  # noqa: E402
from ..rig.units import display  # noqa: E402
from .outputs import write_file  # noqa: E402

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from ..model.result import SimulationResult

DPI = 110


def supported_image_formats() -> tuple[str, ...]:
    """File suffixes matplotlib can write (png, pdf, svg, ...)."""
    return tuple(sorted(FigureCanvasBase.get_supported_filetypes()))


def save(fig: Figure, path: str | os.PathLike, tight: bool = True) -> None:
    """Save ``fig`` to ``path`` in the format its suffix names (``tight``: lay it out tightly first); a
    failed write (a full disk) leaves no partial file."""
    if tight:
        fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, dpi=DPI, format=os.path.splitext(str(path))[1].lstrip(".").lower() or "png")
    plt.close(fig)
    write_file(path, buf.getvalue())


def fitted_title(fig: Figure, text: str, fontsize: float) -> str:
    """``text`` broken into lines that fit ``fig``'s width at ``fontsize`` (pt; a character taken as
    0.55 of the size wide, about DejaVu Sans' average): a long rig name or verdict is not cut off."""
    chars = max(20, int(fig.get_figwidth() * 72 / (0.55 * fontsize)))
    return "\n".join(textwrap.fill(part, chars) for part in text.split("\n"))


def time_axis(t: np.ndarray) -> tuple[np.ndarray, str]:
    """(times, label): in ms for a run under 2 s, else in s."""
    return (1e3 * t, "t (ms)") if t[-1] - t[0] < 2.0 else (t, "t (s)")


def plot_simulation(result: SimulationResult, channels: dict[str, tuple[np.ndarray, str]], path: str | os.PathLike, title: str) -> None:
    """The channels ``simulate`` writes ({name: (values, SI unit)}) against time, one axis per unit, in
    the units an engineer reads (deg, mm, ms; :func:`vcbmodel.rig.units.display`); labelled SIMULATED."""
    units = list(dict.fromkeys(unit for _, unit in channels.values()))
    fig, axes = plt.subplots(len(units), 1, figsize=(8, 2.6 * len(units) + 0.6), sharex=True, squeeze=False)
    t, t_label = time_axis(result.t)
    for ax, unit in zip(axes[:, 0], units):
        shown = display(unit)
        for name, (values, u) in channels.items():
            if u == unit:
                ax.plot(t, shown.factor * values, lw=1.2, label=name.replace("_", " "))
        ax.set_ylabel(f"{' / '.join(n.replace('_', ' ') for n, (_, u) in channels.items() if u == unit)[:40]} "
                      f"({shown.unit or '-'})", fontsize=8)
        ax.legend(fontsize=8, loc="best")
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel(t_label)
    fig.suptitle(fitted_title(fig, f"{title} (SIMULATED, not measured)", 10), fontsize=10)
    save(fig, path)


#: How a residual is drawn, by the measured channel's SI unit: (unit, factor from SI).
RESIDUAL_UNITS = {"rad": ("mrad", 1e3), "m": ("um", 1e6)}


def plot_diagnosis(diagnosis, path: str | os.PathLike, measured_label: str = "measurement") -> None:
    """``diagnose --plot``: :func:`diagnosis_figure` written to ``path``."""
    save(diagnosis_figure(diagnosis, measured_label), path)


def diagnosis_figure(diagnosis, measured_label: str = "measurement") -> Figure:
    """The record and the models before and after, aligned by the fitted nuisance (release time,
    offset, gain); the residuals over the fitted window with the noise band and the window of
    largest disagreement shaded; the part of the record left out (before a hand-driven release)
    greyed. The channel in the unit an engineer reads (deg, mm), its residual in mrad or um, time in
    ms for a record under 2 s."""
    d = diagnosis
    shown = display(d.unit)
    r_unit, r_factor = RESIDUAL_UNITS.get(d.unit, (d.unit, 1.0))
    t_factor, t_unit = (1e3, "ms") if d.measurement.t[-1] - d.measurement.t[0] < 2.0 else (1.0, "s")
    t = t_factor * d.measurement.t
    y = shown.factor * d.measurement.channel(_measured_channel(d))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    ax1.plot(t, y, ".", ms=2, color="0.5", label=measured_label)
    ax1.plot(t, shown.factor * d.baseline.simulations[0].measured, lw=1.5,
             label=f"starting model ({', '.join(d.baseline.effects) or 'no friction'}; {d.baseline.spring_model.label})")
    if d.final is not d.baseline:
        added = ", ".join(d.missing_effects) or "refit"
        ax1.plot(t, shown.factor * d.final.simulations[0].measured, "--", lw=1.5, label=f"+ {added} ({d.final.spring_model.label})")
    w0 = t_factor * (d.nuisance.get("window", [d.measurement.t[0]])[0] if d.nuisance else d.measurement.t[0])
    if w0 > t[0]:
        for ax in (ax1, ax2):
            ax.axvspan(t[0], w0, color="0.85", alpha=0.6, lw=0)
    release = (d.nuisance or {}).get("values", {}).get("release_time")
    if release is not None:
        ax1.axvline(t_factor * release, color="k", lw=0.6, ls="--",
                    label=f"release (fitted) {t_factor * release:.4g} {t_unit}")
    ax1.set_ylabel(f"{_measured_channel(d).replace('_', ' ')} ({shown.unit or d.unit})")
    ax1.legend(fontsize=7)
    verdict = "explained" if d.explained else "NOT explained"
    ax1.set_title(f"diagnosis: missing {', '.join(d.missing_effects) or 'none'}; {verdict}", fontsize=10)
    ax2.plot(t_factor * d.baseline.times[0], r_factor * d.baseline.residuals[0], lw=0.8,
             label=f"residual before (rms {r_factor * d.baseline.rms:.3g} {r_unit})")
    if d.final is not d.baseline:
        ax2.plot(t_factor * d.final.times[0], r_factor * d.final.residuals[0], lw=0.8,
                 label=f"residual after (rms {r_factor * d.final.rms:.3g} {r_unit})")
    for k in (-2, 2):
        ax2.axhline(k * r_factor * d.noise, color="k", lw=0.6, ls=":")
    ax2.plot([], [], ":", color="k", lw=0.6, label=f"noise, +-2 sigma (sigma {r_factor * d.noise:.3g} {r_unit})")
    ax2.axvspan(*(t_factor * np.asarray(d.window)), color="orange", alpha=0.25, label="largest disagreement")
    left = d.verdict.left if d.verdict else None
    if left:
        ax2.axvspan(*(t_factor * np.asarray(left["window"])), color="red", alpha=0.15, label="left unexplained")
    ax2.set_xlabel(f"t ({t_unit}, record time)")
    ax2.set_ylabel(f"model - measurement ({r_unit})")
    ax2.legend(fontsize=7)
    return fig


def _measured_channel(d):
    return experiment_of(d.rig.experiment).measured_channel

"""Figures of a sweep's table (``vcbmodel plot``) and of a friction fit (``identify --plot``).

A sweep's table (docs/cli.md, "sweep") has a column per varied rig field (``friction.mu_k``), a column
per figure of merit whose name ends in its SI unit (``closing_time_s``) and ``status``. A figure is
drawn in the unit an engineer reads (ms, mm, kN; :func:`vcbmodel.rig.units.display`), a varied field
in its rig unit (mm for lengths, deg for angles) when its name says which it is.
"""
from __future__ import annotations

import io
import os
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
import matplotlib.pyplot as plt

from ..errors import InputError
from ..experiments import EXPERIMENTS
from ..rig.reader import read_bytes, text_bytes
from ..experiments.report import label
from ..rig.units import DISPLAY, unit_of_name
from .plots import fitted_title, save

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: SI unit of a rig field by its last name, for a varied column's axis (docs/rig-format.md): lengths
#: in m, angles in rad, and so on; a field not listed is labelled with its path only.
FIELD_UNITS = {
    **dict.fromkeys(("radius", "com_distance", "arm_length", "free_length", "contact_gap", "gap_offsets",
                     "push_rod_length", "roller_radius", "roller_arm", "output_arm", "base_radius", "lift", "diameter",
                     "bore", "pole_pitch", "length", "wire_diameter", "coil_diameter", "roller_width", "arm"), "m"),
    **dict.fromkeys(("initial_angle", "com_angle", "rise_start", "rise_end", "return_start", "return_end", "angle",
                     "rest_angle", "output_angle"), "rad"),
    **dict.fromkeys(("mass", "moving_mass"), "kg"), **dict.fromkeys(("inertia", "inertia_com", "lever_inertia"), "kg m^2"),
    **dict.fromkeys(("stiffness", "wipe_rate", "rod_stiffness"), "N/m"),
    **dict.fromkeys(("preload", "wipe_preload", "bellows_force"), "N"), "shear_modulus": "Pa",
    **dict.fromkeys(("mu_k", "mu_s", "restitution", "count", "active_coils"), "-"),
    **dict.fromkeys(("stick_velocity", "stribeck_velocity", "initial_velocity"), "rad/s"),
    "viscous": "N m s/rad", "release_time": "s",
}
#: Figure columns without a unit in their name
COUNT_COLUMNS = ("bounce_count",)
MAX_GROUPS = 8


def axis_of(column: str) -> tuple[float, str]:
    """(factor, label) of a table column: a figure by its unit suffix (``closing_time_s``: ms), a rig
    field (``breaker.poles.gap_offsets.1``) by its name (:data:`FIELD_UNITS`: mm)."""
    if "." in column:
        parts = column.split(".")
        unit = FIELD_UNITS.get(parts[-2] if parts[-1].isdigit() and len(parts) > 1 else parts[-1])
        name = column
    else:
        unit = unit_of_name(column)
        name = label(column) if unit else column.replace("_", " ")
    if unit == "Pa":
        return 1e-9, f"{name} (GPa)"
    if unit in (None, "-"):
        return 1.0, name
    if unit in DISPLAY:
        return DISPLAY[unit].factor, f"{name} ({DISPLAY[unit].unit})"
    return 1.0, f"{name} ({unit})"


def group_label(column: str, value: float) -> str:
    """``breaker.poles.gap_offsets.1 = -0.3 mm``: a varied field's value in its axis unit."""
    factor, text = axis_of(column)
    unit = text[len(column):].strip(" ()") if text.startswith(column) else ""
    return f"{column} = {factor * value:.4g}" + (f" {unit}" if unit else "")


def read_table(path: str | os.PathLike) -> pd.DataFrame:
    """A sweep's table (``#`` comment lines skipped); refused in one line if it is not one."""
    text = text_bytes(path, read_bytes(path)).decode("utf-8", errors="replace")
    lines = [line for line in text.splitlines() if line.strip() and not line.startswith("#")]
    if len(lines) < 2 or "," not in lines[0]:
        raise InputError(path, "file", "is not a sweep's table (a header and at least one row, comma-separated)")
    try:
        return pd.read_csv(io.StringIO("\n".join(lines)))
    except (ValueError, pd.errors.ParserError) as e:
        raise InputError(path, "file", f"is not a sweep's table ({str(e).splitlines()[0][:80]})") from None


def check_columns(table: pd.DataFrame, path: str, x: str, ys: Sequence[str]) -> None:
    """Each named column exists and holds numbers (one line naming the option, with the columns there are)."""
    for option, column in [("--x", x)] + [("--y", y) for y in ys]:
        if column not in table.columns:
            raise InputError(path, option, f"no column {column!r} (the table has: {', '.join(table.columns)})")
        if not pd.api.types.is_numeric_dtype(table[column]):
            raise InputError(path, option, f"column {column!r} is not numeric")


def varied_columns(table: pd.DataFrame) -> list[str]:
    """The varied rig fields: the columns that are neither ``run``, ``status`` nor a figure of merit."""
    figures = {c for e in EXPERIMENTS.values() for c in e.figure_columns}
    return [c for c in table.columns if c not in ("run", "status") and c not in figures]


def sweep_figure(table: pd.DataFrame, x: str, ys: Sequence[str], title: str) -> Figure:
    """One panel per figure ``ys`` against the varied field ``x``: on a grid, a line per combination of
    the other varied fields (at most MAX_GROUPS); otherwise (random draws) points coloured by the first
    other varied field, with its colour bar. Runs whose ``status`` is not ``ok`` (not closed, failed) are left
    out and counted in the title by status."""
    ok = table[table["status"] == "ok"] if "status" in table.columns else table
    others = [c for c in varied_columns(table) if c != x]
    groups = list(ok.groupby(others)) if others else [((), ok)]
    lines = len(groups) <= MAX_GROUPS and all(g[x].nunique() > 1 and g[x].nunique() == len(g) for _, g in groups)
    fig, axes = plt.subplots(len(ys), 1, figsize=(7.5, 3.2 * len(ys) + 0.8), sharex=True, squeeze=False)
    fx, x_label = axis_of(x)
    for ax, y in zip(axes[:, 0], ys):
        fy, y_label = axis_of(y)
        if lines:
            for k, (key, g) in enumerate(groups):
                g = g.sort_values(x)
                key = key if isinstance(key, tuple) else (key,)
                label = ", ".join(group_label(c, v) for c, v in zip(others, key)) or None
                ax.plot(fx * g[x], fy * g[y], "o-", ms=4, lw=1.3, color=f"C{k % 10}", label=label)
            if others:
                ax.legend(fontsize=7)
        elif others:
            fc, c_label = axis_of(others[0])
            points = ax.scatter(fx * ok[x], fy * ok[y], c=fc * ok[others[0]], s=14, cmap="viridis")
            fig.colorbar(points, ax=ax, label=c_label)
        else:
            ax.plot(fx * ok[x], fy * ok[y], "o", ms=4, color="C0")
        ax.set_ylabel(y_label)
        ax.grid(alpha=0.3)
        missing_values(ax, ok, y)
    axes[-1, 0].set_xlabel(x_label)
    fig.suptitle(fitted_title(fig, title + left_out_text(table, len(ok)), 9), fontsize=9)
    fig.tight_layout()
    return fig


def left_out_text(table: pd.DataFrame, drawn: int) -> str:
    """The title's account of the runs not drawn, by their status: a ``not_closed`` run finished (its
    breaker did not close in the simulated time: a result, counted out of limits by a tolerance study),
    a ``failed: reason`` run did not; empty when every run is drawn."""
    if drawn == len(table):
        return ""
    status = table["status"].astype(str)
    counts = [(int((status == "not_closed").sum()), "not closed (no pole touched in its run)"),
              (int(status.str.startswith("failed").sum()), "failed")]
    counts.append((len(table) - drawn - counts[0][0] - counts[1][0], "of another status"))
    return "; left out: " + ", ".join(f"{n} run{'s' if n > 1 else ''} {what}" for n, what in counts if n)


def missing_values(ax, ok: pd.DataFrame, y: str) -> None:
    """Say in ``ax`` how many drawn (``ok``) runs have no value of ``y`` (an empty cell: a pendulum still
    swinging at the end has no stop time), so an empty or sparse panel is not read as a plotting fault."""
    missing = int(ok[y].isna().sum())
    if missing == len(ok) and missing:
        ax.text(0.5, 0.5, f"no ok run has a value of {y} (its cells are empty)", ha="center", va="center",
                transform=ax.transAxes, fontsize=9)
    elif missing:
        ax.set_title(f"{missing} of {len(ok)} ok runs have no value of {y} (empty cells)", fontsize=8, loc="left")


def plot_sweep(path: str, x: str, ys: Sequence[str], output: str) -> None:
    """``vcbmodel plot``: the sweep table at ``path`` drawn into ``output``."""
    table = read_table(path)
    check_columns(table, path, x, ys)
    title = f"{os.path.basename(path)}: {len(table)} runs, SIMULATED, not measured"  # a figure for a test report
    save(sweep_figure(table, x, ys, title), output, tight=False)


def fit_figure(result) -> Figure:
    """``identify --plot``: per record, the measured angle and the fitted model (deg) against time, and
    the residual (model - record, mrad) with the records' noise band (+-2 sigma)."""
    n = len(result.datasets)
    fig, axes = plt.subplots(2, n, figsize=(7.0 * n, 6.2), squeeze=False, sharex="col",
                             gridspec_kw={"height_ratios": [2, 1]})
    fit = result.fit
    for k, d in enumerate(result.datasets):
        top, bottom = axes[0, k], axes[1, k]
        top.plot(d.t, np.degrees(d.y), ".", ms=2, color="0.55", label="measured")
        top.plot(fit.simulations[k].t, np.degrees(fit.simulations[k].measured), color="tab:red", lw=1.1,
                 label=f"fitted, {result.law} law")
        top.set_ylabel("shaft angle (deg)")
        top.set_title(os.path.basename(d.measurement.path), fontsize=9, loc="left")
        top.legend(fontsize=7)
        top.grid(alpha=0.3)
        times = fit.times[k] if fit.times else d.t
        bottom.plot(times, 1e3 * fit.residuals[k], color="tab:red", lw=0.7,
                    label=f"residual, rms {1e3 * float(np.sqrt(np.mean(fit.residuals[k] ** 2))):.3g} mrad")
        for sign in (-2, 2):
            bottom.axhline(sign * 1e3 * fit.sigma, color="k", ls=":", lw=0.8)
        bottom.plot([], [], ":", color="k", label=f"records' noise, +-2 sigma (sigma {1e3 * fit.sigma:.3g} mrad)")
        bottom.set_ylabel("model - measured (mrad)")
        bottom.set_xlabel("t (s)")
        bottom.legend(fontsize=7)
        bottom.grid(alpha=0.3)
    units = {"stick_velocity": " rad/s", "stribeck_velocity": " rad/s", "viscous": " N m s/rad"}
    values = ", ".join(f"{name} {value:.4g}{units.get(name, '')}" for name, value in result.values.items())
    fig.suptitle(fitted_title(fig, f"friction identification, {result.law} law: {values}", 9), fontsize=9)
    fig.tight_layout()
    return fig


def plot_fit(result, output: str) -> None:
    """``identify --plot``: :func:`fit_figure` written to ``output``."""
    save(fit_figure(result), output, tight=False)


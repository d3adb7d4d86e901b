"""Figures (matplotlib, Agg backend). Synthetic measurements are labelled as such."""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.backend_bases import FigureCanvasBase  # noqa: E402

DPI = 110


def supported_image_formats():
    """File suffixes matplotlib can write (png, pdf, svg, ...)."""
    return tuple(sorted(FigureCanvasBase.get_supported_filetypes()))


def save(fig, path):
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    plt.close(fig)


def plot_diagnosis(diagnosis, path, measured_label="measurement"):
    """Measurement, model before and after; residuals before and after, window shaded."""
    d = diagnosis
    u = d.unit
    t = d.measurement.t
    y = d.baseline.simulations[0].measured - d.baseline.residuals[0]  # the measured channel
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    ax1.plot(t, y, ".", ms=2, color="0.5", label=measured_label)
    ax1.plot(t, d.baseline.simulations[0].measured, lw=1.5,
             label=f"starting model ({', '.join(d.baseline.effects) or 'no friction'}; {d.baseline.spring_model.label})")
    if d.missing_effect:
        ax1.plot(t, d.final.simulations[0].measured, "--", lw=1.5, label=f"+ {d.missing_effect} ({d.final.spring_model.label})")
    ax1.set_ylabel(f"measured channel ({u})")
    ax1.legend(fontsize=8)
    ax1.set_title(f"diagnosis: missing effect = {d.missing_effect}")
    ax2.plot(t, d.baseline.residuals[0], lw=0.8, label=f"residual before (rms {d.baseline.rms:.3g} {u})")
    if d.missing_effect:
        ax2.plot(t, d.final.residuals[0], lw=0.8, label=f"residual after (rms {d.final.rms:.3g} {u})")
    for k in (-2, 2):
        ax2.axhline(k * d.noise, color="k", lw=0.6, ls=":")
    ax2.axvspan(*d.window, color="orange", alpha=0.25, label="largest disagreement")
    ax2.set_xlabel("t (s)")
    ax2.set_ylabel(f"model - measurement ({u})")
    ax2.legend(fontsize=8)
    save(fig, path)

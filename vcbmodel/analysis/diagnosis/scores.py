"""The measures every step judges a fit by: the evidence margin, the share of the noise an effect
must remove, and whether a residual is what the noise alone leaves. Residuals in the measured
channel's unit (rad or m); BIC in units of chi^2 of the whitened residual."""
from __future__ import annotations

import math

import numpy as np

from ..noise import STRUCTURE_TOLERANCE, NoiseModel, consistency, fit_noise, rounding_dominates

#: BIC improvement (in units of chi^2 of the whitened residual) required to name an effect.
#: Kass & Raftery (1995) call a BIC difference above 10 "very strong" evidence.
BIC_MARGIN = 10.0
#: An effect is named only if it also removes at least this fraction of the noise variance from
#: the residual (rms_before^2 - rms_after^2 >= MIN_VARIANCE_GAIN sigma^2). The model's own numerical
#: accuracy against the independent reference is about 0.03 mrad at the pendulum's default step
#: (0.4 % of the potentiometer's noise variance); with n = 6000 samples a systematic difference
#: that small is "significant" by BIC, and an extra parameter can absorb part of it. An effect must
#: explain five times more.
MIN_VARIANCE_GAIN = 0.02
#: A residual that passes the noise tests is told from a model error only when the noise model
#: fitted to it stays within this factor of the record's high-frequency noise; above it the noise
#: is so correlated that a slow model error passes for it, and pairs of effects are tried too
#: (:func:`noise_separable`).
SEPARABLE_NOISE_RATIO = 2.0


def consistent(ctx, fit, noise: NoiseModel | None = None) -> bool:
    """Is ``fit``'s residual what the noise alone leaves (``noise``: its noise model, fitted
    here when not given)?"""
    if noise is None:
        noise = fit_noise(fit.residuals, ctx.sigma_hf, ctx.quantisation)
    return consistency(fit.residuals, noise)["consistent"] and fit.rms <= 1.5 * max(ctx.sigma_hf, noise.marginal_sd)


def noise_of_best(ctx, fits: list) -> NoiseModel:
    """The noise model from the residual of the fit with the smallest residual."""
    best = min(fits, key=lambda f: f.rms)
    return fit_noise(best.residuals, ctx.sigma_hf, ctx.quantisation,
                     source=f"residual of {', '.join(best.effects) or 'no effects'} [{best.spring_model_label}]")


def min_gain(ctx) -> float:
    """The share of the noise variance an effect must remove (MIN_VARIANCE_GAIN; a quantised
    sensor's rounding is deterministic, and a model a little off can follow some of it: there
    an effect must remove STRUCTURE_TOLERANCE, what the verdict tolerates as structure)."""
    return STRUCTURE_TOLERANCE if rounding_dominates(ctx.quantisation, ctx.sigma_hf) else MIN_VARIANCE_GAIN


def variance_gain(ctx, current, fit) -> float:
    """The share of the noise variance a candidate removes from the residual: the drop of the
    white chi^2 (every fitted channel) per sample of the measured channel."""
    def white(f):
        return (float(sum(np.sum(r**2) for r in f.residuals)) / ctx.sigma_hf**2
                + float(sum(np.sum(r**2) for r in f.extra_residuals.values())))
    return (white(current) - white(fit)) / max(1, current.n_data)


def earns_margin(ctx, current, fit, delta_bic: float) -> bool:
    """Does ``fit`` improve on ``current`` enough to be kept: a whitened BIC lower by more than
    :data:`BIC_MARGIN`, and at least :func:`min_gain` of the noise variance removed?"""
    return delta_bic > BIC_MARGIN and variance_gain(ctx, current, fit) >= min_gain(ctx)


def excess_share_left(ctx, current, fit) -> float:
    """The share of the current model's residual variance in excess of the noise that ``fit``
    still leaves."""
    floor = ctx.sigma_hf**2
    before = current.rms**2 - floor
    after = max(fit.rms**2 - floor, 0.0)
    return after / before if before > 0 else 0.0


def noise_separable(ctx, noise: NoiseModel) -> bool:
    """Can a residual consistent with the noise be told from a model error? Not when the noise
    model fitted to that residual (``noise``) is far above the record's own high-frequency noise
    (strongly correlated noise: a slow model error passes for it). Then pairs are tried too."""
    return noise.marginal_sd <= SEPARABLE_NOISE_RATIO * max(ctx.sigma_hf, 1e-300)


def excess(rms: float, sigma: float) -> float:
    """The residual rms in excess of the noise: sqrt(rms^2 - sigma^2), zero below the noise."""
    return math.sqrt(max(rms**2 - sigma**2, 0.0))

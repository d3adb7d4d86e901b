"""Whether a discovered torque earns its place: the same evidence a registered effect must give
the diagnosis (:mod:`vcbmodel.analysis.diagnose`): the BIC of the whitened residual lowered by more
than the margin, and a share of the noise variance removed from the residual. The thresholds are
the caller's (the diagnosis passes its own ``BIC_MARGIN`` and minimum gain), so one number rules both."""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..fit import FitResult
from ..noise import NoiseModel, fit_noise


#: A discovered torque is reported as found only when the model with it leaves no more than the noise
#: in excess, rms <= EXPLAINS x sigma (excess sqrt(rms^2 - sigma^2) <= sigma). A form that lowers BIC
#: but leaves a residual several times the noise absorbs part of something the library does not hold
#: (a forcing at 1.9 Hz on a swing was once "found" as a breakaway torque 45 times the Coulomb level):
#: its coefficient reads that something, not a physical torque. Reported as a partial fit instead.
EXPLAINS = 2.0 ** 0.5


def explains(fit: FitResult, sigma: float) -> bool:
    """Whether ``fit`` leaves the record at the noise in this sense (:data:`EXPLAINS`)."""
    return fit.rms <= EXPLAINS * sigma


def white_chi2(fit: FitResult, sigma: float) -> float:
    """chi^2 of the residual as white noise of level ``sigma`` (every fitted channel)."""
    return (float(sum(np.sum(r**2) for r in fit.residuals)) / sigma**2
            + float(sum(np.sum(r**2) for r in fit.extra_residuals.values())))


def variance_gain(before: FitResult, after: FitResult, sigma: float) -> float:
    """The share of the noise variance ``after`` removes from ``before``'s residual: the drop of the
    white chi^2 per sample of the measured channel (the diagnosis's definition)."""
    return (white_chi2(before, sigma) - white_chi2(after, sigma)) / max(1, before.n_data)


def scoring_noise(fits: Sequence[FitResult], sigma: float, quantisation: float) -> NoiseModel:
    """The noise model every score uses: from the residual of the fit with the smallest residual."""
    best = min(fits, key=lambda f: f.rms)
    return fit_noise(best.residuals, sigma, quantisation, source=f"residual of {best.label or 'the best fit'}")


def evidence(before: FitResult, after: FitResult, noise: NoiseModel, sigma: float, bic_margin: float,
             min_gain: float) -> dict:
    """{delta_bic, variance_gain, earned}: ``after`` against ``before`` under ``noise``."""
    delta = before.bic_with(noise) - after.bic_with(noise)
    gain = variance_gain(before, after, sigma)
    return {"delta_bic": float(delta), "variance_gain": float(gain), "earned": bool(delta > bic_margin and gain >= min_gain)}

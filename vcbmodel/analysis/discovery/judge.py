"""Whether a discovered torque earns its place: the same evidence a registered effect must give
the diagnosis (:mod:`vcbmodel.analysis.diagnose`): the BIC of the whitened residual lowered by more
than the margin, and a share of the noise variance removed from the residual. The thresholds are
the caller's (the diagnosis passes its own ``BIC_MARGIN`` and minimum gain), so one number rules both."""
from __future__ import annotations

from ..fit import FitResult
from ..noise import NoiseModel, noise_of_best as scoring_noise, variance_gain, white_chi2

__all__ = ["evidence", "scoring_noise", "variance_gain", "white_chi2"]


def evidence(before: FitResult, after: FitResult, noise: NoiseModel, sigma: float, bic_margin: float,
             min_gain: float) -> dict:
    """{delta_bic, variance_gain, earned}: ``after`` against ``before`` under ``noise``."""
    delta = before.bic_with(noise) - after.bic_with(noise)
    gain = variance_gain(before, after, sigma)
    return {"delta_bic": float(delta), "variance_gain": float(gain), "earned": bool(delta > bic_margin and gain >= min_gain)}

"""The measures every step judges a fit by: the evidence margin and the share of the noise an
effect must remove (thresholds from :class:`.options.DiagnosisOptions`); whether a residual is at
the noise is :mod:`.at_noise`'s one criterion. Residuals in the measured channel's unit (rad or
m); BIC in units of chi^2 of the whitened residual."""
from __future__ import annotations

from ..noise import NoiseModel, noise_of_best as _noise_of_best, rounding_dominates, variance_gain as _variance_gain


def noise_of_best(ctx, fits: list) -> NoiseModel:
    """The noise model from the residual of the fit with the smallest residual."""
    return _noise_of_best(fits, ctx.sigma_hf, ctx.quantisation)


def min_gain(ctx) -> float:
    """The share of the noise variance an effect must remove (``min_variance_gain``; a quantised
    sensor's rounding is deterministic, and a model a little off can follow some of it: there an
    effect must remove ``structure_tolerance``, what the verdict tolerates as structure)."""
    o = ctx.options
    return o.structure_tolerance if rounding_dominates(ctx.quantisation, ctx.sigma_hf) else o.min_variance_gain


def variance_gain(ctx, current, fit) -> float:
    """The share of the noise variance a candidate removes from the residual
    (:func:`vcbmodel.analysis.noise.variance_gain` at the record's high-frequency level)."""
    return _variance_gain(current, fit, ctx.sigma_hf)


def earns_margin(ctx, current, fit, delta_bic: float) -> bool:
    """Does ``fit`` improve on ``current`` enough to be kept: a whitened BIC lower by more than
    ``bic_margin``, and at least :func:`min_gain` of the noise variance removed?"""
    return delta_bic > ctx.options.bic_margin and variance_gain(ctx, current, fit) >= min_gain(ctx)


def earns(ctx, current, candidate) -> bool:
    """Does ``candidate`` (:class:`.state.Candidate`) earn its place on top of ``current``: its
    evidence (the whitened BIC drop on the record plus, with held-out records, the drop of their
    predictions' whitened chi^2) above ``bic_margin``, and the share of the noise variance it
    removes (on the record, plus the held-out records') at least :func:`min_gain`? Without
    held-out records this is :func:`earns_margin`."""
    return (candidate.evidence > ctx.options.bic_margin
            and variance_gain(ctx, current, candidate.fit) + candidate.held_out_gain >= min_gain(ctx))


def excess_share_left(ctx, current, fit) -> float:
    """The share of the current model's residual variance in excess of the noise that ``fit``
    still leaves."""
    floor = ctx.sigma_hf**2
    before = current.rms**2 - floor
    after = max(fit.rms**2 - floor, 0.0)
    return after / before if before > 0 else 0.0


def noise_separable(ctx, noise: NoiseModel) -> bool:
    """Can a residual at the noise be told from a model error? Not when the noise model fitted to
    that residual (``noise``) is far above the record's own high-frequency noise
    (``separable_noise_ratio``: strongly correlated noise, a slow model error passes for it).
    Then pairs are tried too."""
    return noise.marginal_sd <= ctx.options.separable_noise_ratio * max(ctx.sigma_hf, 1e-300)

"""Step 2, fit the starting model (the rig's ``model``): its free values and the record's
nuisance. For a free swing the fitted model's extremes are compared with the record's: a model
that drifts out of phase is refitted with the period as a nuisance (:mod:`.period`), so the
effect search does not chase it. The first noise model comes from this residual."""
from __future__ import annotations

import time

from ..noise import fit_noise
from .fits import fit_record, parameters
from .period import imply_period, needs_period, period_mismatch


def fit_start(ctx, state) -> None:
    """Set ``state.baseline`` (and ``current``, ``all_fits``; ``period`` if the fit drifts)."""
    rig, rec = ctx.rig, ctx.record
    ctx.say(f"fitting the starting model ({', '.join(rig.model.effects) or 'no effects'}, "
            f"{rig.model.spring_model.label}) with the record's nuisance")
    params = parameters(ctx, rig.model.effects, initial=ctx.guesses[0])
    baseline = fit_record(ctx, rig.model.effects, rig.model.spring_model, params, "starting model",
                          starts=ctx.guesses[1:])
    drift = period_mismatch(ctx, baseline)
    if needs_period(ctx, drift):
        state.period = drift
        imply_period(ctx, drift)
        params = parameters(ctx, rig.model.effects, baseline.values)
        baseline = fit_record(ctx, rig.model.effects, rig.model.spring_model, params, "starting model (period fitted)")
    ctx.search.noise = fit_noise(baseline.residuals, ctx.sigma_hf, ctx.quantisation)
    ctx.say(f"starting model rms {baseline.rms:.3g} {rec.unit} ({baseline.rms / ctx.sigma_hf:.1f}x the "
            f"high-frequency noise); {time.monotonic() - ctx.budget.started:.0f} s")
    state.baseline = state.current = baseline
    state.all_fits = [baseline]

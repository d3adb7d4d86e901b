"""Step 5, judge the residual: the final noise model (an autoregressive model of the best
residual, :mod:`..noise`) re-scores every step of the search; the verdict ``explained`` is true
only when the final residual is what that noise alone leaves (whitened residual white, level as
the record's), otherwise it says what is left (window, size, signature). Selections the evidence
does not settle are reported as ties. The starting model is put on the final model's alignment of
the record, so the gap is not hidden by a nuisance bent to the wrong model."""
from __future__ import annotations

import numpy as np

from ...errors import SimulationError
from ...records.signals import disagreement_window, dominant_frequency, lag1_autocorrelation
from ..fit import FitAborted, FitResult
from ..noise import consistency, fit_noise
from .fits import fit_record, parameters
from .scores import BIC_MARGIN, excess, noise_of_best


def verdict(ctx, final: FitResult) -> dict:
    """Is the final residual what the noise alone would leave? With what is left if not."""
    noise = fit_noise(final.residuals, ctx.sigma_hf, ctx.quantisation, source="final model's residual")
    lags = 20 if final.n_data > 2000 else 10
    c = consistency(final.residuals, noise, lags=lags)
    # level against the record's own high-frequency noise: a correlated residual must also be
    # explained by a plausible noise process (not by model error dressed up as noise)
    white_equiv = ctx.sigma_hf
    c["rms_over_high_frequency_noise"] = final.rms / white_equiv if white_equiv > 0 else float("nan")
    explained = bool(c["consistent"])
    out = {"explained": explained, "tests": c, "noise_of_final_residual": noise.to_json()}
    if not explained:
        t = final.times[0]
        r = final.residuals[0]
        t0, t1, peak = disagreement_window(t, r, noise.marginal_sd)
        out["left"] = {"window": [t0, t1], "rms": final.rms, "excess": excess(final.rms, ctx.noise.marginal_sd),
                       "dominant_frequency_hz": dominant_frequency(t, r), "lag1_autocorrelation":
                       lag1_autocorrelation(r), "peak_running_rms": peak}
    return out


def _tie(ctx, chosen, rival) -> dict:
    """A tie between the kept ``chosen`` and ``rival``, with the part of the record where the two
    fitted models differ most (what would separate them)."""
    t = chosen.fit.times[0] if chosen.fit.times else ctx.dataset.t
    difference = np.asarray(chosen.fit.residuals[0]) - np.asarray(rival.fit.residuals[0])
    t0, t1, _ = disagreement_window(t, difference, ctx.noise.marginal_sd)
    return {"between": [chosen.effect, rival.effect], "round": chosen.round,
            "delta_bic_between": float(chosen.delta_bic - rival.delta_bic),
            "separate_by": {"window": [float(t0), float(t1)],
                            "largest_model_difference": float(np.max(np.abs(difference))),
                            "channel": ctx.record.measured_channel}}


def ties(ctx, path: list, candidates: list) -> list:
    """Selections the evidence does not settle: a kept effect whose runner-up in the same round
    also earned the margin over the model before and trails it by no more than the margin
    (scored with the final noise model). For each: what would separate them, the part of the
    record where the two fitted models differ most."""
    out = []
    for step in path:
        if step.get("with"):
            continue
        chosen = next((c for c in candidates if c.round == step["round"] and c.effect == step["effect"]), None)
        if chosen is None:
            continue
        rivals = [c for c in candidates if c.round == chosen.round and c is not chosen and "+" not in c.effect
                  and c.delta_bic > BIC_MARGIN and chosen.delta_bic - c.delta_bic <= BIC_MARGIN]
        out.extend(_tie(ctx, chosen, rival) for rival in sorted(rivals, key=lambda c: -c.delta_bic))
    return out


def on_final_alignment(ctx, baseline: FitResult, final: FitResult) -> FitResult:
    """The starting model on the record as the final model aligns it: its own free values
    refitted with the record's nuisance (release time, initial angle, sensor offset and gain,
    uncertain rig values) held at the final model's estimate. The nuisance belongs to the
    record, and the best model estimates it best; fitted with the starting model it bends to
    hide part of what that model lacks, and the gap would look smaller than it is. Kept only if
    it is not better than the starting model's own fit (a fit can stop short)."""
    params = parameters(ctx, baseline.effects, baseline.values)
    for name, p in params.items():
        if p.kind != "model" and name in final.parameters:
            p.value, p.vary = final.parameters[name].value, False
    try:
        aligned = fit_record(ctx, baseline.effects, baseline.spring_model, params, "starting model (final alignment)")
    except (FitAborted, SimulationError):
        return baseline
    if aligned.rms <= baseline.rms:
        return baseline
    ctx.say(f"the starting model on the final model's alignment of the record: rms {aligned.rms:.3g} "
            f"(with its own alignment {baseline.rms:.3g})")
    return aligned


def _rescore(ctx, state) -> None:
    """Every step of the search scored again with the final noise model."""
    final = state.final
    ctx.noise = noise_of_best(ctx, [final] + [f for f in state.all_fits if f.rms < final.rms])
    for step in state.path:
        step["delta_bic_final_noise"] = step["_before"].bic_with(ctx.noise) - step["_fit"].bic_with(ctx.noise)
    for b in state.backward:
        b["delta_bic_final_noise"] = b["_without"].bic_with(ctx.noise) - b["_with"].bic_with(ctx.noise)
    for c in state.candidates:
        c.delta_bic = state.round_ref[c.round].bic_with(ctx.noise) - c.fit.bic_with(ctx.noise)
    state.missing = [step["effect"] for step in state.path]
    state.selection = [{k: v for k, v in step.items() if not k.startswith("_")} for step in state.path] + [
        {k: v for k, v in b.items() if not k.startswith("_")} for b in state.backward]


def judge(ctx, state) -> None:
    """Step 5 (see the module docstring): sets ``state.final``, ``verdict``, ``missing``,
    ``selection``, and the baseline on the final alignment."""
    state.final = final = state.current
    _rescore(ctx, state)
    state.verdict = verdict(ctx, final)
    found = ties(ctx, state.path, state.candidates)
    if found:
        state.verdict["ambiguous"] = found
    if state.period:
        state.verdict["period"] = state.period
    if state.coarse_spring is not None:
        state.verdict["spring_model_refined"] = {
            "from": state.coarse_spring.spring_model_label, "to": final.spring_model_label,
            "delta_bic": state.coarse_spring.bic_with(ctx.noise) - final.bic_with(ctx.noise)}
    state.own_alignment = state.baseline
    if final is not state.baseline and not ctx.stop.is_set():
        state.baseline = on_final_alignment(ctx, state.baseline, final)

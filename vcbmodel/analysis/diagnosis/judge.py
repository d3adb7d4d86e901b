"""Step 5, judge the residual: before a "not explained", the record's time base is fitted as a
nuisance (:func:`time_base`); the final noise model (an autoregressive model of the best
residual, :mod:`..noise`) re-scores every step of the search; the verdict ``explained`` is true
only when the final residual, the sensor's lines and timing jitter set aside, is what that noise
alone leaves (whitened residual white, level as the record's) and stands within the noise that
witnesses the fit did not shape show (:mod:`..verdict_evidence`: the rig's stated sensor noise, the
record before the release, its high-frequency level); otherwise it says what is left (window,
size, signature). Selections the evidence
does not settle are reported as ties. The starting model is put on the final model's alignment of
the record, so the gap is not hidden by a nuisance bent to the wrong model."""
from __future__ import annotations

import numpy as np

from ...errors import SimulationError
from ...records.signals import disagreement_window, dominant_frequency, lag1_autocorrelation
from ..fit import FitAborted, FitResult
from ..fit.dataset import time_scale_name
from ..time_base import MIN_CLOCK_ERROR, clock_from_lines
from ..verdict_evidence import gather_witnesses, judge_residual, mechanism_band
from .fits import fit_record, parameters
from .period import period_fields_fitted
from .scores import BIC_MARGIN, excess, noise_of_best


def verdict(ctx, final: FitResult) -> dict:
    """Is the final residual what the noise alone would leave, the sensor's artefacts set aside and
    against witnesses the fit did not shape (:mod:`..verdict_evidence`)? With what is left if not."""
    rec = ctx.record
    band = mechanism_band(rec.natural_frequency(ctx.rig) if rec.natural_frequency else None)
    release = final.values.get("release_time_0", ctx.setup.release)
    witnesses = gather_witnesses((ctx.rig.record or {}).get("sensor_noise"), ctx.measurement.t,
                                 ctx.measurement.channel(rec.measured_channel), release,
                                 ctx.setup.still_start and not ctx.setup.hand_start, ctx.sigma_hf, ctx.quantisation)
    model = final.simulations[0].measured[ctx.dataset.mask()] if final.simulations else None
    out = judge_residual(final.times, final.residuals, ctx.sigma_hf, ctx.quantisation, witnesses, band, release,
                         lags=20 if final.n_data > 2000 else 10, model=model)
    if not out["explained"]:
        t = final.times[0]
        r = out["cleaned"][0]
        t0, t1, peak = disagreement_window(t, r, out["noise_of_final_residual"]["sigma"])
        rms = out["rms_without_sensor_lines"]
        out["left"] = {"window": [t0, t1], "rms": rms, "excess": excess(rms, ctx.noise.marginal_sd),
                       "dominant_frequency_hz": dominant_frequency(t, r), "lag1_autocorrelation":
                       lag1_autocorrelation(r), "peak_running_rms": peak}
    return out


def time_base(ctx, state) -> None:
    """Before the verdict "not explained": the record's clock may be off (:mod:`..time_base`). The
    current model is refitted with the time scale as a nuisance: read off a mains line when the
    residual holds one (the grid's frequency is known), else fitted within +-1 % (not where the
    rig's inertia is fitted too: a clock and an inertia error change a swing alike). Kept if it
    lowers the whitened BIC by more than the margin, stays inside its bounds (a scale at +-1 %
    stands in for something else) and is a clock's error at all (MIN_CLOCK_ERROR)."""
    current = state.current
    if ctx.over() or ctx.time_scale is not None:
        return
    first = verdict(ctx, current)
    if first["explained"]:
        return
    clock = clock_from_lines(first["_lines"])
    if clock is not None:
        ctx.time_scale = {"value": clock[0], "sd": clock[1], "source": "mains line"}
    elif period_fields_fitted(ctx):
        return
    else:
        ctx.time_scale = {"value": 1.0, "sd": None, "source": "fitted"}
    ctx.say(f"the final model leaves more than the noise: refitting it with the record's time base as a nuisance "
            f"({ctx.time_scale['source']})")
    try:
        timed = fit_record(ctx, current.effects, current.spring_model, parameters(ctx, current.effects, current.values),
                           "final model (record's time base fitted)")
    except (FitAborted, SimulationError):
        ctx.time_scale = None
        return
    state.all_fits.append(timed)
    noise = noise_of_best(ctx, state.all_fits)
    gain = current.bic_with(noise) - timed.bic_with(noise)
    scale = timed.parameters[time_scale_name(0)]
    if gain <= BIC_MARGIN or scale.at_bound() or abs(scale.value - 1.0) < MIN_CLOCK_ERROR:
        ctx.say(f"time base: scale {scale.value:.5f}, rms {timed.rms:.3g} {ctx.record.unit}, delta BIC {gain:.1f}: "
                "not kept")
        ctx.time_scale = None
        return
    ctx.say(f"time base: scale {scale.value:.5f}; rms {current.rms:.3g} -> {timed.rms:.3g} {ctx.record.unit} "
            f"(delta BIC {gain:.0f})")
    for step in state.path:  # the selection's steps lead to this model now
        if step["_fit"] is current:
            step["_fit"] = timed
    state.current = timed


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
    also improves on the model before and trails it by no more than the margin
    (scored with the final noise model). For each: what would separate them, the part of the
    record where the two fitted models differ most."""
    out = []
    for step in path:
        if step.get("with"):
            continue
        chosen = next((c for c in candidates if c.round == step["round"] and c.effect == step["effect"]), None)
        if chosen is None:
            continue
        # a rival that improves on the model before and trails the kept effect by no more than the
        # margin: the evidence does not prefer one (also when the rival itself falls short of the
        # margin over the model before: then the kept effect barely earns it)
        rivals = [c for c in candidates if c.round == chosen.round and c is not chosen and "+" not in c.effect
                  and c.delta_bic > 0 and chosen.delta_bic - c.delta_bic <= BIC_MARGIN]
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
    time_base(ctx, state)
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
            "delta_bic": state.coarse_spring.bic_with(ctx.noise) - final.bic_with(ctx.noise),
            # the best other chain can have fewer masses (or another convention): finer only with more
            "finer": final.spring_model.masses > state.coarse_spring.spring_model.masses}
    state.own_alignment = state.baseline
    if final is not state.baseline and not ctx.stop.is_set():
        state.baseline = on_final_alignment(ctx, state.baseline, final)

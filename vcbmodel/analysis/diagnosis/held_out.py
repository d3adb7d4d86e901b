"""Records the fit never saw: a rig's other records (another release angle or preload, a repeat)
predicted with the model values fitted on the diagnosed record. Each held-out record is aligned
as the diagnosed one is (:func:`.align.align`: its own noise, window and nuisance's starting
values), then only its nuisance (release time, sensor offset, initial angle...) is fitted; the
model's values stay as fitted. Its residual is judged by the one criterion (:mod:`.at_noise`)
against its own noise and witnesses. ``explained`` requires every held-out record at its noise:
a model that absorbed a missing effect into wrong values fits its own record at the noise and
mispredicts a record at another amplitude or speed. Units: the record's (rad or m)."""
from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace

from ...errors import SimulationError
from ..fit import FitAborted, FitResult
from ..noise import noise_of_best, variance_gain
from .align import align
from .at_noise import judge_noise
from .context import Context
from .fits import fit_record, parameters
from .state import State


def record_context(ctx, rig: object, measurement: object) -> Context:
    """A context for another record of the rig, aligned, sharing ``ctx``'s pool, budget and options."""
    other = Context(rig, measurement, ctx.pool, ctx.budget, False, ctx.processes, ctx.options)
    align(other, State())
    return other


def predict(hctx: Context, model: FitResult) -> FitResult:
    """``model``'s effects and spring with its model values held, on the record of ``hctx``: only
    the record's nuisance is fitted."""
    params = parameters(hctx, model.effects, model.values)
    for name, p in params.items():
        if p.kind == "model" and name in model.parameters:
            params[name] = replace(p, value=model.parameters[name].value, vary=False)
    return fit_record(hctx, model.effects, model.spring_model, params, f"prediction of {hctx.measurement.path}")


def prediction(hctx: Context, model: FitResult) -> FitResult:
    """:func:`predict`, once per model and record (kept on the record's context with the model,
    so that its id stays its own)."""
    kept = hctx.search.predictions.get(id(model))
    if kept is None or kept[0] is not model:
        kept = hctx.search.predictions[id(model)] = (model, predict(hctx, model))
    return kept[1]


def prediction_pairs(ctx: Context, current: FitResult, fit: FitResult) -> Iterator[tuple[Context, FitResult, FitResult]]:
    """(held-out context, prediction by ``current``, prediction by ``fit``) for each held-out record
    both models predict (a record either cannot simulate is left out)."""
    for h in held_out_contexts(ctx):
        try:
            yield h, prediction(h, current), prediction(h, fit)
        except (FitAborted, SimulationError):
            continue


def held_out_evidence(ctx, current: FitResult, fit: FitResult) -> tuple[float, float]:
    """What the held-out records say of ``fit`` against ``current`` (both fitted on the diagnosed
    record), summed over the records: the drop of the whitened chi^2 of their predictions (under
    each record's noise model, from the better prediction's residual) and the share of each
    record's noise variance removed. Predictions are out of sample: no parameter is charged."""
    delta = gain = 0.0
    for h, before, after in prediction_pairs(ctx, current, fit):
        noise = noise_of_best([before, after], h.sigma_hf, h.quantisation)
        delta += before.chi2_with(noise) - after.chi2_with(noise)
        gain += variance_gain(before, after, h.sigma_hf)
    return delta, gain


def held_out_share_left(ctx, current: FitResult, fit: FitResult) -> float:
    """The share of the held-out records' prediction variance in excess of their noise (summed
    over the records) that ``fit`` still leaves, against ``current``."""
    before = after = 0.0
    for h, a, b in prediction_pairs(ctx, current, fit):
        before += max(a.rms**2 - h.sigma_hf**2, 0.0)
        after += max(b.rms**2 - h.sigma_hf**2, 0.0)
    return after / before if before > 0 else 0.0


def prediction_row(hctx: Context, model: FitResult) -> dict:
    """``model`` predicting the record of ``hctx``: its rms, over the record's noise, and whether
    the residual is at the noise (:func:`.at_noise.judge_noise`)."""
    try:
        fit = prediction(hctx, model)
    except (FitAborted, SimulationError) as e:
        return {"record": str(hctx.measurement.path), "at_noise": False, "rms": None, "rms_over_noise": float("inf"),
                "failed": str(e).splitlines()[0][:200]}
    judgement = judge_noise(hctx, fit)
    return {"record": str(hctx.measurement.path), "at_noise": judgement.at_noise, "rms": fit.rms,
            "noise": hctx.sigma_hf, "rms_over_noise": fit.rms / hctx.sigma_hf, "fit": fit}


def held_out_contexts(ctx) -> list[Context]:
    """The held-out records' contexts, aligned once per diagnosis (kept on ``ctx``)."""
    if ctx.search.held_out_contexts is None:
        ctx.search.held_out_contexts = [record_context(ctx, rig, meas) for rig, meas in ctx.held_out]
    return ctx.search.held_out_contexts


def held_out_at_noise(ctx, model: FitResult) -> bool:
    """Does ``model`` predict every held-out record at its noise (True when there are none)?"""
    return all(prediction_row(h, model)["at_noise"] for h in held_out_contexts(ctx))


def moved_values(ctx, hctx: Context, model: FitResult) -> dict:
    """``model`` refitted on the held-out record of ``hctx`` (its values free): each fitted model
    value there against the diagnosed record's, in combined stated errors (``z``), the names that
    moved by more than the options' ``moved_errors``, and the refit's rms over the record's noise and
    whether it is at the noise (the one criterion).
    A value that moves between records of one rig names an amplitude- or speed-dependent effect the
    model lacks; a refit that stays above the noise, a shape the model cannot follow at any values."""
    try:
        refit = fit_record(hctx, model.effects, model.spring_model, parameters(hctx, model.effects, model.values),
                           f"refit on {hctx.measurement.path}")
    except (FitAborted, SimulationError):
        return {}
    values = {}
    for name, p in model.parameters.items():
        q = refit.parameters.get(name)
        if p.kind != "model" or not p.vary or q is None or not p.stderr or not q.stderr:
            continue
        z = (q.value - p.value) / (p.stderr**2 + q.stderr**2) ** 0.5
        values[name] = {"here": q.value, "stderr": q.stderr, "fitted_record": p.value, "stderr_fitted_record": p.stderr,
                        "z": z}
    moved = [name for name, v in values.items() if abs(v["z"]) > ctx.options.moved_errors]
    return {"values_refitted_here": values, "moved": moved, "refit_rms_over_noise": refit.rms / hctx.sigma_hf,
            "refit_at_noise": judge_noise(hctx, refit).at_noise}


def predict_held_out(ctx, state) -> list[dict]:
    """Every held-out record predicted by the starting and the final model, and the final model
    refitted on it (:func:`moved_values`): rows for the verdict's ``held_out`` (the final model's
    prediction, ``rms_before`` the starting model's)."""
    rows = []
    for hctx in held_out_contexts(ctx):
        before = prediction_row(hctx, state.baseline)
        after = prediction_row(hctx, state.final) if state.final is not state.baseline else before
        row = {k: v for k, v in after.items() if k != "fit"}
        row.update(rms_before=before["rms"], rms_before_over_noise=before["rms_over_noise"])
        row.update(moved_values(ctx, hctx, state.final))
        rows.append(row)
    return rows

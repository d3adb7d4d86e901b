"""Step 7, report: the diagnosis as the user reads it (:class:`.result.Diagnosis`): the window
where model and record disagree most, the residual's signature, the record's nuisance (with the
sensor's artefacts and the record's time base), the model forms around the final model
(:mod:`..model_forms`) with the verdict they can overturn (:func:`.judge.judge_forms`), the
evidence in words (:mod:`.evidence`), the
thresholds that produced it (:class:`.options.DiagnosisOptions`) and the time spent."""
from __future__ import annotations

import time

from ...records.signals import disagreement_window
from ..fit.dataset import time_scale_name
from .evidence import describe_signature, evidence_text, nuisance_report
from .judge import judge_forms
from ..model_forms import diagnosis_model_forms
from .period import period_fields_fitted
from .pinned import pinned_caveat, pinned_gain
from .result import Diagnosis
from .time_base import time_base_report


def window(ctx, fit: object) -> tuple:
    """Where ``fit``'s residual stands out most from the noise (record time, s)."""
    t0, t1, _ = disagreement_window(fit.times[0], fit.residuals[0], ctx.search.noise.marginal_sd)
    return (t0, t1)


def timing(ctx) -> dict:
    """Time and work spent, and whether the budget cut the search short."""
    b = ctx.budget
    return {"seconds": time.monotonic() - b.started, "budget_used_s": b.used(),
            "simulations": ctx.pool.simulations, "simulations_reused": getattr(ctx.pool, "reused", 0),
            "fits": ctx.search.fits,
            "budget_s": b.seconds, "budget_reached": bool(b.skipped or b.stop.is_set()),
            "skipped": list(b.skipped)}


def nuisance(ctx, state) -> dict:
    """The record's nuisance with what the sensor added (each artefact under its name) and the
    record's time base when it was fitted."""
    final = state.final
    out = nuisance_report(ctx, final, state.period, state.verdict.explained)
    out.update({f.name: f.json for f in state.verdict.artefacts})
    if ctx.search.time_scale is not None and time_scale_name(0) in final.parameters:
        p = final.parameters[time_scale_name(0)]
        out["time_base"] = time_base_report(p.value, p.stderr, ctx.search.time_scale["source"], period_fields_fitted(ctx))
    return out


def report(ctx, state) -> None:
    """Sets ``state.diagnosis``."""
    baseline, final = state.baseline, state.final
    stopped = sorted(state.stopped - {c.effect for c in state.candidates})
    where = window(ctx, baseline)
    signature = describe_signature(ctx, baseline, final)
    pinned = pinned_gain(ctx, final)
    forms = diagnosis_model_forms(ctx, final, pinned, ctx.search.noise)
    judge_forms(ctx, state.verdict, final, forms)  # a form the record prefers that moves a stated value
    found = nuisance(ctx, state)
    evidence = evidence_text(ctx, baseline, final, state.missing, where, signature, state.verdict, state.period,
                             state.backward, state.start_at_noise)
    if pinned:
        found["pinned_sensitivity"] = [pinned]
        evidence += (" " + pinned_caveat(pinned)) if pinned_caveat(pinned) else ""
    spent = timing(ctx)
    ctx.say(f"missing effects: {', '.join(state.missing) or 'none'}; rms {baseline.rms:.3g} -> {final.rms:.3g} "
            f"{ctx.record.unit}; explained: {state.verdict.explained}; {spent['seconds']:.0f} s, "
            f"{spent['simulations']} simulations")
    selection = [s.to_json() for s in state.path] + [b.to_json() for b in state.backward]
    state.diagnosis = Diagnosis(ctx.rig, ctx.measurement, ctx.search.noise, baseline, state.candidates, state.missing, final,
                                where, signature, evidence, stopped, state.verdict, found, spent, selection,
                                state.discovery, state.discovered, ctx.options, state.start_at_noise, forms)

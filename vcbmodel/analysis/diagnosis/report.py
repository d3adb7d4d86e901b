"""Step 7, report: the diagnosis as the user reads it (:class:`.result.Diagnosis`): the window
where model and record disagree most, the residual's signature, the record's nuisance, the
evidence in words (:mod:`..diagnosis_report`; the sensor's artefacts, the record's time base and the
verdict's independent evidence from :mod:`..verdict_evidence`) and the time spent."""
from __future__ import annotations

import time

from ...records.signals import disagreement_window
from ..diagnosis_report import describe_signature, evidence_text, nuisance_report
from ..fit.dataset import time_scale_name
from ..model_forms import diagnosis_model_forms
from ..time_base import time_base_report
from ..verdict_evidence import sensor_nuisance, strip_private, verdict_sentences
from .period import period_fields_fitted
from .pinned import pinned_caveat, pinned_gain
from .result import Diagnosis
from .scores import BIC_MARGIN


def window(ctx, fit: object) -> tuple:
    """Where ``fit``'s residual stands out most from the noise (record time, s)."""
    t0, t1, _ = disagreement_window(fit.times[0], fit.residuals[0], ctx.noise.marginal_sd)
    return (t0, t1)


def timing(ctx) -> dict:
    """Time and work spent, and whether the budget cut the search short."""
    b = ctx.budget
    return {"seconds": time.monotonic() - b.started, "budget_used_s": b.used(),
            "simulations": ctx.pool.simulations, "fits": ctx.fits,
            "budget_s": b.seconds, "budget_reached": bool(b.skipped or b.stop.is_set()),
            "skipped": list(b.skipped)}


def report(ctx, state) -> None:
    """Sets ``state.diagnosis``."""
    baseline, final = state.baseline, state.final
    stopped = sorted(state.stopped - {c.effect for c in state.candidates})
    where = window(ctx, baseline)
    signature = describe_signature(ctx, baseline, final)
    nuisance = nuisance_report(ctx, final, state.period, state.verdict["explained"])
    nuisance.update(sensor_nuisance(state.verdict, ctx.quantisation, ctx.sigma_hf, ctx.record.unit))
    if ctx.time_scale is not None and time_scale_name(0) in final.parameters:
        p = final.parameters[time_scale_name(0)]
        nuisance["time_base"] = time_base_report(p.value, p.stderr, ctx.time_scale["source"], period_fields_fitted(ctx))
    evidence = evidence_text(ctx, baseline, final, state.missing, where, signature, state.verdict, state.period,
                             state.backward, BIC_MARGIN)
    evidence += verdict_sentences(state.verdict, ctx.record.unit)
    pinned = pinned_gain(ctx, final)
    if pinned:
        nuisance["pinned_sensitivity"] = [pinned]
        evidence += (" " + pinned_caveat(pinned)) if pinned_caveat(pinned) else ""
    forms = diagnosis_model_forms(ctx, final, pinned, ctx.noise)
    state.verdict = strip_private(state.verdict)
    spent = timing(ctx)
    ctx.say(f"missing effects: {', '.join(state.missing) or 'none'}; rms {baseline.rms:.3g} -> {final.rms:.3g} "
            f"{ctx.record.unit}; explained: {state.verdict['explained']}; {spent['seconds']:.0f} s, "
            f"{spent['simulations']} simulations")
    state.diagnosis = Diagnosis(ctx.rig, ctx.measurement, ctx.noise, baseline, state.candidates, state.missing, final,
                                where, signature, evidence, stopped, state.verdict, nuisance, spent, state.selection,
                                state.own_alignment, state.discovery, state.discovered, forms)

"""Step 5, judge the residual: before a "not explained", the record's time base is fitted as a
nuisance (:func:`time_base`); the final noise model (an autoregressive model of the best
residual, :mod:`..noise`) re-scores every step of the search; the verdict ``explained`` is true
only when the final residual is at the noise by the diagnosis's one criterion (:mod:`.at_noise`:
the sensor's artefacts set aside, the whitened residual white at the record's level, and within
the noise that witnesses the fit did not shape show) and every held-out record of the rig is
predicted at its own noise (:mod:`.held_out`); otherwise it says what is left (window, size,
signature). Selections the evidence does not settle are reported as ties. Once the report step has
fitted the model forms, a plausible form the record prefers by more than the margin that moves a
stated value, or a value the forms determine outside its plausible range, makes the record not
explained (:func:`judge_forms`). The starting model
keeps its own best alignment of the record: the gap is each model at its own best."""
from __future__ import annotations

import numpy as np

from ...errors import SimulationError
from ...records.signals import disagreement_window, dominant_frequency, lag1_autocorrelation
from ..fit import FitAborted, FitResult
from ..fit.dataset import time_scale_name
from ..model_forms import form_values
from ..noise import excess
from ..plausibility import findings_of, implausible
from .artefacts import found_named
from .at_noise import judge_noise
from .fits import fit_record, parameters
from .held_out import predict_held_out
from .period import period_fields_fitted
from .scores import noise_of_best
from .state import Candidate, SelectionStep, Verdict, adopt
from .time_base import clock_from_lines


def what_is_left(ctx, final: FitResult, judgement) -> dict:
    """Where and how much of ``final``'s residual (its artefacts set aside) the noise leaves."""
    t = final.times[0]
    r = judgement.cleaned[0]
    t0, t1, peak = disagreement_window(t, r, judgement.noise.marginal_sd)
    return {"window": [t0, t1], "rms": judgement.rms, "excess": excess(judgement.rms, ctx.search.noise.marginal_sd),
            "dominant_frequency_hz": dominant_frequency(t, r), "lag1_autocorrelation": lag1_autocorrelation(r),
            "peak_running_rms": peak}


def verdict(ctx, final: FitResult, held_out: list | None = None) -> Verdict:
    """Is the final residual at the noise (:func:`.at_noise.judge_noise`), and is every held-out
    record (``held_out``: :func:`.held_out.predict_held_out`'s rows) predicted at its noise?
    With what is left if not."""
    judgement = judge_noise(ctx, final)
    held = held_out or []
    explained = judgement.at_noise and all(row["at_noise"] for row in held)
    left = None if judgement.at_noise else what_is_left(ctx, final, judgement)
    return Verdict(explained, judgement, left, held_out=held)


def time_base(ctx, state) -> None:
    """Before the verdict "not explained": the record's clock may be off (:mod:`.time_base`). The
    current model is refitted with the time scale as a nuisance: read off a mains line when the
    residual holds one (the grid's frequency is known), else fitted within +-1 % (not where the
    rig's inertia is fitted too: a clock and an inertia error change a swing alike). Kept if it
    lowers the whitened BIC by more than the margin, stays inside its bounds (a scale at +-1 %
    stands in for something else) and is a clock's error at all (``min_clock_error``)."""
    current = state.current
    if ctx.over() or ctx.search.time_scale is not None:
        return
    first = judge_noise(ctx, current)
    if first.at_noise:
        return
    lines = found_named(list(first.artefacts), "sensor_lines")
    clock = clock_from_lines(lines.estimate if lines else None)
    if clock is not None:
        ctx.search.time_scale = {"value": clock[0], "sd": clock[1], "source": "mains line"}
    elif period_fields_fitted(ctx):
        return
    else:
        ctx.search.time_scale = {"value": 1.0, "sd": None, "source": "fitted"}
    ctx.say(f"the final model leaves more than the noise: refitting it with the record's time base as a nuisance "
            f"({ctx.search.time_scale['source']})")
    try:
        timed = fit_record(ctx, current.effects, current.spring_model, parameters(ctx, current.effects, current.values),
                           "final model (record's time base fitted)")
    except (FitAborted, SimulationError):
        ctx.search.time_scale = None
        return
    _keep_time_base(ctx, state, current, timed)


def _keep_time_base(ctx, state, current: FitResult, timed: FitResult) -> None:
    """Keep the fit with the record's time base if it earns it (see :func:`time_base`)."""
    state.all_fits.append(timed)
    noise = noise_of_best(ctx, state.all_fits)
    gain = current.bic_with(noise) - timed.bic_with(noise)
    scale = timed.parameters[time_scale_name(0)]
    if gain <= ctx.options.bic_margin or scale.at_bound() or abs(scale.value - 1.0) < ctx.options.min_clock_error:
        ctx.say(f"time base: scale {scale.value:.5f}, rms {timed.rms:.3g} {ctx.record.unit}, delta BIC {gain:.1f}: "
                "not kept")
        ctx.search.time_scale = None
        return
    ctx.say(f"time base: scale {scale.value:.5f}; rms {current.rms:.3g} -> {timed.rms:.3g} {ctx.record.unit} "
            f"(delta BIC {gain:.0f})")
    adopt(state.path, current, timed)  # the selection's steps lead to this model now
    state.current = timed


def _tie(ctx, chosen: Candidate, rival: Candidate) -> dict:
    """A tie between the kept ``chosen`` and ``rival``, with the part of the record where the two
    fitted models differ most (what would separate them)."""
    t = chosen.fit.times[0] if chosen.fit.times else ctx.dataset.t
    difference = np.asarray(chosen.fit.residuals[0]) - np.asarray(rival.fit.residuals[0])
    t0, t1, _ = disagreement_window(t, difference, ctx.search.noise.marginal_sd)
    return {"between": [chosen.effect, rival.effect], "round": chosen.round,
            "delta_bic_between": float(chosen.evidence - rival.evidence),
            "separate_by": {"window": [float(t0), float(t1)],
                            "largest_model_difference": float(np.max(np.abs(difference))),
                            "channel": ctx.record.measured_channel}}


def ties(ctx, path: list[SelectionStep], candidates: list[Candidate]) -> list:
    """Selections the evidence does not settle: a kept effect whose runner-up in the same round
    also improves on the model before and trails it by no more than the margin (scored with the
    final noise model, plus the held-out records' evidence where there are any). For each: what would separate them, the part of the
    record where the two fitted models differ most."""
    out = []
    margin = ctx.options.bic_margin
    for step in path:
        if step.pair:
            continue
        chosen = next((c for c in candidates if c.round == step.round and c.effect == step.effect), None)
        if chosen is None:
            continue
        # a rival that improves on the model before and trails the kept effect by no more than the
        # margin: the evidence does not prefer one (also when the rival itself falls short of the
        # margin over the model before: then the kept effect barely earns it)
        # (the evidence the selection used: the record's BIC drop plus, with held-out records, their
        # predictions' chi^2 drop, which can separate two effects the record alone cannot)
        rivals = [c for c in candidates if c.round == chosen.round and c is not chosen and "+" not in c.effect
                  and c.evidence > 0 and chosen.evidence - c.evidence <= margin]
        out.extend(_tie(ctx, chosen, rival) for rival in sorted(rivals, key=lambda c: -c.delta_bic))
    return out


def _rescore(ctx, state) -> None:
    """Every step of the search scored again with the final noise model."""
    final = state.final
    ctx.search.noise = noise_of_best(ctx, [final] + [f for f in state.all_fits if f.rms < final.rms])
    for step in state.path:
        step.delta_bic_final_noise = step.before.bic_with(ctx.search.noise) - step.fit.bic_with(ctx.search.noise)
    for b in state.backward:
        b.delta_bic_final_noise = b.without.bic_with(ctx.search.noise) - b.with_.bic_with(ctx.search.noise)
    for c in state.candidates:
        c.delta_bic = state.round_ref[c.round].bic_with(ctx.search.noise) - c.fit.bic_with(ctx.search.noise)
    state.missing = [step.effect for step in state.path]


def _spring_refined(ctx, state) -> dict | None:
    """The spring-model refinement, when a finer (or other) chain replaced the selected one."""
    if state.coarse_spring is None:
        return None
    return {"from": state.coarse_spring.spring_model_label, "to": state.final.spring_model_label,
            "delta_bic": state.coarse_spring.bic_with(ctx.search.noise) - state.final.bic_with(ctx.search.noise),
            # the best other chain can have fewer masses (or another convention): finer only with more
            "finer": state.final.spring_model.masses > state.coarse_spring.spring_model.masses}


def judge(ctx, state) -> None:
    """Step 5 (see the module docstring): sets ``state.final``, ``verdict`` and ``missing``."""
    time_base(ctx, state)
    state.final = final = state.current
    _rescore(ctx, state)
    held = predict_held_out(ctx, state) if ctx.held_out else []
    state.verdict = verdict(ctx, final, held)
    state.verdict.implausible = implausible_values(ctx.rig, final)
    state.verdict.explained = state.verdict.explained and not state.verdict.implausible
    state.verdict.ambiguous = ties(ctx, state.path, state.candidates)
    state.verdict.period = state.period
    state.verdict.spring_model_refined = _spring_refined(ctx, state)


def rival_form(rig, final: FitResult, forms, options) -> dict | None:
    """A plausible model form (``forms``: :class:`..model_forms.ModelForms` around ``final``) that
    fits the record better than the final model by more than ``options.rival_form_margin`` (the forms'
    BIC: a rounded record's runs of identical values counted once, :func:`..noise.rounding_bic`) and
    moves a value the final fit states beyond ``options.rival_form_errors`` of its stated errors (in
    the forms' common meanings; a value the form lacks is 0 there): the report's values then belong
    to a model the record itself rejects. None when there is no such form."""
    if forms is None or not forms.forms:
        return None
    # the best form whose values are all in their plausible ranges (when none fits as well as an
    # implausible one, the forms' weights count every form, ``weighed``, but no implausible form
    # refuses the verdict)
    selected, best = forms.forms[0], forms.best_plausible
    gain = selected.bic - best.bic
    if best is selected or gain <= options.rival_form_margin:
        return None
    stated, _ = form_values(rig, final)
    theirs, _ = form_values(rig, best.fit)
    moved = []
    for name, p in final.parameters.items():
        if p.kind != "model" or not p.vary or name not in stated:
            continue
        value, se = stated[name]
        other = theirs.get(name, (0.0, 0.0))[0]
        if 0 < se < float("inf") and abs(other - value) > options.rival_form_errors * se:
            moved.append({"parameter": name, "stated": value, "stderr": se, "form_value": other,
                          "errors": (other - value) / se})
    if not moved:
        return None
    worst = max(moved, key=lambda m: abs(m["errors"]))
    message = (f"the model form '{best.alternative.label}' fits the record better than the final model by "
               f"{gain:.0f} BIC (margin {options.rival_form_margin:g}) and puts {worst['parameter']} at "
               f"{worst['form_value']:.4g}, {abs(worst['errors']):.1f} stated errors from its {worst['stated']:.4g}: "
               "the stated values belong to a model the record rejects")
    return {"form": best.alternative.label, "delta_bic": gain, "moved": moved, "message": message}


def unresolved_forms(rig, final: FitResult, forms, errors: float) -> list[dict]:
    """The parameters of model forms within the evidence margin that the record does not resolve to
    their stated errors (their profiles reach beyond them, :mod:`..fit.profile`) and that, at a profile's
    end, move a value the final fit states beyond ``errors`` of its stated errors (in the forms'
    meanings; ``options.rival_form_errors``, the rival-form rule's): each with those values' model-form
    intervals. The final values then rest on a form the record cannot tell from the final model."""
    if forms is None:
        return []
    stated, _ = form_values(rig, final)
    varied = {name: vse for name, vse in stated.items() if name in forms.quantities
              and final.parameters.get(name) is not None and final.parameters[name].vary and 0 < vse[1] < np.inf}
    out = []
    for f in forms.forms:
        for pr in (pr for pr in f.profiles if f.within_margin and pr.wider):
            moved = {name: [forms.quantities[name].low, forms.quantities[name].high] for name, (v, se) in varied.items()
                     if any(abs(end[name] - v) > errors * se for end in pr.ends if name in end)}
            if moved:
                out.append({"form": f.alternative.label, "parameter": pr.parameter, "stated": list(pr.stated),
                            "profile": [pr.low, pr.high], "values": moved})
    return out


def implausible_forms(rig, forms) -> list[dict]:
    """The quantities the record determines over the model forms (``forms``: the forms within the
    evidence margin, weighed) whose estimate lies outside its plausible range
    (:func:`..plausibility.findings_of`), as JSON: the reading the record prefers among the forms it
    cannot tell apart is no physical rig's, whatever the final fit's own values and errors say (its
    wide error can hold a rival form's implausible value that the rival-form rule then lets pass)."""
    if forms is None or not forms.quantities:
        return []
    return [f.to_json() for f in findings_of(rig, {}, {}, forms.quantities)]


def judge_forms(ctx, verdict: Verdict, final: FitResult, forms) -> None:
    """After the model forms are fitted (report step): a :func:`rival_form` or an implausible estimate
    over the forms (:func:`implausible_forms`) makes the record not explained, with the form and the
    values it moves, or the value, in the verdict; a form the record does not resolve
    (:func:`unresolved_forms`) is named beside the verdict."""
    verdict.unresolved_forms = unresolved_forms(ctx.rig, final, forms, ctx.options.rival_form_errors)
    verdict.rival_form = rival_form(ctx.rig, final, forms, ctx.options)
    verdict.implausible_forms = implausible_forms(ctx.rig, forms)
    if verdict.rival_form or verdict.implausible_forms:
        verdict.explained = False


def implausible_values(rig, fit) -> list[dict]:
    """The fitted model values of ``fit`` no physical rig has or that break their law's constraint
    (:func:`vcbmodel.analysis.plausibility.implausible`, ranges with sources in parameters.py), as JSON."""
    varied = {name: p for name, p in fit.parameters.items() if p.vary and p.kind == "model"}
    findings = implausible(rig, {name: p.value for name, p in varied.items()},
                           {name: p.stderr for name, p in varied.items()})
    return [f.to_json() for f in findings]

"""The diagnosis' evidence in words, the residual's signature and the record's nuisance, from a
finished search (the steps hold the search; this room only describes it). Units: times s,
frequencies Hz, the measured channel's unit (rad or m) for residuals.
"""
from __future__ import annotations

import numpy as np

from ...records.analyser import figures_of_merit
from ...records.signals import disagreement_window, dominant_frequency, lag1_autocorrelation, stands_out
from .state import Verdict
from .witnesses import witness_text


#: What a nuisance value read by a model that does not explain the record is worth: the release
#: time, the period and the time base then absorb the model's error as readily as the record's
#: (a friction law outside the registered ones pausing at each reversal passes for a pre-trigger
#: and a period error), so they support no conclusion about the rig or the record.
UNEXPLAINED_CAVEAT = ("the final model does not explain the record: the nuisance values (pre-trigger, period, "
                      "time base) may absorb its error (e.g. friction outside the registered laws) and support no "
                      "conclusion about the rig or the record")


def nuisance_report(ctx, final, period, explained: bool = True) -> dict:
    """The record's nuisance as the diagnosis estimated it: values, standard errors, what was pinned,
    the fit window, the pre-trigger (s), notes, the rig values taken as uncertain, units; with
    ``conclusive`` false and :data:`UNEXPLAINED_CAVEAT` when the final model does not explain
    the record (``explained``)."""
    s = ctx.setup
    vals = {}
    stderr = {}
    for p in final.parameters.values():
        if p.kind == "model":
            continue
        key = {"release_time_0": "release_time", "sensor_offset_0": "sensor_offset", "sensor_gain_0": "sensor_gain",
               "initial_angle_0": "initial_angle"}.get(p.name, p.name)
        vals[key] = p.value
        if p.vary:
            stderr[key] = p.stderr
    out = {"values": vals, "stderr": stderr, "estimated": list(stderr),
           "pinned": dict(s.pinned), "window": list(s.window), "hand_start": s.hand_start,
           "pre_trigger_s": max(0.0, vals.get("release_time", s.release) - float(ctx.measurement.t[0]))
           if not s.hand_start else None, "notes": list(s.notes),
           "uncertain": dict(ctx.uncertain), "implied_uncertain": dict(ctx.search.implied),
           "units": {"release_time": "s", "initial_angle": "rad", "sensor_offset": ctx.record.unit,
                     "sensor_gain": "-"}}
    if period:
        out["period_mismatch"] = period
    out["conclusive"] = bool(explained)
    if not explained:
        out["caveat"] = UNEXPLAINED_CAVEAT
    return out


def period_sentence(ctx, period: dict, explained: bool) -> str:
    """The swing period's mismatch in words: what it says of the rig or the record's clock, only
    when the final model explains the record; otherwise a friction-model error explains the
    mismatch as well, and the sentence says so and concludes nothing."""
    text = (f" The record's swing period differs from the model's by {100 * period['relative']:+.2f} % "
            f"(+-{100 * period['stderr']:.2f} %)")
    if not explained:
        return (text + ": as the final model does not explain the record, the rig's I/(M g L), the record's time "
                "base or friction outside the registered laws (pauses at reversals) could each cause it; "
                "no conclusion is drawn about the rig or the record.")
    return (text + f": the rig's I/(M g L) is about {200 * period['relative']:+.1f} % off or the record's time base "
            f"{100 * period['relative']:+.2f} %; "
            + ("the period was fitted as a nuisance (pendulum inertia)." if ctx.search.implied else
               "the rig marks the period's fields uncertain, so they were fitted."))


def describe_signature(ctx, baseline, final=None) -> dict:
    """Features of the residual (and, by the experiment's record, of the measurement) that
    point at an effect; for the final model's residual too when given."""
    def feats(fit):
        t = fit.times[0]
        r = fit.residuals[0]
        half = t.size // 2
        return {"residual_rms_over_noise": fit.rms / ctx.search.noise.marginal_sd,
                "residual_growth": float(np.sqrt(np.mean(r[half:] ** 2)) / max(np.sqrt(np.mean(r[:half] ** 2)), 1e-300)),
                "residual_dominant_frequency_hz": dominant_frequency(t, r),
                "lag1_autocorrelation": lag1_autocorrelation(r)}

    sig = feats(baseline)
    m = ctx.dataset.mask()
    meas = ctx.measurement.window(ctx.setup.window[0], ctx.setup.window[1])
    model = baseline.simulations[0].measured[m]
    sig.update(ctx.record.signature(ctx.rig, meas, model, baseline.residuals[0], ctx.search.noise.marginal_sd))
    if final is not None and final is not baseline:
        sig["final"] = feats(final)
    if any(ch.endswith("_contact") for ch in ctx.dataset.fitted_channels):
        sig["figures_of_merit"] = closing_figures(ctx, final or baseline)
    if ctx.record.natural_frequency is not None:
        sig["swing_frequency_hz"] = ctx.record.natural_frequency(ctx.rig)
    return sig


def closing_figures(ctx, fit) -> dict:
    """A closing's figures of merit as a breaker analyser computes them
    (:mod:`vcbmodel.records.analyser`), from the record (times from the fitted release) and from
    the fitted model on the same time axis."""
    t = ctx.measurement.t
    release = fit.values.get("release_time_0", ctx.setup.release)
    chans = sorted((c for c in ctx.dataset.fitted_channels if c.endswith("_contact")),
                   key=lambda c: int(c.split("_")[1]))
    measured = figures_of_merit(t, [ctx.measurement.channel(c) for c in chans],
                                ctx.measurement.channel(ctx.record.measured_channel), release)
    model = fit.simulations[0]
    modelled = figures_of_merit(t, [(np.nan_to_num(model.channels[c]) > 0.5).astype(float) for c in chans],
                                np.nan_to_num(model.measured), release)
    return {"record": measured, "model": modelled}


def evidence_text(ctx, baseline, final, missing, window, signature, verdict: Verdict, period, backward=(),
                  start_at_noise: bool = False) -> str:
    """The diagnosis' evidence in words: the starting residual, what the record's signature shows,
    what forward selection kept (each lowering the whitened BIC by more than the options'
    ``bic_margin``), ties, spring-model refinement, held-out records and the verdict with its
    tests, the sensor's artefacts and the independent witnesses."""
    text = _start_text(ctx, baseline, window, signature, verdict, period)
    text += _selection_text(ctx, baseline, final, missing, backward, start_at_noise)
    text += _ties_text(ctx, verdict)
    text += _verdict_text(ctx, final, verdict)
    if verdict.implausible:
        text += (" Not explained: the final fit's values are not a physical rig's ("
                 + "; ".join(f["message"] for f in verdict.implausible) + ").")
    if verdict.rival_form:
        text += " Not explained: " + verdict.rival_form["message"] + "."
    if verdict.implausible_forms:
        text += (" Not explained: over the model forms the record cannot tell apart, a value is not a physical "
                 "rig's (" + "; ".join(f["message"] for f in verdict.implausible_forms) + ").")
    return text + _unresolved_text(verdict) + artefact_sentences(verdict, ctx.record.unit)


def _unresolved_text(verdict: Verdict) -> str:
    """A sentence for each model form the record does not resolve (``verdict.unresolved_forms``): the
    final values it leaves open, to be read from the model forms' intervals."""
    text = ""
    for u in verdict.unresolved_forms:
        values = "; ".join(f"{name} in [{lo:.4g}, {hi:.4g}]" for name, (lo, hi) in u["values"].items())
        text += (f" The record does not resolve {u['parameter']} of the model form '{u['form']}', which it cannot "
                 f"tell from the final model: refitted with it held, {u['parameter']} keeps [{u['profile'][0]:.4g}, "
                 f"{u['profile'][1]:.4g}] within 95 % (its stated [{u['stated'][0]:.4g}, {u['stated'][1]:.4g}])"
                 + (f"; the final values rest on it, read them from the model forms: {values}." if values else "."))
    return text


def _start_text(ctx, baseline, window, signature, verdict: Verdict, period) -> str:
    """The starting residual and what the record's signature shows."""
    unit = ctx.record.unit
    sigma = ctx.search.noise.marginal_sd
    peak = disagreement_window(baseline.times[0], baseline.residuals[0], sigma)[2]
    where = (f"largest in t = [{window[0]:.4g}, {window[1]:.4g}] s" if stands_out(peak, sigma) else
             "nowhere standing out: its running rms stays under twice the noise")
    text = (f"The starting model leaves an rms residual of {baseline.rms:.3g} {unit}, "
            f"{baseline.rms / sigma:.2f}x the noise {sigma:.3g} {unit} (lag-1 correlation of the noise "
            f"{ctx.search.noise.lag1:.2f}), {where}.")
    if "amplitude_decay" in signature and signature["amplitude_decay"].get("shape") != "unknown":
        d = signature["amplitude_decay"]
        def stops(s):
            return "does not stop within the record" if s is None else f"stops at {s:.2f} s"
        text += (f" The measured swing amplitude decays {d['shape']}ly over {d['peaks']} peaks and "
                 f"{stops(signature['measured_stop_time_s'])} (model: {stops(signature['model_stop_time_s'])}).")
    if "spring_surge_frequency_hz" in signature:
        text += (f" Residual grows {signature['residual_growth']:.1f}x from the first to the second half; "
                 f"its dominant frequency is {signature['residual_dominant_frequency_hz']:.0f} Hz "
                 f"(spring surge {signature['spring_surge_frequency_hz']:.0f} Hz).")
    if period and period["significant"]:
        text += period_sentence(ctx, period, verdict.explained)
    return text


def _selection_text(ctx, baseline, final, missing, backward, start_at_noise: bool) -> str:
    """What forward selection kept, and what the refinements changed."""
    unit, sigma, margin = ctx.record.unit, ctx.search.noise.marginal_sd, ctx.options.bic_margin
    if start_at_noise:
        text = (" The starting model's residual is already at the noise (the criterion the verdict uses), its level "
                "confirmed by evidence the fit did not shape: no effect is searched, none is named.")
    elif missing:
        where = " on this record and the held-out records' predictions together" if ctx.held_out else ""
        text = (f" Forward selection keeps {', '.join(missing)} (each lowering the whitened BIC by more than "
                f"{margin:g}{where}); the rms goes {baseline.rms:.3g} -> {final.rms:.3g} {unit}, each model at its own best "
                f"alignment of the record ({final.rms / sigma:.2f}x the noise).")
    else:
        text = f" No candidate lowers the whitened BIC by more than {margin:g}."
    for b in backward:
        if b.dropped and b.swap_for:
            text += (f" {b.effect} was kept on the way but replaced by {b.swap_for} at the end (whitened BIC "
                     f"lower by {b.delta_bic:.1f}).")
        elif b.dropped:
            text += (f" {b.effect} was kept on the way but dropped at the end: with the others in, it earns only "
                     f"{b.delta_bic:.1f} in BIC.")
    return text


def _ties_text(ctx, verdict: Verdict) -> str:
    """Ties the evidence does not settle, and a spring model refined."""
    unit, margin = ctx.record.unit, ctx.options.bic_margin
    text = ""
    for tie in verdict.ambiguous:
        a, b = tie["between"]
        w = tie["separate_by"]["window"]
        text += (f" AMBIGUOUS between {a} and {b}: {a} was kept, but {b} explains the record almost as well "
                 f"(BIC {tie['delta_bic_between']:.1f} apart, under the margin {margin:g}); the two models differ "
                 f"most in t = [{w[0]:.4g}, {w[1]:.4g}] s (by {tie['separate_by']['largest_model_difference']:.3g} "
                 f"{unit} in {tie['separate_by']['channel']}): a record of that part with less noise, or a second "
                 "test, would separate them.")
    refined = verdict.spring_model_refined
    if refined:
        how = ("was too coarse for this record" if refined.get("finer", True) else
               f"fitted this record less well than {refined['to']}, which is not a finer chain")
        text += (f" The spring model {refined['from']} {how}: with {refined['to']} the "
                 f"whitened BIC drops by {refined['delta_bic']:.0f} (a model fidelity issue, not a missing effect).")
    return text


def _verdict_text(ctx, final, verdict: Verdict) -> str:
    """The verdict with its tests (and the held-out records' predictions)."""
    unit, sigma = ctx.record.unit, ctx.search.noise.marginal_sd
    text = held_out_text(verdict, unit)
    if verdict.explained:
        text += " The final residual is consistent with the noise (white once whitened, at the record's level): explained."
    elif verdict.judgement.at_noise:
        text += (" NOT explained: the fitted record's residual is at its noise, but a held-out record is not predicted "
                 "at its noise: the values fitted here do not hold on the rig's other records (an effect the model "
                 "lacks absorbed into them, or values this record does not pin).")
    else:
        left = verdict.left or {}
        tests = verdict.tests
        text += (f" NOT explained: the final model leaves {final.rms:.3g} {unit} ({final.rms / sigma:.1f}x the noise),"
                 f" largest in t = [{left.get('window', [0, 0])[0]:.4g}, {left.get('window', [0, 0])[1]:.4g}] s, dominant "
                 f"frequency {left.get('dominant_frequency_hz', float('nan')):.3g} Hz; "
                 + _why_not_noise(tests)
                 + ". Something no registered effect describes is missing, or the rig or record is not what its "
                 "files say.")
    return text


def _why_not_noise(tests: dict) -> str:
    """Why a residual is not at the noise, from the judgement's ``tests``: not white once whitened, a
    function of the motion (:mod:`.motion`), or beyond what the independent witnesses show."""
    if not tests.get("consistent"):
        return (f"whitened residual not white (Ljung-Box p {tests.get('ljung_box_p', float('nan')):.2g}, "
                f"periodogram p {tests.get('periodogram_p', float('nan')):.2g})")
    motion = tests.get("motion_structure") or {}
    if motion.get("holds") is False:
        return (f"it passes only as correlated noise, but it is a function of the motion: smooth functions of the "
                f"model's reading and rate take {100 * (1 - motion['rms_left_over_rms']**2):.0f} % of its variance "
                f"(delta BIC {motion['delta_bic']:.0f}, margin {motion['margin']:g}), which a sensor's noise does not")
    return "it passes for the noise model fitted to it, but not for the noise the record shows independently (below)"


def artefact_sentences(verdict: Verdict, unit: str) -> str:
    """The sensor's artefacts set aside and the independent evidence in words."""
    text = "".join(f.sentence for f in verdict.artefacts)
    ev = verdict.judgement.evidence
    if ev:
        text += " " + witness_text(ev, unit)
    return text


def _refit_sentence(row: dict) -> str:
    """What the final model refitted on a held-out record it did not predict says."""
    ratio = row.get("refit_rms_over_noise")
    if row["at_noise"] or ratio is None:
        return ""
    if not row["refit_at_noise"]:
        return (f" Refitted on {row['record']} with its own values the model still leaves {ratio:.2f}x its noise: a "
                "shape it cannot follow at any values, an effect is missing.")
    if row.get("moved"):
        return ""
    values = ", ".join(f"{k} {v['here']:.4g} +- {v['stderr']:.2g}" for k, v in row["values_refitted_here"].items())
    return (f" Refitted on {row['record']} the model reaches {ratio:.2f}x its noise with values within their errors of "
            f"these ({values} there): the model holds, this record does not pin its values.")


def held_out_text(verdict: Verdict, unit: str) -> str:
    """The held-out records' predictions in words ('' when the rig has none)."""
    if not verdict.held_out:
        return ""
    parts = [f"{row['record']} at {row['rms_over_noise']:.2f}x its noise ({'at' if row['at_noise'] else 'NOT at'} "
             "the noise)" for row in verdict.held_out]
    text = (" Predicted with the values fitted here and each record's own alignment, the held-out records stand: "
            + "; ".join(parts) + ".")
    for row in verdict.held_out:
        text += _refit_sentence(row)
        for name in row.get("moved", ()):
            v = row["values_refitted_here"][name]
            text += (f" Refitted on {row['record']}, {name} is {v['here']:.4g} against {v['fitted_record']:.4g} here "
                     f"({abs(v['z']):.1f} combined stated errors): a value that moves between records of one rig names "
                     "an amplitude- or speed-dependent effect the model lacks.")
    return text

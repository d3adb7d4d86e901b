"""The discrepancy workflow: where do model and measurement disagree, and what is missing?

1. Start from the rig's ``model``; fit its free parameters (those the rig does not give).
2. Estimate the sensor noise from the data alone (:func:`vcbmodel.records.signals.noise_estimate`).
3. Locate the disagreement (the window where the running rms of the residual is largest)
   and describe its signature (decay shape, growth, dominant frequency, whiteness).
4. For every registered effect the model lacks (and that applies to the experiment), add
   it, refit, and score it by BIC = chi^2 + k ln N with the estimated noise; the best is
   named only if it lowers BIC by more than :data:`BIC_MARGIN`, else ``missing_effect`` is
   null (the starting model explains the data within the noise).
5. Report the gap before and after, the fitted parameters and the evidence.

The loop runs over :data:`vcbmodel.model.effects.EFFECTS`: registering an effect makes it a
candidate with no change here.
"""
from __future__ import annotations

import math
import multiprocessing
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass

import numpy as np

from ..experiments import experiment_of
from ..model.effects import EFFECTS
from ..model.values import rig_values
from ..records.signals import disagreement_window, dominant_frequency, lag1_autocorrelation, noise_estimate
from . import fitting
from .fitting import Dataset, FitResult, make_parameters, staged_fit
from .progress import progress

#: BIC improvement (in units of chi^2) required to name an effect. Kass & Raftery (1995)
#: call a BIC difference above 10 "very strong" evidence.
BIC_MARGIN = 10.0


@dataclass
class Candidate:
    effect: str
    fit: FitResult
    delta_bic: float  # BIC(baseline) - BIC(with effect): positive is better

    def summary(self):
        r = self.fit
        return {"effect": self.effect, "delta_bic": round(self.delta_bic, 2), "bic": round(r.bic, 2),
                "aic": round(r.aic, 2), "rms": r.rms, "reduced_chi2": round(r.reduced_chi2, 4),
                "lag1_autocorrelation": round(lag1_autocorrelation(r.residuals[0]), 4),
                "spring_model": r.spring_model_label, "parameters": _rounded(r.values)}


@dataclass
class Diagnosis:
    rig: object
    measurement: object
    noise: float
    baseline: FitResult
    candidates: list
    missing_effect: str | None
    final: FitResult
    window: tuple
    signature: dict
    evidence: str
    stopped: list = None  # candidates not fitted to the end: a simpler one explained the data already

    @property
    def unit(self):
        return experiment_of(self.rig.experiment).unit

    def to_json(self):
        b, f = self.baseline, self.final
        return {
            "missing_effect": self.missing_effect,
            "baseline_effects": list(b.effects), "final_effects": list(f.effects),
            "baseline_spring_model": b.spring_model_label, "final_spring_model": f.spring_model_label,
            "rms_before": b.rms, "rms_after": f.rms,
            "max_error_before": b.max_error, "max_error_after": f.max_error,
            "gap_ratio": f.rms / b.rms if b.rms > 0 else None,
            # the model-truth gap: residual rms in excess of the noise, sqrt(rms^2 - sigma^2)
            "excess_before": math.sqrt(max(b.rms**2 - self.noise**2, 0.0)),
            "excess_after": math.sqrt(max(f.rms**2 - self.noise**2, 0.0)),
            "noise_estimate": self.noise, "window": list(self.window),
            "bic_margin": BIC_MARGIN,
            "candidates": [c.summary() for c in self.candidates] + [
                {"effect": name, "delta_bic": None, "status": "stopped: a candidate with no more parameters "
                 "already explains the data within the noise"} for name in self.stopped or []],
            "fitted": _rounded(f.values), "fitted_before": _rounded(b.values),
            "stderr": {p.name: p.stderr for p in f.parameters.values() if p.vary},
            "at_bound": [p.name for p in f.parameters.values() if p.at_bound()],
            "signature": self.signature, "evidence": self.evidence,
        }

    def report(self):
        lines = [f"Diagnosis of {self.measurement.path}",
                 f"  noise estimate {self.noise:.3g} {self.unit}; baseline {', '.join(self.baseline.effects) or '(none)'}"
                 f" [{self.baseline.spring_model}]: rms {self.baseline.rms:.3g} {self.unit}",
                 f"  disagreement largest in t = [{self.window[0]:.4g}, {self.window[1]:.4g}] s",
                 "  candidates (delta BIC, positive = better):"]
        for c in self.candidates:
            lines.append(f"    {c.effect:18s} dBIC {c.delta_bic:12.1f}  rms {c.fit.rms:.3g} {self.unit} [{c.fit.spring_model_label}]")
        for name in self.stopped or []:
            lines.append(f"    {name:18s} stopped: a simpler candidate explains the data within the noise")
        lines.append(f"  missing effect: {self.missing_effect}")
        lines.append(f"  rms {self.baseline.rms:.3g} -> {self.final.rms:.3g} {self.unit}")
        lines.append("  " + self.evidence)
        lines.append(self.final.report())
        return "\n".join(lines)


def _rounded(values):
    return {k: float(f"{v:.6g}") for k, v in values.items()}


def _fit_job(args):
    rig, measurement, effects, spring_model, initial, starts, sigma, label, scan = args
    params = make_parameters(rig, effects, initial=initial)
    try:
        return staged_fit([Dataset(rig, measurement)], effects, spring_model, params, starts=starts, sigma=sigma,
                          label=label, scan=scan)
    except fitting.FitAborted:
        return None


def _init_worker(stop):
    fitting.STOP = stop


def _candidate_jobs(rig, measurement, baseline, guesses, sigma):
    """(effect name, fit-job arguments, number of parameters the effect adds to the fit)."""
    given = rig_values(rig)
    jobs = []
    for name, effect in EFFECTS.items():
        if name in baseline.effects or rig.experiment not in effect.experiments:
            continue
        effects = tuple(e for e in EFFECTS if e in baseline.effects or e == name)
        initial = dict(guesses[0])
        initial.update(baseline.values)
        new = [p for p in effect.parameters if p.vary and p.name not in given]
        scan = {p.name: p.scan for p in new if p.scan}
        for variant in effect.variants or (baseline.spring_model,):
            label = f"+{name}" + (f" [{variant.label}]" if variant != baseline.spring_model else "")
            jobs.append((name, (rig, measurement, effects, variant, initial, guesses, sigma, label, scan), len(new)))
    return jobs


def _run_jobs(jobs, processes):
    """Fit the candidates, simplest (fewest new parameters) first. Once a candidate explains
    the data within the noise, running and pending candidates with at least as many new
    parameters are stopped: they could not beat it by the BIC margin (Occam). Stopped
    candidates come back as None."""
    order = sorted(range(len(jobs)), key=lambda i: jobs[i][2])
    results = [None] * len(jobs)
    winners = []  # parameter counts of candidates at the noise level

    def pruned(i):
        return any(jobs[i][2] >= k for k in winners)

    def record(i, result):
        results[i] = result
        if result is not None and result.at_noise_level:
            winners.append(jobs[i][2])

    if processes <= 1 or len(jobs) <= 1:
        for i in order:
            if not pruned(i):
                record(i, _fit_job(jobs[i][1]))
        return results
    ctx = multiprocessing.get_context("fork")
    stop = ctx.Event()
    with ProcessPoolExecutor(max_workers=processes, mp_context=ctx, initializer=_init_worker,
                             initargs=(stop,)) as pool:
        pending = list(order)
        running = {}
        while pending or running:
            while pending and len(running) < processes:
                i = pending.pop(0)
                if not pruned(i):
                    running[pool.submit(_fit_job, jobs[i][1])] = i
            if not running:
                break
            done, _ = wait(running, return_when=FIRST_COMPLETED)
            for fut in done:
                record(running.pop(fut), fut.result())
            if running and winners and all(pruned(j) for j in running.values()):
                stop.set()  # every running fit is beaten already
    return results


def diagnose(rig, measurement, processes=2, verbose=True) -> Diagnosis:
    """Run the workflow of the module docstring on one measurement."""
    dataset = Dataset(rig, measurement)
    sigma = noise_estimate(dataset.y)
    record = experiment_of(rig.experiment)
    guesses = record.start_guesses(rig, measurement)
    if verbose:
        progress(f"diagnose: noise estimate {sigma:.3g} {record.unit}; fitting the starting model "
                 f"({', '.join(rig.model.effects) or 'no effects'}, {rig.model.spring_model.label})")
    baseline = _fit_job((rig, measurement, rig.model.effects, rig.model.spring_model, guesses[0], guesses[1:],
                         sigma, "starting model", None))
    t0, t1, _ = disagreement_window(measurement.t, baseline.residuals[0], sigma)
    jobs = _candidate_jobs(rig, measurement, baseline, guesses, sigma)
    if verbose:
        progress(f"diagnose: starting model rms {baseline.rms:.3g} {record.unit} ({baseline.rms / sigma:.2f}x noise); "
                 f"trying {len(jobs)} candidate model(s)")
    fits = _run_jobs(jobs, processes)
    best_by_effect, stopped = {}, set()
    for (name, _, _), f in zip(jobs, fits):
        if f is None:
            stopped.add(name)
        elif name not in best_by_effect or f.bic < best_by_effect[name].bic:
            best_by_effect[name] = f
    stopped -= set(best_by_effect)
    candidates = sorted((Candidate(n, f, baseline.bic - f.bic) for n, f in best_by_effect.items()),
                        key=lambda c: -c.delta_bic)
    chosen = candidates[0] if candidates and candidates[0].delta_bic > BIC_MARGIN else None
    final = chosen.fit if chosen else baseline
    signature = describe_signature(rig, measurement, baseline, sigma)
    evidence = _evidence(baseline, final, chosen, sigma, (t0, t1), signature)
    if verbose:
        progress(f"diagnose: missing effect {chosen.effect if chosen else None}; rms {baseline.rms:.3g} -> "
                 f"{final.rms:.3g} {record.unit}")
    return Diagnosis(rig, measurement, sigma, baseline, candidates, chosen.effect if chosen else None, final,
                     (t0, t1), signature, evidence, sorted(stopped))


def describe_signature(rig, measurement, baseline, sigma):
    """Features of the residual (and, by the experiment's record, of the measurement) that
    point at an effect."""
    t = measurement.t
    r = baseline.residuals[0]
    half = t.size // 2
    sig = {"residual_rms_over_noise": baseline.rms / sigma,
           "residual_growth": float(np.sqrt(np.mean(r[half:] ** 2)) / max(np.sqrt(np.mean(r[:half] ** 2)), 1e-300)),
           "residual_dominant_frequency_hz": dominant_frequency(t, r),
           "lag1_autocorrelation": lag1_autocorrelation(r)}
    sig.update(experiment_of(rig.experiment).signature(rig, measurement, baseline.simulations[0].measured, r, sigma))
    return sig


def _evidence(baseline, final, chosen, sigma, window, signature):
    unit = baseline.unit
    text = (f"The starting model leaves an rms residual of {baseline.rms:.3g} {unit}, "
            f"{baseline.rms / sigma:.2f}x the noise estimate {sigma:.3g} {unit}, largest in "
            f"t = [{window[0]:.4g}, {window[1]:.4g}] s (lag-1 autocorrelation {signature['lag1_autocorrelation']:.2f}).")
    if "amplitude_decay" in signature and signature["amplitude_decay"].get("shape") != "unknown":
        d = signature["amplitude_decay"]
        text += (f" The measured swing amplitude decays {d['shape']}ly over {d['peaks']} peaks and stops at "
                 f"{signature['measured_stop_time_s']:.2f} s (model: {signature['model_stop_time_s']:.2f} s).")
    if "spring_surge_frequency_hz" in signature:
        text += (f" Residual grows {signature['residual_growth']:.1f}x from the first to the second half; "
                 f"its dominant frequency is {signature['residual_dominant_frequency_hz']:.0f} Hz "
                 f"(spring surge {signature['spring_surge_frequency_hz']:.0f} Hz).")
    if chosen is None:
        text += f" No candidate lowers BIC by more than {BIC_MARGIN:g}: nothing is missing."
    else:
        text += (f" Adding {chosen.effect} lowers BIC by {chosen.delta_bic:.0f} and leaves "
                 f"{final.rms:.3g} {unit} ({final.rms / sigma:.2f}x noise, lag-1 autocorrelation "
                 f"{lag1_autocorrelation(final.residuals[0]):.2f}): the gap shrinks {baseline.rms / final.rms:.1f}x.")
    return text

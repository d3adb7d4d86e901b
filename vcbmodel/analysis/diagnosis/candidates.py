"""The candidates of forward selection and how one is fitted: every registered effect the model
lacks (or a pair of them), fitted from the record's own starting values; the spring's mass as a
choice among spring models. Residuals in the record's unit."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ...errors import SimulationError
from ...model.effects import EFFECTS
from ...model.values import rig_values
from .. import fit as fitting
from ..fit import FitResult
from .fits import fit_record, parameters
from .scores import consistent

#: Values at which a parameter's effect vanishes (the candidate then equals the model it was
#: added to): a candidate fit is never returned worse than that nested point.
NULL_VALUES = {"mu_k": 0.0, "mu_s": 0.0, "viscous": 0.0, "restitution": 1.0, "bellows_force": 0.0,
               "drag": 0.0, "damping_ratio": 0.0, "stribeck_velocity": None}  # None: any value (no effect once mu_s is null)


def candidate_jobs(rig: object, measurement: object, baseline: object, guesses: list, sigma: float) -> list:
    """(effect name, (effects, spring variants, new-parameter scan), number of parameters the
    effect adds to the fit) for every registered effect the model lacks."""
    given = rig_values(rig)
    jobs = []
    for name, effect in EFFECTS.items():
        if name in baseline.effects or rig.experiment not in effect.experiments:
            continue
        effects = tuple(e for e in EFFECTS if e in baseline.effects or e == name)
        new = [p for p in effect.parameters if p.vary and p.name not in given]
        scan = {p.name: p.scan for p in new if p.scan}
        variants = tuple(effect.variants) if effect.variants and baseline.spring_model.is_massless else ()
        jobs.append((name, (effects, variants, scan), len(new)))
    return jobs


def pair_jobs(rig: object, current: FitResult, singles: list) -> list:
    """Two effects at once, for when no single one earns the evidence (each alone may fit worse
    than neither: Stribeck friction without the viscous term it shares the decay with), or one
    passes for noise only as strongly correlated noise. A pair with the spring's mass searches
    the same spring variants as the single candidate did."""
    names = [name for name, _, _ in singles]
    spring_variants = {name: variants for name, (_, variants, _), _ in singles}
    given = rig_values(rig)
    jobs = []
    for a_i in range(len(names)):
        for b_i in range(a_i + 1, len(names)):
            pair = (names[a_i], names[b_i])
            effects = tuple(e for e in EFFECTS if e in current.effects or e in pair)
            new = [p for e in pair for p in EFFECTS[e].parameters if p.vary and p.name not in given]
            scan = {p.name: p.scan for p in new if p.scan}
            if len(scan) > 2:  # keep the grid small: the two most influential
                scan = dict(list(scan.items())[:2])
            variants = spring_variants[pair[0]] or spring_variants[pair[1]]
            jobs.append(("+".join(pair), (effects, variants, scan), len(new) + (1 if variants else 0)))
    return jobs


def nested(ctx, current: FitResult, effects: tuple, fit: FitResult | None) -> FitResult | None:
    """``fit``, or the current model with the new effects at their null values when that is
    better (a fit of a non-smooth cost can end worse than the model it extends)."""
    if fit is not None and fit.chi2 <= current.chi2:
        return fit
    params = dict(fit.parameters) if fit is not None else parameters(ctx, effects, current.values)
    new = {k: p for k, p in params.items() if k not in current.parameters}
    if any(p.vary and k not in NULL_VALUES for k, p in new.items()):
        return fit
    out = replace(current, effects=tuple(effects), parameters={**{k: replace(p) for k, p in current.parameters.items()},
                                                               **{k: replace(p, value=p.value if NULL_VALUES.get(k) is None
                                                                             else NULL_VALUES[k], stderr=None)
                                                                  for k, p in new.items()}})
    out.label = "nested (new effect at its null value)"
    return out


def fit_candidate(ctx, current: FitResult, name: str, effects: tuple, variants: tuple, scan: dict,
                  should_stop=None) -> tuple:
    """The best fit of ``current`` + effect(s) ``name``; for spring_mass the best spring variant.
    The nuisance starts afresh from the record (the current fit's may have bent to mimic the
    missing effect); the current fit's values are a second start. ``should_stop`` cancels it
    (FitAborted). Returns (FitResult, variants summary or None)."""
    initial = dict(ctx.guesses[0])
    initial.update(current.model_values)
    previous = dict(current.model_values)
    if variants:
        return fit_spring_variants(ctx, current, effects, variants, previous, initial, should_stop)
    params = parameters(ctx, effects, previous, initial)
    fit = fit_record(ctx, effects, current.spring_model, params, f"+{name}", scan=scan, should_stop=should_stop,
                     new=tuple(k for k in params if k not in current.parameters))
    return nested(ctx, current, effects, fit), None


def screen_spring_models(ctx, effects: tuple, variants: list, params: dict, values: dict) -> list:
    """chi^2 of each spring model at ``values`` (one simulation each, all at once on the pool; the
    alignment refitted without simulating); inf where the simulation failed."""
    objs = [fitting.Objective([ctx.dataset], effects, v, params, ctx.pool, ctx.scales()) for v in variants]
    costs = []
    for o, res in zip(objs, ctx.pool.run([o.simulation_job(values, 0) for o in objs])):
        if isinstance(res, Exception):
            costs.append(math.inf)
            continue
        cur = fitting.Curves(res)
        r = np.concatenate(o.residual_parts(o.align(values, [cur]), [cur]))
        costs.append(float(np.dot(r, r)))
    return costs


def _refine_runners(ctx, effects, best, runners, fits, should_stop) -> None:
    """Each runner-up spring model refined from ``best``'s values with its Jacobian."""
    hint = fitting.jacobian_of(best)
    for v in runners:
        p2 = {k: replace(p, stderr=None) for k, p in best.parameters.items()}
        try:
            fits[v.label] = fitting.refine([ctx.dataset], effects, v, p2, hint, pool=ctx.pool, scales=ctx.scales(),
                                           sigma=ctx.sigma_hf, should_stop=should_stop or ctx.stop.is_set,
                                           label=f"+spring_mass [{v.label}]")
        except SimulationError:
            continue


def fit_spring_variants(ctx, current: FitResult, effects: tuple, variants: tuple, previous: dict,
                        initial: dict, should_stop=None) -> tuple:
    """Adding the spring's mass is a discrete choice among mass models. Every model is first
    simulated at the current values (one simulation each, all at once on the pool; alignment
    refitted without simulating); the best is fitted. If it leaves more than the noise, the two
    runners-up and the ANCF continuum are refined from its values with its Jacobian (one
    simulation per step: the ANCF spring costs five to ten lumped ones)."""
    params = parameters(ctx, effects, previous, initial)
    costs = screen_spring_models(ctx, effects, variants, params, {p.name: p.value for p in params.values()})
    order = sorted(range(len(variants)), key=lambda i: costs[i])
    first = variants[order[0]]
    fits = {first.label: fit_record(ctx, effects, first, parameters(ctx, effects, previous, initial),
                                    f"+spring_mass [{first.label}]", starts=[dict(current.values)],
                                    should_stop=should_stop)}
    best = fits[first.label]
    if not consistent(ctx, best):
        runners = [variants[i] for i in order[1:3] if math.isfinite(costs[i])]
        runners += [v for v in variants if v.kind == "ancf" and v not in runners and v is not first]
        _refine_runners(ctx, effects, best, runners, fits, should_stop)
    chosen = min(fits.values(), key=lambda f: f.chi2)
    lumped = [f for f in fits.values() if f.spring_model.kind == "lumped"]
    if chosen.spring_model.kind != "lumped" and lumped:
        # a cheap stand-in for fitting further effects on top of this spring (refined at the end)
        chosen.stand_in = min(lumped, key=lambda f: f.chi2)
    n = max(1, int(ctx.dataset.mask().sum()))
    summary = [{"spring_model": v.label, "rms_at_current_values": math.sqrt(c / n) * ctx.sigma_hf
                if math.isfinite(c) else None, "rms_fitted": fits[v.label].rms if v.label in fits else None}
               for v, c in zip(variants, costs)]
    return chosen, summary

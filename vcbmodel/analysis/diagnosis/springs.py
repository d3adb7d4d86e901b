"""Refinements of the selected model's spring (part of step 4, refine): the continuum the spring's
mass was chosen with, and a finer lumped chain when the model's residual stands above the noise.
Both start from the current fit with its Jacobian (one simulation per step)."""
from __future__ import annotations

import math
from dataclasses import replace

from ...errors import SimulationError
from ...model.effects import EFFECTS
from .. import fit as fitting
from ..fit import FitAborted
from ..noise import fit_noise
from .at_noise import at_noise
from .candidates import screen_spring_models
from .state import adopt


def _refined(ctx, current, spring, label):
    """``current`` refined with ``spring`` from its values and Jacobian; None if it failed."""
    p2 = {k: replace(p, stderr=None) for k, p in current.parameters.items()}
    try:
        return fitting.refine([ctx.dataset], current.effects, spring, p2, fitting.jacobian_of(current),
                              pool=ctx.pool, scales=ctx.scales(), sigma=ctx.sigma_hf, should_stop=ctx.stop.is_set,
                              label=label)
    except (FitAborted, SimulationError):
        return None


def final_spring(ctx, state) -> None:
    """The continuum back in: the selected effects were searched with a lumped chain standing in
    for the spring model chosen for the spring's mass (ANCF, five to ten times dearer); the final
    model is refined with it from the stand-in's values, and kept if it fits better."""
    current = state.current
    if ctx.search.spring_final is None or "spring_mass" not in current.effects or ctx.stop.is_set():
        return
    ctx.say(f"refining the final model with the {ctx.search.spring_final.label} spring")
    fine = _refined(ctx, current, ctx.search.spring_final, f"final [{ctx.search.spring_final.label}]")
    if fine is None:
        return
    state.all_fits.append(fine)
    if fine.chi2 >= current.chi2:
        return
    adopt(state.path, current, fine)
    state.current = fine


def _best_other_chain(ctx, current):
    """The lumped spring chain (other than the current one) that fits best at the current values
    (one simulation each, alignment refitted), or None."""
    variants = [v for v in EFFECTS["spring_mass"].variants if v.kind == "lumped" and v != current.spring_model]
    if not variants:
        return None
    costs = screen_spring_models(ctx, current.effects, variants, current.parameters, dict(current.values))
    best_i = min(range(len(variants)), key=lambda i: costs[i])
    return variants[best_i] if math.isfinite(costs[best_i]) else None


def finer_spring(ctx, state) -> None:
    """A model with the spring's mass whose residual stands above the noise may have too coarse a
    spring model rather than a missing effect (the rig's lumped-2 against a continuum): the best
    other lumped chain at the current values is refined, and kept if it lowers the whitened BIC by
    more than ``bic_margin`` (``state.coarse_spring`` keeps the fit it replaced). The ANCF continuum
    is not tried here (a closing with it costs 8 s)."""
    current = state.current
    if ctx.over() or at_noise(ctx, current):
        return
    if "spring_mass" not in current.effects or current.spring_model.is_massless:
        return
    chain = _best_other_chain(ctx, current)
    if chain is None:
        return
    ctx.say(f"the final model leaves more than the noise: refining it with the {chain.label} spring "
            f"(the best other spring model at its values)")
    finer = _refined(ctx, current, chain, f"final [{chain.label}]")
    if finer is None:
        return
    ctx.search.fits += 1
    state.all_fits.append(finer)
    noise = fit_noise(finer.residuals, ctx.sigma_hf, ctx.quantisation)
    gain = current.bic_with(noise) - finer.bic_with(noise)
    if gain <= ctx.options.bic_margin:
        return
    ctx.say(f"spring model {current.spring_model_label} -> {finer.spring_model_label}: rms {current.rms:.3g} -> "
            f"{finer.rms:.3g} {ctx.record.unit} (delta BIC {gain:.0f})")
    adopt(state.path, current, finer)
    state.current, state.coarse_spring = finer, current

"""Step 4, refine the selection: forward selection keeps one effect at a time and can end in a
model an early choice bent, or on a local minimum. Each refinement below is tried in order,
each only when its one-line reason holds; each keeps its change only if the evidence earns it.

- :func:`backward_elimination`: an effect kept early may be superseded by later ones.
- :func:`swap_effects`: a kept effect may stand in for one never tried on top of the others.
- :func:`.springs.final_spring`: the continuum the spring's mass was chosen with, back in.
- :func:`.springs.finer_spring`: the spring model may be too coarse, not an effect missing.
- :func:`search_harder`: a free swing's cost has local minima a half-swing apart.
"""
from __future__ import annotations

from ...errors import SimulationError
from ...model.effects import EFFECTS
from .. import fit as fitting
from ..fit import FitAborted
from .at_noise import at_noise
from .fits import parameters, refit
from .scores import earns_margin, noise_of_best
from .springs import final_spring, finer_spring
from .state import Refinement, SelectionStep, adopt


def _without(ctx, state, step: SelectionStep) -> bool:
    """Refit the current model without ``step``'s effect; drop it if it no longer earns the
    margin. True when dropped."""
    current = state.current
    effect = step.effect
    effects = tuple(e for e in current.effects if e != effect)
    spring = ctx.rig.model.spring_model if effect == "spring_mass" else current.spring_model
    ctx.say(f"backward: refitting without {effect}")
    try:
        reduced = refit(ctx, effects, spring, dict(current.values), f"-{effect}")
    except (FitAborted, SimulationError):
        return False
    state.all_fits.append(reduced)
    noise = noise_of_best(ctx, state.all_fits)
    evidence = reduced.bic_with(noise) - current.bic_with(noise)
    dropped = not earns_margin(ctx, reduced, current, evidence)
    state.backward.append(Refinement(effect, reduced, current, evidence, dropped))
    ctx.say(f"backward: without {effect} the whitened BIC rises by {evidence:.0f} (rms {reduced.rms:.3g}): "
            + ("dropped" if dropped else "kept"))
    if dropped:
        state.path.remove(step)
        state.current = reduced
        for other in state.path:  # the remaining steps lead to this model now
            other.fit = reduced
    return dropped


def backward_elimination(ctx, state) -> None:
    """An effect kept early may be superseded by later ones (viscous friction stands in for shaft
    friction and spring mass together until both are in): each kept effect is removed in turn
    and the model refitted; if the others explain the record as well, it is dropped. Only after
    two rounds or more (a pair found together has nothing to undo)."""
    if len({step.round for step in state.path}) < 2:
        return
    for step in list(state.path):
        if ctx.over():
            ctx.skipped.append(f"backward elimination of {step.effect}")
            continue
        _without(ctx, state, step)


def _swap_pairs(ctx, state):
    """(kept effect, replacement) pairs: kept effects with parameters, applicable effects not in
    the model (spring models, chosen among variants, are not swapped)."""
    current = state.current
    kept = [s.effect for s in state.path if EFFECTS[s.effect].parameters and not EFFECTS[s.effect].variants]
    others = [name for name, e in EFFECTS.items() if name not in current.effects
              and e.applies_to(ctx.rig.provides, current.spring_model) and e.parameters and not e.variants]
    return [(old, new) for old in kept for new in others]


def _try_swap(ctx, state, old, new) -> Refinement | None:
    """The current model with ``old`` replaced by ``new``, refitted: its record (appended to
    ``state.backward``: ``delta_bic`` the whitened BIC gain, ``with_`` the fit) or None."""
    current = state.current
    effects = tuple(e for e in EFFECTS if (e in current.effects and e != old) or e == new)
    ctx.say(f"swap: {old} -> {new}")
    try:
        f = refit(ctx, effects, current.spring_model, dict(current.values), f"{old}->{new}")
    except (FitAborted, SimulationError):
        return None
    state.all_fits.append(f)
    noise = noise_of_best(ctx, state.all_fits)
    gain = current.bic_with(noise) - f.bic_with(noise)
    record = Refinement(old, current, f, gain, swap_for=new)
    state.backward.append(record)
    return record


def swap_effects(ctx, state) -> None:
    """When the selected model still leaves more than the noise, an effect kept early may stand
    in for another (in a cam drop, viscous friction mimics shaft friction plus the spring's
    mass): each kept effect with parameters is replaced in turn by each applicable effect not in
    the model; the best replacement is taken if it earns the margin."""
    if not state.path or ctx.over() or at_noise(ctx, state.current):
        return
    best = None
    for old, new in _swap_pairs(ctx, state):
        if ctx.over():
            ctx.skipped.append(f"swap {old} -> {new}")
            continue
        tried = _try_swap(ctx, state, old, new)
        if tried is not None and tried.delta_bic > ctx.options.bic_margin and (best is None or
                                                                              tried.delta_bic > best.delta_bic):
            best = tried
    if best is None:
        return
    old, new, f = best.effect, best.swap_for, best.with_
    ctx.say(f"swap: {old} replaced by {new} (whitened BIC lower by {best.delta_bic:.0f})")
    for step in state.path:
        if step.effect == old:
            step.effect, step.swapped_from = new, old
        step.fit = f
    best.dropped = True  # the swap taken (``old`` left the model)
    state.current = f


def _scan_of(ctx, state, params):
    """At most two friction parameters to grid, the kept effects' first."""
    current = state.current
    kept = [s.effect for s in state.path]
    order = [e for e in kept if e in current.effects] + [e for e in current.effects if e not in kept]
    scan = {}
    for e in order:
        for spec in EFFECTS[e].parameters:
            if spec.scan and spec.name in params and params[spec.name].vary and len(scan) < 2:
                scan[spec.name] = spec.scan
    return scan


def _wider_fit(ctx, current, params, scan):
    """The final model refitted from the ``wider_starts`` best grid points, the nuisance from the
    final fit's (a start's own re-alignment moves the release and the offset into its basin)."""
    wider = ctx.options.wider_starts
    starts = fitting.scan_starts([ctx.dataset], current.effects, current.spring_model, params, scan, keep=wider,
                                 pool=ctx.pool, scales=ctx.scales(), step=fitting.scan_step(ctx.rig))
    starts = [{k: v for k, v in start.items() if k in scan} for start in starts]
    return fitting.fit([ctx.dataset], current.effects, current.spring_model, params, starts=starts,
                       sigma=ctx.sigma_hf, verbose=False, pool=ctx.pool, processes=1, scales=ctx.scales(),
                       should_stop=ctx.stop.is_set, max_starts=wider, enough=lambda f: at_noise(ctx, f))


def search_harder(ctx, state) -> None:
    """Before the verdict "not explained", for a free swing only: its cost has local minima where
    a stop comes a half-swing earlier or later, and the staged fit can end in one when the
    nuisance's first estimate is off (a pendulum with viscous friction was left at 3.4x the noise
    with the right effects, and from the grid reached the noise). The final model is refitted
    from a grid of its friction values (:func:`_scan_of`), kept if it fits better. A cam drop's
    or a closing's cost has no such stop, and there a grid costs as much as the search so far."""
    current = state.current
    if ctx.over() or at_noise(ctx, current) or not ctx.record.period_fields:
        return
    params = parameters(ctx, current.effects, current.values)  # the nuisance from the final fit, too
    scan = _scan_of(ctx, state, params)
    if not scan:
        return
    ctx.say(f"the final model leaves more than the noise: refitting it from a grid of {', '.join(scan)}")
    try:
        wider = _wider_fit(ctx, current, params, scan)
    except (FitAborted, SimulationError):
        return
    ctx.search.fits += 1
    wider.label = "final model (wider search)"
    state.all_fits.append(wider)
    if wider.chi2 >= current.chi2:
        return
    ctx.say(f"wider search: rms {current.rms:.3g} -> {wider.rms:.3g} {ctx.record.unit}")
    adopt(state.path, current, wider)
    state.current = wider


#: The refinements, in the order they are tried.
REFINEMENTS = (backward_elimination, swap_effects, final_spring, finer_spring, search_harder)


def refine_selection(ctx, state) -> None:
    """Step 4: each of :data:`REFINEMENTS` in turn (see the module docstring)."""
    for refinement in REFINEMENTS:
        refinement(ctx, state)


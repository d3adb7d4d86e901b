"""Values the rig pins, and what their plausible error would do to the fitted parameters (used by
the report step). The sensor's gain is fitted only when the rig marks ``record.sensor_gain``
uncertain; otherwise the stated errors are conditional on it being exact, and a gain error the
residual does not show (the friction absorbs it) moves the friction values by many stated errors
(the realism study's gain group: mu_k 5 errors off at a residual at the noise).

The shift a gain error ``dg`` causes is measured by refits: the final model refitted with the gain
pinned at ``g - dg`` and at ``g + dg`` (every other value and the nuisance free, from the final fit's
values), half their difference: how far the pinned fit's values lie from those of a gain truly ``dg``
higher. A
linearised shift (the least-squares projection of the gain's column onto the fit's Jacobian) is not
used: a free swing's cost has kinks where a stop comes a step earlier or later, its
difference Jacobian carries them, and on the realism study's gain record it put half the shift in
mu_k and the rest in viscous friction where the refits move mu_k by the whole 1 % and viscous by
0.2 of its stated error (the truth's own split)."""
from __future__ import annotations

import math
from dataclasses import replace

from ... import parameters as P
from ...errors import SimulationError
from .. import fit as fitting
from ..fit import FitAborted
from ..fit.dataset import gain_name
from ..model_forms import CHI2_TOLERANCE, MAX_ITERATIONS
from .fits import parameters


def _refit_at_gain(ctx, fit, gain: float):
    """``fit``'s model refitted with the record's gain pinned at ``gain`` (the rest free, from ``fit``'s
    values, at the model forms' tolerance: it starts next to its optimum); None when the fit fails."""
    params = parameters(ctx, tuple(fit.effects), fit.values)
    gname = gain_name(0, ctx.record.measured_channel)
    params[gname] = replace(params[gname], value=gain, vary=False, prior=None)
    try:
        return fitting.fit([ctx.dataset], fit.effects, fit.spring_model, params, sigma=ctx.sigma_hf, pool=ctx.pool,
                           processes=1, scales=ctx.scales(), verbose=False, label="the pinned gain shifted",
                           should_stop=ctx.stop.is_set, chi2_tolerance=CHI2_TOLERANCE, relative_tolerance=0.0,
                           max_iterations=MAX_ITERATIONS)
    except (FitAborted, SimulationError, ValueError):
        return None


def refitted_shifts(ctx, fit, error: float) -> dict | None:
    """{model parameter: shift in its unit}: how far ``fit``'s varied model values lie from where they
    would be if the record's gain were truly ``error`` higher than pinned, by the central difference of
    two refits with the gain pinned ``error`` lower and higher (half their difference: a refit also slides
    along the cost's flat valleys for reasons of its own, which a one-sided difference from ``fit`` would
    count as the gain's; on the gain record 15001 viscous friction moved the same way at either gain);
    None when either refit fails."""
    g = fit.parameters[gain_name(0, ctx.record.measured_channel)].value
    low, high = _refit_at_gain(ctx, fit, g - error), _refit_at_gain(ctx, fit, g + error)
    if low is None or high is None:
        return None
    return {name: float(0.5 * (low.parameters[name].value - high.parameters[name].value))
            for name, p in fit.parameters.items()
            if p.kind == "model" and p.vary and name in low.parameters and name in high.parameters}


def pinned_gain(ctx, fit) -> dict | None:
    """The sensor gain the rig does not let the fit estimate (not marked uncertain): the shift of
    each fitted model parameter a plausible gain error (parameters.PINNED_GAIN_ERROR) causes, by
    refits (module docstring), in stated errors, and whether any goes beyond the stated 95 % interval
    (the options' ``beyond_stated``). Reason: the stated errors are conditional on the pinned gain,
    and the residual cannot show its error. When the refits fail (the time budget, a solver failure)
    the item says the shift was not measured."""
    main = ctx.record.measured_channel
    p = fit.parameters.get(gain_name(0, main))
    if p is None or p.vary:
        return None
    error = P.PINNED_GAIN_ERROR * p.value
    item = {"field": "record.sensor_gain", "value": p.value, "plausible_error": error, "shifts": {},
            "how": "central difference of two refits with the gain pinned that much lower and higher",
            "beyond_stated": False, "worst": None}
    shifts = refitted_shifts(ctx, fit, error)
    if shifts is None:
        item["how"] = "not measured: the refits with the gain shifted failed or were stopped by the time budget"
        return item
    for name, s in shifts.items():
        se = fit.parameters[name].stderr
        if se:
            item["shifts"][name] = {"shift": s, "stated_errors": abs(s) / se,
                                    "stderr_with_pinned": float(math.hypot(se, s))}
    worst = max(item["shifts"].items(), key=lambda kv: kv[1]["stated_errors"], default=None)
    item["beyond_stated"] = bool(worst and worst[1]["stated_errors"] > ctx.options.beyond_stated)
    item["worst"] = worst[0] if worst else None
    return item


def pinned_caveat(item: dict) -> str | None:
    """The report's sentence when a pinned value's plausible error goes beyond the stated errors."""
    if not item or not item["beyond_stated"]:
        return None
    w = item["worst"]
    row = item["shifts"][w]
    return (f"The stated errors assume {item['field']} = {item['value']:.4g} exactly: a "
            f"{100 * item['plausible_error'] / abs(item['value']):.2g} % error of it, which the residual would not "
            f"show, moves {w} by about {abs(row['shift']):.2g} ({row['stated_errors']:.1f} stated errors); mark it uncertain "
            f"in the rig (\"uncertain\": {{\"{item['field']}\": 0.01}}) to have it fitted and its error counted.")

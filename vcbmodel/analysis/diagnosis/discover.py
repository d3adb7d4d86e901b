"""Step 6, discover: when the best registered model leaves a structured residual (the judge's
verdict is "not explained"), look for the missing torque outside the registry
(:mod:`vcbmodel.analysis.discovery`: the missing torque from the aligned record and the model,
sparse regression over a library of candidate terms, the model refitted with what it finds). A
discovery must earn the evidence a registered effect earns here (the options' ``bic_margin`` and
:func:`.scores.min_gain`). It changes no fit and no verdict of the registered search: it is
reported beside them (``discovered`` in the JSON), each term as *discovered, not registered*."""
from __future__ import annotations

from ...errors import SimulationError
from ..discovery import covers, discovery_step
from ..fit import FitAborted
from .scores import min_gain


def skipped(reason: str) -> dict:
    """What the step reports when it does not search."""
    return {"attempted": False, "reason": reason}


def discover(ctx, state) -> None:
    """Sets ``state.discovery`` (the discovery's JSON, or why none was attempted) and
    ``state.discovered`` (the :class:`~vcbmodel.analysis.discovery.Discovery`); changes no fit."""
    if state.verdict is not None and state.verdict.explained:
        state.discovery = skipped("the registered model explains the record")
        return
    if not ctx.options.discovery:
        state.discovery = skipped("switched off (options.discovery)")
        return
    if not covers(ctx.rig.experiment):
        state.discovery = skipped(f"discovery does not search {ctx.rig.experiment} records")
        return
    if ctx.over(0.95):
        state.discovery = skipped("time budget")
        ctx.skipped.append("discovery (time budget)")
        return
    ctx.say("discover: looking for the missing torque outside the registry")
    try:
        found = discovery_step(ctx.rig, ctx.measurement, state.final, state.baseline, False,
                               dataset=ctx.dataset, sigma=ctx.sigma_hf, quantisation=ctx.quantisation,
                               pool=ctx.pool, bic_margin=ctx.options.bic_margin, min_gain=min_gain(ctx),
                               should_stop=ctx.stop.is_set)
    except (SimulationError, FitAborted, ValueError) as e:
        state.discovery = skipped(f"discovery failed: {str(e).splitlines()[0][:200]}")
        return
    state.discovered = found
    state.discovery = {"attempted": True, **found.to_json(), "report": found.report()}
    ctx.say("discover: " + found.message)

"""The diagnosis as a pipeline of named steps: where do model and record disagree, and what is
missing? Each step is a function ``(ctx, state)`` in its own module; :data:`STEPS` runs them in
order on one record (the README's description of the workflow lists the same steps):

1. align the record (:mod:`.align`)
2. fit the starting model (:mod:`.start`)
3. select effects (:mod:`.select`)
4. refine the selection (:mod:`.refine`)
5. judge the residual (:mod:`.judge`)
6. discover (:mod:`.discover`)
7. report (:mod:`.report`)

``ctx`` (:class:`.context.Context`) is what the steps share (the aligned record, the pool, the
noise model, the time budget); ``state`` (:class:`.state.State`) is what they hand on.
"""
from __future__ import annotations

import time
from typing import Callable, NamedTuple

from threadpoolctl import threadpool_limits

from ...experiments.base import check_samples
from ..fit import SimulationPool
from ..thinning import usual_rate
from .align import align
from .context import Budget, Context
from .discover import discover
from .judge import judge
from .options import DEFAULT_OPTIONS, DiagnosisOptions
from .refine import refine_selection
from .report import report
from .result import Diagnosis
from .select import select_effects
from .start import fit_start
from .state import State


class Step(NamedTuple):
    name: str
    run: Callable


#: The diagnosis' steps, in order.
STEPS = (Step("align the record", align), Step("fit the starting model", fit_start),
         Step("select effects", select_effects), Step("refine the selection", refine_selection),
         Step("judge the residual", judge), Step("discover", discover), Step("report", report))


#: Threads of the linear algebra library (BLAS) while a diagnosis runs. Its matrices are a fit's Jacobian
#: (record samples x a few parameters) and products of it, too small to share out: with the library's
#: default (one thread per core) its threads wait for work by spinning, on the cores the simulations
#: need. Measured on 2 cores: a 6000 x 8 Jacobian's SVD 0.3 ms of processor time on one thread, 2.3 ms on
#: two; a whole diagnosis (the benchmark's unregistered-effect record, 8150 simulations) gives the same
#: result to the bit with 0.87x the processor time and 0.88x the wall time (three runs each, interleaved, on
#: a shared machine).
LINEAR_ALGEBRA_THREADS = 1


def run_steps(ctx: Context, state: State, steps: tuple = STEPS) -> State:
    """Run ``steps`` in order on one record."""
    for step in steps:
        step.run(ctx, state)
    return state


def diagnose(rig: object, measurement: object, processes: int = 2, verbose: bool = True,
             time_budget: float | None = None, options: DiagnosisOptions = DEFAULT_OPTIONS,
             held_out: tuple = ()) -> Diagnosis:
    """Run the pipeline on one record with the thresholds of ``options`` (``time_budget``, s of
    the processes' time, overrides the options' own). ``held_out``: (rig, measurement) pairs of the
    same rig's other records, predicted with the values fitted here (:mod:`.held_out`): the
    verdict ``explained`` requires each at its noise."""
    for _, record in ((rig, measurement), *held_out):  # a record built in Python, not read: checked here
        check_samples(record.t, record.path)
    # a record far denser than its experiment's usual sensor is fitted at about that rate, as identify does
    rig, measurement = usual_rate((rig, measurement), "diagnose")
    held_out = tuple(usual_rate(pair, "diagnose") for pair in held_out)
    if time_budget is not None:
        options = options.with_(time_budget=time_budget)
    started = time.monotonic()
    with threadpool_limits(limits=LINEAR_ALGEBRA_THREADS, user_api="blas"), SimulationPool(processes) as pool:
        budget = Budget(pool, processes, options.time_budget, started, options.wall_factor)
        ctx = Context(rig, measurement, pool, budget, verbose, processes, options, held_out=tuple(held_out))
        with budget.watched():
            return run_steps(ctx, State()).diagnosis

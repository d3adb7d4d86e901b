"""What the steps of one diagnosis share: what is fixed for the run (:class:`Context`: the record
as aligned, the simulation pool, the time budget, the options, a progress voice), and the search's
state the steps update (:class:`Search`, ``ctx.search``: the current noise model, values the
diagnosis takes as uncertain, the record's time base, the number of fits). It holds no logic of
the search: :mod:`.align` fills the context once, the steps read it."""
from __future__ import annotations

import math
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field

from ..progress import progress
from .options import DEFAULT_OPTIONS, DiagnosisOptions


class Budget:
    """The time budget of one diagnosis (``time_budget`` s of :class:`.options.DiagnosisOptions`,
    on its processes: processor seconds of this process and the simulation workers divided by
    their number, so that a machine shared with other work does not cut the search short). Past
    80 % of it no new fit starts; at the budget the running fits stop and the diagnosis reports
    what it has (``timing.budget_reached``). ``wall_factor`` times the budget in wall time stops
    it in any case. Holds what is used, whether a new fit may start, and the event that stops the
    running ones."""

    def __init__(self, pool: object, processes: int, seconds: float = DEFAULT_OPTIONS.time_budget,
                 started: float | None = None, wall_factor: float = DEFAULT_OPTIONS.wall_factor):
        self.pool, self.processes, self.seconds, self.wall_factor = pool, processes, seconds, wall_factor
        self.started = time.monotonic() if started is None else started
        self.cpu0 = pool.cpu_seconds()
        self.stop = threading.Event()
        self.skipped = []  # fits not started for the time budget

    def used(self) -> float:
        """Time used against the budget: processor seconds per process."""
        return (self.pool.cpu_seconds() - self.cpu0) / max(1, self.processes)

    def over(self, fraction: float = 0.8) -> bool:
        """Past ``fraction`` of the time budget (no new fit should start)?"""
        return (self.stop.is_set() or self.used() > fraction * self.seconds
                or time.monotonic() - self.started > self.wall_factor * fraction * self.seconds)

    @contextmanager
    def watched(self) -> Iterator[Budget]:
        """While inside, a watcher sets ``stop`` once the whole budget is used."""
        done = threading.Event()

        def watch():
            while not done.wait(0.5):
                if self.over(1.0):
                    self.stop.set()
                    return

        threading.Thread(target=watch, daemon=True).start()
        try:
            yield self
        finally:
            done.set()


@dataclass
class Search:
    """The search's state the steps update: the current noise model (start, select, judge), rig
    values the diagnosis itself takes as uncertain (a period mismatch), the record's time base when
    it is fitted as a nuisance, the spring model the final model is refined with (the continuum a
    lumped chain stood in for), the number of fits, and caches (the held-out records' contexts,
    a held-out record's predictions by model)."""

    noise: object = None  # the current noise model (NoiseModel)
    implied: dict = field(default_factory=dict)  # uncertain values the diagnosis added itself
    time_scale: dict | None = None  # the record's time base as a nuisance: {"value", "sd", "source"}
    spring_final: object = None  # the spring model the final model is refined with (ANCF)
    fits: int = 0
    held_out_contexts: list | None = None  # the held-out records' contexts, aligned once (.held_out)
    predictions: dict = field(default_factory=dict)  # id(model) -> (model, its prediction of this record)


@dataclass
class Context:
    """What is fixed for one diagnosis: the rig, the record and how it is read, the pool, the time
    budget, the options and the held-out records. The record's fields (``record`` ..
    ``coarse_step``) are set once by :func:`.align.align` (see there for what each is) and only
    read afterwards; what the search changes as it goes is in ``search`` (:class:`Search`)."""

    rig: object
    measurement: object
    pool: object
    budget: Budget
    verbose: bool = True
    processes: int = 1
    options: DiagnosisOptions = DEFAULT_OPTIONS
    #: the rig's other records, (rig, measurement) pairs, predicted but not fitted (.held_out)
    held_out: tuple = ()
    record: object = None  # the experiment's record kind (vcbmodel.experiments)
    quantisation: float = 0.0
    sigma_hf: float = math.nan  # the measured channel's high-frequency noise (record's unit)
    setup: object = None  # the record's nuisance setup (nuisance.RecordSetup)
    channel_sigma: dict = field(default_factory=dict)
    dataset: object = None
    guesses: list = field(default_factory=list)
    #: a free swing's starts spread along the Coulomb-viscous valley (fits.valley_bases)
    valley: list = field(default_factory=list)
    uncertain: dict = field(default_factory=dict)
    coarse_step: float | None = None
    search: Search = field(default_factory=Search)

    @property
    def stop(self) -> threading.Event:
        return self.budget.stop

    @property
    def skipped(self) -> list:
        return self.budget.skipped

    def over(self, fraction: float = 0.8) -> bool:
        """Past ``fraction`` of the time budget?"""
        return self.budget.over(fraction)

    def scales(self) -> dict:
        """Weights of the residual channels: each channel's high-frequency noise level (the
        weights set only how priors weigh against the data and how channels weigh against each
        other; the evidence is scored with the whitened residual)."""
        return {(0, ch): s for ch, s in self.channel_sigma.items()}

    def say(self, message: str) -> None:
        if self.verbose:
            progress(f"diagnose: {message}")

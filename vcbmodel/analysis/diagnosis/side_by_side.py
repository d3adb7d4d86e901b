"""Candidates fitted side by side: threads share the simulation pool, simplest candidate first.
Occam's pruning: once a candidate's residual is consistent with the noise, pending candidates
with at least as many new parameters are not started (they could not beat it by the margin)."""
from __future__ import annotations

import time
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait

from ...errors import SimulationError
from ..fit import FitAborted
from .candidates import fit_candidate
from .scores import consistent


def pruned(size: int, winners: list) -> bool:
    """Occam: a candidate adding ``size`` parameters is not started once one adding no more
    (a size in ``winners``) has reached the noise."""
    return any(size >= k for k in winners)


class _Round:
    """Book-keeping of one round's candidate fits (results, progress messages)."""

    def __init__(self, ctx, jobs, round_no):
        self.ctx, self.jobs, self.round_no = ctx, jobs, round_no
        self.results, self.variants = [None] * len(jobs), [None] * len(jobs)
        self.winners = []
        self.threads = max(1, ctx.processes)
        self.t0 = time.monotonic()
        self.done = 0

    def collect(self, i, fut, pending, running) -> None:
        try:
            res, var = fut.result()
        except (FitAborted, SimulationError):
            res, var = None, None
        self.results[i], self.variants[i] = res, var
        self.done += 1
        if res is not None and consistent(self.ctx, res):
            self.winners.append(self.jobs[i][2])
        left = len([j for j in pending if not pruned(self.jobs[j][2], self.winners)]) + len(running)
        per = (time.monotonic() - self.t0) / self.done
        self.ctx.say(f"round {self.round_no}: {self.done}/{self.done + left} candidate fits done "
                     f"({self.jobs[i][0]}: rms {res.rms if res else float('nan'):.3g} {self.ctx.record.unit}); "
                     f"about {per * left / max(1, min(self.threads, left or 1)):.0f} s left in this round, "
                     f"{time.monotonic() - self.ctx.budget.started:.0f} s so far")


def run_candidates(ctx, current: object, jobs: list, round_no: int) -> tuple:
    """Fit the ``jobs`` (from :func:`.candidates.candidate_jobs`) on top of ``current``. Returns
    (fits, spring-variant summaries), None where a candidate was not fitted."""
    book = _Round(ctx, jobs, round_no)

    def run(i):
        name, (effects, var, scan), _ = jobs[i]
        return fit_candidate(ctx, current, name, effects, var, scan)

    pending = sorted(range(len(jobs)), key=lambda i: jobs[i][2])
    with ThreadPoolExecutor(max_workers=book.threads) as ex:
        running = {}
        while pending or running:
            while pending and len(running) < book.threads:
                i = pending.pop(0)
                if ctx.over():
                    ctx.skipped.append(jobs[i][0])
                    continue
                if not pruned(jobs[i][2], book.winners):
                    running[ex.submit(run, i)] = i
            if not running:
                break
            done, _ = wait(running, return_when=FIRST_COMPLETED)
            for fut in done:
                book.collect(running.pop(fut), fut, pending, running)
    return book.results, book.variants

"""Candidates fitted side by side: threads share the simulation pool, simplest candidate first.
Two rules spare work once a candidate's residual is at the noise (:mod:`.at_noise`; a "winner"):

- Occam's pruning (:func:`pruned`): pending candidates with more new parameters are not started
  (they could not beat it by the margin). One with as many is fitted: it may fit better and win, or
  tie, and the round's choice must not depend on which of two equal candidates finished first
  (under load a pending viscous friction was pruned by an air drag that happened to finish first).
- Cancelling (:func:`cannot_win`): running candidates with *more* new parameters are stopped.
  Each extra parameter costs ln(n) in BIC (8 for 3000 samples); against a model whose residual is
  already what the noise leaves, it can only gain what fitting the noise gives (about one unit of
  chi^2 per parameter), so such a candidate can no longer be the round's best. A candidate with
  as many parameters as the winner runs on: it may fit better and win, or tie.
A pruned or cancelled candidate is reported under ``stopped``. It is not scored, so it cannot be
reported as a tie either: one with a single parameter more than the winner and as good a fit would
trail it by ln(n), inside the margin. Which candidates are scored follows the timing of the fits (what
has finished); the choice among those that could win does not."""
from __future__ import annotations

import threading
import time
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait

from ...errors import SimulationError
from ..fit import FitAborted
from .candidates import fit_candidate
from .at_noise import at_noise


def pruned(size: int, winners: list) -> bool:
    """Occam: a candidate adding ``size`` parameters is not started once one adding fewer (a size
    in ``winners``) has reached the noise: the same rule as :func:`cannot_win` for a running one,
    so the round's choice does not depend on the order in which its fits finish."""
    return cannot_win(size, winners)


def cannot_win(size: int, winners: list) -> bool:
    """A running candidate adding ``size`` parameters is cancelled once one adding fewer has
    reached the noise (see the module docstring)."""
    return any(size > k for k in winners)


class _Round:
    """Book-keeping of one round's candidate fits (results, cancel flags, progress messages)."""

    def __init__(self, ctx, jobs, round_no):
        self.ctx, self.jobs, self.round_no = ctx, jobs, round_no
        self.results, self.variants = [None] * len(jobs), [None] * len(jobs)
        self.cancel = [threading.Event() for _ in jobs]
        self.winners = []
        self.threads = max(1, ctx.processes)
        self.t0 = time.monotonic()
        self.done = 0

    def should_stop(self, i):
        return lambda: self.ctx.stop.is_set() or self.cancel[i].is_set()

    def cancel_losers(self, running) -> None:
        for j in running.values():
            if not self.cancel[j].is_set() and cannot_win(self.jobs[j][2], self.winners):
                self.cancel[j].set()
                self.ctx.say(f"round {self.round_no}: {self.jobs[j][0]} cancelled: a candidate with fewer "
                             "parameters reached the noise")

    def collect(self, i, fut, pending, running) -> None:
        try:
            res, var = fut.result()
        except (FitAborted, SimulationError):
            res, var = None, None
        self.results[i], self.variants[i] = res, var
        self.done += 1
        if res is not None and at_noise(self.ctx, res):
            self.winners.append(self.jobs[i][2])
            self.cancel_losers(running)
        left = len([j for j in pending if not pruned(self.jobs[j][2], self.winners)]) + len(running)
        per = (time.monotonic() - self.t0) / self.done
        outcome = (f"rms {res.rms:.3g} {self.ctx.record.unit}" if res is not None
                   else "cancelled" if self.cancel[i].is_set() else "no fit: its simulation failed")
        self.ctx.say(f"round {self.round_no}: {self.done}/{self.done + left} candidate fits done "
                     f"({self.jobs[i][0]}: {outcome}); "
                     f"about {per * left / max(1, min(self.threads, left or 1)):.0f} s left in this round, "
                     f"{time.monotonic() - self.ctx.budget.started:.0f} s so far")


def run_candidates(ctx, current: object, jobs: list, round_no: int) -> tuple:
    """Fit the ``jobs`` (from :func:`.candidates.candidate_jobs`) on top of ``current``. Returns
    (fits, spring-variant summaries), None where a candidate was not fitted or was cancelled."""
    book = _Round(ctx, jobs, round_no)

    def run(i):
        name, (effects, var, scan), _ = jobs[i]
        return fit_candidate(ctx, current, name, effects, var, scan, should_stop=book.should_stop(i))

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

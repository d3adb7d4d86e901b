"""Simulations for fits: one :class:`SimJob` per simulation, run on a pool of forked worker
processes (:class:`SimulationPool`, with processor time read from /proc), and the integration
step and friction function the experiment chooses for fits."""
from __future__ import annotations

import ctypes
import hashlib
import multiprocessing
import os
import pickle
import signal
import sys
import threading
import time
from collections import OrderedDict
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass

import numpy as np

from ...errors import SimulationError
from ...experiments import experiment_of
from ...experiments.simulation import simulate
from .arithmetic import quiet_trial


@dataclass(frozen=True)
class SimJob:
    """One simulation: the rig (with any overridden values), effects, effect values, spring
    model, the output grid (uniform from 0, or the record's times) and the channels wanted."""

    rig: object
    effects: tuple
    values: tuple  # sorted (name, value) pairs
    spring_model: object
    times: tuple  # (dt, n) for a uniform grid from 0 (s, samples), or None with ``sample_times``
    channels: tuple
    step: float | None = None  # integration step (s; None: the experiment's)
    sample_times: object = None  # explicit times (s; no nuisance)
    user_function: str = "auto"
    backend: str = "fast"  # compiled where it covers the model (vcbmodel.compiled), else Exudyn


@quiet_trial
def run_job(job: SimJob) -> dict | SimulationError:
    """Simulate one job; returns {'t': times (s), channel: samples, ...} or the
    :class:`~vcbmodel.errors.SimulationError` it raised."""
    if job.sample_times is not None:
        times = np.asarray(job.sample_times)
    else:
        dt, n = job.times
        times = np.arange(n + 1) * dt
    try:
        r = simulate(job.rig, job.effects, dict(job.values), spring_model=job.spring_model, sample_times=times,
                     step=job.step, user_function=job.user_function, backend=job.backend)
    except SimulationError as e:
        return e.with_traceback(None)  # kept without the solve's frames (as a worker's pickled one)
    out = {"t": times}
    for ch in job.channels:
        out[ch] = np.asarray(r.channels[ch])
    return out


#: Bytes of results a :class:`SimulationPool` keeps for jobs asked again (least recently used dropped
#: first; an 8 s pendulum's result is about 0.1 MB). Fits of one record ask for the same simulation
#: again, a median 500 simulations later (a discovery of a 1 kHz pendulum record: 325 of 5819): a refit
#: from values another fit started from (the discovery's registered model refitted from its own values
#: before each rebase), a fit's Jacobian at a point its optimiser reached before.
RESULTS_KEPT_BYTES = 200e6


def job_key(job: SimJob) -> bytes:
    """A digest of the bytes a worker receives for ``job`` (its pickle): equal digests, the same inputs
    to the same deterministic simulation."""
    return hashlib.blake2b(pickle.dumps(job, protocol=pickle.HIGHEST_PROTOCOL), digest_size=20).digest()


def _size(result) -> int:
    return sum(v.nbytes for v in result.values() if isinstance(v, np.ndarray)) if isinstance(result, dict) else 0


def _kept(result):
    """``result`` as kept and handed out again: its arrays read-only (no caller may change a result
    another caller receives)."""
    if isinstance(result, dict):
        for v in result.values():
            if isinstance(v, np.ndarray):
                v.flags.writeable = False
    return result


#: A batch of simulations runs in this process, not on the workers, while a simulation takes less than
#: this (s; the running mean of those run here or on the workers) and no other fit's batch runs here
#: (fits run side by side in threads: the second one's goes to the workers): sending a job and its
#: result between processes (pickled arrays) then costs more than a second core gains. Measured (2 cores, three realism
#: pendulum diagnoses of 1-4 ms simulations, identical results): 5-12 % less processor time and
#: 2-7 % less wall time than every batch on the 2 workers; an ANCF cam drop's 0.1-0.3 s simulations
#: keep the workers.
INLINE_BELOW_S = 0.02


class SimulationPool:
    """Worker processes (fork) that run :class:`SimJob` s; ``processes <= 1``: in this process.
    A job asked again is answered from the last results (``kept_bytes`` of them, default
    :data:`RESULTS_KEPT_BYTES`; 0: none kept); ``simulations`` counts the simulations run, ``reused``
    the results handed out again.

    The workers are started at once, before any fitting thread exists (forking a process that
    runs threads is unsafe)."""

    def __init__(self, processes: int = 2, inline_single: bool = False, kept_bytes: float = RESULTS_KEPT_BYTES):
        self.processes = max(1, int(processes))
        self.inline_single = inline_single  # one job at a time runs here (no other fit shares the pool)
        self.pool = None
        self.simulations = 0
        self.reused = 0
        self.kept = max(0.0, float(kept_bytes))
        self.results = OrderedDict()  # job_key -> result
        self.kept_now = 0  # bytes of the results kept
        self.lock = threading.Lock()
        self.inline_lock = threading.Lock()  # one batch at a time here; another fit's goes to the workers
        self.seconds_per_simulation = None  # running mean (s); None until a batch has run
        if self.processes > 1:
            self.pool = ProcessPoolExecutor(max_workers=self.processes, mp_context=multiprocessing.get_context("fork"),
                                            initializer=_worker_start)
            started = set()  # every worker has run its start (a signal before it would still kill it)
            for _ in range(200):
                started.update(self.pool.map(_started, range(self.processes)))
                if len(started) >= self.processes:
                    break

    def run(self, jobs) -> list:
        """Results of ``jobs`` (:func:`run_job`), in order; a job run before is not run again."""
        jobs = list(jobs)
        keys = [job_key(j) for j in jobs] if self.kept else [None] * len(jobs)
        out, todo = [None] * len(jobs), {}
        with self.lock:
            for i, k in enumerate(keys):
                if k is not None and k in self.results:
                    self.results.move_to_end(k)
                    out[i] = self.results[k]
                    self.reused += 1
                elif k is None or k not in todo:
                    todo[k if k is not None else i] = i
            self.simulations += len(todo)
        fresh = self._run([jobs[i] for i in todo.values()])
        with self.lock:
            for k, i, r in zip(todo, todo.values(), fresh):
                out[i] = r
                if self.kept and k not in self.results:
                    self.results[k] = _kept(r)
                    self.kept_now += _size(r)
            while self.results and self.kept_now > self.kept:
                self.kept_now -= _size(self.results.popitem(last=False)[1])
        for i, k in enumerate(keys):  # a job asked twice in one call
            if out[i] is None:
                out[i] = out[todo[k]]
                with self.lock:  # fits in other threads count too
                    self.reused += 1
        return out

    def _run(self, jobs: list) -> list:
        if self.pool is None or len(jobs) == 0:
            return [run_job(j) for j in jobs]
        if len(jobs) == 1 and self.inline_single:
            return [run_job(jobs[0])]
        if self.runs_here() and self.inline_lock.acquire(blocking=False):  # busy: another fit's batch runs here
            try:
                t0 = time.perf_counter()
                out = [run_job(j) for j in jobs]
                self._timed(time.perf_counter() - t0, len(jobs), 1)
            finally:
                self.inline_lock.release()
            return out
        t0 = time.perf_counter()
        out = [self.pool.submit(run_job, jobs[0]).result()] if len(jobs) == 1 else list(self.pool.map(run_job, jobs))
        self._timed(time.perf_counter() - t0, len(jobs), min(self.processes, len(jobs)))
        return out

    def runs_here(self) -> bool:
        """Do simulations run in this process (:data:`INLINE_BELOW_S`)?"""
        s = self.seconds_per_simulation
        return s is not None and s < INLINE_BELOW_S

    def _timed(self, wall: float, jobs: int, parallel: int) -> None:
        """Update the running mean of a simulation's time from a batch of ``jobs`` run ``parallel`` at once."""
        each = wall * parallel / jobs
        with self.lock:
            s = self.seconds_per_simulation
            self.seconds_per_simulation = each if s is None else 0.8 * s + 0.2 * each

    def cpu_seconds(self) -> float:
        """Processor time (s) used so far by this process and the pool's workers (Linux /proc;
        elsewhere this process only)."""
        total = time.process_time()
        if self.pool is None:
            return total
        tick = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100
        for pid in list(getattr(self.pool, "_processes", {}) or {}):
            try:
                with open(f"/proc/{pid}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
                total += (int(fields[11]) + int(fields[12])) / tick
            except (OSError, IndexError, ValueError):
                continue
        return total

    def close(self) -> None:
        if self.pool is not None:
            self.pool.shutdown(cancel_futures=True)
            self.pool = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _started(_) -> int:
    """A worker's pid, after its start (:func:`_worker_start`) ran; the short wait lets every worker take
    one of the pool's first tasks."""
    time.sleep(0.005)
    return os.getpid()


#: Linux's prctl option that signals a process when its parent ends.
PR_SET_PDEATHSIG = 1


def _worker_start() -> None:
    """A worker's start: Ctrl-C and SIGTERM, which a terminal or a batch system sends to every process of the
    command, are the parent's to handle: it prints one line and stops the pool. A worker left to the default
    would print its own traceback, or die while it sends a result, leaving the parent waiting for the rest.
    On Linux the kernel ends the worker when its parent ends, however (``kill -9``): none is left behind."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except (OSError, AttributeError):
            pass


def dataset_pool(datasets, processes: int = 2) -> SimulationPool | None:
    """A simulation pool for a fit of several datasets (None for one dataset and one process)."""
    if processes < 2:
        return None
    return SimulationPool(processes)


# --- the experiment's choices for fits ------------------------------------------------------------

def scan_step(rig) -> float | None:
    """The integration step (s) of a fit's start scan (None: the fit's own): the experiment's."""
    return experiment_of(rig.experiment).scan_step


def fit_step(rig, spring_model) -> float | None:
    """The integration step (s) fits use (None: the experiment's default): the experiment's
    choice for the spring model (``Experiment.fit_step``)."""
    return experiment_of(rig.experiment).fit_step(rig, spring_model.kind)


def user_function_for(rig) -> str:
    """The friction connector's implementation for fits: the experiment's (``Experiment.fit_user_function``)."""
    return experiment_of(rig.experiment).fit_user_function

"""Where a sweep's runs go: this process, a local process pool, or a Dask cluster. Each executor
yields ``(run, values, status, seconds)`` as runs finish, and stops its workers when interrupted.

Runs travel in chunks of about :data:`TASK_SECONDS` of work each, sized from the run times
measured so far (:class:`Chunker`), so that handing out a task costs a negligible part of it;
what every run shares (:class:`~.runs.SweepJob`: the rig with its data files, the evaluation)
travels to each worker once. A local pool's workers die with the sweep however it ends
(:func:`_die_with_parent`). Before a Dask sweep runs, every worker is checked for what the runs
need (:func:`check_workers`).
"""
from __future__ import annotations

import ctypes
import math
import multiprocessing
import os
import signal
import socket
import statistics
import sys
import threading
import time
from collections.abc import Iterable, Iterator, Sequence
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from typing import Any

from ... import __version__
from ...builders.exudyn_loader import exudyn_modules
from ...compiled import compiler_problem
from ...errors import InputError
from .runs import SweepJob, one_line, run_chunk

#: Work (s) a task of runs aims at: long enough that handing it out (a few ms on Dask, less in a
#: local pool) is under 1 % of it, short enough that rows stream back as the sweep goes and the
#: last tasks end close together.
TASK_SECONDS = 1.0
#: Tasks in flight per worker: one running and one waiting, so a worker never idles between tasks.
IN_FLIGHT = 2
#: Run times (the latest) the chunk size is taken from.
MEASURED_RUNS = 200

Result = tuple[int, dict, str, float]


class Chunker:
    """Hands out a sweep's runs ``[(run, overrides)]`` in chunks of about :data:`TASK_SECONDS` of
    work: one run per chunk until run times are measured, then as many runs as the median
    measured run time fits, but never more than the runs left over :data:`IN_FLIGHT` x the
    workers, so the workers finish together."""

    def __init__(self, jobs: Iterable[tuple[int, dict]], workers: int):
        self.jobs = list(jobs)
        self.workers = max(1, int(workers))
        self.taken = 0
        self.times: list[float] = []

    def record(self, seconds: Iterable[float]) -> None:
        self.times = (self.times + [float(s) for s in seconds])[-MEASURED_RUNS:]

    def size(self) -> int:
        left = len(self.jobs) - self.taken
        if not self.times:
            return 1
        wanted = max(1, int(TASK_SECONDS / max(statistics.median(self.times), 1e-6)))
        return max(1, min(wanted, math.ceil(left / (IN_FLIGHT * self.workers))))

    def take(self) -> list[tuple[int, dict]]:
        chunk = self.jobs[self.taken:self.taken + self.size()]
        self.taken += len(chunk)
        return chunk


def _serial(job: SweepJob, jobs: Iterable[tuple[int, dict]]) -> Iterator[Result]:
    for run, overrides in jobs:
        yield from run_chunk(job, [(run, overrides)])


#: The sweep's shared part in a pool's worker (set once per worker by :func:`_worker_start`).
_JOB: list[SweepJob] = []
#: Linux's prctl option that signals a process when its parent ends.
PR_SET_PDEATHSIG = 1
#: Seconds between a pool worker's checks that its parent still runs (where prctl is missing).
LIFELINE_PERIOD = 0.5


def _worker_start(job: SweepJob) -> None:
    """A pool worker's start: SIGTERM ends it (the parent stops the pool), Ctrl-C is the parent's
    to handle, it dies with its parent, and it keeps the sweep's shared part."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    _die_with_parent()
    _JOB[:] = [job]


def _die_with_parent() -> None:
    """End this process when its parent ends, however that ends (``kill -9`` included): on Linux
    the kernel sends SIGKILL (prctl PR_SET_PDEATHSIG); everywhere a daemon thread checks twice a
    second that the parent is still this process's parent (a parent that ends hands its children
    to another process)."""
    parent = os.getppid()
    if sys.platform.startswith("linux"):
        try:
            ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except (OSError, AttributeError):
            pass
    if os.getppid() != parent:  # the parent ended while the lifeline was being set
        os._exit(1)

    def watch():
        while os.getppid() == parent:
            time.sleep(LIFELINE_PERIOD)
        os._exit(1)

    threading.Thread(target=watch, name="vcbmodel-lifeline", daemon=True).start()


def _run_in_worker(chunk: Sequence[tuple[int, dict]]) -> list[Result]:
    return run_chunk(_JOB[0], chunk)


def _terminate_workers(pool):
    """Stop a pool's worker processes at once (an interrupted sweep must leave no orphans)."""
    for process in list(getattr(pool, "_processes", {}).values()):
        if process.is_alive():
            process.terminate()


def _pool_context(exudyn: bool = True):
    """How the pool's workers start. Forked from this process when it runs no other thread
    (quick: vcbmodel, and Exudyn when the runs need it, are imported already; any script works,
    guarded by ``if __name__ == "__main__"`` or not); a fork of a multi-threaded process can
    deadlock, so then from a fork server that imports them once (the calling script must then
    guard its top level with ``if __name__ == "__main__":``). Runs on the compiled path do not
    import Exudyn."""
    if threading.active_count() == 1 and "fork" in multiprocessing.get_all_start_methods():
        if exudyn:
            exudyn_modules()  # imported once here, inherited by every worker
        return multiprocessing.get_context("fork")
    ctx = multiprocessing.get_context("forkserver")
    ctx.set_forkserver_preload(["vcbmodel.analysis.sweep", "exudyn"] if exudyn else ["vcbmodel.analysis.sweep"])
    return ctx


def _local_pool(job: SweepJob, jobs: Iterable[tuple[int, dict]], workers: int, exudyn: bool = True) -> Iterator[Result]:
    """A process pool: the shared part sent to each worker once (at its start), the runs in
    chunks (:class:`Chunker`), :data:`IN_FLIGHT` chunks queued per worker; ``exudyn``: whether the
    runs need Exudyn (imported before the workers start)."""
    chunker = Chunker(jobs, workers)
    with ProcessPoolExecutor(max_workers=workers, mp_context=_pool_context(exudyn), initializer=_worker_start,
                             initargs=(job,)) as pool:
        pending = {}
        finished = False

        def submit():
            chunk = chunker.take()
            if chunk:
                pending[pool.submit(_run_in_worker, chunk)] = chunk

        try:
            for _ in range(IN_FLIGHT * workers):
                submit()
            while pending:
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for f in done:
                    del pending[f]
                    results = f.result()
                    chunker.record(r[3] for r in results)
                    submit()
                    yield from results
            finished = True
        finally:
            for f in pending:
                f.cancel()
            if not finished:  # interrupted (Ctrl-C, SIGTERM) or failed: stop the runs in progress now
                _terminate_workers(pool)
            pool.shutdown(wait=True, cancel_futures=True)


def connect(scheduler: Any, timeout: float = 10) -> tuple[Any, bool]:
    """A Dask ``distributed.Client`` for ``scheduler`` (an address or a Client) with at least one
    worker. Bad input, in a few seconds and one line: an address that is not one, a host that
    does not answer, a web server (the dashboard's port, 8787, instead of the scheduler's),
    a scheduler without workers."""
    import distributed

    if isinstance(scheduler, distributed.Client):
        return scheduler, False
    host, port = _scheduler_address(scheduler)
    _probe(scheduler, host, port)
    try:
        client = distributed.Client(scheduler, timeout=timeout, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as e:
        raise InputError("--scheduler", scheduler, f"cannot connect to a Dask scheduler there ({one_line(e, 160)}); "
                         f"{START_HINT}") from None
    try:
        client.wait_for_workers(1, timeout=WORKER_WAIT)
    except (TimeoutError, OSError):
        client.close()
        raise InputError("--scheduler", scheduler, f"the scheduler has no workers (waited {WORKER_WAIT:g} s); start "
                         "some with 'dask worker ADDRESS --nworkers -1 --nthreads 1'") from None
    return client, True


#: Seconds a Dask sweep waits for its workers' reports (:func:`check_workers`).
CHECK_TIMEOUT = 60.0
#: Where a worker's check passed once: {what was checked: True} (a second sweep is not slowed).
_CHECKED: dict = {}


def worker_report(need_compiler: bool) -> dict:
    """What this process (a cluster's worker) lacks for a sweep's runs: {"host", "vcbmodel"
    (version), "exudyn": why it does not import (absent if it does), "compiler": why no C
    module can be built here (absent if one can; only with ``need_compiler``)}. Runs on the
    worker (``Client.run``); a pass is remembered for the next sweep."""
    report = {"host": socket.gethostname(), "vcbmodel": __version__}
    if not _CHECKED.get("exudyn"):
        try:
            exudyn_modules()
            _CHECKED["exudyn"] = True
        except Exception as e:  # noqa: BLE001 -- whatever stops the import is the report
            report["exudyn"] = one_line(f"{type(e).__name__}: {e}", 200)
    if need_compiler and not _CHECKED.get("compiler"):
        reason = compiler_problem()
        if reason:
            report["compiler"] = reason
        else:
            _CHECKED["compiler"] = True
    return report


def check_workers(client: Any, address: str, need_compiler: bool) -> dict:
    """Refuse a cluster, before any run, when a worker cannot run this sweep: one line naming the
    worker and what it lacks (vcbmodel, or another version of it; Exudyn, e.g. libGL on a headless
    image; a C compiler when the sweep runs on the compiled path). Returns the reports
    {worker address: report}."""
    try:
        reports = client.run(worker_report, need_compiler, on_error="return", callback_timeout=CHECK_TIMEOUT)
    except (TimeoutError, OSError) as e:
        raise InputError("--scheduler", address, f"the workers did not report within {CHECK_TIMEOUT:g} s "
                         f"({one_line(e, 120)})") from None
    for worker, report in sorted(reports.items()):
        if isinstance(report, BaseException):
            lacks = f"a working vcbmodel ({one_line(f'{type(report).__name__}: {report}', 160)})"
        elif report.get("vcbmodel") != __version__:
            lacks = f"vcbmodel {__version__} (it runs {report.get('vcbmodel')})"
        elif "exudyn" in report:
            lacks = (f"Exudyn ({report['exudyn']}); a headless image needs libGL (Debian/Ubuntu: apt install "
                     "libgl1)")
        elif "compiler" in report:
            lacks = (f"a C compiler for the compiled path ({report['compiler']}); install gcc (and the Python "
                     "headers) there, or give --backend exudyn")
        else:
            continue
        host = f" on {report['host']}" if isinstance(report, dict) else ""
        raise InputError("--scheduler", address, f"worker {worker}{host} lacks {lacks}: no run was started")
    return reports


#: How to start a cluster (in the errors about one).
START_HINT = "start one with 'dask scheduler' and workers with 'dask worker ADDRESS --nworkers -1 --nthreads 1'"
#: Seconds to wait for a host to accept a connection, and for a scheduler's first worker.
PROBE_TIMEOUT, WORKER_WAIT = 3.0, 10.0


def _scheduler_address(scheduler):
    """(host, port) of ``tcp://HOST:PORT`` (or ``HOST:PORT``); anything else is bad input."""
    text = str(scheduler)
    rest = text.split("://", 1)[1] if "://" in text else text
    if "://" in text and not text.startswith(("tcp://", "tls://")):
        raise InputError("--scheduler", text, "not a scheduler address: give tcp://HOST:PORT (Dask's default port 8786)")
    host, sep, port = rest.rpartition(":")
    if not sep or not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise InputError("--scheduler", text, "not a scheduler address: give tcp://HOST:PORT (Dask's default port 8786)")
    return host.strip("[]"), int(port)


def _probe(scheduler, host, port):
    """Fail fast where ``distributed`` would wait: an unknown or silent host, a closed port, or a
    port that is not a Dask scheduler's (a Dask server sends its handshake as soon as a connection
    opens; a web server such as the dashboard waits for a request)."""
    try:
        with socket.create_connection((host, port), timeout=PROBE_TIMEOUT) as s:
            s.settimeout(PROBE_TIMEOUT)
            try:
                greeting = s.recv(8)
            except (socket.timeout, OSError):
                greeting = b""
    except socket.gaierror:
        raise InputError("--scheduler", scheduler, f"unknown host {host!r}") from None
    except socket.timeout:
        raise InputError("--scheduler", scheduler, f"no answer from {host}:{port} within {PROBE_TIMEOUT:g} s; "
                         f"{START_HINT}") from None
    except OSError as e:
        raise InputError("--scheduler", scheduler, f"cannot connect ({e.strerror or e}); {START_HINT}") from None
    if not greeting:
        raise InputError("--scheduler", scheduler, f"{host}:{port} is not a Dask scheduler (no handshake in "
                         f"{PROBE_TIMEOUT:g} s; Dask's dashboard is on 8787): give the tcp://HOST:8786 address that "
                         "'dask scheduler' prints first")


def _dask(job: SweepJob, jobs: Iterable[tuple[int, dict]], client: Any) -> Iterator[Result]:
    """The runs as Dask tasks of :class:`Chunker` chunks; the shared part scattered to every worker
    once (each task refers to it); rows back in the order the chunks finish."""
    import distributed

    workers = max(1, sum(int(w.get("nthreads", 1)) for w in client.scheduler_info()["workers"].values()))
    chunker = Chunker(jobs, workers)
    [shared] = client.scatter([job], broadcast=True, hash=False)
    tag = f"{os.getpid()}-{time.time_ns()}"
    pending = {}
    finished = distributed.as_completed(loop=client.loop)

    def submit():
        chunk = chunker.take()
        if chunk:
            f = client.submit(run_chunk, shared, chunk, pure=False, key=f"vcbmodel-sweep-{tag}-run-{chunk[0][0]}")
            pending[f] = chunk
            finished.add(f)

    try:
        for _ in range(IN_FLIGHT * workers):
            submit()
        for f in finished:
            del pending[f]
            results = f.result()
            chunker.record(r[3] for r in results)
            submit()
            yield from results
    finally:
        if pending:
            client.cancel(list(pending))
        shared.release()


def default_workers() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1

"""Where a sweep's runs go: this process, a local process pool, or a Dask cluster. Each executor
yields ``(run, values, status, seconds)`` as runs finish, and stops its workers when interrupted."""
from __future__ import annotations

import itertools
import multiprocessing
import os
import signal
import socket
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from typing import Any

from ...builders.core import exudyn_modules
from ...errors import InputError
from .runs import one_line


def _serial(jobs, call):
    for run, args in jobs:
        yield (run, *call(*args))


def _worker_signals():
    """In a pool's worker: SIGTERM ends the process (the parent stops the pool); Ctrl-C is the
    parent's to handle."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _terminate_workers(pool):
    """Stop a pool's worker processes at once (an interrupted sweep must leave no orphans)."""
    for process in list(getattr(pool, "_processes", {}).values()):
        if process.is_alive():
            process.terminate()


def _pool_context():
    """How the pool's workers start. Forked from this process when it runs no other thread
    (quick: vcbmodel and Exudyn are imported already; any script works, guarded by
    ``if __name__ == "__main__"`` or not); a fork of a multi-threaded process can deadlock, so
    then from a fork server that imports vcbmodel and Exudyn once (the calling script must
    then guard its top level with ``if __name__ == "__main__":``)."""
    if threading.active_count() == 1 and "fork" in multiprocessing.get_all_start_methods():
        exudyn_modules()  # imported once here, inherited by every worker
        return multiprocessing.get_context("fork")
    ctx = multiprocessing.get_context("forkserver")
    ctx.set_forkserver_preload(["vcbmodel.analysis.sweep", "exudyn"])
    return ctx


def _local_pool(jobs, call, workers):
    """A process pool with a few runs queued per worker (a long sweep does not queue all its
    runs' arguments at once)."""
    jobs = iter(jobs)
    with ProcessPoolExecutor(max_workers=workers, mp_context=_pool_context(), initializer=_worker_signals) as pool:
        pending = {}
        finished = False
        try:
            for run, args in itertools.islice(jobs, 2 * workers):
                pending[pool.submit(call, *args)] = run
            while pending:
                done, _ = wait(pending, return_when=FIRST_COMPLETED)
                for f in done:
                    run = pending.pop(f)
                    for nxt, args in itertools.islice(jobs, 1):
                        pending[pool.submit(call, *args)] = nxt
                    yield (run, *f.result())
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


def _dask(jobs, call, client):
    """Every run a Dask task; the rig's JSON object is sent to the workers once (scatter)."""
    import distributed

    futures = {}
    shared = {}
    try:
        for run, (data, *rest) in jobs:
            if "data" not in shared:
                shared["data"] = client.scatter(data, broadcast=True, hash=False)
            key = f"vcbmodel-sweep-run-{run}-{os.getpid()}-{time.time_ns()}"
            futures[client.submit(call, shared["data"], *rest, pure=False, key=key)] = run
        for f in distributed.as_completed(list(futures), loop=client.loop):
            yield (futures.pop(f), *f.result())
    finally:
        if futures:
            client.cancel(list(futures))


def default_workers() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1

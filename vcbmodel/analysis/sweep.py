"""Parameter studies: one rig, many runs, one table (docs/cli.md, ``vcbmodel sweep``).

A sweep varies numeric rig fields, named by their dotted path into the rig's JSON object
(``friction.mu_k``, ``breaker.poles.gap_offsets.1``: list items by index), runs the rig's
experiment with its ``model`` once per parameter set and returns one row per run: ``run``,
the varied paths, the experiment's figures of merit and ``status`` (``ok`` or ``failed:
reason``; a failed run does not stop the sweep).

Parameter sets come from grids ``LO:HI:N`` (the full product of all grids) or from
distributions ``normal:MEAN:SD`` / ``uniform:LO:HI`` (``samples`` draws by Latin hypercube
sampling: scipy's scrambled ``LatinHypercube``, each axis mapped through the distribution's
inverse CDF; repeatable: the default seed is :data:`DEFAULT_SEED`), never both in one sweep.
Studies with their own design (Sobol samples, tied parameters) pass ``runs`` instead.

Execution: each run is an independent job that sends only JSON (the rig's object and the
run's overrides) and gets back numbers: the worker loads the rig and builds its own Exudyn
system (symbolic user functions do not pickle; exudyn-notes "Sweeps and scale-out").
Locally a process pool on all cores (forked workers, a few runs queued each); beyond one
machine a Dask ``distributed`` cluster (``scheduler=ADDRESS``: ``dask scheduler`` on one
machine, ``dask worker ADDRESS --nworkers -1 --nthreads 1`` on each; the rig goes to the
workers once). Dask was chosen over Ray by measurement (README, "Design studies at scale").

Rows are written (and flushed) to the output as runs finish; ``resume=True`` keeps the runs
already in the output (checked against this sweep's design) and runs the rest. When every
run is in, the file is rewritten in run order.
"""
from __future__ import annotations

import copy
import csv
import io
import itertools
import math
import multiprocessing
import os
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd
from scipy.stats import norm, qmc

from ..errors import InputError, SimulationError
from ..experiments import experiment_of
from ..experiments.loading import rig_from_data
from ..experiments.simulation import model_spec, simulate
from ..rig.data import Rig
from ..rig.reader import read_json
from .progress import Progress, progress

#: Figures of merit of each experiment, the sweep's result columns (SI units, docs/cli.md).
FIGURES = {
    "vcb_closing": ("closing_time_s", "touch_speed_m_s", "pole_spread_s", "bounce_count", "bounce_duration_s",
                    "overtravel_m", "peak_cam_roller_force_N"),
    "cam_drop": ("cam_angle_end_rad", "peak_shaft_velocity_rad_s"),
    "pendulum": ("first_peak_rad", "stop_time_s"),
}
#: Seed of the random draws when none is given: every sweep is repeatable (and resumable).
DEFAULT_SEED = 0
#: How distributions are sampled (stated in ``vcbmodel sweep --help`` and the table's attrs).
SAMPLING = {"lhs": "Latin hypercube sampling (scipy.stats.qmc.LatinHypercube, scrambled)", "mc": "plain Monte Carlo"}
#: A larger design is a typo (a grid of 1000 x 1000 x 1000), not a study.
MAX_RUNS = 10_000_000
#: Significant digits of a varied value: the value a run uses is the value its row shows.
DIGITS = 12
DISTRIBUTIONS = ("normal", "uniform")


# --- the design -----------------------------------------------------------------------------------

@dataclass(frozen=True)
class Vary:
    """One ``PATH=SPEC``: a grid (``kind`` ``grid``: ``a`` to ``b`` in ``n`` values) or a
    distribution (``normal``: mean ``a``, sd ``b``; ``uniform``: ``a`` to ``b``)."""

    path: str
    kind: str
    a: float
    b: float
    n: int = 0

    @property
    def is_grid(self):
        return self.kind == "grid"

    def grid(self):
        return np.linspace(self.a, self.b, self.n)

    def from_unit(self, u):
        """Values at probabilities ``u`` in (0, 1) (the inverse CDF)."""
        u = np.clip(np.asarray(u, float), 1e-12, 1 - 1e-12)
        return norm.ppf(u, self.a, self.b) if self.kind == "normal" else self.a + u * (self.b - self.a)

    @property
    def spec(self):
        if self.is_grid:
            return f"{self.a:g}:{self.b:g}:{self.n}"
        return f"{self.kind}:{self.a:g}:{self.b:g}"


def parse_vary(item, source="--vary") -> Vary:
    """``PATH=SPEC`` (text), or a ``(path, spec)`` pair, as a :class:`Vary`; bad syntax raises
    :class:`InputError` naming ``source`` and the item."""
    if isinstance(item, Vary):
        return item
    if isinstance(item, (tuple, list)) and len(item) == 2:
        path, spec = (str(x).strip() for x in item)
    else:
        text = str(item)
        if "=" not in text:
            raise InputError(source, text, "must be PATH=SPEC, e.g. friction.mu_k=0.08:0.18:6")
        path, spec = (s.strip() for s in text.split("=", 1))
    if not path:
        raise InputError(source, f"{path}={spec}", "PATH is empty")
    parts = spec.split(":")

    def number(s, what):
        try:
            v = float(s)
        except ValueError:
            raise InputError(source, path, f"{what} {s!r} in {spec!r} is not a number") from None
        if not math.isfinite(v):
            raise InputError(source, path, f"{what} in {spec!r} must be finite")
        return v

    if parts[0] in DISTRIBUTIONS:
        if len(parts) != 3:
            raise InputError(source, path, f"{parts[0]} needs two numbers: {parts[0]}:"
                             f"{'MEAN:SD' if parts[0] == 'normal' else 'LO:HI'}, got {spec!r}")
        first, second = ("MEAN", "SD") if parts[0] == "normal" else ("LO", "HI")
        a, b = number(parts[1], first), number(parts[2], second)
        if parts[0] == "normal" and not b > 0:
            raise InputError(source, path, f"the standard deviation must be positive, got {b:g}")
        if parts[0] == "uniform" and not b > a:
            raise InputError(source, path, f"uniform:LO:HI needs LO < HI, got {spec!r}")
        return Vary(path, parts[0], a, b)
    if len(parts) != 3:
        raise InputError(source, path, f"SPEC must be LO:HI:N, normal:MEAN:SD or uniform:LO:HI, got {spec!r}")
    if parts[0].strip().isalpha() and parts[0].lower() not in ("nan", "inf", "infinity"):
        raise InputError(source, path, f"unknown distribution {parts[0]!r}: SPEC must be LO:HI:N, normal:MEAN:SD "
                         "or uniform:LO:HI")
    lo, hi = number(parts[0], "LO"), number(parts[1], "HI")
    n = number(parts[2], "N")
    if n != int(n) or n < 1:
        raise InputError(source, path, f"N must be a whole number >= 1, got {parts[2]!r}")
    if n == 1 and lo != hi:
        raise InputError(source, path, f"one value from {lo:g} to {hi:g}: give N >= 2, or LO = HI")
    return Vary(path, "grid", lo, hi, int(n))


def parse_varies(items, source="--vary"):
    varies = [parse_vary(x, source) for x in (items.items() if isinstance(items, dict) else items)]
    seen = set()
    for v in varies:
        if v.path in seen:
            raise InputError(source, v.path, "varied twice: give each PATH once")
        seen.add(v.path)
    return varies


def _rounded(values):
    return np.array([float(f"{v:.{DIGITS}g}") for v in values])


def design(varies, samples=None, seed=None, sampling="lhs") -> pd.DataFrame:
    """The parameter sets, one row per run, one column per varied path (in order).

    Grids: the full product, the last path varying fastest. Distributions: ``samples``
    draws, Latin hypercube (``sampling="lhs"``) or plain Monte Carlo (``"mc"``), seeded by
    ``seed`` (default :data:`DEFAULT_SEED`). Grids and distributions are not mixed.
    """
    varies = parse_varies(varies)
    if not varies:
        raise InputError("--vary", "vary", "give at least one PATH=SPEC")
    grids = [v for v in varies if v.is_grid]
    if grids and len(grids) != len(varies):
        other = next(v for v in varies if not v.is_grid)
        raise InputError("--vary", other.path, f"{other.kind} distribution mixed with the grid of {grids[0].path}: "
                         "one sweep uses grids (LO:HI:N) or distributions (normal:, uniform:), not both")
    if grids:
        if samples is not None:
            raise InputError("--samples", "samples", "applies to distributions only: a grid's size is the "
                             "product of its N")
        total = math.prod(v.n for v in varies)
        if total > MAX_RUNS:
            raise InputError("--vary", varies[0].path, f"the grids make {total} runs (at most {MAX_RUNS})")
        rows = list(itertools.product(*(_rounded(v.grid()) for v in varies)))
        return pd.DataFrame(rows, columns=[v.path for v in varies], dtype=float)
    if samples is None:
        raise InputError("--samples", "samples", "random draws need --samples N (the number of runs)")
    if isinstance(samples, bool) or int(samples) != samples or samples < 1 or samples > MAX_RUNS:
        raise InputError("--samples", "samples", f"must be a whole number from 1 to {MAX_RUNS}, got {samples}")
    seed = DEFAULT_SEED if seed is None else seed
    if isinstance(seed, bool) or int(seed) != seed or seed < 0:
        raise InputError("--seed", "seed", f"must be a whole number >= 0, got {seed}")
    if sampling not in SAMPLING:
        raise ValueError(f"sampling must be one of {', '.join(SAMPLING)}")
    rng = np.random.default_rng(int(seed))
    if sampling == "lhs":
        try:
            lhs = qmc.LatinHypercube(d=len(varies), rng=rng)
        except TypeError:  # scipy < 1.15
            lhs = qmc.LatinHypercube(d=len(varies), seed=rng)
        u = lhs.random(int(samples))
    else:
        u = rng.random((int(samples), len(varies)))
    cols = {v.path: _rounded(v.from_unit(u[:, j])) for j, v in enumerate(varies)}
    return pd.DataFrame(cols, dtype=float)


# --- paths into the rig's JSON object -------------------------------------------------------------

def path_keys(path):
    """``a.b.2.c`` -> ["a", "b", 2, "c"] (digits index lists)."""
    keys = path.split(".")
    if any(k == "" for k in keys):
        raise ValueError("empty component")
    return [int(k) if k.isdigit() else k for k in keys]


def get_path(data, path):
    """The value at ``path``; KeyError if absent."""
    obj = data
    for k in path_keys(path):
        if isinstance(k, int) and isinstance(obj, list) and k < len(obj):
            obj = obj[k]
        elif isinstance(k, str) and isinstance(obj, dict) and k in obj:
            obj = obj[k]
        else:
            raise KeyError(path)
    return obj


def set_path(data, path, value):
    """Set ``path`` in ``data`` (in place), creating missing objects on the way."""
    keys = path_keys(path)
    obj = data
    for k, nxt in zip(keys[:-1], keys[1:]):
        if isinstance(obj, list):
            if not isinstance(k, int) or k >= len(obj):
                raise KeyError(path)
            obj = obj[k]
            continue
        if not isinstance(obj, dict) or isinstance(k, int):
            raise KeyError(path)
        if k not in obj:
            obj[k] = {}
        obj = obj[k]
    last = keys[-1]
    if isinstance(obj, list) and isinstance(last, int) and last < len(obj):
        obj[last] = value
    elif isinstance(obj, dict) and isinstance(last, str):
        obj[last] = value
    else:
        raise KeyError(path)


def with_overrides(data, overrides):
    """A copy of the rig's JSON object with ``overrides`` ({path: value}) set."""
    out = copy.deepcopy(data)
    for path, value in overrides.items():
        set_path(out, path, float(value))
    return out


def check_paths(data, paths, rig_path, experiment):
    """Refuse a path that is not a numeric field of this experiment's rigs (InputError naming
    the rig file and the path). A field the rig does not give but the format knows is allowed:
    the loader is the judge (it refuses unknown keys)."""
    for path in paths:
        try:
            keys = path_keys(path)
        except ValueError:
            raise InputError(rig_path, path, "is not a dotted path (e.g. friction.mu_k)") from None
        if any(isinstance(k, str) and k.startswith("_") for k in keys):
            raise InputError(rig_path, path, "names a comment, not a rig field")
        try:
            value = get_path(data, path)
        except KeyError:
            try:
                probe = with_overrides(data, {path: 1.0})
            except KeyError:
                raise InputError(rig_path, path, f"not a field of this {experiment} rig") from None
            try:
                rig_from_data(probe, rig_path)
            except InputError as e:
                if "unknown field" in str(e) and path.startswith(e.field):
                    hint = str(e).split("unknown field", 1)[1].split(";")[0]
                    at = f" (at {e.field})" if e.field != path else ""
                    raise InputError(rig_path, path, f"unknown field of a {experiment} rig{hint}{at}") from None
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise InputError(rig_path, path, f"is not a number ({type(value).__name__}): only numeric fields can be varied")


# --- one run ---------------------------------------------------------------------------------------

def figures_of_merit(rig, t_end=None):
    """The default evaluation of a run: simulate the rig's model and return the experiment's
    figures of merit (:data:`FIGURES`)."""
    record = experiment_of(rig.experiment)
    result = simulate(rig, t_end=t_end)
    fom = record.figures_of_merit(result, rig)
    return {k: fom.get(k) for k in FIGURES[rig.experiment]}


#: One solve at a time per process, even on a multi-threaded Dask worker (Exudyn systems are
#: independent, but the Python user functions share the interpreter).
_SOLVE_LOCK = threading.Lock()


def one_line(text, limit=300):
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[:limit - 3] + "..."


def run_one(data, overrides, rig_path, evaluate=None, t_end=None):
    """One run, in whichever process: edit the JSON, load the rig, simulate, evaluate.

    Never raises for a bad run: returns ``(values, status, seconds)`` with status ``ok`` or
    ``failed: reason`` (a value that makes the rig invalid, a failed solve, ...)."""
    t0 = time.perf_counter()
    with _SOLVE_LOCK:
        try:
            rig = rig_from_data(with_overrides(data, overrides), rig_path)
            values = (evaluate or figures_of_merit)(rig, t_end)
            status = "ok"
        except InputError as e:
            values, status = {}, f"failed: {e.field}: {one_line(str(e).split(': ', 2)[-1])}"
        except SimulationError as e:
            values, status = {}, f"failed: {one_line(e)}"
        except Exception as e:  # noqa: BLE001 -- any other fault is that run's, the sweep goes on
            values, status = {}, f"failed: {type(e).__name__}: {one_line(e)}"
    return values, status, time.perf_counter() - t0


# --- executors: each yields (run, values, status, seconds) as runs finish -------------------------

def _serial(jobs, call):
    for run, args in jobs:
        yield (run, *call(*args))


def _pool_context():
    """How the pool's workers start. Forked from this process when it runs no other thread
    (quick: vcbmodel and Exudyn are imported already; any script works, guarded by
    ``if __name__ == "__main__"`` or not); a fork of a multi-threaded process can deadlock, so
    then from a fork server that imports vcbmodel and Exudyn once (the calling script must
    then guard its top level with ``if __name__ == "__main__":``)."""
    if threading.active_count() == 1 and "fork" in multiprocessing.get_all_start_methods():
        from ..builders.core import exudyn_modules

        exudyn_modules()  # imported once here, inherited by every worker
        return multiprocessing.get_context("fork")
    ctx = multiprocessing.get_context("forkserver")
    ctx.set_forkserver_preload(["vcbmodel.analysis.sweep", "exudyn"])
    return ctx


def _local_pool(jobs, call, workers):
    """A process pool with a few runs queued per worker (a long sweep does not queue all its
    runs' arguments at once)."""
    jobs = iter(jobs)
    with ProcessPoolExecutor(max_workers=workers, mp_context=_pool_context()) as pool:
        pending = {}
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
        finally:
            for f in pending:
                f.cancel()
            pool.shutdown(wait=True, cancel_futures=True)


def connect(scheduler, timeout=10):
    """A Dask ``distributed.Client`` for ``scheduler`` (an address or a Client); an address
    that cannot be reached is bad input."""
    import distributed

    if isinstance(scheduler, distributed.Client):
        return scheduler, False
    try:
        return distributed.Client(scheduler, timeout=timeout, set_as_default=False), True
    except (OSError, TimeoutError, ValueError) as e:
        raise InputError("--scheduler", scheduler, f"cannot connect to a Dask scheduler there ({one_line(e, 160)}); "
                         "start one with 'dask scheduler' and workers with "
                         "'dask worker ADDRESS --nworkers -1 --nthreads 1'") from None


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


# --- the output file -------------------------------------------------------------------------------

def _text(v):
    if v is None:
        return ""
    if isinstance(v, (bool, np.bool_)):
        return str(int(v))
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    v = float(v)
    return "" if not math.isfinite(v) else f"{v:.9g}"


def _value_text(v):
    return repr(float(v))


def read_finished(output, header, table):
    """Rows already in ``output`` (a resumed sweep): {run: row dict}. A last line cut short by
    an interrupt is dropped (the file is truncated to its last complete row); rows must match
    this sweep's header and design."""
    raw = Path(output).read_bytes()
    if not raw.strip():
        Path(output).write_bytes(b"")
        return {}
    if not raw.endswith(b"\n"):  # the interrupted last row
        raw = raw[:raw.rfind(b"\n") + 1]
        Path(output).write_bytes(raw)
    text = raw.decode("utf-8", errors="replace")
    reader = csv.reader(io.StringIO(text))
    got = next(reader, None)
    if got is None:
        return {}
    if got != header:
        raise InputError(output, "header", f"has the columns of another sweep ({','.join(got)[:120]}); this sweep "
                         f"writes {','.join(header)[:120]}: give another -o or leave out --resume")
    paths = list(table.columns)
    finished = {}
    for lineno, row in enumerate(reader, start=2):
        if not row:
            continue
        if len(row) != len(header):
            raise InputError(output, f"line {lineno}", f"has {len(row)} fields, the header {len(header)}")
        try:
            run = int(row[0])
        except ValueError:
            raise InputError(output, f"line {lineno}", f"run {row[0]!r} is not a run number") from None
        if not 1 <= run <= len(table):
            raise InputError(output, f"line {lineno}", f"run {run} is not in this sweep (1 to {len(table)})")
        for j, path in enumerate(paths, start=1):
            want = float(table.iloc[run - 1][path])
            try:
                have = float(row[j])
            except ValueError:
                have = float("nan")
            if not math.isclose(have, want, rel_tol=1e-9, abs_tol=1e-300):
                raise InputError(output, f"line {lineno}", f"run {run} has {path} = {row[j]}, this sweep {want!r}: "
                                 "it was written by another sweep (same --vary, --samples and --seed to resume)")
        finished.setdefault(run, dict(zip(header, row)))
    return finished


def _typed(row, paths, columns):
    out = {"run": int(row["run"])}
    for k in paths + list(columns):
        v = row.get(k, "")
        out[k] = float(v) if v not in ("", None) else float("nan")
    out["status"] = row["status"]
    return out


# --- the sweep -------------------------------------------------------------------------------------

def _rig_input(rig):
    """(JSON object, path label) of a rig given as a path, a JSON object or a loaded Rig."""
    if isinstance(rig, Rig):
        return rig.data, rig.path
    if isinstance(rig, dict):
        return rig, "(rig)"
    return read_json(str(rig)), str(rig)


def default_workers():
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def sweep(rig, vary=(), *, runs=None, samples=None, seed=None, sampling="lhs", workers=None, scheduler=None,
          output=None, stream=None, resume=False, evaluate=None, columns=None, t_end=None, verbose=True,
          label=None) -> pd.DataFrame:
    """Run the rig's experiment once per parameter set; return the table (a DataFrame).

    Parameters
    ----------
    rig : rig file path, its JSON object (dict), or a loaded :class:`~vcbmodel.rig.data.Rig`.
    vary : ``PATH=SPEC`` texts (or a dict {path: spec}); see :func:`design`.
    runs : instead of ``vary``: the parameter sets (a DataFrame or list of {path: value}).
    samples, seed, sampling : random draws of distributions (see :func:`design`).
    workers : local processes (default: all cores; 1 runs in this process).
    scheduler : address of a running Dask scheduler (``tcp://host:8786``) or a
        ``distributed.Client``: the runs go to that cluster instead.
    output : CSV file, written row by row as runs finish; ``stream``: a text stream as well
        (the command line's stdout).
    resume : keep the runs already in ``output`` and run the rest.
    evaluate, columns : a top-level function ``f(rig, t_end) -> dict`` (it must be importable
        by the workers) and its result columns, instead of the experiment's figures of merit.
    t_end : simulated duration (s), default the experiment's.

    Returns the table sorted by run: ``run``, the paths, the figures, ``status``; ``attrs``
    carry the experiment, the design kind, the sampling and seed, and wall-clock numbers.
    Bad input (unknown path, bad spec, a rig whose model lacks a value) raises
    :class:`~vcbmodel.errors.InputError` before anything runs or is written.
    """
    data, rig_path = _rig_input(rig)
    nominal = rig_from_data(data, rig_path)
    if runs is not None:
        if vary:
            raise ValueError("give vary or runs, not both")
        table = pd.DataFrame(list(runs) if not isinstance(runs, pd.DataFrame) else runs).reset_index(drop=True)
        table = table.astype(float)
        kind, varies = "given", []
        if table.empty:
            raise InputError("runs", "runs", "no parameter sets given")
    else:
        varies = parse_varies(vary)
        table = design(varies, samples, seed, sampling)
        kind = "grid" if varies[0].is_grid else "random"
    paths = list(table.columns)
    check_paths(data, paths, rig_path, nominal.experiment)
    if evaluate is None:
        columns = FIGURES[nominal.experiment]
    elif columns is None:
        raise ValueError("a custom evaluate needs its columns")
    columns = tuple(columns)
    # the nominal model must run: a value it needs but the rig lacks is bad input, before the sweep
    # (fields the rig does not give take the first run's value)
    absent = {}
    for p in paths:
        try:
            get_path(data, p)
        except KeyError:
            given = table[p].dropna()
            if len(given):
                absent[p] = float(given.iloc[0])
    model_spec(rig_from_data(with_overrides(data, absent), rig_path) if absent else nominal)
    if workers is not None and (isinstance(workers, bool) or int(workers) != workers or workers < 1):
        raise InputError("--workers", "workers", f"must be a whole number >= 1, got {workers}")
    header = ["run", *paths, *columns, "status"]
    finished = read_finished(output, header, table) if (resume and output and os.path.exists(output)
                                                         and os.path.getsize(output) > 0) else {}
    todo = [i for i in range(1, len(table) + 1) if i not in finished]
    client, own_client = (connect(scheduler) if scheduler is not None else (None, False))
    address = client.scheduler.address if client is not None else None
    n_workers = 1 if not todo else min(int(workers or default_workers()), len(todo))
    where = (f"Dask cluster {address}" if client is not None
             else f"{n_workers} local process{'es' if n_workers > 1 else ''}")
    draw = (f"{SAMPLING[sampling]}, seed {DEFAULT_SEED if seed is None else seed}" if kind == "random"
            else "grid" if kind == "grid" else "given parameter sets")
    name = label or f"sweep {nominal.name}"
    if verbose:
        progress(f"{name}: {len(table)} runs ({draw}), {len(finished)} already in {output}; {len(todo)} to run on {where}"
                 if finished else f"{name}: {len(table)} runs ({draw}) on {where}")

    rows = {run: _typed(r, paths, columns) for run, r in finished.items()}
    f = None
    if output:
        f = open(output, "a" if finished else "w", newline="")
    writer = csv.writer(f, lineterminator="\n") if f else None
    out_writer = csv.writer(stream, lineterminator="\n") if stream is not None else None
    if f and not finished:
        writer.writerow(header)
        f.flush()
    if out_writer:
        out_writer.writerow(header)
        for run in sorted(finished):
            out_writer.writerow([finished[run][k] for k in header])
        stream.flush()

    values_of = table.to_numpy(dtype=float)
    # a given parameter set without a value for a path (NaN) leaves that field at the rig's value
    jobs = ((run, (data, {p: float(v) for p, v in zip(paths, values_of[run - 1]) if not math.isnan(v)}, rig_path,
                   evaluate, t_end)) for run in todo)
    if client is not None:
        runner = _dask(jobs, run_one, client)
    elif n_workers > 1:
        runner = _local_pool(jobs, run_one, n_workers)
    else:
        runner = _serial(jobs, run_one)
    bar = Progress(len(todo), name, verbose)
    every = max(1, len(todo) // 100)
    seconds, failed = [], 0
    t0 = time.perf_counter()
    try:
        for run, values, status, secs in runner:
            line = [str(run), *(_value_text(v) for v in values_of[run - 1]),
                    *(_text(values.get(c)) for c in columns), status]
            for w, s in ((writer, f), (out_writer, stream)):
                if w:
                    w.writerow(line)
                    s.flush()
            rows[run] = _typed(dict(zip(header, line)), paths, columns)
            seconds.append(secs)
            failed += status != "ok"
            # at most about 100 progress lines, and every failure
            bar.verbose = verbose and (status != "ok" or (bar.done + 1) % every == 0 or bar.done + 1 == len(todo))
            bar.step(f"run {run} {status}")
    except KeyboardInterrupt:
        if verbose:
            progress(f"{name}: stopped after {bar.done} of {len(todo)} runs"
                     + (f"; their rows are in {output}: the same command with --resume runs the rest" if output else ""))
        raise
    finally:
        runner.close()
        if f:
            f.close()
        if own_client:
            client.close()
    wall = time.perf_counter() - t0
    if output and os.path.isfile(output) and len(rows) == len(table) and todo:
        _rewrite_in_order(output, header)
    df = pd.DataFrame([rows[r] for r in sorted(rows)], columns=header)
    df.attrs.update({"experiment": nominal.experiment, "rig": rig_path, "design": kind,
                     "sampling": SAMPLING[sampling] if kind == "random" else None,
                     "seed": (DEFAULT_SEED if seed is None else seed) if kind == "random" else None,
                     "workers": None if client is not None else n_workers,
                     "scheduler": address,
                     "runs_done": len(todo), "wall_s": wall, "run_s": seconds, "failed": failed})
    if verbose:
        progress(f"{name}: {len(todo) - failed} ok, {failed} failed in {wall:.1f} s"
                 + (f"; table in {output}" if output else ""))
    return df


def _rewrite_in_order(output, header):
    """Rewrite a complete sweep's file in run order (atomically: a temporary file, then rename)."""
    text = Path(output).read_text()
    reader = csv.reader(io.StringIO(text))
    head = next(reader)
    rows = sorted((r for r in reader if r), key=lambda r: int(r[0]))
    tmp = Path(output).with_name(f".{Path(output).name}.{os.getpid()}.tmp")
    with open(tmp, "w", newline="") as g:
        w = csv.writer(g, lineterminator="\n")
        w.writerow(head)
        w.writerows(rows)
    os.replace(tmp, output)

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

Execution: each run is an independent job that sends only JSON (the run's overrides) and gets
back numbers: the worker loads the rig and builds its own Exudyn system or compiled module
(symbolic user functions do not pickle; exudyn-notes "Sweeps and scale-out"). What the runs share
(the rig's JSON with its data files read in, :func:`.runs.inline_data_files`) goes to each worker
once, and the runs go in chunks of about a second of work (:class:`.executors.Chunker`). Locally a
process pool on all cores (its workers die with the sweep); beyond one machine a Dask
``distributed`` cluster (``scheduler=ADDRESS``: ``dask scheduler`` on one machine, ``dask worker
ADDRESS --nworkers -1 --nthreads 1`` on each), whose every worker is checked before any run
(:func:`.executors.check_workers`). Dask was chosen over Ray by measurement (docs/findings.md,
"Design studies at scale").

Rows are written (and flushed) to the output as runs finish; ``resume=True`` keeps the runs
already in the output (checked against this sweep's design) and runs the rest. When every
run is in, the file is rewritten in run order. An existing output is replaced only with
``force=True``, and a sweep holds a lock on its output while it writes it.

Rooms: :mod:`.design` (the parameter sets), :mod:`.runs` (one run and the checks of the paths),
:mod:`.executors` (where runs go), :mod:`.table` (the file); this module wires them.
"""
from __future__ import annotations

import csv
import math
import os
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TextIO

import pandas as pd

from ...errors import ImpossibleValue, InputError
from ...experiments import experiment_of
from ...experiments.loading import rig_from_data
from ...compiled import BACKEND_NAME
from ...experiments.simulation import simulation_backend
from ...experiments.simulation import model_spec
from ...rig.data import Rig
from ...rig.paths import get_path, with_overrides
from ...rig.reader import read_json
from ..progress import Progress, progress
from .design import DEFAULT_SEED, DIGITS, DISTRIBUTIONS, MAX_RUNS, SAMPLING, Vary, design, parse_vary, parse_varies
from .executors import _dask, _local_pool, _serial, check_workers, connect, default_workers
from .runs import (SweepJob, check_datasheet_used, check_paths, check_used, figures_of_merit, inline_data_files, one_line,
                   run_chunk, run_one)
from .table import (cell_text, check_table_path, fingerprint_line, read_finished, rewrite_in_order, rig_fingerprint, table_lock,
                    typed_row, value_text)

__all__ = ["sweep", "design", "parse_vary", "parse_varies", "Vary", "figures_of_merit", "run_one", "run_chunk",
           "SweepJob", "connect", "check_workers", "inline_data_files", "default_workers",
           "check_paths", "check_used", "one_line", "DEFAULT_SEED", "DIGITS", "DISTRIBUTIONS",
           "MAX_RUNS", "SAMPLING", "get_path", "with_overrides"]


@dataclass
class SweepPlan:
    """A checked sweep, before anything runs: the rig, the parameter sets and the table's columns."""

    data: dict
    rig_path: str
    experiment: str
    name: str
    table: pd.DataFrame  # one row per run, one column per varied path
    kind: str  # grid | random | given
    columns: tuple  # result columns (figures of merit, SI units in their names)
    draw: str  # how the parameter sets were made, for the progress line
    column_units: dict = field(default_factory=dict)
    backend: str = ""  # what runs the simulations (the compiled path where it covers the model, else Exudyn)
    backend_choice: str = "fast"  # the sweep's backend option: fast | exudyn
    shipped: dict | None = None  # the rig's JSON object as the runs get it: its data files read in

    @property
    def paths(self) -> list[str]:
        return list(self.table.columns)

    @property
    def header(self) -> list[str]:
        return ["run", *self.paths, *self.columns, "status"]


def _rig_input(rig):
    """(JSON object, path label) of a rig given as a path, a JSON object or a loaded Rig."""
    if isinstance(rig, Rig):
        return rig.data, rig.path
    if isinstance(rig, dict):
        return rig, "(rig)"
    return read_json(str(rig)), str(rig)


def _design_table(vary, runs, samples, seed, sampling):
    """(table, kind) from ``vary`` texts or given ``runs``."""
    if runs is None:
        varies = parse_varies(vary)
        return design(varies, samples, seed, sampling), ("grid" if varies[0].is_grid else "random")
    if vary:
        raise ValueError("give vary or runs, not both")
    table = pd.DataFrame(list(runs) if not isinstance(runs, pd.DataFrame) else runs).reset_index(drop=True)
    if table.empty:
        raise InputError("runs", "runs", "no parameter sets given")
    return table.astype(float), "given"


def check_no_unit_slip(data: dict, table: pd.DataFrame, rig_path: str | None) -> None:
    """Refuse, before any run, a varied field whose smallest or largest value no mechanism has (the unit
    slips of docs/rig-format.md 3.11: ``--vary cam.mass=9500:9600:2``, grams typed as kg): such a value is
    bad input, not a failed run. Any other value that makes a run's rig invalid stays that run's ``failed``
    row."""
    for path in table.columns:
        given = table[path].dropna()
        for value in {float(given.min()), float(given.max())} if len(given) else ():
            try:
                rig_from_data(with_overrides(data, {path: value}), rig_path)
            except ImpossibleValue as e:
                if e.field == path:
                    raise InputError("--vary", path, e.message) from None
            except InputError:
                pass  # another value that makes this run's rig invalid: its failed row


def plan(rig: str | Path | dict | Rig, vary: Iterable[str | tuple[str, str] | Vary] | dict[str, str] = (), *,
         runs: pd.DataFrame | Sequence[dict[str, float]] | None = None, samples: int | None = None, seed: int | None = None, sampling: str = "lhs",
         evaluate: Callable | None = None, columns: Sequence[str] | None = None, label: str | None = None, backend: str = "fast") -> SweepPlan:
    """Check a sweep before anything runs (bad input raises InputError naming the rig and the path):
    paths that are numeric fields of this rig, read by its model, and a nominal model that runs.

    Parameters
    ----------
    rig, vary, runs, samples, seed, sampling, evaluate, columns, backend : as for :func:`sweep`
        (varied values in the unit of their rig field: SI, e.g. m, kg, N/m).
    label : the sweep's name in progress lines (default ``sweep NAME``).

    Returns
    -------
    SweepPlan
        The rig's JSON object, the parameter sets (one row per run, one column per path, in the
        paths' units) and the result columns (figures of merit, SI units in their names).
    """
    data, rig_path = _rig_input(rig)
    nominal = rig_from_data(data, rig_path)
    table, kind = _design_table(vary, runs, samples, seed, sampling)
    check_paths(data, table.columns, rig_path, nominal.experiment)
    check_no_unit_slip(data, table, rig_path)
    record = experiment_of(nominal.experiment)
    if evaluate is None:
        columns = record.figure_columns
    elif columns is None:
        raise ValueError("a custom evaluate needs its columns")
    # the nominal model must run: a value it needs but the rig lacks is bad input, before the sweep
    # (fields the rig does not give take the first run's value)
    absent = {}
    for p in table.columns:
        try:
            get_path(data, p)
        except KeyError:
            given = table[p].dropna()
            if len(given):
                absent[p] = float(given.iloc[0])
    spec = model_spec(rig_from_data(with_overrides(data, absent), rig_path) if absent else nominal)
    check_used(table.columns, spec.effects, rig_path, nominal.experiment)
    check_datasheet_used(table.columns, nominal, spec.spring_model.kind, rig_path)
    draw = (f"{SAMPLING[sampling]}, seed {DEFAULT_SEED if seed is None else seed}" if kind == "random"
            else "grid" if kind == "grid" else "given parameter sets")
    return SweepPlan(data, rig_path, nominal.experiment, label or f"sweep {nominal.name}", table, kind,
                     tuple(columns), draw, dict(record.figure_units) if evaluate is None else {},
                     simulation_backend(record, spec.spring_model, backend) if evaluate is None else "the evaluation's own",
                     backend, inline_data_files(data, rig_path))


def sweep(rig: str | Path | dict | Rig, vary: Iterable[str | tuple[str, str] | Vary] | dict[str, str] = (), *,  # noqa: PLR0913 (the front door's documented keyword options)
          runs: pd.DataFrame | Sequence[dict[str, float]] | None = None, samples: int | None = None, seed: int | None = None, sampling: str = "lhs",
          workers: int | None = None, scheduler: Any = None, output: str | None = None, stream: TextIO | None = None, resume: bool = False,
          force: bool = False, evaluate: Callable | None = None, columns: Sequence[str] | None = None, t_end: float | None = None,
          verbose: bool = True, label: str | None = None, backend: str = "fast") -> pd.DataFrame:
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
    force : replace an existing ``output`` (without it, or ``resume``, an existing file is refused).
        While a sweep writes ``output`` it holds a lock on it: a second sweep of the same file is
        refused at once.
    evaluate, columns : a top-level function ``f(rig, t_end) -> dict`` (it must be importable
        by the workers) and its result columns, instead of the experiment's figures of merit.
    t_end : simulated duration (s), default the experiment's.
    backend : ``fast`` (the compiled path where it covers the model, else Exudyn; default) or
        ``exudyn`` (every run on the Exudyn model); ``attrs["simulated_with"]`` names what ran.

    Returns
    -------
    pandas.DataFrame
        The table sorted by run: ``run``, the paths (in their rig fields' units), the figures
        (SI units in their column names: ``closing_time_s``, ...), ``status`` (``ok``,
        ``not_closed`` for a breaker that never closed, or ``failed: reason``); ``attrs`` carry the
        experiment, the design kind, the sampling and seed, and wall-clock numbers (s).

    Bad input
    (unknown path, a path the model does not read, bad spec, a rig whose model lacks a value, an
    existing output without ``force``, a table another sweep is writing) raises
    :class:`~vcbmodel.errors.InputError` before anything runs or is written.
    """
    if backend not in ("fast", "exudyn"):
        raise InputError("backend", "backend", f"must be fast or exudyn, got {backend!r}")
    p = plan(rig, vary, runs=runs, samples=samples, seed=seed, sampling=sampling, evaluate=evaluate,
             columns=columns, label=label, backend=backend)
    _check_where(p, workers, output, resume, force)
    with table_lock(output):
        has_rows = resume and output and os.path.exists(output) and os.path.getsize(output) > 0
        stated = _stated(p, t_end, evaluate)
        finished = read_finished(output, p.header, p.table, rig_fingerprint(p.data, p.rig_path, stated)) if has_rows else {}
        client, own_client = (connect(scheduler) if scheduler is not None else (None, False))
        try:
            if client is not None:
                check_workers(client, str(scheduler if own_client else client.scheduler.address),
                              evaluate is None and p.backend == BACKEND_NAME)
            return _execute(p, finished, client, workers, output, stream, evaluate, (t_end, stated), verbose, seed, sampling)
        finally:
            if own_client:
                client.close()


def _check_where(p: SweepPlan, workers: int | None, output: str | None, resume: bool, force: bool) -> None:
    """Refuse (InputError) a worker count that is not a whole number >= 1, an output that is an input of the
    rig (:func:`.table.check_table_path`), and an existing output without ``force`` or ``resume``."""
    if workers is not None and (isinstance(workers, bool) or int(workers) != workers or workers < 1):
        raise InputError("--workers", "workers", f"must be a whole number >= 1, got {workers}")
    check_table_path(output, p.rig_path, p.data)
    if output and not (resume or force) and os.path.isfile(output) and os.path.getsize(output) > 0:
        raise InputError(output, "output", "exists already: give --force to replace it (or --resume to continue it)")


def _stated(p: SweepPlan, t_end: float | None, evaluate: Callable | None) -> float | None:
    """The duration (s) a table's fingerprint hashes: None for the experiment's own, also when it is
    spelt out (``--t-end 0.055`` on a closing runs the very runs no ``--t-end`` does, so either resumes
    the other's table); a custom ``evaluate`` decides its own default, so its ``t_end`` is kept as given."""
    if t_end is None or evaluate is not None:
        return t_end
    return None if float(t_end) == float(experiment_of(p.experiment).default_duration) else t_end


def _announce(p, finished, todo, where, output, verbose):
    if verbose:
        progress((f"{p.name}: {len(p.table)} runs ({p.draw}), {len(finished)} already in {output}; {len(todo)} to run "
                  f"on {where}" if finished else f"{p.name}: {len(p.table)} runs ({p.draw}) on {where}")
                 + f"; simulated with {p.backend}")


def _open_outputs(p, finished, output, stream, stated_t_end):
    """The table's file (appended to when resuming) and the stream: csv writers, headers written."""
    f = open(output, "a" if finished else "w", newline="") if output else None
    sinks = []
    if f:
        if not finished:
            f.write(fingerprint_line(rig_fingerprint(p.data, p.rig_path, stated_t_end)))
            csv.writer(f, lineterminator="\n").writerow(p.header)
            f.flush()
        sinks.append((csv.writer(f, lineterminator="\n"), f))
    if stream is not None:
        w = csv.writer(stream, lineterminator="\n")
        w.writerow(p.header)
        for run in sorted(finished):
            w.writerow([finished[run][k] for k in p.header])
        stream.flush()
        sinks.append((w, stream))
    return f, sinks


def _runner(p, todo, client, n_workers, evaluate, t_end):
    values_of = p.table.to_numpy(dtype=float)
    # a given parameter set without a value for a path (NaN) leaves that field at the rig's value
    jobs = [(run, {k: float(v) for k, v in zip(p.paths, values_of[run - 1]) if not math.isnan(v)}) for run in todo]
    job = SweepJob(p.shipped if p.shipped is not None else p.data, p.rig_path, evaluate, t_end, p.backend_choice)
    if client is not None:
        return _dask(job, jobs, client)
    if n_workers > 1:
        return _local_pool(job, jobs, n_workers, exudyn=evaluate is not None or p.backend != BACKEND_NAME)
    return _serial(job, jobs)


def _execute(p, finished, client, workers, output, stream, evaluate, durations, verbose, seed, sampling):
    """Run what is not in the table yet, writing each row as it finishes; the table in run order.
    ``durations``: (the runs' ``t_end``, the one the table's fingerprint states: :func:`_stated`)."""
    t_end, stated = durations
    todo = [i for i in range(1, len(p.table) + 1) if i not in finished]
    address = client.scheduler.address if client is not None else None
    n_workers = 1 if not todo else min(int(workers or default_workers()), len(todo))
    where = (f"Dask cluster {address}" if client is not None
             else f"{n_workers} local process{'es' if n_workers > 1 else ''}")
    _announce(p, finished, todo, where, output, verbose)
    rows = {run: typed_row(r, p.paths, p.columns) for run, r in finished.items()}
    f, sinks = _open_outputs(p, finished, output, stream, stated)
    runner = _runner(p, todo, client, n_workers, evaluate, t_end)
    t0 = time.perf_counter()
    try:
        seconds, counts = _write_rows(p, runner, todo, sinks, rows, output, verbose)
    finally:
        runner.close()
        if f:
            f.close()
    wall = time.perf_counter() - t0
    if output and os.path.isfile(output) and len(rows) == len(p.table) and todo:
        rewrite_in_order(output)
    df = pd.DataFrame([rows[r] for r in sorted(rows)], columns=p.header)
    df.attrs.update({"experiment": p.experiment, "rig": p.rig_path, "design": p.kind,
                     "sampling": SAMPLING[sampling] if p.kind == "random" else None,
                     "seed": (DEFAULT_SEED if seed is None else seed) if p.kind == "random" else None,
                     "workers": None if client is not None else n_workers, "scheduler": address,
                     "runs_done": len(todo), "wall_s": wall, "run_s": seconds, "failed": counts["failed"],
                     "not_closed": counts.get("not_closed", 0), "column_units": p.column_units, "simulated_with": p.backend})
    if verbose:
        ok = len(todo) - sum(counts.values())
        apart = "".join(f"{counts[name]} {name.replace('_', ' ')}, " for name in counts if name != "failed")
        progress(f"{p.name}: {ok} ok, {apart}{counts['failed']} failed in {wall:.1f} s"
                 + (f"; table in {output}" if output else ""))
    return df


def _write_rows(p, runner, todo, sinks, rows, output, verbose) -> tuple[list[float], dict[str, int]]:
    """Each finished run's row to the sinks (flushed) and into ``rows`` ({run: typed row}); a progress line
    for about every hundredth run and every run that is not ok. Returns the runs' seconds and the count of
    each status besides ok (``failed`` first, then the experiment's own: a closing's ``not_closed``)."""
    values_of = p.table.to_numpy(dtype=float)
    bar = Progress(len(todo), p.name, verbose)
    every = max(1, len(todo) // 100)
    # the statuses this experiment's runs can end in besides ok and failed (a closing: not_closed)
    missing = [status for _, status in experiment_of(p.experiment).missing_means]
    seconds, counts = [], {"failed": 0, **dict.fromkeys(missing, 0)}
    try:
        for run, values, status, secs in runner:
            line = [str(run), *(value_text(v) for v in values_of[run - 1]),
                    *(cell_text(values.get(c)) for c in p.columns), status]
            for w, s in sinks:
                w.writerow(line)
                s.flush()
            rows[run] = typed_row(dict(zip(p.header, line)), p.paths, p.columns)
            seconds.append(secs)
            counts["failed"] += status.startswith("failed")
            for name in missing:
                counts[name] += status == name
            bar.verbose = verbose and (status != "ok" or (bar.done + 1) % every == 0 or bar.done + 1 == len(todo))
            bar.step(f"run {run} {status}")
    except KeyboardInterrupt:
        if verbose:
            progress(f"{p.name}: stopped after {bar.done} of {len(todo)} runs"
                     + (f"; their rows are in {output}: the same command with --resume runs the rest" if output else ""))
        raise
    return seconds, counts

"""The ``vcbmodel`` command (docs/cli.md): simulate, identify, diagnose, sweep, plot.

Exit status: 0 success; 2 bad input (one line on stderr naming file and field, nothing
written); 1 the simulation or fit failed (one line saying why). Output paths are checked
before any work starts.
"""
from __future__ import annotations

import argparse
import io
import json
import logging
import math
import os
import shlex
import signal
import sys
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from dataclasses import replace
from typing import TYPE_CHECKING

from .. import __version__
from ..analysis.diagnose import diagnose
from ..analysis.identify import identify
from ..analysis.sweep import DEFAULT_SEED, SAMPLING, sweep
from ..errors import InputError, SimulationError
from ..experiments import experiment_of
from ..experiments.report import Report, lines_report, report_json, report_text
from ..experiments.loading import load_record, load_rig, require_experiment, require_noise, rig_of
from ..experiments.sequence import check_sequence, parse_sequence, run_sequence, sequence_failures, sequence_lines
from ..experiments.run_checks import require_motion
from ..experiments.simulation import compiled_path_has, model_spec, output_times, simulate
from ..model.choice import choose, parse_effects_option
from .outputs import check_distinct, check_output, check_table_name, is_regular_or_absent, protected_inputs, write_file
from .templates import TEMPLATES, explain, template
from .closing_plot import plot_closing
from .sequence_plot import plot_sequence
from .plots import plot_diagnosis, plot_simulation, supported_image_formats
from .table_plot import plot_fit, plot_sweep

if TYPE_CHECKING:
    from ..model.result import SimulationResult
    from ..rig.data import Rig


@contextmanager
def results_only_on_stdout() -> Iterator[None]:
    """While a fit runs, send file descriptor 1 to stderr: a native library's messages (LAPACK's
    "On entry to DLASCL ...") cannot then spoil the JSON or CSV a command prints afterwards."""
    try:
        sys.stdout.flush()
        saved = os.dup(1)
    except (OSError, ValueError):
        yield
        return
    os.dup2(2, 1)
    try:
        yield
    finally:
        os.dup2(saved, 1)
        os.close(saved)


log = logging.getLogger("vcbmodel")


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse's own errors: one line, exit 2
        print(f"vcbmodel: {message}", file=sys.stderr)
        raise SystemExit(2)


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="vcbmodel", description="Spring-driven cam dynamics of vacuum circuit breakers (Exudyn). "
                "Docs: docs/cli.md and docs/rig-format.md in the repository.")
    p.add_argument("--version", action="version", version=f"vcbmodel {__version__}")
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("-q", "--quiet", action="store_true", help="no progress lines on stderr (warnings and errors only)")
    sub = p.add_subparsers(dest="command", parser_class=_Parser)

    s = sub.add_parser("simulate", parents=[common], help="simulate a rig's experiment and write its measurement channels")
    s.add_argument("rig", help="rig file NAME.rig.json")
    s.add_argument("--spring-model", help="massless | lumped-N[:exact|paper|uniform] | ancf (overrides the rig's model)")
    s.add_argument("--effects", help="comma-separated effect names (overrides the rig's model)")
    s.add_argument("--t-end", type=float, help="simulated duration in s (default: the experiment's usual duration)")
    s.add_argument("-o", "--output", help="output CSV (default: stdout)")
    s.add_argument("--plot", help="also draw the run (a closing: travel, speed, contact timing, bounces and energy per "
                   "pole, as a breaker analyser shows it); the format by the file's suffix")
    s.add_argument("--force", action="store_true", help="replace the output (and plot) file if it exists")
    s.add_argument("--json", action="store_true", help="print the summary as one JSON object (needs -o for the CSV)")
    s.add_argument("--backend", choices=("exudyn", "compiled", "fast"), default="exudyn",
                   help="exudyn (the model, default); compiled (the same laws traced to C: massless and lumped "
                        "springs); fast (compiled where it covers the model, else exudyn)")
    s.add_argument("--sequence", help="run an operating sequence of a breaker instead (C, O, CO, O-0.3s-CO, ...): "
                   "figures per operation (no CSV; --json for JSON; --plot draws each operation as an analyser shows it)")

    c = sub.add_parser("check", parents=[common], help="validate a rig and say what simulate would run, without solving")
    c.add_argument("rig", help="rig file NAME.rig.json")

    n = sub.add_parser("init", parents=[common], help="write a commented rig file to start from (it simulates as written)")
    n.add_argument("kind", choices=tuple(TEMPLATES), help="experiment kind")
    n.add_argument("-o", "--output", help="rig file to write (default: stdout)")
    n.add_argument("--force", action="store_true", help="replace the output file if it exists")

    i = sub.add_parser("identify", parents=[common], help="fit the shaft friction law to pendulum measurements (paper section 2.2)")
    i.add_argument("measurements", nargs="+", help="pendulum measurement files NAME.csv")
    i.add_argument("--rig", help="rig file (default: each measurement's sibling NAME.rig.json)")
    i.add_argument("--law", choices=("hybrid", "stick-slip"), default="hybrid",
                   help="hybrid: Coulomb + Stribeck + viscous; stick-slip: Coulomb with stick band only")
    i.add_argument("--json", action="store_true", help="print one JSON object")
    i.add_argument("--plot", help="write a figure of the fit (measured and fitted, residual, per record); the format "
                   "by the file's suffix")
    i.add_argument("--force", action="store_true", help="replace the --plot file if it exists")

    d = sub.add_parser("diagnose", parents=[common], help="find the effect the rig's model is missing")
    d.add_argument("measurement", help="measurement file NAME.csv")
    d.add_argument("--rig", help="rig file (default: the sibling NAME.rig.json)")
    d.add_argument("--json", action="store_true", help="print one JSON object")
    d.add_argument("--plot", help="write a figure of the diagnosis; the format by the file's suffix: "
                   + ", ".join(supported_image_formats()))
    d.add_argument("--force", action="store_true", help="replace the --plot file if it exists")
    d.add_argument("--processes", type=int, default=2, help="parallel candidate fits (default 2)")
    d.add_argument("--held-out", action="append", default=[], metavar="MEAS.csv",
                   help="another record of the same rig (its sibling NAME.rig.json), predicted with the values fitted "
                   "on MEAS.csv, not fitted; explained requires it at its noise (repeatable)")

    w = sub.add_parser("sweep", parents=[common], help="run the rig's experiment over a grid or random draws of rig fields: one row per run",
                       description="Runs the rig's experiment (its model) once per parameter set and writes one CSV row "
                       "per run: run, each varied PATH, the experiment's figures of merit, status. Grids LO:HI:N make the "
                       f"full product; distributions give --samples draws by {SAMPLING['lhs']}, seeded (default seed "
                       f"{DEFAULT_SEED}). Rows are written as runs finish; --resume skips runs already in -o. Runs go "
                       "to local processes, or with --scheduler to a Dask cluster (docs/cli.md: how to start one).")
    w.add_argument("rig", help="rig file NAME.rig.json")
    w.add_argument("--vary", action="append", required=True, metavar="PATH=SPEC",
                   help="dotted rig field (friction.mu_k, breaker.poles.gap_offsets.1, ...) = LO:HI:N (grid), "
                   "normal:MEAN:SD or uniform:LO:HI (random draws); repeat for several fields")
    w.add_argument("--samples", type=int, metavar="N", help="number of random draws (distributions only)")
    w.add_argument("--seed", type=int, metavar="S", help=f"seed of the random draws (default {DEFAULT_SEED}: repeatable)")
    where = w.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, metavar="N", help="local processes (default: all cores)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="address of a running Dask cluster's scheduler (tcp://HOST:8786) to run on instead")
    w.add_argument("-o", "--output", metavar="OUT.csv", help="output CSV, written as runs finish (default: stdout)")
    w.add_argument("--resume", action="store_true", help="keep the runs already in -o and run the rest")
    w.add_argument("--force", action="store_true", help="replace -o if it exists (without it an existing table is refused)")
    w.add_argument("--backend", choices=("fast", "exudyn"), default="fast",
                   help="fast: the compiled path where it covers the model, else Exudyn (default); exudyn: every run on Exudyn")
    w.add_argument("--t-end", type=float, help="simulated duration of each run in s (default: the experiment's usual "
                   "duration; a closing whose cam latches later needs a longer one for its kinetic margin)")

    pl = sub.add_parser("plot", parents=[common], help="draw a sweep's table: figures of merit against a varied field",
                        description="Draws figures of merit of a sweep's table (vcbmodel sweep -o) against one varied "
                        "rig field: a line per combination of the other varied fields (a grid), else points; each axis "
                        "in the unit an engineer reads (ms, mm, kN, deg), from the column's name.")
    pl.add_argument("table", help="a sweep's table OUT.csv")
    pl.add_argument("--x", required=True, metavar="PATH", help="the varied rig field on the x axis (a column of the table)")
    pl.add_argument("--y", required=True, action="append", metavar="FIGURE",
                    help="a figure of merit (closing_time_s, bounce_duration_s, ...); repeat for one panel each")
    pl.add_argument("-o", "--output", help="image file; the format by its suffix (default: the table's name, .png)")
    pl.add_argument("--force", action="store_true", help="replace the output if it exists")
    return p


def envelope(rig: Rig, unit: str) -> dict:
    """What every ``--json`` output carries besides its results."""
    return {"vcbmodel_version": __version__, "experiment": rig.experiment, "rig_name": rig.name,
            "rig": rig.path, "units": unit}


def cmd_simulate(args: argparse.Namespace) -> int:
    rig = load_rig(args.rig)
    if args.sequence is not None:
        return simulate_sequence(rig, args)
    record = experiment_of(rig.experiment)
    effects = None if args.effects is None else parse_effects_option(args.effects, record)
    try:  # the spring model (the rig's unless --spring-model) decides spring_mass, whatever --effects says
        choice = choose(rig, effects, args.spring_model or rig.model.spring_model)
    except ValueError as e:
        raise InputError("--spring-model", "spring_model", str(e)) from None
    rig = replace(rig, model=choice)  # the run's model, decided once: every layer below reads it
    spring_model = choice.spring_model
    if not record.has_closing_spring and not spring_model.is_massless:
        raise InputError("--spring-model", "spring_model", f"a {rig.experiment} test has no closing spring")
    check_duration(rig, args.t_end)
    if args.json and not args.output:
        raise InputError("--json", "output", "needs -o OUT.csv (stdout carries the JSON, so the CSV goes to a file)")
    check_distinct(args.plot, args.output, "--plot", "-o")
    inputs = protected_inputs(args.rig, rig.data)
    check_output(args.output, "-o", inputs=inputs, force=args.force)
    check_table_name(args.output, "-o", supported_image_formats(), "--plot FILE.{suffix}")
    check_output(args.plot, "--plot", inputs=inputs, force=args.force, formats=supported_image_formats())
    t_end = args.t_end or record.default_duration
    model_spec(rig)  # a value the model needs but the rig lacks: bad input, first
    if args.backend == "compiled" and not compiled_path_has(record, spring_model):
        raise InputError("--backend compiled", "--spring-model", f"the compiled path does not cover the "
                         f"{spring_model.label} spring (massless and lumped springs only): use --backend exudyn or fast")
    log.info("simulate %s: %s, %g s of %s", rig.name, spring_model.label, t_end, rig.experiment)
    # the figures of merit from every step (as sweeps and studies compute them); the file at the sensor's rate
    full = simulate(rig, t_end=t_end, backend=args.backend)
    require_motion(full, rig)  # a cam that never moved: said plainly, not a summary of nothing
    result = full.resample(output_times(rig, t_end))
    channels = record.record_channels(result, rig)
    spec = result.spec
    buf = io.StringIO()
    buf.write(f"# vcbmodel {__version__} simulate: {rig.name}; effects {','.join(spec.effects) or '(none)'}; "
              f"spring model {spec.spring_model.label}; solved by {result.info['backend']}; SIMULATED, not measured\n")
    buf.write("# " + ", ".join(f"{name} in {unit}" for name, (_, unit) in channels.items())
              + f", t in s, {record.sample_rate:g} samples/s\n")
    buf.write("t," + ",".join(channels) + "\n")
    columns = [values for values, _ in channels.values()]
    for k, t in enumerate(result.t):
        buf.write(f"{t:.7f}," + ",".join(f"{c[k]:.9g}" for c in columns) + "\n")
    report = summary_report(record.summary(full, rig), f"{rig.name}: {rig.experiment}, {spec.spring_model.label} "
                            f"(solved by {result.info['backend']}; SIMULATED)")
    summary = report_text(report)
    if args.output:
        write_file(args.output, buf.getvalue())
        # the file holds the data: the summary is the command's result on stdout
        print(json.dumps(simulate_json(rig, full, report, args.output)) if args.json else summary)
    else:
        sys.stdout.write(buf.getvalue())
        print(summary, file=sys.stderr)
    if args.plot and rig.breaker is not None:  # a closing: the analyser's view, at the solver's step
        plot_closing(full, rig, args.plot, f"{rig.name}: {spec.spring_model.label}", report)
    elif args.plot:
        plot_simulation(result, channels, args.plot, f"{rig.name}: {spec.spring_model.label}")
    return verdict_status(report.failures())


def verdict_status(failures: list[str]) -> int:
    """The exit status of a run judged against its limits (docs/cli.md): 0 when nothing fails; 1 when a
    limit fails or the closing does, with one line on stderr naming what fails. Called once every output
    is written: the report and files stand, the record of why."""
    if not failures:
        return 0
    print(f"vcbmodel: the breaker fails: {'; '.join(failures)} (report and outputs written)", file=sys.stderr)
    return 1


def simulate_sequence(rig: Rig, args: argparse.Namespace) -> int:
    """``simulate --sequence``: the operations' figures (:mod:`vcbmodel.experiments.sequence`), as
    text or one JSON object; options that shape one run's CSV are refused."""
    for option, value in (("-o", args.output), ("--t-end", args.t_end),
                          ("--spring-model", args.spring_model), ("--effects", args.effects)):
        if value is not None:
            raise InputError(option, "--sequence", "a sequence reports figures per operation: it writes no CSV "
                             "and runs the rig's own model and run lengths; leave this option out")
    if rig.experiment != "vcb_closing":
        raise InputError(rig.path, "experiment", f"--sequence operates a breaker (vcb_closing), not a {rig.experiment}")
    check_output(args.plot, "--plot", inputs=protected_inputs(args.rig, rig.data), force=args.force,
                 formats=supported_image_formats())
    check_sequence(rig, parse_sequence(args.sequence))  # bad input: one line, before any progress line
    log.info("simulate %s: sequence %s", rig.name, args.sequence)
    results = []
    report = run_sequence(rig, args.sequence, backend=args.backend, results=results)
    failures = sequence_failures(report)
    if args.json:
        print(json.dumps({**envelope(rig, {"*_s": "s", "*_m": "m", "*_m_s": "m/s", "*_J": "J"}), **_plain(report),
                          "fails": bool(failures)}))
    else:
        print("\n".join(sequence_lines(report)))
    if args.plot:  # each operation as an analyser shows it, at the solver's step
        plot_sequence(report, results, rig, args.plot, rig.name)
    return verdict_status(failures)


def _plain(value):
    """A figure as JSON has it: NaN as null, numpy numbers as Python's, containers element by element."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if hasattr(value, "item"):
        value = value.item()
    return None if isinstance(value, float) and not math.isfinite(value) else value


def summary_report(summary: Sequence[tuple] | Report, title: str) -> Report:
    """The experiment's summary (lines or a report) as a report with ``title``."""
    return replace(summary if isinstance(summary, Report) else lines_report("", summary), title=title)


def simulate_json(rig: Rig, result: SimulationResult, report: Report, output: str) -> dict:
    """``simulate --json``: the report (:func:`vcbmodel.experiments.report.report_json`: the whole run's
    figures as ``summary`` [{what, value, unit}] in the units the text shows, null for what did not
    happen in the run; a closing's ``poles`` with each figure against its limit, ``limits`` and
    ``verdict``; the ``notes``) and the experiment's figures of merit (SI units in their names), with
    the envelope."""
    body = _plain(report_json(report))
    units = {row["what"]: row["unit"] for row in body["summary"]}
    return {**envelope(rig, units), "output": output,
            "spring_model": result.spec.spring_model.label, "effects": list(result.spec.effects),
            "backend": result.info["backend"], "end_s": float(result.t[-1]), **body,
            "figures_of_merit": _plain(experiment_of(rig.experiment).figures_of_merit(result, rig))}


def cmd_check(args: argparse.Namespace) -> int:
    print("\n".join(explain(load_rig(args.rig))))
    return 0


def cmd_init(args: argparse.Namespace) -> int:
    if args.output and not str(args.output).endswith(".json") and is_regular_or_absent(args.output):
        raise InputError(args.output, "-o", "a rig file is NAME.rig.json: give a name ending in .json (a template "
                         "written over a .csv would replace a record or a cam's points)")
    check_output(args.output, "-o", force=args.force)
    text = template(args.kind)
    if args.output:
        write_file(args.output, text)
        log.info("init: wrote %s (simulate it with: vcbmodel simulate %s)", args.output, shlex.quote(str(args.output)))
    else:
        sys.stdout.write(text)
    return 0


def cmd_identify(args: argparse.Namespace) -> int:
    rigs = [rig_of(m, args.rig) for m in args.measurements]
    for rig in rigs:
        require_experiment(rig, "pendulum", "identify")
    check_output(args.plot, "--plot", inputs=tuple(args.measurements) + tuple(r.path for r in rigs), force=args.force,
                 formats=supported_image_formats())
    pairs = [(rig, load_record(m, rig)) for m, rig in zip(args.measurements, rigs)]
    for rig, meas in pairs:
        require_noise(meas, rig)
    with results_only_on_stdout():
        result = identify(pairs, law=args.law)
        if args.plot:
            plot_fit(result, args.plot)
    if result.warning:
        print(f"vcbmodel: warning: {result.warning}", file=sys.stderr)
    if args.json:
        report = result.to_json()
        print(json.dumps({**envelope(pairs[0][0], report.pop("units")), **report}))
    else:
        print(result.report())
    return 0


def cmd_diagnose(args: argparse.Namespace) -> int:
    rig = rig_of(args.measurement, args.rig)
    others = [rig_of(path, None) for path in args.held_out]
    for other in others:  # records of the same rig: the same experiment
        require_experiment(other, rig.experiment, "diagnose --held-out")
    check_output(args.plot, "--plot", inputs=protected_inputs(rig.path, rig.data, (args.measurement, *args.held_out)), force=args.force,
                 formats=supported_image_formats())
    meas = load_record(args.measurement, rig)  # the records once the command is known to be sound
    held_out = [(other, load_record(path, other)) for path, other in zip(args.held_out, others)]
    for record_rig, record in ((rig, meas), *held_out):
        require_noise(record, record_rig)
    with results_only_on_stdout():
        d = diagnose(rig, meas, processes=max(1, args.processes), held_out=held_out)
        if args.plot:
            plot_diagnosis(d, args.plot)
    if args.json:
        report = d.to_json()
        units = {"rms": d.unit, "noise_estimate": d.unit, "window": "s", "release_time": "s", "initial_angle": "rad",
                 "sensor_offset": d.unit, "sensor_gain": "-", "noise_correlation": "-", "timing": "s",
                 **{f"fitted.{name}": unit for name, unit in report.pop("fitted_units").items()}}
        print(json.dumps({**envelope(rig, units), **report}, default=float))
    else:
        print(d.report())
    return 0


def check_duration(rig, t_end: float | None) -> None:
    """``--t-end`` (s), when given: a positive number the rig's experiment can run (bad input otherwise)."""
    if t_end is None:
        return
    if not (math.isfinite(t_end) and t_end > 0):
        raise InputError("--t-end", "t_end", "must be a positive number of seconds")
    experiment_of(rig.experiment).check_duration(t_end, "--t-end", "t_end")


def cmd_sweep(args: argparse.Namespace) -> int:
    if args.resume and not args.output:
        raise InputError("--resume", "output", "needs -o OUT.csv (the file to resume)")
    rig = load_rig(args.rig)  # a fault first, and the rig's unusual values said once (not by every run)
    check_duration(rig, args.t_end)
    check_output(args.output, "-o", inputs=protected_inputs(args.rig, rig.data), force=args.force, keep=args.resume,
                 resumable=True)
    check_table_name(args.output, "-o", supported_image_formats(), "vcbmodel plot TABLE.csv -o FILE.{suffix}")
    table = sweep(args.rig, args.vary, samples=args.samples, seed=args.seed, workers=args.workers,
                  scheduler=args.scheduler, output=args.output, stream=None if args.output else sys.stdout,
                  resume=args.resume, force=args.force, backend=args.backend, t_end=args.t_end)
    require_a_result(table, args.output)
    return 0


def require_a_result(table, output: str | None) -> None:
    """A sweep none of whose runs gave a result (every row ``failed: reason``) is a failed simulation:
    a SimulationError naming how many failed and the first reason (exit status 1). Its table is written
    all the same, as the record of why. A ``not_closed`` row is a result (the breaker did not close in
    the simulated time, as ``simulate`` reports it with status 0), so one such row, or one ``ok``, keeps
    the sweep a success. Judged on the whole table, rows a ``--resume`` kept included."""
    status = table["status"].astype(str)
    failed = status.str.startswith("failed")
    if len(table) and not failed.all():
        return
    if not len(table):
        raise SimulationError("the sweep ran no run")
    first = table.loc[failed.idxmax()]
    where = f"the table {output}" if output else "the table (stdout)"
    raise SimulationError(f"every run of the sweep failed ({int(failed.sum())} of {len(table)}); the first, run "
                          f"{int(first['run'])}: {status[failed.idxmax()][len('failed: '):]}; {where} gives each run's reason")


def cmd_plot(args: argparse.Namespace) -> int:
    output = args.output or os.path.splitext(args.table)[0] + ".png"
    check_output(output, "-o", inputs=(args.table,), force=args.force, formats=supported_image_formats())
    plot_sweep(args.table, args.x, args.y, output)
    log.info("plot: wrote %s", output)
    return 0


COMMANDS = {"check": cmd_check, "init": cmd_init, "simulate": cmd_simulate, "identify": cmd_identify, "diagnose": cmd_diagnose, "sweep": cmd_sweep,
            "plot": cmd_plot}


class Terminated(KeyboardInterrupt):
    """SIGTERM (``timeout``, a batch system): handled like Ctrl-C, so workers stop and files close."""


def _on_sigterm(signum, frame):
    raise Terminated()


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 0
    previous = signal.signal(signal.SIGTERM, _on_sigterm)
    handler = _log_to_stderr(getattr(args, "quiet", False))
    try:
        status = COMMANDS[args.command](args)
        sys.stdout.flush()
        return status
    except InputError as e:
        print(f"vcbmodel: bad input: {e}", file=sys.stderr)
        return 2
    except SimulationError as e:
        print(f"vcbmodel: simulation failed: {e}", file=sys.stderr)
        return 1
    except Terminated:
        print("vcbmodel: stopped (SIGTERM)", file=sys.stderr)
        return 128 + signal.SIGTERM
    except KeyboardInterrupt:
        print("vcbmodel: interrupted", file=sys.stderr)
        return 1
    except OSError as e:  # writing an output failed (a full disk, a closed pipe): nothing half-written is kept
        _quiet_stdout()
        where = e.filename or "stdout"
        print(f"vcbmodel: cannot write {where}: {e.strerror or e}", file=sys.stderr)
        return 1
    finally:
        signal.signal(signal.SIGTERM, previous)
        logging.getLogger("vcbmodel").removeHandler(handler)


def _log_to_stderr(quiet):
    """The library logs progress on the ``vcbmodel`` logger; the command line shows it on stderr."""
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter("%(message)s"))
    logger = logging.getLogger("vcbmodel")
    logger.addHandler(handler)
    logger.setLevel(logging.WARNING if quiet else logging.INFO)
    logger.propagate = False
    return handler


def _quiet_stdout():
    """After stdout failed (``> /dev/full``), keep Python's exit from reporting it a second time."""
    try:
        sys.stdout = open(os.devnull, "w")
    except OSError:
        pass


if __name__ == "__main__":
    sys.exit(main())

"""The ``vcbmodel`` command (spec cli.md): simulate, identify, diagnose.

Exit status: 0 success; 2 bad input (one line on stderr naming file and field, nothing
written); 1 the simulation or fit failed (one line saying why).
"""
from __future__ import annotations

import argparse
import io
import json
import math
import os
import sys

from .errors import InputError, SimulationError


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # argparse's own errors: one line, exit 2
        print(f"vcbmodel: {message}", file=sys.stderr)
        raise SystemExit(2)


def build_parser():
    p = _Parser(prog="vcbmodel", description="Spring-driven cam dynamics of vacuum circuit breakers (Exudyn).")
    sub = p.add_subparsers(dest="command", required=True, parser_class=_Parser)

    s = sub.add_parser("simulate", help="simulate a rig's experiment and write its measurement channels")
    s.add_argument("rig", help="rig file NAME.rig.json")
    s.add_argument("--spring-model", help="massless | lumped-N | ancf (overrides the rig's model)")
    s.add_argument("--effects", help="comma-separated effect names (overrides the rig's model)")
    s.add_argument("--t-end", type=float, help="simulated duration in s (default 6 s pendulum, 35 ms cam drop)")
    s.add_argument("-o", "--output", help="output CSV (default: stdout)")

    i = sub.add_parser("identify", help="fit the shaft friction law to pendulum measurements (paper section 2.2)")
    i.add_argument("measurements", nargs="+", help="pendulum measurement files NAME.csv")
    i.add_argument("--rig", help="rig file (default: each measurement's sibling NAME.rig.json)")
    i.add_argument("--law", choices=("hybrid", "stick-slip"), default="hybrid",
                   help="hybrid: Coulomb + Stribeck + viscous; stick-slip: Coulomb with stick band only")
    i.add_argument("--json", action="store_true", help="print one JSON object")

    d = sub.add_parser("diagnose", help="find the effect the rig's model is missing")
    d.add_argument("measurement", help="measurement file NAME.csv")
    d.add_argument("--rig", help="rig file (default: the sibling NAME.rig.json)")
    d.add_argument("--json", action="store_true", help="print one JSON object")
    d.add_argument("--plot", help="write a figure (PNG) of the diagnosis")
    d.add_argument("--processes", type=int, default=2, help="parallel candidate fits (default 2)")
    return p


def _check_output(path, argname):
    """Refuse an output path we cannot write, before any work (nothing is written on error)."""
    if path is None:
        return
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InputError(path, argname, "the folder does not exist")


def _write_csv(result, rig, path):
    from .rig import CHANNEL_OF_EXPERIMENT

    name = CHANNEL_OF_EXPERIMENT[rig.experiment]
    buf = io.StringIO()
    buf.write(f"# vcbmodel simulate: {rig.name}; effects {','.join(result.spec_effects)}; "
              f"spring model {result.spec.spring_model}; SIMULATED, not measured\n")
    buf.write(f"t,{name}\n")
    for t, y in zip(result.t, result.angle):
        buf.write(f"{t:.7f},{y:.9f}\n")
    if path:
        with open(path, "w") as f:
            f.write(buf.getvalue())
    else:
        sys.stdout.write(buf.getvalue())


def cmd_simulate(args):
    from .rig import check_effects, load_rig, valid_spring_model
    from .runner import simulate

    rig = load_rig(args.rig)
    effects = list(rig.model.effects)
    if args.effects is not None:
        effects = list(check_effects([e for e in args.effects.split(",") if e.strip()], "--effects"))
    spring_model = args.spring_model or rig.model.spring_model
    if not valid_spring_model(spring_model):
        raise InputError("--spring-model", "spring_model", f"must be massless, lumped-N or ancf, got {spring_model!r}")
    if rig.experiment == "pendulum" and spring_model != "massless":
        raise InputError("--spring-model", "spring_model", "a pendulum test has no closing spring")
    # the spec: spring_mass is listed exactly when the spring model is not massless
    effects = [e for e in effects if e != "spring_mass"] + (["spring_mass"] if spring_model != "massless" else [])
    if args.t_end is not None and not (math.isfinite(args.t_end) and args.t_end > 0):
        raise InputError("--t-end", "t_end", "must be a positive number of seconds")
    _check_output(args.output, "-o")
    from .sampling import output_times
    result = simulate(rig, effects, spring_model=spring_model, t_end=args.t_end)
    result = result.resample(output_times(rig, args.t_end or result.t[-1]))
    result.spec_effects = effects
    _write_csv(result, rig, args.output)
    return 0


def _load_pair(measurement_path, rig_path):
    from .rig import load_measurement, load_rig, sibling_rig_path

    rig = load_rig(rig_path or sibling_rig_path(measurement_path))
    meas = load_measurement(measurement_path, rig.experiment)
    return rig, meas


def cmd_identify(args):
    from .identify import identify

    pairs = [_load_pair(m, args.rig) for m in args.measurements]
    for rig, meas in pairs:
        if rig.experiment != "pendulum":
            raise InputError(rig.path, "experiment", "identify needs pendulum measurements")
    result = identify(pairs, law=args.law)
    if args.json:
        print(json.dumps(result.to_json()))
    else:
        print(result.report())
    return 0


def cmd_diagnose(args):
    from .diagnose import diagnose

    rig, meas = _load_pair(args.measurement, args.rig)
    _check_output(args.plot, "--plot")
    d = diagnose(rig, meas, processes=max(1, args.processes))
    if args.plot:
        from .plots import plot_diagnosis
        plot_diagnosis(d, args.plot)
    if args.json:
        print(json.dumps(d.to_json()))
    else:
        print(d.report())
    return 0


def main(argv=None):
    args = build_parser().parse_args(argv)
    handler = {"simulate": cmd_simulate, "identify": cmd_identify, "diagnose": cmd_diagnose}[args.command]
    try:
        return handler(args)
    except InputError as e:
        print(f"vcbmodel: bad input: {e}", file=sys.stderr)
        return 2
    except SimulationError as e:
        print(f"vcbmodel: simulation failed: {e}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("vcbmodel: interrupted", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())

"""Operating sequences of a breaker (IEC 62271-100's rated operating sequence, O - t - CO - t' - CO):
``C``, ``O``, ``CO`` and their chains, e.g. ``O-0.3s-CO``, with each operation's figures of merit.

Each operation is one run of the breaker model (:func:`vcbmodel.experiments.simulation.simulate`,
either backend) with its commands (:class:`vcbmodel.laws.opening.Commands`) on the rig's breaker:

- **O**: from the closed breaker at rest on its trip latch, the closing springs charged (the cam at
  its start angle, held by its closing latch, the roller off the cam); the opening release trips the
  pawl at t = 0; the opening spring and the wipe springs open the contacts into the opening dashpot;
- **C**: from the open breaker at rest, the springs charged: the closing release lets the cam go at
  t = 0 (the closing of ``simulate`` itself, with the rig's cycle parts);
- **CO**: a C whose opening release is energised at the first pole's touch (IEC 62271-100's
  close-open: the release energised at the instant the contacts touch); the pawl lets go after the
  release's delay, the trip-free link collapses and the contacts reopen whatever the cam does.
  Its closing is judged by whether it would have completed: when the trip comes before the cam
  reaches its holding latch, its latching and kinetic margin are those of the same closing run
  without the trip (a C for ``LATCHING_RUN``; up to the trip the two runs are one).

A C whose run ends before its latching is judged (the cam still turning short of its latch) takes its
latching and kinetic margin from the same closing run for ``LATCHING_RUN``; a closing still unjudged
then says so (a note, the verdict line), never passed with the limits.

Times: each run's clock starts when its latch starts to let go (t = 0); a command is given its
release's delay earlier (:mod:`vcbmodel.laws.release`, at rated supply). The sequence's clock runs
from the first command; ``t`` in ``O-t-CO`` is the interval between the commands.

Chaining: each operation starts from a static rest (open or closed), so the previous one must have
come to rest before the next command: checked (its travel settled within its run, before the next
command), else the sequence fails with a SimulationError rather than chain a moving mechanism.

The closing springs: charged at the start (a sequence's first operation finds them charged by the
motor after the breaker's last closing); an O does not use them; a closing
discharges them and the motor recharges them in ``parameters.SPRING_RECHARGE_TIME``: a closing
commanded sooner after the previous closing is refused.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from .. import parameters as P
from ..errors import InputError, SimulationError
from ..laws.opening import NO_TRIP, Commands
from ..laws.release import release_delay
from ..rig.limits import LIMITED_FIGURES
from .closing_evaluation import figures_of_merit
from .simulation import simulate

if TYPE_CHECKING:
    from ..rig.data import Rig

OPERATIONS = ("O", "C", "CO")
#: Each operation's simulated run (s): an O rests within about 20 ms of its trip; a C rests on its
#: holding latch by about 66 ms (parameters.BREAKER_REST_T_END); a CO trips about 55 ms after its
#: latch lets go (the touch and the opening release's delay) and rests open some 20 ms later
RUN_LENGTH = {"O": 0.05, "C": P.BREAKER_REST_T_END, "CO": 0.1}
#: The run (s) of a closing whose latching its operation's run does not show (module docstring): a CO's
#: run length; closing springs of a third of the reference's rate (8000 N/m) stop the cam 92 ms in
LATCHING_RUN = RUN_LENGTH["CO"]
_UNITS = {"s": 1.0, "ms": 1e-3, "min": 60.0}
_INTERVAL = re.compile(r"(\d+(?:\.\d*)?|\.\d+)(ms|s|min)")


@dataclass(frozen=True)
class Step:
    """One operation of a sequence: ``op`` (O, C or CO) commanded at ``at`` (s, sequence clock)."""

    op: str
    at: float


def parse_sequence(text: str) -> list[Step]:
    """Steps of a sequence written as IEC writes it: operations (O, C, CO) separated by intervals
    (``0.3s``, ``300ms``, ``3min``), e.g. ``O-0.3s-CO-3min-CO``; a single operation is a sequence.
    Bad text: InputError naming ``--sequence``."""
    parts = [p.strip() for p in text.split("-")]
    steps, at = [], 0.0
    for k, part in enumerate(parts):
        if k % 2 == 0:
            if part not in OPERATIONS:
                raise InputError("--sequence", "sequence", f"{part!r} is not an operation (O, C or CO) in {text!r}: "
                                 "write operations and intervals alternately, e.g. O-0.3s-CO")
            steps.append(Step(part, at))
            continue
        m = _INTERVAL.fullmatch(part)
        if m is None:
            raise InputError("--sequence", "sequence", f"{part!r} is not an interval (e.g. 0.3s, 300ms, 3min) in {text!r}")
        at += float(m.group(1)) * _UNITS[m.group(2)]
    if len(parts) % 2 == 0:
        raise InputError("--sequence", "sequence", f"{text!r} ends with an interval: it must end with an operation")
    return steps


def check_sequence(rig: Rig, steps: list[Step]) -> None:
    """Refuse (InputError) a sequence this rig cannot run: an opening without ``breaker.trip_latch``
    and ``breaker.opening_dashpot``; an operation the breaker's state does not allow (an O of an open
    breaker, a closing of a closed one: a sequence starting with O starts closed, else open); a
    closing sooner than SPRING_RECHARGE_TIME after the previous closing."""
    b = rig.breaker
    if b is None:
        raise InputError("--sequence", "experiment", f"a {rig.experiment} rig has no breaker to operate")
    if any("O" in s.op for s in steps):
        for key in ("trip_latch", "opening_dashpot"):
            if getattr(b, key) is None:
                raise InputError(rig.path, f"breaker.{key}", "missing: an opening (O, CO) needs the trip latch and the "
                                 "opening dashpot (docs/rig-format.md)")
    closed, last_closing = steps[0].op == "O", None
    for s in steps:
        if (s.op == "O") != closed:
            state = "closed" if closed else "open"
            raise InputError("--sequence", "sequence", f"{s.op} at {s.at:g} s: the breaker is {state} then")
        if s.op != "O":
            if last_closing is not None and s.at - last_closing < P.SPRING_RECHARGE_TIME:
                raise InputError("--sequence", "sequence", f"{s.op} at {s.at:g} s: the closing springs discharged at "
                                 f"{last_closing:g} s recharge in {P.SPRING_RECHARGE_TIME:g} s (parameters."
                                 "SPRING_RECHARGE_TIME): allow at least that between closings")
            last_closing = s.at
        closed = s.op == "C"


def commands_for(rig: Rig, op: str) -> Commands:
    """The run's commands for one operation (module docstring); a CO's trip comes the opening
    release's delay after the touch (0 without an opening release: timed from the pawl)."""
    if op == "O":
        return Commands(close=False, start_closed=True, trip_time=0.0)
    if op == "C":
        return Commands(close=True, start_closed=False)
    release = rig.breaker.opening_release
    delay = release_delay(release) if release is not None else 0.0
    return Commands(close=True, start_closed=False, trip_time=NO_TRIP, trip_after_touch=delay)


def with_commands(rig: Rig, commands: Commands) -> Rig:
    """The rig whose breaker runs ``commands``."""
    return replace(rig, sections=dict(rig.sections, breaker=replace(rig.breaker, commands=commands)))


def run_operation(rig: Rig, step: Step, backend: str = "exudyn", **options) -> tuple[dict, object]:
    """(figures of one operation, its result): the run's figures of merit (:func:`figures_of_merit`)
    with ``op``, ``command_s`` (sequence clock), ``release_delay_s`` (the command's release) and
    ``run_s``."""
    op_rig = with_commands(rig, commands_for(rig, step.op))
    result = simulate(op_rig, backend=backend, t_end=RUN_LENGTH[step.op], **options)
    fom = figures_of_merit(result, op_rig)
    tripped = step.op == "CO" and (fom.get("opening") or {}).get("trip_s", float("inf")) < result.t[-1]
    if fom["kinetic_at_touch_J"] is not None and (tripped and fom["latched"] is not True
                                                   or step.op == "C" and fom["latched"] is None):
        fom = fom | closing_latching(rig, backend, **options)
    release = rig.breaker.opening_release if step.op == "O" else rig.breaker.closing_release
    return {"op": step.op, "command_s": step.at, "release_delay_s": release_delay(release) if release else None,
            "run_s": float(result.t[-1]), "backend": result.info["backend"], "figures": fom}, result


#: The kinetic-margin figures (:func:`vcbmodel.experiments.cycle_evaluation.kinetic_margin`) an operation
#: takes from :func:`closing_latching`
LATCHING = ("kinetic_at_touch_J", "kinetic_margin_J", "kinetic_margin_fraction", "latched", "latched_s", "latch_short_deg")


def closing_latching(rig: Rig, backend: str, **options) -> dict:
    """The latching of a closing its operation's run does not show (a CO tripped before its cam latched,
    a C whose run ends first; module docstring): the :data:`LATCHING` figures of the closing without a
    trip run for ``LATCHING_RUN``, with ``latching_run_s`` (that run's length, s)."""
    c_rig = with_commands(rig, commands_for(rig, "C"))
    fom = figures_of_merit(simulate(c_rig, backend=backend, t_end=LATCHING_RUN, **options), c_rig)
    return {key: fom[key] for key in LATCHING} | {"latching_run_s": LATCHING_RUN}


def operation_summary(entry: dict) -> dict:
    """The figures a sequence reports per operation (SI units; None where it does not apply):
    closing time from the coil (IEC) and from the latch, bounce, kinetic margin; opening time from
    the coil (IEC) and from the pawl, opening speed, rebound; a CO's close-open time."""
    f, op = entry["figures"], entry["op"]
    opening = f.get("opening") or {}
    coil_close = f.get("closing_time_from_coil_s")
    coil_open = f.get("opening_time_from_coil_s")
    out = {"op": op, "command_s": entry["command_s"], "release_delay_s": entry["release_delay_s"],
           "backend": entry["backend"]}
    if op != "O":
        out.update({"closing_time_from_coil_s": coil_close[1] if coil_close else None,
                    "closing_time_from_coil_range_s": [coil_close[0], coil_close[2]] if coil_close else None,
                    "closing_time_from_latch_s": f["closing_time_s"], "first_touch_from_latch_s": f["first_touch_s"],
                    "closing_speed_m_s": f["closing_speed_m_s"],
                    "bounce_count": _all_touched(f, "bounce_count"),
                    "bounce_duration_s": _all_touched(f, "bounce_duration_s"),
                    "kinetic_at_touch_J": f["kinetic_at_touch_J"], "kinetic_margin_J": f["kinetic_margin_J"],
                    "latched": f["latched"], "latching_run_s": f.get("latching_run_s")})
    if op != "C":
        out.update({"opening_time_from_coil_s": coil_open[1] if coil_open else None,
                    "opening_time_from_coil_range_s": [coil_open[0], coil_open[2]] if coil_open else None,
                    "opening_time_from_pawl_s": opening.get("opening_time_s"),
                    "opening_speed_m_s": opening.get("opening_speed_m_s"),
                    "opening_overtravel_m": opening.get("opening_overtravel_m"),
                    "opening_rebound_m": opening.get("opening_rebound_m"), "open_settled_s": opening.get("open_settled_s")})
    if op == "CO":
        out["close_open_time_s"] = f.get("close_open_time_s")
    out["contacts_closed_at_end"] = _closed_at_end(f)
    return out


def _coil(f: dict, part: str) -> float | None:
    """IEC's time from the ``part``'s (closing or opening) coil at rated supply (s; None without its release)."""
    times = f.get(f"{part}_time_from_coil_s")
    return times[1] if times else None


def _opening(f: dict, key: str):
    """One of the run's opening figures (None for a run that does not trip)."""
    return (f.get("opening") or {}).get(key)


def _all_touched(f: dict, key: str):
    """A bounce figure of the closing ``f``: None (no value) unless every pole touched (a pole that has not
    has no bounce yet, not none), as its closing time."""
    return f[key] if f["closing_time_s"] is not None else None


#: The figures a sequence judges against the rig's ``breaker.limits``: {limit: (the part of an operation
#: it bounds, ``closing`` or ``opening``, the run's values (SI) it bounds, every one of which must hold:
#: each pole's closing or opening speed)}. A closing's contact force at the end of its run is not judged
#: (a CO reopens), nor any figure of the travel after the touch.
SEQUENCE_LIMITED = {
    "closing_time": ("closing", lambda f: [f["closing_time_s"]]),
    "closing_time_from_coil": ("closing", lambda f: [_coil(f, "closing")]),
    "pole_spread": ("closing", lambda f: [f["pole_spread_s"]]),
    "closing_speed": ("closing", lambda f: [f["zone_speed_min_m_s"], f["zone_speed_max_m_s"]]),
    "bounce_duration": ("closing", lambda f: [_all_touched(f, "bounce_duration_s")]),
    "bounce_count": ("closing", lambda f: [_all_touched(f, "bounce_count")]),
    "kinetic_margin": ("closing", lambda f: [f["kinetic_margin_J"]]),
    "opening_time": ("opening", lambda f: [_opening(f, "opening_time_s")]),
    "opening_time_from_coil": ("opening", lambda f: [_coil(f, "opening")]),
    "opening_speed": ("opening", lambda f: list(_opening(f, "opening_speeds_m_s") or [None])),
}
#: The parts of each operation, each judged against the limits on it.
OPERATION_PARTS = {"O": ("opening",), "C": ("closing",), "CO": ("closing", "opening")}


def operation_limits(limits: tuple, entry: dict) -> list[dict]:
    """An operation's figures against the rig's limits on its parts (:data:`SEQUENCE_LIMITED`: a
    closing's on C and CO, an opening's on O and CO): one dict per limit, ``limit`` (its key), ``text``
    (as the rig states it), ``values_si`` and ``pass`` (None: the run did not show the figure, e.g. a cam
    that has not latched has no kinetic margin)."""
    f, out = entry["figures"], []
    for lim in limits:
        part, values_of = SEQUENCE_LIMITED.get(lim.figure, (None, None))
        if part not in OPERATION_PARTS[entry["op"]]:
            continue
        values = values_of(f)
        holds = [lim.holds(None if v is None else float(v)) for v in values]
        verdict = None if None in holds else all(holds)
        out.append({"limit": lim.figure, "text": lim.text(), "values_si": values, "pass": verdict})
    return out


def _closed_at_end(f: dict) -> bool:
    """Whether every pole is closed at the end of the run (from its touches, reopenings, partings)."""
    opening = f.get("opening") or {}
    parted = any(x is not None for x in opening.get("parting_s", []))
    touched = all(x is not None for x in f["per_pole"]["touch_s"]) and f["closing_time_s"] is not None
    return bool(touched and not parted and f["contacts_reopen_s"] is None) if touched else False


def run_sequence(rig: Rig, text: str, backend: str = "exudyn", results: list | None = None, **options) -> dict:
    """Run a sequence (module docstring): {``sequence``, ``operations`` (:func:`operation_summary`
    of each, in order), ``notes`` (a closing that fails, a CO whose contacts stay closed, missing
    releases, the springs' recharge), ``dead_times_s``}. ``results``: a list to which each
    operation's :class:`~vcbmodel.model.result.SimulationResult` is appended (for figures)."""
    steps = parse_sequence(text)
    check_sequence(rig, steps)
    entries, notes = [], []
    for k, step in enumerate(steps):
        entry, result = run_operation(rig, step, backend, **options)
        if results is not None:
            results.append(result)
        summary = operation_summary(entry)
        judged = operation_limits(rig.breaker.limits, entry)
        if judged or (step.op != "O" and rig.breaker.limits):  # an O without opening limits: none, as before
            summary["limits"] = judged
        if step.op != "O" and rig.breaker.limits:
            summary["limits_not_judged"] = [lim.figure for lim in rig.breaker.limits if lim.figure not in SEQUENCE_LIMITED]
        entries.append(summary)
        notes += _operation_notes(entry, summary, steps[k + 1] if k + 1 < len(steps) else None)
    notes += unjudged_parts(rig.breaker.limits, steps)
    for key, ops in (("closing_release", ("C", "CO")), ("opening_release", ("O", "CO"))):
        if getattr(rig.breaker, key) is None and any(s.op in ops for s in steps):
            notes.append(f"no breaker.{key}: times from the coil are null, those from the latch or pawl stand"
                         + (" (a CO's pawl lets go at the touch itself)" if key == "opening_release" else ""))
    notes.append(f"closing springs: charged at the start; each closing discharges them and the motor recharges them in "
                 f"{P.SPRING_RECHARGE_TIME:g} s (parameters.SPRING_RECHARGE_TIME), not simulated: an O does not use them")
    return {"sequence": text, "operations": entries, "notes": notes, "dead_times_s": dead_times(steps, entries)}


def unjudged_parts(limits: tuple, steps: list[Step]) -> list[str]:
    """A note for each part of an operation (``closing``, ``opening``) that the rig's limits bound but no
    operation of the sequence has: an O-only sequence judges no closing limit, a C-only one no opening
    limit; said, not left out of the text as if the rig had none. A limit a sequence never judges (the
    contact force closed) bounds a closing: a closing's line lists it."""
    parts = {part for s in steps for part in OPERATION_PARTS[s.op]}
    notes = []
    for part, ops in (("closing", "C or CO"), ("opening", "O or CO")):
        names = [lim.figure.replace("_", " ") for lim in limits
                 if SEQUENCE_LIMITED.get(lim.figure, ("closing",))[0] == part and part not in parts]
        if names:
            notes.append(f"the limits on the {part} ({', '.join(names)}) are not judged: the sequence has no {ops}")
    return notes


def _operation_notes(entry: dict, summary: dict, following: Step | None) -> list[str]:
    """What a reader must not miss about one operation: a closing that does not latch, a CO or O
    whose contacts stay closed, a C whose contacts do not (and :func:`check_rest`)."""
    f, op, notes = entry["figures"], entry["op"], []
    if op != "C" and summary["contacts_closed_at_end"]:
        notes.append(f"{op} at {entry['command_s']:g} s: the contacts are still closed at the end of its run")
    if op == "C" and not summary["contacts_closed_at_end"]:
        notes.append(f"C at {entry['command_s']:g} s: the contacts are not all closed at the end of its run")
    if f.get("latching_run_s") is not None:
        why = ("its trip comes before the cam reaches its holding latch" if op == "CO"
               else "its run ends before the cam reaches its holding latch or stops short of it")
        notes.append(f"{op} at {entry['command_s']:g} s: {why}: the closing's latching and kinetic margin are judged on "
                     f"the same closing without a trip, run for {f['latching_run_s']:g} s (a trip-free mechanism)")
    if op != "O" and f["latched"] is False:
        notes.append(f"{op} at {entry['command_s']:g} s: the cam does not reach its holding latch "
                     f"({f['latch_short_deg']:.3g} deg short): the closing fails")
    if op != "O" and f["latched"] is None:
        notes.append(f"{op} at {entry['command_s']:g} s: whether the closing latches is not judged: {unjudged_latch(f)}")
    check_rest(entry, following)
    return notes


def unjudged_latch(f: dict) -> str:
    """Why a closing's latching is not judged (``f``: its figures, ``latched`` None; the rule:
    :mod:`.cycle_evaluation`'s docstring)."""
    if f["kinetic_at_touch_J"] is None:
        return "no pole touches in its run, or the rig has no holding latch or end stop"
    return "the run ends with the cam on its way to its holding latch, still turning, neither back nor at rest"


def check_rest(entry: dict, following: Step | None) -> None:
    """Refuse (SimulationError) to chain an operation that has not come to rest before the next
    command: the model starts each operation from rest, so the next one's figures would be wrong."""
    if following is None:
        return
    f, op = entry["figures"], entry["op"]
    opening = f.get("opening") or {}
    settled = f["travel_settled_s"] if op == "C" else opening.get("open_settled_s")
    if settled is not None and op != "C":
        settled += opening["trip_s"]  # the opening's settling counts from its trip
    lead = entry["release_delay_s"] or 0.0
    if settled is None:
        raise SimulationError(f"{op} at {entry['command_s']:g} s has not come to rest within its {entry['run_s']:g} s run: "
                              f"the {following.op} at {following.at:g} s cannot start from rest")
    if entry["command_s"] + lead + settled > following.at:
        raise SimulationError(f"{op} at {entry['command_s']:g} s comes to rest {entry['command_s'] + lead + settled:.4g} s "
                              f"into the sequence, after the {following.op} commanded at {following.at:g} s: the model "
                              "starts each operation from rest; allow a longer interval")


def dead_times(steps: list[Step], entries: list[dict]) -> list[float | None]:
    """For each O followed by a closing: the interval (s) from the O's last parting to the closing's
    first touch (the dead time's bound: the arcs go out at a current zero after the parting)."""
    out = []
    for (s, e), (s2, e2) in zip(zip(steps, entries), zip(steps[1:], entries[1:])):
        if s.op == "O" and s2.op != "O":
            part, touch = e.get("opening_time_from_pawl_s"), e2.get("first_touch_from_latch_s")
            if part is None or touch is None:
                out.append(None)
                continue
            part += e["release_delay_s"] or 0.0
            touch += e2["release_delay_s"] or 0.0
            out.append(s2.at + touch - (s.at + part))
    return out


def sequence_lines(report: dict) -> list[str]:
    """The text ``vcbmodel simulate --sequence`` prints: one block per operation, its figures with
    units (ms, m/s, mm, J) and each operation against the limits, then the notes and the operations' verdict."""
    def ms(x):
        return "-" if x is None else f"{1e3 * x:.2f} ms"

    lines = [f"sequence {report['sequence']}"]
    for e in report["operations"]:
        lines.append(f"{e['op']} at {e['command_s']:g} s")
        if "closing_time_from_latch_s" in e:
            rng = e["closing_time_from_coil_range_s"]
            lines.append(f"  closing time from the coil {ms(e['closing_time_from_coil_s'])}"
                         + (f" ({ms(rng[0])} to {ms(rng[1])})" if rng else "")
                         + f"; from the latch {ms(e['closing_time_from_latch_s'])}")
            speed = e.get("closing_speed_m_s")
            if speed is not None:
                lines.append(f"  closing speed {speed:.3g} m/s (the poles' mean over the zone)")
            lines.append(f"  {bounce_text(e)}; kinetic margin{margin_text(e)}")
        if "opening_time_from_pawl_s" in e:
            rng = e["opening_time_from_coil_range_s"]
            speed = e["opening_speed_m_s"]
            lines.append(f"  opening time from the coil {ms(e['opening_time_from_coil_s'])}"
                         + (f" ({ms(rng[0])} to {ms(rng[1])})" if rng else "")
                         + f"; from the pawl {ms(e['opening_time_from_pawl_s'])}")
            lines.append(f"  opening speed {'-' if speed is None else f'{speed:.3g} m/s'}; rebound "
                         f"{1e3 * (e['opening_rebound_m'] or 0.0):.3g} mm")
        if e.get("close_open_time_s") is not None:
            lines.append(f"  close-open time {ms(e['close_open_time_s'])}")
        lines += limit_lines(e)
    return lines + [f"note: {n}" for n in report["notes"]] + sequence_verdict(report)


def bounce_text(e: dict) -> str:
    """A closing's bounce as the sequence's text says it: count and duration, or no value when not every
    pole touched in its run (a pole that has not touched has no bounce yet, not none)."""
    if e["bounce_count"] is None:
        return "bounce - (not every pole touched in its run)"
    return f"bounce {e['bounce_count']} ({1e3 * e['bounce_duration_s']:.2f} ms)"


def margin_text(e: dict, brief: bool = False) -> str:
    """A closing's kinetic margin after the words ``kinetic margin``: its value (``brief``: without the
    energy at touch, as the figure's title says it); ``not latched`` for a cam that stops short of its latch
    (the closing fails); ``not judged`` when no run shows it (the note says why: :func:`unjudged_latch`)."""
    if e["kinetic_margin_J"] is not None:
        return f" {e['kinetic_margin_J']:.1f} J" + ("" if brief else f" of {e['kinetic_at_touch_J']:.1f} J at touch")
    if e["latched"] is False:
        return " not latched" if brief else ": not latched"
    return " not judged"


def limit_lines(e: dict) -> list[str]:
    """An operation against the limits on its parts: ``limits: closing speed 1-1.5 m/s pass; ...``, and, for
    a closing, the limits a sequence does not judge (said also when they are the rig's only ones)."""
    left = [name.replace("_", " ") for name in e.get("limits_not_judged", [])]
    if not e.get("limits") and not left:
        return []
    words = {True: "pass", False: "FAIL", None: "no value"}
    judged = [f"{c['limit'].replace('_', ' ')} {c['text']} {words[c['pass']]}" + (f" ({failing_values(c)})" if c["pass"]
                                                                                 is False else "")
              for c in e.get("limits", [])]
    return ["  limits (breaker.limits): " + "; ".join(judged + ([f"not judged in a sequence: {', '.join(left)}"]
                                                               if left else []))]


def failing_values(c: dict) -> str:
    """The values a failing limit judged (``c``: one of :func:`operation_limits`' dicts), as read: ms for a
    time, m/s for a speed, J for an energy; every pole's for a per-pole limit (the line's mean hides one)."""
    unit, scale = {"s": ("ms", 1e3), "m/s": ("m/s", 1.0), "J": ("J", 1.0)}.get(LIMITED_FIGURES[c["limit"]][0], ("", 1.0))
    shown = ", ".join("-" if v is None else f"{scale * v:.3g}" for v in c["values_si"])
    return f"{shown} {unit}".rstrip()


def sequence_verdict(report: dict) -> list[str]:
    """One line: the operations' limits all pass, or which operation fails which (none without limits
    judged); a closing whose latching is not judged is said there, never passed with the limits."""
    if not any(e.get("limits") for e in report["operations"]):
        return []
    failed = _limit_failures(report)
    unjudged = [f"{e['op']} at {e['command_s']:g} s" for e in report["operations"]
                if "latched" in e and e["latched"] is None]
    latching = f"; latching not judged: {', '.join(unjudged)}" if unjudged else ""
    unseen = [f"{e['op']} at {e['command_s']:g} s: " + ", ".join(c["limit"].replace("_", " ") for c in e["limits"]
                                                                   if c["pass"] is None)
              for e in report["operations"] if any(c["pass"] is None for c in e.get("limits", []))]
    judged = any(c["pass"] is not None for e in report["operations"] for c in e.get("limits", []))
    head = "limits (breaker.limits), the operations: "
    if failed:
        return [head + f"FAIL: {'; '.join(failed)}{latching}"]
    if not unseen:
        return [head + "all pass" + latching]
    return [head + ("all judged pass" if judged else "none judged") + f"; no value in its run for {'; '.join(unseen)}"
            + latching]


def _limit_failures(report: dict) -> list[str]:
    """Each limit an operation fails: ``CO at 0.3 s: bounce duration (limit <= 1 ms)``."""
    return [f"{e['op']} at {e['command_s']:g} s: {c['limit'].replace('_', ' ')} (limit {c['text']})"
            for e in report["operations"] for c in e.get("limits", []) if c["pass"] is False]


def sequence_failures(report: dict) -> list[str]:
    """What fails in a sequence: each limit an operation fails and each closing whose cam stops short of
    its holding latch (the closing fails whatever the limits say); [] when nothing fails."""
    return _limit_failures(report) + [f"{e['op']} at {e['command_s']:g} s: the closing fails (the cam stops short of "
                                      "its latch)" for e in report["operations"] if e.get("latched") is False]

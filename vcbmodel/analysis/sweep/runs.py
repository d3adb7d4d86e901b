"""One run of a sweep, in whichever process: the rig's JSON edited at the run's paths, loaded,
simulated and evaluated; and the checks of the paths before any run."""
from __future__ import annotations

import copy
import threading
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ...errors import InputError, SimulationError
from ...experiments import experiment_of
from ...experiments.loading import rig_from_data
from ...experiments.simulation import simulate
from ...model.effects import effect_reading
from ...rig.cam_points import read_points_file
from ...rig.paths import get_path, path_keys, with_overrides
from ...rig.reader import Reader

if TYPE_CHECKING:
    from ...rig.data import Rig


def check_paths(data: dict, paths: Iterable[str], rig_path: str, experiment: str) -> None:
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
                message = str(e).split(": ", 2)[-1]
                if e.field != path and message.startswith("missing"):  # name what the user varied, not the gap
                    section = path.rsplit(".", 1)[0]
                    raise InputError(rig_path, path, f"this rig has no {section}, and this value alone does not make "
                                     f"one ({e.field} is {message.split(':')[0]}): give the whole {section} section in "
                                     "the rig to vary it") from None
            continue
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise InputError(rig_path, path, f"is not a number ({type(value).__name__}): only numeric fields can be varied")

#: Rig sections no run of a sweep reads, with why (every run would give the same row): {prefixes: message}
NOT_READ_BY_A_SWEEP = {
    ("breaker.limits.",): "a sweep judges no limits (its table holds the figures, docs/cli.md): every run would give "
                          "the same row; judge the table's figures against the limit",
    ("breaker.closing_release.", "breaker.opening_release."):
        "a sweep's closings start at the latch release and its table has no time from the coil: every run would give "
        "the same row; see the coil's effect with simulate (closing time from the coil) or simulate --sequence",
}


def check_used(paths: Iterable[str], effects: Sequence[str], rig_path: str, experiment: str) -> None:
    """Refuse a path that the model does not read (a field of an effect the model leaves out:
    ``friction.mu_s`` without ``stribeck``, ``closing_spring.mass`` on a massless spring), or a limit
    (``breaker.limits.*``: a sweep judges none), or a coil's release (``breaker.closing_release.*``,
    ``breaker.opening_release.*``: a sweep's closings start at the latch release, and its table has no time
    from the coil): every run would give the same row."""
    for path in paths:
        for sections, why in NOT_READ_BY_A_SWEEP.items():
            if path.startswith(sections):
                raise InputError(rig_path, path, why)
        owner = effect_reading(path)
        if owner is not None and owner not in effects:
            raise InputError(rig_path, path, f"is not used by this rig's model (effect {owner!r} is off; the model "
                             f"has {', '.join(effects) or 'no effects'}): every run would give the same row; "
                             f"add {owner!r} to model.effects (or set the spring model) to sweep it")


#: A closing spring's datasheet fields (rig-format.md 3.5)
DATASHEET_FIELDS = ("wire_diameter", "coil_diameter", "active_coils", "shear_modulus", "density")


def check_datasheet_used(paths, rig, spring_kind: str, rig_path: str) -> None:
    """Refuse sweeping a closing spring's datasheet field that changes nothing: when the rig gives
    both k0 and the mass, the datasheet only sizes the ANCF spring's coil (and ``check``'s stress)."""
    spring = getattr(rig, "closing_spring", None)
    if spring is None or spring.from_datasheet or spring_kind == "ancf":
        return
    for path in paths:
        head, _, name = path.partition(".")
        if head == "closing_spring" and name in DATASHEET_FIELDS:
            raise InputError(rig_path, path, "is not used by this rig's model: the rig gives stiffness and mass, so the "
                             "datasheet fields only size an ANCF spring's coil; every run would give the same row. "
                             "Leave stiffness and mass out to derive them from the datasheet (rig-format.md 3.5), or "
                             "sweep closing_spring.stiffness")


def figures_of_merit(rig: Rig, t_end: float | None = None, backend: str = "fast") -> dict:
    """The default evaluation of a run: simulate the rig's model (``backend``: ``fast``, compiled
    where the compiled path covers it, else Exudyn; or ``exudyn``) and return the experiment's
    figures of merit (the record's ``figure_columns``)."""
    record = experiment_of(rig.experiment)
    result = simulate(rig, t_end=t_end, backend=backend)
    fom = record.figures_of_merit(result, rig)
    return {k: fom.get(k) for k in record.figure_columns}


#: One solve at a time per process, even on a multi-threaded Dask worker (Exudyn systems are
#: independent, but the Python user functions share the interpreter).
_SOLVE_LOCK = threading.Lock()


def one_line(text: str, limit: int = 300) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[:limit - 3] + "..."


def run_one(data: dict, overrides: dict[str, float], rig_path: str, evaluate: Callable | None = None, t_end: float | None = None,
            backend: str = "fast") -> tuple[dict, str, float]:
    """One run, in whichever process: edit the JSON, load the rig, simulate, evaluate.

    Never raises for a bad run: returns ``(values, status, seconds)`` with status ``ok`` or
    ``failed: reason`` (a value that makes the rig invalid, a failed solve, ...)."""
    t0 = time.perf_counter()
    with _SOLVE_LOCK:
        try:
            rig = rig_from_data(with_overrides(data, overrides), rig_path)
            values = evaluate(rig, t_end) if evaluate is not None else figures_of_merit(rig, t_end, backend)
            status = experiment_of(rig.experiment).run_status(values) if evaluate is None else "ok"
        except InputError as e:
            # a field the run did not vary is named with the varied values that made it fail
            cause = "" if e.field in overrides else "with " + ", ".join(f"{k} = {v:g}" for k, v in overrides.items()) + ": "
            values, status = {}, f"failed: {cause if overrides else ''}{e.field}: {one_line(str(e).split(': ', 2)[-1])}"
        except SimulationError as e:
            values, status = {}, f"failed: {one_line(e)}"
        except Exception as e:  # noqa: BLE001 -- any other fault is that run's, the sweep goes on
            values, status = {}, f"failed: {type(e).__name__}: {one_line(e)}"
    return values, status, time.perf_counter() - t0


def inline_data_files(data: dict, rig_path: str) -> dict:
    """The rig's JSON object with the data files it names read in, here and once, so that a run
    needs no file where it runs (a cluster's worker has no copy of the rig's folder): a cam
    profile's ``points_file`` becomes its ``points`` (or ``radius_points``), in SI units, exactly
    what the loader reads from the file. A rig without one is returned as it is."""
    breaker = data.get("breaker")
    profile = breaker.get("cam_profile") if isinstance(breaker, dict) else None
    if not isinstance(profile, dict) or "points_file" not in profile:
        return data
    key, points = read_points_file(Reader(rig_path), profile, "breaker.cam_profile.")
    shipped = copy.deepcopy(data)
    del shipped["breaker"]["cam_profile"]["points_file"]
    shipped["breaker"]["cam_profile"][key] = points
    return shipped


@dataclass(frozen=True)
class SweepJob:
    """What every run of a sweep shares, sent to each worker once: the rig's JSON object (with
    its data files read in: :func:`inline_data_files`), the rig's path (for messages), the
    evaluation, the simulated time and the backend option."""

    data: dict
    rig_path: str
    evaluate: Callable | None = None
    t_end: float | None = None
    backend: str = "fast"


def run_chunk(job: SweepJob, chunk: Sequence[tuple[int, dict[str, float]]]) -> list[tuple[int, dict, str, float]]:
    """Several runs of one sweep in this process, one after another: ``chunk`` is
    [(run, overrides)]; returns [(run, values, status, seconds)] in the chunk's order."""
    return [(run, *run_one(job.data, overrides, job.rig_path, job.evaluate, job.t_end, job.backend))
            for run, overrides in chunk]

"""The files a rig stands for: the rig file itself, the files it reads (a cam's ``points_file``) and its
record ``NAME.csv`` beside it. No command may write over any of them, ``--force`` or not
(docs/cli.md, "Output files"); a sweep's table records their fingerprint (``--resume``)."""
from __future__ import annotations

import os

from ..errors import InputError
from .cam_points import points_path
from .reader import read_json

#: The first line of every CSV vcbmodel writes (``simulate``'s output, a sweep's table): such a file
#: beside a rig is a former output (replaceable with ``--force``); any other record beside it is data.
SIMULATED_MARK = "# vcbmodel "


def files_read(rig_path: str, data: object) -> tuple[str, ...]:
    """The files a rig (its JSON object ``data``, read from ``rig_path``) reads besides itself: its
    cam's ``points_file``. Never raises: a malformed rig has none (its loader says why)."""
    try:
        name = data["breaker"]["cam_profile"]["points_file"]
    except (KeyError, TypeError):
        return ()
    return (points_path(rig_path, name),) if isinstance(name, str) and name else ()


def written_by_vcbmodel(path: str | os.PathLike) -> bool:
    """Whether ``path`` is a CSV that vcbmodel wrote (``simulate``'s output, a sweep's table: its first
    line says so)."""
    try:
        with open(path, "rb") as f:
            first = f.readline(400).decode("utf-8", errors="replace")
    except OSError:
        return False
    return first.startswith(SIMULATED_MARK)


def is_record(path: str | os.PathLike) -> bool:
    """Whether ``path`` is a test's record: ``NAME.csv`` beside its ``NAME.rig.json``, not written by
    vcbmodel. Such a file is data: no command replaces it, ``--force`` or not."""
    path = str(path)
    return (path.endswith(".csv") and os.path.isfile(path) and os.path.isfile(path[:-4] + ".rig.json")
            and not written_by_vcbmodel(path))


def rig_inputs(rig_path: str | os.PathLike | None, data: object = None) -> tuple[str, ...]:
    """The rig file, the files it reads and its record ``NAME.csv`` beside it (unless ``vcbmodel
    simulate`` wrote that file): what an output may never replace. ``data``: the rig's JSON object when
    already read (read here otherwise; a malformed rig stands for itself only: its loader refuses it)."""
    if rig_path is None:
        return ()
    rig_path = str(rig_path)
    if data is None:
        try:
            data = read_json(rig_path)
        except InputError:
            data = None
    record = rig_path[:-len(".rig.json")] + ".csv" if rig_path.endswith(".rig.json") else None
    kept = (record,) if record and is_record(record) else ()
    return (rig_path, *files_read(rig_path, data), *kept)


def same_file(a: str | os.PathLike, b: str | os.PathLike) -> bool:
    """Whether two paths name one file (however spelt: ``..``, a symlink, a hard link)."""
    try:
        return os.path.samefile(a, b)
    except OSError:
        return os.path.realpath(a) == os.path.realpath(b)

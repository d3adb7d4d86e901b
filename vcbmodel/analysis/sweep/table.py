"""A sweep's table on disk: one CSV row per run, written and flushed as runs finish, a lock while
a sweep writes it, rows of an interrupted sweep read
back for ``resume``, and the complete table rewritten in run order."""
from __future__ import annotations

import csv
import fcntl
import hashlib
import io
import json
import math
import os
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ...errors import InputError
from ...rig.files import files_read, is_record, rig_inputs, same_file

if TYPE_CHECKING:
    import pandas as pd


@contextmanager
def table_lock(output: str | None) -> Iterator[None]:
    """Hold an exclusive lock on ``output`` while a sweep writes it: a second sweep of the same file
    (or a ``--resume`` of it), however its path is spelt (a symlink, a relative path, a hard link),
    is refused at once. The lock is the OS's (``flock`` on a hidden file beside the table's real
    path), so a killed sweep never leaves a stale one."""
    if not output:
        yield
        return
    real = Path(os.path.realpath(output))
    lock_path = real.with_name(f".{real.name}.lock")
    fd = _locked(lock_path, output)
    try:
        table = _table_locked(real, output)  # a hard link elsewhere names another lock file: the table's own inode
    except InputError:
        _release(lock_path, fd, None)
        raise
    try:
        yield
    finally:
        _release(lock_path, fd, table)


def _release(lock_path: Path, fd: int, table: int | None) -> None:
    """Remove the lock file and let go of both locks."""
    try:
        os.unlink(lock_path)
    except OSError:
        pass
    os.close(fd)
    if table is not None:
        os.close(table)


def _table_locked(real: Path, output: str) -> int | None:
    """An flock-ed descriptor of an existing table itself (None when there is none yet: no other path
    can name it then), so that a sweep through a hard link in another folder is refused too."""
    try:
        fd = os.open(real, os.O_RDONLY)
    except OSError:
        return None
    _lock_or_refuse(fd, output, "through another name for it, a hard link")
    return fd


def _lock_or_refuse(fd: int, output: str, through: str) -> None:
    """flock ``fd`` at once, or close it and refuse: another sweep writes the table (``through``: how)."""
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        os.close(fd)
        raise InputError(output, "output", f"another vcbmodel sweep is writing this table now ({through}): wait "
                         "for it, or give another -o") from None


def _locked(lock_path: Path, output: str) -> int:
    """An open, flock-ed descriptor of ``lock_path``; InputError when another sweep holds it. The file
    is checked to be still the one at ``lock_path`` after locking (a sweep that just finished unlinks
    its lock: locking the unlinked file would let a third sweep in beside this one)."""
    for _ in range(20):
        fd = os.open(lock_path, os.O_CREAT | os.O_RDWR, 0o644)
        _lock_or_refuse(fd, output, "through this path or another, a symlink to it")
        try:
            same = os.fstat(fd).st_ino == os.stat(lock_path).st_ino
        except FileNotFoundError:
            same = False
        if same:
            return fd
        os.close(fd)
    raise InputError(output, "output", "cannot take the table's lock (other sweeps keep replacing it)")


def check_table_path(output: str | None, rig_path: str, data: dict) -> None:
    """Refuse, before anything runs, a table that would replace an input (the rig, a file it reads, its
    record beside it; through any spelling of the path, ``force`` or not) or that names a folder."""
    if not output:
        return
    if os.path.isdir(output):
        raise InputError(output, "output", "is a folder: give a file name")
    if is_record(output):
        raise InputError(output, "output", "is a test's record (beside its rig file, not written by vcbmodel): data "
                         "is never replaced, force or not; give another output file")
    if str(output).endswith(".rig.json"):
        raise InputError(output, "output", "is named as a rig file: a sweep's table is a CSV (give it a .csv name)")
    for source in rig_inputs(rig_path, data) if os.path.exists(rig_path) else files_read(rig_path, data):
        if os.path.exists(output) and os.path.exists(source) and same_file(output, source):
            raise InputError(output, "output", f"is an input of this sweep ({source}): an input is never replaced, "
                             "force or not; give another output file")


#: The comment line a sweep's table starts with: the fingerprint of the rig it ran
FINGERPRINT_MARK = "# vcbmodel sweep rig sha256 "


def rig_fingerprint(data: dict, rig_path: str, t_end: float | None = None) -> str:
    """SHA-256 (hex) of what a sweep's runs read: the rig's JSON object (its values, keys sorted, comments
    left out), the bytes of every file the rig reads (a cam's ``points_file``) and the simulated duration
    ``t_end`` (s) when one is given instead of the experiment's."""
    def strip(obj):
        if isinstance(obj, dict):
            return {k: strip(v) for k, v in obj.items() if not str(k).startswith("_")}
        return [strip(v) for v in obj] if isinstance(obj, list) else obj

    h = hashlib.sha256(json.dumps(strip(data), sort_keys=True, separators=(",", ":")).encode())
    for path in files_read(rig_path, data):
        try:
            h.update(Path(path).read_bytes())
        except OSError:
            h.update(b"(unreadable)")
    if t_end is not None:
        h.update(f"t_end={float(t_end)!r}".encode())
    return h.hexdigest()


def fingerprint_line(fingerprint: str) -> str:
    """The table's first line: the rig's fingerprint (``--resume`` refuses a changed rig)."""
    return f"{FINGERPRINT_MARK}{fingerprint}\n"


def check_fingerprint(output: str, text: str, fingerprint: str | None) -> None:
    """Refuse resuming a table whose rig (or a file it reads) has changed since its rows were written,
    or that carries no fingerprint (written by hand or by an older vcbmodel: the rig cannot be told)."""
    if fingerprint is None:
        return
    marks = [line[len(FINGERPRINT_MARK):].strip() for line in text.splitlines() if line.startswith(FINGERPRINT_MARK)]
    if not marks:
        raise InputError(output, "--resume", "the table carries no fingerprint of the rig its rows came from (written "
                         "by hand or by an older vcbmodel), so a changed rig cannot be told: rerun it with --force")
    if marks[0] != fingerprint:
        raise InputError(output, "--resume", "its rows came from another version of the rig (the rig file or a file "
                         "it reads, such as its cam's points, changed since) or another --t-end: resuming would mix "
                         "two in one table; rerun with --force, or give another -o")


def cell_text(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, (bool, np.bool_)):
        return str(int(v))
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    v = float(v)
    return "" if not math.isfinite(v) else f"{v:.9g}"


def value_text(v: float) -> str:
    return repr(float(v))


def read_finished(output: str, header: list[str], table: pd.DataFrame,
                  fingerprint: str | None = None) -> dict[int, dict[str, str]]:
    """Rows already in ``output`` (a resumed sweep): {run: row dict}. A last line cut short by
    an interrupt is dropped (the file is truncated to its last complete row); rows must match
    this sweep's header and design, and with ``fingerprint`` (:func:`rig_fingerprint`) the table
    must have come from this rig (:func:`check_fingerprint`)."""
    raw = Path(output).read_bytes()
    if not raw.strip():
        Path(output).write_bytes(b"")
        return {}
    if not raw.endswith(b"\n"):  # the interrupted last row
        raw = raw[:raw.rfind(b"\n") + 1]
        Path(output).write_bytes(raw)
    text = raw.decode("utf-8", errors="replace")
    check_fingerprint(output, text, fingerprint)
    reader = csv.reader(line for line in io.StringIO(text) if not line.startswith("#"))
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


def typed_row(row: dict, paths: list[str], columns: Sequence[str]) -> dict:
    out = {"run": int(row["run"])}
    for k in paths + list(columns):
        v = row.get(k, "")
        out[k] = float(v) if v not in ("", None) else float("nan")
    out["status"] = row["status"]
    return out


def rewrite_in_order(output: str | Path) -> None:
    """Rewrite a complete sweep's file in run order (atomically: a temporary file, then rename)."""
    text = Path(output).read_text()
    comments = [line for line in text.splitlines(keepends=True) if line.startswith("#")]
    reader = csv.reader(line for line in io.StringIO(text) if not line.startswith("#"))
    head = next(reader)
    rows = sorted((r for r in reader if r), key=lambda r: int(r[0]))
    tmp = Path(output).with_name(f".{Path(output).name}.{os.getpid()}.tmp")
    with open(tmp, "w", newline="") as g:
        g.writelines(comments)
        w = csv.writer(g, lineterminator="\n")
        w.writerow(head)
        w.writerows(rows)
    os.replace(tmp, output)

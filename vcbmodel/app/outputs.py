"""The files a command writes (docs/cli.md, "Output files").

Every rule here is checked before any work starts:

- an output is never one of the command's inputs (``simulate x.rig.json -o x.rig.json``), nor a file the rig
  reads (its cam's points file) or its record beside it, through any spelling of the path, a symlink or
  a hard link, ``--force`` or not (:func:`protected_inputs`);
- an existing regular file is replaced only with ``--force`` (a sweep may also ``--resume`` it);
- the folder must exist and be writable, a plot's suffix must be a format matplotlib writes.

Writing goes through a temporary file in the same folder and a rename, so a failed write (a full
disk) leaves the old file, or none, never half a file. Devices (``/dev/null``, ``/dev/stdout``) are
written directly and need no ``--force``.
"""
from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Iterable

from ..errors import InputError
from ..rig.files import is_record, rig_inputs, same_file


def protected_inputs(rig_path: str | os.PathLike | None, data: object = None, others: Iterable[str | os.PathLike] = ()) -> tuple[str, ...]:
    """Every file a command reads through its rig, which its outputs may never replace (``--force`` or
    not): :func:`vcbmodel.rig.files.rig_inputs` (the rig, the files it reads, its record beside it
    unless ``vcbmodel simulate`` wrote it) and ``others`` (a measurement)."""
    return (*rig_inputs(rig_path, data), *(str(o) for o in others))


def check_distinct(path: str | os.PathLike | None, other: str | os.PathLike | None, argname: str, other_name: str) -> None:
    """Refuse two outputs of one command that are the same file (however spelt: a symlink, ``./``)."""
    if path is None or other is None:
        return
    same = (os.path.exists(path) and os.path.exists(other) and same_file(path, other)) or \
        os.path.realpath(path) == os.path.realpath(other)
    if same:
        raise InputError(path, argname, f"is also the {other_name} file (one would replace the other): give it another name")


def is_regular_or_absent(path: str | os.PathLike) -> bool:
    """True for a regular file or a path that does not exist yet (what ``--force`` protects)."""
    try:
        return stat.S_ISREG(os.stat(path).st_mode)
    except FileNotFoundError:
        return True


def check_output(path: str | os.PathLike | None, argname: str, *, inputs: Iterable[str | os.PathLike] = (), force: bool = False, keep: bool = False,
                 resumable: bool = False, formats: Iterable[str] | None = None) -> None:
    """Refuse an output path before any work: nothing is written, nothing left behind.

    Parameters
    ----------
    path : the output file (None: stdout, nothing to check).
    argname : the option that gave it (``-o``, ``--plot``), named in the error.
    inputs : the files the command reads; the output may be none of them.
    force : an existing file may be replaced.
    keep : an existing file will be continued, not replaced (``sweep --resume``).
    resumable : the refusal mentions ``--resume`` (a sweep's table).
    formats : allowed suffixes (image formats), or None.
    """
    if path is None:
        return
    _refuse_an_input(path, argname, list(inputs))
    folder = os.path.dirname(os.path.abspath(path))
    if not os.path.isdir(folder):
        raise InputError(path, argname, "the folder does not exist")
    if formats is not None:
        suffix = os.path.splitext(path)[1].lstrip(".").lower()
        if suffix not in formats:
            raise InputError(path, argname, f"unknown image format {suffix or '(none)'!r} (known: {', '.join(formats)})")
    _check_writable(path, argname, folder, force or keep, resumable)


def check_table_name(path: str | os.PathLike | None, argname: str, image_formats: Iterable[str], figure: str) -> None:
    """Refuse a CSV output named as an image or as JSON (``simulate -o closing.png`` meant ``--plot``,
    ``-o result.json`` meant ``--json``): the file would hold a CSV under a name that says otherwise.
    ``figure``: how the command's figure is drawn instead, with ``{suffix}`` for the suffix given."""
    if path is None:
        return
    suffix = os.path.splitext(str(path))[1].lstrip(".").lower()
    if suffix in set(image_formats):
        raise InputError(path, argname, f"writes the CSV table; .{suffix} is an image's name: draw the figure with "
                         f"{figure.format(suffix=suffix)} and give {argname} a .csv name")
    if suffix == "json":
        raise InputError(path, argname, f"writes the CSV table, not JSON: --json prints the JSON on stdout "
                         f"(> FILE.json); give {argname} a .csv name")


def _refuse_an_input(path: str | os.PathLike, argname: str, inputs: list) -> None:
    """Refuse an output that is one of the command's ``inputs``, a folder, a test's record, or named as a rig."""
    for source in inputs:
        if source is not None and os.path.exists(path) and same_file(path, source):
            raise InputError(path, argname, f"is an input of this command ({source}): an input is never replaced, "
                             "--force or not; give another output file")
    if os.path.isdir(path):
        raise InputError(path, argname, "is a folder: give a file name")
    if is_record(path):
        raise InputError(path, argname, "is a test's record (beside its rig file, not written by vcbmodel): data is "
                         "never replaced, --force or not; give another output file")
    inputs = [source for source in inputs if source is not None]
    if inputs and str(path).endswith(".rig.json") and is_regular_or_absent(path):  # a command reading a rig writes none
        raise InputError(path, argname, "is named as a rig file (NAME.rig.json): an output is never a rig; give "
                         "another name")


def _check_writable(path: str | os.PathLike, argname: str, folder: str, replace: bool, resumable: bool) -> None:
    """Refuse an existing file unless it may be replaced (or continued), and a file or folder that cannot be written."""
    if not is_regular_or_absent(path):
        if not os.access(path, os.W_OK):
            raise InputError(path, argname, "cannot be written (permission denied)")
        return  # a device: written directly
    if os.path.exists(path):
        if not replace:
            raise InputError(path, argname, "exists already: give --force to replace it"
                             + (" (or --resume to continue it)" if resumable else ""))
        if not os.access(path, os.W_OK):
            raise InputError(path, argname, "cannot be written (permission denied)")
    try:
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".vcbmodel-check-"):
            pass
    except OSError as e:
        raise InputError(path, argname, f"cannot be written here ({e.strerror or 'not writable'})") from None


def write_file(path: str | os.PathLike, data: str | bytes) -> None:
    """Write ``data`` (str or bytes) to ``path``: a regular file atomically (temporary file, then rename), a device
    directly. An OSError (a full disk) leaves no partial file and propagates."""
    try:
        _write(path, data)
    except OSError as e:
        raise OSError(e.errno, e.strerror, str(path)) from None


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _write(path, data):
    if not is_regular_or_absent(path):
        with open(path, "wb" if isinstance(data, bytes) else "w") as f:
            f.write(data)
        return
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=f".{os.path.basename(path)}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb" if isinstance(data, bytes) else "w") as f:
            f.write(data)
        os.chmod(tmp, 0o666 & ~_umask())  # mkstemp makes 0600: give the file the mode a plain open() would
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise

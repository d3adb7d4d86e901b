"""Reading rig files: bytes -> JSON -> typed, checked values, every fault one line.

Keys starting with ``_`` are free comments wherever they appear.

:func:`read_json` turns a file into a JSON object or raises :class:`InputError` (not UTF-8,
UTF-16, binary, malformed, nested too deeply, NaN/Infinity, numbers out of range).
:class:`Reader` gives typed access to it with errors naming the dotted field, and refuses
unknown keys with a "did you mean" hint. Section readers (:mod:`vcbmodel.rig.sections`) and
the rig loader (:mod:`vcbmodel.experiments.loading`) use it.
"""
from __future__ import annotations

import difflib
import json
import math
import os
import stat
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any, NoReturn

from ..errors import InputError

#: Largest magnitude accepted for any number in a rig (SI units): beyond it a value is a typo
#: or an overflow, and would make the solver run into inf/NaN (the stiffest value in use,
#: a Hertz contact constant, is about 1e11).
LARGEST_NUMBER = 1e15
#: Deepest JSON nesting accepted (a rig needs 4 levels).
MAX_DEPTH = 32
UTF8_BOM = b"\xef\xbb\xbf"


def text_bytes(path: str | Path, raw: bytes) -> bytes:
    """A text file's bytes without a UTF-8 byte-order mark; UTF-16 and binary files are refused
    with a one-line error."""
    if raw.startswith(UTF8_BOM):
        raw = raw[len(UTF8_BOM):]
    if raw.startswith((b"\xff\xfe", b"\xfe\xff")):
        raise InputError(path, "file", "is UTF-16 encoded: save it as UTF-8")
    if b"\x00" in raw:
        raise InputError(path, "file", "is binary, not a text file")
    return raw


def decode_text(path: str | Path, raw: bytes) -> str:
    """The text of a file's bytes: UTF-8, with or without a byte-order mark (:func:`text_bytes`)."""
    raw = text_bytes(path, raw)
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as e:
        line = raw[:e.start].count(b"\n") + 1
        raise InputError(path, f"line {line}", "is not UTF-8 text") from None


#: Largest file read (bytes): a record of two million rows is about 60 MB; a bigger file, or a
#: device such as /dev/zero, would be read until memory runs out.
MAX_FILE_BYTES = 200_000_000


def read_bytes(path: str | Path) -> bytes:
    """A regular file's bytes, at most MAX_FILE_BYTES (InputError otherwise)."""
    try:
        info = os.stat(path)
        if stat.S_ISDIR(info.st_mode):
            raise InputError(path, "file", "is a folder, not a file")
        if not stat.S_ISREG(info.st_mode):
            raise InputError(path, "file", "is not a regular file (a device, pipe or socket): give a file")
        if info.st_size > MAX_FILE_BYTES:
            raise InputError(path, "file", f"is {info.st_size / 1e6:.0f} MB, more than a record of two million "
                             f"rows (at most {MAX_FILE_BYTES / 1e6:.0f} MB): decimate it")
        return Path(path).read_bytes()
    except IsADirectoryError:
        raise InputError(path, "file", "is a folder, not a file") from None
    except OSError as e:
        raise InputError(path, "file", f"cannot read: {e.strerror}") from None


def _depth(obj, level=0):
    if level > MAX_DEPTH:
        return level
    if isinstance(obj, dict):
        return max([_depth(v, level + 1) for v in obj.values()], default=level)
    if isinstance(obj, list):
        return max([_depth(v, level + 1) for v in obj], default=level)
    return level


def _rig_text(path: str) -> str:
    """The rig file's text; an empty file (or one of blank lines) is refused as such."""
    text = decode_text(path, read_bytes(path))
    if not text.strip():
        raise InputError(path, "file", "is empty (a rig is one JSON object: vcbmodel init writes one to start from)")
    return text


def read_json(path: str | Path) -> Any:
    """Parse a JSON file (see module docstring)."""
    path = str(path)
    text = _rig_text(path)
    # a cheap guard before the parser recurses: count the opening brackets' nesting
    level = deepest = 0
    for ch in text:
        if ch in "[{":
            level += 1
            if level > deepest:
                deepest = level
                if deepest > MAX_DEPTH:
                    raise InputError(path, "JSON", f"nested more than {MAX_DEPTH} levels deep")
        elif ch in "]}":
            level -= 1

    def bad_constant(name):
        raise ValueError(f"{name} is not a valid JSON number")

    def unique_keys(pairs):
        seen = {}
        for key, value in pairs:
            if key in seen:  # marked, and found with its dotted path once the whole tree is read
                seen.setdefault(_TWICE, key)
            seen[key] = value
        return seen

    try:  # a number out of range (1e400) reads as inf: Reader.value refuses it, naming the field
        data = json.loads(text, parse_constant=bad_constant, object_pairs_hook=unique_keys)
    except json.JSONDecodeError as e:
        raise InputError(path, f"line {e.lineno}", f"malformed JSON: {e.msg}{json_hint(path, text, e)}") from None
    except (ValueError, RecursionError) as e:
        raise InputError(path, "JSON", str(e) or "cannot be parsed") from None
    twice = _given_twice(data)
    if twice is not None:
        raise InputError(path, twice, "is given twice in the same object: JSON readers keep only one of "
                         "them, so say which value you mean")
    return data


def _given_twice(node, prefix: str = "") -> str | None:
    """The dotted path (``cam.mass``; list items by index) of the first key an object of ``node``
    names twice (:func:`read_json`'s mark), or None."""
    if isinstance(node, dict):
        if _TWICE in node:
            return prefix + node[_TWICE]
        items = node.items()
    elif isinstance(node, list):
        items = ((str(i), v) for i, v in enumerate(node))
    else:
        return None
    for key, value in items:
        found = _given_twice(value, f"{prefix}{key}.")
        if found is not None:
            return found
    return None


def json_hint(path: str | Path, text: str, error: json.JSONDecodeError) -> str:
    """What a malformed rig most likely is: TOML or YAML (rig files are JSON), or JSON with comments
    (comments are keys starting with ``_``); empty otherwise."""
    line = text.splitlines()[error.lineno - 1].strip() if error.lineno <= len(text.splitlines()) else ""
    if str(path).lower().endswith((".toml", ".yaml", ".yml", ".ini")):
        return " (rig files are JSON: NAME.rig.json; TOML and YAML are not read)"
    if str(path).lower().endswith((".csv", ".tsv", ".txt")):
        return " (this is a record, not a rig: its rig is the NAME.rig.json beside it, which check and simulate take)"
    if line.startswith(("//", "/*", "#")):
        return " (JSON has no comments: write them as keys starting with _, e.g. \"_note\": \"...\")"
    return ""


#: The key under which an object that names a key twice records it (not a JSON string a file can hold:
#: a key read from JSON is a str, this is not one).
_TWICE = ("given twice",)


def did_you_mean(name: str, known: Iterable[str]) -> str:
    close = difflib.get_close_matches(name, list(known), n=1, cutoff=0.6)
    return f" (did you mean {close[0]!r}?)" if close else ""


class Reader:
    """Typed access into a parsed rig with errors naming the dotted field (``cam.mass``)."""

    def __init__(self, path):
        self.path = str(path)

    def fail(self, fieldname: str, message: str) -> NoReturn:
        raise InputError(self.path, fieldname, message)

    def known_keys(self, obj: dict, known: Iterable[str], prefix: str = "") -> None:
        """Refuse keys of ``obj`` not in ``known``, naming the first unknown one; keys starting
        with ``_`` are free comments."""
        for key in obj:
            if key not in known and not key.startswith("_"):
                self.fail(prefix + key, f"unknown field{did_you_mean(key, known)}; known: {', '.join(known)}")

    def section(self, obj: dict, key: str, prefix: str = "", known: Iterable[str] | None = None) -> dict:
        name = prefix + key
        if key not in obj:
            self.fail(name, "missing")
        if not isinstance(obj[key], dict):
            self.fail(name, "must be an object")
        if known is not None:
            self.known_keys(obj[key], known, name + ".")
        return obj[key]

    def optional_section(self, obj: dict, key: str, prefix: str = "", known: Iterable[str] | None = None) -> dict:
        if key not in obj:
            return {}
        return self.section(obj, key, prefix, known)

    def number(self, obj: dict, key: str, prefix: str = "", *, positive: bool = False, nonnegative: bool = False,
               default: float | None = None) -> float:
        name = prefix + key
        if key not in obj:
            if default is not None:
                return default
            self.fail(name, "missing")
        return self.value(obj[key], name, positive=positive, nonnegative=nonnegative)

    def value(self, v: Any, name: str, *, positive: bool = False, nonnegative: bool = False) -> float:
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            self.fail(name, f"must be a number, got {json.dumps(v)[:40]}")
        try:
            v = float(v)
        except OverflowError:
            self.fail(name, "is out of range")
        if not math.isfinite(v):
            self.fail(name, "must be finite")
        if abs(v) > LARGEST_NUMBER:
            self.fail(name, f"is implausibly large ({v:g}; values are in SI units)")
        if positive and not v > 0:
            self.fail(name, f"must be positive, got {v:g}")
        if nonnegative and v < 0:
            self.fail(name, f"must not be negative, got {v:g}")
        return v

    def count(self, obj: dict, key: str, prefix: str = "", default: int | None = None) -> int:
        """A whole, positive number (a count)."""
        v = self.number(obj, key, prefix, positive=True, default=default)
        if v != int(v):
            self.fail(prefix + key, "must be a whole number")
        return int(v)

    def boolean(self, obj: dict, key: str, prefix: str = "", default: bool = False) -> bool:
        v = obj.get(key, default)
        if not isinstance(v, bool):
            self.fail(prefix + key, "must be true or false")
        return v

    def choice(self, obj: dict, key: str, prefix: str, options: Sequence[str], default: str | None = None) -> str:
        """``obj[key]`` (``default`` when absent), which must be one of ``options``."""
        v = obj.get(key, default)
        if v not in options:
            self.fail(prefix + key, f"must be one of {', '.join(options)}")
        return v

    def text(self, obj: dict, key: str, prefix: str = "", default: str | None = None) -> str | None:
        v = obj.get(key, default)
        if not isinstance(v, str):
            self.fail(prefix + key, "must be a string")
        return v

    def point(self, obj: dict, key: str, prefix: str = "") -> tuple[float, ...]:
        name = prefix + key
        if key not in obj:
            self.fail(name, "missing")
        v = obj[key]
        if not isinstance(v, list) or len(v) != 2:
            self.fail(name, "must be a list of two numbers [x, y]")
        return tuple(self.value(x, name) for x in v)

    def numbers(self, obj: dict, key: str, prefix: str, count: int, default: Sequence[float] | None) -> tuple[float, ...]:
        """A list of ``count`` numbers."""
        name = prefix + key
        v = obj.get(key, default)
        if not isinstance(v, list) or len(v) != count:
            self.fail(name, f"must be a list of {count} numbers")
        return tuple(self.value(x, name) for x in v)

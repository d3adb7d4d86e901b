"""Measurement files ``NAME.csv``: ``#`` comment lines (free text), a header starting with
``t``, channels in SI units or in the units the header states (the experiment records say which
channels exist). A breaker analyser's export reads as written: ``t [ms]``, ``pole_1_travel [mm]``,
or a units row under the header (``ms,mm,-``); every column is converted to SI on reading
(:mod:`.units`), units such as ``µs``, ``µm`` or ``°`` included (UTF-8). The time column may be
headed ``t`` or ``time`` (``Time [ms]``, as analysers write it); an oscilloscope's preamble above the
header (``Record Length,10000``) is kept as comments, its ``Sample Interval`` checked. Reading refuses anything malformed
with one line naming the file and the line or column; writing is the inverse (SI)."""
from __future__ import annotations

import datetime as dt
import math
import re
from collections.abc import Iterable
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..rig.reader import did_you_mean, read_bytes, text_bytes
from ..rig.units import to_si



@dataclass(frozen=True)
class Measurement:
    """A measured (or synthetic) time series: ``t`` in s, channels in SI units (rad or m)."""

    path: str
    t: np.ndarray
    channels: dict
    comments: tuple = ()

    def channel(self, name: str) -> np.ndarray:
        return self.channels[name]

    def window(self, t0: float = -math.inf, t1: float = math.inf) -> Measurement:
        """The samples with t0 <= t <= t1."""
        keep = (self.t >= t0) & (self.t <= t1)
        return replace(self, t=self.t[keep], channels={k: v[keep] for k, v in self.channels.items()})


#: What starts a comment line: ``#``, or ``%`` as MATLAB and Octave write them.
COMMENT = ("#", "%")
COMMENT_BYTES = tuple(c.encode() for c in COMMENT)
#: The byte-order marks of UTF-16 (little- and big-endian), as Excel's "Unicode text" and other Windows
#: tools write it.
UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")


#: The first bytes of a spreadsheet workbook saved under a record's name: .xlsx (a zip) and .xls.
WORKBOOKS = (b"PK\x03\x04", b"\xd0\xcf\x11\xe0")


def _utf8(path, raw: bytes) -> bytes:
    """A UTF-16 file with its byte-order mark (Excel's "Unicode text", tab-separated) as UTF-8 bytes;
    a spreadsheet workbook refused as such; any other file as it is."""
    if raw.startswith(WORKBOOKS):
        raise InputError(path, "file", "is a spreadsheet workbook (.xlsx or .xls), not a text file: save the sheet "
                         "as CSV")
    if not raw.startswith(UTF16_BOMS):
        return raw
    try:
        return raw.decode("utf-16").encode("utf-8")
    except UnicodeDecodeError:
        raise InputError(path, "file", "starts as UTF-16 text but is not UTF-16 throughout: save it as "
                         "UTF-8") from None


def _lines(path, raw):
    """(line number, text) of each line; comment lines may hold any bytes (free text), the others
    are UTF-8 (a header's or units row's ``µs``, ``°``); a UTF-16 file is read as its text."""
    for i, line in enumerate(text_bytes(path, _utf8(path, raw)).splitlines(), start=1):
        s = line.strip()
        if s.startswith(COMMENT_BYTES):
            yield i, s.decode("utf-8", errors="replace")
            continue
        try:
            yield i, s.decode("utf-8")
        except UnicodeDecodeError:
            raise InputError(path, f"line {i}", "is not UTF-8 text (an analyser's export in another encoding, "
                             "e.g. Windows-1252 for 'µs' or '°': save it as UTF-8)") from None


#: A number as measurement files write it: digits with an optional point and exponent (no
#: underscores, which Python would read as digit separators: 1_0.0 -> 10.0), or nan/inf (refused
#: below with their own message).
NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|[+-]?(nan|inf|infinity)", re.IGNORECASE)


def _number(cell, path, line):
    if not NUMBER.fullmatch(cell):
        why = (" (underscores are not allowed in numbers)" if "_" in cell else
               " (a thousands separator? Save the numbers without them)" if cell.count(".") > 1 else "")
        raise InputError(path, f"line {line}", f"value {cell[:30]!r} is not a number{why}")
    return float(cell)


#: A header name with its unit: ``t [s]``, ``cam_angle (rad)``, ``cam_angle/rad``.
HEADER_UNIT = re.compile(r"(?P<name>[A-Za-z_][A-Za-z0-9_]*)\s*(?:\[(?P<a>[^\]]*)\]|\((?P<b>[^)]*)\)|/\s*(?P<c>\S+))")


#: Excel's first line naming the separator (``sep=;``), written above the header by some exports.
SEPARATOR_LINE = re.compile(r"sep=[;,\t]?", re.IGNORECASE)  # a tab (``sep=\t``) is stripped with the line's ends


def _dialect(header_text, separator=None):
    """(delimiter, decimal comma) from a ``sep=`` line's ``separator`` or else the header line: ``;``
    (spreadsheets with a decimal comma), a tab, ``,``, or None for columns separated by spaces."""
    if separator is not None:
        return separator, separator == ";"
    if ";" in header_text:
        return ";", True
    if "\t" in header_text and "," not in header_text:
        return "\t", False
    if "," not in header_text and len(header_text.split()) > 1:
        return None, False  # columns separated by spaces (Octave's save -ascii, a fixed-width export)
    return ",", False


def _cells(text, delimiter, decimal_comma):
    """A line's cells: split, stripped, symmetric double quotes removed, a trailing empty cell
    (a trailing delimiter) dropped, decimal commas read as points; the header and each row then drop
    their empty cells past the last column (a spreadsheet's padding, :func:`_within`)."""
    cells = [c.strip() for c in text.split(delimiter)]
    if delimiter is None:  # split at spaces: a unit in brackets belongs to the name before it (t [ms])
        cells = [c for c in " ".join(cells).replace(" [", "[").replace(" (", "(").split()]
    if len(cells) > 1 and cells[-1] == "":
        cells = cells[:-1]
    cells = [c[1:-1].strip() if len(c) >= 2 and c[0] == c[-1] == '"' else c for c in cells]
    return [c.replace(",", ".") for c in cells] if decimal_comma else cells


def _factor(stated, name, want, path, field, where):
    """The factor that takes a column stated in ``stated`` to its channel's SI unit ``want`` (None:
    any SI unit); a unit of another quantity, or one this reader does not know, is refused naming both."""
    known = to_si(stated)
    if known is not None and want in (None, "?", known[0]):
        return known[1]
    if stated == want:
        return 1.0
    said = f"{where} {stated!r}" if where else f"is in {stated!r}"
    if known is None:
        raise InputError(path, field, f"{said}: not a unit this reader knows (for {name!r}: {want or 'its SI unit'}, "
                         "or ms, mm, deg for time, travel, angle)")
    raise InputError(path, field, f"{said}: this channel is read in {want!r} (convert the column, or leave the "
                     "unit out of the header)")


def _header(cells, path, line, units):
    """(channel names, factors to SI) from header cells: lower-case, a stated unit converted to the
    channel's (``t [ms]``: 1e-3) or refused if it is another quantity's; None where no unit is stated."""
    names, factors = [], []
    for cell in cells:
        m = HEADER_UNIT.fullmatch(cell)
        name, unit = (m.group("name"), next(u for u in m.group("a", "b", "c") if u is not None).strip()) if m else (cell, None)
        name = name.lower()
        if not names and name in TIME_NAMES:  # the time column as an analyser heads it: Time [ms]
            name = "t"
        want = "s" if name == "t" else (units or {}).get(name)
        factors.append(None if unit is None else _factor(unit, name, want, path, f"column {cell[:40]!r}", ""))
        names.append(name)
    return names, factors


#: A cell of a units row (a logger's second header line: ``s,rad`` or ``[s];[m]``): a unit symbol,
#: bracketed or not (``µs``, ``°`` too), or ``-`` for a dimensionless channel.
UNIT_CELL = re.compile(r"[\[(]?\s*(?P<unit>°|[^\W\d_][\w/^.*]*|-|1)\s*[\])]?")
#: Names of the time column (the first) besides ``t``, lower-cased: analysers head it ``Time``.
TIME_NAMES = ("t", "time")


def _within(cells: list, width: int) -> list:
    """A row's cells without the empty ones past the header's ``width`` columns (a spreadsheet pads
    every row to its widest: ``0.001,0.17,,``); a value past them is kept, for the row's refusal."""
    return cells[:width] if len(cells) > width and not any(cells[width:]) else cells


def _units_row(cells, header, path, line, units) -> list[float] | None:
    """The factors to SI if ``cells`` is a units row under the header (every cell a unit or empty,
    none a number), else None: each unit converted or refused like a unit in the header (``m`` for
    a time is refused, naming both)."""
    cells = _within(cells, len(header))
    if len(cells) != len(header) or any(NUMBER.fullmatch(c) for c in cells) or not any(cells):
        return None
    matches = [UNIT_CELL.fullmatch(c) for c in cells]
    if not all(m or c == "" for m, c in zip(matches, cells)):
        return None
    factors = []
    for name, m in zip(header, matches):
        want = "s" if name == "t" else (units or {}).get(name)
        factors.append(None if m is None else _factor(m.group("unit"), name, want, path, f"line {line}, column {name!r}",
                                                      "the units row says"))
    return factors


def load_measurement(path: str | Path, channel: str | None = None, known: Iterable[str] | None = None,
                     units: dict[str, str] | None = None, channel_hint: str = "") -> Measurement:
    """Read and check ``NAME.csv``; ``channel``: a column the file must have; ``known``: the
    channel names a file may carry (default: any); ``units``: {channel: SI unit} that units stated in
    the header or a units row are converted to (``ms`` to ``s``, ``mm`` to ``m``, ``deg`` to ``rad``;
    a unit of another quantity is refused). Accepted variants (docs/rig-format.md): ``;`` with decimal
    commas, tabs, quoted values, a trailing delimiter, capitals, units in the header or in a row under
    it.

    Parameters
    ----------
    path : the measurement file.
    channel : a column the file must have.
    known : the channel names a file may carry (default: any).
    units : {channel: SI unit, e.g. ``rad``, ``m``} that stated units are converted to.
    channel_hint : what the refusal of a file without ``channel`` says to rename (with its columns).

    Returns
    -------
    Measurement
        ``t`` in s; each channel in its SI unit (rad, m; 0/1 for contact channels).
    """
    path = str(path)
    comments, header, header_line, factors, rows, row_lines, preamble = _parse(path, known, units)
    if len(rows) < 3:
        raise InputError(path, "data", f"needs at least 3 samples, has {len(rows)}")
    arr = np.array(rows) * np.array([1.0 if f is None else f for f in factors])
    t = arr[:, 0]
    bad = np.nonzero(np.diff(t) <= 0)[0]
    if bad.size:
        k = bad[0]
        why = ("the time starts again: a scope's segments or two records joined? One record per file"
               if t[k + 1] <= t[0] and k > 0 else "a repeated or misplaced row")
        raise InputError(path, f"line {row_lines[k + 1]}, column 't'", f"time is not strictly increasing: "
                         f"{rows[k + 1][0]:g} after {rows[k][0]:g} on line {row_lines[k]} ({why})")
    _check_sample_interval(preamble, t, path)
    channels = {col: arr[:, j] for j, col in enumerate(header) if j > 0}
    if channel is not None and channel not in channels:
        hint = f" (it has {', '.join(header)}): {channel_hint}" if channel_hint else ""
        raise InputError(path, f"line {header_line}", f"this record needs the column {channel!r}{hint}")
    return Measurement(path=path, t=t, channels=channels, comments=tuple(comments))


def _parse(path: str, known: Iterable[str] | None, units: dict[str, str] | None) -> tuple:
    """(comments, header, its line, factors to SI, rows of values, each row's line, preamble) of a
    measurement file. A line of empty cells (``;;``, as a spreadsheet exports the formatted rows below
    its data) is a blank line. Lines above a header whose first column names the time, each starting
    with text (an oscilloscope's ``Record Length,10000``), are an instrument's preamble: kept as
    comments (``Record Length: 10000``) and in ``preamble`` ({key: (line, value)})."""
    comments, rows, header, header_line, units_row, factors, row_lines = [], [], None, 0, None, [], []
    separator, preamble, clock = None, {}, {}
    dialect = (",", False)
    lines = list(_lines(path, read_bytes(path)))
    for k, (i, s) in enumerate(lines):
        if not s:
            continue
        if s.startswith(COMMENT):
            comments.append(s[1:].strip())
            continue
        if header is None and SEPARATOR_LINE.fullmatch(s):  # Excel's separator line, above the header
            separator = s[-1] if s[-1] in ";,\t" else "\t"
            continue
        if header is None:
            dialect = _dialect(s, separator)
            found = _header_or_preamble(_cells(s, *dialect), path, i, units, known, preamble, comments)
            if found is not None:
                (header, factors), header_line = found, i
            continue
        cells = _cells(s, *dialect)
        if not any(cells):
            continue
        if not rows and units_row is None:
            units_row = _units_row(cells, header, path, i, units)
            if units_row is not None:  # a logger's units row under the header, read like units in the header
                factors = _merge_units(header, factors, units_row, path, i)
                continue
            units_row = []
        values = _data_or_end(cells, header, dialect, path, i, clock, lines, k + 1, bool(rows))
        if values is None:
            break
        rows.append(values)
        row_lines.append(i)
    if header is None and preamble:
        _time_not_first(path, preamble, 0, "")
    if header is None:
        raise InputError(path, "header", "missing (no line other than comments)")
    _clock_comment(clock, factors, comments, path, header_line)
    return comments, header, header_line, factors, rows, row_lines, preamble


def _header_or_preamble(cells: list, path: str, line: int, units: dict[str, str] | None, known: Iterable[str] | None,
                        preamble: dict, comments: list) -> tuple | None:
    """(names, factors) of the header line, checked; None for a blank line or a preamble line (kept)."""
    if not any(cells):
        return None
    if not _names_time(cells[0]):
        _preamble_line(cells, path, line, preamble, comments)
        return None
    while cells[-1] == "":  # a spreadsheet's padding, empty cells after the last column (t,angle,,)
        cells = cells[:-1]
    names, factors = _header(cells, path, line, units)
    _check_header(names, path, line, known)
    return names, factors


def _names_time(cell: str) -> bool:
    """Whether a header cell names the time column (``t``, ``Time [ms]``, ``TIME``)."""
    m = HEADER_UNIT.fullmatch(cell)
    return (m.group("name") if m else cell).lower() in TIME_NAMES


def _time_not_first(path: str, preamble: dict, line: int, cell: str) -> None:
    """Refuse the header whose first column is not the time: the preamble's first line when there is
    one (no header followed it), else ``cell`` on ``line``."""
    at = min((ln for ln, _ in preamble.values()), default=line)
    name = next(iter(preamble), cell)
    raise InputError(path, f"line {at}", f"the first column must be the time, 't' or 'time', got {name[:40]!r}")


def _preamble_line(cells: list, path: str, line: int, preamble: dict, comments: list) -> None:
    """Keep a line above the header as an instrument's preamble (``Record Length,10000``), or refuse it
    as the header whose first column is not the time: a line that starts with a number (data before
    any header)."""
    if NUMBER.fullmatch(cells[0]):
        _time_not_first(path, preamble, line, cells[0])
    if len(cells) > 1 and cells[0] and all(c == "" or (UNIT_CELL.fullmatch(c) and to_si(UNIT_CELL.fullmatch(c).group("unit")))
                                           for c in cells):  # an empty cell: a channel without a unit
        above = next(((key, ln) for key, (ln, _) in preamble.items()), None)
        where = (f"; the line above it, line {above[1]}, does not start with the time ('t' or 'time'), got {above[0][:40]!r}"
                 if above else ": a units row goes right under the header (or state each unit in it: t [ms])")
        raise InputError(path, f"line {line}", f"reads as a units row ({', '.join(cells)[:40]}) with no header above it{where}")
    if cells[0] == "":
        k = next((j for j, c in enumerate(cells, start=1) if c), len(cells))
        if _names_time(cells[k - 1]):  # pandas' to_csv writes its row index first, its header cell empty
            raise InputError(path, f"line {line}", f"the first column has no name and the time is column {k}: an "
                             "index column before the time (pandas' to_csv without index=False)? Delete it: the "
                             "first column must be the time")
        raise InputError(path, f"line {line}", f"the first column is empty and the values start in column {k}: an "
                         "instrument's layout with its settings in the first columns (an older Tektronix CSV)? Keep "
                         "the time and channel columns alone, headed t and the channel")
    value = ", ".join(c for c in cells[1:] if c)
    preamble.setdefault(cells[0], (line, value))
    comments.append(f"{cells[0]}: {value}" if value else cells[0])


def _data_or_end(cells: list, header: list, dialect: tuple, path: str, line: int, clock: dict, lines: list,
                 below: int, more: bool) -> list[float] | None:
    """A data row's values (:func:`_data_row`), or None for a logger's end marker below the data (``more``:
    there are rows above; ``lines[below:]``: the lines below, read only for a row that is not data: a
    copy for every row made a 10^6-row file take hours); a bad row is refused, said to be a summary line
    where it is one."""
    try:
        return _data_row(cells, header, dialect, path, line, clock)
    except InputError as e:
        after = lines[below:]
        if more and _end_marker(cells, after):
            return None
        raise (_summary_below_the_data(e, cells, after, header, dialect, path) if more else e) from None


#: A logger's last line, alone below the data: the end of the record.
END_MARKERS = ("end", "eof", "[end]", "end of data")


def _end_marker(cells: list, rest: list) -> bool:
    """Whether ``cells`` is a logger's end marker (:data:`END_MARKERS`) with only blank or comment lines after it."""
    return (len([c for c in cells if c]) == 1 and cells[0].lower() in END_MARKERS
            and all(not s or s.startswith(COMMENT) for _, s in rest))


#: The most lines below the data that a refused row and its followers may be to be called a summary
#: (a spreadsheet's mean, max, count... under its data); more are a file whose rows are broken.
SUMMARY_LINES = 10


def _summary_below_the_data(error: InputError, cells: list, rest: list, header: list, dialect: tuple,
                            path: str) -> InputError:
    """A data row's refusal, saying so when it (``cells``) holds text and no line after it, a few at most,
    is a sample (a spreadsheet's ``Mean,0.012`` or ``6001 samples`` under the data); a last row of
    numbers (a NaN sample, a line cut short) is a broken sample, refused as such; a row that names the
    time again is a second header (two records joined in one file)."""
    if cells and _names_time(cells[0]):
        return InputError(error.path, error.field, "a second header below the data (two records joined in one "
                          "file?): give one record per file")
    if all(NUMBER.fullmatch(c) for c in cells if c) or sum(1 for _, s in rest if s and not s.startswith(COMMENT)) > SUMMARY_LINES:
        return error
    for i, s in rest:
        cells = _cells(s, *dialect) if s and not s.startswith(COMMENT) else []
        if not any(cells):
            continue
        try:
            _data_row(cells, header, dialect, path, i)
        except InputError:
            continue
        return error
    return InputError(error.path, error.field, f"{error.message}: a summary line below the data, not a sample "
                      "(delete it, or start it with '#' to keep it as a comment)")


def _check_sample_interval(preamble: dict, t: np.ndarray, path: str) -> None:
    """Refuse a record whose time steps are not the sample interval its instrument's preamble states
    (``Sample Interval,1e-05``, in the preamble's ``Horizontal Units``, seconds if absent): a time
    column in another unit, or a preamble of another record."""
    stated = preamble.get("Sample Interval")
    horizontal = preamble.get("Horizontal Units", (0, "s"))[1].strip().lower()  # a TDS's 'S' is seconds
    if stated is None or to_si(horizontal) != ("s", 1.0) or t.size < 2 or not NUMBER.fullmatch(stated[1]):
        return
    # the mean step over the record, within 1 %: a time column written to fewer digits than the interval
    # has (2.5 us steps in whole us: 2, 3, 2, 3 ...) keeps it, a step's median does not; a unit slip is
    # a factor of 1000, a scope's next interval (1-2-5 or 1-2-4) a factor of 2 or more
    step, interval = float((t[-1] - t[0]) / (t.size - 1)), float(stated[1])
    if interval > 0 and abs(step - interval) > 1e-2 * interval:
        raise InputError(path, f"line {stated[0]}", f"the preamble's sample interval {interval:g} s is not the "
                         f"data's time step {step:g} s: the time column is in another unit, or the preamble "
                         "belongs to another record")


def _merge_units(header: list, factors: list, units_row: list, path: str, line: int) -> list:
    """The header's unit factors completed by a units row's (line ``line``); refused where the two differ."""
    for name, a, b in zip(header, factors, units_row):
        if a is not None and b is not None and a != b:
            raise InputError(path, f"line {line}, column {name!r}", "the units row and the header state "
                             "different units: keep one")
    return [b if a is None else a for a, b in zip(factors, units_row)]


#: A clock time in the time column, as loggers write it: an ISO 8601 date and time
#: (``2026-11-27 10:00:00.000125``, or with ``T``) or a time of day (``10:00:00.001``).
CLOCK = re.compile(r"(\d{4}-\d{2}-\d{2}[T ])?\d{2}:\d{2}:\d{2}(\.\d{1,6})?")


def _clock_comment(clock: dict, factors: list, comments: list, path: str, line: int) -> None:
    """Say in a comment where a time column of clock times starts; refuse one that states a unit."""
    if clock.get("first") is None:
        return
    if factors[0] not in (None, 1.0):
        raise InputError(path, f"line {line}, column 't'", "holds clock times but states a unit other than s: "
                         "leave the unit out")
    first = clock["first"].isoformat(sep=" ") if clock["dated"] else clock["first"].time().isoformat()
    comments.append(f"time from the first sample's clock time, {first}")


def _clock_seconds(cell: str, clock: dict, path: str, line: int) -> float:
    """Seconds (exact to the microsecond) from the first row's clock time (kept in ``clock['first']``)
    to the clock time ``cell``; a column that mixes clock times and numbers is refused."""
    if clock.get("numbers"):
        raise InputError(path, f"line {line}, column 't'", f"a clock time {cell!r} below numbers: one kind of time per column")
    try:
        when = (dt.datetime.fromisoformat(cell) if "-" in cell else
                dt.datetime.combine(dt.date(2000, 1, 1), dt.time.fromisoformat(cell)))
    except ValueError:
        raise InputError(path, f"line {line}, column 't'", f"value {cell!r} is not a clock time") from None
    clock.setdefault("first", when)
    clock.setdefault("dated", "-" in cell)
    return (when - clock["first"]).total_seconds()


def _data_row(cells: list, header: list, dialect: tuple, path: str, line: int, clock: dict | None = None) -> list[float]:
    """One row's values: as many as the header's columns, each a finite number; the time may be a clock
    time (:data:`CLOCK`), read as seconds from the first row's (``clock`` holds it); empty cells past the
    header's columns are padding."""
    cells = _within(cells, len(header))
    if len(cells) != len(header):
        extra = len(cells) > len(header)
        # a decimal comma splits every number in two; a row whose values have decimal points holds a value
        # past the header's columns (under a column it leaves unnamed, such as a spreadsheet's padding)
        comma = extra and dialect[0] == "," and not any("." in c for c in cells)
        raise InputError(path, f"line {line}", f"has {len(cells)} values, the header has {len(header)}"
                         + (" (a decimal comma in a comma-separated file? use ';' between values)" if comma else
                            " (a value under a column the header does not name: name the column or delete the value)"
                            if extra else ""))
    clock = {} if clock is None else clock
    if CLOCK.fullmatch(cells[0]):
        values = [_clock_seconds(cells[0], clock, path, line)] + [_number(c, path, line) for c in cells[1:]]
    elif clock.get("first") is not None:
        raise InputError(path, f"line {line}, column 't'", f"a number {cells[0][:30]!r} below clock times: one kind "
                         "of time per column")
    else:
        clock["numbers"] = True
        values = [_number(c, path, line) for c in cells]
    for col, v in zip(header, values):
        if not math.isfinite(v):
            raise InputError(path, f"line {line}, column {col!r}", "value is not finite (NaN or inf)")
    return values


def _check_header(header, path, line, known):
    if header[0] != "t":
        raise InputError(path, f"line {line}", f"the first column must be the time, 't' or 'time', got {header[0][:40]!r}")
    for j, col in enumerate(header[1:], start=2):
        if col == "" or col in TIME_NAMES:
            what = "has no name" if col == "" else f"is a second time column {col!r}"
            raise InputError(path, f"line {line}, column {j}", f"{what}: two records side by side? Give one "
                             "record per file (one time column, then its channels)")
    for col in header[1:]:
        if known is not None and col not in known:
            raise InputError(path, f"column {col[:40]!r}", f"unknown channel{did_you_mean(col, known)} "
                             f"(known: {', '.join(known)})")
    if len(set(header)) != len(header):
        raise InputError(path, f"line {line}", "a column is named twice")
    if len(header) < 2:
        raise InputError(path, f"line {line}", "no measured channel after 't'")


def write_measurement(measurement: Measurement, path: str | Path) -> None:
    """Write a measurement file (comments, header, one row per sample).

    Parameters
    ----------
    measurement : ``t`` in s (written with 7 decimals, i.e. to 0.1 us) and channels in SI units
        (rad, m; 9 significant digits), written as they are: no unit conversion.
    path : the file to write (``NAME.csv``), replaced if it exists.
    """
    path = Path(path)
    names = list(measurement.channels)
    lines = [f"# {c}" for c in measurement.comments] + ["t," + ",".join(names)]
    cols = [measurement.channels[n] for n in names]
    for i, t in enumerate(measurement.t):
        lines.append(f"{t:.7f}," + ",".join(f"{c[i]:.9g}" for c in cols))
    path.write_text("\n".join(lines) + "\n")


def sibling_rig_path(measurement_path: str | Path) -> str:
    """``NAME.rig.json`` beside ``NAME.csv``."""
    p = Path(measurement_path)
    name = p.name[:-4] if p.name.endswith(".csv") else p.stem
    return str(p.with_name(name + ".rig.json"))

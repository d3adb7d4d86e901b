"""Measurement files ``NAME.csv``: ``#`` comment lines (free text), a header starting with
``t`` (s), channels in SI units (the experiment records say which channels exist). Reading refuses anything malformed with one line naming the
file and the line or column; writing is the inverse."""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..rig.reader import did_you_mean, read_bytes, text_bytes



@dataclass(frozen=True)
class Measurement:
    """A measured (or synthetic) time series: ``t`` in s, channels in SI units (rad or m)."""

    path: str
    t: np.ndarray
    channels: dict
    comments: tuple = ()

    def channel(self, name):
        return self.channels[name]

    def window(self, t0=-math.inf, t1=math.inf):
        """The samples with t0 <= t <= t1."""
        keep = (self.t >= t0) & (self.t <= t1)
        return replace(self, t=self.t[keep], channels={k: v[keep] for k, v in self.channels.items()})


def _lines(path, raw):
    """(line number, text) of each line; comment lines may hold any bytes (free text)."""
    for i, line in enumerate(text_bytes(path, raw).splitlines(), start=1):
        s = line.strip()
        if s.startswith(b"#"):
            yield i, s.decode("utf-8", errors="replace")
            continue
        try:
            yield i, s.decode("ascii")
        except UnicodeDecodeError:
            raise InputError(path, f"line {i}", "holds characters other than numbers and names") from None


def load_measurement(path, channel=None, known=None) -> Measurement:
    """Read and check ``NAME.csv``; ``channel``: a column the file must have; ``known``: the
    channel names a file may carry (default: any)."""
    path = str(path)
    comments, rows, header, header_line = [], [], None, 0
    for i, s in _lines(path, read_bytes(path)):
        if not s:
            continue
        if s.startswith("#"):
            comments.append(s[1:].strip())
            continue
        cells = [c.strip() for c in s.split(",")]
        if header is None:
            header, header_line = cells, i
            if header[0] != "t":
                raise InputError(path, f"line {i}", f"the first column must be 't', got {header[0][:40]!r}")
            for col in header[1:]:
                if known is not None and col not in known:
                    raise InputError(path, f"column {col[:40]!r}", f"unknown channel{did_you_mean(col, known)} "
                                     f"(known: {', '.join(known)})")
            if len(set(header)) != len(header):
                raise InputError(path, f"line {i}", "a column is named twice")
            if len(header) < 2:
                raise InputError(path, f"line {i}", "no measured channel after 't'")
            continue
        if len(cells) != len(header):
            raise InputError(path, f"line {i}", f"has {len(cells)} values, the header has {len(header)}")
        try:
            values = [float(c) for c in cells]
        except ValueError:
            raise InputError(path, f"line {i}", "a value is not a number") from None
        for col, v in zip(header, values):
            if not math.isfinite(v):
                raise InputError(path, f"line {i}, column {col!r}", "value is not finite (NaN or inf)")
        rows.append(values)
    if header is None:
        raise InputError(path, "header", "missing (no line other than comments)")
    if len(rows) < 3:
        raise InputError(path, "data", f"needs at least 3 samples, has {len(rows)}")
    arr = np.array(rows)
    t = arr[:, 0]
    bad = np.nonzero(np.diff(t) <= 0)[0]
    if bad.size:
        raise InputError(path, f"column 't' near t = {t[bad[0] + 1]:g}", "time is not strictly increasing")
    channels = {col: arr[:, j] for j, col in enumerate(header) if j > 0}
    if channel is not None and channel not in channels:
        raise InputError(path, f"line {header_line}", f"this record needs the column {channel!r}")
    return Measurement(path=path, t=t, channels=channels, comments=tuple(comments))


def write_measurement(measurement, path):
    """Write a measurement file (comments, header, one row per sample)."""
    path = Path(path)
    names = list(measurement.channels)
    lines = [f"# {c}" for c in measurement.comments] + ["t," + ",".join(names)]
    cols = [measurement.channels[n] for n in names]
    for i, t in enumerate(measurement.t):
        lines.append(f"{t:.7f}," + ",".join(f"{c[i]:.9g}" for c in cols))
    path.write_text("\n".join(lines) + "\n")


def sibling_rig_path(measurement_path):
    """``NAME.rig.json`` beside ``NAME.csv``."""
    p = Path(measurement_path)
    name = p.name[:-4] if p.name.endswith(".csv") else p.stem
    return str(p.with_name(name + ".rig.json"))

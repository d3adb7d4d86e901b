"""A cam given by points (``breaker.cam_profile.points`` or ``radius_points``): the checks a CAD or
CMM export needs before a spline is fitted through it, each fault one line naming the point.

A CAD export of a closed profile often repeats its first point a turn later (0 and 360 deg): that
point is the same point and is dropped when its value agrees. Anything else that is not a profile
is refused with the point's index and the likely cause: a repeated or unsorted row, angles in
degrees, values in millimetres. Points that scatter (a CMM's noise) are refused unless the rig
gives ``smoothing``, the points' uncertainty, for a smoothing spline.
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import os
import re

import numpy as np

from .. import parameters as P
from ..errors import InputError
from ..laws.cam_follower import TWO_PI
from .reader import Reader, read_bytes, text_bytes

#: Angles closer than this (rad) to a full turn apart are the same angle (a closing point)
SAME_ANGLE = 1e-6


def check_point_pairs(rd: Reader, pairs: list[tuple[float, float]], field: str) -> list[tuple[float, float]]:
    """The points ([(angle rad, value m)]) as a profile takes them: increasing angles within one
    turn, values within ``CAM_POINT_LARGEST``; a last point one turn after the first with the same
    value (a closed export) dropped. Refuses (``rd.fail``, naming ``field.i``) anything else."""
    (a0, v0), (a1, v1) = pairs[0], pairs[-1]
    if abs(a1 - a0 - TWO_PI) < SAME_ANGLE:
        if abs(v1 - v0) > P.CAM_POINT_CLOSURE:
            rd.fail(f"{field}.{len(pairs) - 1}", f"is the first point a turn later (angle {a1:.6g} rad) but its value "
                    f"differs by {1e3 * abs(v1 - v0):.3g} mm: the profile does not close")
        pairs = pairs[:-1]
    angles = [a for a, _ in pairs]
    if max(angles) - min(angles) >= TWO_PI:
        hint = (": are they in degrees? give radians (math.radians)" if max(abs(a) for a in angles) <= 360.0 + SAME_ANGLE
                else "")
        rd.fail(field, f"the angles span {max(angles) - min(angles):.4g}, more than one turn (2 pi rad){hint}")
    for i in range(1, len(pairs)):
        if angles[i] == angles[i - 1]:
            rd.fail(f"{field}.{i}", f"angle {angles[i]:.6g} rad repeats point {i - 1}'s (a duplicated row?): "
                    "give each angle once")
        if angles[i] < angles[i - 1]:
            rd.fail(f"{field}.{i}", f"angle {angles[i]:.6g} rad is below point {i - 1}'s ({angles[i - 1]:.6g}): sort "
                    "the points by angle")
    gaps = np.diff(np.append(angles, angles[0] + TWO_PI))
    k = int(np.argmax(gaps))
    if gaps[k] > P.CAM_POINT_LARGEST_GAP:
        rd.fail(field, f"the points leave {math.degrees(gaps[k]):.1f} deg of the turn without a point (after "
                f"{math.degrees(angles[k]):.4g} deg): a profile from points goes round the whole cam (its dwell and "
                "return too); are the angles in radians under a degree header?")
    i = max(range(len(pairs)), key=lambda k: abs(pairs[k][1]))
    v = pairs[i][1]
    if abs(v) > P.CAM_POINT_LARGEST:
        rd.fail(f"{field}.{i}.1", f"{v:g} m is implausible for a breaker cam (at most {P.CAM_POINT_LARGEST:g} m): "
                "is it in millimetres? values are in m")
    return pairs


def point_scatter(values: Sequence[float]) -> float:
    """The scatter (m, one standard deviation) of a closed profile's values about a smooth curve,
    from their third differences around the turn (a robust estimate: the median absolute deviation,
    scaled for normal scatter; a smooth profile's third differences are far smaller than the
    scatter's, sqrt(20) of it). Assumes roughly even angle steps, as CAD and CMM exports have."""
    v = np.asarray(values, float)
    d3 = np.diff(np.concatenate([v, v[:3]]), 3)
    return float(1.4826 * np.median(np.abs(d3 - np.median(d3))) / math.sqrt(20.0))


def settle_scatter(rd: Reader, cp: dict, angles: Sequence[float], radii: Sequence[float], field: str) -> list[float]:
    """The pitch radii (m) a spline is fitted through: as given when the points are smooth; refused
    when they scatter by more than ``CAM_POINT_SCATTER`` and no ``smoothing`` is given (a spline
    through a CMM's scatter puts it into the follower's acceleration: the roller force rises
    several-fold, the touch speed moves); with ``smoothing`` (m, the points' uncertainty), the
    values of a periodic smoothing spline that stays within about that of the points."""
    scatter = point_scatter(radii)
    prefix = field.rsplit(".", 1)[0] + "."
    if "smoothing" not in cp:
        if scatter > P.CAM_POINT_SCATTER:
            rd.fail(field, f"the points scatter by about {1e6 * scatter:.2g} um about a smooth curve (from their third "
                    "differences): a spline through them puts the scatter into the follower's acceleration; give "
                    f"{prefix}smoothing (m, the measurement's uncertainty, e.g. {scatter:.1g}) or smooth the export")
        return list(radii)
    from scipy.interpolate import splev, splrep

    smoothing = rd.number(cp, "smoothing", prefix, positive=True)
    a = np.append(np.asarray(angles, float), angles[0] + TWO_PI)
    r = np.append(np.asarray(radii, float), radii[0])
    tck = splrep(a, r, per=True, s=(len(a) - 1) * smoothing**2)
    return splev(np.asarray(angles, float), tck).tolist()


#: A points file's column: ``angle_deg``, ``angle [rad]``, ``lift (mm)``, ``radius/m``: the quantity and its unit
POINTS_COLUMN = re.compile(r"(?P<what>angle|lift|radius)\s*(?:_|\[|\(|/)?\s*(?P<unit>deg|rad|mm|m)\s*[\])]?", re.IGNORECASE)
TO_SI = {"deg": math.pi / 180.0, "rad": 1.0, "mm": 1e-3, "m": 1.0}


def points_path(rig_path: str, name: str) -> str:
    """Where a rig's ``points_file`` is: ``name`` relative to the rig file's folder."""
    return os.path.join(os.path.dirname(os.path.abspath(rig_path)), name)


def _cells(row: str, sep: str) -> list[str]:
    """A line's cells: quotes and blanks stripped, decimal commas read after ``;``, and the empty cells
    a spreadsheet leaves after the last column dropped."""
    cells = [c.strip().strip('"').strip() for c in row.split(sep)]
    while cells and cells[-1] == "":
        cells.pop()
    return [c.replace(",", ".") for c in cells] if sep == ";" else cells


#: A unit row under a header without units (``angle,lift`` then ``deg,mm``), as some exports write it
UNITS_ROW = re.compile(r"\[?\(?\s*(deg|rad|mm|m)\s*[\])]?", re.IGNORECASE)


def _columns(path: str, lines: list[tuple[int, str]]) -> tuple[str, list, list[tuple[int, str]]]:
    """(separator, the two columns' matches, the data lines) from the header, which names each column's
    unit (``angle_deg``, ``lift [mm]``) or leaves them to a unit row below it (``deg,mm``)."""
    (hline, header), rows = lines[0], lines[1:]
    sep = ";" if ";" in header else "\t" if "\t" in header else ","
    names = _cells(header, sep)
    if rows and all(UNITS_ROW.fullmatch(c) for c in _cells(rows[0][1], sep)) and len(_cells(rows[0][1], sep)) == len(names):
        units = [UNITS_ROW.fullmatch(c).group(1) for c in _cells(rows[0][1], sep)]
        names, rows = [f"{n}_{u}" for n, u in zip(names, units)], rows[1:]
    columns = [POINTS_COLUMN.fullmatch(c) for c in names]
    if len(columns) != 2 or not all(columns) or columns[0]["what"].lower() != "angle" or columns[1]["what"].lower() == "angle":
        raise InputError(path, f"line {hline}", f"the header must name two columns with their units: the angle (angle_deg "
                         f"or angle_rad), then the lift or pitch radius (lift_mm, lift_m, radius_mm, radius_m); got {header[:60]!r}")
    if columns[0]["unit"].lower() not in ("deg", "rad") or columns[1]["unit"].lower() not in ("mm", "m"):
        raise InputError(path, f"line {hline}", "the angle's unit must be deg or rad, the lift's or radius's mm or m")
    return sep, columns, rows


def read_points_file(rd: Reader, cp: dict, prefix: str) -> tuple[str, list[list[float]]]:
    """``points_file`` (a CSV beside the rig, as CAD or a CMM exports it): two columns, the cam angle
    and the lift (or pitch radius), each naming its unit in the header (``angle_deg,lift_mm``,
    ``angle [rad];radius [m]``) or in a unit row below it (``angle,lift`` then ``deg,mm``). Separators
    ``,``, ``;`` (with decimal commas) or tabs; ``#`` comments, blank lines, a byte-order mark, empty
    cells after the last column and Windows line ends are fine. Returns ("points" or "radius_points",
    [[angle rad, value m], ...]); a fault is one line naming the file and line."""
    name = cp["points_file"]
    if not isinstance(name, str) or not name:
        rd.fail(prefix + "points_file", "must be a file name (a CSV beside the rig file)")
    path = points_path(rd.path, name)
    if not os.path.exists(path):
        rd.fail(prefix + "points_file", f"{name}: no such file (a path relative to the rig file's folder)")
    lines = [(i, line.strip()) for i, line in enumerate(text_bytes(path, read_bytes(path)).splitlines(), start=1)]
    lines = [(i, line.decode("utf-8", errors="replace")) for i, line in lines if line and not line.startswith(b"#")]
    if not lines:
        raise InputError(path, "header", "missing (no line other than comments)")
    sep, columns, rows = _columns(path, lines)
    scale = [TO_SI[c["unit"].lower()] for c in columns]
    points = []
    for i, row in rows:
        try:
            values = [float(c) for c in _cells(row, sep)]
        except ValueError:
            values = []
        if len(values) != 2 or not all(math.isfinite(v) for v in values):
            raise InputError(path, f"line {i}", f"must hold two finite numbers (angle, value), got {row[:60]!r}")
        points.append([values[0] * scale[0], values[1] * scale[1]])
    return ("points" if columns[1]["what"].lower() == "lift" else "radius_points"), points

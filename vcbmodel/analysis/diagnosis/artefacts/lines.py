"""A sensor artefact (:mod:`.`): narrow spectral lines, mains pickup above all.

A narrow line far above the mechanism's own frequencies is the sensor's, not the model's: mains
pickup on a potentiometer's leads (50 or 60 Hz and harmonics), a logger's clock. Left in the
residual, it fails the whiteness tests and the diagnosis calls it unexplained physics (issue 20: a
50 Hz line gave "not explained" at 1.00x the noise). Here such a line is found in the residual,
fitted and removed, and named; the physics is judged on what remains.

:func:`find_lines` is a periodogram line test. Above ``band_hz`` (the mechanism's band: the caller
gives it, e.g. ten times a pendulum's swing frequency), the periodogram's largest ordinate over the
local level of the spectrum around it (a running median over :data:`FLOOR_BINS` bins either side,
divided by ln 2: the median of an exponential variable) is exponential with mean 1 under the null of
a smooth noise spectrum; with ``m`` frequencies tested, a line is significant when
``m exp(-ratio) < ALPHA``. The frequency is refined by maximising the projection on a sinusoid, the
amplitude and phase by linear least squares. A sensor's line is steady: its amplitude in each half
of the record must agree (within :data:`STEADY_TOLERANCE` or four standard errors); a mechanism's
residual is not (a swing dies out). A line within 1 % of a whole multiple (1..10) of 50 or 60 Hz is
named mains pickup, and its frequency is a clock witness: a record whose clock runs fast by c
shows the grid's line at f (1 + c) (grids hold their frequency to about 0.1 %).

Units: s, Hz, the record's unit (rad or m) for amplitudes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

from .protocol import ResidualView, register

#: Family-wise false-alarm probability of the line test over all frequencies tested.
ALPHA = 1e-4
#: Half-width (bins) of the running median that sets the spectrum's local level.
FLOOR_BINS = 100
#: Most lines removed from one residual.
MAX_LINES = 4
#: A steady line's amplitude in either half of the record within this fraction of the whole's.
STEADY_TOLERANCE = 0.3
#: Fewest cycles of a line in the record for the test (fewer: no frequency resolution).
MIN_CYCLES = 20
#: Mains frequencies (Hz) and the harmonics (1..MAINS_HARMONICS) recognised as pickup.
MAINS = (50.0, 60.0)
MAINS_HARMONICS = 10
#: A line within this relative distance of a mains harmonic is mains pickup.
MAINS_TOLERANCE = 0.01


@dataclass
class Line:
    """A steady sinusoid in a residual: ``frequency_hz``, ``amplitude`` (the record's unit) with
    ``amplitude_stderr``, ``phase`` (rad, of sin at the record's first time), ``power_ratio`` (the
    periodogram ordinate over the local level), ``source`` ("mains pickup" or "sensor line") and,
    for mains, ``mains_hz``/``harmonic`` and ``clock_offset`` (relative: f / (k f_mains) - 1)."""

    frequency_hz: float
    amplitude: float
    amplitude_stderr: float
    phase: float
    power_ratio: float
    source: str = "sensor line"
    mains_hz: float | None = None
    harmonic: int | None = None
    clock_offset: float | None = None

    def to_json(self) -> dict:
        return dict(self.__dict__)

    def describe(self, unit: str) -> str:
        what = (f"mains pickup ({self._ordinal()} of {self.mains_hz:g} Hz)" if self.mains_hz
                else "a steady sensor line (not mains)")
        return f"{self.frequency_hz:.2f} Hz line, {self.amplitude:.3g} {unit} amplitude: {what}"

    def _ordinal(self) -> str:
        return "fundamental" if self.harmonic == 1 else f"harmonic {self.harmonic}"


def sinusoid(t: np.ndarray, frequency: float, amplitude: float, phase: float) -> np.ndarray:
    """amplitude sin(2 pi frequency (t - t[0]) + phase)."""
    t = np.asarray(t, float)
    return amplitude * np.sin(2 * math.pi * frequency * (t - t[0]) + phase)


def _periodogram(r: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    n = r.size
    f = np.fft.rfftfreq(n, dt)
    p = np.abs(np.fft.rfft(r - np.mean(r))) ** 2 / n
    return f, p


def _local_level(p: np.ndarray, k: int) -> float:
    """The spectrum's level around bin k: a running median over FLOOR_BINS either side,
    the bins next to k left out (a line leaks into its neighbours), over ln 2."""
    lo, hi = max(1, k - FLOOR_BINS), min(p.size, k + FLOOR_BINS + 1)
    around = np.concatenate([p[lo:max(lo, k - 2)], p[min(hi, k + 3):hi]])
    return float(np.median(around) / math.log(2.0)) if around.size else float("nan")


def _fit_sinusoid(t: np.ndarray, r: np.ndarray, frequency: float) -> tuple[float, float, np.ndarray]:
    """(amplitude, phase, fitted curve) of a sinusoid of ``frequency`` with a constant."""
    w = 2 * math.pi * frequency * (t - t[0])
    X = np.column_stack([np.sin(w), np.cos(w), np.ones_like(w)])
    (a, b, _), *_ = np.linalg.lstsq(X, r, rcond=None)
    return float(math.hypot(a, b)), float(math.atan2(b, a)), X[:, :2] @ np.array([a, b])


def _refine(t: np.ndarray, r: np.ndarray, f0: float, df: float) -> float:
    """The frequency near ``f0`` (within one bin ``df``) that maximises the projection."""
    def cost(f):
        w = 2 * math.pi * f * (t - t[0])
        return -(np.dot(r, np.sin(w)) ** 2 + np.dot(r, np.cos(w)) ** 2)
    res = minimize_scalar(cost, bounds=(f0 - df, f0 + df), method="bounded", options={"xatol": df * 1e-4})
    return float(res.x)


def _steady(t: np.ndarray, r: np.ndarray, frequency: float, amplitude: float, level: float) -> bool:
    """Is the line's amplitude the same in both halves of the record?"""
    half = r.size // 2
    amps = [_fit_sinusoid(t[s], r[s], frequency)[0] for s in (slice(0, half), slice(half, None))]
    se = math.sqrt(2.0 * level / max(half, 1))  # amplitude's standard error in a half
    return all(abs(a - amplitude) <= max(STEADY_TOLERANCE * amplitude, 4 * se) for a in amps)


def name_line(frequency: float) -> dict:
    """Mains pickup when ``frequency`` is within MAINS_TOLERANCE of k x 50 or 60 Hz: {"source",
    "mains_hz", "harmonic", "clock_offset"}; otherwise a sensor line."""
    best = None
    for base in MAINS:
        k = int(round(frequency / base))
        if 1 <= k <= MAINS_HARMONICS:
            rel = frequency / (k * base) - 1.0
            if abs(rel) <= MAINS_TOLERANCE and (best is None or abs(rel) < abs(best[2])):
                best = (base, k, rel)
    if best is None:
        return {"source": "sensor line"}
    return {"source": "mains pickup", "mains_hz": best[0], "harmonic": best[1], "clock_offset": best[2]}


def find_lines(t: np.ndarray, residual: np.ndarray, band_hz: float, alpha: float = ALPHA,
               max_lines: int = MAX_LINES) -> list[Line]:
    """Steady narrow lines above ``band_hz`` (Hz) in a uniformly sampled residual (module
    docstring), strongest first; [] when the record is too short to resolve one."""
    t, r = np.asarray(t, float), np.asarray(residual, float).copy()
    if r.size < 64:
        return []
    dt = float(np.median(np.diff(t)))
    duration = r.size * dt
    lines = []
    for _ in range(max_lines):
        f, p = _periodogram(r, dt)
        tested = np.nonzero((f > band_hz) & (f >= MIN_CYCLES / duration) & (f < 0.5 / dt * 0.98))[0]
        if tested.size < 2 * FLOOR_BINS:
            break
        k = int(tested[np.argmax(p[tested])])
        level = _local_level(p, k)
        ratio = p[k] / level if level > 0 else math.inf
        if tested.size * math.exp(-min(ratio, 700.0)) >= alpha:
            break
        freq = _refine(t, r, float(f[k]), 1.0 / duration)
        amp, phase, curve = _fit_sinusoid(t, r, freq)
        if not _steady(t, r, freq, amp, level):
            break
        lines.append(Line(freq, amp, math.sqrt(2.0 * level / r.size), phase, float(ratio), **name_line(freq)))
        r = r - curve
    return lines


def remove_lines(t: np.ndarray, residual: np.ndarray, lines: list[Line]) -> np.ndarray:
    """The residual with the lines' sinusoids (refitted in amplitude and phase on it) removed."""
    t, r = np.asarray(t, float), np.asarray(residual, float).copy()
    for line in lines:
        r = r - _fit_sinusoid(t, r, line.frequency_hz)[2]
    return r


class SensorLines:
    """The artefact (:mod:`.protocol`): steady lines above the mechanism's band, fitted and removed
    (none where the experiment has no band: a 35 ms cam drop holds under two cycles of mains)."""

    name = "sensor_lines"
    order = 10

    def fit(self, view: ResidualView) -> list[Line] | None:
        if not view.band_hz:
            return None
        return find_lines(view.t, view.residual, view.band_hz) or None

    def remove(self, view: ResidualView, found: list[Line]) -> np.ndarray:
        return remove_lines(view.t, view.residual, found)

    def report(self, found: list[Line], unit: str) -> tuple[list, str]:
        data = [{**line.to_json(), "reading": line.describe(unit)} for line in found]
        text = (" The residual holds " + "; ".join(line.describe(unit) for line in found)
                + ": the sensor's, set aside (the physics is judged on what remains).")
        clock = [line for line in found if line.clock_offset is not None and abs(line.clock_offset) > 1e-3]
        if clock:
            text += (f" The mains line reads the record's clock {100 * clock[0].clock_offset:+.2f} % off "
                     "(if the grid ran at its nominal frequency, within about 0.1 %).")
        return data, text


register(SensorLines())

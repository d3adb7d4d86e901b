"""What the sensor adds to a record besides noise: narrow spectral lines and rounding.

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

:func:`timing_jitter` finds a clock that stamps each sample a little off (a camera's frame timing):
noise whose variance grows with the square of the reading's rate of change, ``j^2 v^2`` for a
jitter of ``j`` s. It is read from the residual's first differences (white jitter noise passes them
with gain 2; a smooth model error sampled densely hardly does), regressed on the model's squared
slope: a model error that grows with speed does not pass for jitter. :func:`jitter_weights` rescales the
residual to the noise level at rest, so the physics is judged on what the jitter does not explain.

:func:`quantisation_nuisance` describes a sensor's rounding (readings on a grid of step q: an
encoder's count, a logger's ADC step) for the report: its noise q / sqrt(12).

Units: s, Hz, the record's unit (rad or m) for amplitudes.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize_scalar

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


#: A jitter is named when its share of the first differences' variance is significant at this many
#: standard errors and holds at least :data:`JITTER_SHARE` of the residual's noise variance.
JITTER_Z = 4.0
JITTER_SHARE = 0.1


def timing_jitter(t: np.ndarray, residual: np.ndarray, model: np.ndarray) -> dict | None:
    """Timing jitter of the record's samples (module docstring): {"jitter_s", "stderr_s",
    "noise_at_rest", "share"} (s, s, the record's unit, fraction of the residual's variance the
    jitter makes), or None when none is found. ``model``: the model's reading at the same times."""
    t, r, m = (np.asarray(a, float) for a in (t, residual, model))
    if r.size < 50 or m.size != r.size:
        return None
    v = np.gradient(m, t)
    d1 = np.diff(r)
    X = np.column_stack([np.full(d1.size, 2.0), 2.0 * (0.5 * (v[1:] + v[:-1])) ** 2])
    coef, *_ = np.linalg.lstsq(X, d1**2, rcond=None)
    if coef[0] <= 0 or coef[1] <= 0:
        return None
    # weighted once with the fitted variance (d1^2 is chi^2(1)-like: its variance 2 fitted^2;
    # neighbouring differences share a sample: 1.5 times as many as independent ones)
    A = X / (X @ coef)[:, None]
    coef, *_ = np.linalg.lstsq(A, d1**2 / (X @ coef), rcond=None)
    cov = np.linalg.pinv(A.T @ A) * 2.0 * 1.5
    se = math.sqrt(max(cov[1, 1], 0.0))
    if coef[0] <= 0 or coef[1] <= 0 or coef[1] < JITTER_Z * se:
        return None
    share = float(coef[1] * np.mean(v**2) / (coef[0] + coef[1] * np.mean(v**2)))
    if share < JITTER_SHARE:
        return None
    j = math.sqrt(coef[1])
    return {"jitter_s": j, "stderr_s": 0.5 * se / j, "noise_at_rest": math.sqrt(coef[0]),
            "share": share, "coefficients": [float(coef[0]), float(coef[1])]}


def jitter_weights(t: np.ndarray, model: np.ndarray, jitter: dict) -> np.ndarray:
    """Factors that bring a residual with timing jitter to the noise level at rest: sqrt(s0^2 /
    (s0^2 + j^2 v^2)), v the model's slope."""
    v = np.gradient(np.asarray(model, float), np.asarray(t, float))
    c0, c1 = jitter["coefficients"]
    return np.sqrt(c0 / (c0 + c1 * v**2))


def quantisation_nuisance(step: float, sigma_hf: float) -> dict | None:
    """A quantised sensor's rounding as a nuisance for the report (None when the record is not
    on a grid): the step, its rounding noise q / sqrt(12) (the record's unit), and whether the
    rounding rules the noise (at least half the record's high-frequency level)."""
    if not step:
        return None
    rounding = step / math.sqrt(12.0)
    return {"step": float(step), "rounding_noise": rounding, "rounding_dominates": bool(rounding >= 0.5 * sigma_hf),
            "reading": "readings on a grid: an encoder's count or a data logger's step"}

"""Signal analysis for identification and diagnosis: noise, peaks, decay, windows.

Pure functions of sampled data (``t`` in s, values in the channel's unit: rad or m).
"""
from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np
from scipy.stats import chi2, kstwobign


def noise_estimate(y: np.ndarray) -> float:
    """Sensor noise sigma (same unit as ``y``) from the data alone.

    Third differences of a smooth signal sampled densely are almost pure noise:
    ``d3 = y[i+3] - 3 y[i+2] + 3 y[i+1] - y[i]`` has variance ``20 sigma^2`` for white noise.
    A median absolute deviation makes the estimate robust to the few samples at kinks
    (stick-slip transitions).
    """
    y = np.asarray(y, float)
    if y.size < 8:
        return float("nan")
    d3 = y[3:] - 3 * y[2:-1] + 3 * y[1:-2] - y[:-3]
    mad = np.median(np.abs(d3 - np.median(d3)))
    return float(1.4826 * mad / math.sqrt(20.0))


def turning_points(y: np.ndarray, reversal: float) -> np.ndarray:
    """Indices of the alternating extremes of ``y``: a running maximum (minimum) becomes a turning
    point once ``y`` has come back from it by more than ``reversal`` (same unit as ``y``). The first
    sample counts as one when the signal leaves it (a release); the last candidate, which the record
    may have cut mid-swing, does not."""
    y = np.asarray(y, float)
    points: list[int] = []
    lo = hi = 0
    direction = 0
    for i in range(1, y.size):
        if direction >= 0 and y[i] > y[hi]:
            hi = i
        if direction <= 0 and y[i] < y[lo]:
            lo = i
        if direction >= 0 and y[hi] - y[i] > reversal:
            points.append(hi)
            direction, lo = -1, i
        elif direction <= 0 and y[i] - y[lo] > reversal:
            points.append(lo)
            direction, hi = 1, i
    return np.array(points, dtype=int)


def swing_centre(y: np.ndarray, sigma: float) -> float:
    """The angle (same unit as ``y``) a free swing turns about.

    Where the swing has stopped within the record (its last 5 % moves by no more than ten noise
    levels or 1 % of the record's span), the median of that stretch: the angle it stuck at. Where it
    is still swinging, that median is wherever the record happens to end, so the centre comes from the
    turning points p_i instead: the median of (p_i + 2 p_(i+1) + p_(i+2)) / 4, in which an amplitude
    that shrinks steadily from one extreme to the next cancels; the mid-point of two; the tail's
    median when the record holds fewer."""
    y = np.asarray(y, float)
    tail = y[-max(10, y.size // 20):]
    span = float(np.ptp(y)) if y.size else 0.0
    still = max(10 * sigma, 0.01 * span) if math.isfinite(sigma) else 0.01 * span
    if float(np.ptp(tail)) <= still:
        return float(np.median(tail))
    p = y[turning_points(y, still)]
    if p.size >= 3:
        return float(np.median((p[:-2] + 2 * p[1:-1] + p[2:]) / 4))
    return float(0.5 * (p[0] + p[1])) if p.size == 2 else float(np.median(tail))


def swing_peaks(t: np.ndarray, angle: np.ndarray, min_separation: float = 0.1, signed: bool = False) -> tuple[np.ndarray, ...]:
    """Extreme values of a free swing: returns (times, |amplitudes|) of alternating peaks,
    and with ``signed`` also the angle values at the peaks.

    A peak is the largest |angle - centre| between two crossings of the centre the swing turns
    about (:func:`swing_centre`); peaks below three noise levels are dropped, and so is a peak
    less than ``min_separation`` s after the one before, and the last sample (a record that ends
    mid-swing has its largest deviation there, which is no turning point).
    """
    t, y = np.asarray(t), np.asarray(angle, float)
    sigma = noise_estimate(y)
    z = y - swing_centre(y, sigma)
    sign = np.sign(z)
    crossings = np.nonzero(np.diff(sign) != 0)[0]
    bounds = np.concatenate([[0], crossings + 1, [y.size]])
    times, amps, vals = [], [], []
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b - a < 3:
            continue
        i = a + int(np.argmax(np.abs(z[a:b])))
        if i < y.size - 1 and abs(z[i]) > 3 * sigma and (not times or t[i] - times[-1] >= min_separation):
            times.append(t[i])
            amps.append(abs(z[i]))
            vals.append(y[i])
    if signed:
        return np.array(times), np.array(amps), np.array(vals)
    return np.array(times), np.array(amps)


def extreme_time(t: np.ndarray, y: np.ndarray, tk: float, half_period: float) -> float:
    """The time (s) of a swing's extreme near ``tk``, from a parabola fitted to the samples within
    a sixth of a half period of it (a quantised sensor holds the extreme for several samples, and
    noise moves the largest sample by many samples); ``tk`` when the parabola's vertex lies outside."""
    w = half_period / 6
    sel = (t >= tk - w) & (t <= tk + w)
    if sel.sum() < 5:
        return tk
    c = np.polyfit(t[sel] - tk, y[sel], 2)
    if c[0] == 0:
        return tk
    vertex = -c[1] / (2 * c[0])
    return float(tk + vertex) if abs(vertex) < w else tk


def complete_swing_extremes(t: np.ndarray, angle: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(times s, |amplitudes|, signed values) of the swing's extremes that the record holds whole,
    each timed by a parabola through its top (:func:`extreme_time`).

    An extreme within a sixth of a half period of either end of the record is left out: a record
    that ends (or starts) mid-swing puts its largest sample at its edge, which is no turning point,
    and a pair of such edge "extremes" drags a drift of the extremes' times (a period mismatch)
    toward zero. Only turning points with the samples to time them on both sides are kept."""
    t, y = np.asarray(t, float), np.asarray(angle, float)
    tp, amp, vals = swing_peaks(t, y, signed=True)
    if tp.size < 2:
        return tp, amp, vals
    half = float(np.median(np.diff(tp)))
    inner = (tp - t[0] >= half / 6) & (t[-1] - tp >= half / 6)
    times = np.array([extreme_time(t, y, tk, half) for tk in tp[inner]])
    return times, amp[inner], vals[inner]


def decay_shape(peak_times: np.ndarray, amplitudes: np.ndarray) -> dict:
    """Compare linear (Coulomb) and exponential (viscous) fits of the peak envelope.

    Returns a dict with the slope of the linear fit (rad/s), the decay rate of the
    exponential fit (1/s) and the rms misfit of each (rad); ``shape`` names the better one.
    """
    t, a = np.asarray(peak_times), np.asarray(amplitudes)
    if t.size < 3:
        return {"shape": "unknown", "peaks": int(t.size)}
    lin = np.polyfit(t, a, 1)
    lin_rms = float(np.sqrt(np.mean((np.polyval(lin, t) - a) ** 2)))
    ex = np.polyfit(t, np.log(a), 1)
    exp_rms = float(np.sqrt(np.mean((np.exp(np.polyval(ex, t)) - a) ** 2)))
    return {"shape": "linear" if lin_rms < exp_rms else "exponential", "peaks": int(t.size),
            "linear_slope": float(lin[0]), "linear_rms": lin_rms,
            "exponential_rate": float(-ex[0]), "exponential_rms": exp_rms}


def running_rms(residual: np.ndarray, width: int) -> np.ndarray:
    """Centred moving rms of ``residual`` over ``width`` samples."""
    r2 = np.asarray(residual, float) ** 2
    width = max(1, min(int(width), r2.size))
    kernel = np.ones(width) / width
    return np.sqrt(np.convolve(r2, kernel, mode="same"))


def stands_out(peak: float, sigma: float) -> bool:
    """Whether a residual's running-rms peak (:func:`disagreement_window`'s) stands out of noise of
    standard deviation ``sigma``: above twice it, the level the window is cut at."""
    return peak > 2.0 * sigma


def disagreement_window(t: np.ndarray, residual: np.ndarray, sigma: float, width: int | None = None) -> tuple[float, float, float]:
    """The time window [t0, t1] (s) around the largest disagreement.

    The running rms of the residual (over ~2 % of the record) is compared with the noise
    level; the window is the contiguous stretch around its maximum where it stays above
    ``max(2 sigma, half the maximum)``, widened by half the running window on each side (the
    samples its values average). Where nothing stands out (the peak below 2 sigma, a residual at
    its noise) it is the running window around the peak: never a window of zero width. Returns
    (t0, t1, peak_running_rms); :func:`stands_out` tells whether the peak stands out.
    """
    t = np.asarray(t)
    width = width or max(5, t.size // 50)
    rr = running_rms(residual, width)
    i = int(np.argmax(rr))
    level = max(2 * sigma, 0.5 * rr[i])
    above = rr >= level
    a = i
    while a > 0 and above[a - 1]:
        a -= 1
    b = i
    while b < t.size - 1 and above[b + 1]:
        b += 1
    half = max(1, min(width, t.size) // 2)
    return float(t[max(0, a - half)]), float(t[min(t.size - 1, b + half)]), float(rr[i])


def dominant_frequency(t: np.ndarray, residual: np.ndarray) -> float:
    """Frequency (Hz) of the largest spectral peak of the detrended residual."""
    t, r = np.asarray(t), np.asarray(residual, float)
    if r.size < 16:
        return float("nan")
    r = r - np.polyval(np.polyfit(t, r, 2), t)
    spec = np.abs(np.fft.rfft(r * np.hanning(r.size)))
    freqs = np.fft.rfftfreq(r.size, d=float(np.mean(np.diff(t))))
    spec[0] = 0
    return float(freqs[int(np.argmax(spec))])


def lag1_autocorrelation(residual: np.ndarray) -> float:
    """Lag-one autocorrelation of the residual: about 0 when it is white noise."""
    r = np.asarray(residual, float) - np.mean(residual)
    den = float(np.dot(r, r))
    return float(np.dot(r[1:], r[:-1]) / den) if den > 0 else 0.0


def swing_spans(t: np.ndarray, angle: np.ndarray, sigma: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The clear part of a free swing: (mid times, spans) with span_i = |p_i - p_(i+1)|
    between successive extremes, from the release on, while spans exceed 20 noise levels
    and extremes follow each other at a regular half period. Empty arrays if none."""
    t = np.asarray(t)
    sigma = noise_estimate(angle) if sigma is None else sigma
    tp, _, values = swing_peaks(t, angle, signed=True)
    if tp.size < 2:
        return np.zeros(0), np.zeros(0), np.zeros(0)
    spans = np.abs(np.diff(values))
    gaps = np.diff(tp)
    n = 0
    while n < spans.size and spans[n] > 20 * sigma and gaps[n] < 1.5 * gaps[0]:
        n += 1
    return 0.5 * (tp[:n] + tp[1:n + 1]), spans[:n], gaps[:n]


def motion_end_time(t: np.ndarray, angle: np.ndarray, sigma: float | None = None) -> float:
    """Time (s) when a free swing visibly stops: the end of :func:`swing_spans` plus half
    a swing; ``t[-1]`` if it never stops."""
    t = np.asarray(t)
    mid, spans, gaps = swing_spans(t, angle, sigma)
    if spans.size == 0:
        return float(t[-1])
    return float(min(t[-1], mid[-1] + 1.5 * np.median(gaps)))


def first_peak_amplitude(t: np.ndarray, angle: np.ndarray) -> float:
    """Amplitude (rad) of the first extreme of a free swing after release (the paper's 0.15 rad)."""
    tp, ap = swing_peaks(t, angle)
    later = ap[tp > t[0] + 0.05 * (t[-1] - t[0]) / 6] if tp.size else ap
    return float(later[0]) if later.size else float(np.max(np.abs(angle)))


# --- sensors that are not ideal: quantisation, correlated noise, a record that starts early ----------

def quantisation_step(y: np.ndarray, max_levels_fraction: float = 0.25) -> float:
    """The step (same unit as ``y``) of a quantised sensor (an encoder, a digitiser with few
    bits), or 0.0 when the values do not lie on a grid.

    A quantised record takes few distinct values (at most ``max_levels_fraction`` of its
    samples) and its distinct values are whole multiples of the smallest gap between them
    (within 2 % of that gap: a gain applied after quantising keeps the grid uniform).
    """
    y = np.asarray(y, float)
    if y.size < 20:
        return 0.0
    levels = np.unique(y)
    if levels.size < 3 or levels.size > max_levels_fraction * y.size:
        return 0.0
    gaps = np.diff(levels)
    q = float(np.min(gaps))
    span = float(levels[-1] - levels[0])
    if q <= 1e-12 * max(span, 1e-300):
        return 0.0
    ratio = gaps / q
    if np.max(np.abs(ratio - np.round(ratio))) > 0.02:
        return 0.0
    return q


def noise_estimate_floored(y: np.ndarray, quantisation: float | None = None) -> float:
    """:func:`noise_estimate`, but never below the rounding noise of a quantised sensor,
    ``q / sqrt(12)`` (a quantised record that moves slowly or not at all has third
    differences that are mostly exactly zero: the median would say "no noise")."""
    q = quantisation_step(y) if quantisation is None else quantisation
    s = noise_estimate(y)
    if not math.isfinite(s):
        s = 0.0
    return float(max(s, q / math.sqrt(12.0)))


def autocovariance(x: np.ndarray, max_lag: int) -> np.ndarray:
    """Biased sample autocovariances of ``x`` (mean removed) at lags 0..max_lag."""
    x = np.asarray(x, float)
    x = x - np.mean(x)
    n = x.size
    max_lag = min(max_lag, n - 1)
    # FFT autocorrelation: O(n log n) for long records
    m = 1 << int(np.ceil(np.log2(2 * n)))
    f = np.fft.rfft(x, m)
    acov = np.fft.irfft(f * np.conj(f), m)[:max_lag + 1] / n
    return acov


def levinson(acov: np.ndarray, order: int) -> tuple[np.ndarray, float]:
    """AR coefficients a_1..a_p and innovation variance from autocovariances (Yule-Walker by
    the Levinson-Durbin recursion): x_t = sum a_k x_(t-k) + u_t."""
    a = np.zeros(0)
    err = float(acov[0])
    for k in range(1, order + 1):
        if err <= 0:
            break
        lam = (acov[k] - np.dot(a, acov[k - 1:0:-1])) / err if k > 1 else acov[1] / err
        a = np.concatenate([a - lam * a[::-1], [lam]])
        err *= (1 - lam**2)
    return a, max(err, 0.0)


def ar_fit(segments: Sequence[np.ndarray], max_order: int = 3) -> tuple[np.ndarray, float, float]:
    """Fit an autoregressive model of order 0..``max_order`` to one or more residual segments
    (pooled autocovariances), the order chosen by BIC. Returns (coefficients, innovation
    variance, marginal variance)."""
    segments = [np.asarray(s, float) for s in segments if np.asarray(s).size > max_order + 2]
    if not segments:
        return np.zeros(0), 0.0, 0.0
    n = sum(s.size for s in segments)
    acov = sum(autocovariance(s, max_order) * s.size for s in segments) / n
    best = None
    for p in range(max_order + 1):
        a, err = levinson(acov, p)
        if err <= 0:
            continue
        bic = n * math.log(err) + p * math.log(n)
        if best is None or bic < best[0] - 1e-9:
            best = (bic, a, err)
    if best is None:
        return np.zeros(0), 0.0, float(acov[0])
    return best[1], best[2], float(acov[0])


def ar_whiten(x: np.ndarray, coefficients: np.ndarray) -> np.ndarray:
    """Innovations u_t = x_t - sum a_k x_(t-k) for t >= p (the first p samples are dropped)."""
    x = np.asarray(x, float)
    p = len(coefficients)
    if p == 0:
        return x.copy()
    if x.size <= p:
        return np.zeros(0)
    u = x[p:].copy()
    for k, a in enumerate(coefficients, start=1):
        u -= a * x[p - k:x.size - k]
    return u


def ar_autocorrelation(coefficients: np.ndarray, lags: int) -> np.ndarray:
    """Autocorrelation at lags 1..lags of the AR process with these coefficients (remembered for the
    last 64 asked: a diagnosis scores every fit under one noise model)."""
    return _ar_autocorrelation(tuple(float(c) for c in np.ravel(coefficients)), int(lags)).copy()


@functools.lru_cache(maxsize=64)
def _ar_autocorrelation(coefficients: tuple, lags: int) -> np.ndarray:
    a = np.array(coefficients, float)
    p = a.size
    if p == 0:
        return np.zeros(lags)
    # simulate the impulse response long enough and correlate it
    n = 4096
    h = np.zeros(n)
    h[0] = 1.0
    for t in range(1, n):
        k = min(p, t)
        h[t] = np.dot(a[:k], h[t - 1::-1][:k])
    g0 = np.dot(h, h)
    return np.array([np.dot(h[:-k], h[k:]) / g0 for k in range(1, lags + 1)])


def ljung_box(x: np.ndarray, lags: int) -> tuple[float, float]:
    """Ljung-Box portmanteau statistic of ``x`` over lags 1..``lags`` and its p-value
    (chi-square with ``lags`` degrees of freedom): small p means not white."""

    x = np.asarray(x, float)
    n = x.size
    lags = int(max(1, min(lags, n // 4)))
    acov = autocovariance(x, lags)
    if acov[0] <= 0:
        return 0.0, 1.0
    rho = acov[1:] / acov[0]
    q = float(n * (n + 2) * np.sum(rho**2 / (n - np.arange(1, lags + 1))))
    return q, float(chi2.sf(q, lags))


def cumulative_periodogram_test(x: np.ndarray) -> tuple[float, float]:
    """Bartlett's cumulative-periodogram test of whiteness: the largest deviation of the
    normalised cumulative periodogram from a straight line, and its p-value (Kolmogorov).
    Sensitive to power concentrated at low frequencies (slow structure left in a residual)."""

    x = np.asarray(x, float) - np.mean(x)
    spec = np.abs(np.fft.rfft(x)) ** 2
    spec = spec[1:(x.size + 1) // 2]  # drop the mean and the Nyquist bin
    m = spec.size
    if m < 4 or spec.sum() <= 0:
        return 0.0, 1.0
    c = np.cumsum(spec) / spec.sum()
    d = float(np.max(np.abs(c - np.arange(1, m + 1) / m)))
    return d, float(kstwobign.sf(d * (math.sqrt(m) + 0.12 + 0.11 / math.sqrt(m))))


def motion_onset(t: np.ndarray, y: np.ndarray, sigma: float, k: float = 6.0, hold: int = 5) -> tuple[int, float, bool]:
    """Index where a record that starts at rest begins to move: the first sample after which
    |y - level| stays above ``k`` sigma for ``hold`` samples, ``level`` the median of the samples
    before it. Returns (index, level, still) with ``still`` False when the record moves from its
    first samples (a hand-driven start, or no pre-trigger at all)."""
    y = np.asarray(y, float)
    n = y.size
    sigma = max(sigma, 1e-300)
    head = 5  # a first level from a few samples (a record may start right at the release)
    level = float(np.median(y[:head]))
    out = np.abs(y - level) > k * sigma
    # first run of `hold` consecutive outliers
    run = np.convolve(out.astype(int), np.ones(hold, int), mode="valid")
    idx = np.nonzero(run == hold)[0]
    i = int(idx[0]) if idx.size else n - 1
    if i >= head:  # refine the level on everything before the onset
        level = float(np.median(y[:i]))
    still = i >= 8 and float(np.std(y[:i])) < 3 * sigma
    return i, level, still

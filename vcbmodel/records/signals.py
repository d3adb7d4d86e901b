"""Signal analysis for identification and diagnosis: noise, peaks, decay, windows.

Pure functions of sampled data (``t`` in s, values in the channel's unit: rad or m).
"""
from __future__ import annotations

import math

import numpy as np


def noise_estimate(y):
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


def swing_peaks(t, angle, min_separation=0.1, signed=False):
    """Extreme values of a free swing: returns (times, |amplitudes|) of alternating peaks,
    and with ``signed`` also the angle values at the peaks.

    A peak is the largest |angle| between two zero crossings of the (median-filtered)
    angle about its final rest value; peaks below three noise levels are dropped.
    """
    t, y = np.asarray(t), np.asarray(angle)
    sigma = noise_estimate(y)
    rest = np.median(y[-max(10, y.size // 20):])
    z = y - rest
    sign = np.sign(z)
    crossings = np.nonzero(np.diff(sign) != 0)[0]
    bounds = np.concatenate([[0], crossings + 1, [y.size]])
    times, amps, vals = [], [], []
    for a, b in zip(bounds[:-1], bounds[1:]):
        if b - a < 3:
            continue
        i = a + int(np.argmax(np.abs(z[a:b])))
        if abs(z[i]) > 3 * sigma and (not times or t[i] - times[-1] >= min_separation):
            times.append(t[i])
            amps.append(abs(z[i]))
            vals.append(y[i])
    if signed:
        return np.array(times), np.array(amps), np.array(vals)
    return np.array(times), np.array(amps)


def decay_shape(peak_times, amplitudes):
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


def running_rms(residual, width):
    """Centred moving rms of ``residual`` over ``width`` samples."""
    r2 = np.asarray(residual, float) ** 2
    width = max(1, min(int(width), r2.size))
    kernel = np.ones(width) / width
    return np.sqrt(np.convolve(r2, kernel, mode="same"))


def disagreement_window(t, residual, sigma, width=None):
    """The time window [t0, t1] (s) around the largest disagreement.

    The running rms of the residual (over ~2 % of the record) is compared with the noise
    level; the window is the contiguous stretch around its maximum where it stays above
    ``max(2 sigma, half the maximum)``. Returns (t0, t1, peak_running_rms).
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
    return float(t[a]), float(t[b]), float(rr[i])


def dominant_frequency(t, residual):
    """Frequency (Hz) of the largest spectral peak of the detrended residual."""
    t, r = np.asarray(t), np.asarray(residual, float)
    if r.size < 16:
        return float("nan")
    r = r - np.polyval(np.polyfit(t, r, 2), t)
    spec = np.abs(np.fft.rfft(r * np.hanning(r.size)))
    freqs = np.fft.rfftfreq(r.size, d=float(np.mean(np.diff(t))))
    spec[0] = 0
    return float(freqs[int(np.argmax(spec))])


def lag1_autocorrelation(residual):
    """Lag-one autocorrelation of the residual: about 0 when it is white noise."""
    r = np.asarray(residual, float) - np.mean(residual)
    den = float(np.dot(r, r))
    return float(np.dot(r[1:], r[:-1]) / den) if den > 0 else 0.0


def swing_spans(t, angle, sigma=None):
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


def motion_end_time(t, angle, sigma=None):
    """Time (s) when a free swing visibly stops: the end of :func:`swing_spans` plus half
    a swing; ``t[-1]`` if it never stops."""
    t = np.asarray(t)
    mid, spans, gaps = swing_spans(t, angle, sigma)
    if spans.size == 0:
        return float(t[-1])
    return float(min(t[-1], mid[-1] + 1.5 * np.median(gaps)))


def first_peak_amplitude(t, angle):
    """Amplitude (rad) of the first extreme of a free swing after release (the paper's 0.15 rad)."""
    tp, ap = swing_peaks(t, angle)
    later = ap[tp > t[0] + 0.05 * (t[-1] - t[0]) / 6] if tp.size else ap
    return float(later[0]) if later.size else float(np.max(np.abs(angle)))

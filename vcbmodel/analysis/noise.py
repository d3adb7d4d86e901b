"""The noise model of a record, and whether a residual is consistent with it.

Real sensors do not give white noise: a potentiometer behind a low-pass filter, a camera's
tracking, an encoder's rounding all leave noise whose samples are correlated. Treating such a
record as white overstates the evidence of every model change by the factor (1 + phi) / (1 - phi)
(19x at a lag-1 correlation phi of 0.9): the diagnosis would name effects that only fit noise.

The model here is an autoregressive process of order 0..3 (chosen by BIC), fitted to the
residual of the most complete model the diagnosis has fitted: ``r_t = sum a_k r_(t-k) + u_t`` with
white innovations ``u`` of standard deviation ``sigma``. Comparisons of models use the whitened
residual (the exact Gaussian likelihood of the AR process, conditional on its first p samples),
so chi^2 = sum u_t^2 / sigma^2 counts independent pieces of evidence only. Two floors keep the
innovation level honest: the rounding noise of a quantised sensor (q / sqrt(12)) and the level
implied by the record's own high-frequency content (third differences, model-free).

:func:`consistency` decides whether a residual is what this noise alone would leave: its
whitened form must be white (Ljung-Box over ``lags`` lags and Bartlett's cumulative periodogram,
both at the 1 % level), or hold at most :data:`STRUCTURE_TOLERANCE` more variance than the
record's model-free noise level; and its high-frequency level must match that estimate. For a
quantised sensor, rounding is deterministic, not white: there the residual must instead stay
within the rounding band (+-q/2 plus the other noise) once smoothed.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from ..records.signals import (ar_autocorrelation, ar_fit, ar_whiten, cumulative_periodogram_test, levinson,
                               ljung_box, running_rms)

#: Largest AR order tried.
MAX_ORDER = 3
#: Significance level of the whiteness tests (each).
ALPHA = 0.01
#: A residual that fails the whiteness tests still counts as noise when its mean square exceeds
#: the record's model-free (high-frequency) noise variance by at most this fraction (its rms by
#: at most 5 %): structure that small is below what any registered effect could be told from.
STRUCTURE_TOLERANCE = 0.1


def third_difference_gain(coefficients: np.ndarray) -> float:
    """Variance of the third difference of a unit-innovation AR process (white: 20)."""
    rho = np.concatenate([[1.0], ar_autocorrelation(coefficients, 3)])
    var = marginal_variance(coefficients)
    h = np.array([1.0, -3.0, 3.0, -1.0])
    return float(var * sum(h[i] * h[j] * rho[abs(i - j)] for i in range(4) for j in range(4)))


def marginal_variance(coefficients: np.ndarray) -> float:
    """Variance of a unit-innovation AR process (1 for white noise)."""
    a = np.asarray(coefficients, float)
    if a.size == 0:
        return 1.0
    rho = ar_autocorrelation(a, a.size)
    den = 1.0 - float(np.dot(a, rho))
    return 1.0 / den if den > 1e-12 else 1e12


@dataclass
class NoiseModel:
    """AR noise: coefficients ``ar`` (a_1..a_p), innovation sd ``sigma`` (the record's unit),
    ``quantisation`` step (0: none), ``high_frequency`` (the model-free white-equivalent level
    from third differences)."""

    sigma: float
    ar: tuple = ()
    quantisation: float = 0.0
    high_frequency: float = 0.0
    source: str = "record"
    details: dict = field(default_factory=dict)

    @classmethod
    def white(cls, sigma: float, quantisation: float = 0.0, source: str = "record (third differences)") -> NoiseModel:
        return cls(float(sigma), (), float(quantisation), float(sigma), source)

    @property
    def order(self) -> int:
        return len(self.ar)

    @property
    def marginal_sd(self) -> float:
        """Standard deviation of the noise itself (not its innovations)."""
        return self.sigma * math.sqrt(marginal_variance(self.ar))

    @property
    def lag1(self) -> float:
        """The noise's lag-1 autocorrelation (0 for white noise)."""
        return float(ar_autocorrelation(self.ar, 1)[0]) if self.ar else 0.0

    @property
    def variance_inflation(self) -> float:
        """How much the variance of a long average exceeds the white-noise value (the
        ratio n / n_eff of an effective sample size): sum of all autocorrelations."""
        a = np.asarray(self.ar, float)
        if a.size == 0:
            return 1.0
        # spectral density at zero over the variance: (1 / (1 - sum a)^2) / marginal variance
        return float(1.0 / (1.0 - a.sum()) ** 2 / marginal_variance(a))

    def whiten(self, residual: np.ndarray) -> np.ndarray:
        """Innovations of one contiguous residual segment, in units of sigma."""
        return ar_whiten(residual, self.ar) / self.sigma

    def chi2(self, segments: Sequence[np.ndarray], weights: Sequence[np.ndarray] | None = None) -> float:
        """sum of squared whitened residuals over contiguous segments (each whitened alone); with
        ``weights`` (one array per segment, a weight per sample), each whitened sample weighted by
        its sample's (the first p samples have no innovation)."""
        if weights is None:
            return float(sum(np.sum(self.whiten(s) ** 2) for s in segments))
        p = self.order
        return float(sum(np.sum(w[p:] * self.whiten(s) ** 2) for w, s in zip(weights, segments) if np.size(s) > p))

    @property
    def other_than_rounding(self) -> float:
        """The record's high-frequency noise level less a quantised sensor's rounding noise (q / sqrt(12))."""
        return math.sqrt(max(self.high_frequency**2 - self.quantisation**2 / 12.0, 0.0))

    def n_data(self, segments: Sequence[np.ndarray]) -> int:
        return int(sum(max(0, np.asarray(s).size - self.order) for s in segments))

    def to_json(self) -> dict:
        return {"sigma_innovation": self.sigma, "sigma": self.marginal_sd, "ar": [float(a) for a in self.ar],
                "lag1_correlation": self.lag1, "quantisation_step": self.quantisation,
                "high_frequency_sigma": self.high_frequency, "source": self.source}


def fit_noise(segments: Sequence[np.ndarray], high_frequency: float, quantisation: float = 0.0, source: str = "residual") -> NoiseModel:
    """An AR noise model fitted to residual segments, with the innovation level floored by the
    quantisation (q / sqrt(12)) and by what the model-free high-frequency level implies for this
    correlation (a residual cannot hold less noise than the record's own third differences)."""
    a, innovation_var, _ = ar_fit(segments, MAX_ORDER)
    a = tuple(float(x) for x in a)
    sigma = math.sqrt(max(innovation_var, 0.0))
    floor_q = quantisation / math.sqrt(12.0)
    gain = third_difference_gain(a)
    floor_hf = high_frequency * math.sqrt(20.0 / gain) if gain > 0 else high_frequency
    floor = max(floor_q, 0.7 * floor_hf)
    details = {"fitted_innovation_sigma": sigma, "floor": floor}
    return NoiseModel(max(sigma, floor, 1e-300), a, quantisation, high_frequency, source, details)


def rounding_dominates(quantisation: float, high_frequency: float) -> bool:
    """Is a quantised sensor's rounding noise, q / sqrt(12), at least half the record's
    high-frequency noise? Then rounding (deterministic) rules the residual, not white noise."""
    return quantisation > 0 and quantisation / math.sqrt(12.0) >= 0.5 * high_frequency


def run_lengths(values: np.ndarray, quantisation: float) -> np.ndarray:
    """For each sample of ``values`` (one contiguous segment of a recorded channel), the length of
    the run of identical recorded values it belongs to: consecutive samples less than half a
    quantisation step apart are one value. All ones when ``quantisation`` is 0 (no grid)."""
    y = np.asarray(values, float)
    if quantisation <= 0 or y.size == 0:
        return np.ones(y.size)
    starts = np.concatenate([[0], np.nonzero(np.abs(np.diff(y)) >= 0.5 * quantisation)[0] + 1, [y.size]])
    lengths = np.diff(starts)
    return np.repeat(lengths, lengths).astype(float)


def recorded_values(fit) -> list[np.ndarray]:
    """The recorded measured channel on each of ``fit``'s residual segments (model - residual)."""
    out = []
    for sim, t, r in zip(fit.simulations, fit.times, fit.residuals):
        idx = np.clip(np.searchsorted(sim.t, t), 0, sim.t.size - 1)
        out.append(np.asarray(sim.measured, float)[idx] - np.asarray(r, float))
    return out


def rounding_weights(values: np.ndarray, quantisation: float, other_noise: float) -> np.ndarray:
    """Each sample's share of independent evidence on a rounded record: 1 - rho (1 - 1 / L), L the
    length of its run of identical recorded values and rho = exp(-2 pi^2 s^2 / q^2) the share of the
    rounding that other noise of level s (``other_noise``) leaves correlated (see :func:`rounding_bic`).
    All ones when ``quantisation`` is 0."""
    lengths = run_lengths(values, quantisation)
    if quantisation <= 0:
        return lengths
    rho = math.exp(-2.0 * math.pi**2 * (other_noise / quantisation) ** 2)
    return 1.0 - rho * (1.0 - 1.0 / lengths)


def rounding_bic(fit, noise: NoiseModel | None) -> float:
    """BIC of ``fit`` that counts a rounded record's evidence once per rounding error: each
    whitened sample weighted by w = 1 - rho (1 - 1 / L) (:func:`rounding_weights`), L the length of
    its run of identical recorded values, and the penalty k ln n_eff with n_eff = sum w.

    Rounding is white noise of variance q^2 / 12, independent of the signal and between samples,
    only while the signal moves by many steps between samples or other noise dithers it (Widrow &
    Kollar, *Quantization Noise*, Cambridge 2008, ch. 4-6 on the quantisation theorems and ch. 19 on
    dither). Where a record moves slowly, as a pendulum near its turning points, the signal stays
    within one step for L samples: without other noise the L rounding errors are one deterministic
    error read L times, and their chi^2 counts one piece of evidence L times. A model that can bend
    the trajectory at low speed (a Stribeck fall, air drag) then "fits" the rounding and wins by
    hundreds. Weighting by 1 / L is the effective-sample-size correction for a run of fully
    correlated errors (the variance of a mean of L identical errors is L times the independent
    one's; Bayley & Hammersley, JRSS B 8, 1946): each run counts as one sample. Gaussian noise of
    level s added before the rounding makes the rounding error independent of the signal to the
    degree the noise's characteristic function vanishes at the quantiser's first harmonic, 2 pi /
    q: rho = exp(-2 pi^2 s^2 / q^2) (Widrow & Kollar's QT condition; 0.007 at s = q / 2, when
    rounding is practically white). ``rho`` interpolates between the two limits; s is the record's
    model-free high-frequency level less the rounding, as :func:`consistency` takes it (it reads a
    partly dithered record's noise low, so it errs towards counting less).

    With no quantisation (q = 0), or every run one sample long, this is
    :meth:`FitResult.bic_with <vcbmodel.analysis.fit.result.FitResult.bic_with>` exactly; with
    other noise above half a step, nearly so. Only the measured channel is weighted (the other
    channels' and the priors' chi^2 as they are)."""
    q = noise.quantisation if noise is not None else 0.0
    if q <= 0:
        return fit.bic_with(noise)
    weights = [rounding_weights(v, q, noise.other_than_rounding) for v in recorded_values(fit)]
    n_eff = float(sum(np.sum(w) for w in weights))
    return fit.chi2_with(noise, weights) + fit.n_varied * math.log(max(2.0, n_eff))


def consistency(segments, noise: NoiseModel, lags=20, smooth=None, tolerance: float = STRUCTURE_TOLERANCE,
                alpha: float = ALPHA):
    """Is the residual (contiguous segments) what the noise alone would leave? (``tolerance``:
    the structure tolerated, :data:`STRUCTURE_TOLERANCE`; ``alpha``: each whiteness test's level.)

    Returns a dict: ``consistent`` (bool), ``level_ratio`` (rms of the innovations / sigma),
    ``ljung_box_p``, ``periodogram_p``, and for a quantised sensor ``band_excess`` (largest
    smoothed excursion beyond the rounding band, in sigma of the smoothed noise).
    """
    segments = [np.asarray(s, float) for s in segments if np.asarray(s).size > noise.order + 8]
    if not segments:
        return {"consistent": True, "level_ratio": float("nan"), "ljung_box_p": 1.0, "periodogram_p": 1.0}
    u = [noise.whiten(s) for s in segments]
    allu = np.concatenate(u)
    level = float(np.sqrt(np.mean(allu**2)))
    # whiteness on the longest segment (tests need contiguity)
    main = max(u, key=lambda x: x.size)
    _, p_lb = ljung_box(main, lags)
    _, p_cp = cumulative_periodogram_test(main)
    out = {"level_ratio": level, "ljung_box_p": p_lb, "periodogram_p": p_cp}
    # the level of the high frequencies must match the record's own (model-free) level
    hf_pred = noise.sigma * math.sqrt(third_difference_gain(noise.ar) / 20.0)
    out["high_frequency_ratio"] = hf_pred / noise.high_frequency if noise.high_frequency > 0 else float("nan")
    if rounding_dominates(noise.quantisation, noise.high_frequency):
        # rounding dominates: deterministic, so test the band, not whiteness
        r = np.concatenate(segments)
        width = smooth or max(5, r.size // 100)
        mean = np.convolve(r, np.ones(width) / width, mode="valid") if r.size > width else np.array([np.mean(r)])
        other = noise.other_than_rounding
        allowed = 0.5 * noise.quantisation + 4.0 * other / math.sqrt(width) + 1e-12
        out["band_excess"] = float(np.max(np.abs(mean)) / allowed)
        rms = float(np.sqrt(np.mean(r**2)))
        out["rms_over_rounding"] = rms / math.sqrt(noise.quantisation**2 / 12.0 + other**2)
        out["consistent"] = bool(out["band_excess"] <= 1.0 and out["rms_over_rounding"] <= 1.5)
        return out
    white = p_lb >= alpha and p_cp >= alpha
    # a residual that is not white but holds barely more than the record's own high-frequency
    # noise (a transient of a few samples where a stop comes a step earlier, a model error far
    # below the noise) is not a missing effect: tolerate up to STRUCTURE_TOLERANCE of the noise
    # variance in excess of the model-free level
    r = np.concatenate(segments)
    excess = float(np.mean(r**2)) / noise.high_frequency**2 - 1.0 if noise.high_frequency > 0 else math.inf
    out["excess_variance_over_high_frequency_noise"] = excess
    out["white"] = bool(white)
    out["consistent"] = bool((white or excess <= tolerance)
                             and 0.5 <= out["high_frequency_ratio"] <= 2.0 and level <= 1.5)
    return out


def white_chi2(fit, sigma: float) -> float:
    """chi^2 of a fit's residual as white noise of level ``sigma`` (every fitted channel: the
    measured one's residual over ``sigma``, the others already scaled)."""
    return (float(sum(np.sum(r**2) for r in fit.residuals)) / sigma**2
            + float(sum(np.sum(r**2) for r in fit.extra_residuals.values())))


def variance_gain(before, after, sigma: float) -> float:
    """The share of the noise variance (``sigma``, the measured channel's unit) that fit ``after``
    removes from fit ``before``'s residual: the drop of the white chi^2 per sample of the measured
    channel. What a named effect (and a discovered term) must remove."""
    return (white_chi2(before, sigma) - white_chi2(after, sigma)) / max(1, before.n_data)


def noise_of_best(fits: Sequence, high_frequency: float, quantisation: float = 0.0) -> NoiseModel:
    """The noise model every score uses: fitted to the residual of the fit with the smallest rms."""
    best = min(fits, key=lambda f: f.rms)
    return fit_noise(best.residuals, high_frequency, quantisation,
                     source=f"residual of {best.label or ', '.join(best.effects) or 'no effects'}")


def excess(rms: float, sigma: float) -> float:
    """The residual rms in excess of the noise: sqrt(rms^2 - sigma^2), zero below the noise."""
    return math.sqrt(max(rms * rms - sigma * sigma, 0.0))


def describe_left(t, residual, noise: NoiseModel, sigma_white=None):
    """Where the residual that the noise does not account for sits: the window of its largest
    smoothed level and the rms there, for the report."""
    t = np.asarray(t)
    r = np.asarray(residual, float)
    width = max(5, r.size // 50)
    rr = running_rms(r, width)
    i = int(np.argmax(rr))
    level = max(2 * noise.marginal_sd, 0.5 * rr[i])
    a = b = i
    while a > 0 and rr[a - 1] >= level:
        a -= 1
    while b < r.size - 1 and rr[b + 1] >= level:
        b += 1
    return {"window": [float(t[a]), float(t[b])], "peak_running_rms": float(rr[i])}


__all__ = ["NoiseModel", "consistency", "describe_left", "excess", "fit_noise", "levinson", "noise_of_best", "recorded_values",
           "rounding_bic", "rounding_weights", "run_lengths", "variance_gain", "white_chi2"]

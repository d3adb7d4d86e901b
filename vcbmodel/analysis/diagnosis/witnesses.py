"""Witnesses of the sensor's noise that the fit did not shape, and whether a residual stands within them.

The diagnosis' noise model (:mod:`..noise`) is an autoregressive process fitted to the residual it
judges. A slow model error fitted that way passes for correlated noise: a camera record whose clock
ran 0.4 % fast was called "explained" at 1.95x its true noise (issue 20). So the verdict must also
hold against evidence of the noise level that no fit touched:

``rig``             the noise level the rig states for its sensor (``record.sensor_noise``, the
                    record's unit, standard deviation of the noise itself): taken as exact.
``pre_trigger``     the record before the release while the shaft is at rest: there the reading is
                    offset plus noise, nothing else. Its variance (mean removed) is the noise's,
                    with its own sampling uncertainty (few samples, correlated: few degrees of
                    freedom).
``high_frequency``  the record's third differences (:func:`vcbmodel.records.signals.noise_estimate`):
                    model-free, but they see only the noise's high frequencies. Correlated noise
                    holds more than that level, so this witness bounds the level only loosely:
                    a residual up to ``high_frequency_factor`` (:class:`.options.DiagnosisOptions`) times it is what a sensor with
                    lag-1 correlation up to 0.65 leaves; above, only a level witness can decide.

The rule (:func:`judge_against_witnesses`): with a level witness of standard deviation ``s_w`` and
``nu_w`` effective degrees of freedom, the residual after the release (``n`` samples, ``nu_r``
effective degrees of freedom) must satisfy

    mean(r^2) / s_w^2  <=  level_factor^2 * F(1 - witness_alpha; nu_r, nu_w)

(``F`` the 99 % point of the F distribution: the ratio of two variance estimates of the same noise;
a stated level counts as nu_w = infinity). A short pre-trigger is a weak witness: 36 camera samples
at lag-1 correlation 0.6 are 17 degrees of freedom, and then only a residual above about 1.9x its
level is caught. The effective degrees of freedom of a variance from ``n`` samples of noise with lag-1 correlation
``phi`` are ``n (1 - phi^2) / (1 + phi^2)`` (an AR(1) process: the sum of squared
autocorrelations). Units: the record's (rad, or m for a closing's follower).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.stats import chi2, f as f_dist

from .options import DEFAULT_OPTIONS, DiagnosisOptions

#: The thresholds of the witness tests (``level_factor``, ``witness_alpha``,
#: ``high_frequency_factor``) are the diagnosis's options (:class:`.options.DiagnosisOptions`). An
#: AR(1) noise of lag-1 correlation phi has a third-difference level of
#: sqrt((20 - 30 phi + 12 phi^2 - 2 phi^3) / 20) of its own, which is 1/2.0 at phi = 0.65: the
#: default ``high_frequency_factor``.
#: Samples of a pre-trigger left out next to the release (its estimate may be a few samples late).
GUARD_SAMPLES = 3
#: Fewest pre-trigger samples that make a witness.
MIN_SAMPLES = 8


@dataclass(frozen=True)
class Witness:
    """Evidence of the sensor's noise level: ``sigma`` (standard deviation of the noise itself,
    the record's unit), ``dof`` (effective degrees of freedom of its variance; inf: stated),
    ``level`` (True: the whole noise level; False: a lower bound, high frequencies only),
    ``lag1`` (the noise's lag-1 correlation where the witness shows it, else None)."""

    name: str
    sigma: float
    dof: float
    level: bool
    lag1: float | None = None
    detail: str = ""

    def to_json(self) -> dict:
        return {"witness": self.name, "sigma": self.sigma, "dof": self.dof if math.isfinite(self.dof) else None,
                "bounds_whole_level": self.level, "lag1_correlation": self.lag1, "detail": self.detail}


def variance_dof(n: int, lag1: float) -> float:
    """Effective degrees of freedom of a variance from ``n`` samples of AR(1) noise with lag-1
    correlation ``lag1`` (n for white noise)."""
    phi = min(abs(float(lag1)), 0.98)
    return max(1.0, n * (1 - phi**2) / (1 + phi**2))


def _lag1(x: np.ndarray) -> float:
    x = x - np.mean(x)
    den = float(np.dot(x, x))
    return float(np.dot(x[1:], x[:-1]) / den) if den > 0 else 0.0


#: Third differences beyond this many times their white-noise spread are kinks, not noise (left out
#: of :func:`rounded_high_frequency_level`).
KINK_FACTOR = 8.0


def rounded_high_frequency_level(y: np.ndarray, robust_level: float, quantisation: float) -> float:
    """The high-frequency noise level (the record's unit) of a record read on a grid of step
    ``quantisation`` (a logger's or an encoder's rounding of a noisy reading): the rms of the
    third differences over sqrt(20), kinks beyond :data:`KINK_FACTOR` times the spread left out.
    On such a record the third differences take a few discrete values and their median absolute
    deviation (``robust_level``, :func:`vcbmodel.records.signals.noise_estimate`) is biased: a
    12-bit logger's rounding of 0.5 mrad noise gave 0.48 for a true 0.65 mrad."""
    y = np.asarray(y, float)
    if y.size < 8:
        return robust_level
    d3 = y[3:] - 3 * y[2:-1] + 3 * y[1:-2] - y[:-3]
    spread = math.sqrt(20.0) * max(robust_level, quantisation / math.sqrt(12.0))
    keep = np.abs(d3) <= KINK_FACTOR * spread
    return float(math.sqrt(np.mean(d3[keep] ** 2) / 20.0)) if keep.any() else robust_level


def stated_witness(sigma: float) -> Witness:
    """The rig's stated sensor noise (``record.sensor_noise``, the record's unit)."""
    return Witness("rig", float(sigma), math.inf, True, None, "record.sensor_noise in the rig")


def high_frequency_witness(sigma_hf: float) -> Witness:
    """The record's model-free high-frequency level (third differences, the record's unit)."""
    return Witness("high_frequency", float(sigma_hf), math.inf, False, None, "third differences of the record")


def pre_trigger_witness(t: np.ndarray, y: np.ndarray, release: float, quantisation: float = 0.0) -> Witness | None:
    """The noise of the record before the release ``release`` (s, record time), where the shaft
    rests: the samples up to :data:`GUARD_SAMPLES` before it, their mean removed (a quantised
    sensor at rest reads one level: its rounding noise, q / sqrt(12), floors the level). None
    with fewer than :data:`MIN_SAMPLES` samples."""
    t, y = np.asarray(t, float), np.asarray(y, float)
    still = np.nonzero(t < release)[0]
    n = still.size - GUARD_SAMPLES
    if n < MIN_SAMPLES:
        return None
    x = y[:n]
    var = float(np.var(x, ddof=1))
    lag1 = _lag1(x) if var > 0 else 0.0
    var = max(var, quantisation**2 / 12.0)
    dof = variance_dof(n - 1, lag1)
    return Witness("pre_trigger", math.sqrt(var), dof, True, lag1,
                   f"{n} samples before the release at {release:.4g} s")


def _after_release(t: np.ndarray | None, r: np.ndarray, release: float | None) -> np.ndarray:
    if t is None or release is None:
        return r
    return r[np.asarray(t) >= release]


def check_witness(witness: Witness, residual: np.ndarray, lag1: float,
                  options: DiagnosisOptions = DEFAULT_OPTIONS) -> dict:
    """One witness against a residual (its samples after the release; ``lag1``: the noise's lag-1
    correlation, for the residual's degrees of freedom). Returns a dict with ``holds`` (True,
    False, or None: this witness cannot decide), the variance ratio and its limit."""
    r = np.asarray(residual, float)
    n = r.size
    ratio = float(np.mean(r**2)) / witness.sigma**2 if witness.sigma > 0 else math.inf
    out = {**witness.to_json(), "samples": int(n), "rms_ratio": math.sqrt(ratio)}
    if not witness.level:
        out["limit_rms_ratio"] = options.high_frequency_factor
        out["holds"] = True if math.sqrt(ratio) <= options.high_frequency_factor else None
        return out
    nu_r = variance_dof(n, witness.lag1 if witness.lag1 is not None else lag1)
    if math.isfinite(witness.dof):
        spread = float(f_dist.ppf(1.0 - options.witness_alpha, nu_r, witness.dof))
    else:
        spread = float(chi2.ppf(1.0 - options.witness_alpha, nu_r) / nu_r)
    limit = options.level_factor**2 * spread
    out.update(variance_ratio=ratio, limit_variance_ratio=limit, holds=bool(ratio <= limit))
    return out


def judge_against_witnesses(residual: np.ndarray, witnesses: list[Witness], lag1: float = 0.0,
                            t: np.ndarray | None = None, release: float | None = None,
                            options: DiagnosisOptions = DEFAULT_OPTIONS) -> dict:
    """Does the residual stand within the noise every independent witness shows? ``holds``:
    False if any level witness is exceeded; True if a level witness holds, or only the
    high-frequency one is there and the residual is within its factor; None when no witness can
    decide (only the high-frequency level, exceeded: explained only if the sensor's noise is that
    correlated). ``decided_by`` names the witnesses that decided."""
    r = _after_release(t, np.asarray(residual, float), release)
    checks = [check_witness(w, r, lag1, options) for w in witnesses if w is not None and w.sigma > 0]
    failed = [c["witness"] for c in checks if c["holds"] is False]
    level_ok = [c["witness"] for c in checks if c["holds"] is True and c["bounds_whole_level"]]
    if failed:
        holds, decided = False, failed
    elif level_ok:
        holds, decided = True, level_ok
    elif any(c["holds"] is True for c in checks):
        holds, decided = True, [c["witness"] for c in checks if c["holds"] is True]
    else:
        holds, decided = None, []
    return {"holds": holds, "decided_by": decided, "checks": checks}


def witness_text(evidence: dict, unit: str) -> str:
    """The independent evidence in a sentence for the report."""
    holds = evidence.get("holds")
    by = {c["witness"]: c for c in evidence.get("checks", ())}
    names = {"rig": "the sensor noise the rig states", "pre_trigger": "the noise of the record before the release",
             "high_frequency": "the record's high-frequency noise"}
    if holds is False:
        parts = [f"{c['rms_ratio']:.2f}x {names[w]} ({c['sigma']:.3g} {unit}; at most "
                 f"{math.sqrt(c['limit_variance_ratio']):.2f}x allowed)" for w, c in by.items() if c["holds"] is False]
        return ("Against evidence the fit did not shape, the residual stands at " + "; ".join(parts)
                + ": the noise model fitted to the residual has absorbed a model error.")
    if holds is True:
        parts = [f"{by[w]['rms_ratio']:.2f}x {names[w]}" for w in evidence["decided_by"]]
        return "Against evidence the fit did not shape, the residual stands at " + ", ".join(parts) + "."
    hf = by.get("high_frequency")
    ratio = f" ({hf['rms_ratio']:.2f}x it)" if hf else ""
    return ("No independent witness confirms the noise level: the residual is above what the record's "
            f"high-frequency noise allows for a mildly correlated sensor{ratio}; it is noise only if the sensor's "
            "noise is that correlated. A pre-trigger at rest or record.sensor_noise in the rig would decide.")

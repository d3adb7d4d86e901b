"""The verdict on a final residual, with the sensor's artefacts set aside and evidence the fit did
not shape (issue 20): what the diagnosis' judge step calls.

1. Sensor artefacts (:mod:`.sensor_artefacts`): steady narrow lines above the mechanism's band
   (:func:`mechanism_band`) are fitted and removed from the residual and reported as nuisance
   (mains pickup, with the record's clock as the line reads it); a timing jitter (noise growing
   with the model's speed) is estimated and the residual brought to the noise level at rest (not on
   a rounded record, whose rounding error also grows with the speed).
2. The noise model (:mod:`.noise`) is fitted to what remains and the residual tested against it
   (whitened residual white, level as the record's; a quantised record's rounding band), the
   high-frequency level of a rounded record taken from the rms of its third differences.
3. Independent witnesses (:mod:`.noise_evidence`): the rig's ``record.sensor_noise``, the record
   before the release, the record's high-frequency level. ``explained`` needs step 2 and no
   witness exceeded; when only the high-frequency level is there and the residual stands above
   what mildly correlated noise leaves, the verdict says the noise level is unconfirmed.

Units: s, Hz, the record's unit (rad or m).
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from .noise import consistency, fit_noise
from .noise_evidence import (high_frequency_witness, judge_against_witnesses, pre_trigger_witness,
                             rounded_high_frequency_level, stated_witness, witness_text)
from .sensor_artefacts import find_lines, jitter_weights, quantisation_nuisance, remove_lines, timing_jitter

#: The mechanism's band reaches this many times a free swing's natural frequency: a swing with
#: friction leaves harmonics of it in the residual (Coulomb friction: odd ones, falling as 1/k^2).
BAND_FACTOR = 10.0
#: Lowest edge of the mechanism's band (Hz).
MIN_BAND_HZ = 10.0


def mechanism_band(natural_frequency_hz: float | None) -> float | None:
    """Upper edge (Hz) of the mechanism's own frequencies, above which a steady line is the
    sensor's; None where the experiment has no swing frequency (a 35 ms cam drop or closing
    holds under two cycles of mains: no line test there)."""
    if not natural_frequency_hz:
        return None
    return max(BAND_FACTOR * float(natural_frequency_hz), MIN_BAND_HZ)


def gather_witnesses(stated_noise: float | None, t: np.ndarray, y: np.ndarray, release: float | None,
                     still_start: bool, sigma_hf: float, quantisation: float) -> list:
    """The witnesses of the sensor's noise for one record: the rig's stated level (None: not
    given), the record before ``release`` when it starts at rest (``still_start``), and the
    high-frequency level (rms-based for a rounded record)."""
    out = []
    if stated_noise:
        out.append(stated_witness(stated_noise))
    if still_start and release is not None:
        pre = pre_trigger_witness(t, y, release, quantisation)
        if pre is not None:
            out.append(pre)
    out.append(high_frequency_witness(high_frequency_level(y, sigma_hf, quantisation)))
    return out


def high_frequency_level(y: np.ndarray, sigma_hf: float, quantisation: float) -> float:
    """The record's high-frequency noise level: ``sigma_hf`` (median-based), or for a rounded
    record the rms of its third differences when larger."""
    if not quantisation:
        return sigma_hf
    return max(sigma_hf, rounded_high_frequency_level(y, sigma_hf, quantisation))


def judge_residual(times: Sequence[np.ndarray], residuals: Sequence[np.ndarray], sigma_hf: float,
                   quantisation: float, witnesses: list, band_hz: float | None, release: float | None = None,
                   lags: int = 20, model: np.ndarray | None = None) -> dict:
    """The verdict on a residual (segments ``residuals`` at record ``times``; the first is the
    measured channel's, ``model`` the model's reading there): ``explained``, ``tests`` (of the
    noise model fitted to the residual, the sensor's lines and timing jitter set aside),
    ``noise_of_final_residual``, ``independent_evidence``, ``sensor_lines``, ``timing_jitter``;
    and ``cleaned`` (the segments so cleaned, not for JSON)."""
    t0 = np.asarray(times[0], float)
    main = np.asarray(residuals[0], float)
    lines = find_lines(t0, main, band_hz) if band_hz else []
    first = remove_lines(t0, main, lines) if lines else main
    # not on a rounded record: its rounding error stays put while the reading rests on one level and
    # alternates when it moves, so it too grows with the speed
    jitter = timing_jitter(t0, first, model) if model is not None and not quantisation else None
    if jitter:
        first = first * jitter_weights(t0, model, jitter)
    cleaned = [first] + [np.asarray(r, float) for r in residuals[1:]]
    hf = next((w.sigma for w in witnesses if w.name == "high_frequency"), sigma_hf)
    noise = fit_noise(cleaned, hf, quantisation, source="final model's residual"
                      + (" (sensor lines removed)" if lines else ""))
    tests = consistency(cleaned, noise, lags=lags)
    rms = float(np.sqrt(np.mean(np.concatenate(cleaned) ** 2)))
    tests["rms_over_high_frequency_noise"] = rms / hf if hf > 0 else float("nan")
    evidence = judge_against_witnesses(cleaned[0], witnesses, noise.lag1, t0, release)
    explained = bool(tests["consistent"]) and evidence["holds"] is not False
    return {"explained": explained, "tests": tests, "noise_of_final_residual": noise.to_json(),
            "independent_evidence": evidence, "noise_confirmed": evidence["holds"],
            "sensor_lines": [line.to_json() for line in lines], "timing_jitter": jitter, "rms_without_sensor_lines": rms,
            "cleaned": cleaned, "_lines": lines}


def sensor_nuisance(verdict: dict, quantisation: float, sigma_hf: float, unit: str) -> dict:
    """What the sensor added, for the report's ``nuisance``: its lines (each with a sentence) and
    its rounding."""
    out = {}
    lines = verdict.get("_lines") or []
    if lines:
        out["sensor_lines"] = [{**line.to_json(), "reading": line.describe(unit)} for line in lines]
    if verdict.get("timing_jitter"):
        j = verdict["timing_jitter"]
        out["timing_jitter"] = {**j, "reading": f"timing jitter of {1e6 * j['jitter_s']:.3g} us (+-{1e6 * j['stderr_s']:.2g}): "
                                f"the record's sample times scatter (a camera's frame timing), noise growing with speed"}
    q = quantisation_nuisance(quantisation, sigma_hf)
    if q:
        out["quantisation"] = q
    return out


def verdict_sentences(verdict: dict, unit: str) -> str:
    """The sensor's artefacts and the independent evidence in words, for the evidence text."""
    text = ""
    lines = verdict.get("_lines") or []
    if lines:
        text += (" The residual holds " + "; ".join(line.describe(unit) for line in lines)
                 + ": the sensor's, set aside (the physics is judged on what remains).")
        clock = [line for line in lines if line.clock_offset is not None and abs(line.clock_offset) > 1e-3]
        if clock:
            text += (f" The mains line reads the record's clock {100 * clock[0].clock_offset:+.2f} % off "
                     "(if the grid ran at its nominal frequency, within about 0.1 %).")
    if verdict.get("timing_jitter"):
        j = verdict["timing_jitter"]
        text += (f" The residual's noise grows with the speed as a timing jitter of {1e6 * j['jitter_s']:.3g} us "
                 f"(+-{1e6 * j['stderr_s']:.2g}) makes it ({100 * j['share']:.0f} % of its variance): the sensor's "
                 "sample timing, set aside.")
    ev = verdict.get("independent_evidence")
    if ev:
        text += " " + witness_text(ev, unit)
    return text


def strip_private(verdict: dict) -> dict:
    """The verdict without its working parts (for JSON)."""
    return {k: v for k, v in verdict.items() if k not in ("cleaned", "_lines")}


def excess_over(rms: float, sigma: float) -> float:
    """Residual rms in excess of the noise, sqrt(rms^2 - sigma^2) (0 when below)."""
    return math.sqrt(max(rms**2 - sigma**2, 0.0))

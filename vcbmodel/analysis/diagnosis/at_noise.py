"""The one criterion for "at the noise": is a fit's residual what the sensor's noise alone
leaves? The search's stopping rules (a model at the noise ends forward selection, prunes the
candidates of its round, stops a fit's further starts) and the verdict ``explained`` all ask
:func:`judge_noise`; nothing else in the diagnosis decides it.

1. The sensor's artefacts (:mod:`.artefacts`: lines above the mechanism's band, timing jitter, an
   ADC's rounding) are fitted and set aside; the physics is judged on what remains.
2. The noise model (:mod:`..noise`) is fitted to what remains and the residual tested against it
   (whitened residual white, level as the record's high-frequency level; a rounded record's
   rounding band), the high-frequency level of a rounded record taken from the rms of its third
   differences.
3. Independent witnesses (:mod:`.witnesses`): the rig's ``record.sensor_noise``, the record
   before the release, the record's high-frequency level. At the noise needs step 2 and no
   witness exceeded; when only the high-frequency level is there and the residual stands above
   what mildly correlated noise leaves, the judgement says the noise level is unconfirmed
   (``noise_confirmed`` None): the residual passes only as strongly correlated noise, which a
   slow model error can pass for too.
4. Where it passes only as correlated noise (no witness of the whole level holds, and it stands
   above ``level_factor`` times the high-frequency level), it must hold no function of the motion
   (:mod:`.motion`: regressed on smooth functions of the model's reading and rate, the noise
   model's BIC must not drop by more than ``bic_margin``): a sensor's noise does not know where the
   mechanism is; a model error does.

So a judgement has three outcomes: at the noise with the level confirmed (``settled``: a witness of
the whole level holds, or the residual is within ``level_factor`` of the record's high-frequency
level, what white noise at that level leaves; the high-frequency witness alone allows up to
``high_frequency_factor`` for correlated noise, which a slow model error can pass for), at the
noise as far as the record can tell (``at_noise``), or not at the noise. The search stops and the verdict says ``explained`` on ``at_noise``;
a starting model gets nothing named only when its residual is ``settled`` (an unconfirmed level
cannot rule out a model error the record's nuisance has bent to hide).

The thresholds are the diagnosis's options (:class:`.options.DiagnosisOptions`). Units: s, Hz,
the record's unit (rad or m).
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..noise import NoiseModel, consistency, fit_noise
from .artefacts import Found, ResidualView, set_aside
from .motion import motion_structure
from .options import DEFAULT_OPTIONS, DiagnosisOptions
from .witnesses import (high_frequency_witness, judge_against_witnesses, pre_trigger_witness,
                        rounded_high_frequency_level, stated_witness)

#: The mechanism's band reaches this many times a free swing's natural frequency: a swing with
#: friction leaves harmonics of it in the residual (Coulomb friction: odd ones, falling as 1/k^2).
BAND_FACTOR = 10.0
#: Lowest edge of the mechanism's band (Hz).
MIN_BAND_HZ = 10.0


@dataclass(frozen=True)
class NoiseJudgement:
    """Whether a residual is at the noise (``at_noise``), with the tests of the noise model fitted
    to it once the sensor's artefacts are set aside (``tests``, ``noise``), the independent
    witnesses (``evidence``), the artefacts found, the residual segments without them
    (``cleaned``) and their rms (the record's unit)."""

    at_noise: bool
    tests: dict
    noise: NoiseModel
    evidence: dict
    artefacts: tuple[Found, ...]
    cleaned: tuple
    rms: float
    level_factor: float = DEFAULT_OPTIONS.level_factor

    @property
    def noise_confirmed(self) -> bool | None:
        return self.evidence["holds"]

    @property
    def settled(self) -> bool:
        """At the noise, and the level confirmed by evidence the fit did not shape: a witness of the
        whole level holds, or the residual stands within ``level_factor`` of the record's
        high-frequency level (what white noise at that level leaves)."""
        if not self.at_noise or self.noise_confirmed is not True:
            return False
        checks = self.evidence["checks"]
        return (any(c["holds"] is True and c["bounds_whole_level"] for c in checks)
                or any(c["witness"] == "high_frequency" and c["rms_ratio"] <= self.level_factor for c in checks))

    def to_json(self) -> dict:
        return {"tests": self.tests, "noise_of_final_residual": self.noise.to_json(),
                "independent_evidence": self.evidence, "noise_confirmed": self.noise_confirmed,
                "sensor_artefacts": {f.name: f.json for f in self.artefacts},
                "rms_without_sensor_artefacts": self.rms}


def mechanism_band(natural_frequency_hz: float | None) -> float | None:
    """Upper edge (Hz) of the mechanism's own frequencies, above which a steady line is the
    sensor's; None where the experiment has no swing frequency (a 35 ms cam drop or closing
    holds under two cycles of mains: no line test there)."""
    if not natural_frequency_hz:
        return None
    return max(BAND_FACTOR * float(natural_frequency_hz), MIN_BAND_HZ)


def high_frequency_level(y: np.ndarray, sigma_hf: float, quantisation: float) -> float:
    """The record's high-frequency noise level: ``sigma_hf`` (median-based), or for a rounded
    record the rms of its third differences when larger."""
    if not quantisation:
        return sigma_hf
    return max(sigma_hf, rounded_high_frequency_level(y, sigma_hf, quantisation))


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


def rests_on_correlation(evidence: dict, level_factor: float) -> bool:
    """Whether a residual passes the witnesses only as correlated noise: no witness of the whole
    level holds, and it stands above ``level_factor`` times the record's high-frequency level (what
    white noise at that level leaves). Then :func:`.motion.motion_structure` must find no function of
    the motion in it."""
    checks = evidence["checks"]
    if any(c["holds"] is True and c["bounds_whole_level"] for c in checks):
        return False
    return any(c["witness"] == "high_frequency" and c["rms_ratio"] > level_factor for c in checks)


def judge_residual(view: ResidualView, others: Sequence[np.ndarray], witnesses: list, release: float | None = None,
                   lags: int = 20, options: DiagnosisOptions = DEFAULT_OPTIONS, unit: str = "") -> NoiseJudgement:
    """The judgement on a residual: the measured channel's in ``view`` (its artefacts set aside
    first), the other fitted channels' (already scaled) in ``others``; ``witnesses`` of the
    sensor's noise (:func:`gather_witnesses`), ``release`` (s) where the witnesses' comparison starts."""
    first, found = set_aside(view, unit)
    cleaned = (first,) + tuple(np.asarray(r, float) for r in others)
    hf = next((w.sigma for w in witnesses if w.name == "high_frequency"), view.sigma_hf)
    noise = fit_noise(cleaned, hf, view.quantisation, source="final model's residual"
                      + (" (sensor artefacts set aside)" if any(f.name == "sensor_lines" for f in found) else ""))
    tests = consistency(cleaned, noise, lags=lags, tolerance=options.structure_tolerance, alpha=options.whiteness_alpha)
    rms = float(np.sqrt(np.mean(np.concatenate(cleaned) ** 2)))
    tests["rms_over_high_frequency_noise"] = rms / hf if hf > 0 else float("nan")
    evidence = judge_against_witnesses(first, witnesses, noise.lag1, view.t, release, options)
    at_noise = bool(tests["consistent"]) and evidence["holds"] is not False
    if at_noise and rests_on_correlation(evidence, options.level_factor):
        structure = motion_structure(view.t, first, view.model, options.bic_margin)
        if structure is not None:
            tests["motion_structure"] = structure
            at_noise = structure["holds"]
    return NoiseJudgement(at_noise, tests, noise, evidence, tuple(found), cleaned, rms, options.level_factor)


def judge_noise(ctx, fit) -> NoiseJudgement:
    """The judgement on ``fit``'s residual for the record of ``ctx`` (the diagnosis's context):
    its witnesses, the mechanism's band, the fit's release and the model's reading."""
    rec = ctx.record
    band = mechanism_band(rec.natural_frequency(ctx.rig) if rec.natural_frequency else None)
    release = fit.values.get("release_time_0", ctx.setup.release)
    witnesses = gather_witnesses((ctx.rig.record or {}).get("sensor_noise"), ctx.measurement.t,
                                 ctx.measurement.channel(rec.measured_channel), release,
                                 ctx.setup.still_start and not ctx.setup.hand_start, ctx.sigma_hf, ctx.quantisation)
    model = fit.simulations[0].measured[ctx.dataset.mask()] if fit.simulations else None
    view = ResidualView(np.asarray(fit.times[0], float), np.asarray(fit.residuals[0], float), model, ctx.sigma_hf,
                        ctx.quantisation, band)
    return judge_residual(view, fit.residuals[1:], witnesses, release, lags=20 if fit.n_data > 2000 else 10,
                          options=ctx.options, unit=getattr(rec, "unit", ""))


def at_noise(ctx, fit) -> bool:
    """Is ``fit``'s residual at the noise (:func:`judge_noise`)?"""
    return judge_noise(ctx, fit).at_noise

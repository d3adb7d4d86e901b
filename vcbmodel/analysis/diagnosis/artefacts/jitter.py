"""A sensor artefact (:mod:`.`): timing jitter.

:func:`timing_jitter` finds a clock that stamps each sample a little off (a camera's frame timing):
noise whose variance grows with the square of the reading's rate of change, ``j^2 v^2`` for a
jitter of ``j`` s. It is read from the residual's first differences (white jitter noise passes them
with gain 2; a smooth model error sampled densely hardly does), regressed on the model's squared
slope: a model error that grows with speed does not pass for jitter. :func:`jitter_weights` rescales the
residual to the noise level at rest, so the physics is judged on what the jitter does not explain.

Units: s, the record's unit (rad or m).
"""
from __future__ import annotations

import math

import numpy as np

from .protocol import ResidualView, register

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


class TimingJitter:
    """The artefact (:mod:`.protocol`): the samples' timing jitter, estimated from the residual and
    the model's slope; the residual brought to the noise level at rest. Not on a rounded record:
    its rounding error stays put while the reading rests on one level and alternates when it
    moves, so it too grows with the speed."""

    name = "timing_jitter"
    order = 20

    def fit(self, view: ResidualView) -> dict | None:
        if view.model is None or view.quantisation:
            return None
        return timing_jitter(view.t, view.residual, view.model)

    def remove(self, view: ResidualView, found: dict) -> np.ndarray:
        return np.asarray(view.residual, float) * jitter_weights(view.t, view.model, found)

    def report(self, found: dict, unit: str) -> tuple[dict, str]:
        data = {**found, "reading": f"timing jitter of {1e6 * found['jitter_s']:.3g} us (+-{1e6 * found['stderr_s']:.2g}): "
                "the record's sample times scatter (a camera's frame timing), noise growing with speed"}
        text = (f" The residual's noise grows with the speed as a timing jitter of {1e6 * found['jitter_s']:.3g} us "
                f"(+-{1e6 * found['stderr_s']:.2g}) makes it ({100 * found['share']:.0f} % of its variance): the sensor's "
                "sample timing, set aside.")
        return data, text


register(TimingJitter())

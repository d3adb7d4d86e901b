"""Does a residual that passes only as correlated noise hold a function of the motion?

When no witness of the whole noise level is there and the residual stands above what white noise
at the record's high-frequency level leaves (``level_factor``), the verdict rests on reading the
excess as correlated sensor noise (:mod:`.witnesses`: up to ``high_frequency_factor`` for the
high-frequency witness). A slow model error passes that reading too: its autoregressive noise
model has flat correlations at short lags (white noise plus a slow part), not a sensor's decay.
What tells them apart is not the residual's spectrum, which the fitted noise model matches by
construction, but its relation to the motion: a sensor's noise does not know where the mechanism
is or how fast it moves; a model error is a function of the state.

The test (:func:`motion_structure`): the residual regressed on smooth functions of the model's
reading x and its rate v (:data:`TERMS`: 1, x, v, x^2, x v, v^2, x^3, v|v|, x and v scaled to
unit spans), the noise model (autoregressive, order by BIC, :func:`vcbmodel.records.signals.ar_fit`)
refitted to what the regression leaves; the evidence is the drop of the noise model's BIC,
n ln(innovation variance) + (order + terms) ln n, against the noise model of the residual alone.
A drop beyond the diagnosis's evidence margin (``bic_margin``) says the excess is a function of the
motion: not noise. Correlated sensor noise (AR(1), lag-1 correlation 0.5-0.9) regressed on eight
smooth terms gains about chi^2_8 and pays 8 ln n (about 48 on a 35 ms cam drop at 12 kHz): the
drop is far below the margin. Units: the record's (rad, or m), s.
"""
from __future__ import annotations

import math

import numpy as np

from ...records.signals import ar_fit
from ..noise import MAX_ORDER

#: The smooth functions of the model's reading x and rate v (both scaled to unit spans) the residual is regressed on.
TERMS = ("1", "x", "v", "x^2", "x v", "v^2", "x^3", "v|v|")


def _basis(t: np.ndarray, model: np.ndarray) -> np.ndarray:
    """The columns of :data:`TERMS` on the record's times ``t`` (s) for the model's reading ``model``."""
    x = np.asarray(model, float)
    v = np.gradient(x, t)
    xs = (x - 0.5 * (x.max() + x.min())) / (np.ptp(x) or 1.0)
    vs = v / (np.max(np.abs(v)) or 1.0)
    return np.column_stack([np.ones_like(xs), xs, vs, xs**2, xs * vs, vs**2, xs**3, vs * np.abs(vs)])


def _noise_bic(r: np.ndarray, extra: int) -> tuple[float, int]:
    """(BIC, order) of the autoregressive noise model of ``r`` with ``extra`` more parameters."""
    a, innovation_var, _ = ar_fit([r], MAX_ORDER)
    n = r.size
    return n * math.log(max(innovation_var, 1e-300)) + (len(a) + extra) * math.log(n), len(a)


def motion_structure(t: np.ndarray, residual: np.ndarray, model: np.ndarray, margin: float) -> dict | None:
    """The evidence that ``residual`` (record's unit, at times ``t``) holds a function of the motion
    the model ``model`` (its reading at ``t``) makes: ``delta_bic`` (the noise model's BIC drop when the
    residual is first regressed on :data:`TERMS`), the rms left over the residual's rms, the noise
    model's order before and after, and ``holds`` (True: no such structure beyond ``margin``). None
    when the record is too short to tell (fewer than 10 samples a term)."""
    r = np.asarray(residual, float)
    t = np.asarray(t, float)
    if model is None or r.size < 10 * len(TERMS) or np.size(model) != r.size:
        return None
    basis = _basis(t, model)
    coefficients, *_ = np.linalg.lstsq(basis, r, rcond=None)
    rest = r - basis @ coefficients
    alone, order = _noise_bic(r, 0)
    regressed, order_after = _noise_bic(rest, len(TERMS))
    drop = alone - regressed
    return {"terms": list(TERMS), "delta_bic": float(drop), "margin": float(margin),
            "rms_left_over_rms": float(np.sqrt(np.mean(rest**2)) / (np.sqrt(np.mean(r**2)) or 1.0)),
            "noise_order": order, "noise_order_after": order_after, "holds": bool(drop <= margin)}

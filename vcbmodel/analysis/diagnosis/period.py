"""The period of a free swing: a model that drifts out of phase with the record (the rig's
geometry or the record's time base is off) is reported, and the period is fitted as a nuisance
(the pendulum's inertia) so the effect search does not chase it. Times in s."""
from __future__ import annotations

import math

import numpy as np

from ...records.signals import complete_swing_extremes
from ..fit import FitResult


def _paired_extremes(ctx, fit):
    """Times of the record's and the model's extremes, paired by order while both swing clearly
    (above 20 times the noise); None when fewer than five pairs. Only extremes the record holds
    whole, each timed by a parabola through its top (a record that ends mid-swing has its largest
    sample at its end, in the record and the model alike: that pair says no drift)."""
    d = ctx.dataset
    m = d.mask()
    t = d.t[m]
    tm, am, _ = complete_swing_extremes(t, d.y[m])
    ts, as_, _ = complete_swing_extremes(t, fit.simulations[0].measured[m])
    n = min(tm.size, ts.size)
    if n < 5:
        return None
    big = 20 * ctx.sigma_hf
    k = 0
    while k < n and am[k] > big and as_[k] > big:
        k += 1
    return (tm[:k], ts[:k]) if k >= 5 else None


def period_mismatch(ctx, fit: FitResult) -> dict | None:
    """Compare the extremes of the record's swing with the model's: a steady drift of their
    times means the periods differ. Returns a dict (relative mismatch, its standard error, and
    whether it is significant: beyond the options' ``period_tolerance`` and 4 standard errors),
    or None when the record does not swing."""
    if not ctx.record.period_fields:  # only a free swing has a period to check
        return None
    pairs = _paired_extremes(ctx, fit)
    if pairs is None:
        return None
    tm, ts = pairs
    k = tm.size
    dt = tm - ts
    idx = np.arange(k)
    A = np.vstack([idx, np.ones(k)]).T
    coef, res, *_ = np.linalg.lstsq(A, dt, rcond=None)
    fitres = dt - A @ coef
    s2 = float(np.sum(fitres**2)) / max(1, k - 2)
    se = math.sqrt(s2 / max(np.sum((idx - idx.mean()) ** 2), 1e-12))
    half = float(np.median(np.diff(ts)))
    rel = float(coef[0] / half)
    rel_se = float(se / half)
    significant = abs(rel) > ctx.options.period_tolerance and abs(rel) > 4 * rel_se
    return {"relative": rel, "stderr": rel_se, "significant": bool(significant),
            "record_half_period_s": half * (1 + rel), "model_half_period_s": half, "extremes_compared": int(k)}


def period_fields_fitted(ctx) -> bool:
    """Is a field that sets the swing's period already fitted (uncertain in the rig, or implied)?"""
    fields = ctx.record.period_fields
    return any(f in ctx.uncertain or f in ctx.search.implied for f in fields)


def imply_period(ctx, period: dict) -> None:
    """A period mismatch the rig does not allow for: fit the period's first field (the
    pendulum's inertia) as a nuisance, with an uncertainty three times the mismatch's."""
    field_name = ctx.record.period_fields[0]
    ctx.search.implied[field_name] = max(0.02, 3 * abs(2 * period["relative"]))
    ctx.say(f"the record's swing period differs from the rig's by {100 * period['relative']:+.2f} %: "
            f"fitting {field_name} as a nuisance")


def needs_period(ctx, period: dict | None) -> bool:
    """A significant mismatch the rig's uncertain values do not already cover."""
    return bool(period and period["significant"] and not period_fields_fitted(ctx))

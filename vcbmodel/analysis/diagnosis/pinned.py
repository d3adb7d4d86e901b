"""Values the rig pins, and what their plausible error would do to the fitted parameters (used by
the report step). The sensor's gain is fitted only when the rig marks ``record.sensor_gain``
uncertain; otherwise the stated errors are conditional on it being exact, and a gain error the
residual does not show (the friction absorbs it) moves the friction values by many stated errors
(the realism study's gain group: mu_k 12-45 errors off at a residual at the noise). Linearised at
the final fit, with no simulation: the gain's column of the Jacobian is the model's reading
itself, so the shift of the fitted parameters a gain error ``dg`` causes is
``(J^T J)^-1 J^T c dg`` (the least-squares projection onto the fitted directions: with the reading
``(g + dg) m`` and the gain pinned at ``g``, the residual at the truth is ``-c dg``, which the fit
absorbs by ``J dx = c dg``)."""
from __future__ import annotations

import math

import numpy as np

from ... import parameters as P
from ..fit.dataset import gain_name, offset_name
from ..fit.result import jacobian_of


def gain_column(ctx, fit) -> np.ndarray | None:
    """d(scaled residual)/d(gain) of the measured channel at ``fit``, in its Jacobian's row order
    (other channels' rows and prior rows zero); None when the rows do not match the Jacobian's."""
    names, jac = jacobian_of(fit)
    d, main = ctx.dataset, ctx.record.measured_channel
    if jac is None or not np.all(np.isfinite(jac)) or fit.simulations[0].channels.get(main) is None:
        return None
    m = d.mask()
    g = fit.parameters[gain_name(0, main)].value if gain_name(0, main) in fit.parameters else 1.0
    off = fit.parameters[offset_name(0, main)].value if offset_name(0, main) in fit.parameters else 0.0
    scale = ctx.scales().get((0, main), 1.0)
    cols = [(np.asarray(fit.simulations[0].channels[main])[m] - off) / g / scale if ch == main else np.zeros(int(m.sum()))
            for ch in d.fitted_channels]
    col = np.concatenate(cols)
    priors = sum(1 for n in names if fit.parameters[n].prior)
    if col.size + priors != np.shape(jac)[0]:
        return None
    return np.concatenate([col, np.zeros(priors)])


def parameter_shifts(fit, column: np.ndarray, error: float) -> dict:
    """{model parameter: shift in its unit} that a pinned value off by ``error`` (in its unit: the
    truth is the pinned value + error) would cause, linearised: the fit moves along its own
    directions to absorb ``column * error``."""
    names, jac = jacobian_of(fit)
    dx = np.linalg.lstsq(np.asarray(jac, float), column * error, rcond=None)[0]
    out = {}
    for name, step in zip(names, dx):
        p = fit.parameters[name]
        if p.kind == "model" and math.isfinite(step):
            out[name] = float(p.value * step if p.log else step)
    return out


def pinned_gain(ctx, fit) -> dict | None:
    """The sensor gain the rig does not let the fit estimate (not marked uncertain): the shift of
    each fitted model parameter a plausible gain error (parameters.PINNED_GAIN_ERROR) would cause,
    in stated errors, and whether any goes beyond the stated 95 % interval (the options'
    ``beyond_stated``). Reason: the stated
    errors are conditional on the pinned gain, and the residual cannot show its error."""
    main = ctx.record.measured_channel
    p = fit.parameters.get(gain_name(0, main))
    if p is None or p.vary:
        return None
    column = gain_column(ctx, fit)
    if column is None:
        return None
    error = P.PINNED_GAIN_ERROR * p.value
    shifts = parameter_shifts(fit, column, error)
    rows = {}
    for name, s in shifts.items():
        se = fit.parameters[name].stderr
        if se:
            rows[name] = {"shift": s, "stated_errors": abs(s) / se, "stderr_with_pinned": float(math.hypot(se, s))}
    worst = max(rows.items(), key=lambda kv: kv[1]["stated_errors"], default=None)
    return {"field": "record.sensor_gain", "value": p.value, "plausible_error": error, "shifts": rows,
            "beyond_stated": bool(worst and worst[1]["stated_errors"] > ctx.options.beyond_stated),
            "worst": worst[0] if worst else None}


def pinned_caveat(item: dict) -> str | None:
    """The report's sentence when a pinned value's plausible error goes beyond the stated errors."""
    if not item or not item["beyond_stated"]:
        return None
    w = item["worst"]
    row = item["shifts"][w]
    return (f"The stated errors assume {item['field']} = {item['value']:.4g} exactly: a "
            f"{100 * item['plausible_error'] / abs(item['value']):.2g} % error of it, which the residual would not "
            f"show, moves {w} by about {abs(row['shift']):.2g} ({row['stated_errors']:.1f} stated errors); mark it uncertain "
            f"in the rig (\"uncertain\": {{\"{item['field']}\": 0.01}}) to have it fitted and its error counted.")

"""The profile of one fitted parameter: how far the record lets it move, refit by refit.

A fit's stated error is read from its cost's curvature at the optimum (the Jacobian's; widened for a
correlated residual by :mod:`.covariance`). Where the cost runs along a long curved valley, as a swing's
decay shared between Coulomb friction, viscous friction and a drifting Coulomb level, that curvature
says little of the cost further out. Measured on a laboratory pendulum (an encoder's 0.09 deg steps,
6 s, a Coulomb level drifting by +0.00133 /s; the realism study's record 84000): the drifting form
stated its drift as -0.00004 +- 0.00044 /s; held at the truth's 0.00133 and refitted, the record's
chi^2 rose by 2 units where the stated error says 16 (at 0.002: 5 units, stated 36).

The profile (Venzon & Moolgavkar, Appl. Statist. 37, 1988) refits with the parameter held at points
outward of its stated 95 % ends, the others free, each from the point before, and keeps those the
record does not reject. A point's chi^2 rise is put on the stated error's scale:

    q = (chi2(point) - chi2(optimum)) * se_naive^2 / (s^2 se^2)

(``se_naive^2 / s^2`` is the Jacobian's (J^T J)^-1 diagonal, ``se`` the stated error): for a
quadratic cost q = ((value - optimum) / se)^2, so the stated interval's ends are where q reaches
1.96^2, and a flatter valley keeps points further out. A point is rejected when q exceeds 1.96^2;
the 95 % end lies between the last kept point and the first rejected one, found by interpolating
sqrt(q) (linear in the value for a quadratic cost). Every value of the fit is interpolated there, so
an end says where each of them stands when the profiled one does.

What a profile does not see: a valley the points do not reach (it stops at the last step,
:data:`STEPS`, or at the parameter's bound), and a refit that stops above its valley's floor (a
swing's cost kinks where a stop falls a step earlier or later): that rejects a point too early, so
the profile can only be too narrow, never wider than the record allows.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

from ..plausibility import Z95
from .result import FitResult

#: Points tried on each side, in multiples of the stated 95 % half-width from the optimum (outward
#: until one is rejected). For a quadratic cost the first is rejected (q = 1.5^2 1.96^2): one refit a side.
STEPS = (1.5, 3.0, 6.0)
#: A one-parameter chi^2's 95 % point: the square of the 95 % half-width in standard deviations.
LIMIT = Z95**2
#: A profile is reported as wider than the stated interval when an end lies beyond it by more than
#: this fraction of the stated half-width (a quarter: half a stated error).
BEYOND = 0.25

#: refit_held(value, start) -> the fit with the profiled parameter held at ``value``, the others free,
#: started from ``start``'s values (None: the refit failed).
HeldRefit = Callable[[float, FitResult], "FitResult | None"]
#: measure(fit) -> {quantity: value}: what an end reports (the parameter's own value among them).
Measure = Callable[[FitResult], dict]


@dataclass
class Profile:
    """One parameter's profile: the stated 95 % ends, the profile's own (``low``, ``high``), the
    quantities at each end, and the points tried: (value, q)."""

    parameter: str
    stated: tuple
    low: float
    high: float
    ends: list = field(default_factory=list)  # [{quantity: value}] at the low and the high end
    points: list = field(default_factory=list)

    @property
    def wider(self) -> bool:
        """Whether the record lets the parameter beyond its stated 95 % interval by more than
        :data:`BEYOND` of the stated half-width on a side (an end is interpolated between refits)."""
        margin = BEYOND * 0.5 * (self.stated[1] - self.stated[0])
        return self.low < self.stated[0] - margin or self.high > self.stated[1] + margin

    def to_json(self) -> dict:
        return {"parameter": self.parameter, "stated": list(self.stated), "profile": [self.low, self.high],
                "wider": self.wider, "points": [list(p) for p in self.points]}


def white_chi2(fit: FitResult) -> float:
    """chi^2 of ``fit`` under white noise of its sigma (the Jacobian's own scale)."""
    return fit.chi2_with(None)


def scale_factor(fit: FitResult, name: str) -> float | None:
    """se_naive^2 / (s^2 se^2) of parameter ``name`` of ``fit`` (module docstring), or None without
    finite errors."""
    p = fit.parameters[name]
    if not (p.vary and p.stderr and p.stderr_naive) or not (math.isfinite(p.stderr) and math.isfinite(p.stderr_naive)):
        return None
    s2 = white_chi2(fit) / max(1, fit.n_data + fit.n_other - fit.n_varied)  # the covariance's s^2: every fitted sample
    return p.stderr_naive**2 / (s2 * p.stderr**2) if s2 > 0 else None


def profile(fit: FitResult, name: str, refit_held: HeldRefit, measure: Measure,
            should_stop: Callable[[], bool] = lambda: False) -> Profile | None:
    """The profile of ``fit``'s parameter ``name`` (module docstring); None without a finite stated
    error."""
    factor = scale_factor(fit, name)
    if factor is None:
        return None
    p = fit.parameters[name]
    half = Z95 * p.stderr
    stated = (max(p.value - half, p.min), min(p.value + half, p.max))  # within the parameter's bounds
    out = Profile(name, stated, *stated)
    for side, direction in ((0, -1.0), (1, 1.0)):
        end_value, end = _side(fit, name, direction, half, factor, refit_held, measure, out.points, should_stop)
        if side == 0:
            out.low = min(out.low, end_value)
        else:
            out.high = max(out.high, end_value)
        out.ends.append(end)
    return out


def _side(fit: FitResult, name: str, direction: float, half: float, factor: float, refit_held: HeldRefit,
          measure: Measure, points: list, should_stop: Callable[[], bool]) -> tuple[float, dict]:
    """(the parameter's 95 % end on one side, the quantities there) by :data:`STEPS` outward."""
    p = fit.parameters[name]
    chi0 = white_chi2(fit)
    last = (p.value, 0.0, measure(fit), fit)  # value, sqrt(q), quantities, fit
    for m in STEPS:
        value = min(max(p.value + direction * m * half, p.min), p.max)
        if value == last[0] or should_stop():
            break  # at the parameter's bound, or out of time
        held = refit_held(value, last[3])
        if held is None:
            break
        q = (white_chi2(held) - chi0) * factor
        points.append((float(value), float(q)))
        root, here = math.sqrt(max(q, 0.0)), measure(held)
        if root > math.sqrt(LIMIT):  # rejected: the end lies between the last kept point and this one
            f = (Z95 - last[1]) / (root - last[1])
            return last[0] + f * (value - last[0]), {k: last[2][k] + f * (here[k] - last[2][k])
                                                     for k in here if k in last[2]}
        last = (value, root, here, held)
    return last[0], last[2]

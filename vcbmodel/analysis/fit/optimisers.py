"""The optimisers on an :class:`~.objective.Objective`: a bounded Levenberg-Marquardt (the fits'
default, converging on a Jacobian) and the paper's Nelder-Mead simplex (a polish). Both return
``(x, chi^2, Jacobian or None, success, message)`` in the objective's internal coordinates."""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import minimize

from .arithmetic import quiet_trial

log = logging.getLogger(__name__)

#: Levenberg-Marquardt's first damping (relative to the diagonal of J^T J)
INITIAL_DAMPING = 1e-3
#: A fit has converged when the next step would lower chi^2 by less than this fraction of the
#: number of samples (the chi^2 of noise alone) or than ``chi2_tolerance``: with stick-slip friction the cost is not smooth at finer scales
#: (a stop one step earlier or later), so steps below it are noise.
RELATIVE_TOLERANCE = 2e-3
#: Damping increases tried per Levenberg-Marquardt iteration before it gives up descending.
DAMPING_ATTEMPTS = 6
#: Least damping (relative to the diagonal of J^T J): the Gauss-Newton step, kept solvable.
MIN_DAMPING = 1e-7
#: A too-damped step is replaced by the least-damped one (damping tenfold lower each time) that
#: reaches this share of the Gauss-Newton step's predicted chi^2 change.
UNDAMPED_SHARE = 0.5


@quiet_trial
def levenberg_marquardt(obj, x0, lo, hi, max_iterations: int, chi2_tolerance: float = 0.1,
                        final_jacobian: bool = True, jacobian=None, relative_tolerance: float | None = None) -> tuple:
    """Bounded Levenberg-Marquardt on the objective's scaled residuals (chi^2 = sum r^2).

    Stops when the Gauss-Newton step (least damping) is predicted to lower chi^2 by less than a
    tolerance (``chi2_tolerance``, or :data:`RELATIVE_TOLERANCE` of the chi^2 that noise alone
    would leave: a change far below what any comparison of models or any standard error can
    see), so a converged fit ends on a Jacobian, without a last confirming simulation. The
    damped step's own prediction does not decide it: in a narrow valley of correlated parameters
    (Coulomb, viscous and drag friction with the release time) a damped step is short and
    predicts little while the Gauss-Newton step still predicts hundreds; the damping is then
    lowered (:func:`_damped_steps`). Parameters at a bound whose gradient points outwards are
    held there. When no damping gives descent (a free swing's cost has kinks where a stop comes a
    step earlier or later), the Jacobian is taken once more with ten times the difference step,
    which averages over the kinks.
    ``final_jacobian=False``: after a small step that the linear model predicted well and that
    leaves less than the tolerance of the Gauss-Newton step's predicted change, stop without a new
    Jacobian (the one before the step serves for the standard errors; used by a polish that starts
    next to the optimum).

    Parameters
    ----------
    obj : Objective
    x0, lo, hi : ndarray
        Start and bounds in internal coordinates (log of the value for log parameters).
    max_iterations : int
    chi2_tolerance : float
        Absolute chi^2 tolerance (dimensionless: the residuals are scaled).
    final_jacobian : bool
    jacobian : callable, optional
        ``jacobian(x, scale=1.0)`` (default: the objective's, with analytic prior rows).
    relative_tolerance : float, optional
        The tolerance's fraction of the noise's chi^2 (default :data:`RELATIVE_TOLERANCE`).

    Returns
    -------
    tuple
        (x, chi^2, Jacobian, success, message).
    """
    jacobian = jacobian or (lambda x, scale=1.0: obj.prior_jacobian_fix(obj.jacobian(x, scale), x))
    x = np.array(x0, float)
    r = obj.residual(x)
    cost = float(np.dot(r, r))
    J = jacobian(x)
    lam = INITIAL_DAMPING
    widened = False
    relative = RELATIVE_TOLERANCE if relative_tolerance is None else relative_tolerance
    for it in range(max_iterations):
        # relative to the cost the noise alone would leave (about one per sample), not to the
        # current cost: far from the optimum a small predicted gain means a poor linear model
        tolerance = max(chi2_tolerance, relative * min(cost, r.size))
        attempt = _damped_steps(obj, J, r, x, cost, lam, lo, hi, tolerance, it)
        lam = attempt.damping
        if attempt.outcome == "converged":
            return x, cost, J, True, f"converged (predicted chi2 change {attempt.undamped:.2g}) after {it} iterations"
        if attempt.outcome == "no descent":
            if widened:
                return x, cost, J, True, f"no further descent after {it} iterations"
            J = jacobian(x, 10.0)
            widened, lam = True, 1e-2
            continue
        gain = cost - attempt.cost
        x, r, cost = attempt.x, attempt.r, attempt.cost
        if (not final_jacobian and gain >= 0.7 * attempt.predicted and attempt.predicted < 0.1 * cost
                and attempt.undamped - attempt.predicted < tolerance):
            return x, cost, J, True, f"converged: a last step as predicted (chi2 change {gain:.3g})"
        J = jacobian(x)
        if gain < tolerance and attempt.predicted >= UNDAMPED_SHARE * attempt.undamped:  # not merely too damped
            return x, cost, J, True, f"converged (chi2 change {gain:.2g}) after {it + 1} iterations"
    return x, cost, J, True, f"at the iteration limit ({max_iterations})"


@dataclass
class _Attempt:
    """One Levenberg-Marquardt iteration's outcome: ``"accepted"`` (a step lowered chi^2 to
    ``cost`` at ``x``), ``"converged"`` (the Gauss-Newton step's predicted change is below the
    tolerance) or ``"no descent"``; ``damping``: the damping to go on with; ``predicted``: the
    step's predicted chi^2 change, ``undamped``: the Gauss-Newton step's."""

    outcome: str
    damping: float
    predicted: float = 0.0
    undamped: float = 0.0
    x: np.ndarray | None = None
    r: np.ndarray | None = None
    cost: float = math.inf


def _damped_steps(obj, J, r, x, cost, lam, lo, hi, tolerance, it) -> _Attempt:
    """Damped Gauss-Newton steps from ``x``, the damping raised tenfold after each that does
    not lower chi^2, until one does (at most :data:`DAMPING_ATTEMPTS`). A step predicted to gain
    less than ``tolerance`` ends the fit only when the Gauss-Newton step (:data:`MIN_DAMPING`)
    is too; otherwise the damping is lowered once (:func:`_less_damping`), and a step that then
    fails all the way back up to a negligible one is ``"no descent"``."""
    g = J.T @ r
    H = J.T @ J
    d = np.maximum(np.diag(H), 1e-12 * max(1.0, float(np.max(np.diag(H)))))
    free = np.ones(x.size, bool)
    free &= ~((x <= lo + 1e-12) & (g > 0))
    free &= ~((x >= hi - 1e-12) & (g < 0))
    undamped = _predicted(H, g, d, MIN_DAMPING, x, lo, hi, free)
    lowered = False
    for _ in range(DAMPING_ATTEMPTS):
        predicted = _predicted(H, g, d, lam, x, lo, hi, free)
        if predicted < tolerance:
            if predicted < -1e-9 * max(cost, 1.0):  # not a descent step (bounds): damp more
                lam *= 10.0
                continue
            if undamped < tolerance:
                return _Attempt("converged", lam, predicted, undamped)
            if lowered:  # the less damped steps failed: the linear model does not hold here
                return _Attempt("no descent", lam, predicted, undamped)
            lam, predicted = _less_damping(H, g, d, lam, x, lo, hi, free, undamped)
            lowered = True
        x_new = np.clip(x + bounded_step(H, g, d, lam, x, lo, hi, free), lo, hi)
        r_new = obj.residual(x_new)
        cost_new = float(np.dot(r_new, r_new))
        log.debug("LM it %d lam %.2g cost %.6g -> %.6g predicted %.3g (undamped %.3g) free %d", it, lam, cost,
                  cost_new, predicted, undamped, free.sum())
        if cost_new < cost:
            return _Attempt("accepted", max(lam / 5.0, MIN_DAMPING), predicted, undamped, x_new, r_new, cost_new)
        lam *= 10.0
    return _Attempt("no descent", lam, undamped=undamped)


def _predicted(H, g, d, lam, x, lo, hi, free) -> float:
    """The chi^2 change the linear model predicts for the damped step at damping ``lam`` (the
    step clipped to the bounds)."""
    step = np.clip(x + bounded_step(H, g, d, lam, x, lo, hi, free), lo, hi) - x
    return float(-(2 * g @ step + step @ H @ step))


def _less_damping(H, g, d, lam, x, lo, hi, free, undamped) -> tuple[float, float]:
    """The damping lowered tenfold at a time until its step is predicted to gain
    :data:`UNDAMPED_SHARE` of the Gauss-Newton step's ``undamped`` change (at most to
    :data:`MIN_DAMPING`): (damping, predicted change). No simulation runs."""
    predicted = _predicted(H, g, d, lam, x, lo, hi, free)
    while predicted < UNDAMPED_SHARE * undamped and lam > MIN_DAMPING:
        lam = max(lam / 10.0, MIN_DAMPING)
        predicted = _predicted(H, g, d, lam, x, lo, hi, free)
    return lam, predicted


def bounded_step(H, g, d, lam, x, lo, hi, free) -> np.ndarray:
    """The damped Gauss-Newton step with parameters that would cross a bound held at it (the
    step solved again for the others: an active set)."""
    free = free.copy()
    step = np.zeros_like(x)
    for _ in range(x.size + 1):
        step[:] = 0.0
        if not free.any():
            break
        A = H[np.ix_(free, free)] + lam * np.diag(d[free])
        try:
            step[free] = np.linalg.solve(A, -g[free])
        except np.linalg.LinAlgError:
            step[free] = -g[free] / (d[free] * (1 + lam))
        out = free & ((x + step < lo) | (x + step > hi))
        if not out.any():
            break
        free &= ~out
    return step


@quiet_trial
def nelder_mead(obj, x0, lo, hi, max_simulations: int | None = None) -> tuple:
    """The paper's simplex from ``x0`` (first simplex: a tenth of each range), within a budget
    of ``max_simulations`` (default 150 per varied parameter). Returns (x, chi^2, None, success,
    message)."""
    span = np.where(np.isfinite(hi - lo), hi - lo, 1.0)
    simplex = [x0] + [x0 + np.eye(len(x0))[i] * 0.1 * span[i] * (1 if x0[i] + 0.1 * span[i] <= hi[i] else -1)
                      for i in range(len(x0))]
    res = minimize(lambda x: float(np.sum(obj.residual(x) ** 2)), x0, method="Nelder-Mead",
                   bounds=list(zip(lo, hi)),
                   options={"initial_simplex": np.array(simplex), "xatol": 1e-4, "fatol": 1e-12,
                            "maxfev": max_simulations or 150 * len(x0)})
    budget = max_simulations or 150 * len(x0)
    ok, msg = (True, f"at its budget of {budget} simulations") if res.nfev >= budget else (
        bool(res.success), str(res.message))
    return res.x, float(res.fun), None, ok, msg

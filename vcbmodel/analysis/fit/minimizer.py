"""Fits (paper section 2.2): :func:`fit` (optimiser runs from ranked starts), :func:`staged_fit`
(the swinging part first, then the whole record) and :func:`refine` (another spring model from a
fitted one's Jacobian). The options of a fit are one :class:`~.options.FitOptions`."""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ...experiments import experiment_of
from ..progress import progress
from .objective import Objective
from .optimisers import levenberg_marquardt, nelder_mead
from .options import FitOptions
from .parameters import make_parameters, pooled_noise
from .pool import SimulationPool
from .result import FitResult, build_result
from .starts import scan_starts, start_points


def fit(datasets, effects, spring_model=None, params: dict | None = None, *, options: FitOptions | None = None,
        **keywords) -> FitResult:
    """Fit the varied parameters to the datasets.

    Parameters
    ----------
    datasets : sequence of Dataset
    effects : sequence of str
    spring_model : SpringModel, optional
        Default: the first dataset's rig's.
    params : dict of str to Parameter, optional
        Default: :func:`~.parameters.make_parameters` of the first rig.
    options : FitOptions, optional
        How the fit runs; ``keywords`` replace single options (``starts``, ``sigma`` (rad or m),
        ``step`` (s), ``pool``, ``max_starts``, ``enough``, ``should_stop``, ...; see
        :class:`~.options.FitOptions`). An unknown keyword raises TypeError.

    Several starts are simulated once each (in parallel) and the optimiser runs from the
    ``max_starts`` best; once the best result so far is at the noise level or passes
    ``enough``, no further start runs. Returns a :class:`FitResult`.
    """
    opts = FitOptions.build(options, **keywords)
    datasets = list(datasets)
    rig0 = datasets[0].rig
    spring_model = rig0.model.spring_model if spring_model is None else spring_model  # a SpringModel: decided by the caller
    params = params or make_parameters(rig0, effects)
    if opts.sigma is None:
        opts = replace(opts, sigma=pooled_noise(datasets))
    own = None
    if opts.pool is None and opts.processes > 1:
        n_sim = sum(p.vary and p.simulated for p in params.values())
        if n_sim >= 2 or len(datasets) >= 2:
            own = SimulationPool(opts.processes)
            opts = replace(opts, pool=own)
    try:
        return _fit(datasets, effects, spring_model, params, opts)
    finally:
        if own is not None:
            own.close()


def noise_scales(datasets, sigma: float) -> dict:
    """Every fitted channel weighted by the noise level ``sigma`` (the measured channel's unit)."""
    return {(i, ch): sigma for i, d in enumerate(datasets) for ch in d.fitted_channels}


@dataclass
class _Optimum:
    """The best optimiser end point so far (internal coordinates, chi^2, its Jacobian)."""

    x: np.ndarray
    cost: float = math.inf
    success: bool = True
    message: str = ""
    jacobian: np.ndarray | None = None


def _fit(datasets, effects, spring_model, params, opts: FitOptions) -> FitResult:
    scales = opts.scales if opts.scales is not None else noise_scales(datasets, opts.sigma)
    obj = Objective(datasets, effects, spring_model, params, opts.pool, scales, opts.step, opts.should_stop)
    best = _Optimum(obj.x0())
    if obj.varied:
        best = _run_starts(obj, start_points(obj, opts.starts, opts.method, opts.max_starts), opts)
        if obj.best[0] < best.cost - 1e-9:  # a trial point better than any optimiser end point
            best.x, best.jacobian = obj.best[1], None
    return build_result(obj, best.x, best.jacobian, opts.sigma, best.success, best.message, opts.method)


def _run_starts(obj, points, opts: FitOptions) -> _Optimum:
    """The optimiser from each start in turn, until one ends at the noise level or the best so
    far is ``enough``."""
    best = _Optimum(obj.x0())
    lo, hi = obj.bounds()
    for k, x0 in enumerate(points):
        x0 = obj.aligned(x0)
        if opts.method == "nelder-mead":
            x, cost, jac, ok, msg = nelder_mead(obj, x0, lo, hi, opts.max_simulations)
        else:
            x, cost, jac, ok, msg = levenberg_marquardt(obj, x0, lo, hi, opts.max_iterations or 10 + 2 * len(x0),
                                                        opts.chi2_tolerance, opts.final_jacobian,
                                                        relative_tolerance=opts.relative_tolerance)
        if opts.verbose:
            progress(f"  fit {opts.label or ', '.join(obj.effects)} start {k + 1}/{len(points)}: "
                     f"rms {obj.measured_rms(x):.3g} {experiment_of(obj.datasets[0].rig.experiment).unit} "
                     f"after {obj.nfev} simulations")
        if cost < best.cost:
            best = _Optimum(x, cost, ok, msg, jac)
        if obj.measured_rms(best.x) <= 1.05 * opts.sigma and not opts.every_start:
            break  # at the noise level: further starts cannot do better
        if opts.enough is not None and k + 1 < len(points) and opts.enough(
                build_result(obj, best.x, best.jacobian, opts.sigma, best.success, best.message, opts.method)):
            break  # the caller's test of "as good as it gets" (e.g. consistent with correlated noise)
    return best


def refine(datasets, effects, spring_model, params: dict, hint: tuple, *, pool=None, scales: dict | None = None,
           sigma: float | None = None, should_stop=None, label: str = "", max_iterations: int = 3) -> FitResult:
    """Refit from ``params`` a model that differs from a fitted one only in structure (another
    spring model), borrowing that fit's Jacobian ``hint`` (:func:`~.result.jacobian_of`) for the
    simulation parameters: one simulation per step. The alignment columns are recomputed.

    Parameters
    ----------
    hint : tuple
        (names of the varied parameters, Jacobian); another set of names: a fresh Jacobian.
    sigma : float, optional
        Noise level (rad or m; default: estimated from the data).
    should_stop : callable, optional
        True aborts the refit (:class:`~.options.FitAborted`).
    """
    names, J0 = hint
    datasets = list(datasets)
    if sigma is None:
        sigma = pooled_noise(datasets)
    if scales is None:
        scales = noise_scales(datasets, sigma)
    obj = Objective(datasets, effects, spring_model, params, pool, scales, None, should_stop)
    x0 = obj.x0()
    lo, hi = obj.bounds()
    if J0 is None or names != tuple(p.name for p in obj.varied):
        x, cost, jac, ok, msg = levenberg_marquardt(obj, x0, lo, hi, max_iterations)
    else:
        x, cost, jac, ok, msg = levenberg_marquardt(obj, x0, lo, hi, max_iterations,
                                                    jacobian=_borrowed_jacobian(obj, J0))
    result = build_result(obj, x, jac, sigma, ok, msg, "refine (borrowed Jacobian)")
    result.label = label
    return result


def _borrowed_jacobian(obj, J0):
    """A Jacobian function: ``J0``'s simulated columns, fresh alignment columns and prior rows."""
    def jacobian(x, scale=1.0):
        vals = obj.values(x)
        base = obj.curves([vals])[0]
        J = np.array(J0, float, copy=True)
        for k, p in enumerate(obj.varied):
            if not p.simulated:
                J[:, k] = obj.alignment_column(vals, base, p)
        return obj.prior_jacobian_fix(J, x)
    return jacobian


def staged_fit(datasets, effects, spring_model=None, params: dict | None = None, *, options: FitOptions | None = None,
               scan: dict | None = None, coarse_step: float | None = None, bases: list | None = None,
               **keywords) -> FitResult:
    """Fit first while the pendulum still swings, then the whole record.

    After a free swing sticks, the stuck angle depends discontinuously on the friction
    (one half-swing more or less), so the full-record cost has many local minima. The
    swinging part is smooth in the parameters: fitting it first (from every start) and then
    polishing on the full record (from that result) finds the global minimum reliably.

    Parameters
    ----------
    options, keywords
        As :func:`fit`'s (the stages run on one pool: the given one, or one of ``processes``).
    scan : dict of str to sequence of float, optional
        The best points of that coarse grid, evaluated on the swinging part, are tried as the
        first starts (:func:`~.starts.scan_starts`).
    coarse_step : float, optional
        Integration step of the first stage (s; a longer step there halves its cost, the polish
        uses the default).
    bases : list of dict, optional
        Values the scan's grid is laid around.
    """
    opts = FitOptions.build(options, **keywords)
    datasets = list(datasets)
    if opts.sigma is None:
        opts = replace(opts, sigma=pooled_noise(datasets))
    own = None
    if opts.pool is None and opts.processes > 1:
        own = SimulationPool(opts.processes)
        opts = replace(opts, pool=own)
    try:
        return _staged(datasets, effects, spring_model, params, replace(opts, processes=1), scan, coarse_step, bases)
    finally:
        if own is not None:
            own.close()


def _swinging_parts(datasets, sigma):
    """Each dataset up to where it stops swinging (the dataset itself when it never does)."""
    early = []
    for d in datasets:
        m = d.mask()
        t_stop = experiment_of(d.rig.experiment).swinging_part(d.t[m], d.y[m], sigma)
        early.append(d if t_stop is None else d.with_window(t_stop))
    return early


def _staged(datasets, effects, spring_model, params, opts: FitOptions, scan, coarse_step, bases) -> FitResult:
    early = _swinging_parts(datasets, opts.sigma)
    params = params or make_parameters(datasets[0].rig, effects)
    if scan:
        opts = replace(opts, starts=scan_starts(early, effects, spring_model, params, scan, pool=opts.pool,
                                                scales=opts.scales, step=coarse_step, bases=bases)
                       + list(opts.starts or []))
    same = all(e is d for e, d in zip(early, datasets))
    if same and coarse_step is None:
        return fit(datasets, effects, spring_model, params, options=opts)
    label = opts.label
    first = fit(early, effects, spring_model, params, options=opts,
                label=f"{label} (while swinging)" if not same else f"{label} (coarse)",
                step=coarse_step if coarse_step is not None else opts.step, final_jacobian=False)
    result = fit(datasets, effects, spring_model, first.parameters, options=opts, starts=None,
                 label=f"{label} (whole record)", max_iterations=5, final_jacobian=False)
    result.nfev += first.nfev
    return result

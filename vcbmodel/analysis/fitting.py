"""Fitting friction parameters to measurements (paper section 2.2), reported like lmfit.

A fit varies some :class:`Parameter` objects (value, bounds, vary, stderr) so that the
simulated angle matches one or more measurements in the least-squares sense. Two
optimisers: ``least_squares`` (scipy trust-region reflective, bounds, finite-difference
Jacobian: fast, and gives the standard errors) and ``nelder-mead`` (the paper's modified
simplex, on bounded transformed coordinates), optionally polished by the other. Several
starts guard against poor local minima.
"""
from __future__ import annotations

import itertools
import math
import multiprocessing
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import least_squares, minimize

from ..errors import SimulationError
from ..experiments import experiment_of
from ..experiments.simulation import simulate
from ..model.effects import parameter_specs
from ..model.values import model_values, rig_values
from ..records.signals import noise_estimate
from ..rig.spring_model import SpringModel
from .progress import progress


@dataclass
class Parameter:
    """A model parameter: value with bounds, whether it is varied, and its standard error."""

    name: str
    value: float
    min: float = -math.inf
    max: float = math.inf
    vary: bool = True
    unit: str = ""
    log: bool = False
    stderr: float | None = None
    tied_to: str | None = None  # value follows this parameter (lmfit's expr, for the simplest case)

    def at_bound(self, rel=1e-3):
        span = (self.max - self.min) if math.isfinite(self.max - self.min) else max(abs(self.value), 1.0)
        return self.vary and (abs(self.value - self.min) <= rel * span or abs(self.max - self.value) <= rel * span)

    # internal (unbounded-ish) coordinate used by the optimisers
    def to_internal(self, v):
        return math.log(v) if self.log else v

    def from_internal(self, x):
        return math.exp(x) if self.log else x

    def internal_bounds(self):
        if self.log:
            return math.log(self.min), math.log(self.max)
        return self.min, self.max


@dataclass
class Dataset:
    """One measurement with the rig it was taken on."""

    rig: object
    measurement: object

    @property
    def t(self):
        return self.measurement.t

    @property
    def y(self):
        return self.measurement.channel(experiment_of(self.rig.experiment).measured_channel)


@dataclass
class FitResult:
    """Outcome of a fit. Residuals and rms in the measured channel's unit (rad, or m for a
    breaker closing); aic/bic from chi^2 with noise ``sigma``."""

    effects: tuple
    spring_model: SpringModel
    parameters: dict
    residuals: list  # per dataset: simulated - measured (rad or m)
    simulations: list  # per dataset: SimulationResult at the measurement times
    sigma: float  # noise level (rad or m) used for chi^2
    nfev: int = 0
    success: bool = True
    message: str = ""
    method: str = ""

    @property
    def unit(self):
        return experiment_of(self.simulations[0].experiment).unit if self.simulations else "rad"

    @property
    def spring_model_label(self):
        """The spring model with its lumped convention, for reports."""
        return self.spring_model.label

    @property
    def values(self):
        return {p.name: p.value for p in self.parameters.values()}

    @property
    def n_data(self):
        return int(sum(r.size for r in self.residuals))

    @property
    def n_varied(self):
        return sum(p.vary for p in self.parameters.values())

    @property
    def chi2(self):
        return float(sum(np.sum(r**2) for r in self.residuals) / self.sigma**2)

    @property
    def reduced_chi2(self):
        return self.chi2 / max(1, self.n_data - self.n_varied)

    @property
    def rms(self):
        return float(math.sqrt(sum(np.sum(r**2) for r in self.residuals) / self.n_data))

    @property
    def max_error(self):
        return float(max(np.max(np.abs(r)) for r in self.residuals))

    @property
    def at_noise_level(self):
        return at_noise_level(self.chi2 * self.sigma**2, self.n_data, self.sigma)

    @property
    def aic(self):
        return self.chi2 + 2 * self.n_varied

    @property
    def bic(self):
        return self.chi2 + self.n_varied * math.log(self.n_data)

    def report(self):
        """A readable fit report; parameters stuck at a bound are flagged."""
        lines = [f"[[Fit]] effects: {', '.join(self.effects) or '(none)'}; spring model: {self.spring_model.label}",
                 f"    method {self.method}, {self.nfev} simulations, {'converged' if self.success else 'stopped: ' + self.message}",
                 f"    data points {self.n_data}, varied {self.n_varied}, noise sigma {self.sigma:.3g} {self.unit}",
                 f"    rms {self.rms:.4g} {self.unit}, max |error| {self.max_error:.4g} {self.unit}, reduced chi2 {self.reduced_chi2:.3f}",
                 f"    AIC {self.aic:.1f}, BIC {self.bic:.1f}", "[[Parameters]]"]
        for p in self.parameters.values():
            if not p.vary:
                how = f"tied to {p.tied_to}" if p.tied_to else "fixed"
                lines.append(f"    {p.name:18s} = {p.value:.6g} {p.unit} ({how})")
                continue
            err = f"+/- {p.stderr:.3g}" if p.stderr is not None and math.isfinite(p.stderr) else "+/- ?"
            flag = "  AT BOUND [%g, %g]" % (p.min, p.max) if p.at_bound() else ""
            lines.append(f"    {p.name:18s} = {p.value:.6g} {err} {p.unit} (bounds [{p.min:g}, {p.max:g}]){flag}")
        return "\n".join(lines)


def make_parameters(rig, effects, initial=None, vary=None):
    """Parameters of ``effects``: fixed where the rig gives a value, varied otherwise.

    ``initial`` overrides starting values; ``vary`` (a set of names) overrides which vary.
    """
    given = rig_values(rig)
    start = model_values(rig, effects, {k: v for k, v in (initial or {}).items() if k not in given}, for_fit=True)
    params = {}
    for spec in parameter_specs(effects):
        is_varied = spec.name not in given and (spec.vary if vary is None else spec.name in vary)
        value = start[spec.name] if spec.name in given else float(np.clip(start[spec.name], spec.min, spec.max))
        params[spec.name] = Parameter(spec.name, value, spec.min, spec.max, is_varied, spec.unit, spec.log)
    return params


def pooled_noise(datasets):
    """Noise level (the measured channel's unit) pooled over datasets: rms of each one's
    estimate (:func:`vcbmodel.records.signals.noise_estimate`)."""
    return float(np.sqrt(np.mean([noise_estimate(d.y) ** 2 for d in datasets])))


def _simulate_job(job):
    rig, effects, values, spring_model, t = job
    return simulate(rig, effects, values, spring_model=spring_model, sample_times=t)


def dataset_pool(datasets, processes=2):
    """A process pool simulating several datasets at once (None for one dataset)."""
    if len(datasets) < 2 or processes < 2:
        return None
    return ProcessPoolExecutor(max_workers=min(processes, len(datasets)),
                               mp_context=multiprocessing.get_context("fork"))


class FitAborted(Exception):
    """Raised inside a fit when :data:`STOP` is set (another candidate already won)."""


#: Set by the diagnosis (a multiprocessing Event in worker processes) to abort running fits.
STOP = None


def at_noise_level(cost, n_data, sigma):
    """Whether a sum of squared residuals is what white noise of ``sigma`` alone would give
    (within three standard deviations of the chi^2 distribution)."""
    return cost <= n_data * sigma**2 * (1 + 3 * math.sqrt(2.0 / n_data))


class _Objective:
    def __init__(self, datasets, effects, spring_model, params, pool=None):
        self.pool = pool  # simulates the datasets in parallel when given
        self.datasets, self.effects, self.spring_model = datasets, tuple(effects), spring_model
        self.params = params
        self.varied = [p for p in params.values() if p.vary]
        self.nfev = 0
        self.best = (math.inf, None)

    def values(self, x):
        vals = {p.name: p.value for p in self.params.values()}
        for p, xi in zip(self.varied, x):
            lo, hi = p.internal_bounds()
            vals[p.name] = p.from_internal(float(np.clip(xi, lo, hi)))
        for p in self.params.values():
            if p.tied_to:
                vals[p.name] = vals[p.tied_to]
        return vals

    def simulate(self, values):
        jobs = [(d.rig, self.effects, values, self.spring_model, d.t) for d in self.datasets]
        if self.pool is not None:
            return list(self.pool.map(_simulate_job, jobs))
        return [_simulate_job(j) for j in jobs]

    def residual(self, x):
        if STOP is not None and STOP.is_set():
            raise FitAborted()
        self.nfev += 1
        try:
            sims = self.simulate(self.values(x))
        except SimulationError:
            return np.full(sum(d.t.size for d in self.datasets), 1.0)  # a diverged trial scores badly
        r = np.concatenate([s.measured - d.y for s, d in zip(sims, self.datasets)])
        cost = float(np.dot(r, r))
        if cost < self.best[0]:
            self.best = (cost, np.array(x, float))
        return r

    def x0(self):
        return np.array([p.to_internal(p.value) for p in self.varied])

    def bounds(self):
        b = [p.internal_bounds() for p in self.varied]
        return np.array([lo for lo, _ in b]), np.array([hi for _, hi in b])


def fit(datasets, effects, spring_model=None, params=None, *, method="least_squares", starts=None,
        sigma=None, verbose=True, label="", max_simulations=None, processes=2):
    """Fit the varied parameters of ``effects`` to the datasets.

    ``starts``: list of dicts of starting values tried in turn (the best result is kept).
    ``sigma``: noise level (rad) for chi^2 / AIC / BIC (default: estimated from the data).
    ``max_simulations``: budget of the simplex (default 150 per varied parameter).
    Returns a :class:`FitResult`.
    """
    datasets = list(datasets)
    rig0 = datasets[0].rig
    spring_model = SpringModel.parse(spring_model or rig0.model.spring_model, rig0.model.spring_model.convention)
    params = params or make_parameters(rig0, effects)
    if sigma is None:
        sigma = pooled_noise(datasets)
    pool = dataset_pool(datasets, processes)
    try:
        return _fit(datasets, effects, spring_model, params, method, starts, sigma, verbose, label,
                    max_simulations, pool)
    finally:
        if pool is not None:
            pool.shutdown()


def _fit(datasets, effects, spring_model, params, method, starts, sigma, verbose, label, max_simulations, pool):
    obj = _Objective(datasets, effects, spring_model, params, pool)
    varied = obj.varied
    best_x, best_cost, success, message = obj.x0(), math.inf, True, ""
    if varied:
        start_points = [obj.x0()]
        for s in starts or []:
            start_points.append(np.array([p.to_internal(float(np.clip(s.get(p.name, p.value), p.min, p.max)))
                                          for p in varied]))
        lo, hi = obj.bounds()
        for k, x0 in enumerate(start_points):
            x0 = np.clip(x0, lo + 1e-9 * (hi - lo), hi - 1e-9 * (hi - lo))
            if method == "nelder-mead":
                span = hi - lo
                simplex = [x0] + [x0 + np.eye(len(x0))[i] * 0.1 * span[i] * (1 if x0[i] + 0.1 * span[i] <= hi[i] else -1)
                                  for i in range(len(x0))]
                res = minimize(lambda x: float(np.sum(obj.residual(x) ** 2)), x0, method="Nelder-Mead",
                               bounds=list(zip(lo, hi)),
                               options={"initial_simplex": np.array(simplex), "xatol": 1e-4, "fatol": 1e-12,
                                        "maxfev": max_simulations or 150 * len(x0)})
                x, cost = res.x, float(res.fun)
                budget = max_simulations or 150 * len(x0)
                if res.nfev >= budget:  # a deliberate budget, not a failure
                    ok, msg = True, f"at its budget of {budget} simulations"
                else:
                    ok, msg = bool(res.success), str(res.message)
            else:
                res = least_squares(obj.residual, x0, bounds=(lo, hi), method="trf", diff_step=1e-3,
                                    x_scale="jac", xtol=1e-6, ftol=1e-8, max_nfev=60 * (len(x0) + 1))
                x, cost = res.x, 2 * float(res.cost)
                ok, msg = bool(res.status > 0), str(res.message)
            if verbose:
                progress(f"  fit {label or ', '.join(effects)} start {k + 1}/{len(start_points)}: "
                         f"rms {math.sqrt(cost / max(1, sum(d.t.size for d in datasets))):.3g} "
                         f"{experiment_of(datasets[0].rig.experiment).unit} after {obj.nfev} simulations")
            if cost < best_cost:
                best_x, best_cost, success, message = x, cost, ok, msg
            if at_noise_level(best_cost, sum(d.t.size for d in datasets), sigma):
                break  # at the noise level: further starts cannot do better
        if obj.best[0] < best_cost:  # a trial point better than any optimiser end point
            best_x = obj.best[1]
    values = obj.values(best_x)
    fitted = {name: replace(p, value=values[name]) for name, p in params.items()}
    sims = obj.simulate(values)
    residuals = [s.measured - d.y for s, d in zip(sims, datasets)]
    result = FitResult(tuple(effects), spring_model, fitted, residuals, sims, sigma, obj.nfev, success, message, method)
    if varied:
        _standard_errors(result, obj, best_x)
    return result


def _standard_errors(result, obj, x):
    """stderr from the Jacobian of the residuals at the optimum: cov = s^2 (J^T J)^-1."""
    r0 = np.concatenate(result.residuals)
    J = np.empty((r0.size, len(x)))
    for i, p in enumerate(obj.varied):
        h = 1e-3 * max(1.0, abs(x[i])) if p.log else 1e-3 * max(abs(x[i]), 1e-3 * (p.max - p.min))
        xp = np.array(x, float)
        xp[i] += h
        J[:, i] = (obj.residual(xp) - r0) / h
    dof = max(1, r0.size - len(x))
    s2 = float(np.dot(r0, r0)) / dof
    try:
        cov = np.linalg.inv(J.T @ J) * s2
    except np.linalg.LinAlgError:
        return
    for i, p in enumerate(obj.varied):
        var = cov[i, i]
        if not (var >= 0 and math.isfinite(var)):
            continue
        sd = math.sqrt(var)
        name = p.name
        result.parameters[name].stderr = result.parameters[name].value * sd if p.log else sd


def truncated(dataset, t_max):
    """The dataset restricted to t <= t_max."""
    m = dataset.measurement
    keep = m.t <= t_max
    sub = replace(m, t=m.t[keep], channels={k: v[keep] for k, v in m.channels.items()})
    return Dataset(dataset.rig, sub)


def scan_starts(datasets, effects, spring_model, params, grid, keep=2):
    """Evaluate the cost on a coarse grid (dict name -> values) with the other parameters
    at their current values; return the ``keep`` best grid points as start dicts."""
    obj = _Objective(datasets, effects, spring_model or datasets[0].rig.model.spring_model, params)
    names = [n for n in grid if n in params and params[n].vary]
    scored = []
    for combo in itertools.product(*(grid[n] for n in names)):
        start = dict(zip(names, combo))
        x = np.array([p.to_internal(float(np.clip(start.get(p.name, p.value), p.min, p.max))) for p in obj.varied])
        r = obj.residual(x)
        scored.append((float(np.dot(r, r)), start))
    scored.sort(key=lambda s: s[0])
    return [s for _, s in scored[:keep]]


def staged_fit(datasets, effects, spring_model=None, params=None, *, starts=None, sigma=None,
               verbose=True, label="", method="least_squares", scan=None):
    """Fit first while the pendulum still swings, then the whole record.

    After a free swing sticks, the stuck angle depends discontinuously on the friction
    (one half-swing more or less), so the full-record cost has many local minima. The
    swinging part is smooth in the parameters: fitting it first (from every start) and then
    polishing on the full record (from that result) finds the global minimum reliably.
    ``scan`` (dict name -> values): the best points of that coarse grid, evaluated on the
    swinging part, are tried as the first starts.
    """
    datasets = list(datasets)
    if sigma is None:
        sigma = pooled_noise(datasets)
    early = []
    for d in datasets:
        t_stop = experiment_of(d.rig.experiment).swinging_part(d.t, d.y, sigma)
        early.append(d if t_stop is None else truncated(d, t_stop))
    if scan:
        params = params or make_parameters(datasets[0].rig, effects)
        starts = scan_starts(early, effects, spring_model, params, scan) + list(starts or [])
    if all(e is d for e, d in zip(early, datasets)):
        return fit(datasets, effects, spring_model, params, starts=starts, sigma=sigma, verbose=verbose,
                   label=label, method=method)
    first = fit(early, effects, spring_model, params, starts=starts, sigma=sigma, verbose=verbose,
                label=f"{label} (while swinging)", method=method)
    return fit(datasets, effects, spring_model, first.parameters, sigma=sigma, verbose=verbose,
               label=f"{label} (whole record)", method=method)

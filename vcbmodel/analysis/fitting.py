"""Fitting model parameters to records (paper section 2.2), reported like lmfit.

A fit varies :class:`Parameter` objects (value, bounds, vary, stderr, optional Gaussian prior)
so that the model matches one or more records in the least-squares sense. Parameters are of
two sorts:

- *simulation* parameters change the simulation: the effects' values (``kind="model"``), a
  record's initial angle (``"state"``), rig values marked uncertain (``"rig"``);
- *alignment* parameters only move the simulation onto the record (:mod:`.nuisance`): the
  release time within the record (``"release"``), the sensor offset (``"offset"``) and gain
  (``"gain"``). Their derivatives are analytic.

The optimiser is a bounded Levenberg-Marquardt (:func:`levenberg_marquardt`) with a Jacobian
assembled here: forward differences for the simulation parameters, one simulation each, run in
parallel on a process pool (:class:`SimulationPool`), and the analytic columns of the alignment
parameters. A fit of k simulation parameters therefore costs 1 + k simulations per iteration, k
of them in parallel; it stops when the next step would change chi^2 by less than a small
fraction of the noise's chi^2. Several starts are simulated once each (in parallel) and the
optimiser runs from the best.
``method="nelder-mead"`` keeps the paper's simplex for a polish.

A dataset without a :class:`~.nuisance.RecordSetup` is fitted as before: the model starts at
the record's t = 0 with the rig's initial state, the sensor reads the model channel itself.
"""
from __future__ import annotations

import itertools
import logging
import math
import multiprocessing
import os
import threading
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass, field, replace

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.optimize import minimize

from ..errors import SimulationError
from ..experiments import experiment_of
from ..experiments.simulation import simulate, simulation_backend
from ..model.effects import parameter_specs
from ..model.values import model_values, rig_values
from ..records.signals import noise_estimate
from ..rig.spring_model import SpringModel
from .nuisance import rig_with
from .progress import progress

#: Parameter kinds that need a new simulation when they change.
SIM_KINDS = ("model", "state", "rig")
#: Relative forward-difference step (internal coordinates, scipy's convention h = s max(1, |x|)).
DIFF_STEP = 1e-3
#: Scaled residual of a sample whose simulation failed (a diverged trial scores badly).
FAILED = 100.0
log = logging.getLogger(__name__)
#: Levenberg-Marquardt's first damping (relative to the diagonal of J^T J)
INITIAL_DAMPING = 1e-3
#: A fit has converged when the next step would lower chi^2 by less than this fraction of the
#: number of samples (the chi^2 of noise alone) or than ``chi2_tolerance``: with stick-slip friction the cost is not smooth at finer scales
#: (a stop one step earlier or later), so steps below it are noise.
RELATIVE_TOLERANCE = 2e-3


@dataclass
class Parameter:
    """A model or nuisance parameter: value with bounds, whether it is varied, its standard
    error, and optionally a Gaussian prior ``(mean, sd)`` (a value known with an uncertainty)."""

    name: str
    value: float
    min: float = -math.inf
    max: float = math.inf
    vary: bool = True
    unit: str = ""
    log: bool = False
    stderr: float | None = None
    tied_to: str | None = None  # value follows this parameter (lmfit's expr, for the simplest case)
    kind: str = "model"  # model | state | rig | release | offset | gain
    dataset: int | None = None  # the record a nuisance belongs to (None: shared)
    path: str | None = None  # rig field of a "state" or "rig" parameter
    prior: tuple | None = None  # (mean, sd)

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

    @property
    def simulated(self):
        return self.kind in SIM_KINDS


@dataclass
class Dataset:
    """One record with the rig it was taken on; ``setup`` (:class:`~.nuisance.RecordSetup`):
    how the record is aligned with the model (None: the model starts at t = 0, no nuisance);
    ``channels``: the record's channels that are fitted (default: the experiment's measured one)."""

    rig: object
    measurement: object
    setup: object = None
    channels: tuple = None

    @property
    def t(self):
        return self.measurement.t

    @property
    def y(self):
        return self.measurement.channel(experiment_of(self.rig.experiment).measured_channel)

    @property
    def measured_channel(self):
        return experiment_of(self.rig.experiment).measured_channel

    @property
    def fitted_channels(self):
        return tuple(self.channels) if self.channels else (self.measured_channel,)

    def mask(self):
        if self.setup is None:
            return np.ones(self.t.size, bool)
        t0, t1 = self.setup.window
        return (self.t >= t0 - 1e-12) & (self.t <= t1 + 1e-12)

    def with_window(self, t1):
        """The dataset fitted up to record time t1 only (a staged fit's first stage)."""
        if self.setup is None:
            return truncated(self, t1)
        return replace(self, setup=replace(self.setup, window=(self.setup.window[0], min(t1, self.setup.window[1]))))


@dataclass
class AlignedModel:
    """The model on a record's time axis: ``measured`` is the prediction of the measured channel
    at every record time (nan before a hand-driven start), ``channels`` the same for every
    fitted channel."""

    t: np.ndarray
    measured: np.ndarray
    channels: dict
    experiment: str
    spec: object = None


@dataclass
class FitResult:
    """Outcome of a fit. Residuals (model - record, on the fit window) and rms in the measured
    channel's unit (rad, or m for a breaker closing); aic/bic from chi^2 with noise ``sigma``
    (white) or, when ``noise`` is set, with the whitened residual (:mod:`.noise`)."""

    effects: tuple
    spring_model: SpringModel
    parameters: dict
    residuals: list  # per dataset: model - record on the window (rad or m)
    simulations: list  # per dataset: AlignedModel on the record's times
    sigma: float  # white noise level (rad or m) used for chi^2 when ``noise`` is None
    nfev: int = 0
    success: bool = True
    message: str = ""
    method: str = ""
    times: list = None  # per dataset: record times of the residual
    extra_residuals: dict = field(default_factory=dict)  # (dataset, channel) -> scaled residual (other channels)
    prior_chi2: float = 0.0
    noise: object = None  # NoiseModel used for chi2 (None: white with sigma)
    label: str = ""

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
    def model_values(self):
        """The effects' values only (no nuisance)."""
        return {p.name: p.value for p in self.parameters.values() if p.kind == "model"}

    @property
    def nuisance_values(self):
        return {p.name: p.value for p in self.parameters.values() if p.kind != "model"}

    @property
    def n_data(self):
        return int(sum(r.size for r in self.residuals))

    @property
    def n_varied(self):
        return sum(p.vary for p in self.parameters.values())

    @property
    def n_model_varied(self):
        return sum(p.vary for p in self.parameters.values() if p.kind == "model")

    def chi2_with(self, noise):
        """chi^2 of the measured channel's residual under ``noise`` (whitened), plus the
        other channels' (already scaled) and the priors'."""
        data = noise.chi2(self.residuals) if noise is not None else float(
            sum(np.sum(r**2) for r in self.residuals) / self.sigma**2)
        extra = float(sum(np.sum(r**2) for r in self.extra_residuals.values()))
        return data + extra + self.prior_chi2

    @property
    def chi2(self):
        return self.chi2_with(self.noise)

    @property
    def reduced_chi2(self):
        return self.chi2 / max(1, self.n_data - self.n_varied)

    @property
    def rms(self):
        return float(math.sqrt(sum(np.sum(r**2) for r in self.residuals) / max(1, self.n_data)))

    @property
    def max_error(self):
        return float(max(np.max(np.abs(r)) for r in self.residuals))

    @property
    def at_noise_level(self):
        return at_noise_level(float(sum(np.sum(r**2) for r in self.residuals)), self.n_data, self.sigma)

    @property
    def aic(self):
        return self.chi2 + 2 * self.n_varied

    @property
    def bic(self):
        return self.chi2 + self.n_varied * math.log(max(2, self.n_data))

    def bic_with(self, noise):
        return self.chi2_with(noise) + self.n_varied * math.log(max(2, self.n_data))

    @property
    def backend(self):
        """What ran the fit's simulations (the compiled path or Exudyn)."""
        if not self.simulations:
            return ""
        return simulation_backend(experiment_of(self.simulations[0].experiment), self.spring_model)

    def report(self):
        """A readable fit report; parameters stuck at a bound are flagged."""
        lines = [f"[[Fit]] effects: {', '.join(self.effects) or '(none)'}; spring model: {self.spring_model.label}",
                 f"    simulated with: {self.backend}",
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
            prior = f" prior {p.prior[0]:.4g} +/- {p.prior[1]:.2g}" if p.prior else ""
            lines.append(f"    {p.name:18s} = {p.value:.6g} {err} {p.unit} (bounds [{p.min:g}, {p.max:g}]){prior}{flag}")
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


class FitAborted(Exception):
    """Raised inside a fit when its stop event is set (another candidate already won)."""


#: Set by the diagnosis to abort running fits (a threading or multiprocessing Event).
STOP = None


def at_noise_level(cost, n_data, sigma):
    """Whether a sum of squared residuals is what white noise of ``sigma`` alone would give
    (within three standard deviations of the chi^2 distribution)."""
    return cost <= n_data * sigma**2 * (1 + 3 * math.sqrt(2.0 / n_data))


# --- simulations, on a pool of processes -----------------------------------------------------------

@dataclass(frozen=True)
class SimJob:
    """One simulation: the rig (with any overridden values), effects, effect values, spring
    model, the output grid (uniform from 0, or the record's times) and the channels wanted."""

    rig: object
    effects: tuple
    values: tuple  # sorted (name, value) pairs
    spring_model: object
    times: tuple  # (dt, n) for a uniform grid from 0, or None with ``sample_times``
    channels: tuple
    step: float | None = None
    sample_times: object = None  # explicit times (no nuisance)
    user_function: str = "auto"
    backend: str = "fast"  # compiled where it covers the model (vcbmodel.compiled), else Exudyn


def run_job(job):
    """Simulate one job; returns {'t': times, channel: samples, ...} or a SimulationError."""
    if job.sample_times is not None:
        times = np.asarray(job.sample_times)
    else:
        dt, n = job.times
        times = np.arange(n + 1) * dt
    try:
        r = simulate(job.rig, job.effects, dict(job.values), spring_model=job.spring_model, sample_times=times,
                     step=job.step, user_function=job.user_function, backend=job.backend)
    except SimulationError as e:
        return e
    out = {"t": times}
    for ch in job.channels:
        out[ch] = np.asarray(r.channels[ch])
    return out


class SimulationPool:
    """Worker processes (fork) that run :class:`SimJob` s; ``processes <= 1``: in this process.

    The workers are started at once, before any fitting thread exists (forking a process that
    runs threads is unsafe)."""

    def __init__(self, processes=2, inline_single=False):
        self.processes = max(1, int(processes))
        self.inline_single = inline_single  # one job at a time runs here (no other fit shares the pool)
        self.pool = None
        self.simulations = 0
        self.lock = threading.Lock()
        if self.processes > 1:
            self.pool = ProcessPoolExecutor(max_workers=self.processes, mp_context=multiprocessing.get_context("fork"))
            list(self.pool.map(_noop, range(self.processes)))

    def run(self, jobs):
        jobs = list(jobs)
        with self.lock:
            self.simulations += len(jobs)
        if self.pool is None or len(jobs) == 0:
            return [run_job(j) for j in jobs]
        if len(jobs) == 1 and self.inline_single:
            return [run_job(jobs[0])]
        if len(jobs) == 1:
            return [self.pool.submit(run_job, jobs[0]).result()]
        return list(self.pool.map(run_job, jobs))

    def cpu_seconds(self):
        """Processor time (s) used so far by this process and the pool's workers (Linux /proc;
        elsewhere this process only)."""
        total = time.process_time()
        if self.pool is None:
            return total
        tick = os.sysconf("SC_CLK_TCK") if hasattr(os, "sysconf") else 100
        for pid in list(getattr(self.pool, "_processes", {}) or {}):
            try:
                with open(f"/proc/{pid}/stat") as f:
                    fields = f.read().rsplit(")", 1)[1].split()
                total += (int(fields[11]) + int(fields[12])) / tick
            except (OSError, IndexError, ValueError):
                continue
        return total

    def close(self):
        if self.pool is not None:
            self.pool.shutdown(cancel_futures=True)
            self.pool = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _noop(_):
    return None


def dataset_pool(datasets, processes=2):
    """A simulation pool for a fit of several datasets (None for one dataset and one process)."""
    if processes < 2:
        return None
    return SimulationPool(processes)


# --- the objective -------------------------------------------------------------------------------

class _Curves:
    """A simulation's channels on its grid, as splines for shifted evaluation."""

    def __init__(self, data):
        self.t = data["t"]
        self.data = data
        self._splines = {}

    def spline(self, ch):
        s = self._splines.get(ch)
        if s is None:
            s = self._splines[ch] = CubicSpline(self.t, self.data[ch])
        return s


class _Objective:
    """Scaled residuals of the fitted channels over the records' windows, plus prior terms."""

    def __init__(self, datasets, effects, spring_model, params, pool=None, scales=None, step=None, stop=None):
        self.datasets, self.effects, self.spring_model = list(datasets), tuple(effects), spring_model
        self.params = params
        self.pool = pool
        self.step = step
        self.stop = stop
        self.varied = [p for p in params.values() if p.vary]
        self.scales = scales or {}
        self.nfev = 0
        self.best = (math.inf, None)
        self.cache = {}
        self.masks = [d.mask() for d in self.datasets]
        self.horizon = []
        for d, m in zip(self.datasets, self.masks):
            if d.setup is None:
                self.horizon.append(None)
            else:
                dt = float(np.median(np.diff(d.t)))
                lo = d.setup.release_bounds[0]
                n = int(math.ceil((d.setup.window[1] - lo) / dt)) + 2
                self.horizon.append((dt, n))

    # -- values ---------------------------------------------------------------------------------
    def values(self, x):
        vals = {p.name: p.value for p in self.params.values()}
        for p, xi in zip(self.varied, x):
            lo, hi = p.internal_bounds()
            vals[p.name] = p.from_internal(float(np.clip(xi, lo, hi)))
        for p in self.params.values():
            if p.tied_to:
                vals[p.name] = vals[p.tied_to]
        return vals

    def aligned(self, x):
        """``x`` with its alignment parameters fitted for the simulation at ``x``."""
        if not any(not p.simulated for p in self.varied):
            return x
        vals = self.values(x)
        vals = self.align(vals, self.curves([vals])[0])
        return np.array([p.to_internal(vals[p.name]) if not p.simulated else xi for p, xi in zip(self.varied, x)])

    def x0(self):
        return np.array([p.to_internal(p.value) for p in self.varied])

    def bounds(self):
        b = [p.internal_bounds() for p in self.varied]
        return np.array([lo for lo, _ in b], float), np.array([hi for _, hi in b], float)

    # -- simulations ------------------------------------------------------------------------------
    def _job(self, vals, i):
        d = self.datasets[i]
        model = {p.name: vals[p.name] for p in self.params.values() if p.kind == "model"}
        overrides = {p.path: vals[p.name] for p in self.params.values()
                     if p.kind in ("state", "rig") and p.dataset == i}
        for path, v in list(overrides.items()):
            if path.startswith("friction."):
                model[path.split(".", 1)[1]] = v
        rig = rig_with(d.rig, overrides)
        chans = tuple(dict.fromkeys(_model_channel(d, ch) for ch in d.fitted_channels))
        uf = user_function_for(rig)
        step = self.step if self.step is not None else fit_step(rig, self.spring_model)
        if d.setup is None:
            return SimJob(rig, self.effects, tuple(sorted(model.items())), self.spring_model, None, chans,
                          step, tuple(d.t), uf)
        return SimJob(rig, self.effects, tuple(sorted(model.items())), self.spring_model, self.horizon[i], chans,
                      step, None, uf)

    def _key(self, vals, i):
        return (i,) + tuple(round(vals[p.name], 15) for p in self.params.values()
                            if p.simulated and (p.dataset is None or p.dataset == i))

    def curves(self, vals_list):
        """Per value set: the list of per-dataset curves (None where a simulation failed)."""
        self._check_stop()
        todo, order = {}, []
        for vals in vals_list:
            keys = [self._key(vals, i) for i in range(len(self.datasets))]
            order.append(keys)
            for i, k in enumerate(keys):
                if k not in self.cache and k not in todo:
                    todo[k] = self._job(vals, i)
        if todo:
            runner = self.pool.run if self.pool is not None else (lambda jobs: [run_job(j) for j in jobs])
            results = runner(list(todo.values()))
            self.nfev += len(todo)
            if len(self.cache) > 256:
                self.cache.clear()
            for k, r in zip(todo, results):
                self.cache[k] = None if isinstance(r, Exception) else _Curves(r)
        return [[self.cache[k] for k in keys] for keys in order]

    def _check_stop(self):
        s = self.stop if self.stop is not None else STOP
        if s is not None and s.is_set():
            raise FitAborted()

    # -- predictions and residuals -----------------------------------------------------------------
    def predict(self, vals, curves, i, full=False):
        """{channel: (times, prediction)} of dataset i (window samples; ``full``: all samples)."""
        d = self.datasets[i]
        t = d.t if full else d.t[self.masks[i]]
        out = {}
        for ch in d.fitted_channels:
            mch = _model_channel(d, ch)
            if d.setup is None:
                y = curves.data[mch] if full else curves.data[mch][self.masks[i]]
                out[ch] = (t, _transform(d, ch, np.asarray(y), curves))
                continue
            tr = vals.get(f"release_time_{i}", d.setup.release)
            tau = np.clip(t - tr, 0.0, curves.t[-1])
            y = curves.spline(mch)(tau)
            y = _transform(d, ch, y, curves)
            g = vals.get(_gain_name(i, ch), 1.0) if _has_gain(d, ch) else 1.0
            c = vals.get(_offset_name(i, ch), 0.0) if _has_offset(d, ch) else 0.0
            pred = c + g * y
            if full and d.setup.hand_start:
                pred = np.where(t < d.setup.window[0] - 1e-12, np.nan, pred)
            out[ch] = (t, pred)
        return out

    def _scale(self, i, ch):
        return self.scales.get((i, ch), 1.0)

    def residual_parts(self, vals, curves_list):
        parts = []
        for i, d in enumerate(self.datasets):
            cur = curves_list[i]
            m = self.masks[i]
            for ch in d.fitted_channels:
                n = int(m.sum())
                if cur is None:
                    parts.append(np.full(n, FAILED))
                    continue
                _, pred = self.predict(vals, cur, i)[ch]
                y = d.measurement.channel(ch)[m]
                parts.append((pred - y) / self._scale(i, ch))
        priors = [(vals[p.name] - p.prior[0]) / p.prior[1] for p in self.varied if p.prior]
        if priors:
            parts.append(np.array(priors))
        return parts

    def residual(self, x):
        vals = self.values(x)
        curves = self.curves([vals])[0]
        r = np.concatenate(self.residual_parts(vals, curves))
        cost = float(np.dot(r, r))
        if cost < self.best[0]:
            self.best = (cost, np.array(x, float))
        return r

    def jacobian(self, x, scale=1.0):
        """Jacobian of the scaled residuals; ``scale`` multiplies the difference step."""
        vals = self.values(x)
        base = self.curves([vals])[0]
        r0 = np.concatenate(self.residual_parts(vals, base))
        J = np.zeros((r0.size, len(self.varied)))
        sims = [k for k, p in enumerate(self.varied) if p.simulated]
        lo, hi = self.bounds()
        steps, shifted = {}, []
        for k in sims:
            h = scale * self.diff_step(k, x[k])
            if x[k] + h > hi[k]:
                h = -h
            xp = np.array(x, float)
            xp[k] += h
            steps[k] = h
            shifted.append(self.values(xp))
        if shifted:
            curves = self.curves(shifted)
            for k, vals_k, cur in zip(sims, shifted, curves):
                if any(c is None for c in cur):
                    continue
                J[:, k] = (np.concatenate(self.residual_parts(vals_k, cur)) - r0) / steps[k]
        for k, p in enumerate(self.varied):
            if p.simulated:
                continue
            J[:, k] = self._analytic_column(vals, base, p)
        return J

    def _analytic_column(self, vals, curves_list, p):
        cols = []
        for i, d in enumerate(self.datasets):
            m = self.masks[i]
            cur = curves_list[i]
            for ch in d.fitted_channels:
                n = int(m.sum())
                if cur is None or p.dataset != i or d.setup is None:
                    cols.append(np.zeros(n))
                    continue
                t = d.t[m]
                tr = vals.get(f"release_time_{i}", d.setup.release)
                tau = t - tr
                inside = (tau > 0) & (tau < cur.t[-1])
                tau_c = np.clip(tau, 0.0, cur.t[-1])
                mch = _model_channel(d, ch)
                g = vals.get(_gain_name(i, ch), 1.0) if _has_gain(d, ch) else 1.0
                s = self._scale(i, ch)
                if p.kind == "offset":
                    col = np.ones(n) if p.name == _offset_name(i, ch) else np.zeros(n)
                elif p.kind == "gain":
                    col = _transform(d, ch, cur.spline(mch)(tau_c)) if p.name == _gain_name(i, ch) else np.zeros(n)
                elif p.kind == "release":
                    dy = _transform_derivative(d, ch, cur.spline(mch), tau_c)
                    col = -g * dy * inside
                else:
                    col = np.zeros(n)
                cols.append(col / s)
        col = np.concatenate(cols) if cols else np.zeros(0)
        n_priors = sum(1 for q in self.varied if q.prior)
        return np.concatenate([col, np.zeros(n_priors)]) if n_priors else col

    def diff_step(self, k, xk):
        """Forward-difference step of varied parameter k at internal value xk: relative to the
        value (a free swing's cost is a narrow valley in the friction: an absolute step of 1e-3
        in mu_k ~ 0.1 would straddle it), with a floor of 1e-4 of the parameter's range."""
        p = self.varied[k]
        if p.log:
            return DIFF_STEP
        lo, hi = p.internal_bounds()
        span = hi - lo if math.isfinite(hi - lo) else 1.0
        return DIFF_STEP * max(abs(xk), 0.1 * min(span, 1.0), 1e-9)

    def align(self, vals, curves_list, iterations=6):
        """Values with the alignment parameters (release time, offset, gain) fitted to the
        record for fixed simulations: Gauss-Newton on their analytic Jacobian, no simulation."""
        cheap = [p for p in self.varied if not p.simulated]
        if not cheap or any(c is None for c in curves_list):
            return vals
        vals = dict(vals)
        cost = math.inf
        for _ in range(iterations):
            r = np.concatenate(self.residual_parts(vals, curves_list))
            new_cost = float(np.dot(r, r))
            if new_cost > cost - 1e-6 * max(cost, 1.0):
                break
            cost = new_cost
            J = np.column_stack([self._analytic_column(vals, curves_list, p) for p in cheap])
            rows = [k for k, q in enumerate(self.varied) if q.prior]
            for j, k in enumerate(rows):  # prior rows of the cheap parameters
                q = self.varied[k]
                if q in cheap:
                    J[J.shape[0] - len(rows) + j, cheap.index(q)] = 1.0 / q.prior[1]
            try:
                step = np.linalg.lstsq(J, -r, rcond=None)[0]
            except np.linalg.LinAlgError:
                break
            trial = dict(vals)
            for p, d in zip(cheap, step):
                trial[p.name] = float(np.clip(vals[p.name] + d, p.min, p.max))
            r2 = np.concatenate(self.residual_parts(trial, curves_list))
            if float(np.dot(r2, r2)) < cost:
                vals = trial
            else:
                break
        return vals

    def prior_jacobian_fix(self, J, x):
        """Prior rows of simulated parameters: analytic (the forward difference of a prior
        residual is exact; log parameters need the chain rule only at the point)."""
        rows = [k for k, p in enumerate(self.varied) if p.prior]
        if not rows:
            return J
        start = J.shape[0] - len(rows)
        vals = self.values(x)
        for j, k in enumerate(rows):
            p = self.varied[k]
            J[start + j, :] = 0.0
            J[start + j, k] = (vals[p.name] if p.log else 1.0) / p.prior[1]
        return J


def scan_step(rig):
    """The integration step of a fit's start scan (None: the fit's own): the experiment's."""
    return experiment_of(rig.experiment).scan_step


def fit_step(rig, spring_model):
    """The integration step fits use (None: the experiment's default): the experiment's choice
    for the spring model (``Experiment.fit_step``)."""
    return experiment_of(rig.experiment).fit_step(rig, SpringModel.parse(spring_model).kind)


def user_function_for(rig):
    """The friction connector's implementation for fits: the experiment's (``Experiment.fit_user_function``)."""
    return experiment_of(rig.experiment).fit_user_function


def _model_channel(dataset, ch):
    """The simulation channel behind a record channel (``pole_i_contact`` is derived from
    ``pole_i_travel``)."""
    if ch.endswith("_contact") and ch.startswith("pole_"):
        return ch.replace("_contact", "_travel")
    return ch


def _transform(dataset, ch, y, curves=None):
    """Record channel from the simulation channel: travel from rest for pole travels (an
    analyser measures from the open position), a smooth contact indicator for pole contacts
    (1 closed: the pole's travel beyond its gap)."""
    if ch.startswith("pole_") and ch.endswith("_travel") and ch != dataset.measured_channel:
        return y - (curves.data[ch][0] if curves is not None else 0.0)
    if ch.startswith("pole_") and ch.endswith("_contact"):
        gap, width = _contact_gap(dataset, ch)
        return 0.5 * (1.0 + np.tanh((y - gap) / width))
    return y


def _transform_derivative(dataset, ch, spline, tau):
    dy = spline(tau, 1)
    if ch.startswith("pole_") and ch.endswith("_contact"):
        gap, width = _contact_gap(dataset, ch)
        y = spline(tau)
        return dy * 0.5 / width / np.cosh(np.clip((y - gap) / width, -50, 50)) ** 2
    return dy


def _contact_gap(dataset, ch):
    info = dataset.setup.contact if dataset.setup is not None else {}
    return info.get(ch, (0.0, 1e-4))


def _has_gain(dataset, ch):
    return dataset.setup is not None and not ch.endswith("_contact")


def _has_offset(dataset, ch):
    return dataset.setup is not None and not ch.endswith("_contact")


def _offset_name(i, ch):
    return f"sensor_offset_{i}" if ch in ("pendulum_angle", "cam_angle", "follower_displacement") else f"offset_{ch}_{i}"


def _gain_name(i, ch):
    return f"sensor_gain_{i}" if ch in ("pendulum_angle", "cam_angle", "follower_displacement") else f"gain_{ch}_{i}"


# --- fitting ---------------------------------------------------------------------------------------

def fit(datasets, effects, spring_model=None, params=None, *, method="least_squares", starts=None,
        sigma=None, verbose=True, label="", max_simulations=None, processes=2, pool=None, step=None,
        scales=None, stop=None, max_iterations=None, chi2_tolerance=0.1, final_jacobian=True, max_starts=1,
        enough=None):
    """Fit the varied parameters to the datasets.

    ``starts``: list of dicts of starting values tried in turn (the best result is kept).
    ``sigma``: white noise level for chi^2 / AIC / BIC (default: estimated from the data).
    ``pool``: a :class:`SimulationPool` to run simulations on (default: one of ``processes``
    processes for this fit, when it would help). ``step``: integration step override (s).
    ``max_simulations``: budget of the simplex (default 150 per varied parameter).
    ``max_starts``: with several starts, all are simulated once (in parallel) and the optimiser
    runs from the ``max_starts`` best. ``enough``: a test of a :class:`FitResult` (e.g. "its
    residual is consistent with the noise"); once the best result so far passes it, no further
    start is run. Returns a :class:`FitResult`.
    """
    datasets = list(datasets)
    rig0 = datasets[0].rig
    spring_model = SpringModel.parse(spring_model or rig0.model.spring_model, rig0.model.spring_model.convention)
    params = params or make_parameters(rig0, effects)
    if sigma is None:
        sigma = pooled_noise(datasets)
    own = None
    if pool is None and processes > 1:
        n_sim = sum(p.vary and p.simulated for p in params.values())
        if n_sim >= 2 or len(datasets) >= 2:
            own = pool = SimulationPool(processes)
    try:
        return _fit(datasets, effects, spring_model, params, method, starts, sigma, verbose, label,
                    max_simulations, pool, step, scales, stop, max_iterations, chi2_tolerance, final_jacobian,
                    max_starts, enough)
    finally:
        if own is not None:
            own.close()


def _fit(datasets, effects, spring_model, params, method, starts, sigma, verbose, label, max_simulations, pool,
         step, scales, stop, max_iterations, chi2_tolerance, final_jacobian, max_starts=1, enough=None):
    if scales is None:
        scales = {(i, ch): sigma for i, d in enumerate(datasets) for ch in d.fitted_channels}
    obj = _Objective(datasets, effects, spring_model, params, pool, scales, step, stop)
    varied = obj.varied
    best_x, best_cost, success, message, best_jac = obj.x0(), math.inf, True, "", None
    if varied:
        start_points = [obj.x0()]
        for s in starts or []:
            start_points.append(np.array([p.to_internal(float(np.clip(s.get(p.name, p.value), p.min, p.max)))
                                          for p in varied]))
        lo, hi = obj.bounds()
        start_points = [np.clip(x0, lo + 1e-9 * np.minimum(hi - lo, 1e9), hi - 1e-9 * np.minimum(hi - lo, 1e9))
                        for x0 in start_points]
        # a start given twice (a scan's own point is the fit's own start) would run the optimiser twice
        unique = {}
        for x0 in start_points:
            unique.setdefault(tuple(np.round(x0, 12)), x0)
        start_points = list(unique.values())
        if len(start_points) > 1 and method != "nelder-mead":
            start_points = _rank_starts(obj, start_points)[:max_starts]
        for k, x0 in enumerate(start_points):
            x0 = obj.aligned(x0)
            if method == "nelder-mead":
                span = np.where(np.isfinite(hi - lo), hi - lo, 1.0)
                simplex = [x0] + [x0 + np.eye(len(x0))[i] * 0.1 * span[i] * (1 if x0[i] + 0.1 * span[i] <= hi[i] else -1)
                                  for i in range(len(x0))]
                res = minimize(lambda x: float(np.sum(obj.residual(x) ** 2)), x0, method="Nelder-Mead",
                               bounds=list(zip(lo, hi)),
                               options={"initial_simplex": np.array(simplex), "xatol": 1e-4, "fatol": 1e-12,
                                        "maxfev": max_simulations or 150 * len(x0)})
                x, cost, jac = res.x, float(res.fun), None
                budget = max_simulations or 150 * len(x0)
                ok, msg = (True, f"at its budget of {budget} simulations") if res.nfev >= budget else (
                    bool(res.success), str(res.message))
            else:
                x, cost, jac, ok, msg = levenberg_marquardt(obj, x0, lo, hi, max_iterations or 10 + 2 * len(x0),
                                                            chi2_tolerance, final_jacobian)
            if verbose:
                progress(f"  fit {label or ', '.join(effects)} start {k + 1}/{len(start_points)}: "
                         f"rms {_rms_of_cost(obj, x):.3g} {experiment_of(datasets[0].rig.experiment).unit} "
                         f"after {obj.nfev} simulations")
            if cost < best_cost:
                best_x, best_cost, success, message, best_jac = x, cost, ok, msg, jac
            if _rms_of_cost(obj, best_x) <= 1.05 * sigma:
                break  # at the noise level: further starts cannot do better
            if enough is not None and k + 1 < len(start_points) and enough(
                    _result(obj, best_x, best_jac, effects, spring_model, params, sigma, success, message, method)):
                break  # the caller's test of "as good as it gets" (e.g. consistent with correlated noise)
        if obj.best[0] < best_cost - 1e-9:  # a trial point better than any optimiser end point
            best_x, best_jac = obj.best[1], None
    return _result(obj, best_x, best_jac, effects, spring_model, params, sigma, success, message, method)


def levenberg_marquardt(obj, x0, lo, hi, max_iterations, chi2_tolerance=0.1, final_jacobian=True, jacobian=None):
    """Bounded Levenberg-Marquardt on the objective's scaled residuals (chi^2 = sum r^2).

    Stops when the step the linear model predicts would lower chi^2 by less than a tolerance
    (``chi2_tolerance``, or :data:`RELATIVE_TOLERANCE` of the chi^2 that noise alone would
    leave: a change far below what any comparison of models or any standard error can see), so
    a converged fit ends on a Jacobian, without a last confirming simulation. Parameters at a
    bound whose gradient points outwards are held there. When no damping gives descent (a
    free swing's cost has kinks where a stop comes a step earlier or later), the Jacobian is
    taken once more with ten times the difference step, which averages over the kinks.
    ``final_jacobian=False``: after a small step that the linear model predicted well, stop
    without a new Jacobian (the one before the step serves for the standard errors; used by a
    polish that starts next to the optimum). Returns (x, chi^2, Jacobian, success, message)."""
    jacobian = jacobian or (lambda x, scale=1.0: obj.prior_jacobian_fix(obj.jacobian(x, scale), x))
    x = np.array(x0, float)
    r = obj.residual(x)
    cost = float(np.dot(r, r))
    J = jacobian(x)
    lam = INITIAL_DAMPING
    widened = False
    for it in range(max_iterations):
        g = J.T @ r
        H = J.T @ J
        d = np.maximum(np.diag(H), 1e-12 * max(1.0, float(np.max(np.diag(H)))))
        free = np.ones(x.size, bool)
        free &= ~((x <= lo + 1e-12) & (g > 0))
        free &= ~((x >= hi - 1e-12) & (g < 0))
        accepted = False
        # relative to the cost the noise alone would leave (about one per sample), not to the
        # current cost: far from the optimum a small predicted gain means a poor linear model
        tolerance = max(chi2_tolerance, RELATIVE_TOLERANCE * min(cost, r.size))
        for attempt in range(6):
            step = _bounded_step(H, g, d, lam, x, lo, hi, free)
            x_new = np.clip(x + step, lo, hi)
            step = x_new - x
            predicted = -(2 * g @ step + step @ H @ step)
            if predicted < tolerance:
                if predicted < -1e-9 * max(cost, 1.0):  # not a descent step (bounds): damp more
                    lam *= 10.0
                    continue
                return x, cost, J, True, f"converged (predicted chi2 change {predicted:.2g}) after {it} iterations"
            r_new = obj.residual(x_new)
            cost_new = float(np.dot(r_new, r_new))
            log.debug("LM it %d lam %.2g cost %.6g -> %.6g predicted %.3g free %d", it, lam, cost, cost_new,
                      predicted, free.sum())
            if cost_new < cost:
                gain = cost - cost_new
                x, r, cost = x_new, r_new, cost_new
                lam = max(lam / 5.0, 1e-7)
                accepted = True
                break
            lam *= 10.0
        if not accepted:
            if widened or jacobian is None:
                return x, cost, J, True, f"no further descent after {it} iterations"
            J = jacobian(x, 10.0)
            widened, lam = True, 1e-2
            continue
        if not final_jacobian and gain >= 0.7 * predicted and predicted < 0.1 * cost:
            return x, cost, J, True, f"converged: a last step as predicted (chi2 change {gain:.3g})"
        J = jacobian(x)
        if gain < tolerance:
            return x, cost, J, True, f"converged (chi2 change {gain:.2g}) after {it + 1} iterations"
    return x, cost, J, True, f"at the iteration limit ({max_iterations})"


def _bounded_step(H, g, d, lam, x, lo, hi, free):
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


def _rank_starts(obj, points):
    """Start points ordered by their cost (all simulated at once on the pool, alignment fitted
    for each): the optimiser then runs from the best only."""
    vals = [obj.values(x) for x in points]
    curves = obj.curves(vals)
    scored = []
    for x, v, cur in zip(points, vals, curves):
        v = obj.align(v, cur)
        r = np.concatenate(obj.residual_parts(v, cur))
        xa = np.array([p.to_internal(v[p.name]) if not p.simulated else xi for p, xi in zip(obj.varied, x)])
        scored.append((float(np.dot(r, r)), xa))
    scored.sort(key=lambda c: c[0])
    return [x for _, x in scored]


def _rms_of_cost(obj, x):
    vals = obj.values(x)
    cur = obj.curves([vals])[0]
    res = []
    for i, d in enumerate(obj.datasets):
        if cur[i] is None:
            return float("nan")
        _, pred = obj.predict(vals, cur[i], i)[d.measured_channel] if d.measured_channel in d.fitted_channels else (None, None)
        if pred is not None:
            res.append(pred - d.y[obj.masks[i]])
    r = np.concatenate(res) if res else np.zeros(1)
    return float(np.sqrt(np.mean(r**2)))


def _result(obj, x, jac, effects, spring_model, params, sigma, success, message, method):
    values = obj.values(x)
    fitted = {name: replace(p, value=values[name], stderr=None) for name, p in params.items()}
    curves = obj.curves([values])[0]
    residuals, sims, times, extra = [], [], [], {}
    for i, d in enumerate(obj.datasets):
        cur = curves[i]
        m = obj.masks[i]
        if cur is None:
            raise SimulationError(f"the fitted model's simulation failed ({', '.join(effects) or 'no effects'})")
        full = obj.predict(values, cur, i, full=True)
        for ch, (_, pred) in full.items():
            r = pred[m] - d.measurement.channel(ch)[m]
            if ch == d.measured_channel:
                residuals.append(r)
            else:
                extra[(i, ch)] = r / obj._scale(i, ch)
        times.append(d.t[m])
        ch_meas = full.get(d.measured_channel, (None, np.full(d.t.size, np.nan)))[1]
        sims.append(AlignedModel(d.t, ch_meas, {ch: p for ch, (_, p) in full.items()}, d.rig.experiment))
    prior_chi2 = float(sum(((values[p.name] - p.prior[0]) / p.prior[1]) ** 2 for p in obj.varied if p.prior))
    result = FitResult(tuple(effects), spring_model, fitted, residuals, sims, sigma, obj.nfev, success, message, method,
                       times, extra, prior_chi2)
    result.jacobian = (tuple(p.name for p in obj.varied), jac)
    if obj.varied:
        _standard_errors(result, obj, x, jac)
    return result


def _standard_errors(result, obj, x, jac=None):
    """stderr from the Jacobian of the scaled residuals at the optimum: cov = s^2 (J^T J)^-1,
    s^2 the reduced chi^2 (the Jacobian of the last least-squares step when there is one)."""
    if jac is None:
        jac = obj.prior_jacobian_fix(obj.jacobian(x), x)
    J = np.asarray(jac)
    r0 = obj.residual(x)
    dof = max(1, r0.size - len(x))
    s2 = float(np.dot(r0, r0)) / dof
    try:
        # by the singular values of J: a direction the data do not determine gets the huge
        # variance it has (a pseudo-inverse would set it to zero and report false precision)
        _, sv, vt = np.linalg.svd(J, full_matrices=False)
    except np.linalg.LinAlgError:
        return
    inv = np.where(sv > 1e-300, 1.0 / np.maximum(sv, 1e-300) ** 2, np.inf)
    cov = (vt.T * inv) @ vt * s2
    for i, p in enumerate(obj.varied):
        var = cov[i, i]
        if not (var >= 0 and math.isfinite(var)):
            continue
        sd = math.sqrt(var)
        result.parameters[p.name].stderr = result.parameters[p.name].value * sd if p.log else sd


def jacobian_of(result):
    """(names of the varied parameters, Jacobian of the scaled residuals) at a fit's optimum."""
    return getattr(result, "jacobian", (None, None))


def refine(datasets, effects, spring_model, params, hint, *, pool=None, scales=None, sigma=None, stop=None,
           label="", max_iterations=3):
    """Refit from ``params`` a model that differs from a fitted one only in structure (another
    spring model), borrowing that fit's Jacobian ``hint`` (:func:`jacobian_of`) for the
    simulation parameters: one simulation per step. The alignment columns are recomputed."""
    names, J0 = hint
    datasets = list(datasets)
    if sigma is None:
        sigma = pooled_noise(datasets)
    if scales is None:
        scales = {(i, ch): sigma for i, d in enumerate(datasets) for ch in d.fitted_channels}
    obj = _Objective(datasets, effects, spring_model, params, pool, scales, None, stop)
    x0 = obj.x0()
    lo, hi = obj.bounds()
    if J0 is None or names != tuple(p.name for p in obj.varied):
        x, cost, jac, ok, msg = levenberg_marquardt(obj, x0, lo, hi, max_iterations)
    else:
        def jacobian(x, scale=1.0):
            vals = obj.values(x)
            base = obj.curves([vals])[0]
            J = np.array(J0, float, copy=True)
            for k, p in enumerate(obj.varied):
                if not p.simulated:
                    J[:, k] = obj._analytic_column(vals, base, p)
            return obj.prior_jacobian_fix(J, x)
        x, cost, jac, ok, msg = levenberg_marquardt(obj, x0, lo, hi, max_iterations, jacobian=jacobian)
    result = _result(obj, x, jac, effects, spring_model, params, sigma, ok, msg, "refine (borrowed Jacobian)")
    result.label = label
    return result


def truncated(dataset, t_max):
    """The dataset restricted to t <= t_max."""
    m = dataset.measurement
    keep = m.t <= t_max
    sub = replace(m, t=m.t[keep], channels={k: v[keep] for k, v in m.channels.items()})
    return replace(dataset, measurement=sub)


def scan_starts(datasets, effects, spring_model, params, grid, keep=1, pool=None, scales=None, step=None,
                bases=None):
    """Evaluate the cost on a coarse grid (dict name -> values) with the other parameters at
    their current values, or at each of ``bases`` (dicts of values), all grid points simulated at
    once on the pool; return the ``keep`` best points of each base as start dicts."""
    obj = _Objective(datasets, effects, spring_model or datasets[0].rig.model.spring_model, params, pool, scales,
                     step)
    names = [n for n in grid if n in params and params[n].vary]
    combos = [dict(zip(names, c)) for c in itertools.product(*(grid[n] for n in names))]
    if not combos:
        return []
    combos.append({n: params[n].value for n in names})  # the parameters' own starting values
    bases = bases or [{}]
    out = []
    for base in bases:
        out += _scan(obj, params, [{**{k: v for k, v in base.items() if k in params}, **c} for c in combos], keep)
    return out


def _scan(obj, params, combos, keep):
    vals_list = []
    for start in combos:
        vals = {p.name: p.value for p in params.values()}
        vals.update({k: float(np.clip(v, params[k].min, params[k].max)) for k, v in start.items()})
        vals_list.append(vals)
    curves = obj.curves(vals_list)
    scored = []
    for start, vals, cur in zip(combos, vals_list, curves):
        if any(c is None for c in cur):
            continue
        v = obj.align(vals, cur)
        r = np.concatenate(obj.residual_parts(v, cur))
        scored.append((float(np.dot(r, r)), {**start, **{p.name: v[p.name] for p in obj.varied if not p.simulated}}))
    scored.sort(key=lambda s: s[0])
    return [s for _, s in scored[:keep]]


def staged_fit(datasets, effects, spring_model=None, params=None, *, starts=None, sigma=None,
               verbose=True, label="", method="least_squares", scan=None, pool=None, processes=2, scales=None,
               stop=None, coarse_step=None, bases=None, max_starts=1):
    """Fit first while the pendulum still swings, then the whole record.

    After a free swing sticks, the stuck angle depends discontinuously on the friction
    (one half-swing more or less), so the full-record cost has many local minima. The
    swinging part is smooth in the parameters: fitting it first (from every start) and then
    polishing on the full record (from that result) finds the global minimum reliably.
    ``scan`` (dict name -> values): the best points of that coarse grid, evaluated on the
    swinging part, are tried as the first starts. ``coarse_step``: integration step of the
    first stage (s; a longer step there halves its cost, the polish uses the default).
    """
    datasets = list(datasets)
    if sigma is None:
        sigma = pooled_noise(datasets)
    own = None
    if pool is None and processes > 1:
        own = pool = SimulationPool(processes)
    try:
        early = []
        for d in datasets:
            m = d.mask()
            t_stop = experiment_of(d.rig.experiment).swinging_part(d.t[m], d.y[m], sigma)
            early.append(d if t_stop is None else d.with_window(t_stop))
        params = params or make_parameters(datasets[0].rig, effects)
        if scan:
            starts = scan_starts(early, effects, spring_model, params, scan, pool=pool, scales=scales,
                                 step=coarse_step, bases=bases) + list(starts or [])
        same = all(e is d for e, d in zip(early, datasets))
        if same and coarse_step is None:
            return fit(datasets, effects, spring_model, params, starts=starts, sigma=sigma, verbose=verbose,
                       label=label, method=method, pool=pool, processes=1, scales=scales, stop=stop,
                       max_starts=max_starts)
        first = fit(early, effects, spring_model, params, starts=starts, sigma=sigma, verbose=verbose,
                    label=f"{label} (while swinging)" if not same else f"{label} (coarse)", method=method, pool=pool,
                    processes=1, scales=scales, stop=stop, step=coarse_step, max_starts=max_starts,
                    final_jacobian=False)
        result = fit(datasets, effects, spring_model, first.parameters, sigma=sigma, verbose=verbose,
                     label=f"{label} (whole record)", method=method, pool=pool, processes=1, scales=scales,
                     stop=stop, max_iterations=5, final_jacobian=False)
        result.nfev += first.nfev
        return result
    finally:
        if own is not None:
            own.close()

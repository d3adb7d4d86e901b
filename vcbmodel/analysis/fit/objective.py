"""The fit's objective: scaled residuals of the fitted channels over the records' windows, plus
prior terms, and their Jacobian (forward differences for the simulation parameters, analytic
columns for the alignment parameters of :mod:`..nuisance`)."""
from __future__ import annotations

import math
from typing import Callable

import numpy as np
from scipy.interpolate import CubicSpline

from ...rig.paths import loaded_with
from .arithmetic import quiet_trial
from .dataset import (TIME_SCALE_SPAN, as_recorded, as_recorded_derivative, gain_name, has_gain, has_offset,
                      model_channel, model_time, offset_name, time_scale_name)
from .options import FitAborted
from .parameters import DIFF_STEP, FAILED
from .pool import SimJob, fit_step, run_job, user_function_for


class Curves:
    """A simulation's channels on its grid (``data``: {'t': times (s), channel: samples}), as
    splines for shifted evaluation."""

    def __init__(self, data: dict):
        self.t = data["t"]
        self.data = data
        self._splines = {}

    def spline(self, ch: str) -> CubicSpline:
        s = self._splines.get(ch)
        if s is None:
            s = self._splines[ch] = CubicSpline(self.t, self.data[ch])
        return s


def simulation_horizon(dataset, time_scaled: bool = False) -> tuple | None:
    """(dt, n) of the uniform grid a dataset with a setup is simulated on: the record's sample
    interval (s), long enough from the earliest release to the window's end (None: no setup, the
    record's own times); ``time_scaled``: long enough for the largest time scale too."""
    if dataset.setup is None:
        return None
    dt = float(np.median(np.diff(dataset.t)))
    lo = dataset.setup.release_bounds[0]
    stretch = 1.0 + TIME_SCALE_SPAN if time_scaled else 1.0
    n = int(math.ceil((dataset.setup.window[1] - lo) * stretch / dt)) + 2
    return (dt, n)


class Objective:
    """Scaled residuals of the fitted channels over the records' windows, plus prior terms.

    Parameters
    ----------
    datasets : sequence of Dataset
    effects : sequence of str
    spring_model : SpringModel
    params : dict of str to Parameter
        All parameters (the varied ones are the optimiser's coordinates, in this order).
    pool : SimulationPool, optional
        Runs the simulations (default: in this process).
    scales : dict, optional
        (dataset, channel) -> residual weight (the channel's unit; default 1).
    step : float, optional
        Integration step (s; default: the experiment's for fits).
    should_stop : callable, optional
        Asked before every batch of simulations; True raises :class:`FitAborted`.
    """

    def __init__(self, datasets, effects, spring_model, params, pool=None, scales=None, step=None,
                 should_stop: Callable[[], bool] | None = None):
        self.datasets, self.effects, self.spring_model = list(datasets), tuple(effects), spring_model
        self.params = params
        self.pool = pool
        self.step = step
        self.should_stop = should_stop
        self.varied = [p for p in params.values() if p.vary]
        self.scales = scales or {}
        self.nfev = 0
        self.best = (math.inf, None)  # (chi^2, x) of the best point evaluated
        self.cache = {}
        self.masks = [d.mask() for d in self.datasets]
        self.horizon = [simulation_horizon(d, time_scale_name(i) in params) for i, d in enumerate(self.datasets)]
        # a record's own times as Python floats, made once: a job's cache key pickles them (numpy scalars
        # pickle by reduction, ~20x slower: that was 60 % of an identification's time)
        self.sample_times = [tuple(np.asarray(d.t, float).tolist()) if d.setup is None else None for d in self.datasets]

    # -- values ---------------------------------------------------------------------------------
    def values(self, x) -> dict:
        """{name: value} of every parameter at internal coordinates ``x`` (clipped to the bounds)."""
        vals = {p.name: p.value for p in self.params.values()}
        for p, xi in zip(self.varied, x):
            lo, hi = p.internal_bounds()
            vals[p.name] = p.from_internal(float(np.clip(xi, lo, hi)))
        for p in self.params.values():
            if p.tied_to:
                vals[p.name] = vals[p.tied_to]
        return vals

    def aligned(self, x) -> np.ndarray:
        """``x`` with its alignment parameters fitted for the simulation at ``x``."""
        if not any(not p.simulated for p in self.varied):
            return x
        vals = self.values(x)
        vals = self.align(vals, self.curves([vals])[0])
        return self.internal_with_alignment(x, vals)

    def internal_with_alignment(self, x, vals) -> np.ndarray:
        """``x`` with the alignment parameters' coordinates taken from ``vals``."""
        return np.array([p.to_internal(vals[p.name]) if not p.simulated else xi for p, xi in zip(self.varied, x)])

    def x0(self) -> np.ndarray:
        return np.array([p.to_internal(p.value) for p in self.varied])

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        b = [p.internal_bounds() for p in self.varied]
        return np.array([lo for lo, _ in b], float), np.array([hi for _, hi in b], float)

    # -- simulations ------------------------------------------------------------------------------
    def simulation_job(self, vals: dict, i: int) -> SimJob:
        """The simulation of dataset ``i`` at parameter values ``vals``."""
        d = self.datasets[i]
        model = {p.name: vals[p.name] for p in self.params.values() if p.kind == "model"}
        overrides = {p.path: vals[p.name] for p in self.params.values()
                     if p.kind in ("state", "rig") and p.dataset == i}
        for path, v in list(overrides.items()):
            if path.startswith("friction."):
                model[path.split(".", 1)[1]] = v
        rig = loaded_with(d.rig, overrides)
        chans = tuple(dict.fromkeys(model_channel(d, ch) for ch in d.fitted_channels))
        uf = user_function_for(rig)
        step = self.step if self.step is not None else fit_step(rig, self.spring_model)
        if d.setup is None:
            return SimJob(rig, self.effects, tuple(sorted(model.items())), self.spring_model, None, chans,
                          step, self.sample_times[i], uf)
        return SimJob(rig, self.effects, tuple(sorted(model.items())), self.spring_model, self.horizon[i], chans,
                      step, None, uf)

    def _key(self, vals, i):
        return (i,) + tuple(round(vals[p.name], 15) for p in self.params.values()
                            if p.simulated and (p.dataset is None or p.dataset == i))

    def curves(self, vals_list) -> list:
        """Per value set: the list of per-dataset curves (None where a simulation failed)."""
        self._check_stop()
        todo, order = {}, []
        for vals in vals_list:
            keys = [self._key(vals, i) for i in range(len(self.datasets))]
            order.append(keys)
            for i, k in enumerate(keys):
                if k not in self.cache and k not in todo:
                    todo[k] = self.simulation_job(vals, i)
        if todo:
            runner = self.pool.run if self.pool is not None else (lambda jobs: [run_job(j) for j in jobs])
            results = runner(list(todo.values()))
            self.nfev += len(todo)
            if len(self.cache) > 256:
                self.cache.clear()
            for k, r in zip(todo, results):
                self.cache[k] = None if isinstance(r, Exception) else Curves(r)
        return [[self.cache[k] for k in keys] for keys in order]

    def _check_stop(self):
        if self.should_stop is not None and self.should_stop():
            raise FitAborted()

    # -- predictions and residuals -----------------------------------------------------------------
    def predict(self, vals, curves, i, full=False) -> dict:
        """{channel: (times (s), prediction)} of dataset i (window samples; ``full``: all samples)."""
        d = self.datasets[i]
        t = d.t if full else d.t[self.masks[i]]
        out = {}
        for ch in d.fitted_channels:
            mch = model_channel(d, ch)
            if d.setup is None:
                y = curves.data[mch] if full else curves.data[mch][self.masks[i]]
                out[ch] = (t, as_recorded(d, ch, np.asarray(y), curves))
                continue
            tr = vals.get(f"release_time_{i}", d.setup.release)
            tau = np.clip(model_time(t, tr, vals.get(time_scale_name(i), 1.0)), 0.0, curves.t[-1])
            y = curves.spline(mch)(tau)
            y = as_recorded(d, ch, y, curves)
            g = vals.get(gain_name(i, ch), 1.0) if has_gain(d, ch) else 1.0
            c = vals.get(offset_name(i, ch), 0.0) if has_offset(d, ch) else 0.0
            pred = c + g * y
            if full and d.setup.hand_start:
                pred = np.where(t < d.setup.window[0] - 1e-12, np.nan, pred)
            out[ch] = (t, pred)
        return out

    def scale(self, i: int, ch: str) -> float:
        """Residual weight of channel ``ch`` of dataset ``i`` (the channel's unit)."""
        return self.scales.get((i, ch), 1.0)

    def residual_parts(self, vals, curves_list) -> list:
        """Scaled residuals per dataset and channel (window samples), then the priors'."""
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
                parts.append((pred - y) / self.scale(i, ch))
        priors = [(vals[p.name] - p.prior[0]) / p.prior[1] for p in self.varied if p.prior]
        if priors:
            parts.append(np.array(priors))
        return parts

    @quiet_trial
    def residual(self, x) -> np.ndarray:
        """Scaled residual vector at internal coordinates ``x`` (chi^2 = its squared norm)."""
        vals = self.values(x)
        curves = self.curves([vals])[0]
        r = np.concatenate(self.residual_parts(vals, curves))
        cost = float(np.dot(r, r))
        if cost < self.best[0]:
            self.best = (cost, np.array(x, float))
        return r

    @quiet_trial
    def measured_rms(self, x) -> float:
        """rms of the measured channel's residual at ``x`` (its unit; nan when a simulation failed)."""
        vals = self.values(x)
        cur = self.curves([vals])[0]
        res = []
        for i, d in enumerate(self.datasets):
            if cur[i] is None:
                return float("nan")
            _, pred = self.predict(vals, cur[i], i)[d.measured_channel] if d.measured_channel in d.fitted_channels else (None, None)
            if pred is not None:
                res.append(pred - d.y[self.masks[i]])
        r = np.concatenate(res) if res else np.zeros(1)
        return float(np.sqrt(np.mean(r**2)))

    # -- Jacobian ---------------------------------------------------------------------------------
    @quiet_trial
    def jacobian(self, x, scale=1.0) -> np.ndarray:
        """Jacobian of the scaled residuals; ``scale`` multiplies the difference step."""
        vals = self.values(x)
        base = self.curves([vals])[0]
        r0 = np.concatenate(self.residual_parts(vals, base))
        J = np.zeros((r0.size, len(self.varied)))
        self._difference_columns(J, x, r0, scale)
        for k, p in enumerate(self.varied):
            if p.simulated:
                continue
            J[:, k] = self.alignment_column(vals, base, p)
        return J

    def _difference_columns(self, J, x, r0, scale):
        """Forward-difference columns of the simulated parameters into J (all shifted
        simulations at once on the pool; a failed one leaves its column zero)."""
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

    def alignment_column(self, vals, curves_list, p) -> np.ndarray:
        """Analytic column of alignment parameter ``p`` (release time, offset, gain, time scale) in the
        Jacobian of the scaled residuals (zero prior rows)."""
        cols = []
        for i, d in enumerate(self.datasets):
            m = self.masks[i]
            cur = curves_list[i]
            for ch in d.fitted_channels:
                n = int(m.sum())
                if cur is None or p.dataset != i or d.setup is None:
                    cols.append(np.zeros(n))
                    continue
                cols.append(self._channel_derivative(vals, cur, i, ch, p) / self.scale(i, ch))
        col = np.concatenate(cols) if cols else np.zeros(0)
        n_priors = sum(1 for q in self.varied if q.prior)
        return np.concatenate([col, np.zeros(n_priors)]) if n_priors else col

    def _channel_derivative(self, vals, cur, i, ch, p):
        """d(prediction of channel ``ch`` of dataset ``i``)/d(p) on the window, unscaled."""
        d = self.datasets[i]
        m = self.masks[i]
        n = int(m.sum())
        t = d.t[m]
        tr = vals.get(f"release_time_{i}", d.setup.release)
        k = vals.get(time_scale_name(i), 1.0)
        tau = model_time(t, tr, k)
        inside = (tau > 0) & (tau < cur.t[-1])
        tau_c = np.clip(tau, 0.0, cur.t[-1])
        mch = model_channel(d, ch)
        g = vals.get(gain_name(i, ch), 1.0) if has_gain(d, ch) else 1.0
        if p.kind == "offset":
            return np.ones(n) if p.name == offset_name(i, ch) else np.zeros(n)
        if p.kind == "gain":
            return as_recorded(d, ch, cur.spline(mch)(tau_c)) if p.name == gain_name(i, ch) else np.zeros(n)
        if p.kind == "release":
            dy = as_recorded_derivative(d, ch, cur.spline(mch), tau_c)
            return -g * k * dy * inside
        if p.kind == "time_scale" and p.name == time_scale_name(i):
            dy = as_recorded_derivative(d, ch, cur.spline(mch), tau_c)
            return g * (t - tr) * dy * inside
        return np.zeros(n)

    def diff_step(self, k, xk) -> float:
        """Forward-difference step of varied parameter k at internal value xk: relative to the
        value (a free swing's cost is a narrow valley in the friction: an absolute step of 1e-3
        in mu_k ~ 0.1 would straddle it), with a floor of 1e-4 of the parameter's range."""
        p = self.varied[k]
        if p.log:
            return DIFF_STEP
        lo, hi = p.internal_bounds()
        span = hi - lo if math.isfinite(hi - lo) else 1.0
        return DIFF_STEP * max(abs(xk), 0.1 * min(span, 1.0), 1e-9)

    # -- alignment without simulating -------------------------------------------------------------
    def align(self, vals, curves_list, iterations=6) -> dict:
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
            J = self._alignment_jacobian(vals, curves_list, cheap)
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

    def _alignment_jacobian(self, vals, curves_list, cheap):
        """Columns of the alignment parameters ``cheap``, with their prior rows."""
        J = np.column_stack([self.alignment_column(vals, curves_list, p) for p in cheap])
        rows = [k for k, q in enumerate(self.varied) if q.prior]
        for j, k in enumerate(rows):  # prior rows of the cheap parameters
            q = self.varied[k]
            if q in cheap:
                J[J.shape[0] - len(rows) + j, cheap.index(q)] = 1.0 / q.prior[1]
        return J

    def prior_jacobian_fix(self, J, x) -> np.ndarray:
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

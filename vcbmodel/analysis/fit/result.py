"""A fit's outcome (:class:`FitResult`): residuals, chi^2 and information criteria, standard
errors from the Jacobian at the optimum, and an lmfit-like report."""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from ...errors import SimulationError
from ...experiments import experiment_of
from ...experiments.simulation import simulation_backend
from ...rig.spring_model import SpringModel
from .dataset import AlignedModel
from .parameters import at_noise_level

if TYPE_CHECKING:
    from ..noise import NoiseModel


@dataclass
class FitResult:
    """Outcome of a fit. Residuals (model - record, on the fit window) and rms in the measured
    channel's unit (rad, or m for a breaker closing); aic/bic from chi^2 with noise ``sigma``
    (white) or, when ``noise`` is set, with the whitened residual (:mod:`..noise`)."""

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
    def unit(self) -> str:
        return experiment_of(self.simulations[0].experiment).unit if self.simulations else "rad"

    @property
    def spring_model_label(self) -> str:
        """The spring model with its lumped convention, for reports."""
        return self.spring_model.label

    @property
    def values(self) -> dict[str, float]:
        return {p.name: p.value for p in self.parameters.values()}

    @property
    def model_values(self) -> dict[str, float]:
        """The effects' values only (no nuisance)."""
        return {p.name: p.value for p in self.parameters.values() if p.kind == "model"}

    @property
    def nuisance_values(self) -> dict[str, float]:
        return {p.name: p.value for p in self.parameters.values() if p.kind != "model"}

    @property
    def n_data(self) -> int:
        return int(sum(r.size for r in self.residuals))

    @property
    def n_varied(self) -> int:
        return sum(p.vary for p in self.parameters.values())

    @property
    def n_model_varied(self) -> int:
        return sum(p.vary for p in self.parameters.values() if p.kind == "model")

    def chi2_with(self, noise: NoiseModel | None) -> float:
        """chi^2 of the measured channel's residual under ``noise`` (whitened), plus the
        other channels' (already scaled) and the priors'."""
        data = noise.chi2(self.residuals) if noise is not None else float(
            sum(np.sum(r**2) for r in self.residuals) / self.sigma**2)
        extra = float(sum(np.sum(r**2) for r in self.extra_residuals.values()))
        return data + extra + self.prior_chi2

    @property
    def chi2(self) -> float:
        return self.chi2_with(self.noise)

    @property
    def reduced_chi2(self) -> float:
        return self.chi2 / max(1, self.n_data - self.n_varied)

    @property
    def rms(self) -> float:
        return float(math.sqrt(sum(np.sum(r**2) for r in self.residuals) / max(1, self.n_data)))

    @property
    def max_error(self) -> float:
        return float(max(np.max(np.abs(r)) for r in self.residuals))

    @property
    def at_noise_level(self) -> bool:
        return at_noise_level(float(sum(np.sum(r**2) for r in self.residuals)), self.n_data, self.sigma)

    @property
    def aic(self) -> float:
        return self.chi2 + 2 * self.n_varied

    @property
    def bic(self) -> float:
        return self.chi2 + self.n_varied * math.log(max(2, self.n_data))

    def bic_with(self, noise: NoiseModel | None) -> float:
        return self.chi2_with(noise) + self.n_varied * math.log(max(2, self.n_data))

    @property
    def backend(self) -> str:
        """What ran the fit's simulations (the compiled path or Exudyn)."""
        if not self.simulations:
            return ""
        return simulation_backend(experiment_of(self.simulations[0].experiment), self.spring_model)

    def report(self) -> str:
        """A readable fit report; parameters stuck at a bound are flagged."""
        lines = [f"[[Fit]] effects: {', '.join(self.effects) or '(none)'}; spring model: {self.spring_model.label}",
                 f"    simulated with: {self.backend}",
                 f"    method {self.method}, {self.nfev} simulations, {'converged' if self.success else 'stopped: ' + self.message}",
                 f"    data points {self.n_data}, varied {self.n_varied}, noise sigma {self.sigma:.3g} {self.unit}",
                 f"    rms {self.rms:.4g} {self.unit}, max |error| {self.max_error:.4g} {self.unit}, reduced chi2 {self.reduced_chi2:.3f}",
                 f"    AIC {self.aic:.1f}, BIC {self.bic:.1f}", "[[Parameters]]"]
        lines += [_report_line(p) for p in self.parameters.values()]
        return "\n".join(lines)


def _report_line(p) -> str:
    if not p.vary:
        how = f"tied to {p.tied_to}" if p.tied_to else "fixed"
        return f"    {p.name:18s} = {p.value:.6g} {p.unit} ({how})"
    err = f"+/- {p.stderr:.3g}" if p.stderr is not None and math.isfinite(p.stderr) else "+/- ?"
    flag = "  AT BOUND [%g, %g]" % (p.min, p.max) if p.at_bound() else ""
    prior = f" prior {p.prior[0]:.4g} +/- {p.prior[1]:.2g}" if p.prior else ""
    return f"    {p.name:18s} = {p.value:.6g} {err} {p.unit} (bounds [{p.min:g}, {p.max:g}]){prior}{flag}"


def build_result(obj, x, jac, sigma: float, success: bool, message: str, method: str) -> FitResult:
    """The :class:`FitResult` of objective ``obj`` at internal coordinates ``x`` (one more
    simulation unless cached), with standard errors from ``jac`` (None: a new Jacobian)."""
    values = obj.values(x)
    fitted = {name: replace(p, value=values[name], stderr=None) for name, p in obj.params.items()}
    residuals, sims, times, extra = _aligned_outputs(obj, values)
    prior_chi2 = float(sum(((values[p.name] - p.prior[0]) / p.prior[1]) ** 2 for p in obj.varied if p.prior))
    result = FitResult(tuple(obj.effects), obj.spring_model, fitted, residuals, sims, sigma, obj.nfev, success, message,
                       method, times, extra, prior_chi2)
    result.jacobian = (tuple(p.name for p in obj.varied), jac)
    if obj.varied:
        standard_errors(result, obj, x, jac)
    return result


def _aligned_outputs(obj, values):
    """Per dataset at ``values``: the measured channel's residual (unit), the model on the
    record's times, the window's times (s); and the other channels' scaled residuals."""
    curves = obj.curves([values])[0]
    residuals, sims, times, extra = [], [], [], {}
    for i, d in enumerate(obj.datasets):
        cur = curves[i]
        m = obj.masks[i]
        if cur is None:
            raise SimulationError(f"the fitted model's simulation failed ({', '.join(obj.effects) or 'no effects'})")
        full = obj.predict(values, cur, i, full=True)
        for ch, (_, pred) in full.items():
            r = pred[m] - d.measurement.channel(ch)[m]
            if ch == d.measured_channel:
                residuals.append(r)
            else:
                extra[(i, ch)] = r / obj.scale(i, ch)
        times.append(d.t[m])
        ch_meas = full.get(d.measured_channel, (None, np.full(d.t.size, np.nan)))[1]
        sims.append(AlignedModel(d.t, ch_meas, {ch: p for ch, (_, p) in full.items()}, d.rig.experiment))
    return residuals, sims, times, extra


def standard_errors(result: FitResult, obj, x, jac=None) -> None:
    """stderr from the Jacobian of the scaled residuals at the optimum: cov = s^2 (J^T J)^-1,
    s^2 the reduced chi^2 (the Jacobian of the last least-squares step when there is one).
    Sets each varied parameter's ``stderr`` (its unit) in ``result``."""
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


def jacobian_of(result: FitResult) -> tuple:
    """(names of the varied parameters, Jacobian of the scaled residuals) at a fit's optimum."""
    return getattr(result, "jacobian", (None, None))

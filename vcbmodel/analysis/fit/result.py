"""A fit's outcome (:class:`FitResult`): residuals, chi^2 and information criteria, standard
errors from the Jacobian at the optimum (stated: covering model-form error, :mod:`.covariance`;
``stderr_naive``: white noise), and an lmfit-like report with the correlations."""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from ...errors import SimulationError
from ...experiments import experiment_of
from ...experiments.simulation import simulation_backend
from ...rig.spring_model import SpringModel
from .covariance import Covariance, parameter_covariance
from .dataset import AlignedModel

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
    covariance: Covariance | None = None  # of the varied parameters (:mod:`.covariance`)
    #: (names of the varied parameters, Jacobian of the scaled residuals) at the optimum
    jacobian: tuple = (None, None)
    #: a cheaper fit standing in for this one while further effects are searched (a lumped
    #: chain for an ANCF spring; the diagnosis refines the final model with this one's spring)
    stand_in: FitResult | None = None

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

    def chi2_with(self, noise: NoiseModel | None, weights=None) -> float:
        """chi^2 of the measured channel's residual under ``noise`` (whitened; ``weights``: a weight
        per sample of each segment, :meth:`NoiseModel.chi2`), plus the other channels' (already
        scaled) and the priors'."""
        data = noise.chi2(self.residuals, weights) if noise is not None else float(
            sum(np.sum(r**2) for r in self.residuals) / self.sigma**2)
        extra = float(sum(np.sum(r**2) for r in self.extra_residuals.values()))
        return data + extra + self.prior_chi2

    @property
    def chi2(self) -> float:
        return self.chi2_with(self.noise)

    @property
    def n_other(self) -> int:
        """Samples of the other fitted channels (a closing record's pole travels and contacts)."""
        return int(sum(np.size(r) for r in self.extra_residuals.values()))

    @property
    def reduced_chi2(self) -> float:
        """chi^2 per degree of freedom: over every sample chi^2 sums, the other channels' too (the
        residual variance the stated errors' white-noise part uses, :mod:`.covariance`)."""
        return self.chi2 / max(1, self.n_data + self.n_other - self.n_varied)

    @property
    def rms(self) -> float:
        return float(math.sqrt(sum(np.sum(r**2) for r in self.residuals) / max(1, self.n_data)))

    @property
    def max_error(self) -> float:
        return float(max(np.max(np.abs(r)) for r in self.residuals))

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
                 f"    data points {self.n_data}" + (f" (and {self.n_other} of the other channels)" if self.n_other else "")
                 + f", varied {self.n_varied}, noise sigma {self.sigma:.3g} {self.unit}",
                 f"    rms {self.rms:.4g} {self.unit}, max |error| {self.max_error:.4g} {self.unit}, reduced chi2 {self.reduced_chi2:.3f}",
                 f"    AIC {self.aic:.1f}, BIC {self.bic:.1f}", "[[Parameters]]"]
        if self.covariance is not None:
            lines.append(f"    (+/- is the stated 1-sigma, {self.stderr_method}; in brackets the white-noise one)")
        lines += [_report_line(p) for p in self.parameters.values()]
        lines += _correlation_lines(self.correlations)
        return "\n".join(lines)

    @property
    def stderr_method(self) -> str:
        """How the stated errors (``stderr``) were obtained."""
        if self.covariance is None:
            return ""
        return f"{self.covariance.method}, lag window {self.covariance.bandwidth} samples"

    @property
    def correlations(self) -> dict[tuple[str, str], float]:
        """Correlations of the varied parameters' errors (covering covariance)."""
        return self.covariance.correlations() if self.covariance is not None else {}


def _report_line(p) -> str:
    if not p.vary:
        how = f"tied to {p.tied_to}" if p.tied_to else "fixed"
        return f"    {p.name:18s} = {p.value:.6g} {p.unit} ({how})"
    err = f"+/- {p.stderr:.3g}" if p.stderr is not None and math.isfinite(p.stderr) else "+/- ?"
    if p.stderr_naive is not None and math.isfinite(p.stderr_naive):
        err += f" ({p.stderr_naive:.2g})"
    flag = "  AT BOUND [%g, %g]" % (p.min, p.max) if p.at_bound() else ""
    prior = f" prior {p.prior[0]:.4g} +/- {p.prior[1]:.2g}" if p.prior else ""
    return f"    {p.name:18s} = {p.value:.6g} {err} {p.unit} (bounds [{p.min:g}, {p.max:g}]){prior}{flag}"


#: Correlations at least this large are listed in the report (lmfit's default).
REPORTED_CORRELATION = 0.1


def _correlation_lines(correlations: dict) -> list[str]:
    """The report's [[Correlations]] section: pairs by decreasing |correlation|."""
    big = sorted(((abs(c), a, b, c) for (a, b), c in correlations.items() if abs(c) >= REPORTED_CORRELATION),
                 reverse=True)
    if not big:
        return []
    return ["[[Correlations]] (unreported correlations are < %.1f)" % REPORTED_CORRELATION] + [
        f"    C({a}, {b}) = {c:+.3f}" for _, a, b, c in big]


def build_result(obj, x, jac, sigma: float, success: bool, message: str, method: str) -> FitResult:
    """The :class:`FitResult` of objective ``obj`` at internal coordinates ``x`` (one more
    simulation unless cached), with standard errors from ``jac`` (None: a new Jacobian)."""
    values = obj.values(x)
    fitted = {name: replace(p, value=values[name], stderr=None, stderr_naive=None) for name, p in obj.params.items()}
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
    """The varied parameters' errors (:mod:`.covariance`) from the Jacobian of the scaled residuals
    at the optimum (the last least-squares step's when there is one): ``stderr`` the covering
    (sandwich) 1-sigma, ``stderr_naive`` the white-noise one, s^2 (J^T J)^-1 with s^2 the reduced
    chi^2 (each in the parameter's unit); the covariance itself in ``result.covariance``."""
    if jac is None:
        jac = obj.prior_jacobian_fix(obj.jacobian(x), x)
    vals = obj.values(x)
    parts = obj.residual_parts(vals, obj.curves([vals])[0])
    n_priors = sum(1 for p in obj.varied if p.prior)
    segments = [part.size for part in (parts[:-1] if n_priors else parts)]
    r0 = np.concatenate(parts)
    try:
        cov = parameter_covariance([p.name for p in obj.varied], np.asarray(jac, float), r0, segments,
                                   r0.size - len(x))
    except np.linalg.LinAlgError:
        return
    result.covariance = cov
    covering, naive = cov.standard_errors("covering"), cov.standard_errors("naive")
    for i, p in enumerate(obj.varied):
        fitted = result.parameters[p.name]
        if math.isfinite(naive[i]):
            fitted.stderr_naive = _in_unit(p, fitted.value, naive[i])
        if math.isfinite(covering[i]):
            fitted.stderr = _in_unit(p, fitted.value, covering[i])


def _in_unit(p, value: float, sd: float) -> float:
    """A 1-sigma error of internal coordinate ``sd`` in the parameter's own unit."""
    return float(value * sd if p.log else sd)


def jacobian_of(result: FitResult) -> tuple:
    """(names of the varied parameters, Jacobian of the scaled residuals) at a fit's optimum."""
    return getattr(result, "jacobian", (None, None))

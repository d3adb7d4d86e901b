"""Fit parameters (lmfit's ``Parameter``): value, bounds, vary, stderr, prior; the noise level a
fit's chi^2 is measured against."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...model.effects import parameter_specs
from ...model.values import model_values, rig_values
from ...records.signals import noise_estimate

#: Parameter kinds that need a new simulation when they change.
SIM_KINDS = ("model", "state", "rig")
#: Relative forward-difference step (internal coordinates, scipy's convention h = s max(1, |x|)).
DIFF_STEP = 1e-3
#: Scaled residual of a sample whose simulation failed (a diverged trial scores badly).
FAILED = 100.0


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
    stderr: float | None = None  # the stated 1-sigma, covering model-form error (fit.covariance)
    tied_to: str | None = None  # value follows this parameter (lmfit's expr, for the simplest case)
    kind: str = "model"  # model | state | rig | release | offset | gain | time_scale
    dataset: int | None = None  # the record a nuisance belongs to (None: shared)
    path: str | None = None  # rig field of a "state" or "rig" parameter
    prior: tuple | None = None  # (mean, sd)
    stderr_naive: float | None = None  # the white-noise 1-sigma s^2 (J^T J)^-1, for comparison

    def at_bound(self, rel: float = 1e-3) -> bool:
        """Does a bound hold the value: within ``rel`` of the span from it and, when the stated
        error is known, nearer to it than one stated error (a value several errors from its bound
        is not held by it, however small)?"""
        span = (self.max - self.min) if math.isfinite(self.max - self.min) else max(abs(self.value), 1.0)
        gap = min(abs(self.value - self.min), abs(self.max - self.value))
        held = gap <= rel * span
        if held and self.stderr is not None and math.isfinite(self.stderr) and self.stderr > 0:
            held = gap < self.stderr
        return self.vary and held

    # internal (unbounded-ish) coordinate used by the optimisers
    def to_internal(self, v: float) -> float:
        return math.log(v) if self.log else v

    def from_internal(self, x: float) -> float:
        return math.exp(x) if self.log else x

    def internal_bounds(self) -> tuple[float, float]:
        if self.log:
            return math.log(self.min), math.log(self.max)
        return self.min, self.max

    @property
    def simulated(self) -> bool:
        return self.kind in SIM_KINDS


def make_parameters(rig, effects, initial: dict | None = None, vary: set | None = None) -> dict[str, Parameter]:
    """Parameters of ``effects``: fixed where the rig gives a value, varied otherwise.

    Parameters
    ----------
    rig : Rig
        The rig; a friction value it gives is fixed at that value.
    effects : sequence of str
        Registered effect names (:data:`vcbmodel.model.effects.EFFECTS`).
    initial : dict, optional
        Starting values by name, in each parameter's own unit (overrides the registry's).
    vary : set of str, optional
        Names that vary (overrides the registry's choice; a value the rig gives never varies).

    Returns
    -------
    dict of str to Parameter
        In the registry's order.
    """
    given = rig_values(rig)
    start = model_values(rig, effects, {k: v for k, v in (initial or {}).items() if k not in given}, for_fit=True)
    params = {}
    for spec in parameter_specs(effects):
        is_varied = spec.name not in given and (spec.vary if vary is None else spec.name in vary)
        value = start[spec.name] if spec.name in given else float(np.clip(start[spec.name], spec.min, spec.max))
        params[spec.name] = Parameter(spec.name, value, spec.min, spec.max, is_varied, spec.unit, spec.log)
    return params


def pooled_noise(datasets) -> float:
    """Noise level (the measured channel's unit: rad, or m for a closing) pooled over datasets:
    rms of each one's estimate (:func:`vcbmodel.records.signals.noise_estimate`)."""
    return float(np.sqrt(np.mean([noise_estimate(d.y) ** 2 for d in datasets])))

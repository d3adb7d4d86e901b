"""What the steps hand on to each other: the search's results so far (fits, candidates, the
selection path, the verdict). Each step reads what the steps before it left and adds its own."""
from __future__ import annotations

from dataclasses import dataclass, field

from ...records.signals import lag1_autocorrelation
from ..fit import FitResult


def rounded(values: dict) -> dict:
    """Values to six significant digits (for the report)."""
    return {k: float(f"{v:.6g}") for k, v in values.items()}


@dataclass
class Candidate:
    """One candidate model of forward selection: ``effect`` (``a+b`` for a pair) added to the
    model of its round."""

    effect: str
    fit: FitResult
    delta_bic: float  # BIC(current model) - BIC(with effect), whitened: positive is better
    round: int = 1
    variants: list = None  # spring models tried: (label, rms)

    def summary(self, noise: object = None) -> dict:
        r = self.fit
        return {"effect": self.effect, "round": self.round, "delta_bic": round(self.delta_bic, 2),
                "bic": round(r.bic_with(noise) if noise is not None else r.bic, 2), "rms": r.rms,
                "lag1_autocorrelation": round(lag1_autocorrelation(r.residuals[0]), 4),
                "spring_model": r.spring_model_label, "parameters": rounded(r.model_values), "simulations": r.nfev,
                **({"variants": self.variants} if self.variants else {})}


@dataclass
class State:
    """The search's results, step by step. ``path`` holds the selection steps (dicts: effect,
    round, delta_bic, ...; keys starting with ``_`` are fits, left out of the report);
    ``backward`` the removals and swaps tried after forward selection."""

    period: dict | None = None  # the swing's period mismatch (align, start)
    baseline: FitResult = None  # the starting model fitted with the record's nuisance (start)
    current: FitResult = None  # the model the search stands at
    all_fits: list = field(default_factory=list)
    candidates: list = field(default_factory=list)  # Candidate, every round
    stopped: set = field(default_factory=set)  # candidates not fitted
    path: list = field(default_factory=list)
    round_ref: dict = field(default_factory=dict)  # round -> the model its candidates extend
    backward: list = field(default_factory=list)
    coarse_spring: FitResult = None  # the fit a finer spring model replaced (refine)
    final: FitResult = None  # judge
    verdict: dict = field(default_factory=dict)
    selection: list = field(default_factory=list)
    missing: list = field(default_factory=list)
    own_alignment: FitResult = None  # the baseline before judge put it on the final alignment
    discovery: dict = field(default_factory=dict)
    discovered: object = None  # the discover step's Discovery (vcbmodel.analysis.discovery), when it searched
    diagnosis: object = None  # report

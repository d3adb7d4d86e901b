"""What the steps hand on to each other: the search's results so far (fits, candidates, the
selection path, the refinements tried, the verdict), each a typed value. Each step reads what the
steps before it left and adds its own."""
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
    variants: list | None = None  # spring models tried: (label, rms)
    #: what the held-out records say (.held_out.held_out_evidence): their predictions' whitened
    #: chi^2 drop and the share of their noise variance removed (0: no held-out records)
    held_out_delta: float = 0.0
    held_out_gain: float = 0.0

    @property
    def evidence(self) -> float:
        """The candidate's evidence: its whitened BIC drop on the record, plus the held-out drop."""
        return self.delta_bic + self.held_out_delta

    def summary(self, noise: object = None) -> dict:
        r = self.fit
        return {"effect": self.effect, "round": self.round, "delta_bic": round(self.delta_bic, 2),
                "bic": round(r.bic_with(noise) if noise is not None else r.bic, 2), "rms": r.rms,
                "lag1_autocorrelation": round(lag1_autocorrelation(r.residuals[0]), 4),
                "spring_model": r.spring_model_label, "parameters": rounded(r.model_values), "simulations": r.nfev,
                **({"variants": self.variants} if self.variants else {}),
                **({"held_out_delta_chi2": round(self.held_out_delta, 2), "held_out_variance_gain":
                    round(self.held_out_gain, 4)} if self.held_out_delta or self.held_out_gain else {})}


@dataclass
class SelectionStep:
    """One effect forward selection kept: in round ``round``, on top of the model ``before``,
    leading to the model ``fit`` (a later refinement of that model moves ``fit`` along: see
    :func:`adopt`). ``pair``: the pair it was kept with (``a+b``), None for a single effect."""

    effect: str
    round: int
    delta_bic: float
    rms: float
    spring_model: str
    before: FitResult
    fit: FitResult
    pair: str | None = None
    swapped_from: str | None = None  # the kept effect a swap replaced with this one
    delta_bic_final_noise: float | None = None  # the step rescored with the final noise model

    def to_json(self) -> dict:
        out = {"effect": self.effect, "round": self.round, "delta_bic": self.delta_bic, "rms": self.rms,
               "spring_model": self.spring_model, "with": self.pair}
        if self.swapped_from:
            out["swapped_from"] = self.swapped_from
        if self.delta_bic_final_noise is not None:
            out["delta_bic_final_noise"] = self.delta_bic_final_noise
        return out


@dataclass
class Refinement:
    """A change of the selection tried after forward selection: the kept ``effect`` removed
    (``swap_for`` None: backward elimination) or replaced by ``swap_for``. ``without`` is the
    model without the change's effect, ``with_`` the one with it (for a removal: the reduced
    model and the current one; for a swap: the current model and the swapped one).
    ``delta_bic``: the whitened BIC of ``without`` minus that of ``with_``; ``dropped``: the
    change was taken."""

    effect: str
    without: FitResult
    with_: FitResult
    delta_bic: float
    dropped: bool = False
    swap_for: str | None = None
    delta_bic_final_noise: float | None = None

    @property
    def backward(self) -> bool:
        return self.swap_for is None

    def to_json(self) -> dict:
        out = {"effect": self.effect, "backward": self.backward, "dropped": self.dropped}
        if self.backward:
            out.update(delta_bic_without=self.delta_bic, rms_without=self.without.rms)
        else:
            out.update(swap_for=self.swap_for, delta_bic=self.delta_bic, rms=self.with_.rms)
        if self.delta_bic_final_noise is not None:
            out["delta_bic_final_noise"] = self.delta_bic_final_noise
        return out


def adopt(path: list[SelectionStep], old: FitResult, new: FitResult) -> None:
    """Selection steps that ended in fit ``old`` now end in ``new`` (a refinement of it)."""
    for step in path:
        if step.fit is old:
            step.fit = new


@dataclass
class Verdict:
    """The judge's verdict: ``explained`` (the final residual at the noise on the fitted record,
    and every held-out record predicted at its noise), the judgement behind it
    (:class:`.at_noise.NoiseJudgement`), what is left when not explained, the ties, a swing's
    period mismatch, a spring model refined, and the held-out records' predictions."""

    explained: bool
    judgement: object  # NoiseJudgement (at_noise)
    left: dict | None = None
    ambiguous: list = field(default_factory=list)
    period: dict | None = None
    spring_model_refined: dict | None = None
    held_out: list = field(default_factory=list)  # per held-out record: its prediction's judgement (dict)
    #: the final fit's values no physical rig has, or that break the law's constraint (plausibility
    #: Finding JSON): with any, the record is not explained, whatever its residual
    implausible: list = field(default_factory=list)
    #: a plausible model form that beats the final model by more than ``options.rival_form_margin``
    #: and moves a stated value beyond ``options.rival_form_errors`` (:func:`.judge.rival_form`):
    #: with one, the record is not explained
    rival_form: dict | None = None
    #: the quantities the model forms determine whose estimate over the forms is outside its plausible
    #: range (plausibility Finding JSON, :func:`.judge.implausible_forms`): with any, not explained
    implausible_forms: list = field(default_factory=list)
    #: model forms within the evidence margin with a parameter the record does not resolve to its stated
    #: error, and the final values whose stated intervals the forms' then exceed (:func:`.judge.unresolved_forms`)
    unresolved_forms: list = field(default_factory=list)

    @property
    def tests(self) -> dict:
        return self.judgement.tests

    @property
    def artefacts(self) -> tuple:
        return self.judgement.artefacts

    def to_json(self) -> dict:
        out = {"explained": self.explained, "fitted_record_at_noise": self.judgement.at_noise, **self.judgement.to_json()}
        for key in ("left", "period", "spring_model_refined"):
            if getattr(self, key) is not None:
                out[key] = getattr(self, key)
        if self.ambiguous:
            out["ambiguous"] = self.ambiguous
        if self.held_out:
            out["held_out"] = self.held_out
        if self.implausible:
            out["implausible"] = self.implausible
        if self.rival_form:
            out["rival_form"] = self.rival_form
        if self.implausible_forms:
            out["implausible_forms"] = self.implausible_forms
        if self.unresolved_forms:
            out["unresolved_forms"] = self.unresolved_forms
        return out


@dataclass
class State:
    """The search's results, step by step: the fits, the candidates of every round, the
    selection ``path`` (:class:`SelectionStep`), the removals and swaps tried after forward
    selection (``backward``, :class:`Refinement`), the verdict and the report."""

    period: dict | None = None  # the swing's period mismatch (align, start)
    baseline: FitResult | None = None  # the starting model fitted with the record's nuisance (start)
    current: FitResult | None = None  # the model the search stands at
    all_fits: list = field(default_factory=list)
    candidates: list = field(default_factory=list)  # Candidate, every round
    stopped: set = field(default_factory=set)  # candidates not fitted
    path: list = field(default_factory=list)  # SelectionStep
    round_ref: dict = field(default_factory=dict)  # round -> the model its candidates extend
    backward: list = field(default_factory=list)  # Refinement
    coarse_spring: FitResult | None = None  # the fit a finer spring model replaced (refine)
    final: FitResult | None = None  # judge
    verdict: Verdict | None = None
    missing: list = field(default_factory=list)
    start_at_noise: bool = False  # the starting model was at the noise: no effect searched (select)
    discovery: dict = field(default_factory=dict)
    discovered: object = None  # the discover step's Discovery (vcbmodel.analysis.discovery), when it searched
    diagnosis: object = None  # report

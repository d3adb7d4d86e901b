"""The diagnosis' result: what the steps found, as a report in words and as JSON (keys listed in
docs/cli.md). The gap is each model at its own best alignment of the record: ``baseline`` is the
starting model with the record's nuisance fitted to it, ``final`` the final model with its own.
Residuals and noise in the measured channel's unit (rad or m), times s."""
from __future__ import annotations

from dataclasses import dataclass, field

from ...experiments import experiment_of
from ...records.signals import disagreement_window, stands_out
from ..fit import FitResult
from ..noise import NoiseModel, excess
from .options import DEFAULT_OPTIONS, DiagnosisOptions
from .state import Verdict, rounded


@dataclass
class Diagnosis:
    """One record's diagnosis (see :mod:`.pipeline` for the steps that made it)."""

    rig: object
    measurement: object
    noise_model: NoiseModel
    baseline: FitResult
    candidates: list
    missing_effects: list
    final: FitResult
    window: tuple
    signature: dict
    evidence: str
    stopped: list | None = None  # candidates not fitted: a simpler one explained the data already
    verdict: Verdict | None = None
    nuisance: dict = field(default_factory=dict)
    timing: dict = field(default_factory=dict)
    selection: list = field(default_factory=list)  # SelectionStep / Refinement JSON
    #: the discover step's report (:mod:`.discover`): a torque outside the registry, or why none
    discovered: dict = field(default_factory=dict)
    discovery: object = None  # its Discovery (vcbmodel.analysis.discovery), when it searched
    options: DiagnosisOptions = DEFAULT_OPTIONS
    start_at_noise: bool = False  # the starting model was at the noise: no effect searched
    #: the forms the record cannot tell apart and every quantity over them (..model_forms.ModelForms)
    model_forms: object = None

    @property
    def baseline_own_alignment(self) -> FitResult:
        """The starting model with its own alignment of the record (the same as ``baseline``)."""
        return self.baseline

    @property
    def missing_effect(self) -> str | None:
        return self.missing_effects[0] if self.missing_effects else None

    @property
    def noise(self) -> float:
        """The noise level (standard deviation of the noise itself, the record's unit)."""
        return self.noise_model.marginal_sd

    @property
    def explained(self) -> bool:
        return bool(self.verdict is not None and self.verdict.explained)

    @property
    def ambiguous(self) -> list:
        """[(kept effect, rival)] the evidence does not separate (BIC within the margin)."""
        return [tuple(t["between"]) for t in (self.verdict.ambiguous if self.verdict else ())]

    @property
    def unit(self) -> str:
        return experiment_of(self.rig.experiment).unit

    def to_json(self) -> dict:
        b, f = self.baseline, self.final
        sigma = self.noise
        return {
            "missing_effect": self.missing_effect, "missing_effects": list(self.missing_effects),
            "explained": self.explained, "ambiguous": [list(pair) for pair in self.ambiguous],
            "baseline_effects": list(b.effects), "final_effects": list(f.effects),
            "baseline_spring_model": b.spring_model_label, "final_spring_model": f.spring_model_label,
            "simulated_with": f.backend, "rms_before": b.rms, "rms_after": f.rms,
            "start_at_noise": self.start_at_noise,
            "max_error_before": b.max_error, "max_error_after": f.max_error,
            "gap_ratio": f.rms / b.rms if b.rms > 0 else None,
            # the model-truth gap: residual rms in excess of the noise, sqrt(rms^2 - sigma^2)
            "excess_before": excess(b.rms, sigma),
            "excess_after": excess(f.rms, sigma),
            "noise_estimate": sigma, "noise_correlation": self.noise_model.lag1,
            "noise": self.noise_model.to_json(),
            "window": list(self.window), "bic_margin": self.options.bic_margin, "options": self.options.to_json(),
            "selection": self.selection,
            "candidates": [c.summary(self.noise_model) for c in self.candidates] + [
                {"effect": name, "delta_bic": None, "status": "stopped: a candidate with no more parameters "
                 "already explains the data within the noise"} for name in self.stopped or []],
            "fitted": rounded(f.model_values), "fitted_before": rounded(b.model_values),
            "stderr": {p.name: p.stderr for p in f.parameters.values() if p.vary and p.kind == "model"},
            "stderr_naive": {p.name: p.stderr_naive for p in f.parameters.values() if p.vary and p.kind == "model"},
            "stderr_method": f.stderr_method,
            "fitted_units": {p.name: p.unit or "-" for fit in (b, f) for p in fit.parameters.values()
                             if p.kind == "model"},
            "at_bound": [p.name for p in f.parameters.values() if p.at_bound()],
            "nuisance": self.nuisance, "verdict": self.verdict.to_json() if self.verdict else {},
            "signature": self.signature, "evidence": self.evidence, "timing": self.timing,
            "discovered": {k: v for k, v in self.discovered.items() if k != "report"},
            "model_forms": self.model_forms.to_json() if self.model_forms is not None else None,
        }

    def disagreement_line(self) -> str:
        """Where the starting model's residual stands out most, or that it stands out nowhere."""
        peak = disagreement_window(self.baseline.times[0], self.baseline.residuals[0], self.noise)[2]
        if not stands_out(peak, self.noise):
            return "  disagreement: nowhere standing out (the starting residual's running rms stays under twice the noise)"
        return f"  disagreement largest in t = [{self.window[0]:.4g}, {self.window[1]:.4g}] s"

    def report(self) -> str:
        u = self.unit
        nz = self.noise_model
        lines = [f"Diagnosis of {self.measurement.path}",
                 f"  noise {self.noise:.3g} {u} (lag-1 correlation {nz.lag1:.2f}, AR({nz.order})"
                 + (f", quantised in steps of {nz.quantisation:.3g} {u}" if nz.quantisation else "") + ")",
                 f"  baseline {', '.join(self.baseline.effects) or '(none)'} [{self.baseline.spring_model_label}]: "
                 f"rms {self.baseline.rms:.3g} {u}",
                 "  nuisance: " + ", ".join(f"{k} {v:.5g}" for k, v in self.nuisance.get("values", {}).items())
                 + (f" ({self.nuisance['caveat']})" if self.nuisance.get("caveat") else ""),
                 self.disagreement_line(),
                 "  candidates (delta BIC of the whitened residual, positive = better):"]
        for c in self.candidates:
            held = f"  held-out dchi2 {c.held_out_delta:.1f}" if c.held_out_delta else ""
            lines.append(f"    round {c.round} {c.effect:18s} dBIC {c.delta_bic:12.1f}  rms {c.fit.rms:.3g} {u} "
                         f"[{c.fit.spring_model_label}]{held}")
        for name in self.stopped or []:
            lines.append(f"    {name:18s} stopped: a simpler candidate explains the data within the noise")
        lines.append(f"  missing effects: {', '.join(self.missing_effects) or 'none'}")
        for tie in self.verdict.ambiguous if self.verdict else ():
            lines.append(f"  AMBIGUOUS between {tie['between'][0]} and {tie['between'][1]} (BIC "
                         f"{tie['delta_bic_between']:.1f} apart, margin {self.options.bic_margin:g})")
        lines.append(f"  rms {self.baseline.rms:.3g} -> {self.final.rms:.3g} {u}; explained: {self.explained}")
        lines.append("  " + self.evidence)
        if self.discovered.get("report"):
            lines.append(self.discovered["report"])
        lines.append(self.final.report())
        if self.model_forms is not None:
            lines.append(self.model_forms.report(u))
        return "\n".join(lines)

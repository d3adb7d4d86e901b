"""Model-form uncertainty: the forms a record cannot tell apart, fitted beside the selected model,
and every physical quantity with an interval that spans them.

A fit's stated errors are those of its own model: when another law would fit the record as well
(Tustin's exponential Stribeck curve for the hybrid law's linear one, a drifting Coulomb level, air
drag for viscous friction), the values can sit many stated errors from the truth while the residual
is white at the noise. So beside the selected model this module fits its *alternatives*
in two steps: the selected model with each registered effect of ``Experiment.form_alternatives`` it lacks,
beside the others or in place of its partner (:func:`added_effects`: air drag, viscous or Coulomb
friction, which share a swing's decay); then, from the best plausible model of those and from the
selected one, the friction forms of :mod:`vcbmodel.laws.friction_forms` (:func:`alternatives`, each
with the Stribeck fall it needs). A form with a value outside its plausible range (:mod:`.plausibility`: a drag coefficient
forty times what any paddle gives) gets no weight: the ranges act as a prior that rules it out, unless no
plausible form fits within the evidence margin of the best (then all are weighed, and the findings say
which values are implausible). Each form says both: ``plausible`` (its values within their ranges) and
``weighed`` (counted in the weights).

Multi-model inference (Burnham & Anderson, *Model Selection and Multimodel Inference*, 2nd ed.
2002, ch. 4 and 6.4), with BIC weights w_i = exp(-dBIC_i / 2) / sum_j exp(-dBIC_j / 2):

- the model-averaged estimate  theta = sum_i w_i theta_i;
- its unconditional variance   var = sum_i w_i (var_i + (theta_i - theta)^2)  (their eq. 6.12);
- the 95 % interval theta +- 1.96 sqrt(var), widened to hold each form within the evidence margin
  (dBIC <= :data:`EVIDENCE_MARGIN`) at its own 95 % interval: those are the forms the record does
  not tell apart (a BIC difference of 10 is "very strong" evidence, Kass & Raftery, JASA 90, 1995),
  and a form the record cannot reject must not fall outside what is reported;
- widened again to hold each such form's values at the ends of the profile of each parameter it adds
  (:func:`profile_forms`, :mod:`.fit.profile`: a drift or an added drag refitted held outward of its
  stated ends until the record rejects it), where a curved valley lets it further than its Jacobian's
  error says (a drift traded against viscous friction along a swing's decay: 3.2 and 3.5 times its stated
  95 % half-width on a laboratory record);
- the stated 1-sigma: the larger of sqrt(var) and the interval's half-width over 1.96, so that a value
  and its error say what the interval beside them says.

BIC rather than AIC: the diagnosis selects effects by BIC, the weights approximate the forms'
posterior probabilities (equal priors, unit-information prior on the parameters), and on records of
thousands of samples AIC's lighter penalty puts weight on every extra parameter that lowers chi^2 by
2, which the records' slightly non-white noise does by itself. A Bayesian model average with
sampled posteriors would cost thousands of simulations per form; the weights need one fit each.

On a rounded record (an encoder, a logger with few bits) the forms' BIC counts each run of identical
recorded values once (:func:`.noise.rounding_bic`): where the signal moves by less than a step between
samples the rounding error is one deterministic error read many times, and a form that bends the
trajectory at low speed would otherwise win by hundreds for fitting it (a clean 12-bit pendulum: a
Gaussian-Stribeck form 328 ahead of the true hybrid law; with the runs counted once, 1.4 behind). On an
unquantised record it is the plain BIC, and nearly so where sensor noise of half a step or more dithers the
rounding.

A quantity's value in a form that lacks it is its physical value there: 0 for an additive effect
(viscous, drag, drift), the kinetic level for ``mu_s`` (no Stribeck fall: the static level is the
kinetic one). ``mu_k`` is put on one meaning across forms, the Coulomb level at speed (the friction
torque at speed less C_v w, over r F): the hybrid law's shifted viscous term C_v (w - w_s) makes its
``mu_k`` that level plus C_v w_s / (r F), with F the journal's static load (pendulum: M g); the
shift's own error is left out. ``stribeck_velocity`` has another meaning in each form (the end of a
linear fall, an exponential or a Gaussian decay speed): it is listed per form, not averaged.

A quantity is *determined by the record* when every form within the margin states a finite error
and its 95 % interval is narrower than its plausible range (:mod:`.plausibility`); otherwise it is
reported as not determined, with the range the forms span (a form without an error: that range and
the plausible one, all that is known without the record).
"""
from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import SimulationError
from ..experiments import experiment_of
from ..laws.friction import effective_static
from ..laws.friction_forms import FORMS
from ..model.effects import EFFECTS, parameter_specs
from . import fit as fitting
from .fit import FitAborted, FitResult, Parameter, make_parameters
from .fit.profile import profile
from .plausibility import Z95, findings_of, plausible_range
from .noise import rounding_bic

#: Forms whose BIC is within this of the best are ones the record does not tell apart (Kass &
#: Raftery 1995: a difference above 10 is very strong evidence; the diagnosis' own BIC margin).
EVIDENCE_MARGIN = 10.0
#: Registered effects added to the best form where the record's experiment has them
#: (``Experiment.form_alternatives``, joined by name: an effect not in the registry is skipped; a
#: pendulum's: a swing's decay is shared between Coulomb friction, viscous friction and air drag).
#: The friction forms are tried on an experiment whose records resolve the friction's shape
#: (``Experiment.friction_shapes``): a cam drop's or a closing's shaft passes the Stribeck range
#: (0.1 rad/s) within its first millisecond and moves 35-70 ms: the forms differ by less than the noise
#: there, and a drift over 70 ms is nil.
#: Starting factors of a newly added Stribeck fall: mu_s as multiples of mu_k (identify's own scan).
MU_S_STARTS = (1.3, 2.0)
#: Levenberg-Marquardt's chi^2 tolerance and iteration limit for a form's fit: a form trades its
#: values against each other along a decaying swing (Coulomb, viscous, a drift), a long curved valley
#: where the fits' usual tolerance (a fraction 2e-3 of the samples: 10 chi^2 units on a 5 s record, the
#: whole evidence margin) stops at the start. The forms' BICs are compared to within a few units, so
#: their fits stop on an absolute tolerance of 0.5 (the relative one off); the cost's kinks (a stop
#: a step earlier or later) end them by "no further descent" instead.
CHI2_TOLERANCE = 0.5
RELATIVE_TOLERANCE = 0.0
MAX_ITERATIONS = 15
#: Seconds the forms' fits may take together in a diagnosis (each fit starts from the selected
#: model's values and rarely needs more than a few seconds on the compiled path).
FORMS_BUDGET_S = 120.0
#: Forms whose fall between mu_s and mu_k is a curve of their own (they need ``stribeck``; their
#: viscous term is not shifted by the Stribeck velocity): fitted from :func:`_curve_starts`.
CURVE_FORMS = tuple(f.name for f in FORMS.values() if f.effect and "stribeck" in f.needs)
#: Values whose meaning differs between forms (the fall's speed scale and shape): reported per form
#: (``form_specific``), never averaged over forms.
SHAPE_VALUES = ("stribeck_velocity", "stribeck_exponent")
#: Why forms of the literature are not fitted (:mod:`vcbmodel.laws.friction_forms`).
NOT_CARRIED = {"dahl": "its bristle state (micrometres, relaxing at about 1e5-1e6 per second) is too stiff for "
                       "the fixed-step RK4 of the compiled path and of Exudyn; once sliding Dahl's friction is the "
                       "Coulomb level the selected model has, and LuGre's is the gaussian form"}


@dataclass(frozen=True)
class Alternative:
    """A form to fit: its label, effects, the effects it adds to the selected model, and the
    friction form it switches on (None: registered effects only)."""

    label: str
    effects: tuple
    added: tuple
    form: str | None = None
    removed: tuple = ()  # effects of the model it came from that it leaves out (one swapped for another)


@dataclass
class FormFit:
    """One fitted form: its fit and BIC (under the record's noise), weight and BIC distance from
    the best."""

    alternative: Alternative
    fit: FitResult
    bic: float
    delta_bic: float = 0.0
    weight: float = 0.0
    #: False when a fitted value lies outside its plausible range by more than its 95 % error
    #: (:func:`plausible_fit`, :mod:`.plausibility`): what that says of the fit, whatever the weighing
    plausible: bool = True
    #: counted in the BIC weights: a plausible form, or every form when no plausible one fits within
    #: the evidence margin of the best (:func:`_weigh`); an unweighed form gets weight 0 (a prior
    #: that rules its value out)
    weighed: bool = True
    #: the profiles of the parameters the form adds (:func:`profile_forms`, :mod:`.fit.profile`): how far
    #: the record lets each move, with the form's other values at the ends
    profiles: list = field(default_factory=list)

    @property
    def within_margin(self) -> bool:
        return self.weighed and self.delta_bic <= EVIDENCE_MARGIN


@dataclass
class Quantity:
    """A physical quantity over the forms: the model-averaged estimate, its unconditional 1-sigma,
    the reported 95 % interval, and each form's (value, stderr)."""

    name: str
    unit: str
    estimate: float
    stderr: float
    low: float
    high: float
    determined: bool
    by_form: dict
    meaning: str = ""

    def to_json(self) -> dict:
        return {"estimate": _finite(self.estimate), "stderr": _finite(self.stderr), "low": _finite(self.low),
                "high": _finite(self.high), "unit": self.unit, "determined": self.determined, "meaning": self.meaning,
                "by_form": {k: {"value": _finite(v), "stderr": _finite(s)} for k, (v, s) in self.by_form.items()}}


def _finite(x: float | None) -> float | None:
    """``x``, or None when it is not a finite number (JSON has no infinity)."""
    return float(x) if x is not None and math.isfinite(x) else None


@dataclass
class ModelForms:
    """The forms fitted beside the selected model and the quantities over them."""

    forms: list
    quantities: dict
    not_tried: dict = field(default_factory=dict)
    form_specific: dict = field(default_factory=dict)  # {form: {stribeck_velocity: value}}
    findings: list = field(default_factory=list)  # plausibility findings (:mod:`.plausibility`)

    @property
    def preferred(self) -> FormFit:
        """The weighed form with the best BIC (a plausible one unless no plausible form fits within
        the evidence margin of the best)."""
        return min((f for f in self.forms if f.weighed), key=lambda f: f.bic, default=self.forms[0])

    @property
    def best_plausible(self) -> FormFit:
        """The form whose values are all plausible with the best BIC (the selected one if none is)."""
        return min((f for f in self.forms if f.plausible), key=lambda f: f.bic, default=self.forms[0])

    @property
    def undetermined(self) -> list[str]:
        return [q.name for q in self.quantities.values() if not q.determined]

    def to_json(self) -> dict:
        return {"method": "BIC weights over the fitted forms (Burnham & Anderson multi-model inference): estimate "
                          "sum w_i theta_i, unconditional variance sum w_i (var_i + (theta_i - theta)^2); the 95 % "
                          f"interval also holds each form within {EVIDENCE_MARGIN:g} of the best BIC at its own",
                "evidence_margin": EVIDENCE_MARGIN,
                "forms": [{"form": f.alternative.label, "effects": list(f.fit.effects), "bic": f.bic,
                           "delta_bic": f.delta_bic, "weight": f.weight, "within_margin": f.within_margin,
                           "plausible": f.plausible, "weighed": f.weighed,
                           "rms": f.fit.rms, "values": {p.name: p.value for p in f.fit.parameters.values()
                                                        if p.kind == "model"},
                           "stderr": {p.name: _finite(p.stderr) for p in f.fit.parameters.values()
                                      if p.kind == "model" and p.vary},
                           "profiles": [pr.to_json() for pr in f.profiles]} for f in self.forms],
                "quantities": {name: q.to_json() for name, q in self.quantities.items()},
                "not_determined": self.undetermined, "form_specific": self.form_specific,
                "preferred_form": self.preferred.alternative.label,
                "selected_delta_bic": self.forms[0].bic - self.preferred.bic,
                "not_tried": dict(self.not_tried), "plausibility": [f.to_json() for f in self.findings]}

    def report(self, unit: str = "rad") -> str:
        lines = [f"  Model forms the record cannot tell apart (BIC weights; 95 % intervals span every form within "
                 f"{EVIDENCE_MARGIN:g} of the best BIC):"]
        for f in self.forms:
            lines.append(f"    {f.alternative.label:34s} dBIC {f.delta_bic:8.1f}  weight {f.weight:.3f}  rms "
                         f"{f.fit.rms:.3g} {unit}" + _form_note(f))
        for name, why in self.not_tried.items():
            lines.append(f"    {name:34s} not fitted: {why}")
        lines += _profile_lines(self.forms)
        best, selected = self.preferred, self.forms[0]
        if best is not selected and selected.bic - best.bic > EVIDENCE_MARGIN:
            lines.append(f"    The record prefers {best.alternative.label} to the selected model by {selected.bic - best.bic:.0f} "
                         "BIC: the values below are mainly that form's")
        for q in self.quantities.values():
            if q.determined:
                lines.append(f"    {q.name:18s} {q.estimate:.5g} +/- {q.stderr:.2g} {q.unit}, 95 % [{q.low:.5g}, "
                             f"{q.high:.5g}]" + (f" ({q.meaning})" if q.meaning else ""))
            else:
                lines.append(f"    {q.name:18s} not determined by this record: the forms span [{q.low:.4g}, "
                             f"{q.high:.4g}] {q.unit}")
        lines += [f"    IMPLAUSIBLE: {f.message}" for f in self.findings]
        return "\n".join(lines)


def _profile_lines(forms: list) -> list[str]:
    """The report's lines on a form whose profile lets a parameter beyond its stated 95 % interval."""
    out = []
    for f in forms:
        for pr in f.profiles:
            if pr.wider:
                out.append(f"    {f.alternative.label}: the record does not resolve {pr.parameter} to its stated error: "
                           f"refitted with it held, it keeps [{pr.low:.4g}, {pr.high:.4g}] within 95 % (stated "
                           f"[{pr.stated[0]:.4g}, {pr.stated[1]:.4g}]); the intervals below hold the values along it")
    return out


def _form_note(f: FormFit) -> str:
    """The report's note on a form: rejected (beyond the margin), implausible and not weighed, or
    implausible but weighed (no plausible form fits as well)."""
    if not f.weighed:
        return "  (implausible values: no weight)"
    note = "" if f.within_margin else "  (rejected)"
    return note + ("" if f.plausible else "  (implausible values, weighed: no plausible form fits as well)")


def alternatives(effects: Sequence[str], experiment: str, searched: bool = False) -> tuple[list[Alternative], dict]:
    """The forms to fit beside a model of ``effects`` for a record of ``experiment``, and {form: why
    not} for those left out. ``searched``: the model was selected by a search that weighed adding
    the registry's ``stribeck`` (the diagnosis): its linear fall is not fitted again; Tustin's and
    the Gaussian fall, which no search tried, are."""
    effects = tuple(effects)
    out, skipped = [], {}
    shapes = experiment_of(experiment).friction_shapes
    friction_forms = shapes and "coulomb_friction" in effects
    if not friction_forms:
        skipped["friction forms"] = (f"a {experiment} record's shaft passes the Stribeck range within its first "
                                     "millisecond" if not shapes else "the model has no Coulomb friction to reshape")
    else:
        if "stribeck" not in effects and not searched:
            out.append(Alternative("hybrid + stribeck", effects + ("stribeck",), ("stribeck",)))
        current = next((f.name for f in FORMS.values() if f.effect and f.effect in effects), "hybrid")
        for form in FORMS.values():
            if not form.effect or form.name == current:
                continue
            base = tuple(e for e in effects if not any(f.effect == e for f in FORMS.values() if f.effect))
            needs = tuple(n for n in form.needs if n not in base)
            out.append(Alternative(form.name + (" + " + " + ".join(needs) if needs else ""), base + needs + (form.effect,),
                                   needs + (form.effect,), form.name))
    return out, skipped


def added_effects(best: FormFit, experiment: str) -> list[Alternative]:
    """The best form without each effect of ``Experiment.form_removable`` it has, with each registered effect of
    ``Experiment.form_alternatives`` it lacks (the record may hold it as well), and with it in place of its
    partner in :data:`PARTNERS` (air drag for viscous friction, or the reverse: the record may hold it
    instead)."""
    effects, out = tuple(best.fit.effects), []
    record = experiment_of(experiment)
    for name in record.form_removable:
        partner = PARTNERS.get(name)
        if name in effects and (partner is None or partner in effects):
            # without it (and a form that needs it): a fall the record may not hold at all, or one of two
            # decay effects where the other may do the work alone
            needs = {f.effect for f in FORMS.values() if f.effect and name in f.needs}
            out.append(Alternative(f"- {name}", tuple(e for e in effects if e != name and e not in needs), (),
                                   removed=(name,)))
    for name in record.form_alternatives:
        if name not in EFFECTS or name in effects or not EFFECTS[name].acts_on(record.provides):
            continue
        out.append(Alternative(f"+ {name}", effects + (name,), (name,)))
        partner = PARTNERS.get(name)
        if partner in effects:
            out.append(Alternative(f"{name} for {partner}",
                                   tuple(e for e in effects if e != partner) + (name,), (name,), removed=(partner,)))
    return out


def alternative_parameters(rig, base: FitResult, alt: Alternative) -> tuple[dict, list]:
    """(parameters, extra starts) of ``alt``: the selected fit's values (nuisance included) and the
    added effects' and form's own parameters at their registry starts."""
    dropped = {spec.name for spec in parameter_specs(alt.removed)}
    params = {k: replace(p, stderr=None, stderr_naive=None) for k, p in base.parameters.items() if k not in dropped}
    registered = tuple(e for e in alt.added if e in EFFECTS)
    for name, p in make_parameters(rig, registered).items():
        params.setdefault(name, p)
    if alt.form is not None:
        for fp in FORMS[alt.form].parameters:
            params.setdefault(fp.name, Parameter(fp.name, fp.initial, fp.min, fp.max, True, fp.unit))
    starts = []
    mu_k = params["mu_k"].value if "mu_k" in params else 0.1
    if alt.form is not None:
        starts = [_level_neutral(fp.name, v, mu_k, base) for fp in FORMS[alt.form].parameters for v in fp.scan]
    curve = alt.form in CURVE_FORMS and params.get("stribeck_velocity") is not None \
        and params["stribeck_velocity"].vary
    if curve:  # the curve's starts, each with the form's own scan values (a free exponent's) besides
        own = starts
        starts = [{**c, **o} for c in _curve_starts(rig, base, params) for o in own or [{}]]
    if "stribeck" in alt.added and params.get("mu_s") is not None and params["mu_s"].vary:
        # a new fall: mu_s as multiples of mu_k (with each of the curve's starts)
        starts = [{**start, "mu_s": f * mu_k} for start in (starts or [{}]) for f in MU_S_STARTS]
    elif len(alt.added) == 1 and alt.added[0] in DECAY_SHARES:
        starts = _decay_starts(rig, base, alt, params)
    return params, starts


#: Registered effects a model is also fitted without (``Experiment.form_removable``; a pendulum's): a
#: Stribeck fall the record does not hold leaves mu_s and w_s undetermined (errors of 1e9-1e16) and,
#: through their correlations, every other value's error with them (identify's hybrid law always has
#: one); of air drag and viscous friction together, either alone may do the work (the diagnosis named a
#: drag 10 times the largest paddle's beside viscous friction on a record without drag).
#: Each decay effect's parameter: an effect added to the best form starts at 0 (the form itself).
DECAY_SHARES = {"coulomb_friction": "mu_k", "viscous_friction": "viscous", "aerodynamic_drag": "drag",
                "spring_damping": "damping_ratio"}
#: Decay effects that may stand in for each other (both dissipate more at speed).
PARTNERS = {"viscous_friction": "aerodynamic_drag", "aerodynamic_drag": "viscous_friction"}


def _decay_starts(rig, base: FitResult, alt: Alternative, params: dict) -> list:
    """Starts of the decay effect ``alt`` adds: beside its partner at 0 (the fitted model itself: the
    fit can only gain); in place of its partner at the partner's dissipation, converted at the first
    swing's mean speed W / 2 (W = theta_0 sqrt(M g L / I), the peak speed of a small swing; a torque
    c w|w| over a sine of amplitude V dissipates as a viscous C_v = 8 c V / (3 pi)). From the registry's
    own start a viscous term added to a fit with air drag began far above the swing's damping and
    stopped at 12 times the noise."""
    effect = alt.added[0]
    name = DECAY_SHARES[effect]
    if name not in params or not params[name].vary:
        return []
    if not alt.removed:
        return [{name: max(params[name].min, 0.0)}]
    p, old = rig.pendulum, DECAY_SHARES.get(alt.removed[0])
    if p is None or old not in base.parameters:
        return []
    speed = 0.5 * abs(p.initial_angle) * math.sqrt(p.mass * rig.gravity * p.com_distance / p.inertia)
    per_drag = 8.0 * speed / (3.0 * math.pi)  # the viscous equivalent of a unit drag coefficient
    value = base.parameters[old].value
    converted = value * per_drag if effect == "viscous_friction" else value / per_drag if per_drag > 0 else 0.0
    return [{name: float(min(max(converted, params[name].min), params[name].max))}]


def _curve_starts(rig, base: FitResult, params: dict) -> list:
    """Starts of an exponential or Gaussian fall from the selected hybrid fit: mu_k at the hybrid's
    Coulomb level at speed (its shifted viscous term moves the level by C_v w_s / (r F)), so the swing
    at speed is the selected fit's, and the decay speed at the linear fall's end and a third of it
    (an exponential falls to 5 % in three decay speeds). From the hybrid's own mu_k a Tustin fit of a
    Tustin pendulum stopped at 12 times the noise, its drifting rival winning with a drift of -0.004 /s."""
    ws = params["stribeck_velocity"]
    level = form_values(rig, base)[0].get("mu_k", (params["mu_k"].value if "mu_k" in params else 0.1, 0.0))[0]
    mu_k = {"mu_k": float(np.clip(level, params["mu_k"].min, params["mu_k"].max))} if "mu_k" in params \
        and params["mu_k"].vary else {}
    return [{**mu_k, "stribeck_velocity": float(np.clip(ws.value / f, ws.min, ws.max))} for f in (1.0, 3.0)]


def _level_neutral(name: str, value: float, mu_k: float, base: FitResult) -> dict:
    """A start with the form's value ``name`` at ``value``; for a drift of the friction levels (1/s),
    mu_k moved so that the level at the fitted records' mean time stays the selected fit's (a drift
    started alone, with mu_k unchanged, ranks below the selected model's own values and a fit from
    there stops in the local valley at zero drift: a 5 s drifting record, BIC 13 short)."""
    if name != "mu_k_drift" or not base.times:
        return {name: value}
    t_mean = float(np.mean(np.concatenate([np.clip(t, 0.0, None) for t in base.times])))
    return {name: value, "mu_k": max(mu_k - value * t_mean, 0.0)}


#: refit(effects, parameters, extra starts, label, **fit options) -> FitResult: one fit of the record(s)
#: (the options: :func:`form_fit_options`, keywords of :func:`vcbmodel.analysis.fit.fit`).
Refit = Callable[..., FitResult]


def form_fit_options(alt: Alternative, starts: list) -> dict:
    """How a form's fit runs: the tolerances above; the optimiser from the best-ranked start, or from
    every start for a form with a scanned value of its own (a drift) or an added decay effect (one in
    place of another): their valleys lie apart, and the start nearest the selected fit ranks first."""
    every = (alt.form is not None and any(p.scan for p in FORMS[alt.form].parameters)) or (
        len(alt.added) == 1 and alt.added[0] in DECAY_SHARES)
    return {"max_starts": 1 + len(starts) if every else 1, "every_start": every, "chi2_tolerance": CHI2_TOLERANCE,
            "relative_tolerance": RELATIVE_TOLERANCE, "max_iterations": MAX_ITERATIONS}


def fit_forms(rig, base: FitResult, refit: Refit, noise=None, *, label: str = "selected",
              pinned: dict | None = None, budget_s: float | None = None, searched: bool = False) -> ModelForms:
    """Fit the alternatives of ``base`` (the selected model's fit of ``rig``'s record or records)
    with ``refit`` and return the forms with their weights and the quantities over them.

    ``noise``: the record's noise model for chi^2 (None: white at each fit's sigma). ``pinned``:
    {parameter: 1-sigma shift} a pinned rig or sensor value's plausible error causes (added to every
    form's variance). ``budget_s``: seconds after which no further form is fitted. ``searched``:
    :func:`alternatives`."""
    selected = FormFit(Alternative(label, tuple(base.effects), ()), base, rounding_bic(base, noise))
    fits, not_tried = [selected], dict(NOT_CARRIED)
    deadline = None if budget_s is None else time.monotonic() + budget_s

    def fit_one(parent: FitResult, alt: Alternative) -> None:
        _fit_one(rig, parent, alt, refit, noise, fits, not_tried, deadline)

    leader = _effects_step(rig, selected, fits, fit_one)
    # the friction's shapes, from the best plausible model of the effects and from the selected one (a
    # decay effect can absorb part of a shape's work: air drag taking a drifting level's share)
    for parent in [leader] + ([selected] if selected.plausible and selected is not leader else []):
        alts, skipped = alternatives(parent.fit.effects, rig.experiment, searched and parent is selected)
        not_tried.update(skipped)
        for alt in alts:
            fit_one(parent.fit, alt if parent is selected else replace(alt, label=f"{alt.label}, {parent.alternative.label}"))
    _weigh(rig, fits, not_tried)
    profile_forms(rig, selected.fit, fits, refit, deadline)
    quantities, specific = quantities_over(rig, fits, pinned or {})
    forms = ModelForms(fits, quantities, not_tried, specific)
    forms.findings = findings_of(rig, {p.name: p.value for p in base.parameters.values() if p.kind == "model"},
                                 {p.name: p.stderr for p in base.parameters.values() if p.kind == "model" and p.vary},
                                 forms.quantities)
    return forms


def _effects_step(rig, selected: FormFit, fits: list, fit_one: Callable) -> FormFit:
    """Fit the selected model's decay-effect alternatives (:func:`added_effects`) and, when one of
    them leads, that one's removals too; return the best plausible model of the effects."""
    for alt in added_effects(selected, rig.experiment):  # the decay effects it lacks, beside or instead
        fit_one(selected.fit, alt)
    leader = _mark_plausible(rig, fits, selected)
    if leader is not selected:  # the best model of the effects without a fall it may not hold either
        for alt in added_effects(leader, rig.experiment):
            # removals only, and not of what the leader added (that model was fitted already)
            if alt.removed and not alt.added and not set(alt.removed) & set(leader.alternative.added):
                fit_one(leader.fit, replace(alt, label=f"{leader.alternative.label}, {alt.label}"))
        leader = _mark_plausible(rig, fits, selected)
    return leader


def _mark_plausible(rig, fits: list, default: FormFit) -> FormFit:
    """Mark each fit's plausibility; the plausible one with the best BIC (``default`` if none)."""
    for f in fits:
        f.plausible = plausible_fit(rig, f.fit)
    return min((f for f in fits if f.plausible), key=lambda f: f.bic, default=default)


def _weigh(rig, fits: list, not_tried: dict) -> None:
    """Mark each form ``plausible`` and ``weighed``; the BIC weights and distances of ``fits`` over
    the weighed ones: the plausible ones, or all of them when no plausible form fits within the
    evidence margin of the best."""
    _mark_plausible(rig, fits, fits[0])
    best_plausible = min((f.bic for f in fits if f.plausible), default=math.inf)
    every = best_plausible - min(f.bic for f in fits) > EVIDENCE_MARGIN  # no plausible form fits as well
    for f in fits:
        f.weighed = every or f.plausible
    if every:
        not_tried["plausible forms"] = ("none fits the record within the evidence margin of a form with an implausible "
                                        "value: all are weighed (the findings say which values are implausible)")
    best = min(f.bic for f in fits if f.weighed)
    raw = [math.exp(-0.5 * (f.bic - best)) if f.weighed else 0.0 for f in fits]
    for f, w in zip(fits, raw):
        f.delta_bic, f.weight = f.bic - best, w / sum(raw)


def profiled_parameters(alt: Alternative) -> list[str]:
    """The parameters a form adds to the model it came from (its friction form's own, a decay
    effect's coefficient): those the record may not resolve as their stated errors say."""
    own = [fp.name for fp in FORMS[alt.form].parameters] if alt.form is not None else []
    return own + [DECAY_SHARES[e] for e in alt.added if e in DECAY_SHARES and e in EFFECTS]


def profile_forms(rig, base: FitResult, fits: list, refit: Refit, deadline: float | None = None) -> None:
    """The profile (:mod:`.fit.profile`) of each parameter a form within the evidence margin adds,
    into its ``profiles``: refitted with it held outward of its stated 95 % ends until the record
    rejects a point. A curved valley (a drift traded against viscous and Coulomb friction along a
    swing's decay) lets a value far beyond the error its Jacobian states; the ends' values then
    widen every quantity's interval (:func:`quantities_over`)."""
    def late() -> bool:
        return deadline is not None and time.monotonic() > deadline

    for f in fits[1:]:
        if not f.within_margin:
            continue
        for name in profiled_parameters(f.alternative):
            if name not in f.fit.parameters or late():
                continue
            pr = profile(f.fit, name, _held_refit(f, name, refit, base),
                         lambda fit: {k: v for k, (v, _) in form_values(rig, fit)[0].items()}, late)
            if pr is not None:
                f.profiles.append(pr)


def _held_refit(form: FormFit, name: str, refit: Refit, base: FitResult) -> Callable:
    """refit_held(value, start) of :func:`.fit.profile.profile`: ``form``'s model refitted with
    ``name`` held at ``value`` from ``start``'s values (a drift's move level-neutral: mu_k moved so
    the level at the record's mean time stays, :func:`_level_neutral`); None when the fit fails."""
    options = {"max_starts": 1, "every_start": False, "chi2_tolerance": CHI2_TOLERANCE,
               "relative_tolerance": RELATIVE_TOLERANCE, "max_iterations": MAX_ITERATIONS}

    def run(value: float, start: FitResult) -> FitResult | None:
        params = {k: replace(p, stderr=None, stderr_naive=None) for k, p in start.parameters.items()}
        if "mu_k" in params and params["mu_k"].vary:
            moved = _level_neutral(name, value - params[name].value, params["mu_k"].value, base).get("mu_k")
            if moved is not None:
                params["mu_k"] = replace(params["mu_k"], value=float(np.clip(moved, params["mu_k"].min, params["mu_k"].max)))
        params[name] = replace(params[name], value=float(value), vary=False)
        try:
            return refit(form.fit.effects, params, [], f"{form.alternative.label}, {name} held at {value:.3g}", **options)
        except (FitAborted, SimulationError, ValueError):
            return None
    return run


def plausible_fit(rig, fit: FitResult) -> bool:
    """Whether every fitted model value of ``fit`` is within its plausible range or within 1.96 of
    its stated errors of it (:func:`.plausibility.plausible_range`)."""
    for name, p in fit.parameters.items():
        bounds = plausible_range(name, rig) if p.kind == "model" else None
        if bounds is None:
            continue
        se = p.stderr if p.vary and p.stderr is not None and math.isfinite(p.stderr) else 0.0
        if p.value + Z95 * se < bounds[0] or p.value - Z95 * se > bounds[1]:
            return False
    return True


def _fit_one(rig, base: FitResult, alt: Alternative, refit: Refit, noise, fits: list, not_tried: dict,
             deadline: float | None) -> None:
    """Fit ``alt`` from ``base``'s values and append it to ``fits`` (or say in ``not_tried`` why not)."""
    if deadline is not None and time.monotonic() > deadline:
        not_tried[alt.label] = "the forms' time budget was spent"
        return
    params, starts = alternative_parameters(rig, base, alt)
    try:
        r = refit(alt.effects, params, starts, alt.label, **form_fit_options(alt, starts))
    except (FitAborted, SimulationError, ValueError) as e:
        not_tried[alt.label] = f"its fit failed ({e})"
        return
    fits.append(FormFit(alt, r, rounding_bic(r, noise)))


def _static_load(rig) -> float | None:
    """The journal's static load F (N) the mu_k meaning uses: a pendulum's weight M g (None otherwise)."""
    return rig.pendulum.mass * rig.gravity if rig.pendulum is not None else None


def form_values(rig, f: FitResult) -> tuple[dict, dict]:
    """({quantity: (value, stderr)}, {form-specific name: value}) of one form in the common meanings
    (module docstring): the model parameters, mu_k as the Coulomb level at speed, mu_s as the level
    at rest, additive effects the form lacks at 0."""
    p = {k: v for k, v in f.parameters.items() if v.kind == "model"}
    out = {}
    for name, q in p.items():
        if name in SHAPE_VALUES or name == "stick_velocity":
            continue
        se = q.stderr if q.vary else 0.0
        out[name] = (float(q.value), math.inf if se is None or not math.isfinite(se) else float(se))
    F = _static_load(rig)
    shifted = {"stribeck", "viscous_friction"} <= set(f.effects) and not any(
        FORMS[n].effect in f.effects for n in CURVE_FORMS)
    if "mu_k" in out and shifted and F:
        v, se = out["mu_k"]
        out["mu_k"] = (v - p["viscous"].value * p["stribeck_velocity"].value / (rig.shaft_radius * F), se)
    if "mu_k" in p:  # the level at rest: the static one the law uses (never below mu_k), else mu_k
        if "mu_s" in p:
            holds = p["mu_s"].value >= p["mu_k"].value
            out["mu_s"] = (float(effective_static(p["mu_s"].value, p["mu_k"].value)),
                           out["mu_s"][1] if holds else out["mu_k"][1])
        else:
            out["mu_s"] = (float(p["mu_k"].value), out["mu_k"][1])
    specific = {name: float(p[name].value) for name in SHAPE_VALUES if name in p}
    return out, specific


def quantities_over(rig, fits: list[FormFit], pinned: dict) -> tuple[dict, dict]:
    """({name: Quantity}, {form: form-specific values}) over the weighted forms."""
    per_form = [form_values(rig, f.fit) for f in fits]
    # the quantities of the forms the record does not reject (a drift only a rejected form has is left out)
    names = list(dict.fromkeys(n for f, (values, _) in zip(fits, per_form) if f.within_margin for n in values))
    units = {p.name: p.unit or "-" for f in fits for p in f.fit.parameters.values()}
    out = {}
    for name in names:
        rows = []
        for f, (values, _) in zip(fits, per_form):
            v, se = values.get(name, (0.0, 0.0))
            rows.append((f, v, math.hypot(se, pinned.get(name, 0.0))))
        if all(se == 0.0 for _, _, se in rows) and len({v for _, v, _ in rows}) == 1:
            continue  # no form fits it: a value the rig gives (mu_k of a closing), not one the record states
        # where the profiles' ends put it (a pinned value's shift around each)
        reach = [end[name] + k * Z95 * pinned.get(name, 0.0) for f in fits if f.within_margin for pr in f.profiles
                 for end in pr.ends if name in end for k in (-1.0, 1.0)]
        out[name] = _average(rig, name, units.get(name, "-"), rows, _physical_bounds(name, fits), reach)
    return out, {f.alternative.label: s for f, (_, s) in zip(fits, per_form) if s}


def _physical_bounds(name: str, fits: list[FormFit]) -> tuple[float, float]:
    """The widest bounds the forms' fits give parameter ``name`` (mu_k, a viscous coefficient, a damping
    ratio cannot be negative): an interval is cut there, as the fits are."""
    params = [f.fit.parameters[name] for f in fits if name in f.fit.parameters]
    return (min((p.min for p in params), default=-math.inf), max((p.max for p in params), default=math.inf))


def _average(rig, name: str, unit: str, rows: list, physical: tuple = (-math.inf, math.inf),
             reach: Sequence[float] = ()) -> Quantity:
    """The model average of one quantity over (form fit, value, stderr) rows: over the forms within
    the evidence margin (the others' weights, below exp(-5) of the best's, are dropped and the rest
    renormalised: a rejected form whose fit states no error must not make the quantity unknown), its
    interval widened to hold the values in ``reach`` (the forms' profile ends) and cut at the
    parameter's ``physical`` bounds. The stated 1-sigma is the one whose 95 % interval is the reported
    one where that is wider than the average's own (a form within the margin or a profile holding
    the interval open): a value and its error must not say less than the interval beside them."""
    by_form = {f.alternative.label: (float(x), float(s)) for f, x, s in rows}
    rows = [row for row in rows if row[0].within_margin]
    w = np.array([f.weight for f, _, _ in rows])
    w = w / w.sum()
    v = np.array([x for _, x, _ in rows])
    se = np.array([s for _, _, s in rows])
    mean = float(np.sum(w * v))
    var = float(np.sum(w * (se**2 + (v - mean) ** 2)))
    sd = math.sqrt(var) if math.isfinite(var) else math.inf
    low, high = mean - Z95 * sd, mean + Z95 * sd
    near = [(x, s) for _, x, s in rows]
    for x, s in near:
        low, high = min(low, x - Z95 * s), max(high, x + Z95 * s)
    for x in reach:
        low, high = min(low, x), max(high, x)
    finite = math.isfinite(sd) and all(math.isfinite(s) for _, s in near)
    bounds = plausible_range(name, rig)
    width = (bounds[1] - bounds[0]) if bounds else 2.0 * abs(mean)
    determined = bool(finite and (high - low) < width)
    if not finite:  # no error: the forms' values and, what is known without the record, the plausible range
        values = [x for x, _ in near] + (list(bounds) if bounds else [])
        low, high = min(values), max(values)
    low, high = max(low, physical[0]), min(high, physical[1])
    if finite:
        sd = max(sd, (high - low) / (2.0 * Z95))
    meaning = ("the Coulomb level at speed: the friction at speed less C_v w, over r F" if name == "mu_k" else
               "the friction level at rest" if name == "mu_s" else "")
    return Quantity(name, unit, mean, sd, float(low), float(high), determined, by_form, meaning)


def diagnosis_model_forms(ctx, final: FitResult, pinned: dict | None, noise) -> ModelForms:
    """The forms around a diagnosis's final fit, fitted to its record as the diagnosis fits it (the
    record's nuisance free, chi^2 under the search's noise model ``noise``; ``ctx``: its ``rig``,
    ``dataset``, ``pool``, ``sigma_hf`` and ``scales()``); ``pinned``: the report's pinned-gain item
    (its 1-sigma shifts join every form's variance)."""
    deadline = time.monotonic() + FORMS_BUDGET_S

    def refit(effects, params, starts, label, **options):
        return fitting.fit([ctx.dataset], effects, final.spring_model, params, sigma=ctx.sigma_hf, pool=ctx.pool,
                           processes=1, scales=ctx.scales(), starts=starts, verbose=False, label=label,
                           should_stop=lambda: time.monotonic() > deadline, **options)

    shifts = {name: row["shift"] for name, row in (pinned or {}).get("shifts", {}).items()}
    return fit_forms(ctx.rig, final, refit, noise, label=f"selected ({_form_name(final.effects)})", pinned=shifts,
                     budget_s=FORMS_BUDGET_S, searched=True)


def _form_name(effects: Sequence[str]) -> str:
    return next((f.name for f in FORMS.values() if f.effect and f.effect in effects), "hybrid")

"""Discovery of a torque no registered effect describes, in named steps:

1. :func:`.force.missing_torque`: the missing torque on the aligned, smoothed record;
2. :func:`.library.columns` / :func:`.library.model_columns`: the candidate terms and the model's own
   directions on that state;
3. :func:`.regression.select`: each term's share of the missing torque (and the lasso's order);
4. :func:`.search.forward`: every term that could matter refitted *alone* to the whole record first
   (:func:`.refit.refit`), then one more term at a time over the kept support; a form is kept only
   with the evidence a registered effect needs (:func:`.judge.evidence`; each further term must earn
   it again over the smaller support), and where the record cannot tell forms apart (BICs within that
   margin) the physically motivated one is kept and the tie reported;
5. the kept terms pruned (each must earn its place over the others) and their errors stated.

Each discovered form is reported as *discovered, not registered*, with its coefficient, standard
error and physical reading; when nothing earns the evidence, the report says the library holds
nothing that fits.
"""
from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field

from ...errors import SimulationError
from ...experiments import EXPERIMENTS, experiment_of
from ...model.effects import MACHINERY as MODEL_MACHINERY
from ...records.signals import noise_estimate_floored, quantisation_step
from ..fit import Dataset, FitAborted, FitResult
from ..noise import excess as excess  # re-exported (discovery.excess)
from ..nuisance import record_setup
from .force import ForceEstimate, missing_torque, unread
from .judge import EXPLAINS, evidence, explains, scoring_noise
from .library import columns, library_for, model_columns, reading, unit
from .refit import MACHINERY, profile, refit, side_by_side, terms_of
from .regression import Selection, select
from .search import forward


#: Profiles of a coefficient taken at most (each one whose parabola's lowest point lies away from the
#: value refits from there; the next profile is taken around the new value).
PROFILE_ROUNDS = 3


@dataclass
class DiscoveredTerm:
    """One term of a discovered torque: ``coefficient`` and ``stderr`` in ``unit`` (so that
    coefficient x term is N m), and what a torque of this form usually is. ``stderr`` is the larger
    of the fit's (``stderr_jacobian``) and the chi^2 profile's (``stderr_profile``)."""

    name: str
    coefficient: float
    stderr: float | None
    unit: str
    reading: str
    stderr_jacobian: float | None = None
    stderr_profile: float | None = None

    def to_json(self) -> dict:
        return {"term": self.name, "coefficient": self.coefficient, "stderr": self.stderr, "unit": self.unit,
                "stderr_jacobian": self.stderr_jacobian, "stderr_profile": self.stderr_profile,
                "reading": self.reading, "status": "discovered, not registered"}


@dataclass
class Discovery:
    """What discovery found on one record. ``found``: a discovered torque earned the evidence;
    ``terms`` its terms; ``before`` the best registered fit (the one given, or the registered model
    refitted from the regression's start when that is better), ``after`` the fit with the kept
    terms (None when nothing was kept); rms in the measured channel's unit (``unit``), the
    noise level ``noise`` (the same unit); ``tried``: every support refitted with its evidence."""

    found: bool
    terms: list
    before: FitResult
    after: FitResult | None
    noise: float
    unit: str
    message: str
    tried: list = field(default_factory=list)
    selection: Selection | None = None
    estimate: ForceEstimate | None = None
    bic_margin: float = 0.0
    min_gain: float = 0.0
    seconds: float = 0.0
    given: FitResult | None = None  # the registered fit discovery started from
    alternatives: list = field(default_factory=list)  # other bases tried (discover_among)
    ties: list = field(default_factory=list)  # forms the record could not tell apart (search.choose)

    @property
    def rms_before(self) -> float:
        return self.before.rms

    @property
    def rms_after(self) -> float:
        return (self.after or self.before).rms

    def to_json(self) -> dict:
        sel = self.selection
        return {"found": self.found, "message": self.message, "terms": [t.to_json() for t in self.terms],
                "rms_before": self.rms_before, "rms_after": self.rms_after, "noise": self.noise, "unit": self.unit,
                "bic_margin": self.bic_margin, "min_variance_gain": self.min_gain, "tried": self.tried,
                "regression": None if sel is None else {
                    "order": sel.order, "terms_by_bic": sel.n_bic, "aliased_with_model": sel.aliased,
                    "samples": sel.samples, "explained_share": [round(e, 4) for e in sel.explained]},
                "smoothing_window_s": None if self.estimate is None else self.estimate.window_s,
                "base_effects": list(self.before.effects), "refitted_effects": list((self.after or self.before).effects),
                "fitted": {k: float(f"{v:.6g}") for k, v in (self.after or self.before).model_values.items()},
                "alternatives": self.alternatives, "ties": self.ties,
                "seconds": round(self.seconds, 2)}

    def report(self) -> str:
        u = self.unit
        lines = [f"  discovery: {self.message}",
                 f"    rms {self.rms_before:.3g} -> {self.rms_after:.3g} {u} (noise {self.noise:.3g} {u})"]
        for t in self.terms:
            err = f" +- {t.stderr:.2g}" if t.stderr is not None else ""
            lines.append(f"    {t.name}: {t.coefficient:.4g}{err} {t.unit} (discovered, not registered): {t.reading}")
        for row in self.tried:
            dropped = (f" ({row['dropped']} dropped: it lowers BIC by {row['dropped_delta_bic']:.1f} over the other terms)"
                       if row.get("dropped") else "")
            lines.append(f"    tried {' + '.join(row['terms'])}: dBIC {row['delta_bic']:.1f}, variance gain "
                         f"{row['variance_gain']:.3f}, rms {row['rms']:.3g} {u}" + dropped + (" (kept)" if row["kept"] else ""))
        for tie in self.ties:
            lines.append(f"    tie: {tie['reason']} (BIC above the best: "
                         + ", ".join(f"{k} {v:g}" for k, v in tie["bic_above_best"].items()) + ")")
        return "\n".join(lines)


def record_dataset(rig, measurement) -> tuple[Dataset, float, float]:
    """(dataset, high-frequency noise level, quantisation step) of a record, set up as the diagnosis does."""
    y = measurement.channel(experiment_of(rig.experiment).measured_channel)
    q = quantisation_step(y)
    sigma = noise_estimate_floored(y, q)
    return Dataset(rig, measurement, record_setup(rig, measurement, sigma)), sigma, q


def _nothing(fit, noise, unit_, message, **kw) -> Discovery:
    return Discovery(False, [], fit, None, noise, unit_, message, **kw)


def covers(experiment: str) -> bool:
    """Whether discovery can search this experiment's records (its equations carry a discovered torque)."""
    return MODEL_MACHINERY[MACHINERY].acts_on(experiment_of(experiment).provides)


def covered() -> list[str]:
    """The experiments whose records discovery can search."""
    return [name for name in EXPERIMENTS if covers(name)]


def discover(rig, measurement, fit: FitResult, *, bic_margin: float, min_gain: float, dataset: Dataset | None = None,
             sigma: float | None = None, quantisation: float | None = None, pool=None,
             library: Sequence[str] | None = None, should_stop=None) -> Discovery:
    """Search ``library`` (default: the experiment's, :func:`.library.library_for`) for the torque
    ``fit`` (the best registered model of ``measurement``) lacks (module docstring). ``bic_margin`` and ``min_gain`` are the evidence a registered
    effect must give (the diagnosis's); ``dataset``, ``sigma`` (measured unit) and
    ``quantisation``: the diagnosis's own (built from the record when not given)."""
    started = time.monotonic()
    rec = experiment_of(rig.experiment)
    if dataset is None:
        dataset, sigma0, q0 = record_dataset(rig, measurement)
        sigma = sigma if sigma is not None else sigma0
        quantisation = quantisation if quantisation is not None else q0
    quantisation = quantisation or 0.0
    kw = {"bic_margin": bic_margin, "min_gain": min_gain, "given": fit}
    if not covers(rig.experiment):
        return _nothing(fit, sigma, rec.unit, f"not tried: discovery covers {', '.join(covered())} "
                        f"tests, not a {rig.experiment} test", **kw)
    why = unread(rig, fit)
    if why:
        return _nothing(fit, sigma, rec.unit, f"not tried on this model: {why}", **kw)
    est = missing_torque(rig, dataset, fit)
    names = list(library_for(rig.experiment) if library is None else library)
    used = est.used
    z_names, Z = model_columns(fit, est)
    sel = select(names, columns(names, est)[used], est.torque[used], Z[used], z_names)
    out = _search(dataset, fit, sel, sigma, quantisation, pool, should_stop, kw)
    out.selection, out.estimate, out.seconds = sel, est, time.monotonic() - started
    return out


def _registered_best(dataset, fit, sel, sigma, pool, should_stop) -> FitResult:
    """``fit``, or the registered model refitted from the regression's start for its own values when
    that is better: a term is credited only with what the registered model cannot do, not with
    the distance its fit stopped short of its own best (the friction forms share a long valley)."""
    try:
        again = refit(dataset, fit, {}, sel.base_shift, sigma=sigma, pool=pool, should_stop=should_stop)
    except (SimulationError, FitAborted):
        return fit
    return again if again.chi2 < fit.chi2 else fit


def _terms(dataset, after, names, noise, sigma, pool, should_stop) -> tuple[list, FitResult]:
    """The kept terms with their stated errors (the largest of the fit's, from its Jacobian, and the
    chi^2 profiles'), and the fit polished along each term's profile."""
    errors = {}
    for name in names:
        errors[name] = None
        for _ in range(PROFILE_ROUNDS):
            try:
                error, polished = profile(dataset, after, name, noise, sigma=sigma, pool=pool, should_stop=should_stop)
            except (SimulationError, FitAborted):
                break
            errors[name] = max((e for e in (errors[name], error) if e is not None), default=None)
            if polished is after:
                break
            after = polished
    terms = []
    for name in names:
        p = after.parameters["discovered:" + name]
        stated = [e for e in (p.stderr, errors[name]) if e is not None]
        terms.append(DiscoveredTerm(name, p.value, max(stated) if stated else None, unit(name), reading(name, p.value), p.stderr,
                                    errors[name]))
    return terms, after


def _search(dataset, fit, sel, sigma, quantisation, pool, should_stop, kw) -> Discovery:
    """Forward selection from the best registered fit, singles first, ties read physics
    (:func:`.search.forward`); the kept terms pruned and their errors stated."""
    unit_ = experiment_of(dataset.rig.experiment).unit
    given, fit = fit, _registered_best(dataset, fit, sel, sigma, pool, should_stop)
    found = forward(dataset, given, fit, sel, sigma=sigma, quantisation=quantisation, kw=kw, pool=pool,
                    should_stop=should_stop)
    tried, ties, fit = found["tried"], found["ties"], found["registered"]
    noise = scoring_noise(found["fits"], sigma, quantisation)
    if not found["support"]:
        best = max(tried, key=lambda row: row["delta_bic"]) if tried else None
        why = ("the library holds nothing that fits: " + (
            f"its best term, {best['terms'][0]}, {'lowers' if best['delta_bic'] > 0 else 'raises'} BIC by "
            f"{abs(best['delta_bic']):.1f} (a term must lower it by more than {kw['bic_margin']:g}) "
            f"and removes {best['variance_gain']:.3f} of the noise variance (needed {kw['min_gain']:g})"
            if best else "no term could be refitted"))
        return _nothing(fit, sigma, unit_, why, tried=tried, ties=ties, **kw)
    support = found["support"]
    index = next(i for i, row in enumerate(tried) if row["terms"] == support)
    if not explains(found["fit"], sigma):
        row = tried[index]
        why = (f"the library holds nothing that explains the record: its best form, {' + '.join(support)}, lowers BIC "
               f"by {row['delta_bic']:.1f} but leaves rms {row['rms']:.3g} {unit_} against the noise {sigma:.3g} (more than "
               f"{EXPLAINS:.2g} times it): part of a torque outside the library, its coefficient no physical value")
        return _nothing(fit, sigma, unit_, why, tried=tried, ties=ties, **kw)
    support, after, index = _prune(dataset, fit, list(support), found["fit"], index, noise, sigma, pool,
                                   should_stop, kw, tried)
    tried[index]["kept"] = True
    terms, after = _terms(dataset, after, support, noise, sigma, pool, should_stop)
    tried[index]["rms_polished"] = after.rms
    text = "; ".join(f"{t.reading} ({t.name} = {t.coefficient:.4g} {t.unit})" for t in terms)
    tie_text = "".join(f"; tie: {tie['reason']}" for tie in ties)
    message = (f"discovered, not registered: {text}; rms {fit.rms:.3g} -> {after.rms:.3g} {unit_} "
               f"(noise {sigma:.3g}), delta BIC {tried[index]['delta_bic']:.1f}{tie_text}")
    return Discovery(True, terms, fit, after, sigma, unit_, message, tried, ties=ties, **kw)


def _prune(dataset, registered, support, after, index, noise, sigma, pool, should_stop, kw, tried) -> tuple:
    """Each kept term must earn the evidence over the kept support without it; the nested search asks
    it only of the last term to enter, and a term that entered before a better one can lose its place
    to it (on a cam drop a position window entered before the second harmonic it stood in for). The
    least needed such term is dropped (the rest refitted without it) until every term earns its place.
    Returns (support, fit, index of its row in ``tried``)."""
    while len(support) > 1:
        weakest = None
        for name, without in zip(support, _without_each(dataset, after, support, sigma, pool, should_stop)):
            if without is None:
                continue
            step = evidence(without, after, noise, sigma, kw["bic_margin"], kw["min_gain"])
            if not step["earned"] and (weakest is None or step["delta_bic"] < weakest[1]["delta_bic"]):
                weakest = (name, step, without)
        if weakest is None:
            break
        name, step, after = weakest
        support = [n for n in support if n != name]
        ev = evidence(registered, after, noise, sigma, kw["bic_margin"], kw["min_gain"])
        tried.append({"terms": list(support), "delta_bic": ev["delta_bic"], "variance_gain": ev["variance_gain"],
                      "delta_bic_over_smaller": None, "rms": after.rms, "kept": False, "coefficients": terms_of(after),
                      "dropped": name, "dropped_delta_bic": step["delta_bic"]})
        index = len(tried) - 1
    return support, after, index


def _without_each(dataset, after, support, sigma, pool, should_stop) -> list:
    """``after`` refitted without each term of ``support`` in turn (None where the refit failed); the
    refits are independent: side by side, in ``support``'s order."""
    def without(name):
        rest = {k: v for k, v in terms_of(after).items() if k != name}
        try:
            return refit(dataset, after, rest, None, sigma=sigma, pool=pool, should_stop=should_stop)
        except (SimulationError, FitAborted):
            return None
    return side_by_side(pool, without, support)


def discover_among(rig, measurement, fits: Sequence[FitResult], **options) -> Discovery:
    """Discovery on each registered model of ``fits`` (e.g. the diagnosis's final model and its
    starting model; ``options`` as :func:`discover`), keeping the one whose resulting model (with
    its discovered torque, or without when none earned it) has the lowest BIC under one noise model.
    A registered effect the diagnosis added can be a stand-in for the torque it could not name
    (a Stribeck curve bent to follow air drag): with the torque found, the simpler base can win.
    The searches on the bases are independent: they run side by side (:func:`.refit.side_by_side`;
    each still runs its own independent fits side by side), and the choice reads them in ``fits``' order."""
    if not covers(rig.experiment):
        return discover(rig, measurement, fits[0], **options)
    bases = [f for i, f in enumerate(fits) if all(f is not g for g in fits[:i])]
    results = side_by_side(options.get("pool"), lambda f: discover(rig, measurement, f, **options), bases)
    if len(results) == 1:
        return results[0]
    sigma = options.get("sigma") or min(r.noise for r in results)
    noise = scoring_noise([r.after or r.before for r in results], sigma, options.get("quantisation") or 0.0)
    best = _registered_first(results, noise, options["bic_margin"])
    if best.given is not fits[0]:
        best.message += base_note(fits[0].effects, best.before.effects)
    best.alternatives = [{"base_effects": list(r.given.effects), "found": r.found, "terms": [t.name for t in r.terms],
                          "bic": (r.after or r.before).bic_with(noise)} for r in results]
    return best


def _registered_first(results: list, noise, margin: float) -> Discovery:
    """The result whose model has the lowest BIC; where the record cannot tell it from one that needs no
    discovered torque (BICs within ``margin``), that one: a registered effect is a known law, a discovered
    term a shape (a self-damping spring's record fitted by a constant torque on the undamped model as well
    as by the registered spring damping). The tie is reported on the kept result."""
    def bic(r):
        return (r.after or r.before).bic_with(noise)
    lowest = min(results, key=bic)
    registered = [r for r in results if not r.found and bic(r) - bic(lowest) <= margin]
    if not lowest.found or not registered:
        return lowest
    kept = min(registered, key=bic)
    found = "+".join(t.name for t in lowest.terms)
    kept.ties.append({"kept": "registered: " + ", ".join(kept.before.effects), "tied_with": [found],
                      "margin": margin, "bic_above_best": {"registered": round(bic(kept) - bic(lowest), 2), found: 0.0},
                      "tier": {}, "stage": 0,
                      "reason": (f"the record cannot tell the registered {', '.join(kept.before.effects)} from "
                                 f"{', '.join(lowest.before.effects)} + discovered {found} (BICs within {margin:g}); kept "
                                 "the registered model, a known law")})
    kept.message += f"; tie: {kept.ties[-1]['reason']}"
    return kept


def base_note(final_effects: Sequence[str], base_effects: Sequence[str]) -> str:
    """The message's note when discovery's best base is not the diagnosis's final model: the
    effects the base leaves out, or, with the same effects, that it is the starting model's fit."""
    others = ", ".join(sorted(set(final_effects) - set(base_effects)))
    if others:
        return f" (on the model without {others}: with the discovered torque that effect is not needed)"
    return (" (on the starting model's fit of the same effects, not the final one's: with the discovered "
            "torque its values fit better)")


def discovery_step(rig, measurement, final: FitResult, starting: FitResult | None, explained: bool,
                   **options) -> Discovery | None:
    """The diagnosis's discover step: None when the final model explains the record (nothing to
    look for), else :func:`discover_among` on the final model and the starting model (with its own
    alignment). ``options``: :func:`discover`'s (the diagnosis passes its dataset, noise level,
    quantisation, pool and its evidence threshold)."""
    if explained:
        return None
    return discover_among(rig, measurement, [final] + ([starting] if starting is not None else []), **options)

"""Which terms a discovered torque keeps: forward selection that tries every term alone first and
reads physics where the record cannot decide.

1. **Singles first.** Every library term is tried alone on the missing torque (its share of the
   torque's variance outside the model's own directions, :meth:`.regression.Selection.ranked`);
   the :data:`SINGLE_REFITS` best whose share is at least :data:`SHARE_OF_BEST` of the best term's,
   and every tier-0 term (a known law's form) whatever its share, are refitted alone to the whole
   record. A term is never tried only as part of a pair. Every tier-0 term is refitted because the
   share is read on the registered fit's linearisation: when that fit sits in another basin (a swing
   with air drag fitted by Coulomb and viscous friction can settle at half the true Coulomb level),
   the shares rank the registered model's own misfit, and the drag's column can rank twelfth.
   A harmonic's sine and cosine are also tried together, as one form: a torque periodic in the angle
   with a phase, A sin(k theta - phi), needs both.
   Every refit here is a screen at the fits' usual tolerance; the forms within twice the evidence
   margin of the best are polished (refitted at an absolute tolerance) before anything is chosen.
2. **Then one more term at a time**, over the kept support: the :data:`NEXT_REFITS` terms that add
   the most, refitted with it; a larger support is kept only if it earns the evidence over the
   smaller one. At most :data:`MAX_TERMS` terms.
3. **Ties read physics.** Two forms *tie* when their BICs (the whitened residual's, under one noise
   model) differ by no more than the evidence margin (the diagnosis's ``BIC_MARGIN``, 10: the
   difference a term needs to enter at all, "very strong" on Kass & Raftery's scale, J. Am. Stat.
   Assoc. 90, 1995). Among tied forms that earn the evidence the one of the lowest physical tier
   (:data:`vcbmodel.laws.discovered.TIERS`: a known law's form before a plausible part's before a
   shape with no mechanism) is kept, the best BIC within the tier, and the tie is reported with each
   form's BIC above the best.
4. **Credit only what the registered model cannot do.** A refit with one more free coefficient can
   leave a local optimum the registered fit sat in (a record with a torque outside the library makes
   the cost bumpy); then every term "earns" about the same. After the singles, the registered model
   is refitted from the best singles' values (their coefficients dropped); if that is better, it
   is the base every candidate's evidence is measured against.
"""
from __future__ import annotations


from ...errors import SimulationError
from ...laws.discovered import TIERS, term
from ..fit import FitAborted, FitResult
from .judge import evidence, scoring_noise
from .refit import polish, refit, side_by_side, terms_of

#: A term is refitted alone when its own share of the missing torque is at least this fraction of the
#: best term's (a term explaining a fifth of what the best explains does not win on the record).
SHARE_OF_BEST = 0.2
#: Most single terms refitted (tier-0 terms above the share come besides).
SINGLE_REFITS = 4
#: Terms refitted as the next addition to a kept support.
NEXT_REFITS = 2
#: Most terms one discovery adds.
MAX_TERMS = 3


def partner(name: str) -> str | None:
    """A harmonic's other phase (``sin_2theta`` <-> ``cos_2theta``), or None."""
    for a, b in (("sin_", "cos_"), ("cos_", "sin_")):
        if name.startswith(a) and name.endswith("theta"):
            return b + name[len(a):]
    return None


def tier(form: tuple) -> int:
    """A form's physical tier: its terms' lowest (:data:`vcbmodel.laws.discovered.TIERS`)."""
    return min(term(name).tier for name in form)


def options(sel, support: list) -> list[tuple]:
    """The forms (tuples of terms) to refit with ``support`` (module docstring, steps 1-2)."""
    ranked = sel.ranked(support)
    if not ranked or ranked[0][1] <= 0:
        return []
    near = [name for name, share in ranked if share >= SHARE_OF_BEST * ranked[0][1]]
    count = NEXT_REFITS if support else SINGLE_REFITS
    physical = [name for name, _ in ranked] if not support else near[count:]
    names = near[:count] + [name for name in physical if term(name).tier == 0 and name not in near[:count]]
    available = {name for name, _ in ranked}
    forms = [(name,) for name in names]
    for name in names:
        other = partner(name)
        pair = tuple(sorted((name, other))) if other in available else None
        if pair and pair not in forms:
            forms.append(pair)
    return forms


def label(form: tuple) -> str:
    return " + ".join(form)


def choose(scored: list, margin: float) -> tuple:
    """(the kept candidate, the tie or None) among ``scored`` [(form, fit, bic, earned)]: the best BIC,
    or within ``margin`` of it the lowest physical tier (module docstring, step 3)."""
    best_bic = min(s[2] for s in scored)
    tied = [s for s in scored if s[2] - best_bic <= margin]
    eligible = [s for s in tied if s[3]] or tied
    kept = min(eligible, key=lambda s: (tier(s[0]), s[2]))
    if len(tied) < 2:
        return kept, None
    others = sorted((s for s in tied if s is not kept), key=lambda s: s[2])
    return kept, {"kept": label(kept[0]), "tied_with": [label(s[0]) for s in others], "margin": margin,
                  "bic_above_best": {label(s[0]): round(s[2] - best_bic, 2) for s in tied},
                  "tier": {label(s[0]): tier(s[0]) for s in tied},
                  "reason": (f"the record cannot tell {label(kept[0])} from {', '.join(label(s[0]) for s in others)} "
                             f"(BICs within {margin:g}); kept {label(kept[0])}, {TIERS[tier(kept[0])]}")}


def forward(dataset, given: FitResult, registered: FitResult, sel, *, sigma: float, quantisation: float, kw: dict,
            pool=None, should_stop=None) -> dict:
    """Forward selection over ``sel`` (:class:`.regression.Selection`) from ``registered`` (the best
    registered fit; ``given``: the fit discovery was handed, the base of every refit). Returns
    {"support": kept terms, "fit": their fit (or None), "tried": rows, "ties": [...], "fits": every fit}."""
    support, current, fits, tried, ties = [], registered, [registered], [], []
    also = registered if registered is not given else None
    while len(support) < MAX_TERMS:
        scored = _refits(dataset, given, current if support else also, sel, support, sigma, pool, should_stop)
        if not scored:
            break
        scored = _polished(dataset, scored, fits, sigma, quantisation, kw["bic_margin"], pool, should_stop)
        fits += [f for _, f in scored]
        if not support:  # step 4: the registered model from the singles' values
            registered = current = _rebased(dataset, given, registered, scored, sigma, pool, should_stop)
            fits.append(registered)
        noise = scoring_noise(fits, sigma, quantisation)
        rows = []
        for form, f in scored:
            ev = evidence(registered, f, noise, sigma, kw["bic_margin"], kw["min_gain"])
            step = evidence(current, f, noise, sigma, kw["bic_margin"], kw["min_gain"])
            rows.append((form, f, f.bic_with(noise), ev["earned"] and step["earned"]))
            tried.append({"terms": support + list(form), "delta_bic": ev["delta_bic"], "variance_gain": ev["variance_gain"],
                          "delta_bic_over_smaller": step["delta_bic"], "rms": f.rms, "kept": False,
                          "coefficients": terms_of(f), "stage": len(support) + 1})
        kept, tie = choose(rows, kw["bic_margin"])
        if not kept[3]:
            break
        if tie is not None:
            ties.append(dict(tie, stage=len(support) + 1))
        support, current = support + list(kept[0]), kept[1]
    return {"support": support, "fit": current if support else None, "tried": tried, "ties": ties, "fits": fits,
            "registered": registered}


def _refits(dataset, given, start, sel, support, sigma, pool, should_stop) -> list:
    """[(form, fit of ``support`` + form)] for each of :func:`options`, in their order; a failed refit
    is left out. The screens are independent fits, run side by side (:func:`.refit.side_by_side`)."""
    starts = [(form, *sel.support_fit(support + list(form))) for form in options(sel, support)
              if len(support) + len(form) <= MAX_TERMS]

    def screened(item):
        form, coefficients, _, shifts = item
        try:
            return form, refit(dataset, given, coefficients, shifts, sigma=sigma, pool=pool,
                               should_stop=should_stop, also=start, screen=True)
        except (SimulationError, FitAborted):
            return None
    return [r for r in side_by_side(pool, screened, starts) if r is not None]


#: Screened forms within this many times the evidence margin of the best screened BIC are polished
#: (refitted at the absolute tolerance) before the choice: a screen stops up to 16 chi^2 short.
POLISH_SPAN = 2.0


def _polished(dataset, scored, fits, sigma, quantisation, margin, pool, should_stop) -> list:
    """``scored`` with the forms near the best (:data:`POLISH_SPAN`) polished."""
    noise = scoring_noise(fits + [f for _, f in scored], sigma, quantisation)
    best = min(f.bic_with(noise) for _, f in scored)

    def polished(item):
        form, f = item
        if f.bic_with(noise) - best <= POLISH_SPAN * margin:
            try:
                again = polish(dataset, f, sigma=sigma, pool=pool, should_stop=should_stop)
                f = again if again.chi2 < f.chi2 else f
            except (SimulationError, FitAborted):
                pass
        return form, f
    return side_by_side(pool, polished, scored)  # independent fits


#: Singles whose values restart the registered model (step 4).
REBASE_FROM = 2


def _rebased(dataset, given, registered, scored, sigma, pool, should_stop) -> FitResult:
    """``registered``, or the registered model refitted from the best singles' values when better (the
    refits are independent: side by side, read in their order)."""
    def rebased(f):
        try:
            return refit(dataset, given, {}, None, sigma=sigma, pool=pool, should_stop=should_stop, also=f)
        except (SimulationError, FitAborted):
            return None
    starts = [f for _, f in sorted(scored, key=lambda s: s[1].chi2)[:REBASE_FROM]]
    best = registered
    for again in side_by_side(pool, rebased, starts):  # independent fits
        if again is not None and again.chi2 < best.chi2:
            best = again
    return best

"""Discovery on more than one base (vcbmodel.analysis.discovery.discover_among): on the starting model
beside the final one, the discovered torque stands in for the effects the final model added, with as
many terms as they have fitted values and no fewer; the forward search stops at that many terms, and
a stage it may still take is searched and decided by the evidence, however close."""
import importlib
from types import SimpleNamespace

import pytest

from vcbmodel.analysis.discovery import search
from vcbmodel.analysis.discovery.discover import Discovery, discover_among, terms_in_place

#: the module (the package exports its function of the same name)
discover_module = importlib.import_module("vcbmodel.analysis.discovery.discover")
MARGIN = 10.0


def model_fit(effects, values):
    """A fit's outline: its effects and its fitted model values (nuisance values besides)."""
    params = {name: SimpleNamespace(vary=True, kind="model") for name in values}
    params["offset"] = SimpleNamespace(vary=True, kind="nuisance")
    return SimpleNamespace(effects=tuple(effects), parameters=params)


COULOMB_VISCOUS = model_fit(("coulomb_friction", "viscous_friction"), ("mu_k", "viscous"))
WITH_STRIBECK = model_fit(("coulomb_friction", "stribeck", "viscous_friction"),
                          ("mu_k", "viscous", "mu_s", "stribeck_velocity"))


def test_the_torque_on_the_starting_model_may_have_as_many_terms_as_the_effects_it_stands_in_for():
    assert terms_in_place(WITH_STRIBECK, COULOMB_VISCOUS) == 2  # Stribeck's two values: two terms, not one
    assert terms_in_place(COULOMB_VISCOUS, model_fit(("coulomb_friction",), ("mu_k",))) == 1
    # an added effect without a fitted value still leaves one term to find
    assert terms_in_place(model_fit(("coulomb_friction", "spring_mass"), ("mu_k",)),
                          model_fit(("coulomb_friction",), ("mu_k",))) == 1
    # the final model itself, the starting fit of the same effects, a base with another effect: no cap
    assert terms_in_place(WITH_STRIBECK, WITH_STRIBECK) == search.MAX_TERMS
    assert terms_in_place(WITH_STRIBECK, model_fit(WITH_STRIBECK.effects, ("mu_k", "viscous"))) == search.MAX_TERMS
    assert terms_in_place(COULOMB_VISCOUS, model_fit(("coulomb_friction", "aerodynamic_drag"), ("mu_k", "drag"))) \
        == search.MAX_TERMS


def test_each_base_is_searched_with_its_own_cap_and_the_choice_reads_them_in_order(monkeypatch):
    seen = []

    def fake_discover(rig, measurement, fit, **options):
        seen.append((fit, options["max_terms"]))
        bic = 100.0 if fit is WITH_STRIBECK else 50.0  # the starting model with its torque wins
        before = SimpleNamespace(bic_with=lambda noise: bic + 30.0, effects=fit.effects, rms=1.0)
        after = SimpleNamespace(bic_with=lambda noise: bic, effects=fit.effects + ("discovered_torque",), rms=1.0)
        return Discovery(fit is COULOMB_VISCOUS, [], before, after, 1.0, "rad", "found", given=fit)
    monkeypatch.setattr(discover_module, "discover", fake_discover)
    monkeypatch.setattr(discover_module, "scoring_noise", lambda fits, sigma, q: None)
    monkeypatch.setattr(discover_module, "covers", lambda experiment: True)
    rig = SimpleNamespace(experiment="pendulum")
    pool = SimpleNamespace(processes=2)
    best = discover_among(rig, None, [WITH_STRIBECK, COULOMB_VISCOUS, WITH_STRIBECK], bic_margin=MARGIN,
                          min_gain=0.0, pool=pool, sigma=1.0)
    assert sorted(((f is WITH_STRIBECK), m) for f, m in seen) == [(False, 2), (True, search.MAX_TERMS)]
    assert best.given is COULOMB_VISCOUS and "without stribeck" in best.message
    assert [a["base_effects"] for a in best.alternatives] == [list(WITH_STRIBECK.effects), list(COULOMB_VISCOUS.effects)]


A, B, C = "w_abs_w", "w3", "theta3"  # library terms (their tiers read only where forms tie)


def _fake_search(monkeypatch, bics):
    """The forward search on fake fits: ``bics`` {form: BIC}; every fit earns by its BIC alone."""
    def fit_of(terms):
        bic = bics[tuple(sorted(terms))]
        return SimpleNamespace(bic_with=lambda noise: bic, rms=bic, chi2=bic, parameters={})

    def refits(dataset, given, start, sel, support, sigma, pool, should_stop, max_terms=search.MAX_TERMS):
        return [((name,), fit_of(support + [name])) for name in (A, B, C)
                if name not in support and len(support) + 1 <= max_terms]

    def evidence(before, after, noise, sigma, margin, gain):
        delta = before.bic_with(noise) - after.bic_with(noise)
        return {"delta_bic": delta, "variance_gain": 1.0, "earned": delta > margin}
    monkeypatch.setattr(search, "_refits", refits)
    monkeypatch.setattr(search, "_polished", lambda dataset, scored, *a: scored)
    monkeypatch.setattr(search, "_rebased", lambda dataset, given, registered, *a: registered)
    monkeypatch.setattr(search, "scoring_noise", lambda fits, sigma, q: None)
    monkeypatch.setattr(search, "evidence", evidence)
    registered = SimpleNamespace(bic_with=lambda noise: 1000.0, rms=1000.0, chi2=1000.0, parameters={})
    return lambda max_terms: search.forward(None, registered, registered, None, sigma=1.0, quantisation=0.0,
                                            kw={"bic_margin": MARGIN, "min_gain": 0.0}, max_terms=max_terms)


@pytest.mark.parametrize("pair_bic,kept", [(969.9, [A, B]), (970.1, [A])])
def test_the_last_stage_the_cap_allows_is_searched_and_decided_by_the_evidence(monkeypatch, pair_bic, kept):
    # B joins A by 10.1 BIC (just over the margin) or 9.9 (just under): the record decides at the cap
    bics = {key: bic for key, bic in [((A,), 980.0), ((B,), 995.0), ((C,), 999.0), ((A, B), pair_bic),
                                      ((A, C), 985.0), ((A, B, C), 900.0)]}
    bics = {tuple(sorted(k)): v for k, v in bics.items()}
    run = _fake_search(monkeypatch, bics)
    found = run(2)
    assert found["support"] == kept
    assert max(len(row["terms"]) for row in found["tried"]) == 2  # never past the cap (the triple would earn)
    assert run(1)["support"] == [A] and run(3)["support"] == ([A, B, C] if kept == [A, B] else [A])

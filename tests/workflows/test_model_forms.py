"""Model-form uncertainty (vcbmodel/analysis/model_forms.py): the forms a record cannot tell apart,
BIC weights, the model-averaged estimate with its unconditional variance, and intervals that hold
the truth when the selected law is not the record's (independent truths: reference/truth_friction.py,
reference/torque_truth.py through analysis/realistic.py)."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from vcbmodel.analysis.diagnose import diagnose
from vcbmodel.analysis.fit import Parameter
from vcbmodel.analysis.fit.profile import Profile
from vcbmodel.analysis.identify import identify
from vcbmodel.analysis.model_forms import (EVIDENCE_MARGIN, Z95, FormFit, ModelForms, _weigh, added_effects,
                                           alternatives, quantities_over)
from vcbmodel.analysis.plausibility import plausible_range
from vcbmodel.analysis.realistic import realistic_record
from vcbmodel.experiments.loading import load_pair


def form(label, delta_bic, weight, effects, **values):
    """A fitted form as fit_forms makes it: values {name: (value, stderr)}."""
    params = {n: Parameter(n, v, 0.0, 10.0, True, "-", stderr=se) for n, (v, se) in values.items()}
    fit = SimpleNamespace(parameters=params, effects=tuple(effects))
    return FormFit(SimpleNamespace(label=label), fit, 0.0, delta_bic, weight)


def test_the_average_and_its_unconditional_variance_are_burnham_and_andersons(pendulum_rig):
    """Two forms with equal weight, mu_k 0.10 and 0.12 +- 0.001: estimate 0.11, variance
    0.5 (1e-6 + 1e-4) * 2 = 1.01e-4; the interval holds both forms' own intervals."""
    fits = [form("a", 0.0, 0.5, ("coulomb_friction",), mu_k=(0.10, 0.001)),
            form("b", 0.0, 0.5, ("coulomb_friction",), mu_k=(0.12, 0.001))]
    q = quantities_over(pendulum_rig, fits, {})[0]["mu_k"]
    assert q.estimate == pytest.approx(0.11)
    assert q.stderr == pytest.approx(math.sqrt(1.01e-4))
    assert q.low == pytest.approx(0.11 - Z95 * math.sqrt(1.01e-4))
    assert q.low < 0.10 - Z95 * 0.001 and q.high > 0.12 + Z95 * 0.001
    assert q.determined


def test_a_form_outside_the_margin_drops_out_even_without_errors(pendulum_rig):
    fits = [form("kept", 0.0, 1.0, ("coulomb_friction", "viscous_friction"), mu_k=(0.1, 0.001), viscous=(0.5, 0.01)),
            form("rejected", EVIDENCE_MARGIN + 5, 1e-5, ("coulomb_friction", "viscous_friction"),
                 mu_k=(0.3, None), viscous=(0.1, None))]
    qs = quantities_over(pendulum_rig, fits, {})[0]
    assert qs["mu_k"].determined and qs["mu_k"].high < 0.11
    assert qs["mu_k"].by_form["rejected"][0] == 0.3  # still listed


def test_a_quantity_a_form_lacks_counts_at_its_physical_value_and_mu_k_has_one_meaning(pendulum_rig):
    """A form without viscous friction has viscous 0 and mu_s = mu_k; the hybrid law's mu_k with its
    shifted viscous term becomes the Coulomb level at speed, mu_k - C_v w_s / (r M g)."""
    p = pendulum_rig.pendulum
    load = p.mass * pendulum_rig.gravity
    hybrid = form("hybrid", 0.0, 0.5, ("coulomb_friction", "stribeck", "viscous_friction"), mu_k=(0.13, 0.001),
                  mu_s=(0.2, 0.002), stribeck_velocity=(0.1, 0.01), viscous=(0.6, 0.01))
    dry = form("dry", 1.0, 0.5, ("coulomb_friction",), mu_k=(0.12, 0.001))
    qs, specific = quantities_over(pendulum_rig, [hybrid, dry], {})
    level = 0.13 - 0.6 * 0.1 / (pendulum_rig.shaft_radius * load)
    assert qs["mu_k"].by_form["hybrid"][0] == pytest.approx(level)
    assert qs["viscous"].by_form["dry"] == (0.0, 0.0)
    assert qs["mu_s"].by_form["dry"] == (0.12, 0.001)
    assert "stribeck_velocity" not in qs and specific["hybrid"]["stribeck_velocity"] == 0.1


def test_a_quantity_no_form_pins_down_is_not_determined_with_its_range(pendulum_rig):
    fits = [form("a", 0.0, 0.6, ("coulomb_friction", "viscous_friction"), mu_k=(0.1, 0.001), viscous=(0.5, None)),
            form("b", 2.0, 0.4, ("coulomb_friction", "viscous_friction"), mu_k=(0.1, 0.001), viscous=(2.0, 0.1))]
    q = quantities_over(pendulum_rig, fits, {})[0]["viscous"]
    assert not q.determined
    petroff = plausible_range("viscous", pendulum_rig)
    assert (q.low, q.high) == (0.0, petroff[1])  # the forms' 0.5 and 2.0 within what is plausible


def test_the_stated_error_is_as_wide_as_the_interval_a_form_within_the_margin_holds_open(pendulum_rig):
    """The selected form lacks drag (0 there, no error) with 90 % of the weight; a form within the
    margin has 0.01 +- 0.004. The interval holds that form's own (to 0.0178); the stated 1-sigma is
    the interval's half-width over 1.96, not the average's 0.0033, so the estimate +- 1.96 stated
    errors says what the interval says (the air-drag record 71001 read 0.00006 +- 0.00075 beside
    an interval [0, 0.0099] that held the truth's 0.0043)."""
    fits = [form("selected", 0.0, 0.9, ("coulomb_friction", "viscous_friction"), mu_k=(0.1, 0.001)),
            form("+ drag", 4.4, 0.1, ("coulomb_friction", "viscous_friction", "aerodynamic_drag"), mu_k=(0.1, 0.001),
                 drag=(0.01, 0.004))]
    q = quantities_over(pendulum_rig, fits, {})[0]["drag"]
    sd = math.sqrt(0.1 * (0.004**2 + 0.009**2) + 0.9 * 0.001**2)  # the unconditional one
    assert q.high == pytest.approx(0.01 + Z95 * 0.004) and q.low == 0.0
    assert q.stderr == pytest.approx((q.high - q.low) / (2 * Z95)) and q.stderr > 1.3 * sd


def test_a_profile_that_lets_a_form_s_parameter_further_widens_every_quantity(pendulum_rig):
    """A drifting form within the margin whose profile keeps drifts to +-0.003 /s (stated +-0.0009),
    with viscous 0.47 and 0.70 at its ends: the drift's, viscous's and mu_k's intervals hold the ends,
    and their stated errors are the intervals' half-widths over 1.96."""
    sel = form("selected", 0.0, 0.9, ("coulomb_friction", "viscous_friction"), mu_k=(0.110, 0.0001),
               viscous=(0.58, 0.004))
    drift = form("drifting", 6.4, 0.1, ("coulomb_friction", "viscous_friction", "drifting_coulomb_friction"),
                 mu_k=(0.110, 0.001), viscous=(0.58, 0.018), mu_k_drift=(0.0, 0.00044))
    drift.fit.parameters["mu_k_drift"] = Parameter("mu_k_drift", 0.0, -0.01, 0.01, True, "1/s", stderr=0.00044)
    drift.profiles = [Profile("mu_k_drift", (-0.00086, 0.00086), -0.003, 0.003,
                              [{"mu_k_drift": -0.003, "viscous": 0.47, "mu_k": 0.119},
                               {"mu_k_drift": 0.003, "viscous": 0.70, "mu_k": 0.100}])]
    assert drift.profiles[0].wider
    before = quantities_over(pendulum_rig, [sel, form("drifting", 6.4, 0.1, drift.fit.effects, mu_k=(0.110, 0.001),
                                                       viscous=(0.58, 0.018), mu_k_drift=(0.0, 0.00044))], {})[0]
    qs = quantities_over(pendulum_rig, [sel, drift], {})[0]
    assert before["viscous"].high < 0.63  # without the profile: the drifting record 84000's truth was out
    assert (qs["mu_k_drift"].low, qs["mu_k_drift"].high) == pytest.approx((-0.003, 0.003))
    assert qs["viscous"].low == pytest.approx(0.47) and qs["viscous"].high == pytest.approx(0.70)
    assert qs["mu_k"].low == pytest.approx(0.100) and qs["mu_k"].high == pytest.approx(0.119)
    for q in qs.values():
        assert q.stderr == pytest.approx((q.high - q.low) / (2 * Z95))


def test_a_form_the_record_does_not_resolve_is_named_only_where_it_moves_a_stated_value(pendulum_rig):
    """A drifting form within the margin whose drift's profile reaches +-0.003 /s (stated +-0.0009) and
    moves viscous from the final fit's 0.58 +- 0.004 to 0.47 and 0.70 is named with viscous's and mu_k's
    model-form intervals; the same form with a profile no wider than stated, or one whose ends leave
    every stated value within 1.96 of its errors, is not."""
    from vcbmodel.analysis.diagnosis.judge import unresolved_forms
    from vcbmodel.analysis.model_forms import ModelForms

    def forms_with(low, high, ends):
        sel = form("selected", 0.0, 0.9, ("coulomb_friction", "viscous_friction"), mu_k=(0.110, 0.0001),
                   viscous=(0.58, 0.004))
        drift = form("drifting", 6.4, 0.1, ("coulomb_friction", "viscous_friction", "drifting_coulomb_friction"),
                     mu_k=(0.110, 0.001), viscous=(0.58, 0.018), mu_k_drift=(0.0, 0.00044))
        drift.profiles = [Profile("mu_k_drift", (-0.0009, 0.0009), low, high, ends)]
        return sel.fit, ModelForms([sel, drift], quantities_over(pendulum_rig, [sel, drift], {})[0])

    far = [{"mu_k_drift": -0.003, "viscous": 0.47, "mu_k": 0.119}, {"mu_k_drift": 0.003, "viscous": 0.70, "mu_k": 0.100}]
    final, forms = forms_with(-0.003, 0.003, far)
    named = unresolved_forms(pendulum_rig, final, forms, 1.96)
    assert [(u["form"], u["parameter"], u["profile"]) for u in named] == [("drifting", "mu_k_drift", [-0.003, 0.003])]
    assert named[0]["values"]["viscous"] == pytest.approx([forms.quantities["viscous"].low, forms.quantities["viscous"].high])
    assert set(named[0]["values"]) == {"mu_k", "viscous"}
    assert unresolved_forms(pendulum_rig, *forms_with(-0.0009, 0.0009, far), 1.96) == []  # resolved
    near = [{"mu_k_drift": -0.003, "viscous": 0.585, "mu_k": 0.1101}, {"mu_k_drift": 0.003, "viscous": 0.575, "mu_k": 0.1099}]
    assert unresolved_forms(pendulum_rig, *forms_with(-0.003, 0.003, near), 1.96) == []  # moves nothing stated


def _weighed_forms(rig, implausible_bic):
    """The selected form (BIC 100) and one with a viscous coefficient 1000 times its plausible range
    at ``implausible_bic``, weighed as fit_forms weighs them."""
    effects = ("coulomb_friction", "viscous_friction")
    fits = [form("selected", 0.0, 0.0, effects, mu_k=(0.10, 0.001), viscous=(0.5, 0.01)),
            form("+ huge viscous", 0.0, 0.0, effects, mu_k=(0.10, 0.001),
                 viscous=(1000.0 * plausible_range("viscous", rig)[1], 0.01))]
    for f, bic in zip(fits, (100.0, implausible_bic)):
        f.bic, f.fit.rms = bic, 1e-3
    not_tried = {}
    _weigh(rig, fits, not_tried)
    return ModelForms(fits, {}, not_tried), fits


def test_a_form_with_an_implausible_value_stays_implausible_where_every_form_is_weighed(pendulum_rig):
    """20 BIC ahead of the only plausible form, the implausible one is weighed (no plausible form fits
    as well) but keeps plausible False, in the JSON and the report too; 5 BIC ahead, it gets no weight."""
    forms, (selected, huge) = _weighed_forms(pendulum_rig, 80.0)
    assert selected.plausible and selected.weighed
    assert huge.weighed and not huge.plausible
    assert huge.weight > 0.99 and huge.within_margin and forms.preferred is huge
    assert "plausible forms" in forms.not_tried
    rows = {r["form"]: r for r in forms.to_json()["forms"]}
    assert (rows["+ huge viscous"]["plausible"], rows["+ huge viscous"]["weighed"]) == (False, True)
    assert (rows["selected"]["plausible"], rows["selected"]["weighed"]) == (True, True)
    assert "implausible values, weighed" in forms.report()
    forms, (selected, huge) = _weighed_forms(pendulum_rig, 95.0)
    assert not huge.plausible and not huge.weighed and huge.weight == 0.0 and not huge.within_margin
    assert selected.weight == 1.0 and forms.preferred is selected and "plausible forms" not in forms.not_tried
    assert "implausible values: no weight" in forms.report()


def test_the_forms_tried_on_a_pendulum_and_why_none_on_a_cam_drop():
    alts, skipped = alternatives(("coulomb_friction", "viscous_friction"), "pendulum")
    labels = {a.label for a in alts}
    assert {"hybrid + stribeck", "tustin + stribeck", "gaussian + stribeck", "drifting"} <= labels
    tustin = next(a for a in alts if a.form == "tustin")
    assert tustin.effects == ("coulomb_friction", "viscous_friction", "stribeck", "tustin_friction")
    assert "friction forms" not in skipped
    alts, skipped = alternatives(("coulomb_friction", "stribeck", "tustin_friction"), "pendulum")
    assert {a.form for a in alts} >= {"gaussian", "drifting"} and "tustin" not in {a.form for a in alts}
    assert alternatives(("coulomb_friction",), "cam_drop")[0] == []
    assert "friction forms" in alternatives(("coulomb_friction",), "cam_drop")[1]


def test_a_model_is_tried_with_the_decay_effects_it_lacks_beside_or_instead_of_its_partner(pendulum_rig):
    best = form("tustin", 0.0, 1.0, ("coulomb_friction", "stribeck", "tustin_friction", "aerodynamic_drag"),
                mu_k=(0.1, 0.001))
    added = [a for a in added_effects(best, "pendulum") if a.added]
    assert [(a.added, a.removed) for a in added] == [(("viscous_friction",), ()),
                                                     (("viscous_friction",), ("aerodynamic_drag",))]
    assert added[0].effects[-1] == "viscous_friction" and "tustin_friction" in added[0].effects
    assert "aerodynamic_drag" not in added[1].effects
    # a cam drop's forms: the drive's dissipation as viscous friction or the springs' internal damping
    assert {a.added for a in added_effects(best, "cam_drop")} == {("viscous_friction",), ("spring_damping",)}
    without = added_effects(form("hybrid", 0.0, 1.0, ("coulomb_friction", "stribeck", "viscous_friction"),
                                 mu_k=(0.1, 0.001)), "pendulum")[0]
    assert without.removed == ("stribeck",) and without.effects == ("coulomb_friction", "viscous_friction")
    assert added_effects(best, "pendulum")[0].effects == ("coulomb_friction", "aerodynamic_drag")  # Tustin needs it


def test_a_tustin_pendulum_is_covered_by_the_model_forms_where_the_hybrid_law_is_not(tmp_path):
    """The realism study's Tustin pendulum (seed 31002, clean): the registered search's best is the
    hybrid law with air drag standing in for the Tustin curve, at a drag no paddle has, so the verdict
    is "not explained" and says why; its mu_k misses the truth's by many stated errors. The Tustin
    form (viscous friction for the drag) wins the model forms with all the weight, and their interval
    holds the truth's kinetic level, its level at rest and its viscous coefficient. (Deterministic:
    equal candidates are both fitted, whichever finishes first.)"""
    _, meas_path, truth = realistic_record("pend_visc", 31002, tmp_path, friction_truth="tustin")
    rig, meas = load_pair(meas_path)
    d = diagnose(rig, meas, verbose=False)
    j = d.to_json()
    tv = truth["truth_friction"]
    assert not j["explained"] and "aerodynamic_drag" in j["missing_effects"]
    assert any(f["parameter"] == "drag" and f["kind"] == "outside" for f in j["verdict"]["implausible"])
    assert abs(j["fitted"]["mu_k"] - tv["mu_k"]) / j["stderr"]["mu_k"] > 5  # the selected law alone misses
    forms = j["model_forms"]
    best = min(forms["forms"], key=lambda f: f["delta_bic"])
    assert best["form"].startswith("tustin") and "viscous_friction" in best["effects"] and best["weight"] > 0.9
    q = forms["quantities"]
    for name, value in (("mu_k", tv["mu_k"]), ("mu_s", tv["mu_s"]), ("viscous", tv["viscous"])):
        assert q[name]["low"] <= value <= q[name]["high"], (name, value, q[name])
        assert q[name]["determined"]
    assert q["mu_k"]["high"] - q["mu_k"]["low"] < 0.1 * tv["mu_k"]  # and says something


def test_a_drifting_coulomb_level_is_found_and_covered(tmp_path):
    """A pendulum whose Coulomb level drifts by 0.0009 /s (the independent torque truth, 5 s): the hybrid
    law alone fits at the noise with mu_k over 20 stated errors off; the drifting form wins and its
    interval holds the drift and mu_k (the hybrid law, 8 BIC behind, is within the margin: zero drift
    stays inside the interval)."""
    _, meas_path, truth = realistic_record("pend_none", 6, tmp_path, friction_truth="drifting_coulomb", t_end=5.0)
    rig, meas = load_pair(meas_path)
    j = diagnose(rig, meas, verbose=False).to_json()
    tv, q = truth["truth_friction"], j["model_forms"]["quantities"]
    assert abs(j["fitted"]["mu_k"] - tv["mu_k"]) / j["stderr"]["mu_k"] > 20
    for name in ("mu_k", "viscous", "mu_k_drift"):
        assert q[name]["low"] <= tv[name] <= q[name]["high"], (name, tv[name], q[name])
    best = min(j["model_forms"]["forms"], key=lambda f: f["delta_bic"])
    assert best["form"] == "drifting" and q["mu_k_drift"]["estimate"] > 0.5 * tv["mu_k_drift"]


def test_a_drift_the_laboratory_record_does_not_resolve_is_said_and_held_by_the_intervals(tmp_path):
    """The realism study's laboratory record 84000 (an encoder's 0.09 deg steps, a clock 0.29 % fast,
    the rig's period 3.5 % off, a hand start, a gain 2.9 % low; a Coulomb level drifting by +0.00133
    /s): explained at the noise, with the selected fit's viscous 12 stated errors off. The drifting form
    stated its drift 0.0000 +- 0.0004 and the forms' intervals missed the truth's drift and viscous;
    held at the truth's drift, the record's chi^2 rises by 2. The drift's profile says the record does
    not resolve it, and the intervals hold the truth's drift, viscous and mu_k, each within 3 of its
    stated errors."""
    from vcbmodel.analysis.realistic import GROUPS
    _, meas_path, truth = realistic_record("pend_none", 84000, tmp_path, GROUPS["lab"][0],
                                           friction_truth="drifting_coulomb")
    rig, meas = load_pair(meas_path)
    d = diagnose(rig, meas, verbose=False, processes=1)
    j = d.to_json()
    tv, q = truth["truth_friction"], j["model_forms"]["quantities"]
    assert j["explained"] and abs(j["fitted"]["viscous"] - tv["viscous"]) / j["stderr"]["viscous"] > 5
    drifting = next(f for f in j["model_forms"]["forms"] if f["form"] == "drifting")
    pr = next(p for p in drifting["profiles"] if p["parameter"] == "mu_k_drift")
    assert pr["wider"] and pr["profile"][1] > tv["mu_k_drift"] > pr["stated"][1]
    for name in ("mu_k", "viscous", "mu_k_drift"):
        assert q[name]["low"] <= tv[name] <= q[name]["high"], (name, tv[name], q[name])
        assert abs(q[name]["estimate"] - tv[name]) <= 3 * q[name]["stderr"], (name, tv[name], q[name])
    assert "does not resolve mu_k_drift" in d.report()
    # the verdict stands (the residual is at the noise) and names the form the values rest on
    unresolved = j["verdict"]["unresolved_forms"]
    assert [(u["form"], u["parameter"]) for u in unresolved] == [("drifting", "mu_k_drift")]
    low, high = unresolved[0]["values"]["viscous"]
    assert low <= tv["viscous"] <= high and not abs(j["fitted"]["viscous"] - tv["viscous"]) <= Z95 * j["stderr"]["viscous"]
    assert "the final values rest on it, read them from the model forms" in j["evidence"]


def test_identify_reports_the_forms_in_text_and_json(pendulum_rig, tmp_path):
    """On a 4 s record of the hybrid law itself the forms' shapes between rest and sliding are not told
    apart (the hybrid law within the margin), but they agree on the kinetic level, and the interval
    holds the truth's."""
    from vcbmodel.analysis.synthetic import synthetic_measurement
    truth = {"mu_k": 0.12, "mu_s": 0.2, "stribeck_velocity": 0.1, "viscous": 0.5, "stick_velocity": 1e-3}
    meas = synthetic_measurement(pendulum_rig, ("coulomb_friction", "stribeck", "viscous_friction"), truth, seed=4,
                                 t_end=4.0)
    r = identify([(pendulum_rig, meas)], verbose=False)
    j = r.to_json()["model_forms"]
    within = {f["form"]: f["within_margin"] for f in j["forms"]}
    assert within["hybrid"]
    level = 0.12 - 0.5 * 0.1 / (pendulum_rig.shaft_radius * pendulum_rig.pendulum.mass * pendulum_rig.gravity)
    q = j["quantities"]["mu_k"]
    assert q["low"] <= level <= q["high"] and q["high"] - q["low"] < 0.02 * level
    assert "Model forms the record cannot tell apart" in r.report()
    assert np.isfinite(q["stderr"])


def test_a_fall_with_a_free_exponent_is_tried_and_its_exponent_is_not_averaged_over_forms(pendulum_rig):
    """A Stribeck fall slower than Tustin's (exp(-(w/w_s)^0.5): its tail reaches through a swing's speeds) is
    in none of the other forms; fitted without it, held-out pendulums of that truth got forms' intervals 4-55
    errors from the truth, one explained. The power form is tried beside Tustin's and the Gaussian; its
    exponent, like w_s, means something else in each form and is reported per form, never averaged."""
    alts, _ = alternatives(("coulomb_friction", "viscous_friction"), "pendulum")
    power = next(a for a in alts if a.form == "power")
    assert power.effects == ("coulomb_friction", "viscous_friction", "stribeck", "power_stribeck_friction")
    fits = [form("selected (hybrid)", 0.0, 0.6, ("coulomb_friction", "viscous_friction"), mu_k=(0.12, 0.001),
                 viscous=(0.6, 0.01)),
            form("power", 1.0, 0.4, ("coulomb_friction", "viscous_friction", "stribeck", "power_stribeck_friction"),
                 mu_k=(0.11, 0.001), mu_s=(0.2, 0.01), viscous=(0.65, 0.01), stribeck_velocity=(0.1, 0.01),
                 stribeck_exponent=(0.5, 0.05))]
    quantities, specific = quantities_over(pendulum_rig, fits, {})
    assert "stribeck_exponent" not in quantities and specific["power"]["stribeck_exponent"] == 0.5
    assert quantities["mu_k"].low <= 0.11 - Z95 * 0.001 and quantities["mu_k"].high >= 0.12 + Z95 * 0.001


@pytest.mark.slow
def test_a_square_root_stribeck_fall_is_not_explained_with_wrong_numbers(tmp_path):
    """A held-out pendulum whose Stribeck fall has exponent 0.5 (the independent truth, 6 s, 0.5 mrad white
    noise; the draws of the audit's validation seed 103, a seed not used to design the power form), started from
    Coulomb friction alone. Without the power form the diagnosis said "explained" with the forms' mu_k and
    viscous 17 and 55 stated errors from the truth. Now: an explained verdict carries no form value more than 3
    stated errors from the truth, and the forms' interval holds the truth's kinetic level and level at rest."""
    import copy
    import json

    from vcbmodel import parameters as P
    from vcbmodel.records.measurement import Measurement, write_measurement
    from vcbmodel.reference.truth_friction import truth_pendulum
    values = {"mu_k": 0.11563, "viscous": 0.55608, "mu_s": 0.21324, "stribeck_velocity": 0.13575,
              "stribeck_exponent": 0.5}
    rig = copy.deepcopy(P.REFERENCE_PENDULUM)
    rig["pendulum"]["initial_angle"] = math.radians(9.546)
    rig["model"]["effects"] = ["coulomb_friction"]
    (tmp_path / "sqrt.rig.json").write_text(json.dumps(rig))
    t = np.arange(0.0, 6.0 + 5e-4, 1e-3)
    theta = truth_pendulum("power", rig["pendulum"], rig["gravity"], rig["shaft"]["radius"], values, t)["theta"]
    noisy = theta + np.random.default_rng(103).normal(0.0, 5e-4, t.size)
    write_measurement(Measurement("", t, {"pendulum_angle": noisy}, ("SYNTHETIC: square-root Stribeck fall",)),
                      tmp_path / "sqrt.csv")
    rig_, meas = load_pair(tmp_path / "sqrt.csv")
    j = diagnose(rig_, meas, verbose=False).to_json()
    q = j["model_forms"]["quantities"]
    truth = {"mu_k": values["mu_k"], "mu_s": values["mu_s"], "viscous": values["viscous"]}
    if j["explained"]:
        for name, value in truth.items():
            assert abs(q[name]["estimate"] - value) <= 3 * q[name]["stderr"], (name, value, q[name])
    for name in ("mu_k", "mu_s"):
        assert q[name]["low"] <= truth[name] <= q[name]["high"], (name, truth[name], q[name])
    # identify on the same record: its residual is at the noise, but the records prefer a model form that
    # moves the law's values, and the warning says so (before, no warning with mu_k 11-228 errors off)
    r = identify([(rig_, meas)], verbose=False)
    assert r.rival_form is not None and r.warning and "fits the record better than the hybrid law" in r.warning
    assert r.to_json()["rival_form"]["form"] == r.rival_form["form"]

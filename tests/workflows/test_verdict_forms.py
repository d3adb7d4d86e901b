"""The verdict against the model forms (vcbmodel/analysis/diagnosis/judge.py: judge_forms): a
value the forms determine outside its plausible range refuses ``explained``, also where the final
fit's own error is too wide for the rival-form rule to fire."""
from types import SimpleNamespace

from vcbmodel.analysis.diagnosis.judge import judge_forms, rival_form
from vcbmodel.analysis.diagnosis.options import DEFAULT_OPTIONS
from vcbmodel.analysis.diagnosis.state import Verdict
from vcbmodel.analysis.fit import Parameter
from vcbmodel.analysis.model_forms import FormFit, ModelForms, _weigh, quantities_over


def _form(label, bic, effects, **values):
    params = {n: Parameter(n, v, 0.0, 10.0, True, "-", stderr=se) for n, (v, se) in values.items()}
    return FormFit(SimpleNamespace(label=label), SimpleNamespace(parameters=params, effects=tuple(effects)), bic)


def _judged(rig, final, rival):
    fits = [final, rival]
    _weigh(rig, fits, {})
    quantities, _ = quantities_over(rig, fits, {})
    forms = ModelForms(fits, quantities)
    verdict = Verdict(True, judgement=SimpleNamespace(at_noise=True, to_json=dict))
    judge_forms(SimpleNamespace(rig=rig, options=DEFAULT_OPTIONS), verdict, final.fit, forms)
    return verdict, forms


def test_an_implausible_value_over_the_forms_refuses_explained_where_the_rival_rule_does_not(cam_rig):
    """A cam drop's final fit (mu_k 0.05 +- 0.077: wide) and a form 41 BIC ahead with mu_k 0.006 +- 0.014
    (its 95 % reaches the plausible range [0.01, 0.6]: a plausible form): its move, 0.044, is 0.3 of
    the final fit's 1.96 errors, so the rival-form rule does not fire, but the forms put mu_k at 0.006,
    outside its range, with an interval narrower than the range: not explained, mu_k named (and mu_s,
    the level at rest, which is mu_k where no form has a Stribeck fall)."""
    effects = ("coulomb_friction",)
    final = _form("selected", 100.0, effects, mu_k=(0.05, 0.077))
    rival = _form("+ spring_damping", 59.0, effects + ("spring_damping",), mu_k=(0.006, 0.014))
    assert rival_form(cam_rig, final.fit, ModelForms([final, rival], {}), DEFAULT_OPTIONS) is None
    verdict, forms = _judged(cam_rig, final, rival)
    assert forms.quantities["mu_k"].determined and forms.quantities["mu_k"].estimate < 0.01
    assert not verdict.explained and verdict.rival_form is None
    assert [f["parameter"] for f in verdict.implausible_forms] == ["mu_k", "mu_s"]  # mu_s: the level at rest
    assert verdict.to_json()["implausible_forms"][0]["kind"] == "outside"
    # the same forms with the rival's mu_k inside the range: explained stays
    inside = _form("+ spring_damping", 59.0, effects + ("spring_damping",), mu_k=(0.03, 0.014))
    verdict, _ = _judged(cam_rig, _form("selected", 100.0, effects, mu_k=(0.05, 0.077)), inside)
    assert verdict.explained and verdict.implausible_forms == []

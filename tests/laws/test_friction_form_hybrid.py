"""The hybrid law as a friction form: the registry's reference (its law is the model's default)."""
from vcbmodel.laws.friction_forms import FORMS, FormLaw
from vcbmodel.laws.friction import NumericOps


def test_the_hybrid_form_is_the_default_law_with_no_effect_name_and_constant_values():
    form = FORMS["hybrid"]
    assert form.effect == "" and form.parameters == ()
    law = FormLaw("hybrid", mu_s=0.3, mu_k=0.1, stribeck_velocity=0.2, viscous=0.4)
    for w, t in ((0.0, 0.0), (0.5, 3.0), (-7.0, 10.0)):
        inst = law.at(w, t, NumericOps)
        assert (inst.mu_s, inst.mu_k, inst.stribeck_velocity, inst.viscous) == (0.3, 0.1, 0.2, 0.4)


def test_the_static_level_is_never_below_the_kinetic_one():
    assert FormLaw("hybrid", mu_s=0.05, mu_k=0.1).mu_s == 0.1

"""The friction forms' registry (vcbmodel/laws/friction_forms): a new form is one file plus its
test. Every registered form is run here on a pendulum by the compiled path and by the Exudyn model
(symbolic user functions), which must agree to 1e-9 rad; its level at rest and at speed must keep
the hybrid law's meaning (mu_s at rest, mu_k at speed); and it must have a test file of its own."""
import math
from pathlib import Path

import numpy as np
import pytest

from vcbmodel.experiments.simulation import simulate
from vcbmodel.laws.friction import FrictionLaw, NumericOps, shaft_friction
from vcbmodel.laws.friction_forms import FORMS, FormLaw, form_of_effect
from vcbmodel.model.effects import MACHINERY

HERE = Path(__file__).resolve().parent
BASE = ("coulomb_friction", "stribeck", "viscous_friction")
VALUES = {"mu_k": 0.1, "mu_s": 0.2, "stribeck_velocity": 0.1, "viscous": 0.05}


def form_values(form, scale=0.5):
    """The form's own values: ``scale`` of the way from its fit start to its upper bound."""
    return {p.name: p.initial + scale * (p.max - p.initial) for p in form.parameters}


def test_the_registry_holds_the_four_forms_and_each_effect_switches_one_on():
    assert {"hybrid", "tustin", "gaussian", "drifting"} <= set(FORMS)
    for form in FORMS.values():
        if form.effect:
            assert form_of_effect(form.effect) is form
            assert MACHINERY[form.effect].form is form


@pytest.mark.parametrize("name", sorted(FORMS))
def test_every_form_has_a_test_file_of_its_own(name):
    assert (HERE / f"test_friction_form_{name}.py").exists(), f"friction form {name!r} has no test file"


@pytest.mark.parametrize("name", sorted(f for f in FORMS if FORMS[f].effect))
def test_every_form_runs_the_same_on_the_compiled_path_and_in_exudyn(pendulum_rig, name):
    form = FORMS[name]
    effects = BASE + (form.effect,)
    values = {**VALUES, **form_values(form)}
    compiled = simulate(pendulum_rig, effects, values, t_end=3.0, backend="compiled")
    exudyn = simulate(pendulum_rig, effects, values, t_end=3.0, backend="exudyn")
    hybrid = simulate(pendulum_rig, BASE, VALUES, t_end=3.0, backend="compiled")
    assert compiled.info["backend"] != exudyn.info["backend"]
    assert np.max(np.abs(compiled.measured - exudyn.measured)) < 1e-9
    # and the form is not the hybrid law: the swing differs by far more than the agreement
    assert np.max(np.abs(compiled.measured - hybrid.measured)) > 1e-4


@pytest.mark.parametrize("name", sorted(FORMS))
def test_every_form_keeps_the_meaning_of_mu_s_at_rest_and_mu_k_at_speed(name):
    form = FORMS[name]
    law = FormLaw(name, mu_s=0.2, mu_k=0.1, stribeck_velocity=0.1, viscous=0.0, radius=0.02,
                  extra=tuple(p.initial for p in form.parameters))
    reaction = (0.0, 100.0, 0.0, 0.0)  # F_n = 100 N, no coupling to the acceleration
    fast = shaft_friction(20.0, 0.0, *reaction, 1.0, law, NumericOps, 0.0)[0]
    assert fast == pytest.approx(0.1 * 0.02 * 100.0, rel=1e-6)
    breakaway = shaft_friction(0.0, 10.0, *reaction, 1.0, law, NumericOps, 0.0)[0]  # cannot hold 10 N m
    assert breakaway == pytest.approx(0.2 * 0.02 * 100.0, rel=1e-9)


def test_a_form_with_the_hybrid_shape_gives_the_hybrid_law_exactly():
    rng = np.random.default_rng(3)
    plain = FrictionLaw(mu_s=0.2, mu_k=0.1, stribeck_velocity=0.1, viscous=0.05, radius=0.02)
    form = FormLaw("hybrid", mu_s=0.2, mu_k=0.1, stribeck_velocity=0.1, viscous=0.05, radius=0.02)
    for _ in range(200):
        w, tc = rng.uniform(-1, 1) * 10 ** rng.uniform(-4, 1), rng.uniform(-5, 5)
        args = (w, tc, 3.0, 480.0, 0.2, -1.5, 2.5)
        assert shaft_friction(*args, form, NumericOps, 1.0) == shaft_friction(*args, plain, NumericOps)


def test_an_unknown_form_and_two_forms_at_once_are_refused(pendulum_rig):
    with pytest.raises(ValueError, match="unknown friction form 'dahl'"):
        FormLaw("dahl")
    with pytest.raises(ValueError, match="two friction forms"):
        simulate(pendulum_rig, BASE + ("tustin_friction", "lugre_steady_friction"), VALUES, t_end=0.1)


def test_form_values_run_through_the_model_values_rule(pendulum_rig):
    r = simulate(pendulum_rig, BASE + ("drifting_coulomb_friction",), {**VALUES, "mu_k_drift": 0.003}, t_end=0.1)
    assert r.spec.friction_form == "drifting" and r.spec.form_values == (0.003,)
    assert math.isfinite(r.measured[-1])


@pytest.mark.parametrize("name", sorted(f for f in FORMS if FORMS[f].effect))
def test_every_form_runs_the_same_on_a_cam_drop(cam_rig, name):
    """The cam shaft's friction (eq. 13) in every form: the compiled path against Exudyn, 35 ms."""
    form = FORMS[name]
    effects = BASE + (form.effect,)
    values = {**VALUES, **form_values(form), "viscous": 0.5}
    compiled = simulate(cam_rig, effects, values, t_end=0.035, backend="compiled")
    exudyn = simulate(cam_rig, effects, values, t_end=0.035, backend="exudyn")
    assert np.max(np.abs(compiled.measured - exudyn.measured)) < 1e-9

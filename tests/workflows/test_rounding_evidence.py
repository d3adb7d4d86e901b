"""A rounded record's evidence counted honestly (vcbmodel/analysis/noise.py: rounding_bic): the model
forms' BIC counts a run of identical recorded values once, so a form that only follows the rounding
where the signal is slow is not preferred; and the verdict that a form the record prefers, moving a
stated value, makes the record not explained (vcbmodel/analysis/diagnosis/judge.py: rival_form)."""
import math
from types import SimpleNamespace

import numpy as np
import pytest

from vcbmodel.analysis.diagnosis.judge import rival_form
from vcbmodel.analysis.diagnosis.options import DEFAULT_OPTIONS
from vcbmodel.analysis.fit import FitResult, Parameter
from vcbmodel.analysis.fit.dataset import AlignedModel
from vcbmodel.analysis.model_forms import EVIDENCE_MARGIN, FormFit, ModelForms, _weigh
from vcbmodel.analysis.noise import NoiseModel, rounding_bic, rounding_weights, run_lengths

Q = 1.45e-3  # a 12-bit logger's step over 340 degrees (rad)
T = np.arange(6000) / 1000.0
#: a decaying swing, slow near its turning points: runs of up to ~70 identical rounded values
SWING = 0.17 * np.exp(-0.15 * T) * np.cos(2 * np.pi * T / 1.2)


def fit_of(model, record, n_varied):
    """A FitResult of ``model`` against ``record`` (residual model - record) with ``n_varied`` values."""
    params = {f"p{i}": Parameter(f"p{i}", 1.0) for i in range(n_varied)}
    sim = AlignedModel(T, np.asarray(model, float), {}, "pendulum")
    return FitResult((), None, params, [np.asarray(model - record, float)], [sim], Q / math.sqrt(12), times=[T])


def test_run_lengths_count_identical_recorded_values():
    y = np.array([0.0, 0.0, 0.0, 1.0, 1.0, 0.0, 2.0]) * Q
    assert run_lengths(y, Q).tolist() == [3, 3, 3, 2, 2, 1, 1]
    assert run_lengths(y, 0.0).tolist() == [1] * 7


def test_without_quantisation_it_is_the_plain_bic_exactly():
    """q = 0 (an analogue sensor), with AR noise: the same number as FitResult.bic_with."""
    rng = np.random.default_rng(1)
    record = SWING + rng.normal(0, 5e-4, T.size)
    fit = fit_of(SWING, record, 5)
    noise = NoiseModel(5e-4, (0.3, 0.1), 0.0, 5e-4)
    assert rounding_bic(fit, noise) == fit.bic_with(noise)
    assert rounding_bic(fit, None) == fit.bic_with(None)


def test_with_every_run_one_sample_long_it_is_the_plain_bic():
    """A quantised record whose every sample takes a new value (a fast ramp): nothing is counted twice."""
    record = np.round(np.linspace(0, 6000 * 2 * Q, T.size) / Q) * Q
    fit = fit_of(record + 1e-4, record, 3)
    noise = NoiseModel.white(Q / math.sqrt(12), Q)
    assert run_lengths(record, Q).max() == 1
    assert rounding_bic(fit, noise) == pytest.approx(fit.bic_with(noise), rel=1e-12)


def test_a_form_that_only_follows_the_rounding_at_low_speed_is_not_preferred():
    """The true swing against one that bends towards the rounded value wherever the swing is slower
    than 0.05 rad/s (two more parameters): the plain BIC prefers the bending one by over 300, the
    rounding-aware one does not prefer it by the evidence margin. A real model error (an offset of 1.5
    steps over a second) still shows by thousands."""
    record = np.round(SWING / Q) * Q
    noise = NoiseModel.white(Q / math.sqrt(12), Q)
    true = fit_of(SWING, record, 5)
    speed = np.gradient(SWING, T)
    bend = SWING + (record - SWING) * np.exp(-(speed / 0.05) ** 2)
    bending = fit_of(bend, record, 7)
    assert true.bic_with(noise) - bending.bic_with(noise) > 300
    assert rounding_bic(true, noise) - rounding_bic(bending, noise) < EVIDENCE_MARGIN
    wrong = fit_of(SWING + 1.5 * Q * ((T > 2) & (T < 3)), record, 5)
    assert rounding_bic(wrong, noise) - rounding_bic(true, noise) > 1000


def test_dithered_rounding_is_counted_as_the_plain_bic_and_partly_dithered_in_between():
    """Sensor noise of two steps before the rounding makes it white (Widrow & Kollar): the two
    measures agree on the difference between the true swing and a 2 % amplitude error. With a third of
    a step of noise the rounding-aware count lies between the plain one and the count of fully
    correlated runs (each run once)."""
    def difference(level, high_frequency):
        rng = np.random.default_rng(3)
        record = np.round((SWING + rng.normal(0, level, T.size)) / Q) * Q
        noise = NoiseModel(math.hypot(level, Q / math.sqrt(12)), (), Q, high_frequency)
        true, off = fit_of(SWING, record, 5), fit_of(1.02 * SWING, record, 5)
        return off.bic_with(noise) - true.bic_with(noise), rounding_bic(off, noise) - rounding_bic(true, noise)

    plain, honest = difference(2 * Q, math.hypot(2 * Q, Q / math.sqrt(12)))
    assert plain > 100 and honest == pytest.approx(plain, rel=1e-6)
    level = Q / 3
    plain, honest = difference(level, math.hypot(level, Q / math.sqrt(12)))
    _, runs_once = difference(level, Q / math.sqrt(12))  # no other noise seen: every run counted once
    assert runs_once < 0.6 * plain and runs_once < honest < plain
    assert rounding_weights(np.array([0.0, 0.0, Q]), Q, 0.0).tolist() == [0.5, 0.5, 1.0]


def _form(label, bic, effects, **values):
    params = {n: Parameter(n, v, 0.0, 10.0, True, "-", stderr=se) for n, (v, se) in values.items()}
    return FormFit(SimpleNamespace(label=label), SimpleNamespace(parameters=params, effects=tuple(effects)), bic)


def test_a_form_the_record_prefers_that_moves_a_stated_value_makes_it_not_explained(pendulum_rig):
    """The final model (Coulomb + viscous) and a form 20 BIC better: with viscous moved by 5 stated
    errors the verdict rule names it; moved by 1 error, or better by only 8 BIC, it does not."""
    effects = ("coulomb_friction", "viscous_friction")
    final = _form("selected", 100.0, effects, mu_k=(0.10, 0.001), viscous=(0.50, 0.01))
    rival = _form("+ drag", 80.0, effects, mu_k=(0.10, 0.001), viscous=(0.45, 0.01))
    found = rival_form(pendulum_rig, final.fit, ModelForms([final, rival], {}), DEFAULT_OPTIONS)
    assert found["form"] == "+ drag" and found["delta_bic"] == pytest.approx(20.0)
    assert [m["parameter"] for m in found["moved"]] == ["viscous"]
    assert found["moved"][0]["errors"] == pytest.approx(-5.0)
    assert "+ drag" in found["message"] and "viscous" in found["message"]
    near = _form("+ drag", 80.0, effects, mu_k=(0.10, 0.001), viscous=(0.49, 0.01))
    assert rival_form(pendulum_rig, final.fit, ModelForms([final, near], {}), DEFAULT_OPTIONS) is None
    close = _form("+ drag", 92.0, effects, mu_k=(0.10, 0.001), viscous=(0.45, 0.01))
    assert rival_form(pendulum_rig, final.fit, ModelForms([final, close], {}), DEFAULT_OPTIONS) is None
    # a form with a value outside its plausible range refuses nothing, also where the forms' weights
    # count it (model_forms weighs every form when none fits as well as an implausible one)
    implausible = _form("+ drag", 80.0, effects, mu_k=(0.10, 0.001), viscous=(500.0, 0.01))
    _weigh(pendulum_rig, [final, implausible], {})
    assert implausible.weighed and not implausible.plausible
    assert rival_form(pendulum_rig, final.fit, ModelForms([final, implausible], {}), DEFAULT_OPTIONS) is None
    found = rival_form(pendulum_rig, final.fit, ModelForms([final, implausible, rival], {}), DEFAULT_OPTIONS)
    assert found["form"] == "+ drag" and found["moved"][0]["form_value"] == pytest.approx(0.45)

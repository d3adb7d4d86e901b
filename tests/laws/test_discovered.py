"""The discovered-torque law (vcbmodel.laws.discovered): each library term at fixed numbers, the
same values through every ops namespace, the sum, and refusal of a name the library lacks."""
import math

import numpy as np
import pytest

from vcbmodel.laws.discovered import (HARMONICS, SIGN_EXP_SPEEDS, TERMS, WINDOW_CENTRES_DEG, WINDOW_KAPPA,
                                      discovered_torque, term)
from vcbmodel.laws.friction import ArrayOps, NumericOps


def test_terms_at_fixed_numbers():
    t, th, w = 2.0, 0.3, -1.5
    expected = {"w_abs_w": -2.25, "w3": -3.375, "theta": 0.3, "theta3": 0.027, "time": 2.0, "constant": 1.0}
    expected.update({f"sign_exp_{v:g}": -math.exp(-1.5 / v) for v in SIGN_EXP_SPEEDS})
    expected.update({f"sin_{k}theta": math.sin(k * th) for k in HARMONICS})
    expected.update({f"cos_{k}theta": math.cos(k * th) for k in HARMONICS})
    expected.update({f"rub_{c}deg": -math.exp(WINDOW_KAPPA * (math.cos(th - math.radians(c)) - 1.0))
                     for c in WINDOW_CENTRES_DEG})  # sign(w) = -1
    assert set(expected) == set(TERMS)
    for name, value in expected.items():
        assert term(name).value(t, th, w, NumericOps) == pytest.approx(value, rel=1e-12, abs=1e-15), name


def test_array_ops_give_the_numeric_values_sample_by_sample():
    rng = np.random.default_rng(0)
    t, th, w = rng.uniform(0, 5, 50), rng.uniform(-1, 1, 50), rng.uniform(-4, 4, 50)
    for name, tm in TERMS.items():
        arr = np.broadcast_to(np.asarray(tm.value(t, th, w, ArrayOps), float), t.shape)
        one = [tm.value(a, b, c, NumericOps) for a, b, c in zip(t, th, w)]
        np.testing.assert_allclose(arr, one, rtol=1e-13, atol=1e-15, err_msg=name)


def test_speed_terms_oppose_nothing_at_rest_and_are_odd_in_speed():
    for name in ("w_abs_w", "w3", *(f"sign_exp_{v:g}" for v in SIGN_EXP_SPEEDS), *(f"rub_{c}deg" for c in WINDOW_CENTRES_DEG)):
        f = term(name).value
        assert f(0.0, 0.2, 0.0, NumericOps) == 0.0
        assert f(0.0, 0.2, 0.7, NumericOps) == pytest.approx(-f(0.0, 0.2, -0.7, NumericOps))


def test_the_torque_is_the_sum_of_coefficient_times_term():
    terms = (("w_abs_w", -0.01), ("sin_2theta", 0.5), ("constant", 0.2))
    got = discovered_torque(1.0, 0.4, 2.0, terms, NumericOps)
    assert got == pytest.approx(-0.01 * 4.0 + 0.5 * math.sin(0.8) + 0.2)
    assert discovered_torque(1.0, 0.4, 2.0, (), NumericOps) == 0.0


def test_an_unknown_term_is_refused_naming_the_known_ones():
    with pytest.raises(ValueError, match="unknown discovered term 'w_squared'.*w_abs_w"):
        discovered_torque(0.0, 0.0, 1.0, (("w_squared", 1.0),), NumericOps)


def test_every_term_has_a_unit_and_a_physical_reading():
    for name, tm in TERMS.items():
        assert tm.name == name and tm.unit and len(tm.reading) > 20

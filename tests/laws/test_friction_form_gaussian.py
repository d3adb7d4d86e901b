"""The LuGre steady-state (Gaussian Stribeck) form against the independent truth's level g(w)
(vcbmodel/reference/truth_friction.py)."""
import pytest

from vcbmodel.laws.friction import ArrayOps, NumericOps
from vcbmodel.laws.friction_forms import FORMS, FormLaw
from vcbmodel.reference.truth_friction import lugre_level
import numpy as np


def test_the_level_is_lugres_steady_state():
    law = FormLaw("gaussian", mu_s=0.25, mu_k=0.13, stribeck_velocity=0.12, viscous=0.6)
    for w in (-2.0, -0.1, 1e-3, 0.05, 0.12, 0.5, 3.0):
        assert law.at(w, 0.0, NumericOps).mu_k == pytest.approx(lugre_level(w, 0.25, 0.13, 0.12), rel=1e-12)


def test_the_level_over_an_array_is_the_same_as_one_by_one():
    law = FormLaw("gaussian", mu_s=0.25, mu_k=0.13, stribeck_velocity=0.12)
    w = np.linspace(-1, 1, 41)
    assert np.allclose(law.at(w, 0.0, ArrayOps).mu_k, [law.at(x, 0.0, NumericOps).mu_k for x in w], rtol=1e-14)
    assert FORMS["gaussian"].needs == ("stribeck",)

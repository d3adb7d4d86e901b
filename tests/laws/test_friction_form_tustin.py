"""Tustin's exponential Stribeck form against the independent truth's coefficient and pendulum
(vcbmodel/reference/truth_friction.py: scipy, event-driven sticking, no import from the laws)."""
import math

import pytest

from conftest import offsets_from_independent_pendulum

from vcbmodel.laws.friction import NumericOps
from vcbmodel.laws.friction_forms import FormLaw
from vcbmodel.reference.truth_friction import tustin_coefficient

VALUES = {"mu_s": 0.25, "mu_k": 0.13, "stribeck_velocity": 0.12, "viscous": 0.6}


def test_the_level_is_tustins_curve():
    law = FormLaw("tustin", mu_s=0.25, mu_k=0.13, stribeck_velocity=0.12, viscous=0.6)
    for w in (-2.0, -0.1, 1e-3, 0.05, 0.12, 0.5, 3.0):
        inst = law.at(w, 0.0, NumericOps)
        assert inst.mu_k == pytest.approx(tustin_coefficient(w, 0.25, 0.13, 0.12), rel=1e-12)
        assert inst.stribeck_velocity == 0.0 and inst.viscous == 0.6  # the viscous term is not shifted


def test_a_tustin_model_follows_the_independent_tustin_pendulum(pendulum_rig):
    """The model with the form against the truth's own solve: within 0.1 mrad over 6 s (the stick
    band and the reaction's coupling differ in detail); the hybrid law with the same values is
    more than 20 times further off."""
    effects = ("coulomb_friction", "stribeck", "viscous_friction")
    off, hybrid_off = offsets_from_independent_pendulum(
        pendulum_rig, "tustin", VALUES, [effects + ("tustin_friction",), effects])
    assert off < 1e-4
    assert hybrid_off > 20 * off
    assert math.isfinite(off)

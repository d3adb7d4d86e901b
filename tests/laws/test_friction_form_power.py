"""The Stribeck fall with a free exponent against the independent truth's coefficient and pendulum
(vcbmodel/reference/truth_friction.py: scipy, event-driven sticking, no import from the laws)."""
import pytest

from conftest import offsets_from_independent_pendulum

from vcbmodel.laws.friction import NumericOps
from vcbmodel.laws.friction_forms import FormLaw
from vcbmodel.reference.truth_friction import power_coefficient, tustin_coefficient

VALUES = {"mu_s": 0.25, "mu_k": 0.13, "stribeck_velocity": 0.08, "viscous": 0.6, "stribeck_exponent": 0.5}


@pytest.mark.parametrize("d", [0.5, 1.0, 2.0])
def test_the_level_is_the_generalised_curve(d):
    law = FormLaw("power", mu_s=0.25, mu_k=0.13, stribeck_velocity=0.12, viscous=0.6, extra=(d,))
    for w in (-2.0, -0.1, 1e-3, 0.05, 0.12, 0.5, 3.0):
        inst = law.at(w, 0.0, NumericOps)
        assert inst.mu_k == pytest.approx(power_coefficient(w, 0.25, 0.13, 0.12, d), rel=1e-12)
        assert inst.stribeck_velocity == 0.0 and inst.viscous == 0.6
    if d == 1.0:  # Tustin's curve
        assert law.at(0.3, 0.0, NumericOps).mu_k == pytest.approx(tustin_coefficient(0.3, 0.25, 0.13, 0.12))
    if d == 2.0:  # the Gaussian form's curve
        gauss = FormLaw("gaussian", mu_s=0.25, mu_k=0.13, stribeck_velocity=0.12, viscous=0.6)
        assert law.at(0.3, 0.0, NumericOps).mu_k == pytest.approx(gauss.at(0.3, 0.0, NumericOps).mu_k, rel=1e-12)


def test_a_square_root_fall_follows_the_independent_pendulum(pendulum_rig):
    """The model with the form (d = 0.5: a fall whose tail reaches through the swing's speeds) against
    the truth's own solve: within 0.1 mrad over 6 s; Tustin's curve with the same values is more than
    10 times further off."""
    effects = ("coulomb_friction", "stribeck", "viscous_friction")
    off, tustin_off = offsets_from_independent_pendulum(
        pendulum_rig, "power", VALUES, [effects + ("power_stribeck_friction",), effects + ("tustin_friction",)])
    assert off < 1e-4
    assert tustin_off > 10 * off

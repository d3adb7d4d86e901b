"""The Hertz / Lankarani-Nikravesh contact law (groundwork for the whole-breaker model)."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from vcbmodel.laws.contact import hertz_contact_force


def bounce(mass, stiffness, restitution, v0, exponent=1.5):
    """A mass hitting a flat at v0: returns the rebound speed and the peak penetration."""
    def rhs(t, y):
        x, v = y  # x: penetration, v: its rate
        return [v, -hertz_contact_force(x, v, stiffness, restitution, v0, exponent) / mass]
    leave = lambda t, y: y[0] if t > 0 else 1.0  # noqa: E731
    leave.terminal, leave.direction = True, -1
    sol = solve_ivp(rhs, (0, 1.0), [0.0, v0], events=leave, rtol=1e-10, atol=1e-14, max_step=1e-6)
    return -sol.y[1, -1], float(np.max(sol.y[0]))


def test_no_force_without_penetration_and_never_pulling():
    assert hertz_contact_force(-1e-6, -1.0, 1e9, 0.8, 1.0) == 0.0
    assert hertz_contact_force(1e-6, -100.0, 1e9, 0.1, 0.1) == 0.0  # fast separation: clipped, not tension
    assert hertz_contact_force(1e-4, 0.0, 1e9, 0.8, 1.0) == pytest.approx(1e9 * 1e-6)


def test_elastic_impact_conserves_energy_and_matches_hertz_peak():
    m, K, v0 = 0.5, 5e9, 1.2
    v1, peak = bounce(m, K, 1.0, v0)
    assert v1 == pytest.approx(v0, rel=1e-6)
    # Hertz: 0.5 m v0^2 = K delta^2.5 / 2.5
    assert peak == pytest.approx((1.25 * m * v0**2 / K) ** 0.4, rel=1e-6)


@pytest.mark.parametrize("e", [0.95, 0.9, 0.8])
def test_damping_gives_the_coefficient_of_restitution(e):
    v1, _ = bounce(0.5, 5e9, e, 1.2)
    # the law is derived for e near 1: measured 0.954 / 0.913 / 0.847 for e = 0.95 / 0.9 / 0.8
    assert v1 / 1.2 == pytest.approx(e, abs=0.05)
    assert v1 / 1.2 >= e

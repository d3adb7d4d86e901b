"""Layer 2: the lumped closing-spring models (paper eq. 7-8, generalised)."""
import math

import numpy as np
import pytest

from vcbmodel.laws.springs import chain_frequencies, fixed_fixed_frequencies, lumped_chain, string_frequencies

K0, M0, L0 = 24230.0, 0.3364, 0.30


def test_paper_two_mass_values_eq_7_8():
    c = lumped_chain(2, K0, M0, L0, "paper")
    k1, k2, k3 = c.stiffnesses
    assert k1 == pytest.approx(k3)
    assert 2 / k1 + 1 / k2 == pytest.approx(1 / K0)  # eq. 7
    w = c.natural_frequencies()
    assert w[0] == pytest.approx(math.sqrt(k1 / c.masses[0]))  # eq. 8
    assert w[0] == pytest.approx(math.sqrt(4 * K0 / M0))
    assert w[1] == pytest.approx(math.sqrt((2 * k2 + k1) / c.masses[0]))
    assert w[1] == pytest.approx(math.sqrt(16 * K0 / M0))
    assert k1 == pytest.approx(8 / 3 * K0) and k2 == pytest.approx(4 * K0)
    assert c.masses[0] == pytest.approx(2 / 3 * M0)
    assert w[0] / (2 * math.pi) == pytest.approx(85.43, abs=0.01)  # the paper's convention, vs its 85.83 Hz


@pytest.mark.parametrize("n", [1, 2, 3, 4, 5, 6])
@pytest.mark.parametrize("convention", ["exact", "paper"])
def test_n_mass_chain_has_harmonic_frequencies_and_series_stiffness(n, convention):
    c = lumped_chain(n, K0, M0, L0, convention)
    w1 = math.pi * math.sqrt(K0 / M0) if convention == "exact" else 2 * math.sqrt(K0 / M0)
    np.testing.assert_allclose(c.natural_frequencies(), w1 * np.arange(1, n + 1), rtol=1e-9)
    assert c.series_stiffness == pytest.approx(K0, rel=1e-12)
    np.testing.assert_allclose(c.masses, c.masses[::-1], rtol=1e-9)
    np.testing.assert_allclose(c.stiffnesses, c.stiffnesses[::-1], rtol=1e-9)
    assert c.free_lengths.sum() == pytest.approx(L0)


def test_exact_chain_mass_approaches_continuum_mass():
    # more masses -> the lumped total mass tends to m0 (slowly, from below)
    totals = [lumped_chain(n, K0, M0, L0).masses.sum() / M0 for n in (1, 2, 4, 8)]
    assert all(a < b for a, b in zip(totals, totals[1:])) and totals[-1] > 0.75


def test_uniform_chain_frequency_formula():
    # independent check of the eigen-solver: uniform chain w_j = 2 sqrt(k/m) sin(j pi / (2(n+1)))
    n, k, m = 4, 1000.0, 0.1
    w = chain_frequencies(np.full(n, m), np.full(n + 1, k))
    np.testing.assert_allclose(w, 2 * np.sqrt(k / m) * np.sin(np.arange(1, n + 1) * np.pi / (2 * (n + 1))))


def test_continuum_and_string_frequencies():
    f = fixed_fixed_frequencies(K0, M0) / (2 * math.pi)
    np.testing.assert_allclose(f, np.arange(1, 4) * 0.5 * math.sqrt(K0 / M0))
    assert f[0] == pytest.approx(134.19, abs=0.01)
    fs = string_frequencies(6000.0, M0, 0.548)[0] / (2 * math.pi)
    assert fs == pytest.approx(0.5 * math.sqrt(6000 / (M0 / 0.548 * 0.548**2)), rel=1e-12)
    assert fs == pytest.approx(90.2, abs=0.1)


def test_equilibrium_positions_follow_compliance():
    c = lumped_chain(3, K0, M0, L0)
    frac = c.equilibrium_fractions()
    comp = 1 / c.stiffnesses
    assert frac[0] == pytest.approx(comp[0] / comp.sum())
    assert np.all(np.diff(frac) > 0) and frac[-1] < 1


def test_uniform_chain_converges_to_the_continuum():
    """The uniform chain's fundamental (its interior masses fixed at both ends) converges to the
    continuum's at second order: w1 = 2 (n+1) sin(pi / (2 (n+1))) sqrt(k0/m0) exactly."""
    errors = []
    for n in (5, 10, 20):
        c = lumped_chain(n, K0, M0, L0, "uniform")
        assert c.series_stiffness == pytest.approx(K0)
        w1 = c.natural_frequencies()[0]
        assert w1 == pytest.approx(2 * (n + 1) * math.sin(math.pi / (2 * (n + 1))) * math.sqrt(K0 / M0), rel=1e-12)
        errors.append(abs(w1 / (math.pi * math.sqrt(K0 / M0)) - 1))
    assert errors[0] / errors[1] == pytest.approx((11 / 6) ** 2, rel=0.02)  # second order in 1/(n+1)
    assert errors[2] == pytest.approx(math.pi**2 / (24 * 21**2), rel=0.01)  # 9.3e-4 at 20 masses


@pytest.mark.parametrize("n", [1, 2, 3, 5, 10, 20])
def test_exact_convention_carries_the_whole_mass_and_rayleighs_pin_mass(n):
    """Revised spec: the mass the harmonic chain lacks sits at the ends; total m0; the
    quasi-static mass at the pin sum m_i f_i^2 + m_pin = m0/3 (Rayleigh)."""
    c = lumped_chain(n, K0, M0, L0, "exact")
    assert c.total_mass == pytest.approx(M0, rel=1e-12)
    assert c.quasi_static_pin_mass == pytest.approx(M0 / 3, rel=1e-12)
    assert 0 < c.pin_mass < M0 / 3 and c.anchor_mass > 0
    np.testing.assert_allclose(c.natural_frequencies(), math.pi * math.sqrt(K0 / M0) * np.arange(1, n + 1), rtol=1e-9)


@pytest.mark.parametrize("n", [1, 4, 20])
def test_uniform_convention_puts_half_a_segment_at_each_end(n):
    c = lumped_chain(n, K0, M0, L0, "uniform")
    assert c.pin_mass == c.anchor_mass == pytest.approx(M0 / (2 * (n + 1)))
    assert c.total_mass == pytest.approx(M0) and c.series_stiffness == pytest.approx(K0)
    # the consistent discretisation's quasi-static pin mass tends to m0/3 from above:
    # sum (i/N)^2 / N + 1/(2N) = 1/3 + 1/(6 N^2) with N = n + 1 segments
    assert c.quasi_static_pin_mass / M0 - 1 / 3 == pytest.approx(1 / (6 * (n + 1) ** 2), rel=1e-9)


def test_paper_convention_puts_nothing_at_the_ends_and_drifts_away_as_n_grows():
    """The paper's w1 = 2 sqrt(k0/m0) with harmonic overtones holds more and more mass as n
    grows (1.33 m0 at n = 2, 2.1 m0 at n = 20): it does not converge to the continuum."""
    totals = []
    for n in (1, 2, 3, 5, 10, 20):
        c = lumped_chain(n, K0, M0, L0, "paper")
        assert c.pin_mass == 0.0 and c.anchor_mass == 0.0
        totals.append(c.total_mass / M0)
    assert totals[0] == pytest.approx(1.0) and totals[1] == pytest.approx(4 / 3)
    assert all(a < b for a, b in zip(totals, totals[1:])) and totals[-1] > 2.0


def test_chain_for_solves_a_spring_once_and_hands_out_a_read_only_chain():
    """A closing's setup, step limits and energy audit ask for the same chain: the same inputs give the same
    object (its arrays read-only, so no caller can change the chain another one holds); other inputs their own."""
    from vcbmodel.laws.springs import chain_for
    from vcbmodel.rig.spring_model import SpringModel

    class Spring:
        stiffness, mass, free_length = K0, M0, L0

    class Stiffer(Spring):
        stiffness = 1.1 * K0

    model = SpringModel("lumped", 2, "exact")
    a, b, c = chain_for(Spring, model), chain_for(Spring, model), chain_for(Stiffer, model)
    assert a is b and c is not a
    fresh = lumped_chain(model.masses, 1.1 * K0, M0, L0, model.convention)
    assert np.array_equal(c.stiffnesses, fresh.stiffnesses) and np.array_equal(c.masses, fresh.masses)
    with pytest.raises(ValueError):
        a.masses[0] = 1.0

"""The independent reference's spring chain (vcbmodel/reference/breaker_chain.py), solved from k0, m0 and
n by the persymmetric Jacobi reconstruction, against closed forms and against the model's least-squares
inverse eigenvalue solve (vcbmodel/laws/springs.py): two methods that share no code."""
import math

import numpy as np
import pytest

from vcbmodel.laws.springs import chain_frequencies, lumped_chain
from vcbmodel.reference.breaker_chain import chain_of

K0, M0, L0 = 24230.0, 0.83, 0.30


def test_two_masses_in_closed_form():
    """Two masses m on springs k1, k2, k1: the in-phase mode w^2 = k1/m, the opposed one
    (k1 + 2 k2)/m; with w and 2w and the series stiffness k0: k1 = m w^2, k2 = 1.5 m w^2,
    m = 8 k0 / (3 w^2). The exact convention's w = pi sqrt(k0/m0)."""
    w = math.pi * math.sqrt(K0 / M0)
    c = chain_of(K0, M0, L0, 2, "exact")
    m = 8 * K0 / (3 * w * w)
    assert c.masses == pytest.approx([m, m], rel=1e-12)
    assert c.stiffnesses == pytest.approx([m * w * w, 1.5 * m * w * w, m * w * w], rel=1e-12)
    # Rayleigh: the pin feels m0/3 with the masses at 3/8 and 5/8 of O-B (compliances 1 : 2/3 : 1)
    places = np.cumsum(1 / np.array(c.stiffnesses))[:-1] / np.sum(1 / np.array(c.stiffnesses))
    assert c.pin_mass == pytest.approx(M0 / 3 - m * np.sum(places**2), rel=1e-12)
    assert sum(c.free_lengths) == pytest.approx(L0)


def test_one_mass_in_closed_form():
    """One mass between two springs 2 k0: w^2 = 4 k0 / m; the paper's w = 2 sqrt(k0/m0) gives m = m0."""
    c = chain_of(K0, M0, L0, 1, "paper")
    assert c.masses == pytest.approx([M0], rel=1e-12) and c.stiffnesses == pytest.approx([2 * K0, 2 * K0])
    assert c.pin_mass == 0.0


@pytest.mark.parametrize("convention", ["exact", "paper"])
@pytest.mark.parametrize("n", [1, 2, 3, 4, 6])
def test_the_reference_chain_is_the_models(n, convention):
    """The frequencies are the convention's harmonics and the chain is the model's to round-off
    (measured below 1e-14 relative up to 8 masses)."""
    c = chain_of(K0, M0, L0, n, convention)
    w1 = (math.pi if convention == "exact" else 2.0) * math.sqrt(K0 / M0)
    assert chain_frequencies(c.masses, c.stiffnesses) == pytest.approx(w1 * np.arange(1, n + 1), rel=1e-10)
    model = lumped_chain(n, K0, M0, L0, convention)
    assert c.masses == pytest.approx(model.masses, rel=1e-9)
    assert c.stiffnesses == pytest.approx(model.stiffnesses, rel=1e-9)
    assert c.pin_mass == pytest.approx(model.pin_mass, rel=1e-9, abs=1e-15)

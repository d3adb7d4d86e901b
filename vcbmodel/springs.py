"""Closing-spring models as pure functions (paper section 3, eq. 7-8, generalised).

A ``lumped-n`` spring is a symmetric chain of n point masses and n+1 axial springs whose
series stiffness is k0 and whose n fixed-fixed natural frequencies are w1, 2 w1, ..., n w1,
with w1 = pi sqrt(k0/m0) (``exact``: the continuum's fundamental) or w1 = 2 sqrt(k0/m0)
(``paper``, eq. 8). A third convention, ``uniform`` (beyond the spec), is the plain
finite-difference discretisation of the continuum, used as a converged reference. Symmetry leaves ceil(n/2) masses and ceil((n+1)/2) stiffnesses:
n + 1 unknowns for n + 1 conditions, solved by :func:`lumped_chain`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares


@dataclass(frozen=True)
class LumpedChain:
    """Masses (kg) and stiffnesses (N/m) of one spring's chain, anchor side first."""

    masses: np.ndarray  # n
    stiffnesses: np.ndarray  # n + 1
    free_lengths: np.ndarray  # n + 1 (m), free length split in proportion to compliance

    @property
    def series_stiffness(self):
        return 1.0 / np.sum(1.0 / self.stiffnesses)

    def natural_frequencies(self):
        """Fixed-fixed natural angular frequencies (rad/s), ascending."""
        return chain_frequencies(self.masses, self.stiffnesses)

    def equilibrium_fractions(self):
        """Positions of the masses along O->B as fractions of |OB| (static equilibrium)."""
        compliance = 1.0 / self.stiffnesses
        return np.cumsum(compliance)[:-1] / compliance.sum()


def chain_stiffness_matrix(stiffnesses):
    """Tridiagonal stiffness matrix (N/m) of a chain fixed at both ends."""
    k = np.asarray(stiffnesses, float)
    K = np.diag(k[:-1] + k[1:])
    K -= np.diag(k[1:-1], 1) + np.diag(k[1:-1], -1)
    return K


def chain_frequencies(masses, stiffnesses):
    m = np.asarray(masses, float)
    K = chain_stiffness_matrix(stiffnesses)
    s = 1.0 / np.sqrt(m)
    lam = np.linalg.eigvalsh(K * s[:, None] * s[None, :])
    return np.sqrt(lam)


def fundamental(k0, m0, convention="exact"):
    """w1 (rad/s): pi sqrt(k0/m0) (``exact``, fixed-fixed continuum) or 2 sqrt(k0/m0) (``paper``)."""
    if convention == "exact":
        return math.pi * math.sqrt(k0 / m0)
    if convention == "paper":
        return 2.0 * math.sqrt(k0 / m0)
    raise ValueError(f"unknown lumped convention {convention!r}")


def _expand(half, total):
    """Mirror the first ceil(total/2) values into a symmetric array of length total."""
    return np.concatenate([half, half[: total // 2][::-1]])


def lumped_chain(n, k0, m0, free_length, convention="exact") -> LumpedChain:
    """Solve the symmetric n-mass inverse eigenvalue problem (module docstring).

    Solved in log-coordinates by least squares from a uniform chain; the solution is
    checked (frequencies to 1e-9 relative) and a failure raises ``ValueError``.
    """
    if n < 1:
        raise ValueError("a lumped chain needs at least one mass")
    if convention == "uniform":
        # finite-difference continuum: n equal masses m0/(n+1), n+1 equal springs (n+1) k0;
        # its modes converge to the continuum's as n grows (f1 within 0.1 % at n = 20)
        return LumpedChain(masses=np.full(n, m0 / (n + 1)), stiffnesses=np.full(n + 1, (n + 1) * k0),
                           free_lengths=np.full(n + 1, free_length / (n + 1)))
    w1 = fundamental(k0, m0, convention)
    target = w1 * np.arange(1, n + 1)
    nm, nk = (n + 1) // 2, (n + 2) // 2
    # uniform chain as a start, masses scaled so its fundamental is w1
    k_uniform = (n + 1) * k0
    w_uniform = 2 * math.sqrt(k_uniform) * math.sin(math.pi / (2 * (n + 1)))
    m_uniform = (w_uniform / w1) ** 2
    x0 = np.log(np.concatenate([np.full(nm, m_uniform), np.full(nk, k_uniform)]))

    def unpack(x):
        return _expand(np.exp(x[:nm]), n), _expand(np.exp(x[nm:]), n + 1)

    def residual(x):
        m, k = unpack(x)
        w = chain_frequencies(m, k)
        return np.concatenate([np.log(w / target), [math.log(k0 * np.sum(1.0 / k))]])

    sol = least_squares(residual, x0, xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=2000)
    if np.max(np.abs(residual(sol.x))) > 1e-9:
        raise ValueError(f"lumped-{n}: the inverse eigenvalue problem did not converge")
    m, k = unpack(sol.x)
    return LumpedChain(masses=m, stiffnesses=k, free_lengths=free_length * k0 / k)


def fixed_fixed_frequencies(k0, m0, count=3):
    """The continuum spring's axial natural frequencies (rad/s): w_n = n pi sqrt(k0/m0)."""
    return math.pi * math.sqrt(k0 / m0) * np.arange(1, count + 1)


def string_frequencies(tension, m0, length, count=3):
    """Lateral (string) natural frequencies (rad/s) of a preloaded spring: n pi sqrt(T L / m0) / L."""
    return np.arange(1, count + 1) * math.pi * math.sqrt(tension / (m0 * length))

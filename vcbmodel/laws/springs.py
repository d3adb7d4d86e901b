"""Closing-spring models as pure functions (paper section 3, eq. 7-8, generalised).

A ``lumped-n`` spring is a symmetric chain of n point masses and n+1 axial springs with series
stiffness k0, plus the share of the spring's mass that sits at its two ends: the anchor's is
fixed, the pin's rides on the cam's pin B (spec "lumped_convention"). Conventions:

- ``paper``: eq. 7-8 generalised: the n fixed-fixed natural frequencies are w1, 2 w1, ..., n w1
  with w1 = 2 sqrt(k0/m0); nothing at the ends (the chain holds 1.0-1.5 m0).
- ``exact``: the same harmonic structure with the continuum's w1 = pi sqrt(k0/m0); the mass the
  chain lacks sits at the ends so that the total is m0 and the quasi-static mass felt at the
  pin is Rayleigh's m0/3: m_pin = m0/3 - sum m_i f_i^2 (f_i: mass i's position along O-B).
- ``uniform``: n+1 equal segments of stiffness (n+1) k0, interior masses m0/(n+1), half a
  segment's mass m0/(2(n+1)) at each end: the consistent discretisation of the continuum.

For ``paper`` and ``exact``, symmetry leaves ceil(n/2) masses and ceil((n+1)/2) stiffnesses:
n + 1 unknowns for n + 1 conditions (n frequencies and the series stiffness), solved as an
inverse eigenvalue problem by :func:`lumped_chain`.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, replace

import numpy as np
from numpy.typing import ArrayLike
from scipy.optimize import least_squares


@dataclass(frozen=True)
class LumpedChain:
    """Masses (kg) and stiffnesses (N/m) of one spring's chain, anchor side first."""

    masses: np.ndarray  # n
    stiffnesses: np.ndarray  # n + 1
    free_lengths: np.ndarray  # n + 1 (m), free length split in proportion to compliance
    pin_mass: float = 0.0  # kg riding on the pin B (moves with the cam)
    anchor_mass: float = 0.0  # kg at the fixed anchor O (never moves)

    @property
    def total_mass(self) -> float:
        """All of the spring's mass in the model (kg): chain, pin and anchor shares."""
        return float(self.masses.sum() + self.pin_mass + self.anchor_mass)

    @property
    def quasi_static_pin_mass(self) -> float:
        """Mass (kg) a slowly moving pin feels: sum m_i f_i^2 + m_pin (Rayleigh: m0/3)."""
        return float(np.sum(self.masses * self.equilibrium_fractions() ** 2) + self.pin_mass)

    @property
    def series_stiffness(self) -> float:
        return 1.0 / np.sum(1.0 / self.stiffnesses)

    def natural_frequencies(self) -> np.ndarray:
        """Fixed-fixed natural angular frequencies (rad/s), ascending."""
        return chain_frequencies(self.masses, self.stiffnesses)

    def equilibrium_fractions(self) -> np.ndarray:
        """Positions of the masses along O->B as fractions of |OB| (static equilibrium)."""
        compliance = 1.0 / self.stiffnesses
        return np.cumsum(compliance)[:-1] / compliance.sum()


def chain_stiffness_matrix(stiffnesses: ArrayLike) -> np.ndarray:
    """Tridiagonal stiffness matrix (N/m) of a chain fixed at both ends."""
    k = np.asarray(stiffnesses, float)
    K = np.diag(k[:-1] + k[1:])
    K -= np.diag(k[1:-1], 1) + np.diag(k[1:-1], -1)
    return K


def chain_frequencies(masses: ArrayLike, stiffnesses: ArrayLike) -> np.ndarray:
    m = np.asarray(masses, float)
    K = chain_stiffness_matrix(stiffnesses)
    s = 1.0 / np.sqrt(m)
    lam = np.linalg.eigvalsh(K * s[:, None] * s[None, :])
    return np.sqrt(lam)


def fundamental(k0: float, m0: float, convention: str = "exact") -> float:
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
        # consistent discretisation: n equal masses m0/(n+1), n+1 equal springs (n+1) k0, half a
        # segment's mass at each end; its modes converge to the continuum's as n grows
        segment = m0 / (n + 1)
        return LumpedChain(masses=np.full(n, segment), stiffnesses=np.full(n + 1, (n + 1) * k0),
                           free_lengths=np.full(n + 1, free_length / (n + 1)), pin_mass=segment / 2,
                           anchor_mass=segment / 2)
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
    chain = LumpedChain(masses=m, stiffnesses=k, free_lengths=free_length * k0 / k)
    if convention == "exact":
        pin = m0 / 3.0 - float(np.sum(m * chain.equilibrium_fractions() ** 2))
        anchor = m0 - float(m.sum()) - pin
        if pin < 0 or anchor < 0:
            raise ValueError(f"lumped-{n} (exact): the chain carries more than the spring's mass")
        chain = replace(chain, pin_mass=pin, anchor_mass=anchor)
    return chain


def kelvin_voigt_time(damping_ratio: float, k0: float, m0: float) -> float:
    """The closing spring's internal damping as a Kelvin-Voigt material: every part of the coil
    carries a damper beta times its stiffness (a segment k_i of a lumped chain gets c_i = beta k_i in
    N s/m, the ANCF cable EA_t = beta EA; the damping matrix is beta K, stiffness-proportional
    Rayleigh damping: Woodhouse, J. Sound Vib. 215 (1998) 547). Each mode of natural frequency w_n
    then has the damping ratio beta w_n / 2, rising with the mode's order as a material's loss does
    faster than a friction's. Returns beta (s) = 2 zeta_1 / w_1 from ``damping_ratio`` zeta_1 of the
    continuum's first fixed-fixed surge mode, w_1 = pi sqrt(k0/m0) (k0 N/m, m0 kg)."""
    return 2.0 * damping_ratio / fundamental(k0, m0, "exact")


def modal_damping_ratios(masses: ArrayLike, stiffnesses: ArrayLike, beta: float) -> np.ndarray:
    """Damping ratios of a fixed-fixed chain's axial modes, ascending, under Kelvin-Voigt links
    (:func:`kelvin_voigt_time` ``beta`` in s): beta w_n / 2 (proportional damping keeps the modes)."""
    return 0.5 * beta * chain_frequencies(masses, stiffnesses)


def fixed_fixed_frequencies(k0: float, m0: float, count: int = 3) -> np.ndarray:
    """The continuum spring's axial natural frequencies (rad/s): w_n = n pi sqrt(k0/m0)."""
    return math.pi * math.sqrt(k0 / m0) * np.arange(1, count + 1)


def string_frequencies(tension: float, m0: float, length: float, count: int = 3) -> np.ndarray:
    """Lateral (string) natural frequencies (rad/s) of a preloaded spring: n pi sqrt(T L / m0) / L."""
    return np.arange(1, count + 1) * math.pi * math.sqrt(tension / (m0 * length))


#: How many chains :func:`chain_for` keeps per process (least recently used dropped first): a closing's
#: setup, step limits and energy audit ask for the same spring's chain five times, and its least-squares
#: solve was a seventh of a tolerance study's processor time; a sweep that draws a new spring every run
#: keeps at most this many (a few kB each).
CHAINS_KEPT = 256


@functools.lru_cache(maxsize=CHAINS_KEPT)
def _kept_chain(n: int, k0: float, m0: float, free_length: float, convention: str) -> LumpedChain:
    """:func:`lumped_chain` of these values, solved once per process: the key is the values themselves
    (the spring's numbers as ``float``, so equal inputs of other number types share one chain of float arrays),
    and the chain is computed from the key alone; its arrays are read-only, so no caller can change the
    chain another one holds. ``functools.lru_cache``: bounded and safe to call from several threads."""
    chain = lumped_chain(n, k0, m0, free_length, convention)
    for a in (chain.masses, chain.stiffnesses, chain.free_lengths):
        a.flags.writeable = False
    return chain


def chain_for(spring, spring_model) -> LumpedChain | None:
    """The lumped chain of ``spring`` (k0, m0, free length) for a spring model (``kind``,
    ``masses``, ``convention``); None for massless and ANCF springs. The same values give the same
    chain object (read-only arrays), solved once per process (:func:`_kept_chain`)."""
    if spring_model.kind != "lumped":
        return None
    return _kept_chain(spring_model.masses, float(spring.stiffness), float(spring.mass),
                       float(spring.free_length), str(spring_model.convention))

"""The independent reference's lumped closing-spring chain, from the spring's own numbers (k0, m0, n).

The model solves the chain's inverse eigenvalue problem by least squares on the sorted eigenvalues
(:func:`vcbmodel.laws.springs.lumped_chain`); this module solves it another way and shares no code
with it, so the reference tests the model's chain, not a copy of it.

A symmetric fixed-fixed chain (masses m_i mirrored, springs k_1..k_{n+1} mirrored) has a
mass-normalised stiffness matrix J = M^(-1/2) K M^(-1/2) that is a persymmetric Jacobi matrix, and a
persymmetric Jacobi matrix is fixed by its eigenvalues alone (Hochstadt 1967; de Boor & Golub,
Linear Algebra Appl. 21, 1978): the squared first components of its normalised eigenvectors are
w_i proportional to 1 / |prod_{j != i} (lambda_i - lambda_j)|, and Lanczos's recursion on
diag(lambda) from the vector sqrt(w) rebuilds J. The chain follows from J: K 1 = (k_1, 0, ..., 0,
k_{n+1}) (a fixed-fixed chain's interior rows sum to zero), so s_i = sqrt(m_i) solves J's interior
rows, a three-term recursion fixed up to scale by the mirror symmetry s_n = s_1; then
k_{i+1} = -J_{i,i+1} s_i s_{i+1}, k_1 = J_11 m_1 - k_2, k_{n+1} = J_nn m_n - k_n, and the scale by the
series stiffness 1 / sum(1/k_i) = k0.

What it shares with the model is the definition of the conventions (the spec's): ``exact`` targets
w_j = j pi sqrt(k0/m0) and puts the mass the chain lacks at its ends so that the pin feels
Rayleigh's m0/3 (m_pin = m0/3 - sum m_i f_i^2, f_i the masses' static places along O-B); ``paper``
targets w_j = 2 j sqrt(k0/m0), nothing at the ends; ``uniform`` is n masses m0/(n+1) on n+1 springs
(n+1) k0 with m0/(2(n+1)) at the pin. Free lengths are split in proportion to each spring's
compliance. Units: kg, N/m, m, rad/s.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Chain:
    """One spring's chain, anchor side first: masses (kg), stiffnesses and free lengths (N/m, m) of
    its n+1 springs, and the mass riding on the pin B (kg)."""

    masses: list
    stiffnesses: list
    free_lengths: list
    pin_mass: float


def persymmetric_jacobi(eigenvalues: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(diagonal, off-diagonal >= 0) of the persymmetric Jacobi matrix with these distinct eigenvalues
    (de Boor & Golub's weights, Lanczos with full reorthogonalisation)."""
    lam = np.asarray(eigenvalues, float)
    n = lam.size
    w = np.array([1.0 / abs(np.prod([lam[i] - lam[j] for j in range(n) if j != i])) for i in range(n)])
    q = [np.sqrt(w / w.sum())]
    diag, off = [], []
    for j in range(n):
        v = lam * q[j]
        diag.append(float(q[j] @ v))
        for u in q:  # full reorthogonalisation: removes the diagonal term and the previous vector too
            v = v - (u @ v) * u
        if j < n - 1:
            off.append(float(np.linalg.norm(v)))
            q.append(v / off[-1])
    return np.array(diag), np.array(off)


def symmetric_chain(eigenvalues: np.ndarray, series_stiffness: float) -> tuple[np.ndarray, np.ndarray]:
    """(masses kg, stiffnesses N/m) of the mirror-symmetric fixed-fixed chain whose squared natural
    frequencies are ``eigenvalues`` (rad^2/s^2) and whose series stiffness is ``series_stiffness``."""
    a, b = persymmetric_jacobi(eigenvalues)
    n = a.size
    b = -b  # a chain's coupling is negative (flipping signs is a similarity that keeps the spectrum)

    def recursion(s1, s2):
        s = [s1, s2][:n]
        for i in range(1, n - 1):  # interior row i: b_{i-1} s_{i-1} + a_i s_i + b_i s_{i+1} = 0
            s.append(-(b[i - 1] * s[i - 1] + a[i] * s[i]) / b[i])
        return np.array(s)

    if n == 1:
        s = np.ones(1)
    else:
        u, v = recursion(1.0, 0.0), recursion(0.0, 1.0)
        s = u + (1.0 - u[-1]) / v[-1] * v  # the mirror symmetry: s_n = s_1 = 1
    if np.any(s <= 0.0):
        raise ValueError("no symmetric spring-mass chain has these frequencies")
    m = s * s
    k = np.empty(n + 1)
    k[1:n] = -b * s[:-1] * s[1:]
    k[0] = a[0] * m[0] - (k[1] if n > 1 else 0.0)
    k[n] = a[-1] * m[-1] - (k[n - 1] if n > 1 else 0.0)
    if n == 1:  # one mass between two springs: symmetry splits a m equally
        k[0] = k[1] = 0.5 * a[0] * m[0]
    scale = series_stiffness * float(np.sum(1.0 / k))  # masses and stiffnesses scale together
    return m * scale, k * scale


def chain_of(stiffness: float, mass: float, free_length: float, n: int, convention: str) -> Chain:
    """The chain of n masses of a spring of rate ``stiffness`` (N/m), active mass ``mass`` (kg) and free
    length ``free_length`` (m) in a convention (module docstring)."""
    if n < 1:
        raise ValueError("a lumped chain needs at least one mass")
    if convention == "uniform":
        m, k, pin = np.full(n, mass / (n + 1)), np.full(n + 1, (n + 1) * stiffness), mass / (2 * (n + 1))
    elif convention in ("exact", "paper"):
        w1 = (math.pi if convention == "exact" else 2.0) * math.sqrt(stiffness / mass)
        m, k = symmetric_chain((w1 * np.arange(1, n + 1)) ** 2, stiffness)
        pin = 0.0
        if convention == "exact":
            places = np.cumsum(1.0 / k)[:-1] / np.sum(1.0 / k)
            pin = mass / 3.0 - float(np.sum(m * places**2))
            if pin < 0.0 or m.sum() + pin > mass:
                raise ValueError(f"lumped-{n} (exact): the chain carries more than the spring's mass")
    else:
        raise ValueError(f"unknown lumped convention {convention!r}")
    lengths = free_length * (1.0 / k) / np.sum(1.0 / k)
    return Chain([float(x) for x in m], [float(x) for x in k], [float(x) for x in lengths], float(pin))

"""The covariance of fitted parameters, stated so that it covers model-form error.

The textbook (here *naive*) covariance of a least-squares fit, ``s^2 (J^T J)^-1`` with ``s^2``
the reduced chi^2 and ``J`` the Jacobian of the noise-scaled residual, assumes the residual is
white noise. When the fitted law is not the truth (issue 20: Tustin or LuGre friction fitted with
the hybrid law) the residual holds a slow, structured discrepancy instead, and the naive errors
are far too small (mu_k 86 standard errors off the truth).

The stated covariance (``stderr``) is ``B (M + D) B`` with ``B = (J^T J)^-1`` and two terms, both
from the residual ``r`` of each contiguous record, so no simulation is added:

- ``M = J^T Omega J``, ``Omega`` the Bartlett-tapered autocovariance of ``r`` over a lag window
  (the Newey & West 1987 sandwich, in its stationary form): the spread the parameters would have
  if the residual's correlated part were a random process. It also covers correlated sensor noise.
- ``D = g1 L J^T J``: a discrepancy of the residual's lag-1 autocovariance ``g1`` (white noise has
  none, a slow discrepancy its whole variance), constant over the lag window ``L`` and aligned
  with the parameters' columns. The part of a discrepancy the fit absorbed is invisible in the
  residual (the residual is orthogonal to the columns); this term states how far it could move
  the parameters if it were as large as the part left visible. Kennedy & O'Hagan (2001) model
  the discrepancy as a random function of the residual's size and correlation; this is the
  cheapest conservative version of their idea for a least-squares fit. Its variance is corrected
  for the degrees of freedom the fit took, m / (m - p) with m the residual's independent pieces
  (samples over the lag window) and p the varied parameters, as ``s^2`` is for a white residual.

Why not the alternatives: inflation by the residual's excess over the noise is already ``s^2`` in
the naive covariance and was 50-70 standard errors short on the position-dependent truth; a
moving-block bootstrap needs a refit per replicate, and in the linear approximation estimates the
sandwich ``M`` alone, which was still about 5x short there; a discrepancy function inside the law
would need a new law in every backend.

Lag window: ``BANDWIDTH_FACTOR`` times the first lag at which the residual's autocorrelation is
not positive: one period of an oscillating discrepancy (its first zero is a quarter period in),
a few samples for white noise (then both terms reduce to the naive covariance within its sampling
error). No stated variance is below the naive one.

Limits (measured in docs/findings.md): a discrepancy the fit absorbs completely, leaving a residual
at the noise (a Stribeck curve of another shape reproduced by the fitted law's own Stribeck and
viscous terms), is invisible to any estimate from the record; then the parameters mean something
else in each law, and the interval covers the fitted law's parameters, not the other law's.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.signal import fftconvolve

from .arithmetic import quiet_trial

#: The lag window spans this many first zero crossings of the residual's autocorrelation: four
#: quarter periods, one period of an oscillating discrepancy.
BANDWIDTH_FACTOR = 4
#: Name of the stated (covering) method in reports.
METHOD = "sandwich of the residual's autocorrelation + aligned discrepancy"


@dataclass
class Covariance:
    """Covariances of the varied parameters in the optimiser's internal coordinates (log for a
    log parameter): ``naive`` (white noise, ``s^2 (J^T J)^-1``) and ``covering`` (sandwich, never
    below the naive on the diagonal); ``bandwidth`` the longest lag window used (samples)."""

    names: tuple
    naive: np.ndarray
    covering: np.ndarray
    bandwidth: int
    method: str = METHOD

    def standard_errors(self, which: str = "covering") -> np.ndarray:
        """1-sigma errors (internal coordinates); inf where the data do not determine a direction."""
        m = self.covering if which == "covering" else self.naive
        d = np.diag(m)
        return np.where(np.isfinite(d) & (d >= 0), np.sqrt(np.abs(d)), np.inf)

    def correlations(self) -> dict[tuple[str, str], float]:
        """Correlation of each pair of varied parameters under the covering covariance."""
        se = self.standard_errors()
        out = {}
        for i, a in enumerate(self.names):
            for j in range(i + 1, len(self.names)):
                if math.isfinite(se[i]) and math.isfinite(se[j]) and se[i] > 0 and se[j] > 0:
                    out[(a, self.names[j])] = float(np.clip(self.covering[i, j] / (se[i] * se[j]), -1.0, 1.0))
        return out


def _bread(J: np.ndarray) -> np.ndarray:
    """(J^T J)^-1 by the singular values of J: a direction the data do not determine gets the
    infinite variance it has (a pseudo-inverse would set it to zero and report false precision)."""
    _, sv, vt = np.linalg.svd(J, full_matrices=False)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        inv = np.where(sv > 1e-300, 1.0 / np.maximum(sv, 1e-300) ** 2, np.inf)
        return (vt.T * inv) @ vt


def bandwidth(r: np.ndarray) -> int:
    """Lag window (samples) of a residual segment: BANDWIDTH_FACTOR times the first lag at which
    its autocorrelation is not positive, at most half the segment."""
    n = r.size
    if n < 4:
        return 0
    f = np.fft.rfft(r, 2 * n)
    acov = np.fft.irfft(f * np.conj(f), 2 * n)[: n // 2 + 1]
    if acov[0] <= 0:
        return 0
    nonpositive = np.nonzero(acov[1:] <= 0)[0]
    first = int(nonpositive[0]) + 1 if nonpositive.size else n // 2
    return int(min(BANDWIDTH_FACTOR * first, n // 2))


def _meat(J: np.ndarray, r: np.ndarray, lags: int) -> np.ndarray:
    """J^T Omega J for one contiguous segment: Omega the Bartlett-tapered autocovariance of ``r``
    over ``lags`` lags (Toeplitz; positive semi-definite by construction)."""
    n = r.size
    f = np.fft.rfft(r, 2 * n)
    acov = np.fft.irfft(f * np.conj(f), 2 * n)[: lags + 1] / n
    w = 1.0 - np.arange(lags + 1) / (lags + 1.0)
    c = acov * w
    kernel = np.concatenate([c[:0:-1], c])  # lags -L..L
    omega_j = np.column_stack([fftconvolve(J[:, k], kernel, mode="same") for k in range(J.shape[1])])
    return J.T @ omega_j


def _discrepancy_meat(J: np.ndarray, r: np.ndarray, lags: int) -> np.ndarray:
    """J^T K J of a discrepancy constant over ``lags`` samples with the residual's lag-1 covariance
    (white noise has none; a smooth discrepancy its whole variance), aligned with the columns."""
    n = r.size
    g1 = max(0.0, float(np.dot(r[1:], r[:-1])) / n)
    return g1 * max(1, lags) * (J.T @ J)


def _degrees_of_freedom_correction(pieces: float, n_params: int) -> float:
    """m / (m - p): the residual shows a discrepancy of m independent pieces (samples over the lag
    window) less the p the fit absorbed, as s^2 = RSS / (n - p) corrects a white residual; with
    no more pieces than parameters (m <= p + 1), m (a discrepancy over the whole record)."""
    return pieces / (pieces - n_params) if pieces > n_params + 1 else max(pieces, 1.0)


@quiet_trial
def parameter_covariance(names, J: np.ndarray, r: np.ndarray, segments, dof: int) -> Covariance:
    """Naive and covering covariance of the varied parameters.

    Parameters
    ----------
    names : the varied parameters' names (J's columns).
    J : Jacobian of the scaled residual ``r`` (rows: residual samples, then prior rows).
    r : the scaled residual (dimensionless) at the optimum.
    segments : lengths of the contiguous record segments, in row order; rows after them (priors,
        each already in units of its own sd) count as independent with unit variance.
    dof : residual degrees of freedom (samples - varied parameters).
    """
    J = np.asarray(J, float)
    r = np.asarray(r, float)
    bread = _bread(J)
    s2 = float(np.dot(r, r)) / max(1, dof)
    with np.errstate(invalid="ignore"):
        naive = bread * s2
    meat = np.zeros((J.shape[1], J.shape[1]))
    disc = np.zeros_like(meat)
    start, widest, pieces = 0, 0, 0.0
    for n in segments:
        seg = slice(start, start + n)
        lags = bandwidth(r[seg])
        widest = max(widest, lags)
        if n > 1:
            meat += _meat(J[seg], r[seg], lags)
            disc += _discrepancy_meat(J[seg], r[seg], lags)
            pieces += n / max(1, lags)
        start += n
    disc *= _degrees_of_freedom_correction(pieces, J.shape[1])
    meat += J[start:].T @ J[start:]  # prior rows: independent, unit variance
    with np.errstate(invalid="ignore"):
        sandwich = bread @ meat @ bread
    with np.errstate(invalid="ignore"):
        sandwich = sandwich + bread @ disc @ bread
    covering = _floored(sandwich, naive)
    return Covariance(tuple(names), naive, covering, widest)


def _floored(sandwich: np.ndarray, naive: np.ndarray) -> np.ndarray:
    """The sandwich with each variance at least the naive one (correlations kept); a direction
    the naive covariance leaves undetermined stays so."""
    dn, ds = np.diag(naive), np.diag(sandwich)
    ok = np.isfinite(ds) & (ds > 0)
    target = np.where(ok, np.maximum(ds, np.where(np.isfinite(dn), dn, np.inf)), dn)
    scale = np.where(ok, np.sqrt(target / np.where(ok, ds, 1.0)), 1.0)
    out = sandwich * np.outer(scale, scale)
    bad = ~ok | ~np.isfinite(dn)
    out[bad, :] = naive[bad, :]
    out[:, bad] = naive[:, bad]
    return out

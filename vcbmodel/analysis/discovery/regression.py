"""Regression of a missing torque on the library's terms (scikit-learn's LARS-lasso for the order).

The model's own parameter directions are projected out of the target and of every library column
first (Frisch-Waugh-Lovell: the same coefficients as a regression with those directions free and
unpenalised), so a term is credited only with what the registered model cannot do by moving its
values. On the standardised remainder the lasso path (``sklearn.linear_model.lars_path``) gives
the order in which terms enter and ``LassoLarsIC`` with the Bayesian information criterion how
many the torque estimate supports (both reported). The estimate's noise is correlated by the
smoothing, so its scores only rank: :meth:`Selection.ranked` orders the terms that could join a
support by the share of what is left they explain, and :meth:`Selection.support_fit` gives a
support's least-squares coefficients and the model's shifts, a refit's start. The refit of the
whole record, scored as a registered effect is, decides (:mod:`.judge`, :mod:`.discover`).
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from sklearn.linear_model import LassoLarsIC, lars_path

#: Most terms one discovery adds (nested supports refitted: 1, 2, ... up to this).
MAX_TERMS = 3
#: A library column whose part outside the model's own directions is below this fraction of its
#: norm is what the model already does (aliased with a registered parameter): left out.
ALIASED = 1e-3


@dataclass
class Selection:
    """The regression's proposal. ``order``: terms in the order they enter the lasso path;
    ``n_bic``: how many LassoLarsIC's BIC keeps; ``supports``: the nested term sets to refit,
    each with its least-squares ``coefficients`` (term units) and ``explained`` share of the
    missing torque's variance (outside the model's own directions); ``aliased``: terms the
    model's parameters already span; ``samples``: samples regressed; ``model_shifts``: per support,
    the change of each model parameter the same regression asks for (its unit), a refit's start;
    ``base_shift``: the same without any term (the registered model's own better start)."""

    order: list
    n_bic: int
    supports: list
    coefficients: list
    explained: list
    aliased: list = field(default_factory=list)
    samples: int = 0
    model_shifts: list = field(default_factory=list)
    base_shift: dict = field(default_factory=dict)
    parts: tuple = ()  # (names, X, y, Z, z_names, X_p, y_p, kept columns): what support_fit and ranked read

    def support_fit(self, support: Sequence[str]) -> tuple[dict, float, dict]:
        """({term: least-squares coefficient}, share of the projected target's variance explained,
        {model parameter: shift}) of the terms ``support`` (the model's directions free)."""
        names, X, y, Z, z_names, X_p, y_p, _ = self.parts
        cols = [names.index(n) for n in support]
        beta, *_ = np.linalg.lstsq(X_p[:, cols], y_p, rcond=None)
        left = y_p - X_p[:, cols] @ beta
        total = float(np.dot(y_p, y_p))
        explained = 1.0 - float(np.dot(left, left)) / total if total > 0 else 0.0
        delta = np.linalg.lstsq(Z, y - X[:, cols] @ beta, rcond=None)[0] if Z.shape[1] else []
        return ({names[j]: float(b) for j, b in zip(cols, beta)}, explained,
                {name: float(v) for name, v in zip(z_names, delta)})

    def ranked(self, support: Sequence[str] = ()) -> list[tuple[str, float]]:
        """[(term, share)] of every term not aliased and not in ``support``, best first: the share of
        the projected target's variance the term adds to ``support`` (alone: its own share)."""
        names, _, _, _, _, X_p, y_p, keep = self.parts
        base = [names.index(n) for n in support]
        left = y_p
        if base:
            beta, *_ = np.linalg.lstsq(X_p[:, base], y_p, rcond=None)
            left = y_p - X_p[:, base] @ beta
        others = [j for j in keep if j not in base]
        if not others:
            return []
        Xo = _project_out(X_p[:, base], *(X_p[:, j] for j in others)) if base else [X_p[:, j] for j in others]
        total = float(np.dot(y_p, y_p)) or 1.0
        shares = [(names[j], float(np.dot(x, left) ** 2 / max(float(np.dot(x, x)), 1e-300)) / total)
                  for j, x in zip(others, Xo)]
        return sorted(shares, key=lambda item: -item[1])


def _project_out(Z: np.ndarray, *arrays: np.ndarray) -> list[np.ndarray]:
    """Each array minus its least-squares projection on the columns of Z."""
    if Z.shape[1] == 0:
        return list(arrays)
    q, _ = np.linalg.qr(Z)
    return [a - q @ (q.T @ a) for a in arrays]


def entry_order(X: np.ndarray, y: np.ndarray) -> list[int]:
    """Column indices in the order they first become active on the lasso path."""
    _, _, coefs = lars_path(X, y, method="lasso")
    first = []
    for j in range(X.shape[1]):
        nz = np.nonzero(np.abs(coefs[j]) > 0)[0]
        first.append(nz[0] if nz.size else np.inf)
    return [j for j in np.argsort(first, kind="stable") if np.isfinite(first[j])]


def select(names: Sequence[str], X: np.ndarray, y: np.ndarray, Z: np.ndarray, z_names: Sequence[str] = ()) -> Selection:
    """Propose nested supports of library columns ``X`` (samples, terms; named ``names``) for the
    target ``y`` (N m), with the model's directions ``Z`` (samples, k; named ``z_names``) free
    (module docstring)."""
    y_p, X_p = _project_out(Z, y, X)
    norms = np.linalg.norm(X, axis=0)
    kept_norms = np.linalg.norm(X_p, axis=0)
    keep = [j for j in range(X.shape[1]) if norms[j] > 0 and kept_norms[j] > ALIASED * norms[j]]
    aliased = [names[j] for j in range(X.shape[1]) if j not in keep]
    Xs = X_p[:, keep] / kept_norms[keep]
    order = [keep[j] for j in entry_order(Xs, y_p)] if keep else []
    n_bic = int(np.count_nonzero(LassoLarsIC(criterion="bic", fit_intercept=False).fit(Xs, y_p).coef_)) if keep else 0
    supports, coefficients, explained, shifts = [], [], [], []
    total = float(np.dot(y_p, y_p))
    for k in range(1, min(MAX_TERMS, max(1, n_bic), len(order)) + 1):
        cols = order[:k]
        beta, *_ = np.linalg.lstsq(X_p[:, cols], y_p, rcond=None)
        left = y_p - X_p[:, cols] @ beta
        supports.append(tuple(names[j] for j in cols))
        coefficients.append({names[j]: float(b) for j, b in zip(cols, beta)})
        explained.append(1.0 - float(np.dot(left, left)) / total if total > 0 else 0.0)
        delta = np.linalg.lstsq(Z, y - X[:, cols] @ beta, rcond=None)[0] if Z.shape[1] else []
        shifts.append({name: float(v) for name, v in zip(z_names, delta)})
    base = np.linalg.lstsq(Z, y, rcond=None)[0] if Z.shape[1] else []
    return Selection([names[j] for j in order], n_bic, supports, coefficients, explained, aliased, int(y.size), shifts,
                     {name: float(v) for name, v in zip(z_names, base)}, (list(names), X, y, Z, list(z_names), X_p, y_p, keep))

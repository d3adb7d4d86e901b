"""A sweep's design: the parameter sets, from grids ``LO:HI:N`` (their full product) or from
distributions ``normal:MEAN:SD`` / ``uniform:LO:HI`` drawn by Latin hypercube sampling (scipy's
scrambled ``LatinHypercube``, each axis through the distribution's inverse CDF), seeded."""
from __future__ import annotations

import itertools
import math
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.stats import norm, qmc

from ...errors import InputError

#: Seed of the random draws when none is given: every sweep is repeatable (and resumable).
DEFAULT_SEED = 0
#: How distributions are sampled (stated in ``vcbmodel sweep --help`` and the table's attrs).
SAMPLING = {"lhs": "Latin hypercube sampling (scipy.stats.qmc.LatinHypercube, scrambled)", "mc": "plain Monte Carlo"}
#: A larger design is a typo (a grid of 1000 x 1000 x 1000), not a study.
MAX_RUNS = 10_000_000
#: Significant digits of a varied value: the value a run uses is the value its row shows.
DIGITS = 12
DISTRIBUTIONS = ("normal", "uniform")


@dataclass(frozen=True)
class Vary:
    """One ``PATH=SPEC``: a grid (``kind`` ``grid``: ``a`` to ``b`` in ``n`` values) or a
    distribution (``normal``: mean ``a``, sd ``b``; ``uniform``: ``a`` to ``b``)."""

    path: str
    kind: str
    a: float
    b: float
    n: int = 0

    @property
    def is_grid(self) -> bool:
        return self.kind == "grid"

    def grid(self) -> np.ndarray:
        return np.linspace(self.a, self.b, self.n)

    def from_unit(self, u: np.ndarray) -> np.ndarray:
        """Values at probabilities ``u`` in (0, 1) (the inverse CDF)."""
        u = np.clip(np.asarray(u, float), 1e-12, 1 - 1e-12)
        return norm.ppf(u, self.a, self.b) if self.kind == "normal" else self.a + u * (self.b - self.a)

    @property
    def spec(self) -> str:
        if self.is_grid:
            return f"{self.a:g}:{self.b:g}:{self.n}"
        return f"{self.kind}:{self.a:g}:{self.b:g}"


def parse_vary(item, source="--vary") -> Vary:
    """``PATH=SPEC`` (text), or a ``(path, spec)`` pair, as a :class:`Vary`; bad syntax raises
    :class:`InputError` naming ``source`` and the item."""
    if isinstance(item, Vary):
        return item
    if isinstance(item, (tuple, list)) and len(item) == 2:
        path, spec = (str(x).strip() for x in item)
    else:
        text = str(item)
        if "=" not in text:
            raise InputError(source, text, "must be PATH=SPEC, e.g. friction.mu_k=0.08:0.18:6")
        path, spec = (s.strip() for s in text.split("=", 1))
    if not path:
        raise InputError(source, f"{path}={spec}", "PATH is empty")
    parts = spec.split(":")
    if parts[0] in DISTRIBUTIONS:
        return _distribution(path, spec, parts, source)
    return _grid(path, spec, parts, source)


def _spec_number(s: str, what: str, path: str, spec: str, source: str) -> float:
    """One number of a SPEC (``what``: LO, HI, N, MEAN, SD), finite."""
    try:
        v = float(s)
    except ValueError:
        raise InputError(source, path, f"{what} {s!r} in {spec!r} is not a number") from None
    if not math.isfinite(v):
        raise InputError(source, path, f"{what} in {spec!r} must be finite")
    return v


def _distribution(path: str, spec: str, parts: list[str], source: str) -> Vary:
    """``normal:MEAN:SD`` or ``uniform:LO:HI``."""
    if len(parts) != 3:
        raise InputError(source, path, f"{parts[0]} needs two numbers: {parts[0]}:"
                         f"{'MEAN:SD' if parts[0] == 'normal' else 'LO:HI'}, got {spec!r}")
    first, second = ("MEAN", "SD") if parts[0] == "normal" else ("LO", "HI")
    a, b = _spec_number(parts[1], first, path, spec, source), _spec_number(parts[2], second, path, spec, source)
    if parts[0] == "normal" and not b > 0:
        raise InputError(source, path, f"the standard deviation must be positive, got {b:g}")
    if parts[0] == "uniform" and not b > a:
        raise InputError(source, path, f"uniform:LO:HI needs LO < HI, got {spec!r}")
    return Vary(path, parts[0], a, b)


def _grid(path: str, spec: str, parts: list[str], source: str) -> Vary:
    """``LO:HI:N``: N values from LO to HI."""
    if len(parts) != 3:
        raise InputError(source, path, f"SPEC must be LO:HI:N, normal:MEAN:SD or uniform:LO:HI, got {spec!r}")
    if parts[0].strip().isalpha() and parts[0].lower() not in ("nan", "inf", "infinity"):
        raise InputError(source, path, f"unknown distribution {parts[0]!r}: SPEC must be LO:HI:N, normal:MEAN:SD "
                         "or uniform:LO:HI")
    lo, hi = _spec_number(parts[0], "LO", path, spec, source), _spec_number(parts[1], "HI", path, spec, source)
    n = _spec_number(parts[2], "N", path, spec, source)
    if n != int(n) or n < 1:
        raise InputError(source, path, f"N must be a whole number >= 1, got {parts[2]!r}")
    if n == 1 and lo != hi:
        raise InputError(source, path, f"one value from {lo:g} to {hi:g}: give N >= 2, or LO = HI")
    return Vary(path, "grid", lo, hi, int(n))


def parse_varies(items: Iterable[str | tuple[str, str] | Vary] | dict[str, str], source: str = "--vary") -> list[Vary]:
    varies = [parse_vary(x, source) for x in (items.items() if isinstance(items, dict) else items)]
    seen = set()
    for v in varies:
        if v.path in seen:
            raise InputError(source, v.path, "varied twice: give each PATH once")
        seen.add(v.path)
    return varies


def _rounded(values):
    return np.array([float(f"{v:.{DIGITS}g}") for v in values])


def design(varies: Iterable[str | tuple[str, str] | Vary] | dict[str, str], samples: int | None = None, seed: int | None = None,
           sampling: str = "lhs") -> pd.DataFrame:
    """The parameter sets, one row per run, one column per varied path (in order).

    Grids: the full product, the last path varying fastest. Distributions: ``samples``
    draws, Latin hypercube (``sampling="lhs"``) or plain Monte Carlo (``"mc"``), seeded by
    ``seed`` (default :data:`DEFAULT_SEED`). Grids and distributions are not mixed.

    Parameters
    ----------
    varies : ``PATH=SPEC`` texts, ``(path, spec)`` pairs, :class:`Vary` objects or a dict {path: spec};
        SPEC is ``LO:HI:N`` (a grid), ``normal:MEAN:SD`` or ``uniform:LO:HI``, in the unit of the
        path's rig field (SI: m, kg, N/m, ...).
    samples : number of draws of distributions.
    seed : random seed of the draws.
    sampling : ``lhs`` or ``mc``.

    Returns
    -------
    pandas.DataFrame
        One row per run, one column per path, values in the path's unit (rounded to :data:`DIGITS`
        significant digits).
    """
    varies = parse_varies(varies)
    if not varies:
        raise InputError("--vary", "vary", "give at least one PATH=SPEC")
    grids = [v for v in varies if v.is_grid]
    if grids and len(grids) != len(varies):
        other = next(v for v in varies if not v.is_grid)
        raise InputError("--vary", other.path, f"{other.kind} distribution mixed with the grid of {grids[0].path}: "
                         "one sweep uses grids (LO:HI:N) or distributions (normal:, uniform:), not both")
    if grids:
        if samples is not None:
            raise InputError("--samples", "samples", "applies to distributions only: a grid's size is the "
                             "product of its N")
        total = math.prod(v.n for v in varies)
        if total > MAX_RUNS:
            raise InputError("--vary", varies[0].path, f"the grids make {total} runs (at most {MAX_RUNS})")
        rows = list(itertools.product(*(_rounded(v.grid()) for v in varies)))
        return pd.DataFrame(rows, columns=[v.path for v in varies], dtype=float)
    if samples is None:
        raise InputError("--samples", "samples", "random draws need --samples N (the number of runs)")
    if isinstance(samples, bool) or int(samples) != samples or samples < 1 or samples > MAX_RUNS:
        raise InputError("--samples", "samples", f"must be a whole number from 1 to {MAX_RUNS}, got {samples}")
    seed = DEFAULT_SEED if seed is None else seed
    if isinstance(seed, bool) or int(seed) != seed or seed < 0:
        raise InputError("--seed", "seed", f"must be a whole number >= 0, got {seed}")
    if sampling not in SAMPLING:
        raise ValueError(f"sampling must be one of {', '.join(SAMPLING)}")
    rng = np.random.default_rng(int(seed))
    if sampling == "lhs":
        try:
            lhs = qmc.LatinHypercube(d=len(varies), rng=rng)
        except TypeError:  # scipy < 1.15
            lhs = qmc.LatinHypercube(d=len(varies), seed=rng)
        u = lhs.random(int(samples))
    else:
        u = rng.random((int(samples), len(varies)))
    cols = {v.path: _rounded(v.from_unit(u[:, j])) for j, v in enumerate(varies)}
    return pd.DataFrame(cols, dtype=float)

"""Where a fit's optimiser starts: the given starts clipped into the bounds and ranked by their
cost (all simulated at once), and coarse grid scans whose best points become starts."""
from __future__ import annotations

import itertools

import numpy as np

from .objective import Objective


def start_points(obj: Objective, starts, method: str, max_starts: int) -> list:
    """The optimiser's start points (internal coordinates): the parameters' own values and
    ``starts`` (dicts, each parameter's unit), just inside the bounds, without repeats; with
    several and a least-squares fit, the ``max_starts`` of lowest cost."""
    varied = obj.varied
    points = [obj.x0()]
    for s in starts or []:
        points.append(np.array([p.to_internal(float(np.clip(s.get(p.name, p.value), p.min, p.max)))
                                for p in varied]))
    lo, hi = obj.bounds()
    points = [np.clip(x0, lo + 1e-9 * np.minimum(hi - lo, 1e9), hi - 1e-9 * np.minimum(hi - lo, 1e9))
              for x0 in points]
    # a start given twice (a scan's own point is the fit's own start) would run the optimiser twice
    unique = {}
    for x0 in points:
        unique.setdefault(tuple(np.round(x0, 12)), x0)
    points = list(unique.values())
    if len(points) > 1 and method != "nelder-mead":
        points = rank_starts(obj, points)[:max_starts]
    return points


def rank_starts(obj: Objective, points) -> list:
    """Start points ordered by their cost (all simulated at once on the pool, alignment fitted
    for each): the optimiser then runs from the best only."""
    vals = [obj.values(x) for x in points]
    curves = obj.curves(vals)
    scored = []
    for x, v, cur in zip(points, vals, curves):
        v = obj.align(v, cur)
        r = np.concatenate(obj.residual_parts(v, cur))
        scored.append((float(np.dot(r, r)), obj.internal_with_alignment(x, v)))
    scored.sort(key=lambda c: c[0])
    return [x for _, x in scored]


def scan_starts(datasets, effects, spring_model, params: dict, grid: dict, keep: int = 1, pool=None,
                scales: dict | None = None, step: float | None = None, bases: list | None = None) -> list[dict]:
    """Evaluate the cost on a coarse grid with the other parameters at their current values, or
    at each of ``bases``, all grid points simulated at once on the pool; return the ``keep`` best
    points of each base as start dicts.

    Parameters
    ----------
    datasets : sequence of Dataset
    effects : sequence of str
    spring_model : SpringModel or str, optional
        Default: the first dataset's rig's.
    params : dict of str to Parameter
    grid : dict of str to sequence of float
        Values of each varied parameter to try (the parameter's unit).
    keep : int
        Best points returned per base.
    pool : SimulationPool, optional
    scales : dict, optional
        (dataset, channel) -> residual weight (the channel's unit).
    step : float, optional
        Integration step (s).
    bases : list of dict, optional
        Values (the parameters' units) the grid is laid around.
    """
    obj = Objective(datasets, effects, spring_model or datasets[0].rig.model.spring_model, params, pool, scales,
                    step)
    names = [n for n in grid if n in params and params[n].vary]
    combos = [dict(zip(names, c)) for c in itertools.product(*(grid[n] for n in names))]
    if not combos:
        return []
    combos.append({n: params[n].value for n in names})  # the parameters' own starting values
    bases = bases or [{}]
    out = []
    for base in bases:
        out += _best_of_grid(obj, params, [{**{k: v for k, v in base.items() if k in params}, **c} for c in combos],
                             keep)
    return out


def _best_of_grid(obj, params, combos, keep):
    """The ``keep`` grid points of lowest cost (alignment fitted for each; failed simulations
    dropped), each with its fitted alignment values."""
    vals_list = []
    for start in combos:
        vals = {p.name: p.value for p in params.values()}
        vals.update({k: float(np.clip(v, params[k].min, params[k].max)) for k, v in start.items()})
        vals_list.append(vals)
    curves = obj.curves(vals_list)
    scored = []
    for start, vals, cur in zip(combos, vals_list, curves):
        if any(c is None for c in cur):
            continue
        v = obj.align(vals, cur)
        r = np.concatenate(obj.residual_parts(v, cur))
        scored.append((float(np.dot(r, r)), {**start, **{p.name: v[p.name] for p in obj.varied if not p.simulated}}))
    scored.sort(key=lambda s: s[0])
    return [s for _, s in scored[:keep]]

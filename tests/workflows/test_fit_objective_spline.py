"""The fits' spline of a simulated channel (objective.GridSpline): scipy's not-a-knot CubicSpline to the
bit, with the grid's part computed once."""
import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from vcbmodel.analysis.fit.objective import Curves, GridSpline, spline_on_grid


def _grids():
    rng = np.random.default_rng(7)
    uniform = np.arange(6056) * 0.0010000000000000009  # a 1 kHz record's simulation grid
    uneven = np.cumsum(rng.uniform(0.5e-3, 1.5e-3, 500))
    return [uniform, uneven, np.array([0.0, 0.1, 0.25, 0.3])]


@pytest.mark.parametrize("k", range(3))
def test_grid_spline_is_cubic_spline_to_the_bit(k):
    x = _grids()[k]
    rng = np.random.default_rng(k)
    grid = GridSpline(x)
    for y in (np.sin(7 * x) * np.exp(-x) + 1e-4 * rng.normal(size=x.size), rng.normal(size=x.size)):
        ours, scipy = grid(y), CubicSpline(x, y)
        assert np.array_equal(ours.c, scipy.c) and np.array_equal(ours.x, scipy.x)
        tau = np.clip(x - 0.3 * np.median(np.diff(x)), x[0], x[-1])
        assert np.array_equal(ours(tau), scipy(tau))
        assert np.array_equal(ours(tau, 1), scipy(tau, 1))


def test_a_curve_spline_keeps_scipy_behaviour_at_the_edges():
    x = _grids()[0][:100]
    y = np.cos(x)
    bad = y.copy()
    bad[50] = np.nan
    with pytest.raises(ValueError, match="finite"):
        spline_on_grid(x, bad)
    short = spline_on_grid(x[:3], y[:3])  # under 4 points: scipy's own (a parabola)
    assert np.array_equal(short(x[:3] + 1e-4), CubicSpline(x[:3], y[:3])(x[:3] + 1e-4))
    curves = Curves({"t": x, "angle": y})
    assert curves.spline("angle") is curves.spline("angle")
    assert np.array_equal(curves.spline("angle")(x[5:9] + 1e-4), CubicSpline(x, y)(x[5:9] + 1e-4))

"""The profile of one fitted parameter (vcbmodel/analysis/fit/profile.py): refits with it held
outward of its stated 95 % ends until the record rejects a point. On a quadratic cost whose curvature
is the stated error's the profile's ends are the stated ones; on a valley four times flatter they
lie four times further out, with every other value interpolated to the end."""
import pytest

from vcbmodel.analysis.fit import Parameter
from vcbmodel.analysis.fit.profile import Z95, profile

N = 1000  # samples less varied parameters: the white chi^2 at the optimum is N, so s^2 = 1


class FakeFit:
    """A fit of x (the profiled value) and y = 1 + 2 x, whose cost rises as ((x - 0.5) / width)^2."""

    def __init__(self, x, width, stderr, stderr_naive, vary=True):
        self.x, self.width = x, width
        self.parameters = {"x": Parameter("x", x, -5.0, 5.0, vary, stderr=stderr, stderr_naive=stderr_naive),
                           "y": Parameter("y", 1.0 + 2.0 * x, -50.0, 50.0, True)}
        self.n_data, self.n_varied, self.n_other = N + 2, 2, 0  # one channel: no other channels

    def chi2_with(self, noise):
        assert noise is None  # the Jacobian's white scale
        return N + ((self.x - 0.5) / self.width) ** 2


def run(width, stderr, stderr_naive):
    best = FakeFit(0.5, width, stderr, stderr_naive)
    calls = []

    def held(value, start):
        calls.append((value, start.x))
        return FakeFit(value, width, None, None, vary=False)

    pr = profile(best, "x", held, lambda f: {"x": f.x, "y": f.parameters["y"].value})
    return pr, calls


def test_a_quadratic_cost_keeps_the_stated_interval_with_one_refit_a_side():
    pr, calls = run(width=0.1, stderr=0.1, stderr_naive=0.1)
    assert pr.stated == pytest.approx((0.5 - Z95 * 0.1, 0.5 + Z95 * 0.1))
    assert (pr.low, pr.high) == pytest.approx(pr.stated)
    assert not pr.wider and len(calls) == 2
    assert pr.ends[1]["y"] == pytest.approx(1.0 + 2.0 * pr.high)


def test_a_stated_error_widened_for_a_correlated_residual_scales_the_cost_alike():
    """stderr twice the white-noise one: the cost's rise is read on the stated scale (a quarter),
    so the profile's ends are the stated ones, not the narrower white-noise ones."""
    pr, _ = run(width=0.1, stderr=0.2, stderr_naive=0.1)
    assert (pr.low, pr.high) == pytest.approx((0.5 - Z95 * 0.2, 0.5 + Z95 * 0.2))
    assert not pr.wider


def test_a_valley_flatter_than_its_stated_error_widens_the_interval_and_moves_the_other_values():
    """The cost four times flatter than the stated error says: the ends lie four stated half-widths
    out (the 3rd step is rejected, the end interpolated in sqrt of the rise), each refit starting from
    the one before, and y at each end is y of the end's x."""
    pr, calls = run(width=0.4, stderr=0.1, stderr_naive=0.1)
    assert (pr.low, pr.high) == pytest.approx((0.5 - 4 * Z95 * 0.1, 0.5 + 4 * Z95 * 0.1))
    assert pr.wider and len(calls) == 6
    assert calls[1][1] == pytest.approx(calls[0][0]) and calls[0][1] == 0.5  # continued from the point before
    assert pr.ends[0]["y"] == pytest.approx(1.0 + 2.0 * pr.low)
    assert pr.to_json()["profile"] == pytest.approx([pr.low, pr.high])


def test_no_profile_without_a_finite_stated_error():
    best = FakeFit(0.5, 0.1, None, None)
    assert profile(best, "x", lambda v, s: None, lambda f: {}) is None

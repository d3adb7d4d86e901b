"""The design studies' inputs and statistics (vcbmodel/analysis/design.py): every distribution names its
source, the bearing estimate is its Petroff calculation, the per-pole evaluation, the Wilson interval
and the split of a tolerance study's mean shift."""
import math

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.analysis.design import (breaker_factors, closing_poles, mean_shift, pole_columns, wilson,
                                      with_viscous_shaft)
from vcbmodel.experiments.loading import load_rig

from conftest import write_rig


@pytest.fixture(scope="module")
def rig(tmp_path_factory):
    return load_rig(write_rig(tmp_path_factory.mktemp("design"), with_viscous_shaft(P.REFERENCE_BREAKER), "breaker"))


def test_the_bearing_estimate_is_petroffs():
    """Cv = 2 bearings x 2 pi mu r^3 L / c at the stated ends (mu 0.05-0.4 Pa s, r 20 mm, L 30 mm, c 37.5-12.5 um)."""
    def petroff(mu, c):
        return 2 * 2 * math.pi * mu * 0.02**3 * 0.03 / c
    lo, hi = P.VISCOUS_BEARING_ESTIMATE
    assert lo == pytest.approx(petroff(0.05, 37.5e-6), rel=0.01)
    assert hi == pytest.approx(petroff(0.4, 12.5e-6), rel=0.01)
    assert hi * 150.0 < 0.5 * 47.6  # at the cam's 150 rad/s well under the springs' torque at release


def test_every_factor_names_its_source_and_the_ranges_are_the_sourced_ones(rig):
    factors = {f.key: f for f in breaker_factors(rig)}
    assert all(len(f.basis) > 20 for f in factors.values())
    v, e = factors["viscous"], factors["restitution"]
    assert (v.low, v.high) == pytest.approx(P.VISCOUS_BEARING_ESTIMATE) and v.distribution == "uniform"
    assert "Petroff" in v.basis
    assert (e.low, e.high) == pytest.approx(P.RESTITUTION_RANGE) and e.distribution == "uniform"
    assert "Goldsmith" in e.basis or "Johnson" in e.basis
    # another range, with its own source, when a study asks for it
    old = {f.key: f for f in breaker_factors(rig, viscous_range=P.VISCOUS_PENDULUM_RANGE, viscous_basis="pendulum")}
    assert (old["viscous"].low, old["viscous"].high) == pytest.approx(P.VISCOUS_PENDULUM_RANGE)
    assert "pendulum" in old["viscous"].basis


def test_wilson_interval():
    """Wilson's score interval: 0 of 20 -> [0, 0.161]; 10 of 20 -> [0.299, 0.701] (z = 1.96)."""
    assert wilson(0, 20) == pytest.approx((0.0, 0.1611), abs=1e-4)
    assert wilson(10, 20) == pytest.approx((0.2993, 0.7007), abs=1e-4)
    assert all(math.isnan(x) for x in wilson(0, 0))


def test_mean_shift_splits_a_linear_response_exactly_and_names_the_curvature():
    rng = np.random.default_rng(1)
    x = rng.uniform([0.0, 1.0], [2.0, 3.0], size=(400, 2))
    nominal = np.array([0.2, 2.0])
    linear = 2.0 * x[:, 0] - 3.0 * x[:, 1] + 5.0
    m = mean_shift(x, linear, nominal, 2.0 * 0.2 - 3.0 * 2.0 + 5.0)
    assert m["shares"] == pytest.approx([2.0 * (x[:, 0].mean() - 0.2), -3.0 * (x[:, 1].mean() - 2.0)])
    assert abs(m["curvature"]) < 1e-9 and m["r2"] == pytest.approx(1.0)
    curved = linear + (x[:, 0] - 1.0) ** 2  # the nominal sits off the line through the draws
    m2 = mean_shift(x, curved, nominal, 2.0 * 0.2 - 3.0 * 2.0 + 5.0 + 0.64)
    assert m2["shift"] == pytest.approx(sum(m2["shares"]) + m2["curvature"])
    assert abs(m2["curvature"]) > 0.1


def test_closing_poles_reports_every_pole(rig):
    """Every pole's zone speed, bounce count and duration, and the slowest and fastest zone speed."""
    out = closing_poles(rig)
    assert set(pole_columns(3)) <= set(out)
    zones = [out[f"pole_{i}_zone_speed_m_s"] for i in (1, 2, 3)]
    assert out["zone_speed_min_m_s"] == min(zones) and out["zone_speed_max_m_s"] == max(zones)
    assert out["closing_speed_m_s"] == pytest.approx(np.mean(zones))
    assert out["bounce_count"] == max(out[f"pole_{i}_bounces"] for i in (1, 2, 3))
    assert out["bounce_duration_s"] == max(out[f"pole_{i}_bounce_s"] for i in (1, 2, 3))
    # the kinetic margin after the touch: the reference's cam reaches its latch at 51.8 ms
    assert out["latched"] is True and 0.0 < out["kinetic_margin_J"] < out["kinetic_at_touch_J"]
    short = closing_poles(rig, t_end=0.045)  # the run ends before the cam reaches its latch: not known
    assert short["latched"] is None and short["kinetic_margin_J"] is None

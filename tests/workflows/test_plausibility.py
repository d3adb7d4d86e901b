"""Physical plausibility (vcbmodel/analysis/plausibility.py): documented ranges with sources in
vcbmodel/parameters.py, the law's own constraint, and errors that say a value is not determined."""
import math

import pytest

from vcbmodel import parameters as P
from vcbmodel.analysis.plausibility import SOURCES, implausible, plausible_range


def test_viscous_friction_is_bounded_by_petroffs_film_torque(pendulum_rig):
    r = pendulum_rig.shaft_radius
    lo, hi = plausible_range("viscous", pendulum_rig)
    petroff = 2 * math.pi * P.PETROFF_VISCOSITY[1] * r**3 * (P.PETROFF_LENGTH_RATIO[1] * 2 * r) / (
        P.PETROFF_CLEARANCE_RATIO[0] * r)
    assert (lo, hi) == (0.0, pytest.approx(petroff))
    assert 5.0 < hi < 10.0  # 8 N m s/rad at r = 20 mm
    assert not implausible(pendulum_rig, {"viscous": 0.6}, {"viscous": 0.01})
    found = implausible(pendulum_rig, {"viscous": 3 * hi}, {"viscous": 0.01})
    assert [f.kind for f in found] == ["outside"] and "Petroff" in found[0].message


def test_air_drag_is_bounded_by_a_large_paddle(pendulum_rig):
    lo, hi = plausible_range("drag", pendulum_rig)
    radius = P.DRAG_MAX_RADIUS_OVER_COM * pendulum_rig.pendulum.com_distance
    assert hi == pytest.approx(0.5 * P.AIR_DENSITY * P.DRAG_MAX_CD * P.DRAG_MAX_AREA * radius**3)
    # the discovery demo's first drag (0.01 N m s^2 for a 0.02 m^2 paddle at 0.3 m) stands 25 times above
    # 0.5 rho Cd A R^3 for that paddle, but a large paddle could give it: the range is not a point
    assert not implausible(pendulum_rig, {"drag": 0.5 * 1.2 * 1.17 * 0.02 * 0.3**3}, {})


def test_the_issues_cases_are_said_plainly(pendulum_rig):
    """mu_s below mu_k with an error of 2.9e12 (said: outside its range, not determined); mu_s below mu_k
    by more than the errors allow; mu_k 24 times too low."""
    found = implausible(pendulum_rig, {"mu_k": 0.038, "mu_s": 1.5e-9, "viscous": 0.6},
                        {"mu_k": 0.001, "mu_s": 2.9e12, "viscous": 0.01})
    kinds = {(f.name, f.kind) for f in found}
    assert {("mu_s", "outside"), ("mu_s", "stderr")} <= kinds
    below = implausible(pendulum_rig, {"mu_k": 0.12, "mu_s": 0.10}, {"mu_k": 0.001, "mu_s": 0.003})
    assert [(f.name, f.kind) for f in below] == [("mu_s", "constraint")]
    assert not implausible(pendulum_rig, {"mu_k": 0.12, "mu_s": 0.118}, {"mu_k": 0.001, "mu_s": 0.003})
    assert not any(f.name in ("mu_k", "viscous") for f in found)
    low = implausible(pendulum_rig, {"mu_k": 0.0056}, {"mu_k": 0.001})
    assert [(f.name, f.kind) for f in low] == [("mu_k", "outside")]
    assert "steel journal" in low[0].message
    assert implausible(pendulum_rig, {"mu_k": 0.1}, {"mu_k": math.inf})[0].kind == "stderr"


def test_every_range_has_a_source_and_is_ordered(pendulum_rig):
    for name, source in SOURCES.items():
        lo, hi = plausible_range(name, pendulum_rig)
        assert lo < hi and source
    assert plausible_range("discovered:w_abs_w", pendulum_rig) is None

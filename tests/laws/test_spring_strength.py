"""The closing spring checked as a spring maker would (vcbmodel/laws/spring_strength.py): limits and
identities of Shigley's formulas, and the reference breaker's spring, which fails as an extension spring."""
import copy
import math

import pytest

from vcbmodel import parameters as P
from vcbmodel.experiments.loading import load_rig
from vcbmodel.laws.coil import coil_stiffness, wire_strength
from vcbmodel.laws.spring_strength import (bergstrasser_factor, body_stress, closing_pulls, compression_reading,
                                           critical_deflection, extension_checks, goodman_factor, hook_bending_stress,
                                           hook_torsion_stress, initial_tension_range, wire_for_index)

from conftest import write_rig

PSI = 6894.757  # Pa


def test_curvature_factors_vanish_for_a_slender_coil():
    """At a large index the body and hook factors tend to 1: the straight bar's 8 F D / (pi d^3) in
    torsion and, at the hook, the bending of F D / 2 plus the direct tension 4 F / (pi d^2)."""
    d, D, F = 0.001, 0.2, 100.0  # index 200
    torsion = 8 * F * D / (math.pi * d**3)
    assert body_stress(F, d, D) == pytest.approx(torsion, rel=0.01)
    assert hook_bending_stress(F, d, D) == pytest.approx(32 * F * D / 2 / (math.pi * d**3) + 4 * F / (math.pi * d**2), rel=0.01)
    assert hook_torsion_stress(F, d, D, bend_index=200.0) == pytest.approx(torsion, rel=0.01)
    assert bergstrasser_factor(6.0) == pytest.approx(26.0 / 21.0)


def test_goodman_factor_is_one_on_the_tables_own_cycle():
    """A stress cycling from zero to the table's R = 0 strength sits on Goodman's line: n_f = 1; half
    as high: more than 2 (the mean's share falls with the amplitude)."""
    assert goodman_factor(500e6, 0.0, 500e6, 1400e6) == pytest.approx(1.0)
    assert goodman_factor(250e6, 0.0, 500e6, 1400e6) > 2.0
    assert goodman_factor(500e6, 250e6, 500e6, 1400e6) > 1.0  # the same peak with less amplitude


def test_initial_tension_range_is_shigleys_in_psi():
    """Shigley eq. 10-39 in its own units: tau_i = 33500 / exp(0.105 C) +- 1000 (4 - (C - 3) / 6.5) psi."""
    d, D = 0.00784, 0.047
    C = D / d
    centre, half = 33500 / math.exp(0.105 * C), 1000 * (4 - (C - 3) / 6.5)
    lo, hi = initial_tension_range(d, D)
    per = math.pi * d**3 / (8 * D)
    assert lo == pytest.approx((centre - half) * PSI * per, rel=2e-3)
    assert hi == pytest.approx((centre + half) * PSI * per, rel=2e-3)


def test_buckling_limit_is_shigleys_absolute_stability():
    """Steel springs are absolutely stable below L0 = 2.63 D / alpha (Shigley eq. 10-13); just above it
    they buckle at a finite deflection, and pivoted ends buckle sooner than ground ends."""
    D = 0.05
    assert critical_deflection(2.6 * D / 0.5, D, "fixed-fixed") == math.inf
    y = critical_deflection(2.7 * D / 0.5, D, "fixed-fixed")
    assert 0 < y < 2.7 * D / 0.5
    assert critical_deflection(6 * D, D, "pivoted-pivoted") < critical_deflection(6 * D, D, "fixed-fixed")


def test_the_thinnest_wire_that_passes_is_on_the_edge_of_a_check():
    """wire_for_index's spring has the asked rate, and its worst check sits at its allowable."""
    s = wire_for_index(6.0, 24230.0, 3000.0, 500.0)
    d, D = s["wire_diameter_m"], s["coil_diameter_m"]
    assert coil_stiffness(d, D, s["active_coils"], P.DEFAULT_SHEAR_MODULUS) == pytest.approx(24230.0)
    ratios = [c.ratio for c in extension_checks(d, D, 3000.0, 500.0)[:6]]
    assert max(ratios) == pytest.approx(1.0, abs=1e-6)
    thinner = [c.ratio for c in extension_checks(0.99 * d, 0.99 * D, 3000.0, 500.0)[:6]]
    assert max(thinner) > 1.0
    plugs = wire_for_index(6.0, 24230.0, 3000.0, 500.0, hooks=False)
    assert plugs["wire_diameter_m"] < d  # without hooks the body alone decides: a thinner wire


def test_reference_spring_fails_as_an_extension_spring(tmp_path):
    """The reference breaker's spring (7.84 mm wire on 47.0 mm, k0 24230 N/m) cycles 500-3000 N; as an
    extension spring with standard hooks (hand calculation: body 0.92 GPa with Bergstrasser's factor
    against 0.45 S_ut = 0.72 GPa; hook bending 1.76 GPa against 0.75 S_ut = 1.20 GPa) it fails; as a
    compression spring its body passes (0.65 S_ut = 1.04 GPa) but it buckles unless guided."""
    rig = load_rig(write_rig(tmp_path, copy.deepcopy(P.REFERENCE_BREAKER), "ref"))
    high, low = closing_pulls(rig.closing_spring, rig.cam)
    assert high == pytest.approx(P.REFERENCE_SPRING_CHARGED, rel=0.01)
    assert low == pytest.approx(P.REFERENCE_SPRING_DISCHARGED, rel=0.01)
    d, D = 0.00784, 0.0470
    checks = {c.name.split(" (")[0]: c for c in extension_checks(d, D, high, low)}
    s_ut = wire_strength(d)
    assert checks["body torsion"].value == pytest.approx(0.922e9, rel=0.01)
    assert checks["body torsion"].allowable == pytest.approx(0.45 * s_ut)
    assert checks["hook bending"].value == pytest.approx(1.763e9, rel=0.01)
    assert not checks["body torsion"].passes and not checks["hook bending"].passes
    assert not checks["body fatigue"].passes
    n_a = P.DEFAULT_SHEAR_MODULUS * d**4 / (8 * D**3 * 24230.0)
    comp = compression_reading(d, D, n_a, 24230.0, high)
    assert comp["body_stress_Pa"] < comp["allowable_Pa"]
    assert comp["buckles_at_pivoted-pivoted_m"] < comp["deflection_m"]


def test_check_reports_the_spring_makers_checks(tmp_path):
    """`vcbmodel check` on the reference breaker names each check with its allowable and says it fails."""
    from vcbmodel.app.templates import explain

    rig = load_rig(write_rig(tmp_path, copy.deepcopy(P.REFERENCE_BREAKER), "ref"))
    text = "\n".join(explain(rig))
    for name in ("body torsion:", "hook bending (A):", "hook torsion (B", "body fatigue:", "initial tension"):
        assert name in text, name
    assert "FAILS 6 of 6 strength checks" in text and "screwed-in plug ends" in text
    assert "compression spring" in text and "guide" in text


def test_the_compression_reading_counts_the_coils_in_the_rigs_own_wire(tmp_path):
    """A datasheet spring in a wire of G = 69 GPa (stainless): check's compression reading has the
    datasheet's 15 active coils in its free length (solid (n_a + 2) d + 1.15 x the deflection), not the
    coils a 79.3 GPa steel wire of the same rate would need."""
    from vcbmodel.app.templates import explain

    data = copy.deepcopy(P.REFERENCE_BREAKER)
    spring = data["closing_spring"]
    for key in ("stiffness", "mass"):
        spring.pop(key, None)
    spring.update(wire_diameter=0.0078, coil_diameter=0.047, active_coils=15, shear_modulus=69e9)
    rig = load_rig(write_rig(tmp_path, data, "stainless"))
    high, _ = closing_pulls(rig.closing_spring, rig.cam)
    free = (15 + 2) * 0.0078 + (1 + P.CLASH_ALLOWANCE) * high / rig.closing_spring.stiffness
    line = next(x for x in explain(rig) if "read as a compression spring" in x)
    assert f"free length {1e3 * free:.0f} mm" in line

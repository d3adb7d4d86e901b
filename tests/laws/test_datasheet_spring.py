"""A closing spring given by its datasheet (wire and mean diameter, active coils, shear modulus):
k0, the active mass and the surge frequency follow; given values must agree; the stress check."""
import json

import pytest

from vcbmodel import parameters as P
from vcbmodel.app.templates import explain
from vcbmodel.errors import InputError
from vcbmodel.experiments.loading import load_rig
from vcbmodel.laws.coil import coil_stiffness, spring_check, surge_frequency, wire_strength

from conftest import write_rig

SHEET = {"wire_diameter": 0.00784, "coil_diameter": 0.047, "active_coils": 15.0, "shear_modulus": 79.3e9}


def datasheet_rig(tmp_path, **changes):
    rig = json.loads(json.dumps(P.REFERENCE_CAM))
    spring = {k: v for k, v in rig["closing_spring"].items() if k not in ("stiffness", "mass")}
    spring.update(SHEET)
    spring.update(changes)
    rig["closing_spring"] = {k: v for k, v in spring.items() if v is not None}
    return write_rig(tmp_path, rig, "sheet")


def test_datasheet_gives_rate_mass_and_a_surge_frequency_like_wahls_rule(tmp_path):
    rig = load_rig(datasheet_rig(tmp_path))
    s = rig.closing_spring
    assert set(s.from_datasheet) == {"stiffness", "mass"}
    assert s.stiffness == pytest.approx(24047, rel=1e-3)  # G d^4 / (8 D^3 n)
    # the wire's volume times steel's density
    assert s.mass == pytest.approx(7850 * 3.14159265 * 0.00784**2 / 4 * 3.14159265 * 0.047 * 15, rel=1e-6)
    # Shigley's rule for steel springs (sec. 10-10): f = 14 000 d / (D^2 N_a) Hz with d, D in inches,
    # 355.6 d / (D^2 N_a) in metres: an independent form (no density or modulus in it)
    wahl = 14000 * 0.0254 * 0.00784 / (0.047**2 * 15)
    assert surge_frequency(s.stiffness, s.mass) == pytest.approx(wahl, rel=0.01)


def test_given_and_datasheet_values_must_agree(tmp_path):
    with pytest.raises(InputError, match="closing_spring.stiffness.*datasheet fields give"):
        load_rig(datasheet_rig(tmp_path, stiffness=30000.0))
    # within catalogue rounding they may both be given
    rig = load_rig(datasheet_rig(tmp_path, stiffness=24500.0))
    assert rig.closing_spring.stiffness == 24500.0 and rig.closing_spring.from_datasheet == ("mass",)


def test_a_datasheet_without_shear_modulus_is_refused_not_defaulted(tmp_path):
    with pytest.raises(InputError, match="closing_spring.stiffness: missing.*shear_modulus"):
        load_rig(datasheet_rig(tmp_path, shear_modulus=None))


def test_stress_check_against_shigley(tmp_path):
    rig = load_rig(datasheet_rig(tmp_path))
    c = spring_check(rig.closing_spring, 3000.0)
    # 8 F D / (pi d^3) with Wahl's factor at C = 6.0: 0.93 GPa at 3 kN
    assert c["shear_stress_Pa"] == pytest.approx(0.93e9, rel=0.01)
    # Shigley Table 10-4, Cr-Si (A401): S_ut = 2005 / d^0.108 MPa, d in mm
    assert wire_strength(0.00784) == pytest.approx(2005 / 7.84**0.108 * 1e6, rel=1e-9)
    assert c["stress_ratio"] > 1.0  # above 0.45 S_ut of an extension spring's body
    text = "\n".join(explain(rig))
    assert "from the datasheet" in text and "body torsion:" in text and "FAILS" in text
    # the body's stress is judged once (Bergstrasser's factor), not again with Wahl's beside it
    assert "(Wahl)" not in text and text.count("body torsion:") == 1


def test_coil_stiffness_scales_as_d4_over_d3_n():
    k = coil_stiffness(0.008, 0.048, 12, 79.3e9)
    assert coil_stiffness(0.016, 0.048, 12, 79.3e9) == pytest.approx(16 * k)
    assert coil_stiffness(0.008, 0.096, 12, 79.3e9) == pytest.approx(k / 8)
    assert coil_stiffness(0.008, 0.048, 24, 79.3e9) == pytest.approx(k / 2)


def test_check_says_the_density_a_datasheet_springs_mass_rests_on(tmp_path):
    """The mass from a datasheet without `density` is steel's (documented): check says so, not only
    'from the datasheet'; a given density is the rig's."""
    text = "\n".join(explain(load_rig(datasheet_rig(tmp_path))))
    assert "active mass" in text and "from the datasheet, at steel's 7850 kg/m^3: no density given" in text
    text = "\n".join(explain(load_rig(datasheet_rig(tmp_path, density=8000.0))))
    assert "no density given" not in text and "kg (from the datasheet)" in text

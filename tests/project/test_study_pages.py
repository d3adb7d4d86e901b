"""The studies' pages say what their run computed: the prose's numbers are the computed values, and a
claim that depends on them is printed only where they support it."""
import importlib.util
from pathlib import Path

import numpy as np
import pytest

STUDIES = Path(__file__).resolve().parents[2] / "studies"


@pytest.fixture
def study(monkeypatch):
    monkeypatch.syspath_prepend(str(STUDIES))  # the studies import their _common

    def load(name):
        spec = importlib.util.spec_from_file_location(name, STUDIES / f"{name}.py")
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return module

    return load


def test_the_optimum_page_prints_the_equal_speed_gain_it_computed(study):
    s = study("design_optimum")
    c = {"gain_at_own_speed_percent": 8.0, "speed_squared_share_percent": 5.7, "stored_gain_percent": 1.8,
         "reference_at_target_within_limits": False, "reference_at_target_breaks": ["pole_spread_s over 2 ms"]}
    text = s.comparison_text(c)
    assert "the gain is 1.8 %" in text and "about 1 %" not in text
    assert "outside the limits (pole_spread_s over 2 ms)" in text and "slack" not in text
    assert "within the assumed margins" not in s.comparison_text(dict(c, stored_gain_percent=7.0))
    loss = s.comparison_text(dict(c, stored_gain_percent=-1.5))  # the optimum stores more: no gain of 1.5 %
    assert "the gain is" not in loss and "the optimum stores 1.5 % more than the reference, under 2 %" in loss
    assert "the optimum's gain is -1.5 %" in loss


def test_the_optimum_names_the_limits_a_design_breaks(study):
    s = study("design_optimum")
    ok = {"closing_speed_m_s": 1.25, "zone_speed_min_m_s": 1.24, "zone_speed_max_m_s": 1.26, "pole_spread_s": 5e-4,
          "preload_N": 3000.0, "min_spring_force_N": 500.0, "latched": True}
    assert s.broken_limits(ok) == []
    broke = s.broken_limits(dict(ok, min_spring_force_N=100.0, zone_speed_max_m_s=1.6))
    assert len(broke) == 2 and any("slack" in b for b in broke) and any("zone speed" in b for b in broke)
    assert s.broken_limits(dict(ok, pole_spread_s=3e-3)) == ["pole spread over 2 ms"]  # not the column's name


def test_the_spring_reading_page_quotes_its_own_table(study):
    s = study("spring_reading")
    rows = [s.reading(*r) for r in s.READINGS]
    text = s.conclusion(rows)
    each = [r["shear_stress_Pa"] / 1e9 for r in rows if r["force_per_spring_N"] == s.CHARGED]
    assert f"{min(each):.2f}-{max(each):.2f} GPa" in text and "1.8-3.3" not in text
    assert f"{rows[3]['pair_energy_6000_to_1000_N_J']:.0f} J" in text
    assert text.startswith("Only m0 as eq. 8's chain parameter")
    # a reading whose frequency also met f0 would take the claim away
    rows[0] = dict(rows[0], fixed_fixed_frequency_hz=s.F0_PAPER)
    other = s.conclusion(rows)
    assert not other.startswith("Only")
    assert f"reading (within {100 * s.F0_MATCH:g} %); with m0 as eq. 8's chain parameter, the spring's fixed-fixed" in other  # not "its"


def test_the_conclusion_map_names_the_side_only_where_the_ratios_order_it(study):
    s = study("design_conclusion_map")
    ordered = np.array([[2.0, 3.0], [0.5, 0.8]])  # rows: spring mass, columns: mu_k
    grids = {col: ordered for col, _ in s.RATIOS}
    assert s.where_it_holds(grids).startswith("left of the black line")
    grids[s.RATIOS[0][0]] = np.array([[2.0, 3.0], [2.5, 0.8]])  # heavier spring, larger ratio at low mu_k
    assert not s.where_it_holds(grids).startswith("left")
    failed = {col: np.full((2, 2), np.nan) for col, _ in s.RATIOS}  # every run failed: nothing is ordered
    assert not s.where_it_holds(failed).startswith("left")


def test_the_tolerance_page_says_where_the_bounce_limit_falls_among_the_counts(study):
    s = study("design_tolerance")
    limit = 1e-3 * s._BOUNCE["max"]
    text = s.cluster_text({1: {"min": 0.4 * limit, "max": 0.6 * limit}, 2: {"min": 0.8 * limit, "max": 1.2 * limit}})
    assert f"{1e3 * 0.8 * limit:.2f}-{1e3 * 1.2 * limit:.2f} ms with 2" in text and "with 2 bounce(s)." in text
    one, three = {"min": 0.4 * limit, "max": 0.6 * limit}, {"min": 1.4 * limit, "max": 1.6 * limit}
    assert "falls between the poles with 1 and with 3 bounce(s)" in s.cluster_text({1: one, 3: three})
    # a limit below (above) every count's durations does not fall "between the counts"
    assert "lies below every count's durations" in s.cluster_text({3: three})
    assert "lies above every count's durations" in s.cluster_text({0: {"min": 0.0, "max": 0.0}, 1: one})
    assert "with 0" not in s.cluster_text({0: {"min": 0.0, "max": 0.0}, 1: one})
    assert s.cluster_text({0: {"min": 0.0, "max": 0.0}}).startswith("No pole bounces")


def test_the_spring_modes_note_quotes_the_stress_ratio_it_computed(study):
    s = study("spring_models")
    from vcbmodel import parameters as P
    sp = P.REFERENCE_CAM["closing_spring"]
    data = {"continuum_axial_hz": [134.2], "lateral_string_hz_at_6000N": [90.3], "models": {}}
    for n in s.TABLE_NS:
        data["models"][f"lumped-{n} (exact)"] = {"quasi_static_pin_mass_over_m0": 1 / 3}
        data["models"][f"lumped-{n} (paper)"] = {"total_mass_over_m0": 1.0 + n / 10, "quasi_static_pin_mass_over_m0": 0.3,
                                                 "frequencies_hz": [85.4]}
    data["coil_geometry"] = {f"{sp['mass']:g} kg": {"wire_diameter_m": 5e-3, "coil_diameter_m": 2e-2, "active_coils": 30.0,
                                                   "shear_stress_at_6000N_Pa": 3.0e9, "allowable_extension_body_Pa": 0.75e9}}
    note = s.modes_note(data, sp["stiffness"], sp["mass"])
    assert "4.0x the 0.45 S_ut" in note and "3.00 m0 at n = 20" in note and "no steel spring" in note
    data["coil_geometry"][f"{sp['mass']:g} kg"]["shear_stress_at_6000N_Pa"] = 0.5e9
    assert "no steel spring" not in s.modes_note(data, sp["stiffness"], sp["mass"])


def test_the_closing_page_reads_the_former_rise_from_its_runs(study):
    """vcb_closing's roller-jump paragraph printed 'above the 0.6-1.5 m/s' whatever the speed, and 'the
    roller stays on the cam (at 2400 N it can)' for a roller that does not jump."""
    s = study("vcb_closing")
    lo, hi = s.VACUUM_CLOSING_SPEEDS
    assert "2.15 m/s over the zone, above the" in s.rise_speed_text(2.15)
    assert "within the" in s.rise_speed_text(0.5 * (lo + hi)) and "below the" in s.rise_speed_text(0.5 * lo)

    def run(lift, preload):
        return {"figures_of_merit": {"roller_first_lift_off_s": lift}, "opening_preload_N": preload}
    jumps = s.jump_text(run(-3.8e-4, 1200.0), run(None, 2400.0))
    assert "leaves the cam 0.38 ms before" in jumps and "1200 N opening spring" in jumps and "(at 2400 N it can)" in jumps
    assert "(at 2400 N it still cannot)" in s.jump_text(run(-3.8e-4, 1200.0), run(-1e-4, 2400.0))
    stays = s.jump_text(run(None, 1200.0), run(None, 2400.0))
    assert stays == "the roller stays on the cam up to the touch. "


def test_the_closing_page_says_a_coil_fails_only_where_its_stress_is_over_the_allowable(study):
    s = study("vcb_closing")
    over = s.coil_claim({"shear_stress_Pa": 2.94e9, "allowable_extension_Pa": 0.76e9})
    assert over.startswith("which no steel coil") and "2.94 GPa against the 0.76 GPa allowed" in over
    assert s.coil_claim({"shear_stress_Pa": 0.5e9, "allowable_extension_Pa": 0.76e9}).startswith("which a steel coil")


def test_the_closing_page_takes_gaps_johnson_and_the_stick_band_from_the_rig_and_the_laws(study):
    """vcb_closing typed the pole gaps ('11 mm + 0 / +0.3 / -0.3 mm', '+-0.3 mm'), Johnson's '8-13 %' and a
    passive stick band '0.018 rad/s at 1e-5 s'; they come from the rig and the laws (the band is
    laws.friction.band_width at the rest state of the independent solve)."""
    import copy

    from vcbmodel import parameters as P
    from vcbmodel.experiments.loading import rig_from_data
    s = study("vcb_closing")
    rig = rig_from_data(copy.deepcopy(P.REFERENCE_BREAKER))
    assert s.gap_text(rig.breaker.poles) == "11 mm + 0 / +0.3 / -0.3 mm"
    assert s.gap_tolerance_text(rig.breaker.poles) == "+-0.3 mm"
    low, high = s.johnson_over_palmgren(rig)
    assert (round(100 * (low - 1)), round(100 * (high - 1))) == (8, 13)
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    data["breaker"]["poles"].update(contact_gap=0.012, gap_offsets=[0.0, -0.0005, 0.0002])
    data["breaker"]["contact"]["roller_width"] = 0.04  # a wider roller: Palmgren stiffer, Johnson's ratio other
    other = rig_from_data(data)
    assert s.gap_text(other.breaker.poles) == "12 mm + 0 / -0.5 / +0.2 mm"
    assert s.gap_tolerance_text(other.breaker.poles) == "+-0.5 mm"
    assert s.johnson_over_palmgren(other) != (low, high)
    band = s.passive_stick_band(rig)
    assert 0.0 < band[0] <= band[1] and band[1] > 10 * rig.friction.get("stick_velocity", P.DEFAULT_STICK_VELOCITY)
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    data["closing_spring"]["stiffness"] *= 1.2  # more reaction on the shaft at rest: a wider band
    assert s.passive_stick_band(rig_from_data(data))[0] > band[0]


def test_the_closing_page_says_what_the_elastic_shaft_does_only_where_the_runs_show_it(study):
    """The main-shaft paragraph said the far levers 'lengthen their poles' bounce' and the far poles 'keep less of
    their wipe', and the static check that the levers' inertia 'adds to the quasi-static twist', whatever the runs
    gave."""
    s = study("vcb_closing")

    def run(bounce, closed):
        return {"figures_of_merit": {"per_pole": {"bounce_duration_s": bounce}}, "closed_rod_forces_N": closed}
    rigid = run([1e-3, 1e-3, 1e-3], [3500.0, 3500.0, 3500.0])
    worse = s.far_poles_text(rigid, run([1e-3, 1.4e-3, 1.2e-3], [3450.0, 3300.0, 3350.0]), 1)
    assert "and lengthen their poles' bounce" in worse and "the far poles keep less of their wipe" in worse
    assert "pole 2 (its contact force) carries 3.30 kN against 3.50 kN" in worse
    same = s.far_poles_text(rigid, run([1e-3, 0.9e-3, 1e-3], [3500.0, 3510.0, 3520.0]), 1)
    assert "without lengthening" in same and "keep less" not in same and "keep their wipe" in same

    def twist(static_before, model_before):
        static = {"closed (end of the run)": {"largest_twist_rad": 1e-3},
                  "before the first touch": {"largest_twist_rad": static_before}}
        spread = {"rigid": {}, "ref": {"largest_twist_rad": {"end": 1e-3, "before": model_before}}}
        return s.static_check_sentence(static, spread)
    assert "add to the quasi-static twist" in twist(0.2e-3, 0.3e-3)
    assert "add to" not in twist(0.2e-3, 0.1e-3) and "less than the quasi-static twist" in twist(0.2e-3, 0.1e-3)
    assert s.drive_side(1, 3) == "the first pole's side" and s.drive_side(2, 3) == "the middle pole"
    assert s.drive_side(3, 3) == "the last pole's side" and s.drive_side(2, 4) == "pole 2"

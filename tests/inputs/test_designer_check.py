"""`check` as a designer's check, and what every run must satisfy (docs/rig-format.md 3.11, docs/cli.md):
values a unit slip gives are refused naming the field and the slip, unusual ones warned; a spring or
damper too stiff for the fixed step is refused before the run; a run that creates energy fails; a cam
that never moved is said plainly; the templates are commented everywhere and within their allowables."""
import copy
import json
from pathlib import Path

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.app.cli import main
from vcbmodel.app.templates import ANGLE_FIELDS, TEMPLATES, template
from vcbmodel.errors import InputError, SimulationError
from vcbmodel.experiments.loading import load_rig, rig_from_data
from vcbmodel.experiments.run_checks import audit_energy
from vcbmodel.experiments.simulation import simulate
from vcbmodel.rig.paths import set_path

ROOT = Path(__file__).resolve().parents[2]
SYNTHETIC = ROOT / "results" / "synthetic"
CLOSING = json.loads((SYNTHETIC / "vcb_closing.rig.json").read_text())
CAM = json.loads((SYNTHETIC / "cam_drop_m0_0.336kg.rig.json").read_text())
PENDULUM = json.loads(template("pendulum"))


def edited(tmp_path, base, changes, name="my.rig.json"):
    data = copy.deepcopy(base)
    for path, value in changes.items():
        set_path(data, path, value)
    f = tmp_path / name
    f.write_text(json.dumps(data))
    return f


def one_line(capsys, argv, status):
    assert main(argv) == status
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if line.startswith("vcbmodel:") and not line.startswith("vcbmodel: warning:")]
    assert len(err) == 1 and "Traceback" not in err[0], err
    return err[0]


# --- unit slips: refused, naming the field and the slip -------------------------------------------------

@pytest.mark.parametrize("base, path, value, hint", [
    (CLOSING, "breaker.poles.moving_mass", 1500.0, "grams typed as kg?"),
    (CLOSING, "cam.mass", 9500.0, "grams typed as kg?"),
    (CAM, "closing_spring.mass", 336.4, "grams typed as kg?"),
    (PENDULUM, "pendulum.mass", 60000.0, "grams typed as kg?"),
    (CLOSING, "breaker.main_shaft.shear_modulus", 80.0, "GPa typed instead of Pa?"),
    (CLOSING, "breaker.main_shaft.diameter", 60.0, "millimetres typed as m?"),
    (CLOSING, "breaker.main_shaft.pole_pitch", 210.0, "millimetres typed as m?"),
    (CLOSING, "breaker.poles.contact_gap", 11.0, "millimetres typed as m?"),
    (CLOSING, "cam.inertia_com", 20000.0, "kg mm^2 typed as kg m^2?"),
    (CLOSING, "breaker.follower.inertia", 80000.0, "kg mm^2 typed as kg m^2?"),
    (CAM, "closing_spring.stiffness", 24.23, "N/mm typed where N/m is asked?"),
    (CLOSING, "breaker.end_stop.stiffness", 2.0, "N/mm typed where N/m is asked?"),
    (CLOSING, "gravity", 981.0, "cm/s^2"),
    (CLOSING, "friction.mu_k", 13.0, "percentage"),
    (CLOSING, "breaker.latch.release_time", 2.0, "milliseconds typed as s?"),
    (CAM, "closing_spring.anchor", [0.0, 300.0], "millimetres typed as m?"),
])
def test_a_unit_slip_is_refused_naming_the_field_and_the_slip(tmp_path, capsys, base, path, value, hint):
    f = edited(tmp_path, base, {path: value} if path != "friction.mu_k" else {path: value, "friction.mu_s": value})
    line = one_line(capsys, ["check", str(f)], 2)
    assert f"my.rig.json: {path}" in line and hint in line and "impossible" in line, line
    assert one_line(capsys, ["simulate", str(f), "-o", str(tmp_path / "o.csv")], 2) == line
    assert not (tmp_path / "o.csv").exists()
    with pytest.raises(InputError, match=path.replace(".", r"\.")):  # the Python API: the same error, no traceback
        rig_from_data(json.loads(f.read_text()), str(f))


@pytest.mark.parametrize("base, path, value", [
    (CLOSING, "breaker.poles.moving_mass", 30.0),
    (CLOSING, "breaker.main_shaft.shear_modulus", 10e9),
    (CLOSING, "breaker.contact.cam_roller_stiffness", 1e14),
    (CAM, "closing_spring.stiffness", 500.0),
    (PENDULUM, "friction.mu_k", 0.6),
])
def test_an_unusual_value_is_warned_and_listed_by_check(tmp_path, capsys, base, path, value):
    changes = {path: value, "friction.mu_s": 0.7} if path == "friction.mu_k" else {path: value}
    f = edited(tmp_path, base, changes)
    assert main(["check", str(f)]) == 0
    captured = capsys.readouterr()
    assert f"warning: {f}: {path}: {value:g}" in captured.err and "unusual" in captured.err
    assert "values: 1 unusual" in captured.out and f"    {path}: {value:g}" in captured.out


def test_the_shipped_rigs_and_templates_hold_no_unusual_value(tmp_path, capsys):
    for f in sorted(SYNTHETIC.glob("*.rig.json")):
        assert load_rig(f).warnings == (), f
    for kind in TEMPLATES:
        (tmp_path / f"{kind}.rig.json").write_text(template(kind))
        assert main(["check", str(tmp_path / f"{kind}.rig.json")]) == 0
        out = capsys.readouterr()
        assert "every one within its usual range" in out.out and "warning" not in out.err


# --- a lift that cannot close the poles ---------------------------------------------------------------

@pytest.mark.parametrize("scale", [1e-3, 0.02])
def test_points_in_metres_under_a_millimetre_header_are_refused(tmp_path, capsys, scale):
    """The docs' example cam (degrees, mm) written in metres under its mm header: 0.0094 mm of lift; or
    a lift of 50 times too little (0.2 mm): the poles could never close."""
    rows = [line for line in (ROOT / "docs" / "examples" / "cam_lift.csv").read_text().splitlines()
            if line and not line.startswith("#")]
    text = rows[0] + "\n" + "\n".join(f"{a},{float(v) * scale:.9g}" for a, v in (r.split(",") for r in rows[1:])) + "\n"
    (tmp_path / "cam_lift.csv").write_text(text)
    data = copy.deepcopy(CLOSING)
    data["breaker"]["cam_profile"] = {"base_radius": 0.045, "points_file": "cam_lift.csv"}
    f = tmp_path / "my.rig.json"
    f.write_text(json.dumps(data))
    line = one_line(capsys, ["check", str(f)], 2)
    assert "breaker.cam_profile.points_file" in line and "could never close" in line and "millimetre" in line


# --- the fixed step's stability -----------------------------------------------------------------------

@pytest.mark.parametrize("path, value, unit", [
    ("breaker.end_stop.stiffness", 1e12, "N/m"),
    ("breaker.hold_latch.stiffness", 5e12, "N/m"),
    ("breaker.poles.rod_damping", 1e9, "N s/m"),
    ("breaker.end_stop.damping", 1e9, "N s/m"),
    ("breaker.poles.rod_stiffness", 1e12, "N/m"),
    ("breaker.main_shaft.damping", 1e5, "N m s/rad"),
])
def test_a_spring_or_damper_too_stiff_for_the_step_is_refused_before_the_run(tmp_path, capsys, path, value, unit):
    f = edited(tmp_path, CLOSING, {path: value})
    line = one_line(capsys, ["simulate", str(f), "-o", str(tmp_path / "o.csv")], 2)
    assert f"{path}: {value:g} {unit}" in line and "fixed RK4 step" in line and "integrates it only up to" in line
    assert not (tmp_path / "o.csv").exists()
    largest = float(line.split("only up to ")[1].split()[0])
    assert largest < value
    # the largest value the step integrates runs (the limit is not conservative by orders of magnitude)
    g = edited(tmp_path, CLOSING, {path: 0.9 * largest}, "edge.rig.json")
    rig = load_rig(g)
    assert simulate(rig, backend="compiled", t_end=0.01).info["energy_residual"] < P.ENERGY_CREATED_FRACTION


# --- energy conservation of every run -----------------------------------------------------------------

@pytest.mark.parametrize("rig_file, kwargs", [
    ("vcb_closing.rig.json", {"backend": "compiled"}),
    ("vcb_closing.rig.json", {"backend": "compiled", "spring_model": "massless"}),
    ("cam_drop_m0_0.336kg.rig.json", {}),
    ("cam_drop_m0_1kg.rig.json", {"spring_model": "massless"}),
    ("cam_drop_m0_1kg.rig.json", {"spring_model": "lumped-5", "backend": "compiled"}),
])
def test_the_energy_balance_of_a_sound_run_closes(rig_file, kwargs):
    r = simulate(load_rig(SYNTHETIC / rig_file), **kwargs)
    assert r.info["energy_residual"] < 1e-3


def test_the_pendulums_energy_balance_closes_and_catches_energy_added(tmp_path):
    f = tmp_path / "p.rig.json"
    f.write_text(template("pendulum"))
    rig = load_rig(f)
    r = simulate(rig, backend="compiled")
    assert 0.0 <= r.info["energy_residual"] < 1e-4
    r.channels["shaft_velocity"] = r.channels["shaft_velocity"] * np.linspace(1.0, 1.5, r.t.size)  # energy from nowhere
    with pytest.raises(SimulationError, match="created energy"):
        audit_energy(r, rig)


def test_a_cam_drop_that_gains_energy_fails():
    rig = load_rig(SYNTHETIC / "cam_drop_m0_0.336kg.rig.json")
    r = simulate(rig)
    r.channels["shaft_velocity"] = r.channels["shaft_velocity"] * 1.2
    with pytest.raises(SimulationError, match="the run created energy"):
        audit_energy(r, rig)


@pytest.mark.parametrize("backend", ["compiled", "exudyn"])
def test_a_run_that_creates_energy_fails_in_one_line(tmp_path, capsys, backend):
    """A Hertz pole contact far stiffer than any (nonlinear: the step check cannot bound it) makes the
    run unstable: it fails in one line, writes nothing, and names the energy it made."""
    f = edited(tmp_path, CLOSING, {"breaker.contact.pole_stiffness": 1e15})
    line = one_line(capsys, ["simulate", str(f), "-o", str(tmp_path / "o.csv"), "--backend", backend], 1)
    assert "simulation failed: the run created energy" in line and "J more than the 371 J it started with" in line
    assert not (tmp_path / "o.csv").exists()


def test_a_sweep_counts_a_run_that_creates_energy_as_failed(tmp_path, capsys):
    f = edited(tmp_path, CLOSING, {})
    assert main(["sweep", str(f), "--vary", "breaker.contact.pole_stiffness=1e10:1e15:2", "-o", str(tmp_path / "s.csv"),
                 "--workers", "1", "-q"]) == 0
    rows = [r for r in (tmp_path / "s.csv").read_text().splitlines() if r[:1].isdigit()]
    assert rows[0].endswith(",ok") and "created energy" in rows[1]


# --- the cam did not move -----------------------------------------------------------------------------

@pytest.mark.parametrize("base, changes, what", [
    (PENDULUM, {"friction.mu_s": 4.0, "friction.mu_k": 3.0}, "the pendulum did not swing"),
    (CAM, {"friction.mu_s": 4.9, "friction.mu_k": 4.0}, "the cam did not move"),
    (CLOSING, {"friction.mu_s": 4.9, "friction.mu_k": 4.5}, "the cam did not move"),
])
def test_a_cam_that_never_moved_is_said_plainly(tmp_path, capsys, base, changes, what):
    f = edited(tmp_path, base, changes)
    line = one_line(capsys, ["simulate", str(f), "-o", str(tmp_path / "o.csv")], 1)
    assert what in line and "--t-end will not help" in line
    assert not (tmp_path / "o.csv").exists()


def test_a_run_too_short_to_show_motion_is_not_called_stuck(tmp_path, capsys):
    f = tmp_path / "p.rig.json"
    f.write_text(template("pendulum"))
    assert main(["simulate", str(f), "--t-end", "0.002", "-o", str(tmp_path / "o.csv"), "-q"]) == 0


# --- check: the closing stroke's pressure angle; the templates ----------------------------------------

def test_check_reports_the_pressure_angle_over_the_closing_stroke(capsys):
    assert main(["check", str(SYNTHETIC / "vcb_closing.rig.json")]) == 0
    out = capsys.readouterr().out
    stroke = next(line for line in out.splitlines() if "over the closing stroke" in line)
    rest = next(line for line in out.splitlines() if "over the rest of the turn" in line)
    assert "to 250.0 deg, to the end stop" in stroke
    assert float(stroke.split("): ")[1].split(" deg")[0]) < 10.0 < float(rest.split("): ")[1].split(" deg")[0])
    assert "ABOVE" not in stroke and "the poles travel up to" in out


def _sections(obj, where=""):
    for key, value in obj.items():
        if isinstance(value, dict) and not key.startswith("_"):
            yield f"{where}{key}", value
            yield from _sections(value, f"{where}{key}.")


@pytest.mark.parametrize("kind", list(TEMPLATES))
def test_a_template_is_commented_in_every_section_and_within_its_allowables(tmp_path, capsys, kind):
    data = json.loads(template(kind))
    for name, section in _sections(data):
        assert "_units" in section, name
        for key, value in section.items():
            if key in ANGLE_FIELDS and isinstance(value, (int, float)):
                assert f"{np.degrees(value):.2f} deg" in section[f"_{key}"], (name, key)
    f = tmp_path / "t.rig.json"
    f.write_text(template(kind))
    assert main(["check", str(f)]) == 0
    out = capsys.readouterr().out
    assert "ABOVE" not in out and "FAILS" not in out
    if kind != "pendulum":  # plug ends: the body's two checks, no hook's
        assert "(screwed-in plug ends, Cr-Si wire)" in out and "passes all 2 strength checks" in out
        assert "hook" not in out.split("(screwed-in plug ends", 1)[1].split("thinnest", 1)[0]
    assert main(["simulate", str(f), "-o", str(tmp_path / "o.csv"), "-q"]) == 0


def test_the_ends_of_a_closing_spring_decide_which_strength_checks_apply(tmp_path, capsys):
    """The same coil with hooks is checked for its hooks too (six checks; the template's 9.6 mm wire
    fails the hooks' fatigue); a value other than hooks or plugs is refused in one line naming the field."""
    data = json.loads(template("vcb_closing"))
    data["closing_spring"]["ends"] = "hooks"
    f = tmp_path / "hooks.rig.json"
    f.write_text(json.dumps(data))
    assert main(["check", str(f)]) == 0
    out = capsys.readouterr().out
    assert "(standard hooks, Cr-Si wire)" in out and "of 6 strength checks" in out and "hook bending fatigue" in out
    data["closing_spring"]["ends"] = "welded"
    f.write_text(json.dumps(data))
    assert main(["check", str(f)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "closing_spring.ends" in err[0] and "hooks, plugs" in err[0]


def test_rig_format_lists_every_plausibility_range_as_parameters_holds_it():
    page = (ROOT / "docs" / "rig-format.md").read_text()

    def cell(v):
        return "" if v is None else f"{v:g}"

    for path, (no_low, low, high, no_high, unit, _, _) in P.PLAUSIBLE.items():
        assert f"| `{path}` | {unit} | {cell(no_low)} | {cell(low)} | {cell(high)} | {cell(no_high)} |" in page, path


@pytest.mark.parametrize("changes, field", [
    ({"breaker.main_shaft.diameter": 0.005}, "breaker.main_shaft.diameter"),
    ({"breaker.main_shaft.diameter": 0.012}, "breaker.main_shaft.diameter"),
    ({"breaker.main_shaft.shear_modulus": 2e8}, "breaker.main_shaft.shear_modulus"),
])
def test_a_main_shaft_too_soft_to_hold_its_levers_is_refused(tmp_path, capsys, changes, field):
    """A 5 mm shaft was a math domain error from the levers' rest position; a 0.2 GPa one twisted 57 deg."""
    f = edited(tmp_path, CLOSING, changes)
    line = one_line(capsys, ["simulate", str(f), "-o", str(tmp_path / "o.csv")], 2)
    assert f"{field}: a " in line and "no pole lever could hold its rod" in line


def test_a_soft_main_shaft_is_warned_of(tmp_path, capsys):
    f = edited(tmp_path, CLOSING, {"breaker.main_shaft.diameter": 0.02})
    assert main(["check", str(f)]) == 0
    assert "breaker.main_shaft.diameter: a 20 mm shaft of 79.3 GPa" in capsys.readouterr().out


def test_the_reachable_travel_is_kept_per_geometry_not_per_breaker():
    """A sweep loads one breaker per run; the travel a turn of the cam reaches depends on the geometry alone:
    a breaker with other pole masses and gaps gets the kept value, one with another lift its own, as
    computed afresh (travel_curve)."""
    from vcbmodel.rig import plausibility
    from vcbmodel.rig.plausibility import reachable_travel, travel_curve

    def breaker(changes):
        data = copy.deepcopy(P.REFERENCE_BREAKER)
        for path, value in changes.items():
            set_path(data, path, value)
        rig = rig_from_data(data, "test")
        return rig.breaker, rig.cam

    b0, cam0 = breaker({})
    base = reachable_travel(b0, cam0)
    kept = plausibility._kept_travel.cache_info()
    b1, cam1 = breaker({"breaker.poles.moving_mass": 1.7, "breaker.poles.gap_offsets": [0.0, 0.0002, -0.0002]})
    assert reachable_travel(b1, cam1) == base
    now = plausibility._kept_travel.cache_info()  # loading b1 asked for it too: kept, not computed
    assert now.misses == kept.misses and now.currsize == kept.currsize and now.hits > kept.hits
    b2, cam2 = breaker({"breaker.cam_profile.lift": 0.0104})
    fresh = float(np.max(travel_curve(b2, cam2, cam2.initial_angle + np.linspace(0.0, 2 * np.pi, 361))))
    assert reachable_travel(b2, cam2) == fresh and fresh > 1.05 * base

"""Never lose data, never a silent wrong answer, never a traceback (docs/cli.md "Output files", "Sweeps"):
inputs are never replaced through any spelling of their path; a sweep's lock holds through links;
``--resume`` refuses a changed rig; conflicting profile fields are refused naming both; the reference
solve covers a rig or says what it does not cover; identify finds the release itself."""
import copy
import json
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from vcbmodel.analysis.sweep import sweep
from vcbmodel.analysis.sweep.table import table_lock
from vcbmodel.app.cli import main
from vcbmodel.errors import InputError
from vcbmodel.experiments.loading import load_rig, rig_from_data
from vcbmodel.experiments.simulation import simulate

ROOT = Path(__file__).resolve().parents[2]
SYNTHETIC = ROOT / "results" / "synthetic"
CLOSING = json.loads((SYNTHETIC / "vcb_closing.rig.json").read_text())
POINTS = ROOT / "docs" / "examples" / "cam_lift.csv"


def refused(capsys, argv, *words):
    assert main(argv) == 2
    err = [x for x in capsys.readouterr().err.strip().splitlines() if not x.startswith("vcbmodel: warning:")]
    assert len(err) == 1 and "Traceback" not in err[0], err
    for w in words:
        assert w in err[0], err[0]
    return err[0]


@pytest.fixture
def point_rig(tmp_path):
    """A closing whose cam is given by a points file beside the rig, and its measured record."""
    shutil.copy(POINTS, tmp_path / "cam_lift.csv")
    data = copy.deepcopy(CLOSING)
    data["breaker"]["cam_profile"] = {"base_radius": 0.045, "points_file": "cam_lift.csv"}
    (tmp_path / "b.rig.json").write_text(json.dumps(data))
    shutil.copy(SYNTHETIC / "vcb_closing.csv", tmp_path / "b.csv")
    return tmp_path / "b.rig.json"


def spellings(tmp_path, target):
    """The same file named other ways: relative with .., a symlink, a hard link."""
    (tmp_path / "sub").mkdir(exist_ok=True)
    link, hard = tmp_path / "link.csv", tmp_path / "hard.csv"
    for p in (link, hard):
        if p.exists() or p.is_symlink():
            p.unlink()
    link.symlink_to(target)
    os.link(target, hard)
    return [str(target), str(tmp_path / "sub" / ".." / target.name), str(link), str(hard)]


@pytest.mark.parametrize("which", ["cam_lift.csv", "b.csv", "b.rig.json"])
def test_simulate_never_replaces_an_input_however_it_is_named(point_rig, tmp_path, capsys, which):
    target = tmp_path / which
    before = target.read_bytes()
    for name in spellings(tmp_path, target):
        line = refused(capsys, ["simulate", str(point_rig), "-o", name, "--force"], "an input", "never replaced")
        assert "-o" in line
        refused(capsys, ["simulate", str(point_rig), "-o", str(tmp_path / "x.csv"), "--plot", name, "--force"], "--plot")
    assert target.read_bytes() == before


@pytest.mark.parametrize("which", ["cam_lift.csv", "b.csv", "b.rig.json"])
def test_sweep_never_replaces_an_input(point_rig, tmp_path, capsys, which):
    target = tmp_path / which
    before = target.read_bytes()
    for name in spellings(tmp_path, target):
        refused(capsys, ["sweep", str(point_rig), "--vary", "friction.mu_k=0.1:0.2:2", "-o", name, "--force"], "an input")
    assert target.read_bytes() == before


def test_a_former_simulation_beside_the_rig_may_be_replaced_with_force(tmp_path, capsys):
    rig = tmp_path / "c.rig.json"
    rig.write_text(json.dumps(CLOSING))
    out = tmp_path / "c.csv"
    assert main(["simulate", str(rig), "-o", str(out), "--backend", "compiled", "-q"]) == 0
    assert main(["simulate", str(rig), "-o", str(out), "--backend", "compiled", "-q", "--force"]) == 0
    assert out.read_text().startswith("# vcbmodel ")


def test_plot_and_output_the_same_file_through_a_link_is_refused(tmp_path, capsys):
    rig = tmp_path / "c.rig.json"
    rig.write_text(json.dumps(CLOSING))
    (tmp_path / "o.png").write_bytes(b"")
    (tmp_path / "o2.png").symlink_to(tmp_path / "o.png")
    refused(capsys, ["simulate", str(rig), "-o", str(tmp_path / "o.png"), "--plot", str(tmp_path / "o2.png"), "--force"],
            "--plot", "is also the -o file")


# --- sweeps: locks through links, a changed rig on --resume --------------------------------------------

def test_a_second_sweep_through_a_symlink_is_refused_while_the_first_writes(tmp_path):
    out = tmp_path / "t.csv"
    out.write_text("")
    (tmp_path / "alias.csv").symlink_to(out)
    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "t2.csv").symlink_to(out)
    rig = tmp_path / "c.rig.json"
    rig.write_text(json.dumps(CLOSING))
    with table_lock(str(out)):
        for other in (tmp_path / "alias.csv", tmp_path / "d" / "t2.csv", tmp_path / "d" / ".." / "t.csv"):
            with pytest.raises(InputError, match="another vcbmodel sweep is writing this table"):
                sweep(str(rig), ["friction.mu_k=0.1:0.2:2"], output=str(other), force=True, workers=1, verbose=False)
    assert out.read_text() == ""  # nothing written by the refused sweeps
    assert not (tmp_path / ".t.csv.lock").exists()  # released with the lock


def _sweep(capsys, rig, out, *extra):
    return main(["sweep", str(rig), "--vary", "friction.mu_k=0.10:0.16:4", "-o", str(out), "--workers", "1", "-q",
                 *extra])


def test_resume_refuses_a_changed_rig_or_points_file(point_rig, tmp_path, capsys):
    out = tmp_path / "s.csv"
    assert _sweep(capsys, point_rig, out) == 0
    lines = out.read_text().splitlines()
    assert lines[0].startswith("# vcbmodel sweep rig sha256 ") and len(lines) == 6
    out.write_text("\n".join(lines[:4]) + "\n")  # an interrupted sweep: two runs in
    # a comment edited: the same rig, resumed
    data = json.loads(point_rig.read_text())
    data["_note"] = "edited comment"
    point_rig.write_text(json.dumps(data))
    assert _sweep(capsys, point_rig, out, "--resume") == 0
    assert len(out.read_text().splitlines()) == 6
    out.write_text("\n".join(lines[:4]) + "\n")
    data["breaker"]["poles"]["moving_mass"] = 1.6  # the rig changed
    point_rig.write_text(json.dumps(data))
    refused(capsys, ["sweep", str(point_rig), "--vary", "friction.mu_k=0.10:0.16:4", "-o", str(out), "--resume"],
            "--resume", "another version of the rig")
    data["breaker"]["poles"]["moving_mass"] = 1.5
    point_rig.write_text(json.dumps(data))
    points = tmp_path / "cam_lift.csv"
    points.write_text(points.read_text() + "# a comment added\n")  # a file the rig reads changed
    refused(capsys, ["sweep", str(point_rig), "--vary", "friction.mu_k=0.10:0.16:4", "-o", str(out), "--resume"],
            "another version of the rig")
    assert out.read_text().splitlines() == lines[:4]  # the refused resumes left the table as it was


def test_resume_refuses_a_table_without_a_fingerprint(tmp_path, capsys):
    rig = tmp_path / "c.rig.json"
    rig.write_text(json.dumps(CLOSING))
    out = tmp_path / "s.csv"
    assert _sweep(capsys, rig, out) == 0
    lines = out.read_text().splitlines()
    out.write_text("\n".join(lines[1:3]) + "\n")
    refused(capsys, ["sweep", str(rig), "--vary", "friction.mu_k=0.10:0.16:4", "-o", str(out), "--resume"],
            "no fingerprint")


def test_a_path_absent_from_the_rig_is_named_not_the_field_it_lacks(tmp_path, capsys):
    data = copy.deepcopy(CLOSING)
    del data["breaker"]["end_stop"], data["breaker"]["hold_latch"]
    rig = tmp_path / "c.rig.json"
    rig.write_text(json.dumps(data))
    line = refused(capsys, ["sweep", str(rig), "--vary", "breaker.end_stop.angle=4.3:4.4:2", "-o", str(tmp_path / "s.csv")],
                   "c.rig.json: breaker.end_stop.angle:", "no breaker.end_stop")
    assert "breaker.end_stop.arm:" not in line


# --- conflicting fields, values a slip gives, the reference solve ------------------------------------

@pytest.mark.parametrize("extra", [{"lift": 0.012}, {"rise_start": 0.2, "rise_end": 4.0}, {"return_end": 6.4}])
def test_points_and_polynomial_fields_are_refused_naming_both(point_rig, capsys, extra):
    data = json.loads(point_rig.read_text())
    data["breaker"]["cam_profile"].update(extra)
    point_rig.write_text(json.dumps(data))
    name = next(iter(extra))
    refused(capsys, ["check", str(point_rig)], f"breaker.cam_profile.{name}: conflicts with breaker.cam_profile.points_file")


def test_radius_points_and_a_conflicting_base_radius_are_refused(tmp_path, capsys):
    data = copy.deepcopy(CLOSING)
    angles = np.linspace(0, 2 * np.pi, 72, endpoint=False)
    lift = 0.0094 * 0.5 * (1 - np.cos(np.clip((angles - 0.2) / 4.0, 0, 1) * np.pi))
    data["breaker"]["cam_profile"] = {"radius_points": [[a, 0.065 + v] for a, v in zip(angles, lift)], "base_radius": 0.05,
                                      "smoothing": 1e-6}
    f = tmp_path / "r.rig.json"
    f.write_text(json.dumps(data))
    refused(capsys, ["check", str(f)], "breaker.cam_profile.base_radius", "conflicts with breaker.cam_profile.radius_points")


@pytest.mark.parametrize("G", [80.0, 79.3, 8e7])
def test_a_shaft_modulus_in_gpa_is_refused_not_a_traceback(tmp_path, capsys, G):
    data = copy.deepcopy(CLOSING)
    data["breaker"]["main_shaft"]["shear_modulus"] = G
    f = tmp_path / "g.rig.json"
    f.write_text(json.dumps(data))
    refused(capsys, ["check", str(f)], "breaker.main_shaft.shear_modulus", "GPa typed instead of Pa?")


def test_the_reference_backend_on_the_shipped_closing_raises_one_clear_input_error():
    rig = load_rig(SYNTHETIC / "vcb_closing.rig.json")
    for method in ("DOP853", "rk4"):
        with pytest.raises(InputError, match="breaker.main_shaft: backend='reference' does not cover"):
            simulate(rig, backend="reference", method=method, t_end=0.01)


def test_the_reference_backend_runs_a_rigid_shaft_closing_with_rk4_and_names_what_dop853_lacks():
    data = copy.deepcopy(CLOSING)
    del data["breaker"]["main_shaft"]
    rig = rig_from_data(data, "rigid.rig.json")
    with pytest.raises(InputError, match="method='rk4'"):
        simulate(rig, backend="reference", t_end=0.01)
    ref = simulate(rig, backend="reference", method="rk4", t_end=0.02)
    model = simulate(rig, backend="compiled", t_end=0.02)
    assert np.max(np.abs(ref.measured - model.measured)) < 1e-9


# --- identify finds the release -------------------------------------------------------------------------

def _record(tmp_path, name, t, y):
    rig = SYNTHETIC / "pendulum_10deg.rig.json"
    (tmp_path / f"{name}.rig.json").write_text(rig.read_text())
    f = tmp_path / f"{name}.csv"
    f.write_text("t,pendulum_angle\n" + "".join(f"{a:.6f},{b:.7g}\n" for a, b in zip(t, y)))
    return f


def _mu_k(capsys, f):
    assert main(["identify", str(f), "--json", "-q"]) == 0
    return json.loads(capsys.readouterr().out)


def test_identify_finds_the_release_of_a_shifted_or_pre_triggered_record(tmp_path, capsys):
    rows = [r for r in (SYNTHETIC / "pendulum_10deg.csv").read_text().splitlines() if r[:1].isdigit()]
    data = np.array([[float(x) for x in r.split(",")] for r in rows])
    t, y = data[:, 0], data[:, 1]
    plain = _mu_k(capsys, _record(tmp_path, "plain", t, y))["mu_k"]
    rest = y[0] + np.random.default_rng(3).normal(0.0, 5e-4, 400)
    cases = {"clock": (t + 1.5, y), "negative": (t - 0.2, y),
             "pretrigger": (np.concatenate([np.arange(-400, 0) * 1e-3, t]), np.concatenate([rest, y])),
             "shifted": (np.arange(400 + t.size) * 1e-3, np.concatenate([rest, y]))}
    for name, (tt, yy) in cases.items():
        found = _mu_k(capsys, _record(tmp_path, name, tt, yy))
        assert found["mu_k"] == pytest.approx(plain, rel=0.01), name
        assert found["residual_to_noise"] < 1.5 and found["warning"] is None, name  # fitted to its noise


def test_another_tests_record_is_never_replaced(tmp_path, capsys):
    """A record beside its rig (data) is refused as an output of any command; a table or a simulation
    vcbmodel wrote there may be replaced with --force."""
    for name in ("p.csv", "p.rig.json"):
        shutil.copy(SYNTHETIC / name.replace("p.", "pendulum_10deg."), tmp_path / name)
    rig = tmp_path / "c.rig.json"
    rig.write_text(json.dumps(CLOSING))
    before = (tmp_path / "p.csv").read_bytes()
    refused(capsys, ["simulate", str(rig), "-o", str(tmp_path / "p.csv"), "--force"], "a test's record", "never replaced")
    refused(capsys, ["sweep", str(rig), "--vary", "friction.mu_k=0.1:0.2:2", "-o", str(tmp_path / "p.csv"), "--force"],
            "a test's record")
    with pytest.raises(InputError, match="a test's record"):
        sweep(CLOSING, ["friction.mu_k=0.1:0.2:2"], output=str(tmp_path / "p.csv"), force=True, workers=1, verbose=False)
    assert (tmp_path / "p.csv").read_bytes() == before


def test_init_never_writes_its_template_over_a_points_file_or_another_csv(point_rig, tmp_path, capsys):
    """A rig template written to a .csv name is a slip (the cam's points, a record, a table beside the rig):
    refused with --force too; the suggestion to simulate it is quoted so a path with spaces can be pasted."""
    points = tmp_path / "cam_lift.csv"
    before = points.read_bytes()
    refused(capsys, ["init", "vcb_closing", "-o", str(points), "--force"], str(points), "-o", ".json")
    assert points.read_bytes() == before
    spaced = tmp_path / "my breaker.rig.json"
    assert main(["init", "vcb_closing", "-o", str(spaced)]) == 0
    assert f"vcbmodel simulate '{spaced}'" in capsys.readouterr().err


@pytest.mark.parametrize("given", ["path", "dict", "rig"])
def test_the_sweep_api_never_replaces_its_rig(tmp_path, given):
    rig = tmp_path / "c.rig.json"
    rig.write_text(json.dumps(CLOSING))
    before = rig.read_bytes()
    source = {"path": str(rig), "dict": copy.deepcopy(CLOSING), "rig": load_rig(rig)}[given]
    with pytest.raises(InputError, match="is an input of this sweep|named as a rig file"):
        sweep(source, ["friction.mu_k=0.1:0.2:2"], output=str(rig), force=True, workers=1, verbose=False)
    with pytest.raises(InputError, match="is a folder"):
        sweep(source, ["friction.mu_k=0.1:0.2:2"], output=str(tmp_path), force=True, workers=1, verbose=False)
    assert rig.read_bytes() == before


@pytest.mark.parametrize("kwargs, argument", [
    ({"backend": "bogus"}, "backend"), ({"t_end": -1.0}, "t_end"), ({"t_end": 0.0}, "t_end"),
    ({"step": -1e-5}, "step"), ({"effects": ("coulomb",)}, "effects"), ({"values": {"mu_q": 0.1}}, "values.mu_q"),
    ({"values": {"mu_k": -0.1}}, "values.mu_k"), ({"values": {"mu_k": "0.1"}}, "values.mu_k"),
    ({"sample_times": [0.01, 0.0]}, "sample_times"),
])
def test_the_python_api_refuses_what_it_cannot_run_naming_the_argument(kwargs, argument):
    rig = load_rig(SYNTHETIC / "cam_drop_m0_0.336kg.rig.json")
    with pytest.raises(InputError, match=f"simulate: {argument}:"):
        simulate(rig, **kwargs)


def test_identify_refuses_no_records_or_a_closing_record():
    from vcbmodel.analysis.identify import identify
    from vcbmodel.experiments.loading import load_pair

    with pytest.raises(InputError, match="no records given"):
        identify([])
    with pytest.raises(InputError, match="pendulum records; this is a vcb_closing record"):
        identify([load_pair(SYNTHETIC / "vcb_closing.csv")])


def _points_rig(tmp_path, name, text, mode="w"):
    (tmp_path / name).write_bytes(text) if isinstance(text, bytes) else (tmp_path / name).write_text(text)
    data = copy.deepcopy(CLOSING)
    data["breaker"]["cam_profile"] = {"base_radius": 0.045, "points_file": name}
    f = tmp_path / "pts.rig.json"
    f.write_text(json.dumps(data))
    return f


def _example_pairs():
    rows = [r for r in POINTS.read_text().splitlines() if r and not r.startswith("#")][1:]
    return [r.split(",") for r in rows]


@pytest.mark.parametrize("style", ["excel", "unit_row", "trailing_cells", "brackets", "tabs"])
def test_a_points_file_as_spreadsheets_write_it_gives_the_same_cam(tmp_path, capsys, style):
    pairs = _example_pairs()
    text = {"excel": b"\xef\xbb\xbf" + ("angle_deg;lift_mm\r\n" + "".join(f"{a};{v.replace('.', ',')}\r\n"
                                                                          for a, v in pairs)).encode(),
            "unit_row": "angle,lift\ndeg,mm\n" + "".join(f"{a},{v}\n" for a, v in pairs),
            "trailing_cells": "angle_deg;lift_mm;;\n" + "".join(f"{a};{v.replace('.', ',')};;\n" for a, v in pairs),
            "brackets": '"Angle [deg]","Lift [mm]"\n' + "".join(f'"{a}","{v}"\n' for a, v in pairs),
            "tabs": "angle_deg\tlift_mm\n" + "".join(f"{a}\t{v}\n" for a, v in pairs)}[style]
    rig = load_rig(_points_rig(tmp_path, f"{style}.csv", text))
    shutil.copy(POINTS, tmp_path / "plain.csv")
    reference = load_rig(_points_rig(tmp_path, "plain.csv", POINTS.read_text()))
    assert rig.breaker.profile.table == reference.breaker.profile.table


@pytest.mark.parametrize("angles", ["radians_under_deg", "rise_only"])
def test_points_that_do_not_go_round_the_cam_are_refused(tmp_path, capsys, angles):
    pairs = _example_pairs()
    if angles == "radians_under_deg":
        text = "angle_deg,lift_mm\n" + "".join(f"{np.radians(float(a)):.6g},{v}\n" for a, v in pairs)
    else:
        text = "angle_deg,lift_mm\n" + "".join(f"{a},{v}\n" for a, v in pairs if float(a) <= 200)
    f = _points_rig(tmp_path, "p.csv", text)
    refused(capsys, ["check", str(f)], "breaker.cam_profile.points_file", "without a point", "radians under a degree")


def test_a_failed_sweep_run_names_the_varied_values_behind_another_field(tmp_path):
    rig = tmp_path / "c.rig.json"
    rig.write_text(json.dumps(CLOSING))
    df = sweep(str(rig), ["breaker.poles.gap_offsets.2=-0.003:0:2", "breaker.poles.contact_gap=0.002:0.011:2"],
               workers=1, verbose=False)
    assert df.status[0] == ("failed: with breaker.poles.gap_offsets.2 = -0.003, breaker.poles.contact_gap = 0.002: "
                            "breaker.poles.gap_offsets: make a pole's gap zero or negative")
    assert (df.status[1:] == "ok").all()


def test_a_second_sweep_through_a_hard_link_elsewhere_is_refused(tmp_path):
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    out = tmp_path / "a" / "t.csv"
    out.write_text("")
    os.link(out, tmp_path / "b" / "same.csv")
    with table_lock(str(out)):
        with pytest.raises(InputError, match="another vcbmodel sweep is writing this table"):
            sweep(copy.deepcopy(CLOSING), ["friction.mu_k=0.1:0.2:2"], output=str(tmp_path / "b" / "same.csv"), force=True,
                  workers=1, verbose=False)
    assert out.read_text() == "" and not (tmp_path / "b" / ".same.csv.lock").exists()


@pytest.mark.parametrize("lift", [9.4e-6, 1e-4])
def test_a_lift_too_small_to_close_the_poles_is_refused(tmp_path, capsys, lift):
    data = copy.deepcopy(CLOSING)
    data["breaker"]["cam_profile"]["lift"] = lift
    f = tmp_path / "l.rig.json"
    f.write_text(json.dumps(data))
    refused(capsys, ["check", str(f)], "breaker.cam_profile.lift")

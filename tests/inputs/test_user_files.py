"""Files as users make them (a new user's trial, docs/your-breaker.md): a logger's units row under a
record's header; a cam's points as CAD and CMM exports give them (a closing 360 deg point, angles
from -180 deg, a duplicated or unsorted row, degrees, millimetres, a CMM's scatter). Each is read as
meant or refused with one line naming the file and the field."""
import copy
import csv
import json
import math

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.app.cli import main
from vcbmodel.compiled import compiler_works
from vcbmodel.errors import InputError
from vcbmodel.experiments.closing_evaluation import figures_of_merit
from vcbmodel.experiments.loading import load_pair, load_rig
from vcbmodel.experiments.simulation import simulate
from vcbmodel.rig.cam_points import point_scatter

from conftest import ROOT, write_rig

PENDULUM = ROOT / "results" / "synthetic" / "pendulum_10deg"


# --- a record with a units row -------------------------------------------------------------------------

def record_with(tmp_path, name, second_line, separator=","):
    lines = (PENDULUM.with_suffix(".csv")).read_text().splitlines()
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    body = lines[:header + 1] + [second_line] + lines[header + 1:]
    if separator == ";":
        body = [line if line.startswith("#") else line.replace(",", ";").replace(".", ",") for line in body]
    (tmp_path / f"{name}.csv").write_text("\r\n".join(body) + "\r\n")
    (tmp_path / f"{name}.rig.json").write_text((PENDULUM.with_suffix(".rig.json")).read_text())
    return tmp_path / f"{name}.csv"


@pytest.mark.parametrize("units, separator", [("s,rad", ","), ("[s],[rad]", ","), ("s,rad", ";")])
def test_a_units_row_in_the_channels_units_is_read_as_meant(tmp_path, units, separator):
    _, plain = load_pair(PENDULUM.with_suffix(".csv"))
    _, with_units = load_pair(record_with(tmp_path, "units", units, separator))
    assert np.array_equal(with_units.t, plain.t)
    assert np.array_equal(with_units.channel("pendulum_angle"), plain.channel("pendulum_angle"))


def test_a_units_row_in_ms_and_deg_is_converted_to_seconds_and_radians(tmp_path):
    _, plain = load_pair(PENDULUM.with_suffix(".csv"))
    lines = PENDULUM.with_suffix(".csv").read_text().splitlines()
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    rows = [[float(c) for c in line.split(",")] for line in lines[header + 1:]]
    body = lines[:header + 1] + ["ms,deg"] + [f"{1e3 * t!r},{math.degrees(a)!r}" for t, a in rows]
    (tmp_path / "deg.csv").write_text("\n".join(body) + "\n")
    (tmp_path / "deg.rig.json").write_text(PENDULUM.with_suffix(".rig.json").read_text())
    _, converted = load_pair(tmp_path / "deg.csv")
    assert np.allclose(converted.t, plain.t, rtol=0, atol=1e-12)
    assert np.allclose(converted.channel("pendulum_angle"), plain.channel("pendulum_angle"), rtol=1e-12, atol=1e-15)


def spreadsheet_export(tmp_path, name, edit=lambda rows: rows):
    """The 10 deg pendulum record as a spreadsheet saves it: UTF-8 BOM, CRLF, ';' with decimal commas,
    a units row, a trailing empty column, time in ms; ``edit`` changes the data rows (text)."""
    lines = PENDULUM.with_suffix(".csv").read_text().splitlines()
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    rows = [[float(c) for c in line.split(",")] for line in lines[header + 1:]]
    data = edit([f"{1e3 * t:.4f};{a!r};".replace(".", ",") for t, a in rows])
    text = "\r\n".join(["Time;Pendulum_Angle;", "ms;rad;"] + data) + "\r\n"
    (tmp_path / f"{name}.csv").write_bytes(("\ufeff" + text).encode())
    (tmp_path / f"{name}.rig.json").write_text(PENDULUM.with_suffix(".rig.json").read_text())
    return tmp_path / f"{name}.csv"


def test_a_small_swing_in_degrees_without_its_unit_is_refused_not_fitted(tmp_path, capsys):
    """A 2.5 deg release written in degrees stays within pi, the range check's bound: read as rad it was
    fitted, and the diagnosis 'discovered' a torsional spring. Its first sample reads the rig's initial angle
    in degrees: refused, naming the column and the unit to state."""
    rig = json.loads(PENDULUM.with_suffix(".rig.json").read_text())
    rig["pendulum"]["initial_angle"] = math.radians(2.5)
    (tmp_path / "small.rig.json").write_text(json.dumps(rig))
    t = np.arange(0, 3, 1e-3)
    degrees = 2.5 * np.cos(2 * np.pi * t / 0.93) * np.exp(-t)
    body = "t,pendulum_angle\n" + "".join(f"{a:.3f},{b:.5f}\n" for a, b in zip(t, degrees))
    (tmp_path / "small.csv").write_text(body)
    for command in ("diagnose", "identify"):
        assert main([command, str(tmp_path / "small.csv"), "--json"]) == 2
        out, err = capsys.readouterr()
        assert out == "" and len(err.strip().splitlines()) == 1
        assert "small.csv: column 'pendulum_angle': starts at 2.5" in err and "pendulum_angle [deg]" in err
    (tmp_path / "small.csv").write_text(body.replace("pendulum_angle", "pendulum_angle [deg]", 1))
    _, read = load_pair(tmp_path / "small.csv")
    assert read.channel("pendulum_angle")[0] == pytest.approx(math.radians(2.5))


def test_a_rad_record_is_read_through_the_start_offset_and_gain_its_rig_states(tmp_path, capsys):
    """The degrees check reads the first sample as the diagnosis would: less the rig's stated sensor offset,
    over its gain, against the record's stated initial angle. A rad record whose sensor reads 2.46 rad more
    (a stated offset) is accepted; a rig whose pendulum angle is a placeholder but whose record section states
    where the record starts is accepted; without either, the refusal says both readings."""
    rig = json.loads(PENDULUM.with_suffix(".rig.json").read_text())
    rig["pendulum"]["initial_angle"] = math.radians(2.5)
    t = np.arange(0, 3, 1e-3)
    swing = math.radians(2.5) * np.cos(2 * np.pi * t / 0.93) * np.exp(-t)
    offset = 2.5 - math.radians(2.5)  # the first sample reads 2.5: the degrees value, by the offset
    (tmp_path / "off.csv").write_text("t,pendulum_angle\n" + "".join(f"{a:.3f},{b + offset:.6f}\n" for a, b in zip(t, swing)))
    (tmp_path / "off.rig.json").write_text(json.dumps(dict(rig, record={"sensor_offset": offset})))
    _, read = load_pair(tmp_path / "off.csv")
    assert read.channel("pendulum_angle")[0] == pytest.approx(2.5, abs=1e-6)
    placeholder = dict(rig, pendulum=dict(rig["pendulum"], initial_angle=0.01))
    big = 0.55 * np.cos(2 * np.pi * t / 0.93) * np.exp(-t)  # 0.55 rad: 0.01 rad read in degrees is 0.573
    (tmp_path / "big.csv").write_text("t,pendulum_angle\n" + "".join(f"{a:.3f},{b:.6f}\n" for a, b in zip(t, big)))
    (tmp_path / "big.rig.json").write_text(json.dumps(dict(placeholder, record={"initial_angle": 0.55})))
    load_pair(tmp_path / "big.csv")
    (tmp_path / "big.rig.json").write_text(json.dumps(placeholder))
    assert main(["identify", str(tmp_path / "big.csv")]) == 2
    err = capsys.readouterr().err
    assert "state the unit" in err and "if it is in rad, the rig's pendulum.initial_angle is not where the record starts" in err


def test_rows_of_empty_cells_below_a_spreadsheets_data_are_blank_lines(tmp_path):
    _, plain = load_pair(PENDULUM.with_suffix(".csv"))
    _, padded = load_pair(spreadsheet_export(tmp_path, "padded", lambda rows: rows[:100] + [";;"] + rows[100:] + [";;"] * 3))
    assert np.allclose(padded.t, plain.t, rtol=0, atol=1e-12)
    assert np.array_equal(padded.channel("pendulum_angle"), plain.channel("pendulum_angle"))


def test_excels_separator_line_above_the_header_is_read_as_the_separator(tmp_path):
    _, plain = load_pair(PENDULUM.with_suffix(".csv"))
    record = spreadsheet_export(tmp_path, "sep")
    text = record.read_bytes().decode("utf-8-sig")
    record.write_bytes(("\ufeffsep=;\r\n" + text).encode())
    _, read = load_pair(record)
    assert np.allclose(read.t, plain.t, rtol=0, atol=1e-12)
    assert np.array_equal(read.channel("pendulum_angle"), plain.channel("pendulum_angle"))


def test_a_repeated_time_stamp_is_refused_naming_its_line(tmp_path, capsys):
    record = spreadsheet_export(tmp_path, "repeated", lambda rows: rows[:200] + [rows[199]] + rows[200:])
    assert main(["diagnose", str(record), "--json"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.strip().splitlines()) == 1
    # the header is line 1, the units row line 2: the 200th data row is line 202, its copy line 203
    assert f"{record}: line 203, column 't': time is not strictly increasing" in err and "199" in err


@pytest.mark.parametrize("units, column", [("s,m", "pendulum_angle"), ("m,rad", "t")])
def test_a_units_row_in_another_unit_is_refused_naming_line_and_column(tmp_path, capsys, units, column):
    f = record_with(tmp_path, "other_units", units)
    assert main(["identify", str(f), "--json"]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert captured.out == "" and len(err.splitlines()) == 1 and "Traceback" not in err
    assert f"other_units.csv: line 3, column {column!r}" in err and units.split(",")[column == "pendulum_angle"] in err


# --- a cam given by points, as exports give them ----------------------------------------------------------

def example_points():
    """The docs' example cam (docs/examples/cam_lift.csv: degrees and millimetres) in rad and m."""
    lines = (ROOT / "docs" / "examples" / "cam_lift.csv").read_text().splitlines()
    rows = csv.DictReader(line for line in lines if not line.startswith("#"))
    return [[math.radians(float(r["angle_deg"])), float(r["lift_mm"]) / 1000] for r in rows]


def cam_rig(tmp_path, points, name="cam", **extra):
    """The reference breaker with a cam from points, on a rigid main shaft: with the elastic shaft the
    pole levers ring, and the touch speed at the instant moves 3 % with 10 um of cam scatter
    (measured; the shaft's own tests: tests/models/test_main_shaft.py)."""
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    data["breaker"].pop("main_shaft", None)
    data["breaker"]["cam_profile"] = {"base_radius": 0.045, "points": points, **extra}
    return write_rig(tmp_path, data, name)


def test_a_closing_point_at_360_deg_and_angles_from_minus_180_give_the_same_cam(tmp_path):
    points = example_points()
    table = load_rig(cam_rig(tmp_path, points)).breaker.profile.table
    closed = points + [[points[0][0] + 2 * math.pi, points[0][1]]]
    assert load_rig(cam_rig(tmp_path, closed, "closed")).breaker.profile.table == pytest.approx(table, abs=1e-12)
    wrapped = sorted([[math.remainder(a, 2 * math.pi), v] for a, v in points])
    assert wrapped[0][0] < 0
    assert load_rig(cam_rig(tmp_path, wrapped, "wrapped")).breaker.profile.table == pytest.approx(table, abs=1e-9)


def points_refused(tmp_path, points, field, *words, **extra):
    with pytest.raises(InputError) as e:
        load_rig(cam_rig(tmp_path, points, "bad", **extra))
    text = str(e.value)
    assert f"breaker.cam_profile.{field}:" in text and "\n" not in text, text
    for word in words:
        assert word in text, text


def test_points_that_are_not_a_profile_are_refused_naming_the_point(tmp_path):
    points = example_points()
    points_refused(tmp_path, [[math.degrees(a), v] for a, v in points], "points", "in degrees")
    peak = max(range(len(points)), key=lambda k: points[k][1])
    points_refused(tmp_path, [[a, 1000 * v] for a, v in points], f"points.{peak}.1", "millimetres")
    points_refused(tmp_path, points[:50] + [points[49]] + points[50:], "points.50", "repeats point 49")
    swapped = points[:20] + [points[21], points[20]] + points[22:]
    points_refused(tmp_path, swapped, "points.21", "sort")
    opened = points + [[points[0][0] + 2 * math.pi, points[0][1] + 1e-4]]
    points_refused(tmp_path, opened, f"points.{len(points)}", "does not close")


def noisy(points, sigma, seed=5):
    rng = np.random.default_rng(seed)
    return [[a, v + float(rng.normal(0.0, sigma))] for a, v in points]


def test_the_scatter_estimate_finds_the_noise_added_and_not_the_design():
    points = example_points()
    clean = point_scatter([v for _, v in points])
    assert clean < 0.1 * P.CAM_POINT_SCATTER  # the export's rounding (0.1 um)
    for sigma in (1e-6, 1e-5):
        assert point_scatter([v for _, v in noisy(points, sigma)]) == pytest.approx(sigma, rel=0.25)


@pytest.mark.skipif(not compiler_works(), reason="no working C compiler")
def test_a_cmm_export_with_scatter_is_refused_and_closes_like_the_clean_cam_when_smoothed(tmp_path, capsys):
    """10 um of scatter (a CMM's) through a plain spline raises the peak roller force 2.5-fold
    (measured); refused without ``smoothing``. With it, the closing is the clean cam's within 1 %
    (touch speed) and 3 % (peak force): the clean points are the truth, the scatter added from outside."""
    points = example_points()
    rough = cam_rig(tmp_path, noisy(points, 1e-5), "rough")
    assert main(["check", str(rough)]) == 2
    err = capsys.readouterr().err
    assert "breaker.cam_profile.points: the points scatter by about" in err and "smoothing" in err
    clean_rig = load_rig(cam_rig(tmp_path, points, "clean"))
    smoothed_rig = load_rig(cam_rig(tmp_path, noisy(points, 1e-5), "smoothed", smoothing=1e-5))
    clean = figures_of_merit(simulate(clean_rig, backend="compiled"), clean_rig)
    smoothed = figures_of_merit(simulate(smoothed_rig, backend="compiled"), smoothed_rig)
    assert smoothed["per_pole"]["touch_speed_m_s"] == pytest.approx(clean["per_pole"]["touch_speed_m_s"], rel=0.01)
    assert smoothed["peak_cam_roller_force_N"] == pytest.approx(clean["peak_cam_roller_force_N"], rel=0.03)
    assert main(["check", str(cam_rig(tmp_path, noisy(points, 1e-5), "shown", smoothing=1e-5))]) == 0
    assert "smoothing spline (within about 10 um" in capsys.readouterr().out


# --- rig files as users write them ------------------------------------------------------------------------

def refused_one_line(capsys, path, *words):
    assert main(["check", str(path)]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert captured.out == "" and len(err.splitlines()) == 1 and "Traceback" not in err, err
    for word in words:
        assert word in err, err


def test_angles_in_degrees_are_refused_where_a_turn_bounds_them(tmp_path, capsys):
    """An end stop at 250 (meant as degrees) would be 40 turns on: never met, so the run is the
    breaker's without a stop; a cam starting at 10 (degrees) would start at 213 deg."""
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    data["breaker"]["end_stop"]["angle"] = 250.0
    data["breaker"]["hold_latch"]["angle"] = 4.3
    refused_one_line(capsys, write_rig(tmp_path, data, "stop_deg"), "breaker.end_stop.angle", "in degrees?")
    data = copy.deepcopy(P.REFERENCE_CAM)
    data["cam"]["initial_angle"] = 10.0
    refused_one_line(capsys, write_rig(tmp_path, data, "start_deg"), "cam.initial_angle", "in degrees?")


def test_a_toml_rig_or_json_with_comments_is_refused_saying_what_rigs_are(tmp_path, capsys):
    toml = tmp_path / "my.rig.toml"
    toml.write_text('experiment = "vcb_closing"\n[friction]\nmu_k = 0.1\n')
    refused_one_line(capsys, toml, "my.rig.toml: line 1", "rig files are JSON")
    text = json.dumps(P.REFERENCE_CAM, indent=1).replace("{", "{\n// measured 2026-11-20", 1)
    commented = tmp_path / "commented.rig.json"
    commented.write_text(text)
    refused_one_line(capsys, commented, "commented.rig.json: line 2", "keys starting with _")


@pytest.mark.parametrize("change, field, hint", [
    ({"wire_diameter": 7.84, "coil_diameter": 47.0}, "closing_spring.wire_diameter", "millimetres"),
    ({"shear_modulus": 79.3}, "closing_spring.shear_modulus", "in GPa?"),
    ({"density": 7.85}, "closing_spring.density", "g/cm^3"),
    ({"coil_diameter": 0.47}, "closing_spring.coil_diameter", "spring index D/d of 59.9"),
])
def test_a_datasheet_in_the_wrong_units_is_refused(tmp_path, capsys, change, field, hint):
    """A datasheet in mm (k0 = G d^4 / (8 D^3 n): 1000x the rate) or G in GPa (1e-9 of it) was read
    as a valid spring ('within the allowable') and simulated."""
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    spring = data["closing_spring"]
    for key in ("stiffness", "mass"):
        spring.pop(key)
    spring.update(wire_diameter=0.00784, coil_diameter=0.047, active_coils=15.0, shear_modulus=79.3e9)
    assert main(["check", str(write_rig(tmp_path, data, "sheet"))]) == 0
    capsys.readouterr()
    spring.update(change)
    refused_one_line(capsys, write_rig(tmp_path, data, "wrong_units"), field, hint)


# --- a cam's points straight from its CSV export (breaker.cam_profile.points_file) -------------------------

def file_rig(tmp_path, text, name="from_file", encoding_bom=False, newline="\n"):
    f = tmp_path / f"{name}.csv"
    f.write_bytes((b"\xef\xbb\xbf" if encoding_bom else b"") + newline.join(text).encode() + newline.encode())
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    data["breaker"]["cam_profile"] = {"base_radius": 0.045, "points_file": f.name}
    return write_rig(tmp_path, data, name)


def test_a_points_file_in_degrees_and_millimetres_is_the_same_cam_as_its_points(tmp_path):
    table = load_rig(cam_rig(tmp_path, example_points())).breaker.profile.table
    example = (ROOT / "docs" / "examples" / "cam_lift.csv").read_text().splitlines()
    assert load_rig(file_rig(tmp_path, example)).breaker.profile.table == pytest.approx(table, abs=1e-15)
    # a spreadsheet's export: semicolons, decimal commas, units in brackets, a BOM, CRLF, blank lines at the end
    body = [line if line.startswith("#") else line.replace(",", ";").replace(".", ",") for line in example]
    body = [line.replace("angle_deg;lift_mm", "Angle [deg];Lift [mm]") for line in body] + ["", ""]
    rig = file_rig(tmp_path, body, "spreadsheet", encoding_bom=True, newline="\r\n")
    assert load_rig(rig).breaker.profile.table == pytest.approx(table, abs=1e-15)


def test_a_points_file_without_units_or_with_a_bad_row_is_refused_naming_file_and_line(tmp_path, capsys):
    example = (ROOT / "docs" / "examples" / "cam_lift.csv").read_text().splitlines()
    no_units = [line.replace("angle_deg,lift_mm", "angle,lift") for line in example]
    refused_one_line(capsys, file_rig(tmp_path, no_units, "no_units"), "no_units.csv: line 3", "with their units")
    gap = example[:10] + [example[10].split(",")[0] + ","] + example[11:]
    refused_one_line(capsys, file_rig(tmp_path, gap, "gap"), "gap.csv: line 11", "two finite numbers")
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    data["breaker"]["cam_profile"] = {"base_radius": 0.045, "points_file": "absent.csv"}
    refused_one_line(capsys, write_rig(tmp_path, data, "absent"), "breaker.cam_profile.points_file", "no such file")
    dup = example[:20] + [example[19]] + example[20:]
    refused_one_line(capsys, file_rig(tmp_path, dup, "dup"), "breaker.cam_profile.points_file.17", "repeats point 16")


def test_excels_tab_separator_line_is_read_as_a_tab(tmp_path):
    """``sep=<TAB>`` above a tab-separated table (the line's tab is whitespace at its end)."""
    _, plain = load_pair(PENDULUM.with_suffix(".csv"))
    lines = PENDULUM.with_suffix(".csv").read_text().splitlines()
    header = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    body = "\n".join(line.replace(",", "\t") for line in lines[header:])
    (tmp_path / "tab.csv").write_text("sep=\t\n" + body + "\n")
    (tmp_path / "tab.rig.json").write_text(PENDULUM.with_suffix(".rig.json").read_text())
    _, read = load_pair(tmp_path / "tab.csv")
    assert np.allclose(read.t, plain.t, rtol=0, atol=1e-12)
    assert np.array_equal(read.channel("pendulum_angle"), plain.channel("pendulum_angle"))

"""Bad input: one line naming file and field, exit status 2, nothing written (spec cli.md)."""
import subprocess
import sys
from pathlib import Path

import pytest

from vcbmodel.app.cli import main
from vcbmodel.experiments.loading import load_rig
from vcbmodel.records.measurement import load_measurement

BAD = Path(__file__).resolve().parents[1] / "bad_rigs"
GOOD_CAM = BAD / "good_cam.rig.json"
GOOD_PENDULUM = BAD / "good_pendulum.rig.json"

RIGS = [  # file, the field the message must name
    ("missing_cam", "cam"), ("missing_spring", "closing_spring"), ("missing_pendulum", "pendulum"),
    ("missing_shaft", "shaft"), ("missing_model", "model"), ("missing_arm_length", "cam.arm_length"),
    ("missing_pendulum_mass", "pendulum.mass"), ("negative_cam_mass", "cam.mass"),
    ("negative_spring_mass", "closing_spring.mass"), ("zero_stiffness", "closing_spring.stiffness"),
    ("negative_inertia", "pendulum.inertia"), ("string_number", "cam.inertia_com"), ("bad_pivot", "cam.pivot"),
    ("unknown_effect", "model.effects"), ("effect_twice", "model.effects"),
    ("unknown_spring_model", "model.spring_model"), ("spring_mass_inconsistent", "model.effects"),
    ("unknown_convention", "model.lumped_convention"), ("unknown_friction_key", "friction.mu_static"),
    ("mu_s_below_mu_k", "friction.mu_s"), ("negative_mu", "friction.mu_k"),
    ("uncharged_spring", "closing_spring.free_length"), ("wrong_format", "format"),
    ("unknown_experiment", "experiment"), ("pendulum_with_spring_model", "model."),
    ("fractional_count", "closing_spring.count"), ("malformed_trailing_comma", "line"),
    ("malformed_truncated", "line"), ("nan_value", "JSON"), ("infinity_value", "JSON"),
    ("not_an_object", "top level"), ("end_stop_without_damping", "breaker.end_stop.damping"),
    ("hold_latch_negative_stiffness", "breaker.hold_latch.stiffness"),
    ("hold_latch_beyond_end_stop", "breaker.hold_latch.angle"), ("end_stop_before_start", "breaker.end_stop.angle"),
]
CSVS = [
    ("no_header", "header"), ("first_column_not_t", "line 1"), ("unknown_channel", "cam_angel"),
    ("nan_value", "line 3"), ("not_a_number", "line 3"), ("wrong_column_count", "line 3"),
    ("time_decreasing", "column 't'"), ("time_repeated", "column 't'"), ("too_few_rows", "data"),
    ("wrong_channel_for_rig", "line 1"), ("inf_value", "line 3"), ("duplicate_column", "line 1"),
]


def assert_refused(capsys, argv, filename, field, tmp_path):
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert filename in lines[0] and field in lines[0], lines[0]
    assert "Traceback" not in err and out == ""
    assert list(tmp_path.iterdir()) == []  # nothing written


@pytest.mark.parametrize("name,field", RIGS, ids=[r[0] for r in RIGS])
def test_bad_rig_simulate(name, field, capsys, tmp_path):
    f = BAD / f"{name}.rig.json"
    assert_refused(capsys, ["simulate", str(f), "-o", str(tmp_path / "out.csv")], f.name, field, tmp_path)


@pytest.mark.parametrize("name,field", RIGS[:8], ids=[r[0] for r in RIGS[:8]])
def test_bad_rig_diagnose(name, field, capsys, tmp_path):
    f = BAD / f"{name}.rig.json"
    assert_refused(capsys, ["diagnose", str(BAD / "good.csv"), "--rig", str(f), "--plot", str(tmp_path / "d.png")],
                   f.name, field, tmp_path)


@pytest.mark.parametrize("text", ["", "\r\n  \n"])
def test_an_empty_rig_is_said_to_be_empty(text, capsys, tmp_path):
    rigs = tmp_path / "rigs"
    rigs.mkdir()
    f = rigs / "empty.rig.json"
    f.write_text(text)
    out = tmp_path / "out"
    out.mkdir()
    assert_refused(capsys, ["simulate", str(f), "-o", str(out / "x.csv")], f"{f}: file: is empty", "init", out)


@pytest.mark.parametrize("name,field", CSVS, ids=[c[0] for c in CSVS])
def test_bad_measurement(name, field, capsys, tmp_path):
    f = BAD / f"{name}.csv"
    assert_refused(capsys, ["diagnose", str(f), "--rig", str(GOOD_CAM), "--plot", str(tmp_path / "d.png")],
                   f.name, field, tmp_path)


def test_identify_refuses_cam_data_and_bad_csv(capsys, tmp_path):
    assert_refused(capsys, ["identify", str(BAD / "good.csv"), "--rig", str(GOOD_CAM)], "good_cam.rig.json",
                   "experiment", tmp_path)
    assert_refused(capsys, ["identify", str(BAD / "nan_value.csv"), "--rig", str(GOOD_PENDULUM)], "nan_value.csv",
                   "line", tmp_path)


@pytest.mark.parametrize("args,field", [
    (["--effects", "coulomb_friction,bogus"], "effects"),
    (["--spring-model", "lumped-0"], "spring_model"),
    (["--t-end", "-1"], "t_end"),
    (["--t-end", "nan"], "t_end"),
])
def test_bad_options(args, field, capsys, tmp_path):
    assert_refused(capsys, ["simulate", str(GOOD_CAM), "-o", str(tmp_path / "o.csv"), *args], "", field, tmp_path)


def test_missing_file_and_output_folder(capsys, tmp_path):
    assert_refused(capsys, ["simulate", str(tmp_path / "nope.rig.json")], "nope.rig.json", "file", tmp_path)
    code = main(["simulate", str(GOOD_CAM), "-o", str(tmp_path / "no" / "such" / "o.csv")])
    assert code == 2 and len(capsys.readouterr().err.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_pendulum_has_no_spring_model(capsys, tmp_path):
    assert_refused(capsys, ["simulate", str(GOOD_PENDULUM), "--spring-model", "lumped-2"], "", "spring_model", tmp_path)


def test_argparse_errors_are_one_line_exit_2():
    p = subprocess.run([sys.executable, "-m", "vcbmodel", "frobnicate"], capture_output=True, text=True)
    assert p.returncode == 2 and len(p.stderr.strip().splitlines()) == 1 and p.stdout == ""


def test_good_files_are_accepted():
    assert load_rig(GOOD_CAM).experiment == "cam_drop"
    assert load_measurement(BAD / "good.csv", "cam_angle").t.size == 4

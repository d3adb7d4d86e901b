"""Records as analysers and loggers write them: the time column headed ``Time [ms]``, units such as
``µs`` and ``°`` (UTF-8) in the header or a units row, a closing export whose drive travel carries
another name (refused with what to rename), and records too short to analyse (refused before any
work, one line, for every command that reads records)."""
import math
import pickle

import numpy as np
import pytest

from vcbmodel.app.cli import main
from vcbmodel.errors import InputError
from vcbmodel.experiments.base import MIN_SAMPLES
from vcbmodel.experiments.loading import load_pair

from conftest import ROOT

BAD = ROOT / "tests" / "bad_rigs"
CAM, PENDULUM = BAD / "good_cam.rig.json", BAD / "good_pendulum.rig.json"
T = np.arange(120) * 5e-4  # a 60 ms cam drop at 2 kHz
ANGLE = 0.17 + 60.0 * np.clip(T - 0.004, 0.0, None) ** 2  # rad


def write(path, head, rows):
    path.write_text("\n".join(head + rows) + "\n", encoding="utf-8")
    return path


def refused(capsys, argv, name, field):
    assert main(argv) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and name in lines[0] and field in lines[0], captured.err
    assert "Traceback" not in captured.err and captured.out == ""
    return lines[0]


@pytest.mark.parametrize("head, scale_t, scale_y, separator", [
    (["Time [ms];cam_angle [°]"], 1e3, 180 / np.pi, ";"),  # a German locale: decimal commas, degrees
    (["time,cam_angle", "µs,°"], 1e6, 180 / np.pi, ","),  # a units row under the header (micro sign)
    (["Time (\u03bcs),cam_angle (mrad)"], 1e6, 1e3, ","),  # the Greek mu typed for the micro sign
])
def test_an_analysers_time_column_and_utf8_units_read_as_si(tmp_path, head, scale_t, scale_y, separator):
    rows = [f"{scale_t * t!r}{separator}{scale_y * y!r}" for t, y in zip(T.tolist(), ANGLE.tolist())]
    if separator == ";":
        rows = [r.replace(".", ",") for r in rows]
    f = write(tmp_path / "drop.csv", head, rows)
    _, m = load_pair(f, CAM)
    assert np.allclose(m.t, T, rtol=0, atol=1e-12) and np.allclose(m.channels["cam_angle"], ANGLE, rtol=1e-12, atol=0)


def test_a_header_in_another_encoding_is_refused_naming_the_line(tmp_path, capsys):
    f = tmp_path / "drop.csv"
    f.write_bytes("t [ms],cam_angle [°]\n".encode("cp1252") + b"".join(
        f"{1e3 * t!r},{y!r}\n".encode() for t, y in zip(T.tolist(), ANGLE.tolist())))
    line = refused(capsys, ["diagnose", str(f), "--rig", str(CAM)], "drop.csv", "line 1")
    assert "UTF-8" in line


def test_time_is_the_first_column_only(tmp_path, capsys):
    f = write(tmp_path / "drop.csv", ["cam_angle,time"], [f"{y!r},{t!r}" for t, y in zip(T.tolist(), ANGLE.tolist())])
    line = refused(capsys, ["diagnose", str(f), "--rig", str(CAM)], "drop.csv", "line 1")
    assert "'t' or 'time'" in line


def test_a_closing_export_without_the_drive_travel_says_what_to_rename(tmp_path, capsys):
    """An analyser's per-pole travels and contacts, its drive travel under the analyser's own name."""
    head = ["Time [ms],Travel [mm],pole_1_travel [mm],pole_1_contact [-]"]
    rows = [f"{1e3 * t!r},{1e3 * y / 20!r},{1e3 * y / 20!r},0" for t, y in zip(T.tolist(), ANGLE.tolist())]
    f = write(tmp_path / "closing.csv", head, rows)
    rig = ROOT / "results" / "synthetic" / "vcb_closing.rig.json"
    line = refused(capsys, ["diagnose", str(f), "--rig", str(rig)], "closing.csv", "follower_displacement")
    assert "unknown channel" in line and "'travel'" in line  # the analyser's name is not a channel
    f = write(tmp_path / "closing.csv", [head[0].replace("Travel [mm],", "")],
              [r.split(",", 2)[0] + "," + r.split(",", 2)[2] for r in rows])
    line = refused(capsys, ["diagnose", str(f), "--rig", str(rig)], "closing.csv", "line 1")
    assert "needs the column 'follower_displacement' (it has t, pole_1_travel, pole_1_contact)" in line
    assert "name that column 'follower_displacement'" in line
    assert "not a pole's travel" in line and "the poles alone cannot be fitted" in line  # renaming one would mislead


@pytest.mark.parametrize("samples", [3, 10, MIN_SAMPLES - 1])
def test_a_record_too_short_to_analyse_is_refused_before_any_work(tmp_path, capsys, samples):
    """diagnose (a 3-sample record raised an IndexError in the release fit) and identify, and the
    Python API: one line naming the file and the field, exit 2, nothing written."""
    t = np.linspace(0.0, 0.3, samples).tolist()
    drop = write(tmp_path / "drop.csv", ["t,cam_angle"], [f"{a!r},{0.17 + a * a!r}" for a in t])
    swing = write(tmp_path / "swing.csv", ["t,pendulum_angle"], [f"{a!r},{0.17 * math.cos(5 * a)!r}" for a in t])
    plot = tmp_path / "d.png"
    line = refused(capsys, ["diagnose", str(drop), "--rig", str(CAM), "--plot", str(plot)], "drop.csv", "data")
    assert f"{samples} samples" in line and f"at least {MIN_SAMPLES}" in line and not plot.exists()
    refused(capsys, ["identify", str(swing), "--rig", str(PENDULUM)], "swing.csv", "data")
    with pytest.raises(InputError, match="data"):
        load_pair(drop, CAM)


def test_an_input_error_survives_a_worker_process():
    """Raised in a diagnosis worker, it must reach the command line as itself (pickled and back)."""
    e = pickle.loads(pickle.dumps(InputError("x.csv", "data", "too few")))
    assert isinstance(e, InputError) and str(e) == "x.csv: data: too few" and e.field == "data"


def test_diagnose_from_python_refuses_a_short_record_built_in_code():
    from vcbmodel.analysis.diagnose import diagnose
    from vcbmodel.experiments.loading import load_rig
    from vcbmodel.records.measurement import Measurement

    m = Measurement("made.csv", np.array([0.0, 0.01, 0.02]), {"cam_angle": np.array([0.1, 0.2, 0.3])})
    with pytest.raises(InputError, match="made.csv: data: 3 samples"):
        diagnose(load_rig(CAM), m, processes=1, verbose=False)

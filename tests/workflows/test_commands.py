"""The front door's commands (issue 17, section 3): init writes a commented rig that simulates as
written, check explains a rig without solving it, simulate prints a one-run summary with units,
writes every record channel of a closing and draws it; help text agrees with what works."""
import json

import pytest
from matplotlib.backend_bases import FigureCanvasBase

from vcbmodel.app.cli import build_parser, main
from vcbmodel.experiments import experiment_of
from vcbmodel.experiments.loading import load_record, load_rig

KINDS = ("pendulum", "cam_drop", "vcb_closing")
T_END = {"pendulum": "1.0", "cam_drop": "0.01", "vcb_closing": "0.045"}


@pytest.mark.parametrize("kind", KINDS)
def test_init_writes_a_commented_rig_that_check_explains_and_simulate_runs(kind, tmp_path, capsys):
    rig = tmp_path / f"{kind}.rig.json"
    assert main(["init", kind, "-o", str(rig)]) == 0
    data = json.loads(rig.read_text())
    assert data["experiment"] == kind and "_about" in data and "SI units" in data["_about"]
    assert any("_units" in v for v in data.values() if isinstance(v, dict))
    capsys.readouterr()
    assert main(["check", str(rig)]) == 0
    out = capsys.readouterr().out
    assert f"a valid {kind} rig" in out and "it reports:" in out
    csv = tmp_path / f"{kind}.csv"
    assert main(["simulate", str(rig), "--t-end", T_END[kind], "-o", str(csv), "--plot", str(tmp_path / "p.png")]) == 0
    summary = capsys.readouterr().out
    assert summary.startswith(data["name"]) and len(summary.strip().splitlines()) >= 3
    assert (tmp_path / "p.png").stat().st_size > 5000
    # what simulate wrote is a record the tools read back
    meas = load_record(csv, load_rig(rig))
    assert experiment_of(kind).measured_channel in meas.channels


def test_a_closing_writes_every_pole_channel_and_a_summary_with_units(tmp_path, capsys):
    rig = tmp_path / "b.rig.json"
    main(["init", "vcb_closing", "-o", str(rig)])
    csv = tmp_path / "b.csv"
    capsys.readouterr()
    assert main(["simulate", str(rig), "-o", str(csv)]) == 0
    summary = capsys.readouterr().out
    for words in ("pole 1", "pole 3", "closing time (touch)", "speed at touch", "pole spread", "bounces", "overtravel",
                  "contact force closed"):
        assert words in summary
    assert " m/s " in summary and " ms " in summary and " mm " in summary and " kN " in summary
    lines = [line for line in csv.read_text().splitlines() if line.startswith("#")]
    header = [line for line in csv.read_text().splitlines() if not line.startswith("#")][0].split(",")
    per_pole = [f"pole_{i}_{c}" for i in (1, 2, 3) for c in ("travel", "velocity", "contact")]
    forces = [f"pole_{i}_{c}_force" for i in (1, 2, 3) for c in ("contact", "rod")] + ["cam_roller_force"]
    assert header[:11] == ["t", "follower_displacement"] + per_pole and set(forces) <= set(header)
    assert {"cam_angle", "shaft_velocity"} <= set(header)
    # every column's unit is stated, none unknown
    stated = dict(part.strip().split(" in ") for part in lines[1].lstrip("# ").split(",")[:-1])
    assert set(stated) == set(header) and "?" not in stated.values()
    assert stated["pole_1_velocity"] == "m/s" and stated["cam_roller_force"] == "N"
    meas = load_record(csv, load_rig(rig))
    assert set(meas.channels["pole_1_contact"]) == {0.0, 1.0}  # the analyser's timing channel: open, then closed


def test_init_and_check_refuse_what_they_should(tmp_path, capsys):
    rig = tmp_path / "p.rig.json"
    rig.write_text("mine")
    assert main(["init", "pendulum", "-o", str(rig)]) == 2 and rig.read_text() == "mine"
    assert "--force" in capsys.readouterr().err
    data = json.loads(__import__("vcbmodel.app.templates", fromlist=["template"]).template("pendulum"))
    del data["friction"]["mu_k"]
    rig.write_text(json.dumps(data))
    assert main(["check", str(rig)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "friction.mu_k" in err[0]


def test_help_lists_every_image_format_matplotlib_writes():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices
    for command in ("diagnose", "simulate"):
        text = sub[command].format_help()
        if command == "diagnose":
            for fmt in FigureCanvasBase.get_supported_filetypes():
                assert fmt in text, fmt


def test_quiet_silences_progress_but_not_results(tmp_path, capfd):
    rig = tmp_path / "c.rig.json"
    main(["init", "cam_drop", "-o", str(rig), "--quiet"])
    capfd.readouterr()
    assert main(["simulate", str(rig), "--t-end", "0.005", "-o", str(tmp_path / "c.csv"), "--quiet"]) == 0
    out, err = capfd.readouterr()
    assert err == "" and "cam angle at the end" in out
    assert main(["simulate", str(rig), "--t-end", "0.005", "-o", str(tmp_path / "d.csv")]) == 0
    assert "simulate my cam drop" in capfd.readouterr().err

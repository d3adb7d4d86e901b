"""The command line's happy paths and its solver-failure path (spec cli.md)."""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from conftest import EXAMPLES, examples_available
from vcbmodel.analysis.synthetic import synthetic_measurement
from vcbmodel.app.cli import main
from vcbmodel.errors import SimulationError
from vcbmodel.records.measurement import load_measurement, write_measurement

GOOD_CAM = Path(__file__).resolve().parents[1] / "bad_rigs" / "good_cam.rig.json"


def test_simulate_writes_a_measurement_file(tmp_path, capsys):
    out = {}
    for model in ("massless", "lumped-2"):
        f = tmp_path / f"{model}.csv"
        assert main(["simulate", str(GOOD_CAM), "--spring-model", model, "-o", str(f)]) == 0
        m = load_measurement(f, "cam_angle")
        assert m.t[-1] == pytest.approx(0.035)
        assert np.allclose(np.diff(m.t), 1 / 12000, atol=2e-7)  # times are written to 0.1 us
        assert np.all(np.isfinite(m.channels["cam_angle"]))
        assert any("SIMULATED" in c for c in m.comments)
        out[model] = m.channels["cam_angle"]
    assert np.max(np.abs(out["massless"] - out["lumped-2"])) > 0.01


def test_simulate_to_stdout_with_overrides(capsys):
    assert main(["simulate", str(GOOD_CAM), "--effects", "", "--t-end", "0.01"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    comments = [ln for ln in lines if ln.startswith("#")]
    data = [ln for ln in lines if not ln.startswith("#")]
    assert any("cam_angle in rad" in c for c in comments)  # the unit is stated
    assert data[0] == "t,cam_angle" and len(data) == 1 + 120 + 1


def test_solver_failure_exits_1_with_one_line(monkeypatch, capsys, tmp_path):
    def boom(*a, **k):
        raise SimulationError("the solution diverged (non-finite angle) at the experiment's fixed step")
    monkeypatch.setattr("vcbmodel.app.cli.simulate", boom)
    assert main(["simulate", str(GOOD_CAM), "-o", str(tmp_path / "x.csv"), "--quiet"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "diverged" in err[0]
    assert not (tmp_path / "x.csv").exists()


def test_help_everywhere(capsys):
    p = subprocess.run([sys.executable, "-m", "vcbmodel", "--help"], capture_output=True, text=True)
    assert p.returncode == 0 and "usage" in p.stdout  # the module runs as a program
    for command in ("simulate", "identify", "diagnose", "sweep", "check", "init", "plot"):
        with pytest.raises(SystemExit) as e:
            main([command, "--help"])
        assert e.value.code == 0 and f"usage: vcbmodel {command}" in capsys.readouterr().out


@pytest.mark.skipif(not examples_available(), reason="shared example data not present")
def test_diagnose_json_and_plot(tmp_path):
    png = tmp_path / "d.png"
    p = subprocess.run(["vcbmodel", "diagnose", str(EXAMPLES / "example05.csv"), "--json", "--plot", str(png)],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    assert j["missing_effect"] == "coulomb_friction" and j["rms_after"] < 0.5 * j["rms_before"]
    assert png.stat().st_size > 10_000
    assert "diagnose:" in p.stderr  # progress goes to stderr, the JSON alone to stdout


def test_identify_json(tmp_path, pendulum_rig):
    meas = synthetic_measurement(pendulum_rig, ("coulomb_friction",), {"mu_k": 0.12}, seed=3, t_end=2.0)
    f = tmp_path / "p.csv"
    write_measurement(meas, f)
    p = subprocess.run(["vcbmodel", "identify", str(f), "--rig", pendulum_rig.path, "--law", "stick-slip", "--json"],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    j = json.loads(p.stdout)
    for key in ("law", "mu_s", "mu_k", "stick_velocity", "stribeck_velocity", "viscous", "zeta", "rms",
                "max_error_percent"):
        assert key in j
    assert j["mu_k"] == pytest.approx(0.12, rel=0.05) and j["viscous"] == 0.0


@pytest.mark.parametrize("model", ["lumped-3", "ancf"])
def test_stdout_carries_only_the_csv(model, tmp_path):
    """Exudyn's own console messages (e.g. its memory-allocation warning with Python user
    functions) must not leak into the CSV written to stdout."""
    p = subprocess.run(["vcbmodel", "simulate", str(GOOD_CAM), "--spring-model", model, "--t-end", "0.005"],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    data = [ln for ln in lines if not ln.startswith("# ")]
    assert lines[0].startswith("# ") and data[0] == "t,cam_angle"
    assert all(len(l.split(",")) == 2 and float(l.split(",")[1]) == float(l.split(",")[1]) for l in data[1:])

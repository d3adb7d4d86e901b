"""Every study script runs (quick mode) and writes its outputs: build, run, plot, save."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

STUDIES = Path(__file__).resolve().parents[2] / "studies"

EXPECTED = {
    "friction_identification.py": ["friction_identification.png", "friction_identification.json",
                                   "synthetic/pendulum_10deg.csv"],
    "spring_models.py": ["cam_drop_fig9a.png", "cam_drop_fig9b.png", "spring_modes.md", "spring_fidelity.json",
                         "spring_convergence.png", "spring_shapes_fig10.png", "spring_lateral.png", "cam_drop.gif",
                         "synthetic/cam_drop_m0_1kg.csv"],
    "discrepancy_demo.py": ["discrepancy_demo_cam.png", "discrepancy_demo_pendulum.png", "discrepancy_demo.json"],
    "discovery_demo.py": ["discovery.png", "discovery_cam.png", "discovery.json", "discovery.md",
                          "synthetic/discovery_demo.rig.json", "synthetic/discovery_cam.rig.json"],
    "diagnosis_sweep.py": ["diagnosis_sweep.json", "diagnosis_sweep.md"],
    "diagnosis_realism.py": ["diagnosis_realism.json", "diagnosis_realism.md", "diagnosis_realism.png"],
    "benchmark.py": ["benchmark.json", "benchmark.md"],
    "spring_reading.py": ["spring_reading.json", "spring_reading.md"],
    "vcb_closing.py": ["vcb_closing_fig12.png", "vcb_closing_detail.png", "vcb_closing_energy_split.png", "vcb_closing.json", "vcb_closing.md",
                       "synthetic/vcb_closing.csv"],
    "design_sensitivity.py": ["design_sensitivity_tornado.png", "design_sensitivity_sobol.png",
                              "design_sensitivity.json", "design_sensitivity.md"],
    "design_tolerance.py": ["design_tolerance.png", "design_tolerance.json", "design_tolerance.md",
                            "design_tolerance_runs.csv"],
    "design_conclusion_map.py": ["design_conclusion_map.png", "design_conclusion_map.json", "design_conclusion_map.md"],
    "design_optimum.py": ["design_optimum.png", "design_optimum.json", "design_optimum.md"],
}


#: Smoke runs over a minute each on 2 cores: run with plain `python -m pytest` (CI keeps its 10-minute
#: budget; the sweep machinery itself is tested in test_sweep.py, the conclusion map stays in CI).
SLOW = {"design_sensitivity.py", "design_tolerance.py", "design_optimum.py", "benchmark.py"}


@pytest.mark.parametrize("script", [pytest.param(s, marks=pytest.mark.slow) if s in SLOW else s for s in sorted(EXPECTED)])
def test_study_runs_and_writes_outputs(script, tmp_path):
    p = subprocess.run([sys.executable, str(STUDIES / script), "--quick", "--out", str(tmp_path)],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr[-2000:]
    for name in EXPECTED[script]:
        f = tmp_path / name
        assert f.exists() and f.stat().st_size > 100, name
    for f in tmp_path.glob("*.json"):
        json.loads(f.read_text())
    for f in tmp_path.glob("*.png"):
        assert f.stat().st_size < 500_000  # small enough to commit


def test_every_study_is_smoke_tested():
    scripts = {p.name for p in STUDIES.glob("*.py") if not p.name.startswith("_") and p.name != "run_all.py"}
    assert scripts == set(EXPECTED)

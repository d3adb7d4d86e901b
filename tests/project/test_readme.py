"""The README is a manual: its two opening commands, its length, and a quick start that runs as written."""
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def _bash_blocks(text):
    return re.findall(r"```bash\n(.*?)```", text, re.S)


def _commands(block):
    return [ln for ln in block.splitlines() if ln.strip() and not ln.lstrip().startswith("#")]


def test_readme_opens_with_exactly_the_two_commands_ci_runs():
    first = _commands(_bash_blocks(README)[0])
    assert len(first) == 2
    assert "studies/run_all.py" in first[0] and "pip install" in first[0]
    assert "pytest" in first[1] and '".[test]"' in first[1]
    ci = subprocess.run([sys.executable, str(ROOT / ".ci" / "readme_command.py"), "test"],
                        capture_output=True, text=True, check=True).stdout.strip()
    assert ci == first[1]


def test_readme_is_a_manual_not_a_notebook():
    assert len(README.splitlines()) <= 200
    for word in ("overturn", "was 2.0", "the earlier README"):
        assert word not in README, f"history belongs in docs/findings.md or CHANGELOG.md: {word!r}"
    for link in re.findall(r"\]\(((?:docs/|results/|CHANGELOG)[^)#]*)", README):
        assert (ROOT / link).exists(), link


def test_quick_start_runs_as_written(tmp_path):
    """Every line of the quick start, run by bash from the repository's root, with vcbmodel on PATH."""
    section = README.split("## Quick start", 1)[1]
    block = _bash_blocks(section)[0]
    env = dict(os.environ, PATH=str(Path(sys.executable).parent) + os.pathsep + os.environ["PATH"],
               TMPDIR=str(tmp_path), MPLBACKEND="Agg")
    script = "set -euo pipefail\n" + block + 'echo "OUT=$out"\n'
    run = subprocess.run(["bash", "-c", script], cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    out = Path(run.stdout.strip().splitlines()[-1].split("=", 1)[1])
    assert out.parent == tmp_path
    diagnosis = json.loads((out / "diagnosis.json").read_text())
    assert diagnosis["missing_effects"] == ["viscous_friction"]  # what the README says it finds
    assert diagnosis["explained"] is True and diagnosis["ambiguous"] == []
    fitted_units = {k.split(".", 1)[1]: u for k, u in diagnosis["units"].items() if k.startswith("fitted.")}
    assert set(diagnosis["fitted"]) <= set(fitted_units) and fitted_units["viscous"] == "N m s/rad"
    friction = json.loads((out / "friction.json").read_text())
    assert "mu_k" in json.dumps(friction)
    sweep = pd.read_csv(out / "sweep.csv", comment="#")
    assert len(sweep) == 3 and set(sweep["status"]) == {"ok"}
    assert json.loads((out / "my.rig.json").read_text())["experiment"] == "cam_drop"
    assert "a valid cam_drop rig" in run.stdout and "cam angle at the end" in run.stdout
    assert (out / "drop.csv").stat().st_size > 1000 and (out / "diagnosis.png").stat().st_size > 1000
    cycle = json.loads((out / "cycle.json").read_text())  # O - 0.3 s - CO: an opening, then a closing and opening
    assert [op["op"] for op in cycle["operations"]] == ["O", "CO"], cycle["operations"]

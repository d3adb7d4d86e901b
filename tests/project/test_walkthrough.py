"""docs/your-breaker.md's walk-through (a cam from points, a spring from its datasheet) runs as written and
prints the lines the page shows (the block marked ``<!-- doctest: walk-through -->``, matched as
test_doc_examples.py matches an example)."""
import os
import re
import subprocess
import sys
from pathlib import Path

from test_doc_examples import missing_lines

ROOT = Path(__file__).resolve().parents[2]
PAGE = (ROOT / "docs" / "your-breaker.md").read_text(encoding="utf-8")


def test_walkthrough_runs_as_written(tmp_path):
    block = re.findall(r"```bash\n(.*?)```", PAGE, re.S)[0]
    env = dict(os.environ, PATH=str(Path(sys.executable).parent) + os.pathsep + os.environ["PATH"],
               TMPDIR=str(tmp_path), MPLBACKEND="Agg")
    run = subprocess.run(["bash", "-c", "set -euo pipefail\n" + block + 'echo "OUT=$out"\n'], cwd=ROOT, env=env,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    out = Path(run.stdout.strip().splitlines()[-1].split("=", 1)[1])
    # check reported the datasheet spring and the cam from points
    assert "from the datasheet" in run.stdout and "spline through the rig's points" in run.stdout
    assert "largest pressure angle" in run.stdout
    # the closing ran and closed every pole
    csv_text = (out / "closing.csv").read_text()
    assert "follower_displacement" in csv_text and "pole_3_contact" in csv_text
    touch_row = run.stdout.split("closing time (touch)", 1)[1].splitlines()[0].split()
    assert touch_row[0] == "ms" and all(float(v) > 0 for v in touch_row[1:4])  # a closing time on each pole
    shown = PAGE.split("<!-- doctest: walk-through -->\n```\n", 1)[1].split("```", 1)[0].splitlines()
    assert missing_lines(shown, run.stdout.splitlines()) == []

"""One line, no traceback, for two things a user meets before any model runs: a node whose Exudyn
cannot be imported (a headless image without libGL) is told what it lacks and what to do (exit 1), and a
record given where a rig is expected is named as a record (exit 2)."""
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

# Exudyn's wheel fails to import without libGL.so.1; a meta-path finder reproduces that failure
BLOCK_EXUDYN = textwrap.dedent("""
    import sys
    class NoLibGL:
        def find_spec(self, name, path=None, target=None):
            if name == "exudyn" or name.startswith("exudyn."):
                raise ImportError("libGL.so.1: cannot open shared object file: No such file or directory")
    sys.meta_path.insert(0, NoLibGL())
    from vcbmodel.app.cli import main
    sys.exit(main(sys.argv[1:]))
""")


def test_a_node_without_libgl_is_told_in_one_line(tmp_path):
    rig = ROOT / "results" / "synthetic" / "cam_drop_m0_0.336kg.rig.json"
    out = tmp_path / "drop.csv"
    run = subprocess.run([sys.executable, "-c", BLOCK_EXUDYN, "simulate", str(rig), "--backend", "exudyn",
                          "-o", str(out)], capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert run.returncode == 1, run.stderr
    assert "Traceback" not in run.stderr and "ImportError" not in run.stderr, run.stderr
    errors = [line for line in run.stderr.splitlines() if line.startswith("vcbmodel:")]
    assert len(errors) == 1, run.stderr  # the progress line before it is not an error
    assert "libGL" in errors[0] and "apt install libgl1" in errors[0]
    assert not out.exists()


def test_a_record_given_where_a_rig_is_expected_is_named_as_such(tmp_path):
    """`vcbmodel check NAME.csv` (a record, whose first line is a '#' comment) is told it gave a record,
    not a rig, in one line with exit status 2, rather than that its JSON has comments."""
    record = ROOT / "results" / "synthetic" / "pendulum_10deg.csv"
    run = subprocess.run([sys.executable, "-m", "vcbmodel", "check", str(record)], capture_output=True, text=True,
                         timeout=120, cwd=tmp_path)
    assert run.returncode == 2 and "Traceback" not in run.stderr
    errors = [line for line in run.stderr.splitlines() if line.strip()]
    assert len(errors) == 1 and "this is a record, not a rig" in errors[0] and "no comments" not in errors[0], run.stderr

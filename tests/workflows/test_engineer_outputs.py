"""What a breaker engineer takes from a run into a test report (a second new user's trial): the
making current's channels in simulate's CSV, as rig-format.md's `breaker.making_current` says."""
import numpy as np

from vcbmodel.app.cli import main
from vcbmodel.experiments.loading import load_pair

from conftest import ROOT

CYCLE = ROOT / "results" / "synthetic" / "vcb_cycle.rig.json"


def test_a_closing_onto_a_fault_writes_each_poles_making_current_and_repulsion(tmp_path, capsys):
    out = tmp_path / "making.csv"
    assert main(["simulate", str(CYCLE), "--backend", "fast", "-o", str(out), "-q"]) == 0
    capsys.readouterr()
    units_line = out.read_text().splitlines()[1]
    for pole in (1, 2, 3):
        assert f"pole_{pole}_making_current in A" in units_line and f"pole_{pole}_repulsion_force in N" in units_line
    (tmp_path / "making.rig.json").write_text(CYCLE.read_text())  # read back as a record of its rig
    _, record = load_pair(out)
    t, contact = record.t, record.channel("pole_1_contact")
    current = record.channel("pole_1_making_current")
    touch = t[np.argmax(contact > 0)]
    assert np.all(current[t < touch] == 0.0) and np.max(np.abs(current)) > 5e4  # the fault flows from the touch
    assert np.max(record.channel("pole_1_repulsion_force")) > 100.0  # Holm's force pushes the contacts apart

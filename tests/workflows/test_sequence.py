"""``vcbmodel simulate --sequence`` (docs/cli.md): an operating sequence's figures per operation, as
text or one JSON object; what it refuses."""
import json
from pathlib import Path

import pytest

from vcbmodel.app.cli import main
from vcbmodel.compiled import compiler_works
from vcbmodel.experiments.sequence import parse_sequence

CYCLE = Path(__file__).resolve().parents[2] / "results" / "synthetic" / "vcb_cycle.rig.json"


def test_sequences_parse_as_iec_writes_them():
    steps = parse_sequence("O-0.3s-CO-3min-CO")
    assert [(s.op, s.at) for s in steps] == [("O", 0.0), ("CO", 0.3), ("CO", 180.3)]
    assert [s.at for s in parse_sequence("C-300ms-O")] == [0.0, 0.3]


@pytest.mark.skipif(not compiler_works(), reason="no working C compiler")
def test_o_03s_co_json_reports_every_operations_figures(capsys):
    assert main(["simulate", str(CYCLE), "--sequence", "O-0.3s-CO", "--json", "--backend", "compiled", "-q"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["sequence"] == "O-0.3s-CO" and report["rig"] == str(CYCLE)
    o, co = report["operations"]
    assert (o["op"], co["op"], co["command_s"]) == ("O", "CO", 0.3)
    for key in ("opening_time_from_coil_s", "opening_time_from_pawl_s", "opening_speed_m_s", "opening_rebound_m"):
        assert o[key] is not None and co[key] is not None, key
    for key in ("closing_time_from_coil_s", "bounce_duration_s", "kinetic_margin_J", "close_open_time_s"):
        assert co[key] is not None, key
    assert "closing_time_from_coil_s" not in o  # an O does not close
    assert co["closing_time_from_coil_s"] > co["closing_time_from_latch_s"] > 0.0
    assert o["opening_time_from_coil_s"] > o["opening_time_from_pawl_s"] > 0.0
    assert any("recharge" in n for n in report["notes"])


@pytest.mark.skipif(not compiler_works(), reason="no working C compiler")
def test_text_output_names_each_operation(capsys):
    assert main(["simulate", str(CYCLE), "--sequence", "O", "--backend", "compiled", "-q"]) == 0
    out = capsys.readouterr().out
    assert out.startswith("sequence O\nO at 0 s\n") and "opening time from the coil" in out and " ms" in out


@pytest.mark.parametrize("option", [["-o", "x.csv"], ["--t-end", "0.1"], ["--effects", ""], ["--plot", "x.png"]])
def test_options_of_one_run_are_refused(option, capsys, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["simulate", str(CYCLE), "--sequence", "O"] + option) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--sequence" in err[0]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.skipif(not compiler_works(), reason="no working C compiler")
def test_without_releases_the_times_from_the_coil_are_null_and_said_so(tmp_path, capsys):
    data = json.loads(CYCLE.read_text())
    for key in ("closing_release", "opening_release"):
        data["breaker"].pop(key)
    rig = tmp_path / "norelease.rig.json"
    rig.write_text(json.dumps(data))
    assert main(["simulate", str(rig), "--sequence", "CO", "--json", "--backend", "compiled", "-q"]) == 0
    report = json.loads(capsys.readouterr().out)
    (co,) = report["operations"]
    assert co["closing_time_from_coil_s"] is None and co["opening_time_from_coil_s"] is None
    assert co["closing_time_from_latch_s"] > 0 and co["opening_time_from_pawl_s"] > 0
    assert sum("breaker.closing_release" in n or "breaker.opening_release" in n for n in report["notes"]) == 2


@pytest.mark.skipif(not compiler_works(), reason="no working C compiler")
def test_an_operation_still_moving_at_the_next_command_fails(capsys):
    """The O rests 16 ms after its trip (33 ms after its command): a CO 10 ms after it cannot start
    from rest, and a wrong chain is worse than an error (exit 1, one line)."""
    assert main(["simulate", str(CYCLE), "--sequence", "O-10ms-CO", "--backend", "compiled", "-q"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "comes to rest" in err[0] and "CO commanded at 0.01 s" in err[0]

"""The breaker's cycle sections (rig sections breaker.making_current, trip_latch, opening_dashpot,
closing_release, opening_release, opening_speed_zone; docs/rig-format.md): every field required,
each bad value refused with one line naming the field, exit status 2, nothing written; and a
sequence the rig cannot run refused the same way."""
import copy
import json
from pathlib import Path

import pytest

from vcbmodel import parameters as P
from vcbmodel.app.cli import main
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.sequence import parse_sequence

CASES = [  # (section, field, value: None removes it), the field the message must name
    ("making_current", "spots", None, "breaker.making_current.spots"),
    ("making_current", "peak", 100.0, "breaker.making_current.peak"),  # kA read as A
    ("making_current", "asymmetry", 1.5, "breaker.making_current.asymmetry"),
    ("making_current", "spot_radius", 0.03, "breaker.making_current.spot_radius"),
    ("making_current", "time_constant", 45.0, "breaker.making_current.time_constant"),
    ("making_current", "frequency", 5000.0, "breaker.making_current.frequency"),
    ("trip_latch", "travel", 0.02, "breaker.trip_latch.travel"),  # beyond what the cam lifts F
    ("trip_latch", "reset_travel", 0.015, "breaker.trip_latch.reset_travel"),
    ("trip_latch", "release_time", 2.0, "breaker.trip_latch.release_time"),
    ("trip_latch", "stiffness", -1.0, "breaker.trip_latch.stiffness"),
    ("trip_latch", "damping", None, "breaker.trip_latch.damping"),
    ("opening_dashpot", "stroke", 0.015, "breaker.opening_dashpot.stroke"),
    ("opening_dashpot", "ramp", 0.01, "breaker.opening_dashpot.ramp"),
    ("opening_dashpot", "stop_stiffness", 0.0, "breaker.opening_dashpot.stop_stiffness"),
    ("closing_release", "voltage_range", [0.9, 0.95], "breaker.closing_release.voltage_range"),
    ("closing_release", "load", 400.0, "breaker.closing_release.force_constant"),  # never picks up
    ("closing_release", "stroke", 4.0, "breaker.closing_release.stroke"),
    ("opening_release", "inductance", None, "breaker.opening_release.inductance"),
    ("opening_release", "coil", 1.0, "breaker.opening_release.coil"),  # unknown field
]


def cycle_rig(tmp_path, section=None, key=None, value=None, drop=False):
    d = copy.deepcopy(P.REFERENCE_CYCLE_BREAKER)
    if section is not None:
        if drop:
            d["breaker"][section].pop(key)
        else:
            d["breaker"][section][key] = value
    path = tmp_path / "cycle.rig.json"
    path.write_text(json.dumps(d))
    return path


@pytest.mark.parametrize("section,key,value,field", CASES, ids=[f"{c[0]}.{c[1]}" for c in CASES])
def test_bad_cycle_field_is_refused_naming_it(section, key, value, field, tmp_path, capsys):
    path = cycle_rig(tmp_path, section, key, value, drop=value is None)
    out = tmp_path / "out.csv"
    assert main(["simulate", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and field in err[0] and "cycle.rig.json" in err[0], err
    assert not out.exists()


def test_dashpot_needs_the_trip_latch(tmp_path, capsys):
    d = copy.deepcopy(P.REFERENCE_CYCLE_BREAKER)
    d["breaker"].pop("trip_latch")
    path = tmp_path / "nolatch.rig.json"
    path.write_text(json.dumps(d))
    assert main(["check", str(path)]) == 2
    assert "breaker.opening_dashpot" in capsys.readouterr().err


def test_the_reference_cycle_reads_back_as_stated(tmp_path):
    b = load_rig(cycle_rig(tmp_path)).breaker
    assert b.trip_latch.travel == P.REFERENCE_TRIP_LATCH["travel"]
    assert b.opening_dashpot.damping == P.REFERENCE_OPENING_DASHPOT["damping"]
    assert b.closing_release.voltage_range == (0.85, 1.1) and b.opening_release.voltage_range == (0.7, 1.1)
    assert b.making_current.peak == 1e5 and b.opening_speed_zone == (0.0, 0.004)


@pytest.mark.parametrize("text,message", [("O-0.3-CO", "interval"), ("O-0.3s", "ends with an interval"),
                                          ("OC", "not an operation"), ("O--CO", "interval"), ("", "not an operation")])
def test_bad_sequence_text(text, message):
    from vcbmodel.errors import InputError
    with pytest.raises(InputError, match=message):
        parse_sequence(text)


@pytest.mark.parametrize("sequence,field", [("C-1s-O", "sequence"), ("CO-1s-CO", "sequence"), ("C-1s-C", "sequence"),
                                            ("O-0.3s-O", "sequence")])
def test_a_sequence_the_breaker_cannot_run_is_refused(sequence, field, tmp_path, capsys):
    """C-1s-O runs (a closing, then an opening of the closed breaker); the others are refused: a
    closing 1 s after a closing (the springs are not recharged), an O of an open breaker."""
    path = cycle_rig(tmp_path)
    status = main(["simulate", str(path), "--sequence", sequence, "--backend", "compiled", "-q"])
    err = capsys.readouterr().err
    if sequence == "C-1s-O":
        assert status == 0, err
        return
    assert status == 2 and "--sequence" in err and len(err.strip().splitlines()) == 1, err


def test_a_sequence_needs_the_opening_parts(capsys):
    rig = Path(__file__).resolve().parents[2] / "results" / "synthetic" / "vcb_closing.rig.json"
    assert main(["simulate", str(rig), "--sequence", "O", "-q"]) == 2
    assert "breaker.trip_latch" in capsys.readouterr().err

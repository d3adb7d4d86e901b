"""``vcbmodel simulate --sequence`` (docs/cli.md): an operating sequence's figures per operation, as
text or one JSON object; what it refuses."""
import json
from pathlib import Path

import matplotlib
import pytest

from vcbmodel.app.cli import main
from vcbmodel.app.sequence_plot import operation_text
from vcbmodel.compiled import compiler_works
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.sequence import (SEQUENCE_LIMITED, operation_summary, parse_sequence, run_sequence,
                                           sequence_failures, sequence_lines)

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


@pytest.mark.parametrize("option", [["-o", "x.csv"], ["--t-end", "0.1"], ["--effects", ""]])
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
    # the pawl lets go at the touch itself: the poles bounce 2.72 ms, over the rig's 2 ms limit (status 1)
    assert main(["simulate", str(rig), "--sequence", "CO", "--json", "--backend", "compiled", "-q"]) == 1
    report = json.loads(capsys.readouterr().out)
    (co,) = report["operations"]
    assert report["fails"] and [c["limit"] for c in co["limits"] if c["pass"] is False] == ["bounce_duration"]
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


def _markers(ax, marker):
    """{colour: (x, y)} of the single-point markers of one kind drawn in ``ax``."""
    return {line.get_color(): (float(line.get_xdata()[0]), float(line.get_ydata()[0])) for line in ax.lines
            if line.get_marker() == marker and len(line.get_xdata()) == 1}


@pytest.mark.skipif(not compiler_works(), reason="no working C compiler")
def test_the_sequence_figure_shows_each_operation_as_an_analyser_does():
    """O - 0.3 s - CO: a row per operation; the O's travel with its opening zone shaded after the
    parting and each pole's parting marked where the report has it, each pole's opening speed over
    the zone as a bar at its value; the CO's closing panels (touches at the poles' touch times) and
    its trip marked; the headline figures are the report's."""
    from vcbmodel.app.closing_plot import pole_colour
    from vcbmodel.app.sequence_plot import sequence_figure
    from vcbmodel.experiments.closing_evaluation import figures_of_merit
    from vcbmodel.experiments.sequence import commands_for, with_commands

    rig = load_rig(str(CYCLE))
    results = []
    report = run_sequence(rig, "O-0.3s-CO", backend="compiled", results=results)
    fig = sequence_figure(report, results, rig, "test")
    assert len(fig.axes) == 8
    o_travel, o_speed, o_timing, o_end, co_travel, _, co_timing, co_bounce = fig.axes
    foms = [figures_of_merit(r, with_commands(rig, commands_for(rig, op))) for r, op in zip(results, ("O", "CO"))]
    opening = foms[0]["opening"]
    # the opening zone: 0-4 mm of travel after the parting, below the gap
    zone = next(p for p in o_travel.patches if p.get_label().startswith("opening zone"))
    gap = 1e3 * rig.breaker.poles.contact_gap
    assert zone.get_label() == "opening zone, 0-4 mm after parting"
    assert (zone.get_y(), zone.get_y() + zone.get_height()) == pytest.approx((gap - 4.0, gap))
    partings = _markers(o_travel, "X")
    for i, (part, pole_gap) in enumerate(zip(opening["parting_s"], rig.breaker.poles.gap_offsets), start=1):
        assert partings[pole_colour(i)] == pytest.approx((1e3 * (opening["trip_s"] + part), gap + 1e3 * pole_gap))
    bars = [c for c in o_speed.collections if c.get_segments()]
    speeds = sorted(float(seg[0][1]) for c in bars for seg in c.get_segments())
    assert speeds == pytest.approx(sorted(opening["opening_speeds_m_s"]))
    assert "overtravel 0.021 mm" in o_end.get_title(loc="left")
    # the CO: touches where the closing's figures put them, its trip as a dashed line in the timing panel
    touches = _markers(co_travel, "o")
    assert sorted(x for x, _ in touches.values()) == pytest.approx(sorted(1e3 * t for t in foms[1]["per_pole"]["touch_s"]))
    trip = 1e3 * foms[1]["opening"]["trip_s"]
    assert any(line.get_linestyle() == "--" and float(line.get_xdata()[0]) == pytest.approx(trip) for line in co_timing.lines)
    assert "bounces" in co_bounce.get_title(loc="left")
    heads = [t.get_text() for ax in (o_travel, co_travel) for t in ax.texts]
    assert heads[0].startswith("O at 0 s") and "3.07 ms from the pawl" in heads[0]
    assert heads[1].startswith("CO at 0.3 s") and "kinetic margin 78.3 J" in heads[1]
    matplotlib.pyplot.close(fig)


@pytest.mark.skipif(not compiler_works(), reason="no working C compiler")
def test_sequence_plot_is_written_and_never_replaces_a_file_without_force(tmp_path, capsys):
    out = tmp_path / "seq.png"
    assert main(["simulate", str(CYCLE), "--sequence", "O", "--backend", "compiled", "--plot", str(out), "-q"]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    capsys.readouterr()
    out.write_bytes(b"mine")
    assert main(["simulate", str(CYCLE), "--sequence", "O", "--backend", "compiled", "--plot", str(out), "-q"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--force" in err[0] and out.read_bytes() == b"mine"
    assert main(["simulate", str(CYCLE), "--sequence", "O", "--plot", str(CYCLE), "--force", "-q"]) == 2
    assert "input" in capsys.readouterr().err


def test_a_closing_not_every_pole_touched_has_no_bounce_to_judge():
    """A closing whose run ends before every pole touches has no closing time, and no bounce figure
    either (it read the touched poles' bounce, or 0 ms for none, and passed a bounce limit)."""
    cut = {"closing_time_s": None, "bounce_duration_s": 0.0, "bounce_count": 0}
    whole = {"closing_time_s": 0.05, "bounce_duration_s": 1.2e-3, "bounce_count": 2}
    for limit, key in (("bounce_duration", "bounce_duration_s"), ("bounce_count", "bounce_count")):
        values = SEQUENCE_LIMITED[limit][1]
        assert values(cut) == [None] and values(whole) == [whole[key]]


def test_a_closing_whose_latching_is_not_judged_is_never_passed_with_the_limits():
    """A CO whose cam has neither latched nor stopped short (``latched`` None) passes its limits, but the
    verdict line says its latching is not judged (it read 'all pass'), and its margin reads 'not judged',
    not 'not latched'."""
    co = {"op": "CO", "command_s": 0.0, "release_delay_s": None, "backend": "compiled", "closing_time_from_coil_s": None,
          "closing_time_from_coil_range_s": None, "closing_time_from_latch_s": 0.067, "bounce_count": 1,
          "bounce_duration_s": 8e-4, "kinetic_at_touch_J": 89.9, "kinetic_margin_J": None, "latched": None,
          "limits": [{"limit": "closing_time", "text": "<= 80 ms", "values_si": [0.067], "pass": True}]}
    report = {"sequence": "CO", "operations": [co], "notes": []}
    lines = sequence_lines(report)
    assert lines[-1] == "limits (breaker.limits), the operations: all pass; latching not judged: CO at 0 s"
    assert any(line.endswith("kinetic margin not judged") for line in lines)
    assert sequence_lines({**report, "operations": [{**co, "latched": False}]})[-1].endswith("all pass")
    assert sequence_failures({**report, "operations": [{**co, "latched": False}]})


@pytest.mark.skipif(not compiler_works(), reason="no working C compiler")
def test_a_weak_cos_closing_fails_on_the_closing_it_would_have_made(tmp_path, capsys):
    """Closing springs at 9500 N/m (the rig's 24230) and no closing-speed limit: the CO's trip comes
    16.8 ms after the touch with the cam at 203 deg, still on its way to its 248 deg holding latch; the
    run ended with the freed cam creeping at 1.6 rad/s 37.4 deg short, and the CO passed with exit 0. The
    same closing without the trip stops 42.7 deg short and turns back: the closing fails (exit 1)."""
    data = json.loads(CYCLE.read_text())
    data["closing_spring"]["stiffness"] = 9500.0
    data["breaker"]["limits"].pop("closing_speed")
    rig = tmp_path / "weak.rig.json"
    rig.write_text(json.dumps(data))
    assert main(["simulate", str(rig), "--sequence", "CO", "--json", "--backend", "compiled", "-q"]) == 1
    report = json.loads(capsys.readouterr().out)
    (co,) = report["operations"]
    assert report["fails"] and co["latched"] is False and co["latching_run_s"] == 0.1 and co["kinetic_margin_J"] is None
    assert all(c["pass"] for c in co["limits"])  # the limits pass: the latch fails it
    assert any("its trip comes before the cam reaches its holding latch" in n for n in report["notes"])
    assert any("42.7 deg short): the closing fails" in n for n in report["notes"])


@pytest.mark.skipif(not compiler_works(), reason="no working C compiler")
def test_a_weak_c_whose_run_ends_first_is_judged_on_a_longer_run(tmp_path):
    """Closing springs at 9500 N/m: the touch comes 65.7 ms after the latch, and the C's 75 ms run ends
    with the cam still turning 60 deg short of its latch (not judged); the same closing run for 0.1 s
    stops 42.7 deg short, as the CO's closing does: the C fails too."""
    data = json.loads(CYCLE.read_text())
    data["closing_spring"]["stiffness"] = 9500.0
    path = tmp_path / "weak.rig.json"
    path.write_text(json.dumps(data))
    report = run_sequence(load_rig(path), "C", backend="compiled")
    (c,) = report["operations"]
    assert c["latched"] is False and c["latching_run_s"] == 0.1
    assert any("42.7 deg short): the closing fails" in n for n in report["notes"])
    assert sequence_failures(report)[-1] == "C at 0 s: the closing fails (the cam stops short of its latch)"


@pytest.mark.parametrize("sequence", ["foo", "O-0.3-CO", "O-0.3s-", "C-10s-C"])
def test_a_bad_sequence_is_one_line_before_any_progress(sequence, capsys, tmp_path, monkeypatch):
    """A sequence the rig cannot run is refused before the progress line ``simulate NAME: sequence ...``:
    bad input is exactly one line on stderr (docs/cli.md, exit status 2)."""
    monkeypatch.chdir(tmp_path)
    assert main(["simulate", str(CYCLE), "--sequence", sequence, "--plot", "seq.png"]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("vcbmodel: bad input: --sequence"), err
    assert captured.out == "" and list(tmp_path.iterdir()) == []


def _slow_closing(latched=None, touches=(None, None, None)):
    """The figures of a C whose 75 ms run (RUN_LENGTH) ends before its slow breaker's poles touch (the
    template with 60 active coils touches at 95 ms), or after the touch but before the latch."""
    touched = all(x is not None for x in touches)
    return {"op": "C", "command_s": 0.0, "release_delay_s": None, "backend": "compiled", "run_s": 0.075,
            "figures": {"closing_time_s": 0.0487 if touched else None, "first_touch_s": touches[0],
                        "closing_speed_m_s": 0.99 if touched else None, "bounce_count": 0, "bounce_duration_s": 0.0,
                        "kinetic_at_touch_J": 150.0 if touched else None, "kinetic_margin_J": None,
                        "latched": latched, "latch_short_deg": None, "contacts_reopen_s": None,
                        "per_pole": {"touch_s": list(touches)}}}


def test_a_closing_the_run_ends_before_shows_no_bounce_and_no_verdict_of_pass():
    """A sequence's C runs 75 ms, which the user cannot lengthen (--t-end is refused with --sequence): on a
    slow breaker no pole touched, yet it read 'bounce 0 (0.00 ms)' above its limits' 'no value', and the
    verdict 'the operations: all pass' (exit 0) with no limit judged."""
    summary = operation_summary(_slow_closing())
    assert summary["bounce_count"] is None and summary["bounce_duration_s"] is None
    limits = [{"limit": "bounce_duration", "text": "<= 2 ms", "values_si": [None], "pass": None},
              {"limit": "closing_time", "text": "<= 80 ms", "values_si": [None], "pass": None}]
    report = {"sequence": "C", "notes": [], "operations": [dict(summary, limits=limits)]}
    text = "\n".join(sequence_lines(report))
    assert "bounce 0" not in text and "0.00 ms" not in text
    verdict = text.splitlines()[-1]
    assert "all pass" not in verdict and "none judged" in verdict and "C at 0 s: bounce duration, closing time" in verdict
    report["operations"][0]["limits"][1] = {"limit": "closing_time", "text": "<= 80 ms", "values_si": [0.07], "pass": True}
    verdict = sequence_lines(report)[-1]
    assert verdict.endswith("all judged pass; no value in its run for C at 0 s: bounce duration; latching not judged: "
                            "C at 0 s"), verdict


def test_a_closing_the_run_ends_before_its_latch_is_not_said_to_fail_latching():
    """Touched but not yet latched when the run ends (latched None, not judged): it read 'kinetic margin
    not latched', as a closing whose cam stops short of its latch (latched False, which fails)."""
    on_its_way = "\n".join(sequence_lines({"sequence": "C", "notes": [], "operations": [
        operation_summary(_slow_closing(None, (0.048, 0.0487, 0.0483)))]}))
    assert "not latched" not in on_its_way and "kinetic margin not judged" in on_its_way
    short = "\n".join(sequence_lines({"sequence": "C", "notes": [], "operations": [
        operation_summary(_slow_closing(False, (0.048, 0.0487, 0.0483)))]}))
    assert "kinetic margin: not latched" in short

    title = operation_text(operation_summary(_slow_closing(None, (0.048, 0.0487, 0.0483))))
    assert "not latched" not in title and "kinetic margin not judged" in title

"""simulate's report, as a breaker analyser prints one: per pole in ms, mm, m/s and kN to 3-4 significant
figures, each figure against the rig's limits (breaker.limits) with pass or FAIL; the same in JSON; a
figure the evaluation adds gets its row; other experiments in degrees and milliseconds."""
import copy
import json
import re

import pytest

from vcbmodel import parameters as P
from vcbmodel.app.cli import main
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.report import report_json, report_text
from vcbmodel.experiments.simulation import simulate
from vcbmodel.experiments import summaries
from vcbmodel.rig.units import format_value

from conftest import write_rig


def breaker(limits=None, name="b"):
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    if limits is None:
        data["breaker"].pop("limits")
    else:
        data["breaker"]["limits"] = limits
    return data, name


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    """The reference breaker simulated once (fast backend), its rig, result and figures of merit."""
    folder = tmp_path_factory.mktemp("report")
    rig = load_rig(write_rig(folder, P.REFERENCE_BREAKER, "ref"))
    result = simulate(rig, backend="fast")
    return rig, result, summaries.result_figures(result, rig)


def table(text):
    """{row label: [cells]} of the per-pole table (label, unit, a value per pole, limit, result)."""
    lines = text.splitlines()
    cut = lines[1].index("unit")  # the labels' column ends where the header's "unit" begins
    rows = {}
    for line in lines[2:]:
        if line.strip() == "whole breaker":
            break
        rows[line[:cut].strip()] = line[cut:].split()
    return rows


def test_the_per_pole_table_is_in_engineering_units_against_the_limits(run):
    rig, result, fom = run
    text = report_text(summaries.closing_report(result, rig))
    assert re.search(r"per pole\s+unit\s+pole 1\s+pole 2\s+pole 3\s+limit\s+result", text)
    rows = table(text)
    touch = rows["closing time (touch)"]
    assert touch[0] == "ms" and touch[4:] == ["<=", "80", "ms", "pass"]
    for cell, t in zip(touch[1:4], fom["per_pole"]["touch_s"]):
        assert float(cell) == pytest.approx(1e3 * t, abs=0.006) and len(cell.replace(".", "")) == 4  # 4 figures
    speed = rows["closing speed, 4-0 mm before touch"]
    assert speed[0] == "m/s" and [float(v) for v in speed[1:4]] == pytest.approx(fom["per_pole"]["closing_speed_m_s"], abs=6e-4)
    assert rows["contact force closed"][0] == "kN" and rows["wipe (travel after touch)"][0] == "mm"
    assert rows["bounces"][:3] == [str(n) for n in fom["per_pole"]["bounces"]]
    # no base SI with six digits, no exponents, no mean of the poles' touch speeds
    assert not re.search(r"\de[-+]\d", text) and "mean" not in text
    assert "limits (breaker.limits): 5 of 5 judged: all pass" in text


def test_a_limit_on_a_per_pole_figure_judges_the_poles_not_the_mechanism(run, tmp_path):
    """A wipe limit judges each pole's wipe; the mechanism's wipe after the first touch (4.37 mm, a
    different travel) is shown without it, and so is the last pole's closing time under a per-pole
    closing-time limit."""
    rig, result, fom = run
    limits = {"wipe": {"min": 3.5, "max": 5.0, "unit": "mm"}, "closing_time": {"max": 80, "unit": "ms"}}
    report = summaries.closing_report(result, load_rig(write_rig(tmp_path, breaker(limits)[0], "wipe")))
    text = report_text(report)
    assert table(text)["wipe (travel after touch)"][-3:] == ["FAIL", "pole", "2"]  # 3.462 mm
    mechanism = next(line for line in text.splitlines() if "mechanism wipe" in line)
    last = next(line for line in text.splitlines() if "closing time (last pole)" in line)
    assert mechanism.split()[-1] == "4.366" and last.split()[-1] == "39.08"  # no limit, no result
    assert "2 of 2 judged" in text
    body = report_json(report)
    assert all("limit" not in row for row in body["summary"] if row.get("figure") in ("wipe_m", "closing_time_s"))


def test_a_tighter_limit_fails_on_the_poles_that_break_it(run, tmp_path):
    rig, result, fom = run
    bounces = fom["per_pole"]["bounce_duration_s"]
    cut = sorted(bounces)[1]  # between the poles: at least one passes, at least one fails
    limits = {"bounce_duration": {"max": 1e3 * cut, "unit": "ms"}, "pole_spread": {"max": 100, "unit": "us"}}
    tight = load_rig(write_rig(tmp_path, breaker(limits)[0], "tight"))
    report = summaries.closing_report(result, tight)
    text = report_text(report)
    failing = [i for i, b in enumerate(bounces, start=1) if b > cut]
    row = table(text)["bounce duration"]
    assert row[-3:] == ["FAIL", "pole", ", ".join(map(str, failing))] and failing
    assert "FAIL: bounce duration on pole" in text and "pole spread (" in text  # 0.538 ms > 100 us
    body = report_json(report)
    assert [p["bounce_duration"]["pass"] for p in body["poles"]] == [b <= cut for b in bounces]
    assert {lim["figure"]: lim["result"].split()[0] for lim in body["limits"]} == {"bounce_duration": "FAIL",
                                                                                  "pole_spread": "FAIL"}
    assert next(lim for lim in body["limits"] if lim["figure"] == "pole_spread")["max_si"] == pytest.approx(1e-4)


def test_without_limits_the_report_says_so_and_judges_nothing(run, tmp_path):
    _, result, _ = run
    plain = load_rig(write_rig(tmp_path, breaker(None)[0], "plain"))
    text = report_text(summaries.closing_report(result, plain))
    assert table(text)["closing time (touch)"][-3:] == ["no", "limit", "given"]
    assert "pass" not in text and "FAIL" not in text
    assert "limits: none given (breaker.limits): no figure is judged" in text


def test_a_figure_the_evaluation_adds_gets_its_row(run, monkeypatch):
    """h4's figures slot in: a per-pole entry and a whole-breaker figure named with their unit."""
    rig, result, fom = run
    more = dict(fom, kinetic_margin_J=12.34, per_pole=dict(fom["per_pole"], making_current_A=[31e3, 32e3, 33e3]))
    monkeypatch.setattr(summaries, "result_figures", lambda r, g: more)
    report = summaries.closing_report(result, rig)
    text = report_text(report)
    assert re.search(r"making current\s+kA\s+31.00\s+32.00\s+33.00", text)
    assert re.search(r"kinetic margin \(cam's least, touch to latch\)\s+J\s+12.3\b", text)
    assert report_json(report)["poles"][2]["making_current"] == {"what": "making current", "value": 33.0, "unit": "kA",
                                                                 "figure": "making_current_A"}


def test_a_plain_closing_shows_no_close_open_row_a_run_that_trips_does(run, monkeypatch):
    """The close-open time belongs to a run that trips (a CO: first touch to the last pole's parting); a
    plain closing has none to show, in the text or the JSON. A run with opening figures gets the row."""
    rig, result, fom = run
    assert fom["opening"] is None and fom["close_open_time_s"] is None
    report = summaries.closing_report(result, rig)
    assert "close open" not in report_text(report).lower()
    assert all(row.get("figure") != "close_open_time_s" for row in report_json(report)["summary"])
    tripped = dict(fom, opening={"opening_time_s": 0.01850}, close_open_time_s=0.02023)
    monkeypatch.setattr(summaries, "result_figures", lambda r, g: tripped)
    text = report_text(summaries.closing_report(result, rig))
    assert re.search(r"close open time\s+ms\s+20.23\b", text)


def test_simulate_json_gives_each_pole_with_its_limit(tmp_path, capsys):
    rig = write_rig(tmp_path, P.REFERENCE_BREAKER, "ref")
    assert main(["simulate", str(rig), "--backend", "fast", "-o", str(tmp_path / "c.csv"), "--json", "-q"]) == 0
    body = json.loads(capsys.readouterr().out)
    fom = body["figures_of_merit"]
    assert [p["pole"] for p in body["poles"]] == [1, 2, 3]
    for pole, touch in zip(body["poles"], fom["per_pole"]["touch_s"]):
        assert pole["closing_time"]["unit"] == "ms" and pole["closing_time"]["value"] == pytest.approx(1e3 * touch)
        assert pole["closing_time"]["limit"] == "<= 80 ms" and pole["closing_time"]["pass"] is True
    assert body["verdict"].endswith("all pass") and len(body["limits"]) == 5
    assert all(lim["source"] for lim in body["limits"])
    assert "touch_speed" not in {s.get("figure", "")[:11] for s in body["summary"]}  # no mean of the poles


@pytest.mark.parametrize("limits, field, words", [
    ({"pole_spread": {"max": 2}}, "breaker.limits.pole_spread.unit", "missing"),
    ({"pole_spread": {"max": 2, "unit": "mm"}}, "breaker.limits.pole_spread.unit", "not a unit of pole_spread"),
    ({"pole_sprad": {"max": 2, "unit": "ms"}}, "breaker.limits.pole_sprad", "pole_spread"),
    ({"closing_speed": {"min": 1.5, "max": 1.0, "unit": "m/s"}}, "breaker.limits.closing_speed.max", "below min"),
    ({"closing_speed": {"unit": "m/s"}}, "breaker.limits.closing_speed.min", "min, max or both"),
])
def test_bad_limits_are_refused_in_one_line(tmp_path, capsys, limits, field, words):
    rig = write_rig(tmp_path, breaker(limits)[0], "bad")
    assert main(["check", str(rig)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and field in err and words in err and "Traceback" not in err


@pytest.mark.parametrize("value, step, text", [(38.84214, 1e-3, "38.84"), (0.537937, 1e-3, "0.538"),
                                               (25646.4e-3, 1e-3, "25.65"), (8.1e-6, 1e-3, "0.000"),
                                               (-1e-7, 1e-3, "0.000"), (252.119, 0.01, "252.1"), (1234.6, 0.0, "1235"),
                                               (-3.0381e-6, 0.0, "-3.038e-06"), (2.5e7, 0.0, "2.500e+07"),
                                               (None, 1e-3, "-"), (float("nan"), 1e-3, "-"), (2, 1.0, "2")])
def test_values_are_printed_to_four_figures_and_no_finer_than_their_unit(value, step, text):
    assert format_value(value, step) == text


def test_a_cam_drop_reports_in_milliseconds_and_degrees(tmp_path, capsys):
    rig = write_rig(tmp_path, P.REFERENCE_CAM, "cam")
    assert main(["simulate", str(rig), "--t-end", "0.02", "-o", str(tmp_path / "c.csv"), "-q"]) == 0
    lines = capsys.readouterr().out.splitlines()[1:]
    assert re.fullmatch(r"\s+end time\s+ms\s+20.00", lines[0]) and " deg " in lines[1] + " "
    assert not any(re.search(r"\d\.\d{5}|e-0", line) for line in lines)


def test_the_verdict_says_when_the_cam_does_not_latch_whatever_the_limits_say(tmp_path, capsys):
    """The template breaker with the lightest hooked springs that pass the strength checks (3.7 kg): at
    55 ms its cam has not reached its latch (the limits all pass, latching is not judged); at 100 ms it
    has stopped short and turned back: the closing fails, said in the verdict, not only in a note. The
    template's own plug-ended springs (1.9 kg) carry it to the latch: nothing is added."""
    template = tmp_path / "t.rig.json"
    assert main(["init", "vcb_closing", "-o", str(template)]) == 0
    hooked = json.loads(template.read_text())
    hooked["closing_spring"].update(wire_diameter=0.0114, coil_diameter=0.0684, active_coils=21.6, ends="hooks")
    heavy = tmp_path / "hooked.rig.json"
    heavy.write_text(json.dumps(hooked))
    capsys.readouterr()
    verdicts = {}
    for rig, t_end, status in ((heavy, "0.055", 0), (heavy, "0.1", 1), (template, "0.1", 0)):
        assert main(["simulate", str(rig), "--backend", "fast", "--t-end", t_end, "-o",
                     str(tmp_path / f"{rig.stem}{t_end}.csv"), "--json", "-q"]) == status  # 1: the closing fails
        out, err = capsys.readouterr()
        verdicts[rig.stem, t_end] = json.loads(out)["verdict"]
        if status:  # stopped short: no longer run shows the end stop (the note said 'a longer --t-end shows it')
            assert not any("before the cam meets its end stop" in n for n in json.loads(out)["notes"])
        # turned back short of its latch, the closing fails (its contacts reopen: pole 2's force fails too)
        assert err.strip() == ("vcbmodel: the breaker fails: contact force closed on pole 2; CLOSING FAILS (latch not "
                               "reached) (report and outputs written)" if status else "")
    assert "all pass; latching not judged: the run ends at 55 ms before the cam reaches its latch" in \
        verdicts["hooked.rig", "0.055"]
    assert "THE CLOSING FAILS: the cam stops 10.4 deg short of its latch" in verdicts["hooked.rig", "0.1"]
    assert verdicts["t.rig", "0.1"].endswith("all pass")  # it latched: nothing to add
    no_touch = summaries.latching_verdict({"latched": None, "kinetic_at_touch_J": None, "end_s": 0.02})
    assert no_touch is None  # no pole touched: the notes say the run is not a complete closing


def single_pole(limits):
    data, _ = breaker(limits)
    data["breaker"]["poles"].update(count=1, gap_offsets=[0.0])
    data["breaker"].pop("main_shaft")
    return data


def test_a_single_pole_has_no_pole_spread_to_print_or_limit(tmp_path, capsys):
    """One pole: the report said 'pole spread 0.000 ms' (and 'no limit given' beside it); it says the
    figure does not apply, in text and JSON, and a pole-spread limit is refused (check and simulate:
    status 2, naming the field), the other limits kept."""
    limits = {"pole_spread": {"max": 2, "unit": "ms"}, "closing_speed": {"min": 1.0, "max": 1.5, "unit": "m/s"}}
    refused = write_rig(tmp_path, single_pole(limits), "spread")
    for command in (["check", str(refused)], ["simulate", str(refused), "-o", str(tmp_path / "x.csv")]):
        assert main(command) == 2
        out, err = capsys.readouterr()
        assert out == "" and err.strip() == (f"vcbmodel: bad input: {refused}: breaker.limits.pole_spread: a single-pole "
                                             "breaker (breaker.poles.count 1) has no pole spread: delete this limit")
    assert not (tmp_path / "x.csv").exists()
    del limits["pole_spread"]
    rig = load_rig(write_rig(tmp_path, single_pole(limits), "one"))
    report = summaries.closing_report(simulate(rig, backend="fast"), rig)
    line = next(x for x in report_text(report).splitlines() if x.strip().startswith("pole spread"))
    assert line.split() == ["pole", "spread", "does", "not", "apply:", "one", "pole"]  # no number, no limit cell
    row = next(r for r in report_json(report)["summary"] if r.get("figure") == "pole_spread_s")
    assert row["value"] is None and row["does_not_apply"] == "one pole" and "limit" not in row
    assert "1 of 1 judged: all pass" in report.verdict()
    three = load_rig(write_rig(tmp_path, breaker(limits)[0], "three"))  # three poles: the figure as it was
    assert all(not r.absent for r in summaries.closing_report(simulate(three, backend="fast"), three).rows)


def test_a_run_too_short_to_touch_shows_no_closed_contact_force(tmp_path, capsys):
    """A 20 ms run (no pole has touched) printed a closed contact force of 0.000 kN per pole and failed
    the limit on it: 'the breaker fails' (status 1) for a run the notes call not a complete closing,
    while its closing time read 'no value'. A pole not yet touched has no closed force to judge, and no
    bounce (it read a bounce duration of 0 ms, passing its limit), and the verdict counts as judged only
    the limits the run gives a value (it read '3 of 3 judged: all pass' with no value for any)."""
    data, _ = breaker({"contact_force_closed": {"min": 3, "unit": "kN"}, "closing_time": {"max": 80, "unit": "ms"},
                       "bounce_duration": {"max": 2, "unit": "ms"}})
    rig = write_rig(tmp_path, data, "short")
    assert main(["simulate", str(rig), "--backend", "fast", "--t-end", "0.02", "-o", str(tmp_path / "s.csv"),
                 "--json", "-q"]) == 0
    out, err = capsys.readouterr()
    body = json.loads(out)
    force = [p["contact_force_closed"] for p in body["poles"]]
    assert all(f["value"] is None and f["pass"] is None for f in force) and len(force) == 3
    assert body["fails"] is False and err == ""
    assert any("not a complete closing" in n for n in body["notes"])
    assert all(p["bounce_duration"]["value"] is None and p["bounce_duration"]["pass"] is None for p in body["poles"])
    report = summaries.closing_report(simulate(load_rig(rig), backend="fast", t_end=0.02), load_rig(rig))
    assert report.verdict().startswith("limits (breaker.limits): 0 of 3 judged: no value in this run for ")
    assert "all pass" not in report.verdict()


def test_a_cam_at_rest_before_any_pole_touches_fails_the_closing(tmp_path):
    """A closing cut at 25 ms (no pole touched yet) is not judged; the same run with its cam standing
    still over its last CAM_REST_TIME and more, no pole touched, will never close: the closing fails
    (it read 'not a complete closing (a longer --t-end)', status 0, every limit 'no value')."""
    from dataclasses import replace

    import numpy as np
    rig = load_rig(write_rig(tmp_path, breaker({"closing_time": {"max": 80, "unit": "ms"}})[0], "rest"))
    r = simulate(rig, backend="fast", t_end=0.025)
    cut = summaries.closing_report(r, rig)
    assert cut.failures() == [] and any("not a complete closing" in n for n in cut.notes)
    theta = r.channels["cam_angle"].copy()
    still = r.t >= r.t[-1] - P.CAM_REST_TIME - 1e-3
    theta[still] = theta[np.argmax(still) - 1]
    held = replace(r, channels={**r.channels, "cam_angle": theta})
    report = summaries.closing_report(held, rig)
    assert report.failures() == ["CLOSING FAILS (no pole touches)"]
    assert "THE CLOSING FAILS: no pole touches" in report.verdict()
    assert any(n.startswith("no pole touches: the cam comes to rest") for n in report.notes)
    assert not any("a longer --t-end" in n and "touch" in n for n in report.notes)

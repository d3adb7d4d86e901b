"""What a closing's summary says about how the run ends (vcbmodel.experiments.closing_evaluation.run_events,
summaries.closing_notes): a run that stops before the contacts touch, before the cam meets its stop,
or with the cam still turning is said to be truncated; a breaker without an end stop run long, whose
springs turn the cam back so that the contacts reopen, is said to reopen. Each claim is checked
against the run's own channels (pole travel against its gap, the shaft's speed), not against the
figures it is computed from."""
import copy
import json

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.app.cli import main
from vcbmodel.compiled import compiler_works
from vcbmodel.experiments.closing_evaluation import figures_of_merit
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import simulate
from vcbmodel.experiments.summaries import closing_summary
from vcbmodel.laws.breaker import pole_gaps

from conftest import write_rig

pytestmark = pytest.mark.skipif(not compiler_works(), reason="no working C compiler")


def without_stop():
    d = copy.deepcopy(P.REFERENCE_BREAKER)
    d["breaker"].pop("end_stop")
    d["breaker"].pop("hold_latch")
    return d


@pytest.fixture(scope="module")
def rigs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("run_end")
    return {"stop": load_rig(write_rig(folder, P.REFERENCE_BREAKER, "stop")),
            "no_stop": load_rig(write_rig(folder, without_stop(), "no_stop"))}


@pytest.fixture(scope="module")
def long_no_stop(rigs):
    rig = rigs["no_stop"]
    r = simulate(rig, t_end=0.1, backend="compiled")
    return r, figures_of_merit(r, rig), closing_summary(r, rig)


def notes(lines):
    return [text for _, text, _ in lines if isinstance(text, str)]


def test_contacts_that_reopen_without_an_end_stop_are_said_with_their_time(rigs, long_no_stop):
    r, fom, lines = long_no_stop
    gaps = pole_gaps(rigs["no_stop"].breaker.poles)
    open_at_end = [i for i, gap in enumerate(gaps, start=1) if r.channels[f"pole_{i}_travel"][-1] <= gap]
    assert open_at_end and fom["reopened_poles"] == open_at_end
    # at the time said, one pole has just left its contact (closed the sample before) and stays open to the end
    k = int(np.searchsorted(r.t, fom["contacts_reopen_s"]))
    assert fom["closing_time_s"] < fom["contacts_reopen_s"] < r.t[-1]
    assert any(r.channels[f"pole_{i}_travel"][k - 1] > gaps[i - 1] and np.all(r.channels[f"pole_{i}_travel"][k:] <= gaps[i - 1])
               for i in open_at_end)
    # the springs turned the cam back (the shaft turns backwards) before the contacts reopened
    assert fom["cam_falls_back_turning"] == "back" and fom["cam_falls_back_s"] < fom["contacts_reopen_s"]
    assert r.channels["shaft_velocity"][np.searchsorted(r.t, fom["cam_falls_back_s"])] < 0
    said = notes(lines)
    assert any(n.startswith("CONTACTS REOPEN") and f"{1e3 * fom['contacts_reopen_s']:.4g} ms" in n for n in said), said
    assert any("turns back down its rise" in n and "no breaker.end_stop" in n for n in said), said


def test_the_final_reopening_is_not_counted_as_a_bounce(rigs, long_no_stop):
    """The bounces all happen within 47 ms; the same rig run to 55 ms (before the cam turns back)
    counts the same bounces as the long run that ends with the contacts open."""
    _, fom, _ = long_no_stop
    short = simulate(rigs["no_stop"], backend="compiled")
    short_fom = figures_of_merit(short, rigs["no_stop"])
    assert short_fom["contacts_reopen_s"] is None and short_fom["cam_falls_back_s"] is None
    assert fom["bounce_count"] == short_fom["bounce_count"]
    assert fom["bounce_duration_s"] == pytest.approx(short_fom["bounce_duration_s"], abs=2e-5)


@pytest.mark.parametrize("t_end, expected", [
    (0.03, ("before pole 1, 2, 3 touch", "still turning")),
    (0.045, ("before the cam meets its end stop", "still turning")),
    (P.BREAKER_T_END, ("still turning",)),
])
def test_a_truncated_run_says_so(rigs, t_end, expected):
    """The usual 55 ms run ends 3.2 ms after the cam meets its stop (51.8 ms), still turning; a
    shorter one before the stop, or before any pole touches. The shaft's own speed at the end is
    the evidence that it still turns."""
    rig = rigs["stop"]
    r = simulate(rig, t_end=t_end, backend="compiled")
    said = notes(closing_summary(r, rig))
    for text in expected:
        assert any(text in n for n in said), said
    w = r.channels["shaft_velocity"]
    assert abs(w[-1]) > 0.01 * np.max(np.abs(w))
    assert not any("REOPEN" in n for n in said)


def test_a_run_to_rest_on_the_latch_has_no_note(rigs):
    rig = rigs["stop"]
    r = simulate(rig, t_end=0.1, backend="compiled")
    fom = figures_of_merit(r, rig)
    assert notes(closing_summary(r, rig)) == []
    assert fom["end_stop_met"] and not fom["moving_at_end"] and fom["contacts_reopen_s"] is None
    assert fom["lift_lost_m"] < P.CAM_FALL_BACK_FRACTION * rig.breaker.profile.lift


def test_simulate_json_carries_the_notes(rigs, tmp_path, capsys):
    out = tmp_path / "long.csv"
    # the contacts reopen: their force at the end of the run fails the rig's limit (status 1, the report written)
    assert main(["simulate", rigs["no_stop"].path, "--backend", "compiled", "--t-end", "0.1", "-o", str(out), "--json", "-q"]) == 1
    report = json.loads(capsys.readouterr().out)
    assert report["fails"] and "contact_force_closed" in [lim["figure"] for lim in report["limits"]
                                                          if lim["result"].startswith("FAIL")]
    assert any(n.startswith("CONTACTS REOPEN") for n in report["notes"])
    assert report["figures_of_merit"]["contacts_reopen_s"] > report["figures_of_merit"]["closing_time_s"]
    assert report["end_s"] == pytest.approx(0.1) and out.exists()
    never = {s["figure"]: s["value"] for s in report["summary"] if "figure" in s}["travel_settled_s"]
    assert never is None
    # without -o the CSV would share stdout with the JSON: refused before any work, nothing written
    assert main(["simulate", rigs["no_stop"].path, "--json"]) == 2
    assert "--json" in capsys.readouterr().err

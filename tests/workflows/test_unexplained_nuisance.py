"""When the final model does not explain a record, the diagnosis draws no conclusion about the
rig or the record from its nuisance (issue 20: a LuGre record's pauses at reversals were read as
a pre-trigger and a period error, and the report said the rig's inertia was off)."""
from types import SimpleNamespace

import numpy as np

from vcbmodel.analysis.diagnosis.evidence import UNEXPLAINED_CAVEAT, nuisance_report, period_sentence


def fake_ctx():
    setup = SimpleNamespace(pinned={}, window=(0.0, 5.0), hand_start=False, release=0.1, notes=[])
    record = SimpleNamespace(unit="rad")
    return SimpleNamespace(setup=setup, measurement=SimpleNamespace(t=np.array([0.0, 1.0])), uncertain={},
                           search=SimpleNamespace(implied={"pendulum.inertia": 0.02}), record=record)


def fake_fit():
    p = SimpleNamespace(kind="nuisance", name="release_time_0", value=0.1089, vary=True, stderr=1e-4)
    return SimpleNamespace(parameters={"release_time_0": p})


PERIOD = {"relative": 0.0165, "stderr": 0.001, "significant": True}


def test_unexplained_nuisance_is_marked_not_conclusive():
    out = nuisance_report(fake_ctx(), fake_fit(), PERIOD, explained=False)
    assert out["conclusive"] is False and out["caveat"] == UNEXPLAINED_CAVEAT
    assert abs(out["pre_trigger_s"] - 0.1089) < 1e-12  # still reported, with the caveat
    explained = nuisance_report(fake_ctx(), fake_fit(), PERIOD, explained=True)
    assert explained["conclusive"] is True and "caveat" not in explained


def test_period_mismatch_blames_the_rig_only_when_explained():
    ctx = fake_ctx()
    unexplained = period_sentence(ctx, PERIOD, explained=False)
    assert "I/(M g L) is about" not in unexplained and "no conclusion" in unexplained
    assert "friction outside the registered laws" in unexplained
    explained = period_sentence(ctx, PERIOD, explained=True)
    assert "I/(M g L) is about +3.3 % off" in explained

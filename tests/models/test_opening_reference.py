"""The model's opening against an independent solve (vcbmodel.reference.breaker_opening: scipy's
DOP853 on equations written from the rig file's numbers, sharing no model code; its docstring lists
the readings of the rig it shares). The O of the reference cycle breaker, from the closed rest on
the trip latch through the contacts' parting to F's entry into the dashpot (8 ms)."""
from pathlib import Path

import numpy as np
import pytest

from vcbmodel.compiled import compiler_works
from vcbmodel.experiments.cycle_evaluation import _parting
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.sequence import commands_for, with_commands
from vcbmodel.experiments.simulation import simulate
from vcbmodel.laws.breaker import pole_gaps
from vcbmodel.reference.breaker_opening import solve_opening

RIG = Path(__file__).resolve().parents[2] / "results" / "synthetic" / "vcb_cycle.rig.json"


@pytest.mark.skipif(not compiler_works(), reason="no working C compiler")
def test_opening_agrees_with_the_independent_solve():
    """Measured at the model's 1e-5 s step: the closed rests agree to 1e-14; over 8 ms the follower
    within 3.6e-7 rad, the poles within 6.4e-8 m, F within 5.8e-8 m and the partings within 3e-8 s
    (at a quarter of the step: 3e-8 rad, 9e-9 m: the difference is the model's RK4 step)."""
    ref = solve_opening(RIG, 0.008)
    rig = load_rig(RIG)
    run = with_commands(rig, commands_for(rig, "O"))
    full = simulate(run, backend="compiled", t_end=0.008)
    model = full.resample(ref["t"])
    assert abs(model.channels["follower_angle"][0] - ref["follower_angle"][0]) < 1e-12
    assert np.max(np.abs(model.channels["follower_angle"] - ref["follower_angle"])) < 1e-6
    assert np.max(np.abs(model.channels["f_travel"] - ref["f_travel"])) < 2e-7
    for i, gap in enumerate(pole_gaps(rig.breaker.poles), start=1):
        assert np.max(np.abs(model.channels[f"pole_{i}_travel"] - ref[f"pole_{i}_travel"])) < 2e-7
        assert _parting(full.t, full.channels[f"pole_{i}_travel"], gap, 0.0) == pytest.approx(
            _parting(ref["t"], ref[f"pole_{i}_travel"], gap, 0.0), abs=2e-7)
    assert np.max(np.abs(model.channels["pole_2_lever_angle"] - ref["pole_2_lever_angle"])) < 1e-6

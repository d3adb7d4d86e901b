"""The analyser's closing speed: the mean speed over a travel zone before each pole's touch,
configurable in the rig (breaker.speed_zone)."""
import copy

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.errors import InputError
from vcbmodel.experiments.closing_evaluation import crossing_time, zone_speed
from vcbmodel.experiments.loading import load_rig
from vcbmodel.rig.sections import DEFAULT_SPEED_ZONE

from conftest import write_rig


def test_zone_speed_of_a_known_motion():
    t = np.linspace(0.0, 0.02, 2001)
    z = 0.5 * 2000.0 * t**2  # constant acceleration 2000 m/s^2 from rest
    gap = 0.011
    # crossing the zone [gap - 4 mm, gap]: times from z = a t^2 / 2
    t0, t1 = np.sqrt(2 * (gap - 0.004) / 2000.0), np.sqrt(2 * gap / 2000.0)
    assert crossing_time(t, z, gap) == pytest.approx(t1, abs=1e-7)
    assert zone_speed(t, z, gap, (0.004, 0.0)) == pytest.approx(0.004 / (t1 - t0), rel=1e-4)
    # the mean over a zone is below the speed at its end for an accelerating pole
    assert zone_speed(t, z, gap, (0.004, 0.0)) < 2000.0 * t1
    assert zone_speed(t, z, 0.5, (0.004, 0.0)) is None  # never reaches the gap


def test_rig_zone_is_read_checked_and_used(tmp_path):
    rig = load_rig(write_rig(tmp_path, P.REFERENCE_BREAKER, "default"))
    assert rig.breaker.speed_zone == DEFAULT_SPEED_ZONE
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    data["breaker"]["speed_zone"] = [0.006, 0.001]
    assert load_rig(write_rig(tmp_path, data, "zone")).breaker.speed_zone == (0.006, 0.001)
    for bad, message in (([0.001, 0.006], "start > end"), ([0.02, 0.0], "within the smallest pole gap"),
                         ([0.004], "list of 2 numbers")):
        data["breaker"]["speed_zone"] = bad
        with pytest.raises(InputError, match=f"breaker.speed_zone.*{message}"):
            load_rig(write_rig(tmp_path, data, "bad"))

"""The design evaluation's energies: stored when charged, and released up to the first touch."""
import pytest

from vcbmodel import parameters as P
from vcbmodel.analysis.design import closing_design, spring_length
from vcbmodel.experiments.loading import load_rig

from conftest import write_rig


def test_released_to_touch_is_the_springs_energy_drop_to_the_touch_angle(tmp_path):
    rig = load_rig(write_rig(tmp_path, P.REFERENCE_BREAKER, "breaker"))
    r = closing_design(rig)
    s = rig.closing_spring
    assert 0 < r["released_to_touch_J"] < r["stored_energy_J"]
    # the energy left in the springs at the touch, from their length there: a linear spring's
    # energy is F^2 / (2 k), so stored - released = count F_touch^2 / (2 k)
    left = r["stored_energy_J"] - r["released_to_touch_J"]
    pull_at_touch = (2 * s.stiffness * left / s.count) ** 0.5
    assert s.free_length + pull_at_touch / s.stiffness == pytest.approx(
        float(spring_length(rig, rig.cam.initial_angle)) - (r["preload_N"] - pull_at_touch) / s.stiffness, rel=1e-9)
    assert pull_at_touch > r["min_spring_force_N"] - 1e-6  # the pull keeps falling after the touch

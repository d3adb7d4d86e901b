import json
import math
from pathlib import Path

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import simulate
from vcbmodel.reference.truth_friction import truth_pendulum

ROOT = Path(__file__).resolve().parents[1]
#: The seven example records with their answers (a copy of the shared examples, so a clone tests them)
EXAMPLES = ROOT / "tests" / "data" / "examples"


def write_rig(tmp_path, rig_dict, name="rig"):
    path = tmp_path / f"{name}.rig.json"
    path.write_text(json.dumps(rig_dict))
    return path


@pytest.fixture
def pendulum_rig(tmp_path):
    return load_rig(write_rig(tmp_path, P.REFERENCE_PENDULUM, "pendulum"))


@pytest.fixture
def cam_rig(tmp_path):
    return load_rig(write_rig(tmp_path, P.REFERENCE_CAM, "cam"))


def offsets_from_independent_pendulum(rig, kind, values, effect_sets, duration=6.0, step=1e-3):
    """The largest |model - truth| angle (rad) of the pendulum ``rig`` simulated with each of
    ``effect_sets`` against the independent truth's own solve of friction ``kind`` (truth_friction.py),
    both with ``values``, over ``duration`` s sampled every ``step`` s."""
    p = rig.pendulum
    t = np.arange(0.0, duration + step / 2, step)
    truth = truth_pendulum(kind, {"mass": p.mass, "inertia": p.inertia, "com_distance": p.com_distance,
                                  "initial_angle": p.initial_angle}, rig.gravity, rig.shaft_radius, values, t)["theta"]
    return [float(np.max(np.abs(simulate(rig, effects, values, sample_times=t).measured - truth)))
            for effects in effect_sets]


def examples_available():
    return (EXAMPLES / "answers.json").exists()


def ar1(rng, n, sigma, phi):
    """``n`` samples of stationary AR(1) noise: standard deviation ``sigma``, lag-1 correlation ``phi``."""
    e = np.empty(n)
    e[0] = rng.normal(0, sigma)
    u = rng.normal(0, sigma * math.sqrt(1 - phi**2), n)
    for i in range(1, n):
        e[i] = phi * e[i - 1] + u[i]
    return e

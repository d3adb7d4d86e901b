import json
import math
from pathlib import Path

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.experiments.loading import load_rig

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

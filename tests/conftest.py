import json
from pathlib import Path

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

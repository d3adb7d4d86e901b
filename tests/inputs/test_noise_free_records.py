"""A record with no noise at all (vcbmodel simulate's own output read back) is refused by identify and
diagnose in one line naming the file and the channel: a fit weighs its residual by the record's noise,
and with none the fit failed with messages that named no file ('bad input: simulate: values.mu_k: must be
a finite number, not negative, got nan'; 'simulation failed: the fitted model's simulation failed')."""
import json

import numpy as np
import pandas as pd
import pytest

from vcbmodel.app.cli import main
from vcbmodel.errors import InputError
from vcbmodel.experiments.loading import load_record, load_rig, require_noise


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    """A pendulum rig whose friction is to be identified, and its own simulation as simulate writes it (6 s)."""
    folder = tmp_path_factory.mktemp("noise_free")
    rig = folder / "pend.rig.json"
    assert main(["init", "pendulum", "-o", str(rig), "-q"]) == 0
    assert main(["simulate", str(rig), "-o", str(folder / "pend.csv"), "-q"]) == 0  # 6 s: at rest from 2.8 s
    data = json.loads(rig.read_text())
    for key in ("mu_k", "mu_s", "viscous", "stribeck_velocity"):
        data["friction"].pop(key)
    rig.write_text(json.dumps(data))
    return folder


@pytest.mark.parametrize("command", ["identify", "diagnose"])
def test_a_noise_free_record_is_refused_naming_file_and_channel(simulated, command, capsys):
    csv = simulated / "pend.csv"
    assert main([command, str(csv), "-q"]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"vcbmodel: bad input: {csv}: pendulum_angle: shows no noise"), err
    assert captured.out == ""


def test_the_same_record_with_a_sensor_s_noise_is_read(simulated, tmp_path):
    table = pd.read_csv(simulated / "pend.csv", comment="#")
    table["pendulum_angle"] += np.random.default_rng(2).normal(0.0, 2e-4, len(table))
    noisy = tmp_path / "noisy.csv"
    table.to_csv(noisy, index=False)
    rig = load_rig(simulated / "pend.rig.json")
    require_noise(load_record(noisy, rig), rig)  # a record with a sensor's noise passes
    with pytest.raises(InputError, match="pendulum_angle"):
        require_noise(load_record(simulated / "pend.csv", rig), rig)

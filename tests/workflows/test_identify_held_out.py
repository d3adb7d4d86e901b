"""Validation on records the fit never saw (vcbmodel/analysis/held_out.py), through identify: records
of one rig at two release angles, from the independent torque truth (reference/torque_truth.py)."""
import copy
import json
import math

import numpy as np

from vcbmodel import parameters as P
from vcbmodel.analysis.identify import identify
from vcbmodel.app.cli import main
from vcbmodel.experiments.loading import load_pair
from vcbmodel.records.measurement import Measurement, write_measurement
from vcbmodel.reference.torque_truth import pendulum_with_torque

#: A big paddle's air drag, 0.5 rho Cd A R^3 with a 0.1 m^2 bluff plate (Cd 2) at 0.5 m (N m s^2/rad^2)
DRAG = 0.5 * 1.2 * 2.0 * 0.1 * 0.5**3
FRICTION = {"mu_k": 0.12, "viscous": 0.5}


def record(tmp_path, name, degrees, drag, seed, t_end=6.0):
    """A pendulum record (rad, 1 kHz, 0.5 mrad white noise) from the torque truth with drag -c w|w|."""
    rig = copy.deepcopy(P.REFERENCE_PENDULUM)
    rig["pendulum"]["initial_angle"] = math.radians(degrees)
    rig["model"] = {"effects": ["coulomb_friction", "viscous_friction"], "spring_model": "massless"}
    rig["name"] = name
    t = np.arange(0.0, t_end + 5e-4, 1e-3)
    theta = pendulum_with_torque(rig["pendulum"], rig["gravity"], rig["shaft"]["radius"], FRICTION,
                                 lambda time, th, w: -drag * w * abs(w), t)
    y = np.where(np.isnan(theta), theta[np.isfinite(theta)][-1], theta) + np.random.default_rng(seed).normal(0, 5e-4, t.size)
    (tmp_path / f"{name}.rig.json").write_text(json.dumps(rig))
    write_measurement(Measurement(str(tmp_path / f"{name}.csv"), t, {"pendulum_angle": y}, ("SYNTHETIC test record",)),
                      tmp_path / f"{name}.csv")
    return tmp_path / f"{name}.csv"


def test_air_drag_is_exposed_by_the_held_out_records(tmp_path):
    """With drag the law lacks, the two records fitted together leave a residual at their noise
    (reduced chi^2 about 1.01), but the law fitted to either one does not predict the other (1.8 and
    2.2 times its noise), and the viscous coefficient that stands in for the drag is larger at the
    faster swing: the report names a missing effect."""
    pairs = [load_pair(record(tmp_path, f"drag{d}", d, DRAG, seed)) for d, seed in ((10, 1), (25, 2))]
    r = identify(pairs, verbose=False, forms=False)
    assert r.residual_to_noise < 1.1
    j = r.to_json()["held_out"]
    assert all(p["ratio"] > 1.5 for p in j["predictions"]) and not j["predicted_at_noise"]
    singles = j["single_record_fits"]["viscous"]
    assert singles[1]["value"] > singles[0]["value"]
    assert j["missing_effect"]
    assert "NOT PREDICTED at its noise" in r.report()


def test_records_of_one_law_are_predicted_at_their_noise_and_nothing_moves(tmp_path):
    pairs = [load_pair(record(tmp_path, f"dry{d}", d, 0.0, seed)) for d, seed in ((10, 3), (20, 4))]
    r = identify(pairs, verbose=False, forms=False)
    j = r.to_json()["held_out"]
    assert j["predicted_at_noise"] and not j["moving"] and not j["missing_effect"]
    assert all(p["ratio"] < 1.2 for p in j["predictions"])
    assert len(j["predictions"]) == 2 and j["predictions"][0]["trained_on"] == [str(tmp_path / "dry20.csv")]


def test_identify_json_carries_the_held_out_records_and_the_forms(tmp_path, capsys):
    paths = [record(tmp_path, f"r{d}", d, 0.0, seed, t_end=3.0) for d, seed in ((10, 5), (15, 6))]
    assert main(["identify", *map(str, paths), "--json", "-q"]) == 0
    j = json.loads(capsys.readouterr().out)
    assert set(j["held_out"]) >= {"predictions", "single_record_fits", "moving", "missing_effect"}
    assert {"forms", "quantities", "not_determined", "plausibility"} <= set(j["model_forms"])
    # the hybrid law on records without a Stribeck fall: its fall is said to be undetermined, nothing else
    assert {(f["parameter"], f["kind"]) for f in j["implausible"]} <= {("mu_s", "stderr"), ("stribeck_velocity", "stderr")}

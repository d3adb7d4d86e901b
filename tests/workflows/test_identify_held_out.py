"""Validation on records the fit never saw (vcbmodel/analysis/held_out.py), through identify: records
of one rig at two release angles, from the independent torque truth (reference/torque_truth.py)."""
import copy
import json
import math

import numpy as np
import pytest

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


@pytest.mark.slow
def test_air_drag_is_exposed_by_the_held_out_records(tmp_path):
    """With drag the law lacks, the two records fitted together leave a residual at their noise
    (reduced chi^2 about 1.0), but they do not agree on one set of values: the likelihood ratio of
    the joint fit against the two single fits is about 180 chi^2 units for 4 degrees of freedom. The
    viscous coefficient that stands in for the drag is larger at the faster swing, the law fitted to
    one record predicts the other at 1.2 and 2.2 times its noise, and the report names a missing
    effect and the value that must move."""
    pairs = [load_pair(record(tmp_path, f"drag{d}", d, DRAG, seed)) for d, seed in ((10, 1), (25, 2))]
    r = identify(pairs, verbose=False, forms=False)
    assert r.residual_to_noise < 1.1
    j = r.to_json()["held_out"]
    c = j["consistency"]
    assert c["statistic"] > 100 and c["dof"] == 4 and c["p_value"] < 1e-10 and not j["consistent"]
    assert max(p["ratio"] for p in j["predictions"]) > 1.5
    singles = j["single_record_fits"]["viscous"]
    assert singles[1]["value"] > singles[0]["value"]
    assert j["missing_effect"] and j["moving"][0]["delta_chi2"] > 20
    assert "INCONSISTENT" in r.report() and "MISSING EFFECT" in r.report()
    assert "the records disagree on the values" in r.warning


def test_records_of_one_law_are_consistent_and_nothing_moves(tmp_path):
    pairs = [load_pair(record(tmp_path, f"dry{d}", d, 0.0, seed)) for d, seed in ((10, 3), (20, 4))]
    r = identify(pairs, verbose=False, forms=False)
    j = r.to_json()["held_out"]
    assert j["consistent"] and not j["moving"] and not j["missing_effect"] and j["needed_moves"] == {}
    assert j["consistency"]["statistic"] < 10  # chi^2 with 4 degrees of freedom: 13.3 at 99 %
    assert all(p["ratio"] < 1.2 for p in j["predictions"])
    assert len(j["predictions"]) == 2 and j["predictions"][0]["trained_on"] == [str(tmp_path / "dry20.csv")]
    # each record's own fit, from its own starts, ends at the truth (Coulomb plus viscous is in the law)
    for name in ("mu_k", "viscous"):
        assert all(abs(row["value"] - FRICTION[name]) < 0.02 * FRICTION[name] for row in j["single_record_fits"][name])


def test_identify_json_carries_the_held_out_records_and_the_forms(tmp_path, capsys):
    paths = [record(tmp_path, f"r{d}", d, 0.0, seed, t_end=3.0) for d, seed in ((10, 5), (15, 6))]
    assert main(["identify", *map(str, paths), "--json", "-q"]) == 0
    j = json.loads(capsys.readouterr().out)
    assert set(j["held_out"]) >= {"consistency", "consistent", "predictions", "single_record_fits", "needed_moves",
                                  "moving", "missing_effect"}
    assert j["held_out"]["consistent"] and not j["held_out"]["missing_effect"]
    assert {"forms", "quantities", "not_determined", "plausibility"} <= set(j["model_forms"])
    # the hybrid law on records without a Stribeck fall: its fall is said to be undetermined, nothing else
    assert {(f["parameter"], f["kind"]) for f in j["implausible"]} <= {("mu_s", "stderr"), ("stribeck_velocity", "stderr")}


# --- the consistency test's statistics, on fits built by hand (fast) ---------------------------

def _fit_of(residuals, varied=("mu_k", "viscous"), values=None, sigma=1e-3):
    from vcbmodel.analysis.fit import FitResult, Parameter
    from vcbmodel.rig.spring_model import SpringModel
    values = values or {}
    params = {n: Parameter(n, values.get(n, 0.1), 0.0, 1.0, vary=True) for n in varied}
    params["release_time_1"] = Parameter("release_time_1", 0.01, 0.0, 0.1, kind="release", dataset=1)
    return FitResult(("coulomb_friction",), SpringModel(), params, [np.asarray(r, float) for r in residuals], [], sigma)


def test_the_likelihood_ratio_is_the_joint_chi2_over_the_single_fits_and_rejects_only_beyond_its_quantile():
    from scipy import stats

    from vcbmodel.analysis import held_out as H
    rng = np.random.default_rng(0)
    sigmas = [1e-3, 2e-3]
    noise = [rng.normal(0, s, 2000) for s in sigmas]
    singles = [_fit_of([noise[0]]), _fit_of([noise[1]])]
    # the joint fit leaves each record's own residual plus a misfit worth `extra` chi^2 units in record 1
    for extra, consistent in ((2.0, True), (60.0, False)):
        bump = np.zeros(2000)
        bump[:100] = math.sqrt(extra / 100) * sigmas[0]
        joint = _fit_of([noise[0] + bump, noise[1]])
        c = H.consistency_test(joint, singles, sigmas)
        expected = float(np.sum((noise[0] + bump) ** 2) - np.sum(noise[0] ** 2)) / sigmas[0] ** 2
        assert c["statistic"] == pytest.approx(expected, rel=1e-9)
        assert c["dof"] == 2  # (records - 1) x the varied model values; the nuisance does not count
        s2 = (np.sum(noise[0] ** 2) / sigmas[0] ** 2 + np.sum(noise[1] ** 2) / sigmas[1] ** 2) / (4000 - 6)
        assert c["residual_variance"] == pytest.approx(s2, rel=1e-9)
        f = max(expected - H.ROUGHNESS_ALLOWANCE, 0.0) / 2 / s2
        assert c["p_value"] == pytest.approx(stats.f.sf(f, 2, 4000 - 6), rel=1e-6)
        assert c["consistent"] is consistent


def test_a_single_fit_above_the_joint_fits_share_of_its_record_counts_as_that_share():
    from vcbmodel.analysis import held_out as H
    rng = np.random.default_rng(1)
    r = [rng.normal(0, 1e-3, 500), rng.normal(0, 1e-3, 500)]
    joint = _fit_of(r)
    worse = _fit_of([1.1 * r[0]])  # stopped short of its floor: the joint values do better on its record
    c = H.consistency_test(joint, [worse, _fit_of([r[1]])], [1e-3, 1e-3])
    assert c["statistic"] == pytest.approx(0.0, abs=1e-9) and c["consistent"]


def test_the_value_the_records_need_most_is_named_and_none_below_the_roughness():
    from vcbmodel.analysis import held_out as H
    needs = {"mu_k": {"delta_chi2": 3.0, "z": 1.7, "values": [0.12, 0.121]},
             "viscous": {"delta_chi2": 40.0, "z": 6.3, "values": [0.53, 0.515]}}
    m = H._most_moving(needs, [math.radians(10), math.radians(20)])
    assert m["parameter"] == "viscous" and m["records"] == [2, 1] and m["values"] == [0.515, 0.53]
    assert "viscous must move most" in m["message"]
    needs["viscous"]["delta_chi2"] = H.ROUGHNESS_ALLOWANCE / 2
    assert H._most_moving(needs, [0.2, 0.3]) is None
    # z: two records, one degree of freedom: the square root; an underflowing p-value stays finite
    assert H._z_of(4.0, 1) == pytest.approx(2.0) and H._z_of(9.21, 2) == pytest.approx(2.576, abs=2e-3)
    assert math.isfinite(H._z_of(1.5e5, 2))


def test_a_records_nuisance_is_renumbered_when_it_is_fitted_alone():
    from vcbmodel.analysis import held_out as H
    params = _fit_of([np.zeros(3)]).parameters
    alone = H.own_parameters(params, [1])
    assert set(alone) == {"mu_k", "viscous", "release_time_0"} and alone["release_time_0"].dataset == 0
    assert set(H.own_parameters(params, [0])) == {"mu_k", "viscous"}

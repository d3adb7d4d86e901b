"""Issue 20: the stated errors cover model-form error. Records are drawn from truths outside the
fitted family, identified with the hybrid law, and each stated 95 % interval (1.96 stderr) is
checked against the truth of the parameters whose meaning the laws share: the kinetic friction
level mu_k and the viscous coefficient. The naive (white-noise) intervals are counted alongside.

Truths (independent solves; they share with the model the pendulum's equation of motion and the
journal reaction, eq. 1 and 5-6, not the friction law):
- vcbmodel.reference.truths.position_dependent_pendulum: journal friction varying with the shaft
  angle, mu_k (1 + 0.5 sin(2 pi theta / lambda + phase)); each record its own defect and noise;
- vcbmodel.reference.truth_friction.truth_pendulum: Tustin, LuGre and Dahl friction; one truth,
  a noise draw per record.
In family, the covering interval must not be absurdly wider than the naive one. The numbers are in
docs/findings.md ("Parameter errors that cover model-form error").
"""
import copy

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.analysis.identify import WARN_RATIO, identify
from vcbmodel.analysis.synthetic import synthetic_measurement
from vcbmodel.experiments.loading import rig_from_data
from vcbmodel.experiments.pendulum import start_guesses
from vcbmodel.records.measurement import Measurement
from vcbmodel.reference.truth_friction import truth_pendulum
from vcbmodel.reference.truths import position_dependent_pendulum

SHARED = ("mu_k", "viscous")
TRUTH = {"mu_k": 0.13, "viscous": 0.6}
#: The friction truths' values: the hybrid truth's (parameters.REFERENCE_PENDULUM_TRUTH) where
#: the laws share a meaning, the bristle constants of parameters.py.
LAW_TRUTH = {"mu_s": 0.20, "mu_k": 0.13, "stribeck_velocity": 0.10, "viscous": 0.6}
BRISTLES = {"lugre": {"sigma0": P.LUGRE_SIGMA0, "sigma1": P.LUGRE_SIGMA1}, "dahl": {"sigma0": P.DAHL_SIGMA0}}
SIGMA = 5e-4  # rad
Z95 = 1.96


def pendulum_rig():
    data = copy.deepcopy(P.REFERENCE_PENDULUM)
    data["friction"] = {}
    return rig_from_data(data, "p.rig.json"), data


def out_of_family_record(seed: int, t_end: float = 6.0):
    """A 1 kHz record of the position-dependent truth (amplitude 0.5 of mu_k), own defect and noise."""
    rig, data = pendulum_rig()
    rng = np.random.default_rng(1000 + seed)
    t = np.arange(0.0, t_end, 1e-3)
    theta = position_dependent_pendulum(data["pendulum"], data["gravity"], data["shaft"]["radius"], TRUTH, 0.5,
                                        float(rng.uniform(0.05, 0.09)), float(rng.uniform(0.0, 2 * np.pi)), t)
    y = theta + np.random.default_rng(seed).normal(0.0, SIGMA, t.size)
    return rig, Measurement("p.csv", t, {"pendulum_angle": y})


def friction_truth_records(kind: str, seeds, t_end: float = 6.0) -> list:
    """1 kHz records of one Tustin, LuGre or Dahl truth, a noise draw per seed."""
    rig, data = pendulum_rig()
    t = np.arange(0.0, t_end, 1e-3)
    values = {**LAW_TRUTH, **BRISTLES.get(kind, {})}
    if kind == "dahl":
        values = {k: values[k] for k in ("mu_k", "viscous", "sigma0")}
    theta = truth_pendulum(kind, data["pendulum"], data["gravity"], data["shaft"]["radius"], values, t)["theta"]
    return [(rig, Measurement("p.csv", t, {"pendulum_angle": theta + np.random.default_rng(seed).normal(0.0, SIGMA, t.size)}))
            for seed in seeds]


def in_family_record(seed: int, t_end: float = 6.0):
    rig, _ = pendulum_rig()
    meas = synthetic_measurement(rig, ("coulomb_friction", "stribeck", "viscous_friction"),
                                 P.REFERENCE_PENDULUM_TRUTH, seed=seed, t_end=t_end, sigma=SIGMA)
    return rig, meas


def coverage(records, truth) -> dict:
    """Fraction of (record, shared parameter) pairs whose 95 % interval holds the truth, for the
    stated and the naive errors; the stated/naive width ratios; per record whether identify warned
    and whether all its stated intervals held the truth."""
    hits = {"stated": 0, "naive": 0}
    ratios, n, records_out = [], 0, []
    for rig, meas in records:
        result = identify([(rig, meas)], verbose=False, forms=False)
        held = True
        for name in SHARED:
            p = result.fit.parameters[name]
            miss = abs(p.value - truth[name])
            hits["stated"] += miss <= Z95 * p.stderr
            hits["naive"] += miss <= Z95 * p.stderr_naive
            held &= bool(miss <= Z95 * p.stderr)
            ratios.append(p.stderr / p.stderr_naive)
            n += 1
        records_out.append((result.residual_to_noise > WARN_RATIO, held))
    return {"stated": hits["stated"] / n, "naive": hits["naive"] / n, "ratios": np.array(ratios),
            "records": records_out}


def test_stated_errors_cover_out_of_family_truths_where_the_naive_ones_do_not():
    angle = coverage([out_of_family_record(seed) for seed in range(6)], TRUTH)
    assert angle["stated"] >= 0.75
    assert angle["naive"] <= 0.4 and angle["naive"] < angle["stated"] - 0.3
    lugre = coverage(friction_truth_records("lugre", range(2)), LAW_TRUTH)
    assert lugre["stated"] == 1.0 and lugre["naive"] <= 0.5


def test_in_family_the_stated_errors_stay_near_the_naive_ones():
    c = coverage([in_family_record(seed) for seed in range(3)], P.REFERENCE_PENDULUM_TRUTH)
    assert np.all(c["ratios"] >= 1.0 - 1e-9) and np.all(c["ratios"] <= 3.0)
    assert c["stated"] >= c["naive"]


@pytest.mark.slow
def test_coverage_over_many_records():
    """Out of family the stated intervals hold the truth at least twice as often as the naive ones
    (every time for LuGre and Dahl, and on every Tustin record whose residual stands above the
    noise: a law that absorbs the difference completely leaves nothing to measure it by); in family
    they stay within 1.5x the naive width on average (3x at most)."""
    angle = coverage([out_of_family_record(seed) for seed in range(20)], TRUTH)
    laws = {kind: coverage(friction_truth_records(kind, range(10)), LAW_TRUTH) for kind in ("tustin", "lugre", "dahl")}
    inside = coverage([in_family_record(seed) for seed in range(20)], P.REFERENCE_PENDULUM_TRUTH)
    for name, c in [("angle", angle), *laws.items(), ("in family", inside)]:
        print(f"{name}: stated {c['stated']:.2f}, naive {c['naive']:.2f}, width ratio median "
              f"{np.median(c['ratios']):.2f} max {c['ratios'].max():.2f}")
    assert angle["stated"] >= 0.7 and angle["stated"] >= 2 * angle["naive"]
    assert laws["lugre"]["stated"] == 1.0 and laws["dahl"]["stated"] == 1.0
    assert all(held for warned, held in laws["tustin"]["records"] if warned)
    for kind in ("tustin", "lugre"):
        assert laws[kind]["stated"] >= 2 * laws[kind]["naive"]
    assert inside["stated"] >= 0.85
    assert np.mean(inside["ratios"]) <= 1.5 and inside["ratios"].max() <= 3.0


@pytest.mark.parametrize("kind, seed, best", [("tustin", 0, 1.1), ("lugre", 2, 3.0)])
def test_identify_finds_the_better_optimum_of_an_out_of_family_record(kind, seed, best):
    """Out-of-family records where the fit from the record's own span regression stopped with
    viscous 0 at 7-9 times the noise (Tustin seed 0: 6.97x, LuGre seed 2: 9.05x); the better
    optimum, from starts spread along the Coulomb-viscous valley (identify.DECAY_SPLITS), lies at
    1.0x (Tustin) and 2.8x (LuGre, whose pre-sliding no hybrid law has). The starting regression
    itself still puts the whole decay in Coulomb friction here, so the test needs the spread starts."""
    rig, meas = friction_truth_records(kind, [seed])[0]
    assert start_guesses(rig, meas)[0]["viscous"] < 0.1  # the regression's start is in the wrong valley end
    r = identify([(rig, meas)], verbose=False, forms=False)
    assert r.residual_to_noise < best
    assert r.values["viscous"] == pytest.approx(LAW_TRUTH["viscous"], rel=0.2)
    assert abs(r.values["mu_k"] - 0.14) < 0.01  # not the local optimum's 0.17

"""Layer 4: the discrepancy workflow on measurements with a hidden effect (made here, random)."""
import json
from pathlib import Path

import numpy as np
import pytest

from conftest import EXAMPLES, examples_available
from vcbmodel.model import effects as effects_module
from vcbmodel.analysis.diagnose import BIC_MARGIN, _candidate_jobs, diagnose
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.loading import load_record
from vcbmodel.records.measurement import load_measurement
from vcbmodel.analysis.synthetic import CASES, random_case
from vcbmodel.records.signals import noise_estimate
from vcbmodel.rig.spring_model import SpringModel


def run_case(case, seed, tmp_path):
    # 3 s of swing is enough for a pendulum, except for Stribeck friction, which shows most
    # while the swing dies out
    short = CASES[case][0] == "pendulum" and case != "pend_strib"
    rig_path, meas_path, truth = random_case(case, seed, tmp_path, t_end=3.0 if short else None)
    rig = load_rig(rig_path)
    d = diagnose(rig, load_record(meas_path, rig), verbose=False)
    return d, truth


def check(d, truth):
    assert d.missing_effect == truth["answer"], d.report()
    if truth["answer"] is None:
        assert d.final is d.baseline
        assert all(c.delta_bic <= BIC_MARGIN for c in d.candidates)
        assert d.baseline.rms < 1.1 * d.noise  # explained within the noise
    else:
        # the gap between model and truth is the residual in excess of the noise
        j = d.to_json()
        assert j["excess_after"] <= 0.5 * j["excess_before"]
        assert d.final.rms < 1.15 * d.noise  # the gap closes down to the noise
        assert truth["answer"] in d.final.effects


#: Case kinds run by default (one per effect kind and a control); the rest with the slow checks.
QUICK = {"pend_visc", "pend_strib", "cam_mass", "cam_none"}


@pytest.mark.parametrize("case", [c if c in QUICK else pytest.param(c, marks=pytest.mark.slow) for c in sorted(CASES)])
def test_names_hidden_effect(case, tmp_path):
    """One random draw per case kind (both experiments, every registry effect, and controls)."""
    d, truth = run_case(case, 11, tmp_path)
    check(d, truth)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [12, 13])
@pytest.mark.parametrize("case", sorted(CASES))
def test_names_hidden_effect_more_seeds(case, seed, tmp_path):
    d, truth = run_case(case, seed, tmp_path)
    check(d, truth)


def test_report_contents(tmp_path):
    d, truth = run_case("cam_coul", 11, tmp_path)
    j = d.to_json()
    for key in ("missing_effect", "baseline_effects", "final_effects", "rms_before", "rms_after", "noise_estimate",
                "window", "candidates", "fitted"):
        assert key in j
    json.dumps(j)  # serialisable
    assert j["final_effects"] == ["coulomb_friction"] and j["baseline_effects"] == []
    assert 0.13 * 0.5 < j["fitted"]["mu_k"] < 0.2
    assert {c["effect"] for c in j["candidates"]} == {"coulomb_friction", "stribeck", "viscous_friction", "spring_mass",
                                                      "spring_damping"}
    t0, t1 = j["window"]
    assert 0 <= t0 <= t1 <= 0.035
    # the disagreement of a frictionless model grows with travel: the window is late in the drop
    assert t1 > 0.02
    assert j["noise_estimate"] == pytest.approx(2e-3, rel=0.15)
    # every field the JSON gives is documented in docs/cli.md (top level, verdict and nuisance)
    doc = (Path(__file__).resolve().parents[2] / "docs" / "cli.md").read_text()
    keys = set(j) | set(j["verdict"]) | set(j["verdict"]["tests"]) | set(j["nuisance"]) | set(j["discovered"])
    assert {k for k in keys if f"`{k}`" not in doc} == set()


def test_noise_estimate_recovers_sigma():
    t = np.linspace(0, 6, 6001)
    y = 0.17 * np.cos(6.8 * t) * np.exp(-0.2 * t)
    for sigma in (5e-4, 2e-3):
        noisy = y + np.random.default_rng(1).normal(0, sigma, t.size)
        assert noise_estimate(noisy) == pytest.approx(sigma, rel=0.05)


def test_registering_an_effect_makes_it_a_candidate(monkeypatch, tmp_path):
    """Adding an entry to the registry is all it takes: the workflow loops over it."""
    class Backlash(effects_module.Effect):
        name = "shaft_backlash"
        parameters = ()
        def on(self, spec, values, rig):
            pass
        def off(self, spec, values, rig):
            pass
    registry = dict(effects_module.EFFECTS, shaft_backlash=Backlash())
    monkeypatch.setattr("vcbmodel.analysis.diagnosis.candidates.EFFECTS", registry)
    rig_path, meas_path, _ = random_case("cam_none", 3, tmp_path)
    rig = load_rig(rig_path)

    class Baseline:
        effects, spring_model, values = ("coulomb_friction",), SpringModel(), {"mu_k": 0.1}
    jobs = _candidate_jobs(rig, load_measurement(meas_path), Baseline, [{}], 2e-3)
    assert "shaft_backlash" in {name for name, _, _ in jobs}
    assert "coulomb_friction" not in {name for name, _, _ in jobs}


@pytest.mark.skipif(not examples_available(), reason="shared example data not present")
@pytest.mark.parametrize("name", ["example05"])
def test_examples_quick(name):
    answers = json.loads((EXAMPLES / "answers.json").read_text())
    rig = load_rig(EXAMPLES / f"{name}.rig.json")
    d = diagnose(rig, load_record(EXAMPLES / f"{name}.csv", rig), verbose=False)
    assert d.missing_effect == answers[name]["answer"]


@pytest.mark.slow
@pytest.mark.skipif(not examples_available(), reason="shared example data not present")
@pytest.mark.parametrize("name", ["example01", "example02", "example03", "example04", "example06", "example07"])
def test_examples_all(name):
    answers = json.loads((EXAMPLES / "answers.json").read_text())
    rig = load_rig(EXAMPLES / f"{name}.rig.json")
    d = diagnose(rig, load_record(EXAMPLES / f"{name}.csv", rig), verbose=False)
    assert d.missing_effect == answers[name]["answer"]
    if d.missing_effect:
        assert d.final.rms <= 0.5 * d.baseline.rms

"""Sensor artefacts behind one protocol (vcbmodel/analysis/diagnosis/artefacts): a made-up
artefact defined in this file alone is set aside by the one criterion of "at the noise", and an
ADC's quantisation is noise, not friction."""
import math

import numpy as np
import pytest

from vcbmodel.analysis.diagnose import diagnose
from vcbmodel.analysis.diagnosis.artefacts import ARTEFACTS, Artefact, ResidualView, register
from vcbmodel.analysis.diagnosis.at_noise import judge_residual
from vcbmodel.analysis.diagnosis.witnesses import high_frequency_witness
from vcbmodel.analysis.realistic import LOGGER_STEP, realistic_record
from vcbmodel.experiments.loading import load_record, load_rig

SIGMA = 5e-4


class Glitches:
    """A made-up artefact: single samples a logger's glitch threw far off (beyond 8 noise levels
    from both neighbours), fitted as their indices, removed by the neighbours' mean."""

    name = "glitches"
    order = 5

    def fit(self, view):
        r = np.asarray(view.residual, float)
        far = 8 * view.sigma_hf
        i = np.nonzero((np.abs(r[1:-1] - r[:-2]) > far) & (np.abs(r[1:-1] - r[2:]) > far))[0] + 1
        return [int(k) for k in i] or None

    def remove(self, view, found):
        r = np.asarray(view.residual, float).copy()
        for k in found:
            r[k] = 0.5 * (r[k - 1] + r[k + 1])
        return r

    def report(self, found, unit):
        return {"samples": found}, f" {len(found)} glitch(es) set aside."


@pytest.fixture
def glitches():
    artefact = register(Glitches())
    yield artefact
    del ARTEFACTS[artefact.name]


def glitched_residual():
    rng = np.random.default_rng(3)
    t = np.arange(4000) / 1000.0
    r = rng.normal(0.0, SIGMA, t.size)
    r[[500, 1700, 3100]] += 0.05
    return t, r


def judged(t, r):
    return judge_residual(ResidualView(t, r, None, SIGMA, 0.0, None), [], [high_frequency_witness(SIGMA)])


def test_a_made_up_artefact_in_one_file_is_set_aside(glitches):
    assert isinstance(glitches, Artefact)
    t, r = glitched_residual()
    out = judged(t, r)
    assert out.at_noise and out.to_json()["sensor_artefacts"]["glitches"] == {"samples": [500, 1700, 3100]}
    assert "3 glitch(es) set aside." in "".join(f.sentence for f in out.artefacts)


def test_without_it_the_same_residual_is_not_at_the_noise():
    t, r = glitched_residual()
    assert "glitches" not in ARTEFACTS and not judged(t, r).at_noise


def test_an_object_that_does_not_follow_the_protocol_is_refused():
    with pytest.raises(TypeError, match="Artefact protocol"):
        register(object())


@pytest.mark.parametrize("complication", [("quantised",), ("logger_12bit",)])
def test_a_12_bit_record_gets_no_friction_effect_named(tmp_path, complication):
    """A pendulum from the independent reference solve (no code shared with the model), read on a
    12-bit grid over a potentiometer's 340 degrees (1.45 mrad): alone, and after 0.5 mrad of
    sensor noise. The rounding is counted as noise: no Stribeck friction is named for it (the
    rounded record of seed 11 had Stribeck friction named at 0.97x its noise; of 36 such records,
    Coulomb or viscous friction hidden or none, it was the only one whose answer changed)."""
    values = {"quantised": LOGGER_STEP} if complication == ("quantised",) else None
    rig_path, meas_path, truth = realistic_record("pend_none", 11, tmp_path, complication, values=values)
    rig = load_rig(rig_path)
    j = diagnose(rig, load_record(meas_path, rig), verbose=False).to_json()
    assert j["missing_effects"] == [] and j["explained"], j["evidence"]
    q = j["nuisance"]["quantisation"]
    assert q["step"] == pytest.approx(LOGGER_STEP, rel=1e-6)
    assert q["rounding_noise"] == pytest.approx(LOGGER_STEP / math.sqrt(12), rel=1e-6)
    assert "counted as noise" in j["evidence"]
    # the model forms count a run of identical rounded values once (noise.rounding_bic): no form that
    # follows the rounding at low speed beats the selected law by the margin (counted per sample, the
    # Gaussian-Stribeck form led the rounded record by 328), so the verdict names no rival form
    assert j["model_forms"]["selected_delta_bic"] <= j["options"]["rival_form_margin"]
    assert "rival_form" not in j["verdict"]

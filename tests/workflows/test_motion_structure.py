"""A residual that passes only as correlated noise must hold no function of the motion
(vcbmodel/analysis/diagnosis/motion.py, at_noise.judge_residual): a cam drop's slow model error
(white noise plus a smooth function of the state, 1.35x the high-frequency level: within the
high-frequency witness's factor 2 for correlated noise) is not at the noise; a correlated sensor's
noise at the same level, and white noise with the same error too small to leave the level, are."""
import numpy as np

from vcbmodel.analysis.diagnosis.artefacts import ResidualView
from vcbmodel.analysis.diagnosis.at_noise import judge_residual
from vcbmodel.analysis.diagnosis.motion import motion_structure
from vcbmodel.analysis.diagnosis.witnesses import high_frequency_witness
from vcbmodel.records.signals import noise_estimate

SIGMA = 2e-3  # rad, a camera's noise
T = np.arange(420) / 12e3  # a 35 ms cam drop at 12 kHz


def _drop() -> np.ndarray:
    """A cam's angle falling by 0.3 rad over the record with an accelerating start (rad)."""
    return 0.17 - 0.3 * (1 - np.cos(np.pi * T / T[-1])) / 2


def _misfit(x: np.ndarray, rms: float) -> np.ndarray:
    """A progressive spring's missing cubic term: a smooth function of the angle, rms ``rms``."""
    m = (x - x.mean()) ** 3
    m = m - m.mean()
    return rms * m / np.sqrt(np.mean(m**2))


def _ar1(rng, phi: float) -> np.ndarray:
    e = np.empty(T.size)
    e[0] = rng.normal(0, SIGMA)
    for i in range(1, T.size):
        e[i] = phi * e[i - 1] + rng.normal(0, SIGMA * np.sqrt(1 - phi**2))
    return e


def _judged(residual: np.ndarray, model: np.ndarray):
    hf = noise_estimate(residual)
    return judge_residual(ResidualView(T, residual, model, hf, 0.0, None), [], [high_frequency_witness(hf)])


def test_a_slow_model_error_does_not_pass_as_correlated_noise():
    """Of 12 noise draws with the error, those whose whitened residual passes the noise tests and that
    the high-frequency witness alone lets pass (1.15-2x its level) are not at the noise."""
    x = _drop()
    passing = 0
    for seed in range(12):
        rng = np.random.default_rng(seed)
        j = _judged(rng.normal(0, SIGMA, T.size) + _misfit(x, 0.9 * SIGMA), x)
        if not (j.tests["consistent"] and 1.15 < j.tests["rms_over_high_frequency_noise"] < 2.0):
            continue
        passing += 1
        assert j.evidence["holds"] is True  # the witness alone would call it noise
        assert j.tests["motion_structure"]["delta_bic"] > 10 and not j.at_noise
    assert passing >= 1


def test_correlated_sensor_noise_and_a_small_error_under_white_noise_still_pass():
    for seed in range(3):
        rng = np.random.default_rng(seed)
        noise = _ar1(rng, 0.6)
        j = _judged(noise, _drop())
        assert j.tests["rms_over_high_frequency_noise"] > 1.15
        assert j.tests["motion_structure"]["delta_bic"] < -20 and j.at_noise
    # within level_factor of the high-frequency level the test is not asked (white noise at that level)
    rng = np.random.default_rng(3)
    j = _judged(rng.normal(0, SIGMA, T.size) + _misfit(_drop(), 0.3 * SIGMA), _drop())
    assert "motion_structure" not in j.tests and j.at_noise


def test_too_short_a_record_or_no_model_says_nothing():
    assert motion_structure(T[:40], np.zeros(40), _drop()[:40], 10.0) is None
    assert motion_structure(T, np.zeros(T.size), None, 10.0) is None


def test_the_evidence_says_the_residual_is_a_function_of_the_motion():
    from vcbmodel.analysis.diagnosis.evidence import _why_not_noise
    x = _drop()
    rng = np.random.default_rng(4)
    tests = _judged(rng.normal(0, SIGMA, T.size) + _misfit(x, 0.9 * SIGMA), x).tests
    assert tests["consistent"] and tests["motion_structure"]["holds"] is False
    assert "function of the motion" in _why_not_noise(tests)
    assert "not white" in _why_not_noise({**tests, "consistent": False})

"""Layer 4: the verdict of whole diagnoses on realistic records with sensor artefacts and an
approximate clock (issue 20). The records come from :mod:`vcbmodel.analysis.realistic` (truth from
the independent reference, noise drawn there); each test states what the record carries."""
import json
import math

import pytest

from vcbmodel.analysis.diagnose import diagnose
from vcbmodel.analysis.realistic import LOGGER_STEP, realistic_record
from vcbmodel.experiments.loading import load_record, load_rig


def realistic(case, seed, tmp_path, complications, values=None, t_end=None, rig_edit=None, friction_truth="hybrid"):
    rig_path, meas_path, truth = realistic_record(case, seed, tmp_path, complications, t_end=t_end, values=values,
                                                  friction_truth=friction_truth)
    if rig_edit:
        data = json.loads(rig_path.read_text())
        rig_edit(data)
        rig_path.write_text(json.dumps(data))
    rig = load_rig(rig_path)
    return diagnose(rig, load_record(meas_path, rig), verbose=False), truth


def test_mains_pickup_is_the_sensors_and_the_physics_is_explained(tmp_path):
    """A potentiometer with a 60 Hz line of 0.43 mrad: the missing viscous friction is named and,
    the line set aside as mains pickup, explained (before: "not explained" at 1.16x the noise,
    with a window of zero width)."""
    d, truth = realistic("pend_visc", 41, tmp_path, ("mains",), t_end=3.0)
    j = d.to_json()
    assert j["missing_effects"] == ["viscous_friction"] and j["explained"], d.evidence
    (line,) = j["nuisance"]["sensor_lines"]
    mains = truth["complications"]["mains"]
    assert line["frequency_hz"] == pytest.approx(mains["frequency_hz"], abs=0.05)
    assert line["amplitude"] == pytest.approx(mains["amplitude"], rel=0.15)
    assert line["source"] == "mains pickup" and "mains pickup" in d.evidence


def test_a_logger_rounding_is_reported_and_explained(tmp_path):
    """A 12-bit logger on the potentiometer (1.45 mrad steps over 0.5 mrad noise): explained,
    the rounding reported under nuisance with its step."""
    d, _ = realistic("pend_visc", 52, tmp_path, ("logger_12bit",))
    j = d.to_json()
    assert j["missing_effects"] == ["viscous_friction"] and j["explained"], d.evidence
    assert j["nuisance"]["quantisation"]["step"] == pytest.approx(LOGGER_STEP, rel=1e-6)


def test_a_mains_line_reads_the_records_clock(tmp_path):
    """Mains pickup on a record whose clock is 0.22 % off, with a pre-trigger: the line's
    frequency gives the time scale (within 1e-4 of the truth), which is fitted as the record's
    nuisance with the grid's tolerance; the physics is then explained (before: 2.6x the noise,
    "not explained")."""
    d, truth = realistic("pend_coul", 46, tmp_path, ("mains", "time_base", "pre_trigger"))
    j = d.to_json()
    assert j["missing_effects"] == ["coulomb_friction"] and j["explained"], d.evidence
    base = j["nuisance"]["time_base"]
    assert base["source"] == "mains line" and base["separable_from_inertia"]
    assert base["time_scale"] == pytest.approx(1 + truth["complications"]["time_base"], abs=1e-4)
    assert j["verdict"]["independent_evidence"]["holds"] is True


def test_a_stated_sensor_noise_is_a_witness(tmp_path):
    """The rig's record.sensor_noise: a clean record holds against the true level; stated at
    half of it, the same residual does not, and the verdict says so."""
    def state(level):
        def edit(data):
            data["record"] = {"sensor_noise": level}
        return edit
    d, truth = realistic("pend_visc", 43, tmp_path, (), t_end=3.0, rig_edit=state(5e-4))
    j = d.to_json()
    assert j["explained"] and j["verdict"]["independent_evidence"]["decided_by"] == ["rig"]
    d2, _ = realistic("pend_visc", 43, tmp_path, (), t_end=3.0, rig_edit=state(2.5e-4))
    j2 = d2.to_json()
    assert not j2["explained"] and j2["verdict"]["independent_evidence"]["holds"] is False
    assert j2["verdict"]["tests"]["consistent"]  # the fitted noise model alone would have said explained
    assert "noise model fitted to the residual" in d2.evidence
    assert math.isclose(j2["rms_after"], j["rms_after"], rel_tol=1e-6)


@pytest.mark.slow
def test_camera_frame_jitter_is_the_sensors(tmp_path):
    """The camera record of issue 20 (spring mass hidden, 3 ms pre-trigger, offset, noise of lag-1
    correlation 0.6, clock 0.4 % off with 20 us frame jitter): the residual's excess grows with the
    speed as the jitter makes it; estimated (within 3 standard errors of 20 us) and set aside, the
    residual stands at the pre-trigger's noise: explained, with the jitter named."""
    values = {"time_base": 0.004, "correlated": 0.6, "pre_trigger": 0.003}
    d, _ = realistic("cam_mass", 61, tmp_path, ("pre_trigger", "offset", "correlated", "time_base"), values=values)
    j = d.to_json()
    assert j["missing_effects"] == ["spring_mass"] and j["explained"], d.evidence
    jit = j["nuisance"]["timing_jitter"]
    assert abs(jit["jitter_s"] - 2e-5) < 3 * jit["stderr_s"]
    assert j["verdict"]["independent_evidence"]["decided_by"] == ["pre_trigger"]


def test_a_gain_the_rig_pins_is_said_to_condition_the_stated_errors(tmp_path):
    """A pendulum read with a gain 2.9 % off that the rig does not mark uncertain: the friction
    absorbs it at a residual at the noise (mu_k 45 stated errors off). The diagnosis cannot see
    the error, but says that a plausible gain error (parameters.PINNED_GAIN_ERROR) moves the fitted
    values beyond their stated errors, in the direction and by the size the true error moved them; marked
    uncertain, the gain is fitted and no such caveat is given."""
    d, truth = realistic("pend_coul", 15001, tmp_path, ("gain",))
    j = d.to_json()
    (item,) = j["nuisance"]["pinned_sensitivity"]
    assert item["field"] == "record.sensor_gain" and item["beyond_stated"]
    assert "record.sensor_gain" in d.evidence and "stated errors" in d.evidence
    gain_error = truth["complications"]["gain"] - 1.0
    bias = j["fitted"]["mu_k"] - truth["truth_friction"]["mu_k"]
    predicted = item["shifts"]["mu_k"]["shift"] / item["plausible_error"] * gain_error
    # sign and size of what the gain did (measured by a refit: 1.04; a linearised shift on the swing's
    # kinky cost said 0.48)
    assert predicted * bias > 0 and 0.7 < predicted / bias < 1.4
    # viscous friction does not depend on the gain (a decay's ratio): a one-sided refit, sliding along
    # the valley, put a stated error's worth there; the central difference does not
    assert item["shifts"]["viscous"]["stated_errors"] < 0.7 and item["how"].startswith("central difference")
    assert abs(bias) > 1.96 * j["stderr"]["mu_k"] and item["shifts"]["mu_k"]["stated_errors"] > 1.96

    def uncertain_gain(data):
        data["uncertain"] = {"record.sensor_gain": 0.03}
    d2, _ = realistic("pend_coul", 15001, tmp_path, ("gain",), rig_edit=uncertain_gain)
    assert "pinned_sensitivity" not in d2.to_json()["nuisance"] and "record.sensor_gain = " not in d2.evidence


@pytest.mark.slow
def test_a_lugre_pendulum_read_by_a_12_bit_logger_names_viscous_friction(tmp_path):
    """LuGre friction on a pendulum whose truth has viscous friction, read through a 12-bit logger:
    the record's own span regression put the whole decay in Coulomb friction and the scan for
    viscous friction stayed at that end of the Coulomb-viscous valley, so nothing was named at
    3.0x the noise. With scan centres spread along the valley (fits.valley_bases) the nearest
    registered effects are named and the verdict stays "not explained" (pre-sliding is in no law)."""
    d, truth = realistic("pend_visc", 52, tmp_path, ("logger_12bit",), friction_truth="lugre")
    j = d.to_json()
    assert "viscous_friction" in j["missing_effects"] and not j["explained"]
    assert j["rms_after"] < 0.6 * j["rms_before"]

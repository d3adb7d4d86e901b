"""Discovery on cam drops (vcbmodel.analysis.discovery): the cam's equations carry a discovered
torque on every backend from one source; the independent truth (vcbmodel.reference.cam_torque_truth)
agrees with the model where they share the physics; on its synthetic records a profile torque
-A sin(2 theta - phi) is found with its coefficients, and a torque outside the library gives "nothing"."""
import math
from pathlib import Path

import numpy as np
import pytest
from conftest import write_rig

from vcbmodel.analysis import fit as fitting
from vcbmodel.analysis.diagnose import BIC_MARGIN, MIN_VARIANCE_GAIN, diagnose
from vcbmodel.analysis.discovery import discover, discover_among
from vcbmodel.analysis.discovery.force import smoothing_points, unread
from vcbmodel.analysis.discovery.library import library_for
from vcbmodel.compiled import compiler_works
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import simulate
from vcbmodel.laws.discovered import TERMS
from vcbmodel.laws.friction import ArrayOps
from vcbmodel.records.measurement import Measurement
from vcbmodel.records.signals import noise_estimate
from vcbmodel.reference.cam_torque_truth import cam_drop_with_torque

CAM = {"mass": 6.0, "inertia_com": 0.05, "com_distance": 0.02, "com_angle": 0.5, "pivot": [0.4445, 0.0],
       "arm_length": 0.1032, "initial_angle": 0.17453292519943295, "initial_velocity": 0.0}
SPRING = {"count": 2, "stiffness": 24230.0, "mass": 1.0, "free_length": 0.3, "anchor": [0.0, 0.0]}
MU_K = 0.13
SIGMA = 2e-3
T = np.arange(421) / 12000.0  # a 35 ms drop filmed at 12 kHz


@pytest.fixture(scope="module")
def cam_rig(tmp_path_factory):
    rig = {"format": "vcb-rig/1", "name": "cam", "experiment": "cam_drop", "gravity": 9.81, "shaft": {"radius": 0.02},
           "cam": CAM, "closing_spring": SPRING, "friction": {"stick_velocity": 0.001},
           "model": {"effects": ["coulomb_friction"], "spring_model": "massless"}}
    return load_rig(write_rig(tmp_path_factory.mktemp("camdisc"), rig, "cam"))


def truth(extra, eccentric=None):
    return cam_drop_with_torque(CAM, SPRING, 9.81, 0.02, {"mu_k": MU_K}, extra, T, eccentric)


def discovery_of(rig, extra, seed):
    """Discovery on the registered model (Coulomb friction, value unknown) fitted to a noisy record."""
    y = truth(extra)[0] + np.random.default_rng(seed).normal(0.0, SIGMA, T.size)
    meas = Measurement("synthetic.csv", T, {"cam_angle": y})
    ds = fitting.Dataset(rig, meas)
    sigma = noise_estimate(y)
    params = fitting.make_parameters(rig, ("coulomb_friction",), initial={"mu_k": 0.1})
    registered = fitting.fit([ds], ("coulomb_friction",), rig.model.spring_model, params, sigma=sigma, verbose=False,
                             processes=1)
    return discover(rig, meas, registered, dataset=ds, sigma=sigma, quantisation=0.0, bic_margin=BIC_MARGIN,
                    min_gain=MIN_VARIANCE_GAIN)


VALUES = {"mu_k": MU_K, "discovered:w_abs_w": -2e-3, "discovered:sin_2theta": 20.0, "discovered:rub_120deg": -15.0,
          "discovered:time": 300.0}


@pytest.mark.parametrize("backend,user_function", [("exudyn", "symbolic"), pytest.param(
    "compiled", "auto", marks=pytest.mark.skipif(not compiler_works(), reason="no working C compiler"))])
def test_every_backend_runs_the_same_discovered_torque_on_the_cam(cam_rig, backend, user_function):
    effects = ("coulomb_friction", "discovered_torque")
    python = simulate(cam_rig, effects, VALUES, t_end=0.035, backend="exudyn", user_function="python")
    other = simulate(cam_rig, effects, VALUES, t_end=0.035, backend=backend, user_function=user_function)
    without = simulate(cam_rig, ("coulomb_friction",), VALUES, t_end=0.035, backend="exudyn", user_function="python")
    assert np.max(np.abs(other.measured - python.measured)) < 1e-9
    assert np.max(np.abs(without.measured - python.measured)) > 1e-2  # the torque acts


def test_the_independent_cam_truth_is_the_model_where_they_share_the_physics(cam_rig):
    # the truth's extra torque against the model's discovered one (same form), and nothing against nothing
    for extra, values in ((lambda t, th, w: 0.0, {}), (lambda t, th, w: -20.0 * math.sin(2 * th) - 3e-4 * w * abs(w),
                                                       {"discovered:sin_2theta": -20.0, "discovered:w_abs_w": -3e-4})):
        effects = ("coulomb_friction",) + (("discovered_torque",) if values else ())
        model = simulate(cam_rig, effects, {"mu_k": MU_K, **values}, sample_times=T, backend="exudyn",
                         user_function="python")
        assert np.max(np.abs(model.measured - truth(extra)[0])) < 1e-7
    # an eccentric mass (weight, inertia, bearing force) moves the drop: the truth's own physics acts
    assert np.max(np.abs(truth(lambda t, th, w: 0.0, {"mass": 1.0, "distance": 0.1, "angle": 1.0})[0]
                         - truth(lambda t, th, w: 0.0)[0])) > 5e-3


def test_the_cam_library_and_its_smoothing(cam_rig):
    names = library_for("cam_drop")
    assert "rub_120deg" in names and "sin_2theta" in names and not any(n.startswith("sign_exp") for n in names)
    assert not any(n.startswith("rub_") for n in library_for("pendulum"))
    theta = np.linspace(0.0, 2 * np.pi, 721)
    windows = sum(np.asarray(TERMS[n].value(0.0 * theta, theta, 1.0 + 0.0 * theta, ArrayOps)) for n in names
                  if n.startswith("rub_"))
    assert np.ptp(windows) / np.mean(windows) < 0.05  # the windows cover the whole turn evenly
    window = np.asarray(TERMS["rub_120deg"].value(0.0, theta, -2.0, ArrayOps))
    assert window[240] == pytest.approx(-1.0) and abs(window[480]) < 1e-6  # opposes the motion, localized
    assert smoothing_points(cam_rig, 1 / 12000.0, 0.035) == 85  # a fifth of the stroke


def test_a_lumped_model_is_read_with_its_chain_and_an_ancf_one_is_not(cam_rig):
    fit = type("Fit", (), {"spring_model": cam_rig.model.spring_model})()
    assert unread(cam_rig, fit) is None
    fit.spring_model = type("S", (), {"kind": "lumped", "label": "lumped-3 (exact)"})()
    assert unread(cam_rig, fit) is None
    fit.spring_model = type("S", (), {"kind": "ancf", "label": "ancf"})()
    assert "Exudyn's alone" in unread(cam_rig, fit)


def test_the_missing_torque_of_a_lumped_record_the_model_made_is_nil(cam_rig):
    """On a lumped model the chain's state is the fitted model's own: on a record that model made, the
    missing torque is nil (what is left is the smoothing's), and the inertia the one the cam feels."""
    from types import SimpleNamespace

    from vcbmodel.analysis.discovery.force import missing_torque
    from vcbmodel.laws.mechanics import cam_inertia
    from vcbmodel.laws.springs import chain_for
    from vcbmodel.rig.spring_model import SpringModel
    lumped = SpringModel.parse("lumped-3")
    effects, values = ("coulomb_friction", "spring_mass"), {"mu_k": MU_K, "stick_velocity": 1e-3}
    y = simulate(cam_rig, effects, values, spring_model=lumped, sample_times=T).measured
    dataset = SimpleNamespace(setup=SimpleNamespace(release=0.0), mask=lambda: np.ones(T.size, bool), t=T, y=y)
    fit = SimpleNamespace(values=dict(values), model_values=values, effects=effects, spring_model=lumped, parameters={})
    est = missing_torque(cam_rig, dataset, fit)
    assert len(est.chain[0]) == 6 and est.used.sum() > 200
    pin = cam_rig.closing_spring.count * chain_for(cam_rig.closing_spring, lumped).pin_mass
    # the equations' response to a unit torque: 1/I less the friction's share through the reaction (0.1 %)
    assert est.inertia == pytest.approx(cam_inertia(cam_rig.cam, pin), rel=3e-3)
    spring_torque = 2 * 24230.0 * 0.1 * CAM["arm_length"]  # N m: the springs' pull at 0.1 m of stretch, on the arm
    assert np.max(np.abs(est.torque[est.used])) < 1e-9 * spring_torque  # 1e-9 N m seen
    massless = SimpleNamespace(values=dict(values), model_values=values, effects=("coulomb_friction",),
                               spring_model=SpringModel.parse("massless"), parameters={})
    wrong = missing_torque(cam_rig, dataset, massless)  # the chain's surge read as a missing torque
    assert np.max(np.abs(wrong.torque[wrong.used])) > 1e-3 * spring_torque


def test_a_profile_torque_is_found_with_its_coefficients(cam_rig):
    A, phi = 30.0, 0.6
    found = discovery_of(cam_rig, lambda t, th, w: -A * math.sin(2 * th - phi), seed=11)
    assert found.found and found.rms_after < 0.7 * found.rms_before
    terms = {t.name: t for t in found.terms}
    assert set(terms) == {"sin_2theta", "cos_2theta"}
    # the harmonic's sine and cosine are one form (a phase): tried together among the singles, where a
    # greedy search of single terms would take a position window first
    kept = next(row for row in found.tried if row["kept"])
    assert kept["stage"] == 1 and sorted(kept["terms"]) == ["cos_2theta", "sin_2theta"]
    for name, true in (("sin_2theta", -A * math.cos(phi)), ("cos_2theta", A * math.sin(phi))):
        assert abs(terms[name].coefficient - true) < 3 * terms[name].stderr
        assert abs(terms[name].coefficient - true) < 0.05 * A


@pytest.mark.slow
def test_a_torque_outside_the_library_gives_nothing_after_the_diagnosis(cam_rig):
    # a 120 Hz hum leaves a gap the registered model cannot close (its verdict depends on the noise's
    # draw: searched here either way, on the diagnosis's models and alignment); nothing in the library fits
    y = truth(lambda t, th, w: 100.0 * math.sin(2 * math.pi * 120.0 * t))[0]
    meas = Measurement("hum.csv", T, {"cam_angle": y + np.random.default_rng(12).normal(0.0, SIGMA, T.size)})
    d = diagnose(cam_rig, meas, verbose=False)
    hum = d.discovery or discover_among(cam_rig, meas, [d.final, d.baseline_own_alignment], bic_margin=BIC_MARGIN,
                                        min_gain=MIN_VARIANCE_GAIN)
    assert not hum.found and "holds nothing that fits" in hum.message and hum.rms_before > 1.3 * SIGMA


def test_an_in_family_record_gives_nothing(cam_rig):
    clean = discovery_of(cam_rig, lambda t, th, w: 0.0, seed=13)
    assert not clean.found and clean.after is None


@pytest.mark.slow
def test_a_profile_torque_found_on_the_starting_model_retires_the_viscous_friction_it_stood_in_for(tmp_path, monkeypatch):
    """The discovery demo's cam (a profile torque -30 sin(2 theta - 0.6), no viscous friction in the truth):
    the diagnosis names viscous friction as the torque's stand-in; discovery must search the starting model
    with the torque's two terms (a harmonic's cos and sin) and keep that base, not the one with viscous friction."""
    import importlib.util
    studies = Path(__file__).resolve().parents[2] / "studies"
    monkeypatch.syspath_prepend(str(studies))
    spec = importlib.util.spec_from_file_location("discovery_demo", studies / "discovery_demo.py")
    demo = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(demo)
    rig_path = tmp_path / "cam.rig.json"
    demo.write_rig(dict(demo.CAM_RIG), rig_path)
    case = demo.run_case(load_rig(rig_path), "profile", demo.CAM_DURATION, 11)
    found = case["discovery"]
    assert found.found and {t.name for t in found.terms} == {"sin_2theta", "cos_2theta"}
    assert "viscous_friction" not in found.to_json()["base_effects"]

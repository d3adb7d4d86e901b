"""The ANCF continuum spring: modal checks against the continuum, mesh convergence, cam drop."""
import math

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.builders.ancf import ancf_modes
from vcbmodel.errors import SimulationError
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import simulate
from vcbmodel.laws.coil import coil_bending_stiffness

K0, M0, L0 = 24230.0, 0.3364, 0.30
EFFECTS = ("coulomb_friction", "stribeck", "spring_mass")
T = np.arange(0, 421) / 12000.0


def test_axial_frequencies_converge_to_fixed_fixed_continuum():
    exact = 0.5 * math.sqrt(K0 / M0) * np.arange(1, 4)  # n * 134.19 Hz
    errors = []
    for n in (2, 4, 8):
        axial, _ = ancf_modes(K0, M0, L0, n, count=3)
        errors.append(np.max(np.abs(np.array(axial) / exact - 1)))
    assert errors[2] < 0.01 and errors[0] > errors[1] > errors[2]


def test_preloaded_lateral_mode_is_the_string_mode_plus_bending():
    """6000 N over the stretched length: f^2 = T/(4 m0 L) + bending term of a pinned beam."""
    T_pre = 6000.0
    L = L0 + T_pre / K0
    axial, lateral = ancf_modes(K0, M0, L0, 8, preload=T_pre, count=3)
    string = 0.5 * math.sqrt(T_pre / (M0 * L))
    assert string == pytest.approx(90.2, abs=0.2)
    EI = coil_bending_stiffness(type("S", (), dict(stiffness=K0, free_length=L0, wire_diameter=None, coil_diameter=None,
                                                  shear_modulus=None, active_coils=None)))
    bending = (math.pi / L) ** 2 * math.sqrt(EI / (M0 / L)) / (2 * math.pi)
    assert lateral[0] == pytest.approx(math.hypot(string, bending), rel=0.02)
    assert axial[0] == pytest.approx(134.19, rel=0.001)  # preload does not change the axial modes


@pytest.fixture(scope="module")
def heavy_cam(tmp_path_factory):
    import copy
    import json
    d = copy.deepcopy(P.REFERENCE_CAM)
    d["closing_spring"]["mass"] = 1.0
    path = tmp_path_factory.mktemp("ancf") / "cam.rig.json"
    path.write_text(json.dumps(d))
    return load_rig(path)


def test_cam_drop_converges_under_mesh_refinement(heavy_cam):
    runs = {n: simulate(heavy_cam, EFFECTS, spring_model="ancf", ancf_elements=n, sample_times=T, step=1.25e-6)
            for n in (4, 8, 16)}
    d1 = np.max(np.abs(runs[4].measured - runs[16].measured))
    d2 = np.max(np.abs(runs[8].measured - runs[16].measured))
    assert d2 < d1 and d2 < 1e-4
    assert all(np.all(np.isfinite(r.measured)) for r in runs.values())


def test_uniform_chains_approach_the_ancf_continuum(heavy_cam):
    ancf = simulate(heavy_cam, EFFECTS, spring_model="ancf", sample_times=T)
    uniform = heavy_cam
    gaps = [np.max(np.abs(simulate(uniform, EFFECTS, spring_model=f"lumped-{n}:uniform", sample_times=T).measured - ancf.measured))
            for n in (5, 10, 20)]
    assert gaps[0] > gaps[1] > gaps[2]
    assert gaps[2] < 0.05  # 20 equal masses: within 50 mrad of the continuum after a 3.5 rad stroke


def test_ancf_channels_and_divergence_is_reported(heavy_cam):
    r = simulate(heavy_cam, EFFECTS, spring_model="ancf", ancf_elements=4, t_end=0.01)
    assert {"ancf_node_1_x", "ancf_node_3_y", "cam_angle"} <= set(r.channels)
    with pytest.raises(SimulationError):
        simulate(heavy_cam, EFFECTS, spring_model="ancf", ancf_elements=4, t_end=0.01, step=1e-4)

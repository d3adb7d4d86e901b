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
    EI = coil_bending_stiffness(type("S", (), dict(stiffness=K0, mass=M0, free_length=L0, wire_diameter=None,
                                                  coil_diameter=None, shear_modulus=None, active_coils=None)))
    EI_stretched = EI * L / L0  # the coil's bending stiffness grows with its length (Haringx)
    for mode in (1, 2, 3):
        string_n = mode * string
        bending = (mode * math.pi / L) ** 2 * math.sqrt(EI_stretched / (M0 / L)) / (2 * math.pi)
        assert lateral[mode - 1] == pytest.approx(math.hypot(string_n, bending), rel=2e-3)
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


@pytest.mark.slow  # a convergence sweep (what the slow marker is for)
def test_cam_drop_converges_under_mesh_refinement(heavy_cam):
    runs = {n: simulate(heavy_cam, EFFECTS, spring_model="ancf", ancf_elements=n, sample_times=T, step=1.25e-6)
            for n in (4, 8, 16)}
    d1 = np.max(np.abs(runs[4].measured - runs[16].measured))
    d2 = np.max(np.abs(runs[8].measured - runs[16].measured))
    assert d2 < d1 and d2 < 1e-4
    assert all(np.all(np.isfinite(r.measured)) for r in runs.values())


@pytest.mark.slow  # a convergence sweep (what the slow marker is for)
def test_uniform_chains_approach_the_ancf_continuum(heavy_cam):
    """Two independent discretisations of the same coil meet: uniform chains (with half a
    segment's mass on the pin) approach the rigid-tie ANCF continuum, to 0.3 mrad rms at 20
    masses (the rest is the coil's bending stiffness, which chains lack) after a 3.5 rad stroke."""
    from vcbmodel.experiments.simulation import simulate_rigid_ties
    truth = simulate_rigid_ties(heavy_cam, EFFECTS, sample_times=T).measured
    gaps = [np.sqrt(np.mean((simulate(heavy_cam, EFFECTS, spring_model=f"lumped-{n}:uniform", sample_times=T).measured
                             - truth) ** 2)) for n in (5, 10, 20)]
    assert gaps[0] > 4 * gaps[1]  # measured 2.1 -> 0.42 mrad
    assert gaps[2] < 0.5e-3  # measured 0.32 mrad


def test_ancf_channels_and_divergence_is_reported(heavy_cam):
    r = simulate(heavy_cam, EFFECTS, spring_model="ancf", ancf_elements=4, t_end=0.01)
    assert {"ancf_node_1_x", "ancf_node_3_y", "cam_angle"} <= set(r.channels)
    with pytest.raises(SimulationError):
        simulate(heavy_cam, EFFECTS, spring_model="ancf", ancf_elements=4, t_end=0.01, step=1e-4)


def test_coil_geometry_is_consistent_with_k0_and_m0():
    """The derived coil (index 4) has the spring's stiffness and active mass; the stress it
    would see at 6000 N shows why no steel spring meets the paper's k0, m0 and force at once."""
    from types import SimpleNamespace
    from vcbmodel.laws.coil import coil_geometry
    for m0 in (M0, 1.0):
        s = SimpleNamespace(stiffness=K0, mass=m0, free_length=L0, wire_diameter=None, coil_diameter=None,
                            active_coils=None, shear_modulus=None)
        g = coil_geometry(s)
        assert g.mass() == pytest.approx(m0, rel=1e-9)
        assert g.shear_modulus * g.wire_diameter**4 / (8 * g.coil_diameter**3 * g.active_coils) == pytest.approx(K0)
        assert g.active_coils * g.wire_diameter < L0  # the wire fits side by side in the free length
        assert g.shear_stress(6000.0) > 1.5e9  # far above ~0.85 GPa allowable (parameters.py)


def test_tie_error_falls_as_one_over_k_and_extrapolates(heavy_cam):
    """The ties' compliance error ~ 1/k: successive differences shrink 10x per decade, so
    the two-point extrapolation to rigid ties is exact to that order (10 ms window)."""
    from vcbmodel.experiments.simulation import simulate_rigid_ties
    t = np.arange(121) / 12000.0
    runs = {k: simulate(heavy_cam, EFFECTS, spring_model="ancf", sample_times=t, ancf_tie_stiffness=k).measured
            for k in (1e7, 1e8, 1e9)}
    d1, d2 = np.max(np.abs(runs[1e7] - runs[1e8])), np.max(np.abs(runs[1e8] - runs[1e9]))
    assert d2 > 0 and d1 / d2 == pytest.approx(10.0, rel=0.15)
    rigid = simulate_rigid_ties(heavy_cam, EFFECTS, sample_times=t, stiffnesses=(1e8, 1e9)).measured
    coarse = simulate_rigid_ties(heavy_cam, EFFECTS, sample_times=t, stiffnesses=(1e7, 1e8)).measured
    assert np.max(np.abs(rigid - coarse)) < 0.05 * d1  # both extrapolate to the same rigid limit


def _with_spring_mass(rig, mass):
    from vcbmodel.rig.paths import loaded_with
    return loaded_with(rig, {"closing_spring.mass": mass})


@pytest.mark.parametrize("mass", [0.1, 3.0])
def test_stable_step_tracks_the_ties_fast_mode(heavy_cam, mass):
    """The step bound sqrt(m_end / k_tie) is the real stability limit: at the bound a 0.1 kg and
    a 3 kg spring run (a 0.1 kg spring diverged at the old fixed 2.5e-6 s), at 1.5x it RK4
    diverges for both (measured limit 1.19-1.35x the bound), and the studies' step never exceeds it."""
    from vcbmodel.builders.ancf import AncfOptions
    rig = _with_spring_mass(heavy_cam, mass)
    h = AncfOptions().stable_step(rig.closing_spring)
    assert AncfOptions().step(rig.closing_spring) <= h
    t = np.arange(121) / 12000.0
    r = simulate(rig, EFFECTS, spring_model="ancf", sample_times=t)
    assert np.all(np.isfinite(r.measured)) and r.info["step"] <= h
    with pytest.raises(SimulationError):
        simulate(rig, EFFECTS, spring_model="ancf", sample_times=t, step=1.5 * h)


def test_fit_step_of_the_continuum_is_accurate(heavy_cam):
    """Fits run the continuum at its stability-bounded step (1.7x the studies' for 1 kg): the
    cam angle stays within 0.01 mrad of the studies' step, far below any sensor's noise."""
    from vcbmodel.analysis.fit import fit_step
    from vcbmodel.rig.spring_model import SpringModel
    h = fit_step(heavy_cam, SpringModel.parse("ancf"))
    assert h > 1.5 * P.ANCF_STEP
    fine = simulate(heavy_cam, EFFECTS, spring_model="ancf", sample_times=T).measured
    fast = simulate(heavy_cam, EFFECTS, spring_model="ancf", sample_times=T, step=h).measured
    assert np.max(np.abs(fast - fine)) < 1e-5

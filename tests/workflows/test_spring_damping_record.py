"""A cam drop whose closing springs damp themselves (a Kelvin-Voigt continuum, the independent solve
vcbmodel/reference/cam_spring_truth) on a rig with lumped springs: the diagnosis names the springs'
internal damping (``spring_damping``) with its damping ratio, not shaft viscous friction (which it named
before the effect was registered: mu_k 0.105 and Cv 0.084 N m s/rad for a truth of mu_k 0.13 and no
viscous friction), and says the two are close (``ambiguous``)."""
import numpy as np
from conftest import write_rig

from vcbmodel.analysis.diagnose import diagnose
from vcbmodel.experiments.loading import load_rig
from vcbmodel.records.measurement import Measurement
from vcbmodel.reference.cam_spring_truth import cam_drop_with_damped_spring

CAM = {"mass": 6.0, "inertia_com": 0.05, "com_distance": 0.02, "com_angle": 0.5, "pivot": [0.4445, 0.0],
       "arm_length": 0.1032, "initial_angle": 0.17453292519943295, "initial_velocity": 0.0}
SPRING = {"count": 2, "stiffness": 24230.0, "mass": 1.0, "free_length": 0.3, "anchor": [0.0, 0.0]}
MU_K, ZETA, SIGMA = 0.13, 0.05, 2e-3
T = np.arange(421) / 12000.0


def test_a_self_damping_spring_is_not_read_as_shaft_viscous_friction(tmp_path):
    rig = load_rig(write_rig(tmp_path, {
        "format": "vcb-rig/1", "name": "lumped springs", "experiment": "cam_drop", "gravity": 9.81,
        "shaft": {"radius": 0.02}, "cam": CAM, "closing_spring": SPRING, "friction": {"stick_velocity": 0.001},
        "model": {"effects": ["coulomb_friction", "spring_mass"], "spring_model": "lumped-8",
                  "lumped_convention": "uniform"}}, "lumped"))
    theta, _ = cam_drop_with_damped_spring(CAM, SPRING, 9.81, 0.02, {"mu_k": MU_K}, ZETA, T, 32)
    meas = Measurement("damped.csv", T, {"cam_angle": theta + np.random.default_rng(14).normal(0.0, SIGMA, T.size)})
    d = diagnose(rig, meas, verbose=False)
    assert d.missing_effects == ["spring_damping"] and "viscous_friction" not in d.final.effects
    for name, truth in (("damping_ratio", ZETA), ("mu_k", MU_K)):
        p = d.final.parameters[name]
        assert abs(p.value - truth) < 2 * p.stderr, (name, p.value, p.stderr)
    assert d.final.rms < 1.1 * SIGMA

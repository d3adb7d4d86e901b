"""The cam drop (paper section 3): the charged closing springs turn the free cam."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from .. import parameters as P
from ..builders.cam_drop import build_cam_drop
from ..compiled import OdeModel
from ..reference.solve import reference_cam_drop
from ..compiled.equations import cam_drop_equations, prepare_cam_drop
from ..laws.springs import fundamental
from ..rig.sections import read_cam_and_spring
from ..builders.ancf import AncfOptions
from .random_rigs import cam_drop_random_rig
from .base import Experiment, refuse_discovered_torque, shaft_channels
from .summaries import cam_drop_summary

if TYPE_CHECKING:
    from ..builders.core import ExudynModel
    from ..laws.friction import FrictionLaw
    from ..laws.springs import LumpedChain
    from ..model.effects import ModelSpec
    from ..model.result import SimulationResult
    from ..records.measurement import Measurement
    from ..rig.data import Rig


def build(rig: Rig, spec: ModelSpec, law: FrictionLaw, chain: LumpedChain | None, user_function: str,
          ancf_elements: AncfOptions | int | None) -> ExudynModel:
    return build_cam_drop(rig, law, spec.spring_model, chain, user_function, ancf_elements=ancf_elements,
                          discovered=spec.discovered, spring_damping=spec.spring_damping)


def reference(rig: Rig, spec: ModelSpec, law: FrictionLaw, chain: LumpedChain | None, t_end: float,
              method: str = "DOP853", step: float | None = None) -> tuple[dict[str, np.ndarray], dict]:
    """The reference solve (:func:`vcbmodel.reference.solve.reference_cam_drop`); it has no
    discovered torque, so a model that carries one is refused rather than solved without it."""
    refuse_discovered_torque(spec)
    return reference_cam_drop(rig, spec, law, chain, t_end, method, step)


def channels(data: dict[str, np.ndarray], rig: Rig, spec: ModelSpec, info: dict) -> dict[str, np.ndarray]:
    return shaft_channels(data, "cam_angle")


def default_step(rig: Rig) -> float:
    return P.CAM_STEP


#: Integration steps of the cam drop's fits (s): the experiment's 1e-5 s is sized for the
#: accuracy of studies; against a 2.5e-6 s solve a 35 ms drop is within 0.06 mrad at 2e-5 s
#: (massless spring: the stick band at the release sets the error) and within 1e-10 rad at
#: 4.2e-5 s (lumped chains), far below the camera's 2 mrad, at half and a quarter of the cost.
CAM_FIT_STEP = {"massless": 2e-5, "lumped": 4.2e-5}


def fit_step(rig: Rig, spring_kind: str) -> float | None:
    """Step (s) of the cam drop's fits. The ANCF spring's is its stability-bounded step
    (:meth:`AncfOptions.stable_step`: 4.3e-6 s for a 1 kg spring, 1.7x the studies' 2.5e-6 s,
    within 0.01 mrad of it)."""
    if spring_kind == "ancf":
        return AncfOptions().stable_step(rig.closing_spring)
    return CAM_FIT_STEP.get(spring_kind)


def figures_of_merit(result: SimulationResult, rig: Rig) -> dict:
    """``cam_angle_end_rad``: cam angle at the end; ``peak_shaft_velocity_rad_s``."""
    return {"cam_angle_end_rad": float(result.channels["cam_angle"][-1]),
            "peak_shaft_velocity_rad_s": float(np.max(np.abs(result.channels["shaft_velocity"])))}


def spring_signature(rig: Rig, measurement: Measurement, model_curve: np.ndarray, residual: np.ndarray, sigma: float) -> dict:
    """The closing spring's surge frequency (Hz) and how the residual follows the travel."""
    s = rig.closing_spring
    y = model_curve - residual  # the measured channel (residual = model - measured)
    travel = y - y[0]
    return {"spring_surge_frequency_hz": fundamental(s.stiffness, s.mass, "exact") / (2 * math.pi),
            "residual_travel_correlation": float(np.corrcoef(travel, residual)[0, 1]) if np.std(residual) > 0 else 0.0}


CAM_DROP = Experiment(
    name="cam_drop", description="cam released and turned by the closing springs (paper section 3, eq. 7-13)",
    measured_channel="cam_angle", unit="rad", sections=("cam", "closing_spring"), read_sections=read_cam_and_spring,
    provides=("journal", "closing_spring", "shaft_torque"),
    # model-form uncertainty: a drive's dissipation at speed is shared between the shaft's viscous
    # friction and the closing springs' internal damping; a record at the noise may hold either
    form_alternatives=("viscous_friction", "spring_damping"),
    # high-speed camera at 12000 frames/s, sigma 2 mrad (the example data's sensor)
    sample_rate=12000.0, noise_sigma=2e-3, default_duration=P.CAM_T_END, max_duration=1.0,
    # a drop shorter than 2 ms barely moves the cam; cam angles beyond two turns are degrees
    min_duration=2e-3, max_magnitude=4 * math.pi, unit_hint=": is it in degrees? cam_angle must be in rad",
    build=build, channels=channels, step=default_step, figures_of_merit=figures_of_merit,
    signature=spring_signature, initial_angle_field="cam.initial_angle",
    figure_units=(("cam_angle_end_rad", "rad"), ("peak_shaft_velocity_rad_s", "rad/s")), summary=cam_drop_summary,
    # fits run the compiled path (ode_model) where a C compiler works; on Exudyn (no compiler) they use the Python
    # friction function: a 35 ms massless drop takes 0.15 s with it, 0.6-1.1 s with Exudyn's symbolic one (the
    # symbolic expression of the spring's pull does not share subexpressions); "auto" is that Python function,
    # with the ANCF spring (always on Exudyn) its law compiled where a C compiler works: the same trajectory,
    # about half the processor time of a 35 ms drop (builders.ancf)
    fit_step=fit_step, fit_user_function="auto",
    ode_model=OdeModel("cam_drop", prepare_cam_drop, cam_drop_equations), reference=reference,
    sensor="camera", random_rig=cam_drop_random_rig)

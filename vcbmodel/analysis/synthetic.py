"""Synthetic measurements: a documented truth model plus sensor noise.

The paper's raw data are unpublished; every "measured" curve this project plots is made
here and labelled synthetic. Noise levels are those of the paper's sensors as the example
data describe them: potentiometer at 1 kHz with sigma 0.5 mrad (pendulum), high-speed
camera at 12000 frames/s with sigma 2 mrad (cam drop).
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from ..experiments import experiment_of
from ..experiments.loading import load_rig
from ..experiments.simulation import output_times, simulate
from ..records.measurement import Measurement, write_measurement


def synthetic_measurement(rig, effects, values, *, spring_model=None, sigma=None, seed=0, t_end=None,
                          path="synthetic.csv", ancf_elements=None) -> Measurement:
    """Simulate the truth and add white Gaussian noise of ``sigma`` (default: the experiment's
    usual sensor; rad, or m for a closing) at the sensor's rate."""
    record = experiment_of(rig.experiment)
    t = output_times(rig, t_end or record.default_duration)
    truth = simulate(rig, effects, values, spring_model=spring_model, sample_times=t, ancf_elements=ancf_elements)
    sigma = record.noise_sigma if sigma is None else sigma
    noisy = truth.measured + np.random.default_rng(seed).normal(0.0, sigma, t.size)
    return Measurement(path=str(path), t=t, channels={record.measured_channel: noisy},
                       comments=(f"SYNTHETIC: truth effects {','.join(effects)}, spring model "
                                 f"{truth.spring_model.label}, noise sigma {sigma:g} {record.unit}, seed {seed}",))


def write_rig(rig_dict: dict, path: str | Path) -> None:
    Path(path).write_text(json.dumps(rig_dict, indent=2) + "\n")


#: Hidden-effect cases: (experiment, starting effects, truth effects, truth spring model or None).
#: The first seven mirror the kinds of the example data; ``cam_visc`` goes beyond them.
CASES = {
    "pend_none": ("pendulum", ("coulomb_friction",), ("coulomb_friction",)),
    "pend_coul": ("pendulum", ("viscous_friction",), ("coulomb_friction", "viscous_friction")),
    "pend_visc": ("pendulum", ("coulomb_friction",), ("coulomb_friction", "viscous_friction")),
    "pend_strib": ("pendulum", ("coulomb_friction", "viscous_friction"),
                   ("coulomb_friction", "stribeck", "viscous_friction")),
    "cam_none": ("cam_drop", ("coulomb_friction",), ("coulomb_friction",)),
    "cam_coul": ("cam_drop", (), ("coulomb_friction",)),
    "cam_mass": ("cam_drop", ("coulomb_friction",), ("coulomb_friction", "spring_mass")),
    "cam_visc": ("cam_drop", ("coulomb_friction",), ("coulomb_friction", "viscous_friction")),
}


def case_answer(case: str) -> str | None:
    _, start, truth = CASES[case]
    missing = [e for e in truth if e not in start]
    return missing[0] if missing else None


def random_case(case: str, seed: int, folder: str | Path, t_end: float | None = None) -> tuple[Path, Path, dict]:
    """A randomised rig + synthetic measurement with one hidden effect (or none).

    Geometry and friction are drawn from ranges around the reference rigs (the ranges of
    the example data); the rig gives the friction values a starting model would know (cam:
    mu_k when Coulomb friction is in the starting model) and nothing else. Returns
    (rig path, measurement path, truth dict).
    """
    rng = np.random.default_rng(seed)
    experiment, start, truth_effects = CASES[case]
    folder = Path(folder)
    friction = {"mu_k": rng.uniform(0.09, 0.16), "stick_velocity": 1e-3,
                "stribeck_velocity": rng.uniform(0.09, 0.15)}
    friction["mu_s"] = friction["mu_k"] * rng.uniform(1.8, 2.0)
    spring_model = None
    record = experiment_of(experiment)
    rig = record.random_rig(rng, friction, start, "synthetic")
    if "spring_mass" in truth_effects and record.has_closing_spring:
        spring_model = f"lumped-{rng.integers(1, 4)}"
    rig["model"] = {"effects": list(start), "spring_model": "massless"}
    rig["name"] = f"{case}-{seed}"
    rig_path = folder / f"{case}-{seed}.rig.json"
    write_rig(rig, rig_path)
    meas_path = folder / f"{case}-{seed}.csv"
    meas = synthetic_measurement(load_rig(rig_path), truth_effects, friction, spring_model=spring_model,
                                 seed=seed, path=meas_path, t_end=t_end)
    write_measurement(meas, meas_path)
    return rig_path, meas_path, {"answer": case_answer(case), "truth_effects": list(truth_effects),
                                 "truth_friction": friction, "truth_spring_model": spring_model or "massless"}

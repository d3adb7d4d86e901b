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

from .rig import CHANNEL_OF_EXPERIMENT, Measurement
from .runner import simulate
from .sampling import output_times

NOISE_SIGMA = {"pendulum": 0.5e-3, "cam_drop": 2e-3}  # rad


def synthetic_measurement(rig, effects, values, *, spring_model=None, sigma=None, seed=0, t_end=None,
                          path="synthetic.csv") -> Measurement:
    """Simulate the truth and add white Gaussian noise of ``sigma`` rad."""
    t_end = t_end or (6.0 if rig.experiment == "pendulum" else 0.035)
    t = output_times(rig, t_end)
    truth = simulate(rig, effects, values, spring_model=spring_model, sample_times=t)
    sigma = NOISE_SIGMA[rig.experiment] if sigma is None else sigma
    noisy = truth.angle + np.random.default_rng(seed).normal(0.0, sigma, t.size)
    name = CHANNEL_OF_EXPERIMENT[rig.experiment]
    return Measurement(path=str(path), t=t, channels={name: noisy},
                       comments=(f"SYNTHETIC: truth effects {','.join(effects)}, spring model "
                                 f"{truth.spec.spring_model}, noise sigma {sigma:g} rad, seed {seed}",))


def write_measurement(measurement, path):
    path = Path(path)
    names = list(measurement.channels)
    lines = [f"# {c}" for c in measurement.comments] + ["t," + ",".join(names)]
    cols = [measurement.channels[n] for n in names]
    for i, t in enumerate(measurement.t):
        lines.append(f"{t:.7f}," + ",".join(f"{c[i]:.7f}" for c in cols))
    path.write_text("\n".join(lines) + "\n")


def write_rig(rig_dict, path):
    Path(path).write_text(json.dumps(rig_dict, indent=2) + "\n")

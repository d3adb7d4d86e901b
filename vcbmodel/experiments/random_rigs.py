"""Randomised rigs of each experiment kind, for synthetic records whose truth is known (the
diagnosis studies, :mod:`vcbmodel.analysis.synthetic` and :mod:`vcbmodel.analysis.realistic`).

Each ``*_random_rig(rng, friction, start, variant)`` returns a rig file's JSON object drawn
around the reference rigs (the ranges of the example data) and sets the experiment's typical
viscous coefficient in ``friction`` (the truth's friction values, drawn by the caller). The rig
gives the friction values a starting model would know (``start``: its effects) and nothing
else. ``variant``: ``synthetic`` (the clean-record study), ``realistic`` (the realism study) or
``small`` (a small laboratory pendulum). The order of the random draws is part of each study's
seeds: keep it.
"""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np


def pendulum_random_rig(rng: np.random.Generator, friction: dict[str, float], start: Sequence[str], variant: str = "synthetic") -> dict:
    """A pendulum rig like the paper's (40-60 kg at 0.19-0.235 m, let go from 10 or 15 deg), or
    with ``variant="small"`` a small laboratory pendulum (0.3-0.8 kg bob on a 0.1-0.2 m rod, a
    4-8 mm shaft in plain bearings, let go from 15-25 deg: it swings for tens of seconds; its
    friction is scaled to a light plain bearing)."""
    if variant == "small":
        m, L = float(rng.uniform(0.3, 0.8)), float(rng.uniform(0.1, 0.2))
        rig = {"format": "vcb-rig/1", "experiment": "pendulum", "gravity": 9.81,
               "shaft": {"radius": float(rng.uniform(0.002, 0.004))},
               "pendulum": {"mass": m, "inertia": m * L**2 * float(rng.uniform(1.05, 1.3)), "com_distance": L,
                            "initial_angle": float(np.radians(rng.uniform(15.0, 25.0))), "initial_velocity": 0.0},
               "friction": {}}
        p = rig["pendulum"]
        # damping ratio 0.3-0.6 %: Cv = 2 zeta sqrt(I M g L)
        friction["viscous"] = float(2 * rng.uniform(0.003, 0.006) * math.sqrt(p["inertia"] * p["mass"] * 9.81
                                                                               * p["com_distance"]))
        friction["mu_k"] *= 0.3  # plain bearing, light load
        friction["mu_s"] *= 0.3
        friction["stribeck_velocity"] *= 3
        return rig
    friction["viscous"] = float(rng.uniform(0.5, 0.75))
    rig = {"format": "vcb-rig/1", "experiment": "pendulum", "gravity": 9.81,
           "shaft": {"radius": float(rng.uniform(0.015, 0.025))},
           "pendulum": {"mass": float(rng.uniform(40, 60)), "inertia": float(rng.uniform(2.0, 3.0)),
                        "com_distance": float(rng.uniform(0.19, 0.235)),
                        "initial_angle": float(np.radians(rng.choice([10.0, 15.0]))), "initial_velocity": 0.0},
           "friction": {}}
    p = rig["pendulum"]
    # the inertia is at least the weight's as a point mass (the realism study keeps 2 % above it)
    p["inertia"] = max(p["inertia"], (1.02 if variant == "realistic" else 1.0) * p["mass"] * p["com_distance"] ** 2)
    return rig


def cam_drop_random_rig(rng: np.random.Generator, friction: dict[str, float], start: Sequence[str], variant: str = "synthetic") -> dict:
    """A cam drop rig around the reference cam (4-7 kg cam, arm 98-106 mm) with two closing
    springs of 0.9-1.15 kg; the rig knows mu_k when Coulomb friction is in the starting model."""
    if variant not in ("synthetic", "realistic"):
        raise ValueError(f"no {variant!r} variant of a cam drop rig")
    friction["viscous"] = float(rng.uniform(0.03, 0.08))
    rig = {"format": "vcb-rig/1", "experiment": "cam_drop", "gravity": 9.81,
           "shaft": {"radius": float(rng.uniform(0.018, 0.025))},
           "cam": {"mass": float(rng.uniform(4.0, 7.0)), "inertia_com": float(rng.uniform(0.045, 0.06)),
                   "com_distance": float(rng.uniform(0.02, 0.03)), "com_angle": float(rng.uniform(0.1, 1.0)),
                   "pivot": [0.4445, 0.0], "arm_length": float(rng.uniform(0.098, 0.106)),
                   "initial_angle": float(rng.uniform(0.14, 0.23)), "initial_velocity": 0.0},
           "closing_spring": {"count": 2, "stiffness": 24230.0, "mass": float(rng.uniform(0.9, 1.15)),
                              "free_length": 0.3, "anchor": [0.0, 0.0]},
           "friction": {}}
    if "coulomb_friction" in start:
        rig["friction"] = {"mu_k": friction["mu_k"], "stick_velocity": 1e-3}
    return rig

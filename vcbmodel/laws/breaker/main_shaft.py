"""The main shaft that carries the pole levers: its segments' twist between the levers and its
torsional modes (rig section ``breaker.main_shaft``; absent: a rigid shaft). Units in each docstring."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..friction import NumericOps
from ..mechanics import shaft_torsional_stiffness
from ..types import Ops, Scalar


@dataclass(frozen=True)
class MainShaft:
    """The main shaft that carries the pole levers (rig section ``breaker.main_shaft``): pole
    levers 1..n along it in pole order, ``pole_pitch`` (m) apart; a round shaft of ``diameter``
    (m) with a ``bore`` (m, 0: solid) and ``shear_modulus`` (Pa), so each segment between two
    levers has the torsional stiffness :func:`segment_stiffness` (N m/rad) and the torsional
    ``damping`` (N m s/rad); each pole lever has ``lever_inertia`` (kg m^2, its share of the
    follower's inertia); the lever of pole ``drive_pole`` (1..n) sits at the drive, rigid with the
    roller's follower lever. Absent (None): a rigid shaft, every rod on the follower."""

    pole_pitch: float  # m
    diameter: float  # m
    bore: float  # m
    shear_modulus: float  # Pa
    damping: float  # N m s/rad per segment
    lever_inertia: float  # kg m^2 per pole lever
    drive_pole: int  # 1..poles.count


def segment_stiffness(shaft: MainShaft) -> float:
    """Torsional stiffness (N m/rad) of one shaft segment between adjacent pole levers:
    G pi (d^4 - d_i^4) / 32 / pole_pitch (:func:`vcbmodel.laws.mechanics.shaft_torsional_stiffness`)."""
    return shaft_torsional_stiffness(shaft.diameter, shaft.shear_modulus, shaft.bore) / shaft.pole_pitch


def segment_torque(a_j: Scalar, a_next: Scalar, rate_j: Scalar, rate_next: Scalar, stiffness: Scalar, damping: Scalar,
                   ops: Ops = NumericOps) -> Scalar:
    """Torque (N m) of the shaft segment between lever j and lever j+1 (angles rad, speeds rad/s):
    T = k (a_j - a_{j+1}) + c (a_j' - a_{j+1}') with the segment's stiffness k (N m/rad) and
    damping c (N m s/rad); it acts +T on lever j+1 and -T on lever j. Linear: ``ops`` is not
    needed, kept for the laws' signature."""
    return stiffness * (a_j - a_next) + damping * (rate_j - rate_next)


def torsional_frequencies(shaft: MainShaft, poles, output_arm: float) -> np.ndarray:
    """Natural frequencies (Hz, ascending) of the pole levers twisting the shaft with the drive
    lever held (the cam, the springs and the roller hold it): each free lever with its inertia and
    its pole's mass reflected through a stiff rod (moving_mass output_arm^2), the segments'
    stiffness between them. An estimate: the rods' and wipe springs' own compliance is left out."""
    n, drive = poles.count, shaft.drive_pole - 1
    k = segment_stiffness(shaft)
    stiff = np.zeros((n, n))
    for j in range(n - 1):
        stiff[j:j + 2, j:j + 2] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    free = [j for j in range(n) if j != drive]
    if not free:
        return np.zeros(0)
    inertia = shaft.lever_inertia + poles.moving_mass * output_arm**2
    w2 = np.linalg.eigvalsh(stiff[np.ix_(free, free)] / inertia)
    return np.sqrt(np.maximum(w2, 0.0)) / (2.0 * math.pi)

"""The closing spring as a 2-D ANCF cable continuum (Exudyn ``ObjectANCFCable2D``).

Axial stiffness EA = k0 L_free, mass per length m0 / L_free, and the equivalent bending
stiffness of a helical spring (:func:`vcbmodel.laws.coil.coil_bending_stiffness`). ``count``
springs in one plane are one cable with count times EA, EI and mass.

Preload: the nodes start at the charged (stretched) positions O -> B0 while each element's
reference length is L_free / N, so the axial strain |r'| - 1 gives the spring force
k0 (|OB0| - L_free) from the start (exudyn-notes, "ANCF spring").

The cable's ends are tied to the anchor O and to the cam pin B by stiff, critically damped
penalty springs instead of joints: the model has no constraints, so Exudyn's explicit RK4 is
exact for it (its constraint elimination is wrong for mass-coupled ANCF coordinates,
exudyn-notes). The friction user function reads the end node's state at the current
Runge-Kutta stage and takes the penalty spring's force as the spring's pull on B.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from .. import parameters as P
from ..laws.coil import coil_bending_stiffness
from ..laws.mechanics import cam_pin
from .core import ExudynModel, add_cam_body, add_cam_friction, exudyn_modules


def _add_cable(mbs, it, start, end, free_length, elements, EA, rhoA, EI):
    """Nodes from start to end (stretched), element reference length free_length / N."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    direction = end - start
    stretch = np.linalg.norm(direction) / free_length
    slope = direction / np.linalg.norm(direction) * stretch
    nodes = [mbs.AddNode(it.NodePoint2DSlope1(referenceCoordinates=[*(start + direction * i / elements), *slope]))
             for i in range(elements + 1)]
    cables = [mbs.AddObject(it.ObjectANCFCable2D(nodeNumbers=[nodes[i], nodes[i + 1]], length=free_length / elements,
                                                 massPerLength=rhoA, axialStiffness=EA,
                                                 bendingStiffness=EI))
              for i in range(elements)]
    return nodes, cables


def build_cam_drop_ancf(rig, law, user_function="auto", elements=None, extra_loads=None):
    """Cam drop with the closing springs as one ANCF cable (see module docstring)."""
    exu, it = exudyn_modules()
    cam, spring, g = rig.cam, rig.closing_spring, rig.gravity
    N = elements or P.ANCF_ELEMENTS
    c = spring.count
    EA, rhoA = c * spring.stiffness * spring.free_length, c * spring.mass / spring.free_length
    EI = c * coil_bending_stiffness(spring)
    model = ExudynModel()
    mbs = model.mbs
    body = model.cam_body = add_cam_body(model, rig)
    B0 = cam_pin(cam.initial_angle, cam)
    nodes, _ = _add_cable(mbs, it, spring.anchor, B0, spring.free_length, N, EA, rhoA, EI)
    end_mass = rhoA * spring.free_length / N / 2
    k_pen = c * P.ANCF_PENALTY_STIFFNESS
    d_pen = 2 * math.sqrt(k_pen * end_mass)
    mFirst = mbs.AddMarker(it.MarkerNodePosition(nodeNumber=nodes[0]))
    mLast = mbs.AddMarker(it.MarkerNodePosition(nodeNumber=nodes[-1]))
    for pair in ((body.mAnchor, mFirst), (mLast, body.mPin)):
        mbs.AddObject(it.ObjectConnectorCartesianSpringDamper(markerNumbers=list(pair), stiffness=[k_pen, k_pen, 0.0],
                                                              damping=[d_pen, d_pen, 0.0]))
    if spring.weight:
        for i, n in enumerate(nodes):
            share = (1.0 if 0 < i < N else 0.5) * rhoA * spring.free_length / N
            m = mbs.AddMarker(it.MarkerNodePosition(nodeNumber=n))
            mbs.AddLoad(it.LoadForceVector(markerNumber=m, loadVector=[0.0, -share * g, 0.0]))
    for i, n in enumerate(nodes[1:-1], start=1):
        model.add_sensor(f"ancf_node_{i}", n, "Position")
    nLast = nodes[-1]
    position, velocity = exu.OutputVariableType.Position, exu.OutputVariableType.Velocity

    def pin_force(theta, omega, ops):
        px, py = mbs.GetNodeOutput(nLast, position)[:2]
        vx, vy = mbs.GetNodeOutput(nLast, velocity)[:2]
        bx, by = cam_pin(theta, cam)
        # velocity of B: omega e_z x (B - A)
        bvx, bvy = -omega * (by - cam.pivot[1]), omega * (bx - cam.pivot[0])
        return k_pen * (px - bx) + d_pen * (vx - bvx), k_pen * (py - by) + d_pen * (vy - bvy)

    if user_function == "symbolic":
        raise ValueError("the ANCF spring's friction needs the Python user function")
    add_cam_friction(model, rig, law, body, pin_force, "python", extra_loads)
    return model


def ancf_modes(k0, m0, free_length, elements, preload=0.0, count=6):
    """Fixed-fixed natural frequencies (Hz) of one cable along x: (axial, lateral) lists.

    ``preload`` (N) stretches it to free_length + preload / k0. Both end nodes' positions are
    held (``constrainedCoordinates``); modes are sorted into axial and lateral by where the
    eigenvector's position coordinates move most.
    """
    exu, it = exudyn_modules()
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()

    spring = SimpleNamespace(stiffness=k0, free_length=free_length, wire_diameter=None, coil_diameter=None,
                             shear_modulus=None, active_coils=None)

    length = free_length + preload / k0
    nodes, _ = _add_cable(mbs, it, (0.0, 0.0), (length, 0.0), free_length, elements, k0 * free_length,
                          m0 / free_length, coil_bending_stiffness(spring))
    mbs.Assemble()
    fixed = [0, 1, 4 * elements, 4 * elements + 1]  # x, y of the first and the last node
    n_dof = 4 * (elements + 1) - len(fixed)
    values, vectors = mbs.ComputeODE2Eigenvalues(constrainedCoordinates=fixed, numberOfEigenvalues=n_dof,
                                                  useSparseSolver=False, convert2Frequencies=True)
    free = [i for i in range(4 * (elements + 1)) if i not in fixed]
    axial, lateral = [], []
    for f, vec in zip(values, np.asarray(vectors).T):
        full = np.zeros(4 * (elements + 1))
        full[free] = vec[:len(free)] if len(vec) >= len(free) else 0
        ux, uy = full[0::4], full[1::4]
        (axial if np.sum(ux**2) > np.sum(uy**2) else lateral).append(float(f))
    SC.Reset()
    return axial[:count], lateral[:count]


def ancf_fixed_fixed_frequencies(k0, m0, free_length, elements, count=3, preload=0.0):
    """The first ``count`` axial fixed-fixed frequencies (Hz)."""
    return ancf_modes(k0, m0, free_length, elements, preload, count)[0][:count]

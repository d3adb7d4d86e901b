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

The ties' compliance moves the cam angle by O(1/k): 1e7 -> 1e8 N/m by 8.4 mrad rms, 1e8 -> 1e9
by 0.73 mrad (0.34 kg spring). The ties start preloaded (the end nodes sit inside them by
their static stretch, so they carry the spring force from t = 0 instead of jolting the cable)
and :func:`vcbmodel.experiments.simulation.simulate_rigid_ties` extrapolates two tie
stiffnesses to infinity (value = value_inf + c / k): against exact constraint ties solved by
generalized alpha (measured once, extrapolated in the step) the result is within 0.001 mrad.
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from types import SimpleNamespace
from typing import TYPE_CHECKING

import numpy as np

from .. import parameters as P
from ..laws.coil import coil_bending_stiffness
from ..laws.mechanics import cam_pin
from ..laws.springs import kelvin_voigt_time
from ..compiled import compiler_works
from ..compiled.function import compiled_function
from .core import (ExudynModel, add_cam_body, add_cam_friction, add_discovered_torque, add_friction_connector,
                   cam_friction_inputs, cam_friction_torque)
from .exudyn_loader import exudyn_modules

if TYPE_CHECKING:
    from ..laws.friction import FrictionLaw
    from ..rig.data import ClosingSpring, Rig


def _add_cable(mbs, it, start, end, free_length, elements, EA, rhoA, EI, beta=0.0):
    """Nodes from start to end (stretched), element reference length free_length / N; ``beta`` (s):
    Kelvin-Voigt damping, axial EA_t = beta EA and bending EI_t = beta EI."""
    start, end = np.asarray(start, float), np.asarray(end, float)
    direction = end - start
    stretch = np.linalg.norm(direction) / free_length
    slope = direction / np.linalg.norm(direction) * stretch
    nodes = [mbs.AddNode(it.NodePoint2DSlope1(referenceCoordinates=[*(start + direction * i / elements), *slope]))
             for i in range(elements + 1)]
    cables = [mbs.AddObject(it.ObjectANCFCable2D(nodeNumbers=[nodes[i], nodes[i + 1]], length=free_length / elements,
                                                 massPerLength=rhoA, axialStiffness=EA,
                                                 bendingStiffness=EI, axialDamping=beta * EA,
                                                 bendingDamping=beta * EI))
              for i in range(elements)]
    return nodes, cables


@dataclass(frozen=True)
class AncfOptions:
    """How the ANCF spring is built: ``elements``; ``penalty_stiffness`` of each end tie per
    spring (N/m); ``preload_ties`` (module docstring); ``bending_stiffness`` EI of one spring
    (N m^2, default from the coil, :func:`vcbmodel.laws.coil.coil_bending_stiffness`)."""

    elements: int = P.ANCF_ELEMENTS
    penalty_stiffness: float = P.ANCF_PENALTY_STIFFNESS
    preload_ties: bool = True
    bending_stiffness: float | None = None

    @classmethod
    def of(cls, value: AncfOptions | int | None) -> AncfOptions:
        """From None (defaults), an element count or an AncfOptions."""
        if isinstance(value, AncfOptions):
            return value
        return cls() if value is None else cls(elements=int(value))

    def step(self, spring: ClosingSpring | None = None) -> float:
        """RK4 step (s) for studies: ANCF_STEP up to ANCF_ELEMENTS elements and the default tie
        stiffness, shorter in proportion to the elements above and by sqrt(k_default / k) for
        stiffer ties, and never above :meth:`stable_step` for ``spring`` (a rig's
        ``closing_spring``; a light spring's ties are faster)."""
        accurate = (P.ANCF_STEP * min(1.0, P.ANCF_ELEMENTS / self.elements)
                    * min(1.0, math.sqrt(P.ANCF_PENALTY_STIFFNESS / self.penalty_stiffness)))
        return accurate if spring is None else min(accurate, self.stable_step(spring))

    def stable_step(self, spring: ClosingSpring) -> float:
        """The longest step (s) kept well inside RK4's stability limit, set by the ties' damped
        fast mode: ANCF_STEP_FACTOR sqrt(m_end / k_tie), m_end = m0 / (2 N) per spring (the
        count cancels). Fits use it: within 0.01 mrad of a step half as long."""
        end_mass = spring.mass / (2 * self.elements)
        return P.ANCF_STEP_FACTOR * math.sqrt(end_mass / self.penalty_stiffness)


def build_cam_drop_ancf(rig: Rig, law: FrictionLaw, user_function: str = "auto", options: AncfOptions | int | None = None,
                        extra_loads: Callable | None = None, discovered: tuple = (), spring_damping: float = 0.0) -> ExudynModel:
    """Cam drop with the closing springs as one ANCF cable (see module docstring);
    ``options``: :class:`AncfOptions` (or an element count); ``discovered``: a discovered torque on
    the cam shaft (:func:`vcbmodel.builders.core.add_discovered_torque`); ``spring_damping``: the first
    surge mode's damping ratio of a Kelvin-Voigt cable (:func:`vcbmodel.laws.springs.kelvin_voigt_time`)."""
    _, it = exudyn_modules()
    opt = AncfOptions.of(options)
    cam, spring, g = rig.cam, rig.closing_spring, rig.gravity
    N = opt.elements
    c = spring.count
    EA, rhoA = c * spring.stiffness * spring.free_length, c * spring.mass / spring.free_length
    EI = c * (coil_bending_stiffness(spring) if opt.bending_stiffness is None else opt.bending_stiffness)
    model = ExudynModel()
    mbs = model.mbs
    body = model.cam_body = add_cam_body(model, rig)
    k_pen = c * opt.penalty_stiffness
    start, end = np.asarray(spring.anchor, float), np.asarray(cam_pin(cam.initial_angle, cam), float)
    if opt.preload_ties:  # each tie stretched by delta: k_pen delta = EA ((|OB0| - 2 delta) / L_free - 1)
        length = np.linalg.norm(end - start)
        delta = (EA / spring.free_length) * (length - spring.free_length) / (k_pen + 2 * EA / spring.free_length)
        u = (end - start) / length
        start, end = start + delta * u, end - delta * u
    beta = kelvin_voigt_time(spring_damping, spring.stiffness, spring.mass) if spring_damping else 0.0
    nodes, _ = _add_cable(mbs, it, start, end, spring.free_length, N, EA, rhoA, EI, beta)
    end_mass = rhoA * spring.free_length / N / 2
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
    read_end = node_state_of(mbs, nodes[-1])
    if user_function == "symbolic":
        raise ValueError("the ANCF spring's friction needs the Python user function")
    inputs = cam_friction_inputs(rig, law, body, discovered) | {"tie_stiffness": k_pen, "tie_damping": d_pen}
    if user_function == "auto" and compiler_works():
        add_compiled_tie_friction(model, body, inputs, read_end, extra_loads, (*end, 0.0, 0.0))
        return model

    def pin_force(theta, omega, ops):
        return tie_pull(theta, omega, read_end(), inputs, ops)

    add_cam_friction(model, rig, law, body, pin_force, "python", extra_loads, discovered)
    return model


def node_state_of(mbs, node) -> Callable[[], tuple]:
    """A function returning a 2-D node's (x, y, vx, vy) (m, m/s) at the current Runge-Kutta stage."""
    exu, _ = exudyn_modules()
    position, velocity = exu.OutputVariableType.Position, exu.OutputVariableType.Velocity

    def read():  # lists of floats: unpacked faster than numpy arrays, the same numbers
        p, v = mbs.GetNodeOutput(node, position).tolist(), mbs.GetNodeOutput(node, velocity).tolist()
        return p[0], p[1], v[0], v[1]

    return read


def tie_pull(theta, omega, end, inputs: dict, ops):
    """Pull (N) of the cable's end node ``end`` = (x, y, vx, vy) (m, m/s) on pin B through the
    penalty tie: k (P - B) + d (v_P - v_B), v_B = omega e_z x (B - A); ``inputs``: the cam and the
    tie's ``tie_stiffness`` k (N/m) and ``tie_damping`` d (N s/m)."""
    px, py, vx, vy = end
    cam, k, d = inputs["cam"], inputs["tie_stiffness"], inputs["tie_damping"]
    bx, by = cam_pin(theta, cam, ops)
    bvx, bvy = -omega * (by - cam.pivot[1]), omega * (bx - cam.pivot[0])
    return k * (px - bx) + d * (vx - bvx), k * (py - by) + d * (vy - bvy)


def tie_friction_torque(args, inputs: dict, ops):
    """The cam shaft's friction torque T_f (N m) at ``args`` = (t, theta, omega, x, y, vx, vy of the
    cable's end node[, T_e, Ex, Ey]): :func:`tie_pull` into
    :func:`~vcbmodel.builders.core.cam_friction_torque` (the law of the compiled friction callback)."""
    t, theta, omega = args[:3]
    fx, fy = tie_pull(theta, omega, args[3:7], inputs, ops)
    return cam_friction_torque((t, theta, omega, fx, fy, *args[7:]), inputs, ops)


def add_compiled_tie_friction(model, body, inputs: dict, read_end: Callable, extra_loads: Callable | None,
                              end0: tuple) -> None:
    """The cam's friction connector whose Python user function reads the end node (``read_end``)
    and the ``extra_loads`` and evaluates :func:`tie_friction_torque` compiled
    (:func:`vcbmodel.compiled.function.compiled_function`; ``end0``: the trace point's node state)."""
    cam = inputs["cam"]
    start = (0.0, cam.initial_angle, cam.initial_velocity, *end0)
    if extra_loads is None:
        value = compiled_function("ancf_tie_friction", tie_friction_torque, inputs, start)

        def friction_of_state(t, theta, omega, ops):
            return value(t, theta, omega, *read_end())
    else:
        value = compiled_function("ancf_tie_friction", tie_friction_torque, inputs, (*start, 0.0, 0.0, 0.0))

        def friction_of_state(t, theta, omega, ops):
            return value(t, theta, omega, *read_end(), *extra_loads(t, theta, omega))

    add_discovered_torque(model, body.shaft, inputs["discovered"], "python")
    add_friction_connector(model, body.shaft, friction_of_state, "python")


def ancf_modes(k0: float, m0: float, free_length: float, elements: int, preload: float = 0.0, count: int = 6) -> tuple[list[float], list[float]]:
    """Fixed-fixed natural frequencies (Hz) of one cable along x: (axial, lateral) lists.

    ``preload`` (N) stretches it to free_length + preload / k0. Both end nodes' positions are
    held (``constrainedCoordinates``); modes are sorted into axial and lateral by where the
    eigenvector's position coordinates move most.
    """
    exu, it = exudyn_modules()
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()

    spring = SimpleNamespace(stiffness=k0, mass=m0, free_length=free_length, wire_diameter=None, coil_diameter=None,
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


def ancf_fixed_fixed_frequencies(k0: float, m0: float, free_length: float, elements: int, count: int = 3, preload: float = 0.0) -> list[float]:
    """The first ``count`` axial fixed-fixed frequencies (Hz)."""
    return ancf_modes(k0, m0, free_length, elements, preload, count)[0][:count]

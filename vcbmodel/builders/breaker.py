"""Exudyn model of the whole breaker's closing (paper section 4, Fig. 11-12).

Coordinates (all minimal, for explicit RK4 without constraints): the cam angle (the cam-drop
model with its closing springs and shaft friction, :func:`.cam_drop.build_cam_drop`), the
follower angle (``Node1D`` + ``ObjectRotationalMass1D`` at the follower pivot), and one
``Node1D`` + ``ObjectMass1D`` per pole sliding on its vertical guide (the translational
joint is the coordinate itself). The parts, each a function below, wrap the pure laws of
:class:`vcbmodel.laws.breaker.BreakerLaws`:

- :func:`add_follower`: the follower body and its output point F;
- :func:`add_cam_roller_contact`: ``ObjectGenericODE2`` on (cam, follower) whose force user
  function returns the contact's torques on both (the rig's contact law: Hertz point or line
  contact, Lankarani-Nikravesh or Hunt-Crossley damping);
- :func:`add_latch` (``LoadCoordinate`` on the cam with a time user function) and
  :func:`add_opening_spring` (a plain ``ObjectConnectorSpringDamper``);
- :func:`add_stops`: the closing end stop and the holding latch (optional rig sections
  ``breaker.end_stop``, ``breaker.hold_latch``), a coordinate connector on the cam angle;
- :func:`add_levers`: with a main shaft (rig section ``breaker.main_shaft``) each pole but the
  drive pole gets its own lever (``Node1D`` + ``ObjectRotationalMass1D`` at the follower pivot),
  the shaft's segments ``ObjectConnectorCoordinateSpringDamper`` between the levers' angles;
- :func:`add_poles`: push rods with wipe springs (``ObjectConnectorSpringDamper`` from the
  pole's lever's output point, F on a rigid shaft, to the pole pin), pole contacts (``ObjectConnectorCoordinateSpringDamper`` ground -> pole travel),
  bellows force minus weight (constant ``LoadCoordinate``);
- :func:`add_impact_latching`: each contact's impact speed (the damping's reference speed) is
  latched by a pre-step function from the state at the start of the step in which the
  contact begins; so is the holding latch's engagement (rig section ``breaker.hold_latch``).

The end stop's and the holding latch's forces also load the journal (they enter the shaft
friction's reaction with the roller's and the latch's, :meth:`BreakerLaws.cam_loads`).

The shaft friction also sees the roller force and the latch force (they load the journal): the
latch holds the cam with a force at its latch point (:meth:`BreakerLaws.latch_loads`), not with
a pure couple.
The follower's own weight is left out (a balanced main shaft).
"""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..laws.breaker import BreakerLaws, massless_pull, pin_weight_torque, push_rod_force
from ..laws.cycle import CycleLaws, closed_state
from .cam_drop import build_cam_drop
from .core import ExudynModel
from .exudyn_loader import exudyn_modules

if TYPE_CHECKING:
    from ..laws.friction import FrictionLaw
    from ..laws.springs import LumpedChain
    from ..model.effects import ModelSpec
    from ..rig.data import Rig
    from .ancf import AncfOptions


@dataclass
class Follower:
    """Handles of the follower: its angle node and the marker at its output point F."""

    node: int
    mOutput: int


def build_vcb_closing(rig: Rig, spec: ModelSpec, law: FrictionLaw, chain: LumpedChain | None = None, user_function: str = "auto",
                      ancf_elements: AncfOptions | int | None = None) -> ExudynModel:
    """The whole breaker in Exudyn (module docstring); returns the model with ``laws`` and
    ``initial`` (the static rest held by the latch) attached."""
    laws = BreakerLaws.of_rig(rig, spec)
    # every spring model starts from the massless springs' pull (a lumped chain starts stretched
    # along O-B in its static equilibrium, which pulls the same)
    pin_mass = chain.pin_mass if chain is not None else 0.0
    initial = laws.initial_state(massless_pull(rig.cam, rig.closing_spring),
                                 pin_weight_torque(rig.cam, rig.closing_spring, pin_mass, rig.gravity))
    cycle = CycleLaws(laws, initial.follower_angle)
    if cycle.commands.start_closed:
        initial = closed_state(laws, cycle, initial)
    impact = np.zeros(rig.breaker.poles.count + 1)  # [cam-roller, pole 1..n] impact speeds (m/s)
    engaged = [0.0]  # the holding latch's memory (1: engaged), when the rig has one
    memory = cycle.initial_memory()  # the cycle parts' memory (laws.cycle), when the rig has them
    follower_state = {}  # the follower's node and system, known once built (the cam's friction reads them)

    def extra_loads(t, theta, omega):
        # the roller and the latch load the cam: torque about A and force (both enter the shaft reaction)
        phi, phi_dot = follower_state["read"]()
        if not cycle.active:
            return laws.cam_loads(t, theta, omega, phi, phi_dot, initial.holding_torque, impact[0], engaged[0])
        loads = laws.cam_loads(t - cycle.close_at, theta, omega, phi, phi_dot, initial.holding_torque, impact[0], engaged[0])
        return collapsed_link_loads(laws, cycle, loads, t, memory, theta, omega, phi, phi_dot, impact[0])

    # the cam's friction: a Python user function (its loads read other bodies); with the ANCF spring and
    # "auto" its law is compiled (builders.ancf), with the other springs "auto" is the Python law
    uf = "python" if user_function == "symbolic" else user_function
    model = build_cam_drop(rig, law, spec.spring_model, chain, uf, extra_loads=extra_loads, ancf_elements=ancf_elements,
                           spring_damping=spec.spring_damping)
    follower = add_follower(model, rig.breaker.follower, initial.follower_angle, laws.follower_inertia)
    follower_state["read"] = node_state_reader(model.mbs, follower.node)
    cam_node = model.cam_body.shaft.node
    add_cam_roller_contact(model, laws, cam_node, follower.node, impact, cycle, memory)
    add_latch(model, laws, initial.holding_torque, cycle.close_at)
    if laws.has_stops:
        add_stops(model, laws, engaged)
    add_opening_spring(model, laws, follower)
    outputs = add_levers(model, laws, follower, initial.lever_angles)
    pole_nodes = add_poles(model, laws, outputs, initial.pole_travel, impact)
    also = None
    if cycle.active:
        add_cycle_parts(model, cycle, follower, pole_nodes, memory)
        also = cycle_memory_update(cycle, memory)
    add_impact_latching(model, laws, cam_node, follower.node, pole_nodes, impact, engaged, also)
    model.laws, model.initial = laws, initial
    return model


def collapsed_link_loads(laws: BreakerLaws, cycle: CycleLaws, loads: tuple, t, memory: list, theta, omega, phi, phi_dot,
                         impact_speed) -> tuple:
    """The cam's loads (torque N m, Fx N, Fy N) less the share of the roller's that a tripped
    trip-free link no longer carries (:meth:`CycleLaws.link`)."""
    if cycle.trip_latch is None:
        return loads
    keep = cycle.link(t, cycle.split(memory)[1])
    t_cam, _, fx, fy = laws.roller_loads(theta, omega, phi, phi_dot, impact_speed)
    return loads[0] - (1.0 - keep) * t_cam, loads[1] - (1.0 - keep) * fx, loads[2] - (1.0 - keep) * fy


def add_cycle_parts(model: ExudynModel, cycle: CycleLaws, follower: Follower, pole_nodes: list, memory: list) -> None:
    """The cycle parts the rig has (:class:`vcbmodel.laws.cycle.CycleLaws`): the trip latch's pawl,
    the opening dashpot and the open stop on the follower (``ObjectConnectorCoordinateSpringDamper``
    ground -> follower angle, its force :meth:`CycleLaws.follower_torque` negated), and each pole's
    Holm repulsion under the making current (a connector ground -> pole travel, like its contact)."""
    _, it = exudyn_modules()
    mbs = model.mbs
    mGround = model.cam_body.shaft.mGroundCoordinate
    if cycle.trip_latch is not None or cycle.dashpot is not None:
        mFollowerCoordinate = mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=follower.node, coordinate=0))

        def follower_uf(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, offset):
            return -cycle.follower_torque(t, deltaL, deltaL_t, cycle.split(memory)[1])

        mbs.AddObject(it.ObjectConnectorCoordinateSpringDamper(
            markerNumbers=[mGround, mFollowerCoordinate], springForceUserFunction=follower_uf,
            visualization=it.VObjectConnectorCoordinateSpringDamper(show=False)))
    if cycle.making is None:
        return
    for i, nPole in enumerate(pole_nodes):
        mPoleTravel = mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=nPole, coordinate=0))

        def repulsion_uf(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, offset, i=i):
            return cycle.repulsion(i, t, cycle.split(memory)[0], deltaL)

        mbs.AddObject(it.ObjectConnectorCoordinateSpringDamper(
            markerNumbers=[mGround, mPoleTravel], springForceUserFunction=repulsion_uf,
            visualization=it.VObjectConnectorCoordinateSpringDamper(show=False)))


def cycle_memory_update(cycle: CycleLaws, memory: list) -> Callable:
    """The pre-step's update of the cycle parts' memory (:meth:`CycleLaws.update`) from the state
    at the step's start: called with (t, follower angle, pole travels, roller penetration).
    Exudyn calls the pre-step function with the time at the step's end: the step's start is the
    previous call's time (0 at the first), the time the compiled path latches at."""
    start = [0.0]

    def update(t, phi, z, roller_penetration):
        memory[:] = cycle.update(memory, start[0], phi, z, roller_penetration)
        start[0] = t
    return update


def node_state_reader(mbs, node) -> Callable[[], tuple]:
    """A function returning (coordinate, velocity) of a 1-D node at the current RK stage."""
    exu, _ = exudyn_modules()
    coordinates, velocities = exu.OutputVariableType.Coordinates, exu.OutputVariableType.Coordinates_t
    return lambda: (mbs.GetNodeOutput(node, coordinates), mbs.GetNodeOutput(node, velocities))


def add_follower(model, f, phi0, inertia) -> Follower:
    """The follower (``inertia`` kg m^2 about its pivot: ``follower.inertia``, less the free pole
    levers' with a main shaft) at angle ``phi0`` (rad), recorded as ``follower_angle`` and
    ``follower_velocity``; F at ``output_arm``, ``output_angle``."""
    nFollower, mF = add_lever(model, f, phi0, inertia)
    model.add_sensor("follower_angle", nFollower, "Coordinates")
    model.add_sensor("follower_velocity", nFollower, "Coordinates_t")
    return Follower(nFollower, mF)


def add_lever(model, f, angle, inertia) -> tuple[int, int]:
    """A lever turning about the follower's pivot (``Node1D`` + ``ObjectRotationalMass1D``, handles
    nLever, oLever) at ``angle`` (rad) with ``inertia`` (kg m^2); returns its node and the marker
    mLeverOutput at its output point (``output_arm``, ``output_angle``)."""
    _, it = exudyn_modules()
    mbs = model.mbs
    nLever = mbs.AddNode(it.Node1D(referenceCoordinates=[0.0], initialCoordinates=[angle], initialVelocities=[0.0]))
    oLever = mbs.AddObject(it.ObjectRotationalMass1D(nodeNumber=nLever, inertia=inertia,
                                                     referencePosition=[f.pivot[0], f.pivot[1], 0.0]))
    mLeverOutput = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=oLever, localPosition=[
        f.output_arm * math.cos(f.output_angle), f.output_arm * math.sin(f.output_angle), 0.0]))
    return nLever, mLeverOutput


def add_levers(model: ExudynModel, laws: BreakerLaws, follower: Follower, angles: list) -> list[int]:
    """The pole levers on the main shaft (rig section ``breaker.main_shaft``): the drive pole's is
    the follower; each other pole's is its own lever (:func:`add_lever`, ``lever_inertia``) at its
    rest angle, recorded as ``pole_{j}_lever_angle`` and ``_velocity``; the segments between
    adjacent levers are ``ObjectConnectorCoordinateSpringDamper`` on their angles with the laws'
    stiffness and damping (:func:`vcbmodel.laws.breaker.segment_torque`: the connector's force
    k (a_{j+1} - a_j) + c (a_{j+1}' - a_j') acts on lever j+1 negated, on lever j as is). Returns
    each pole's output marker (the follower's for every pole on a rigid shaft)."""
    _, it = exudyn_modules()
    mbs, n = model.mbs, laws.b.poles.count
    if not laws.free_levers:
        return [follower.mOutput] * n
    nodes, outputs = [0] * n, [0] * n
    nodes[laws.drive], outputs[laws.drive] = follower.node, follower.mOutput
    for j, angle in zip(laws.free_levers, angles):
        nodes[j], outputs[j] = add_lever(model, laws.b.follower, angle, laws.lever_inertia)
        model.add_sensor(f"pole_{j + 1}_lever_angle", nodes[j], "Coordinates")
        model.add_sensor(f"pole_{j + 1}_lever_velocity", nodes[j], "Coordinates_t")
    markers = [mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=node, coordinate=0)) for node in nodes]
    for j in range(n - 1):
        mbs.AddObject(it.ObjectConnectorCoordinateSpringDamper(
            markerNumbers=[markers[j], markers[j + 1]], stiffness=laws.segment_stiffness, damping=laws.segment_damping,
            offset=0.0, visualization=it.VObjectConnectorCoordinateSpringDamper(show=False)))
    return outputs


def add_cam_roller_contact(model: ExudynModel, laws: BreakerLaws, cam_node, follower_node, impact: list,
                           cycle: CycleLaws | None = None, memory: list | None = None) -> None:
    """The cam-roller contact: torques on cam and follower from the contact force (with a trip
    latch, times the trip-free link's share, :meth:`CycleLaws.link`; ``memory``: the cycle's)."""
    _, it = exudyn_modules()
    linked = cycle is not None and cycle.trip_latch is not None

    def roller_uf(mbs, t, itemNumber, q, q_t):
        t_cam, t_fol, _, _ = laws.roller_loads(q[0], q_t[0], q[1], q_t[1], impact[0])
        if linked:
            keep = cycle.link(t, cycle.split(memory)[1])
            return [keep * t_cam, keep * t_fol]
        return [t_cam, t_fol]

    model.mbs.AddObject(it.ObjectGenericODE2(nodeNumbers=[cam_node, follower_node], forceUserFunction=roller_uf,
                                             visualization=it.VObjectGenericODE2(show=False)))


def add_latch(model: ExudynModel, laws: BreakerLaws, holding_torque: float, close_at: float = 0.0) -> None:
    """The closing latch's torque on the cam, released from t = ``close_at`` (s; 0: at the start)."""
    _, it = exudyn_modules()
    model.mbs.AddLoad(it.LoadCoordinate(markerNumber=model.cam_body.shaft.mShaftCoordinate, load=0.0,
                                        loadUserFunction=lambda mbs, t, load: laws.latch(t - close_at, holding_torque)))


def add_stops(model: ExudynModel, laws: BreakerLaws, engaged: list) -> None:
    """The closing end stop's and the holding latch's torque on the cam
    (:meth:`BreakerLaws.stop_loads`; ``engaged``: the holding latch's memory, set by the
    pre-step function), as a coordinate connector ground -> cam angle."""
    _, it = exudyn_modules()
    shaft = model.cam_body.shaft

    def stops_uf(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, offset):
        # deltaL = cam angle, deltaL_t = its speed; the connector's force acts on the cam negated
        return -laws.stop_loads(deltaL, deltaL_t, engaged[0])[0]

    model.mbs.AddObject(it.ObjectConnectorCoordinateSpringDamper(
        markerNumbers=[shaft.mGroundCoordinate, shaft.mShaftCoordinate], stiffness=0.0, damping=0.0,
        springForceUserFunction=stops_uf, visualization=it.VObjectConnectorCoordinateSpringDamper(show=False)))


def add_opening_spring(model, laws, follower: Follower):
    """Tension spring from its anchor below F to F."""
    _, it = exudyn_modules()
    mbs = model.mbs
    ox, oy = laws.opening_anchor
    mOpeningAnchor = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=model.cam_body.oGround, localPosition=[ox, oy, 0.0]))
    mbs.AddObject(it.ObjectConnectorSpringDamper(markerNumbers=[mOpeningAnchor, follower.mOutput],
                                                 stiffness=laws.b.opening_spring.stiffness,
                                                 referenceLength=laws.opening_free_length, damping=0.0))


def add_poles(model, laws, outputs: list, travel0, impact):
    """One body per pole on its vertical guide, pushed from its lever's output point (``outputs``:
    each pole's marker, :func:`add_levers`) through its push rod and wipe spring, stopped by its
    fixed contact; recorded as ``pole_i_travel`` and ``pole_i_travel_velocity``. Returns the pole
    nodes."""
    _, it = exudyn_modules()
    mbs, poles = model.mbs, laws.b.poles
    vertical = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]  # local x (travel) along global y
    mGroundCoordinate = model.cam_body.shaft.mGroundCoordinate

    def rod_uf(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
        # deltaL = length - rest length: compression is -deltaL; tension positive
        return -push_rod_force(-deltaL, -deltaL_t, poles)

    nodes = []
    for i in range(poles.count):
        nPole = mbs.AddNode(it.Node1D(referenceCoordinates=[0.0], initialCoordinates=[travel0[i]], initialVelocities=[0.0]))
        oPole = mbs.AddObject(it.ObjectMass1D(nodeNumber=nPole, mass=poles.moving_mass,
                                              referencePosition=[laws.pin_rest[0], laws.pin_rest[1], 0.0],
                                              referenceRotation=vertical))
        mPolePin = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=oPole, localPosition=[0.0, 0.0, 0.0]))
        mPoleTravel = mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=nPole, coordinate=0))
        mbs.AddObject(it.ObjectConnectorSpringDamper(markerNumbers=[outputs[i], mPolePin],
                                                     referenceLength=poles.push_rod_length, springForceUserFunction=rod_uf))

        def pole_uf(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, offset, i=i):
            return laws.pole_contact(i, deltaL, deltaL_t, impact[i + 1])

        mbs.AddObject(it.ObjectConnectorCoordinateSpringDamper(
            markerNumbers=[mGroundCoordinate, mPoleTravel], springForceUserFunction=pole_uf,
            visualization=it.VObjectConnectorCoordinateSpringDamper(show=False)))
        mbs.AddLoad(it.LoadCoordinate(markerNumber=mPoleTravel, load=laws.pole_load))
        model.add_sensor(f"pole_{i + 1}_travel", nPole, "Coordinates")
        model.add_sensor(f"pole_{i + 1}_travel_velocity", nPole, "Coordinates_t")
        nodes.append(nPole)
    return nodes


def add_impact_latching(model: ExudynModel, laws: BreakerLaws, cam_node, follower_node, pole_nodes, impact: list,
                        engaged: list, also: Callable | None = None) -> None:
    """A pre-step function that latches each contact's impact speed (see
    :meth:`BreakerLaws.latch_impact_speeds`) and the holding latch's engagement
    (:meth:`BreakerLaws.engage`, when the rig has a holding latch) from the state at the start of
    the step."""
    cam = node_state_reader(model.mbs, cam_node)
    follower = node_state_reader(model.mbs, follower_node)
    poles = [node_state_reader(model.mbs, n) for n in pole_nodes]
    hold_latch = laws.b.hold_latch is not None

    def latch_impact_speeds(mbs, t):
        (theta, omega), (phi, phi_dot) = cam(), follower()
        states = [p() for p in poles]
        roller = laws.latch_impact_speeds(impact, theta, omega, phi, phi_dot, [z for z, _ in states],
                                          [zd for _, zd in states])
        if hold_latch:
            engaged[0] = laws.engage(engaged[0], theta)
        if also is not None:
            also(t, phi, [z for z, _ in states], roller.penetration)
        return True

    model.mbs.SetPreStepUserFunction(latch_impact_speeds)

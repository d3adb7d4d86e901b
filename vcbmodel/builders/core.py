"""Parts every Exudyn builder shares: the lazy Exudyn import, the model with its solve, the
shaft coordinate, the shaft-friction connector and the cam body.

Coordinates are chosen for explicit Runge-Kutta (Exudyn's constraint elimination is wrong
for mass-coupled coordinates): a shaft angle is a ``Node1D`` with an
``ObjectRotationalMass1D`` (diagonal mass, no constraint), lever points are
``MarkerBodyPosition`` on it. The shaft friction is an ``ObjectConnectorCoordinateSpringDamper``
between ground and the shaft angle whose user function returns the friction torque of
:func:`vcbmodel.laws.friction.shaft_friction`: compiled (Exudyn symbolic) when its inputs
follow from the angle alone, a Python function otherwise.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import SimulationError
from ..laws.discovered import discovered_torque
from ..laws.friction import ArrayOps, NumericOps, shaft_friction
from ..laws.mechanics import aerodynamic_drag_torque, cam_inertia, cam_loads
from .exudyn_loader import exudyn_modules
from .symbolic import lean_expression

class ExudynModel:
    """A built system: container, system, named item handles and sensors."""

    def __init__(self):
        exu, _ = exudyn_modules()
        self.SC = exu.SystemContainer()
        self.mbs = self.SC.AddSystem()
        self.sensors = {}
        #: channels computed after the solve from the recorded shaft state: {name: torque(t, theta,
        #: omega, ops)}, evaluated with ArrayOps on the ``angle`` and ``velocity`` sensors
        #: (:func:`add_friction_connector`'s ``state_only``)
        self.derived = {}
        self.keep = []  # symbolic user functions must outlive the solve

    def add_sensor(self, name: str, node, output: str) -> None:
        """Store a node's output (``exu.OutputVariableType`` name) under ``name``."""
        exu, it = exudyn_modules()
        self.sensors[name] = self.mbs.AddSensor(it.SensorNode(
            nodeNumber=node, outputVariableType=getattr(exu.OutputVariableType, output),
            storeInternal=True, writeToFile=False))

    def solve(self, t_end: float, step: float, sensor_period: float | None = None) -> dict[str, np.ndarray]:
        """Run explicit RK4 with a fixed step; returns {sensor name: array of (t, values...)}."""
        exu, _ = exudyn_modules()
        mbs = self.mbs
        mbs.Assemble()
        sim = exu.SimulationSettings()
        ti = sim.timeIntegration
        ti.endTime = t_end
        ti.numberOfSteps = max(1, int(round(t_end / step)))
        ti.verboseMode = 0
        sim.solution.file.write = False
        sim.solution.sensors.writePeriod = sensor_period or step
        # the accelerations at a step's end are one right-hand side in five and nothing reads them
        # (sensors record coordinates and speeds): the same trajectories, 13 % less time
        ti.explicit.computeEndOfStepAccelerations = False
        sim.show.computationTime = False
        sim.show.statistics = False
        try:
            ok = mbs.SolveDynamic(sim, solverType=exu.DynamicSolverType.RK44)
        except Exception as e:  # Exudyn raises on solver failure; keep the first line of its message
            first = str(e).strip().splitlines()
            raise SimulationError("Exudyn solver failed: " + " ".join(first[:2])[:300]) from None
        if ok is False:
            raise SimulationError("Exudyn solver reported failure")
        out = {}
        for name, s in self.sensors.items():
            data = np.array(mbs.GetSensorStoredData(s))
            if data.size == 0 or not np.all(np.isfinite(data)):
                raise SimulationError(f"the solution diverged (non-finite {name}) at the experiment's fixed step: "
                                      "a stiffness, mass or contact value far outside its documented range is the "
                                      "usual cause (docs/rig-format.md)")
            out[name] = data
        self.SC.Reset()  # frees symbolic user functions (exudyn-notes: they leak otherwise)
        out.update(self.derived_channels(out))
        return out

    def derived_channels(self, out: dict) -> dict[str, np.ndarray]:
        """The :attr:`derived` channels from the recorded shaft state, as a sensor's (t, value) rows."""
        channels = {}
        if not self.derived:
            return channels
        t, theta, omega = out["angle"][:, 0], out["angle"][:, 1], out["velocity"][:, 1]
        for name, torque in self.derived.items():
            with np.errstate(all="ignore"):  # ArrayOps computes every branch and chooses
                value = np.broadcast_to(np.asarray(torque(t, theta, omega, ArrayOps), float), t.shape)
            if not np.all(np.isfinite(value)):
                raise SimulationError(f"the {name} of the solved state is not finite: the law's inputs are outside "
                                      "its range (docs/rig-format.md)")
            channels[name] = np.column_stack([t, value])
        return channels


@dataclass
class Shaft:
    """Handles of a shaft coordinate: node, body, and the coordinate markers of ground and
    shaft (the friction connector's and coordinate loads' markers)."""

    node: int
    body: int
    mGroundCoordinate: int
    mShaftCoordinate: int


def add_shaft(model, inertia, theta0, omega0, position=(0.0, 0.0)) -> Shaft:
    """A rotating body on a fixed axis at ``position`` (m): angle (rad) and speed (rad/s)
    recorded as ``angle`` and ``velocity``."""
    exu, it = exudyn_modules()
    mbs = model.mbs
    nShaft = mbs.AddNode(it.Node1D(referenceCoordinates=[0.0], initialCoordinates=[theta0],
                                   initialVelocities=[omega0]))
    oShaft = mbs.AddObject(it.ObjectRotationalMass1D(nodeNumber=nShaft, inertia=inertia,
                                                     referencePosition=[position[0], position[1], 0.0]))
    nGround = mbs.AddNode(it.NodePointGround())
    mGroundCoordinate = mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=nGround, coordinate=0))
    mShaftCoordinate = mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=nShaft, coordinate=0))
    model.add_sensor("angle", nShaft, "Coordinates")
    model.add_sensor("velocity", nShaft, "Coordinates_t")
    return Shaft(nShaft, oShaft, mGroundCoordinate, mShaftCoordinate)


def add_friction_connector(model, shaft: Shaft, friction_of_state, user_function, record: str = "friction_torque",
                           state_only: bool = False):
    """Friction torque connector on the shaft; ``friction_of_state(t, theta, omega, ops)`` -> T_f
    (N m). ``user_function``: 'symbolic' (compiled), 'python', or 'none' (no friction item).
    The torque is recorded as ``record``: by a sensor of the connector's force, or, when
    ``state_only`` (the torque is a function of the shaft's own t, theta, omega and of nothing another
    body holds), computed after the solve by the same function on the recorded angle and speed
    (:meth:`ExudynModel.derived_channels`): the same values to rounding, and no evaluation of the
    law per step for the record (a force sensor costs 6 % of a 6 s pendulum's solve)."""
    exu, it = exudyn_modules()
    mbs = model.mbs
    if user_function == "none":
        return

    def friction_torque_uf(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, offset):
        return friction_of_state(t, deltaL, deltaL_t, ops_holder[0])

    def lean_friction_torque_uf(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, offset):
        return lean_expression(friction_of_state, (t, deltaL, deltaL_t))  # recorded lean (builders.symbolic)

    oFriction = mbs.AddObject(it.ObjectConnectorCoordinateSpringDamper(
        markerNumbers=[shaft.mGroundCoordinate, shaft.mShaftCoordinate], stiffness=0.0, damping=0.0,
        visualization=it.VObjectConnectorCoordinateSpringDamper(show=False)))
    if user_function == "symbolic":
        from exudyn.advancedUtilities import CreateSymbolicUserFunction  # Exudyn, lazily (see exudyn_modules)
        symbolic = CreateSymbolicUserFunction(mbs, lean_friction_torque_uf, "springForceUserFunction", oFriction)
        model.keep.append(symbolic)
        mbs.SetObjectParameter(oFriction, "springForceUserFunction", symbolic)
    elif user_function == "python":
        ops_holder = [NumericOps]
        mbs.SetObjectParameter(oFriction, "springForceUserFunction", friction_torque_uf)
    else:
        raise ValueError(f"unknown user_function {user_function!r}")
    if state_only:
        model.derived[record] = friction_of_state
        return
    model.sensors[record] = mbs.AddSensor(it.SensorObject(
        objectNumber=oFriction, outputVariableType=exu.OutputVariableType.Force,
        storeInternal=True, writeToFile=False))


@dataclass
class CamBody:
    """Handles of the cam on its shaft at A (eq. 11-13): the shaft, the spring pin B, ground
    and the springs' anchor O."""

    shaft: Shaft
    mPin: int
    oGround: int
    mAnchor: int
    pin_mass: float = 0.0  # kg riding on B (all springs)


def add_cam_body(model, rig, pin_mass=0.0) -> CamBody:
    """The cam of eq. 11-13 on its shaft at A with its weight, the pin marker B and the anchor
    O of the closing springs (shared by the lumped and ANCF builders). ``pin_mass`` (kg, all
    springs): the springs' mass riding on B; it adds m_pin l_AB^2 to the cam's inertia and, when
    the spring masses carry weight, its weight at B."""
    exu, it = exudyn_modules()
    cam, spring, g = rig.cam, rig.closing_spring, rig.gravity
    mbs = model.mbs
    shaft = add_shaft(model, cam_inertia(cam, pin_mass), cam.initial_angle, cam.initial_velocity, cam.pivot)
    mPin = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=shaft.body, localPosition=[cam.arm_length, 0.0, 0.0]))
    mCamCom = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=shaft.body, localPosition=[
        cam.com_distance * math.cos(-cam.com_angle), cam.com_distance * math.sin(-cam.com_angle), 0.0]))
    mbs.AddLoad(it.LoadForceVector(markerNumber=mCamCom, loadVector=[0.0, -cam.mass * g, 0.0]))
    if pin_mass and spring.weight:
        mbs.AddLoad(it.LoadForceVector(markerNumber=mPin, loadVector=[0.0, -pin_mass * g, 0.0]))
    oGround = mbs.AddObject(it.ObjectGround())
    mAnchor = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=oGround, localPosition=[spring.anchor[0], spring.anchor[1], 0.0]))
    return CamBody(shaft, mPin, oGround, mAnchor, pin_mass)


def add_cam_friction(model, rig, law, body: CamBody, pin_force, user_function, extra_loads=None, discovered: tuple = ()):
    """The cam shaft's friction connector (eq. 11-13): ``pin_force(theta, omega, ops)`` is the
    closing springs' pull (N) on pin B at the current Runge-Kutta stage; ``extra_loads(t, theta,
    omega)`` -> (torque about A in N m, Fx, Fy in N) adds other loads on the cam (the whole
    breaker's roller contact and latch) to the applied torque and the shaft reaction. The
    springs' pin mass (``body.pin_mass``) rides on the cam: inertia, reaction, weight.
    ``discovered``: a discovered torque T_d on the cam shaft (:func:`add_discovered_torque`).
    The torque is :func:`cam_friction_torque` of :func:`cam_friction_inputs`."""
    inputs = cam_friction_inputs(rig, law, body, discovered)

    def friction_of_state(t, theta, omega, ops):
        fx, fy = pin_force(theta, omega, ops)
        extra = () if extra_loads is None else tuple(extra_loads(t, theta, omega))
        return cam_friction_torque((t, theta, omega, fx, fy, *extra), inputs, ops)

    add_discovered_torque(model, body.shaft, discovered, user_function)
    add_friction_connector(model, body.shaft, friction_of_state, user_function)


def cam_friction_inputs(rig, law, body: CamBody, discovered: tuple = ()) -> dict:
    """The parameters of :func:`cam_friction_torque` for the cam of ``rig`` on ``body``."""
    return {"cam": rig.cam, "law": law, "gravity": rig.gravity, "pin_mass": body.pin_mass,
            "pin_weight": bool(rig.closing_spring.weight), "discovered": tuple(discovered)}


def cam_friction_torque(args, inputs: dict, ops):
    """The cam shaft's friction torque T_f (N m; eq. 2-6 on the loads of eq. 11-13) at ``args`` =
    (t in s, theta in rad, omega in rad/s, Fx, Fy: the springs' pull on pin B in N[, T_e in N m,
    Ex, Ey in N: other loads on the cam, ``add_cam_friction``'s ``extra_loads``]); ``inputs``:
    :func:`cam_friction_inputs`. One source for the Python user function and the compiled one
    (:func:`vcbmodel.compiled.function.compiled_function`)."""
    t, theta, omega, fx, fy = args[:5]
    cam, pin, discovered = inputs["cam"], inputs["pin_mass"], inputs["discovered"]
    Tc, R0x, R0y, R1x, R1y = cam_loads(theta, omega, cam, fx, fy, inputs["gravity"], ops, pin, inputs["pin_weight"])
    if len(args) > 5:
        torque, ex, ey = args[5:8]
        Tc, R0x, R0y = Tc + torque, R0x - ex, R0y - ey
    if discovered:
        Tc = Tc + discovered_torque(t, theta, omega, discovered, ops)
    return shaft_friction(omega, Tc, R0x, R0y, R1x, R1y, cam_inertia(cam, pin), inputs["law"], ops, t)[0]


def add_discovered_torque(model, shaft: Shaft, discovered: tuple, user_function) -> None:
    """A discovered torque T_d, ((term, coefficient), ...) (:mod:`vcbmodel.laws.discovered`), on
    ``shaft`` by a connector of its own, recorded as ``discovered_torque`` (N m: the torque the
    connector applies against the shaft, -T_d); nothing when ``discovered`` is empty. The shaft's
    friction must count T_d in its applied torque (its caller's friction function adds it)."""
    if discovered:
        add_shaft_torque(model, shaft, lambda t, theta, omega, ops: discovered_torque(t, theta, omega, discovered, ops),
                         user_function, "discovered_torque")


def add_drag_torque(model, shaft: Shaft, drag: float, user_function) -> None:
    """Air drag -c_d w|w| (:func:`vcbmodel.laws.mechanics.aerodynamic_drag_torque`, ``drag`` c_d in
    N m s^2/rad^2) on ``shaft`` by a connector of its own, recorded as ``drag_torque`` (N m, against
    the shaft); nothing when ``drag`` is 0. The shaft's friction must count it in its applied torque."""
    if drag:
        add_shaft_torque(model, shaft, lambda t, theta, omega, ops: aerodynamic_drag_torque(omega, drag, ops),
                         user_function, "drag_torque")


def add_shaft_torque(model, shaft: Shaft, torque, user_function, sensor: str) -> None:
    """``torque(t, theta, omega, ops)`` (N m, applied to the shaft; a function of the shaft's own
    state) by a connector of its own, recorded as ``sensor`` (the torque the connector applies against
    the shaft: minus it)."""
    def against(t, theta, omega, ops):  # a connector's torque opposes its coordinate
        return -torque(t, theta, omega, ops)

    add_friction_connector(model, shaft, against, "python" if user_function == "none" else user_function,
                           record=sensor, state_only=True)

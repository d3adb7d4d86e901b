"""Exudyn builders for the pendulum test and the cam drop (paper sections 2 and 3).

Coordinates are chosen for explicit Runge-Kutta (see shared exudyn-notes): the shaft angle
is a ``Node1D`` with an ``ObjectRotationalMass1D`` (diagonal mass, no constraint), lever
points are ``MarkerBodyPosition`` on it; lumped spring masses are ``MassPoint2D`` joined by
``ObjectConnectorSpringDamper``. The shaft friction is an
``ObjectConnectorCoordinateSpringDamper`` between ground and the shaft angle whose user
function returns the friction torque of :func:`vcbmodel.friction.shaft_friction`:
compiled (Exudyn symbolic) when its inputs follow from the angle alone (pendulum, massless
spring), a Python function otherwise (it then reads the last spring mass's position at
the current Runge-Kutta stage).
"""
from __future__ import annotations

import math

import numpy as np

from .errors import SimulationError
from .friction import NumericOps, shaft_friction, symbolic_ops
from .mechanics import cam_loads, cam_pin, massless_spring_force, pendulum_loads

_EXU = None


def _exudyn():
    global _EXU
    if _EXU is None:
        import exudyn as exu
        from exudyn import itemInterface as items
        # Exudyn writes solver warnings and failure banners to stdout, which would corrupt
        # `--json` output and CSV on stdout; failures reach the caller as SimulationError
        exu.config.printToConsole = False
        _EXU = (exu, items)
    return _EXU


class ExudynModel:
    """A built system: container, system, named item handles and sensors."""

    def __init__(self):
        exu, _ = _exudyn()
        self.SC = exu.SystemContainer()
        self.mbs = self.SC.AddSystem()
        self.sensors = {}
        self.keep = []  # symbolic user functions must outlive the solve

    def solve(self, t_end, step, sensor_period=None):
        """Run explicit RK4 with a fixed step; returns {sensor name: (t, values)}."""
        exu, _ = _exudyn()
        mbs = self.mbs
        mbs.Assemble()
        sim = exu.SimulationSettings()
        ti = sim.timeIntegration
        ti.endTime = t_end
        ti.numberOfSteps = max(1, int(round(t_end / step)))
        ti.verboseMode = 0
        sim.solution.file.write = False
        sim.solution.sensors.writePeriod = sensor_period or step
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
                raise SimulationError(f"the solution diverged (non-finite {name}); reduce the step")
            out[name] = data
        self.SC.Reset()  # frees symbolic user functions (exudyn-notes: they leak otherwise)
        return out


def _shaft(model, inertia, theta0, omega0, position=(0.0, 0.0)):
    exu, it = _exudyn()
    mbs = model.mbs
    nShaft = mbs.AddNode(it.Node1D(referenceCoordinates=[0.0], initialCoordinates=[theta0],
                                   initialVelocities=[omega0]))
    oShaft = mbs.AddObject(it.ObjectRotationalMass1D(nodeNumber=nShaft, inertia=inertia,
                                                     referencePosition=[position[0], position[1], 0.0]))
    nGround = mbs.AddNode(it.NodePointGround())
    mGroundCoordinate = mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=nGround, coordinate=0))
    mShaftCoordinate = mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=nShaft, coordinate=0))
    model.sensors["angle"] = mbs.AddSensor(it.SensorNode(
        nodeNumber=nShaft, outputVariableType=exu.OutputVariableType.Coordinates,
        storeInternal=True, writeToFile=False))
    model.sensors["velocity"] = mbs.AddSensor(it.SensorNode(
        nodeNumber=nShaft, outputVariableType=exu.OutputVariableType.Coordinates_t,
        storeInternal=True, writeToFile=False))
    return nShaft, oShaft, mGroundCoordinate, mShaftCoordinate


def _friction_connector(model, markers, friction_of_state, user_function):
    """Friction torque connector; ``friction_of_state(t, theta, omega, ops)`` -> T_f.

    ``user_function``: 'symbolic' (compiled), 'python', or 'none' (no friction item).
    """
    exu, it = _exudyn()
    mbs = model.mbs
    if user_function == "none":
        return None

    def friction_torque_uf(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, offset):
        return friction_of_state(t, deltaL, deltaL_t, ops_holder[0])

    oFriction = mbs.AddObject(it.ObjectConnectorCoordinateSpringDamper(
        markerNumbers=list(markers), stiffness=0.0, damping=0.0,
        visualization=it.VObjectConnectorCoordinateSpringDamper(show=False)))
    if user_function == "symbolic":
        from exudyn.advancedUtilities import CreateSymbolicUserFunction
        ops_holder = [symbolic_ops()]
        symbolic = CreateSymbolicUserFunction(mbs, friction_torque_uf, "springForceUserFunction", oFriction)
        model.keep.append(symbolic)
        mbs.SetObjectParameter(oFriction, "springForceUserFunction", symbolic)
    elif user_function == "python":
        ops_holder = [NumericOps]
        mbs.SetObjectParameter(oFriction, "springForceUserFunction", friction_torque_uf)
    else:
        raise ValueError(f"unknown user_function {user_function!r}")
    model.sensors["friction_torque"] = mbs.AddSensor(it.SensorObject(
        objectNumber=oFriction, outputVariableType=exu.OutputVariableType.Force,
        storeInternal=True, writeToFile=False))
    return oFriction


def build_pendulum(rig, law, user_function="symbolic"):
    """Pendulum of eq. 1 on the shaft coordinate; the weight M g acts at distance L."""
    exu, it = _exudyn()
    p, g = rig.pendulum, rig.gravity
    model = ExudynModel()
    mbs = model.mbs
    nShaft, oShaft, mGround, mShaft = _shaft(model, p.inertia, p.initial_angle, p.initial_velocity)
    mWeight = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=oShaft, localPosition=[0.0, -p.com_distance, 0.0]))
    mbs.AddLoad(it.LoadForceVector(markerNumber=mWeight, loadVector=[0.0, -p.mass * g, 0.0]))

    def friction_of_state(t, theta, omega, ops):
        Tc, R0x, R0y, R1x, R1y = pendulum_loads(theta, omega, p.mass, p.com_distance, g, ops)
        return shaft_friction(omega, Tc, R0x, R0y, R1x, R1y, p.inertia, law, ops)[0]

    model.oFriction = _friction_connector(model, (mGround, mShaft), friction_of_state, user_function)
    model.nShaft, model.oShaft = nShaft, oShaft
    return model


def cam_friction(model, rig, law, pin_force, user_function, extra_loads=None):
    """The cam shaft's friction connector (eq. 11-13): ``pin_force(theta, omega, ops)`` is the
    closing springs' pull (N) on pin B at the current Runge-Kutta stage; ``extra_loads(t, theta,
    omega)`` -> (torque about A in N m, Fx, Fy in N) adds other loads on the cam (the whole
    breaker's roller contact and latch) to the applied torque and the shaft reaction."""
    cam, g = rig.cam, rig.gravity

    def friction_of_state(t, theta, omega, ops):
        fx, fy = pin_force(theta, omega, ops)
        Tc, R0x, R0y, R1x, R1y = cam_loads(theta, omega, cam, fx, fy, g, ops)
        if extra_loads is not None:
            torque, ex, ey = extra_loads(t, theta, omega)
            Tc, R0x, R0y = Tc + torque, R0x - ex, R0y - ey
        return shaft_friction(omega, Tc, R0x, R0y, R1x, R1y, cam.inertia_pivot, law, ops)[0]

    model.oFriction = _friction_connector(model, (model.mGroundCoordinate, model.mShaftCoordinate),
                                          friction_of_state, user_function)


def build_cam_drop(rig, law, chain=None, user_function="auto", extra_loads=None):
    """The cam of eq. 11-13 on its shaft at A, pulled at pin B by the closing springs.

    ``chain`` is a :class:`vcbmodel.springs.LumpedChain` (None: massless springs). The
    ``count`` identical springs act in the same plane, so one chain with ``count`` times
    the masses and stiffnesses represents them. ``extra_loads``: see :func:`cam_friction`.
    """
    exu, it = _exudyn()
    cam, spring, g = rig.cam, rig.closing_spring, rig.gravity
    model = ExudynModel()
    mbs = model.mbs
    nCam, oCam, mGround, mShaft = _shaft(model, cam.inertia_pivot, cam.initial_angle,
                                         cam.initial_velocity, cam.pivot)
    model.mGroundCoordinate, model.mShaftCoordinate = mGround, mShaft
    mPin = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=oCam, localPosition=[cam.arm_length, 0.0, 0.0]))
    mCamCom = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=oCam, localPosition=[
        cam.com_distance * math.cos(-cam.com_angle), cam.com_distance * math.sin(-cam.com_angle), 0.0]))
    mbs.AddLoad(it.LoadForceVector(markerNumber=mCamCom, loadVector=[0.0, -cam.mass * g, 0.0]))
    oGround = mbs.AddObject(it.ObjectGround())
    model.oGround = oGround
    mAnchor = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=oGround, localPosition=[spring.anchor[0], spring.anchor[1], 0.0]))
    c = spring.count
    model.spring_nodes = []
    if chain is None:
        mbs.AddObject(it.ObjectConnectorSpringDamper(markerNumbers=[mAnchor, mPin], stiffness=c * spring.stiffness,
                                                     referenceLength=spring.free_length, damping=0.0))

        def pin_force(theta, omega, ops):
            bx, by = cam_pin(theta, cam, ops)
            return massless_spring_force(bx, by, spring, ops)

        uf = "symbolic" if user_function == "auto" and extra_loads is None else user_function
    else:
        bx0, by0 = cam_pin(cam.initial_angle, cam)
        ox, oy = spring.anchor
        previous = mAnchor
        for frac, m in zip(chain.equilibrium_fractions(), chain.masses):
            nMass = mbs.AddNode(it.NodePoint2D(referenceCoordinates=[ox + frac * (bx0 - ox), oy + frac * (by0 - oy)]))
            oMass = mbs.AddObject(it.MassPoint2D(nodeNumber=nMass, mass=c * m))
            mMass = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=oMass, localPosition=[0.0, 0.0, 0.0]))
            if spring.weight:
                mbs.AddLoad(it.LoadForceVector(markerNumber=mMass, loadVector=[0.0, -c * m * g, 0.0]))
            model.spring_nodes.append(nMass)
            k = len(model.spring_nodes)
            for prefix, output in (("spring_mass", exu.OutputVariableType.Position),
                                   ("spring_velocity", exu.OutputVariableType.Velocity)):
                model.sensors[f"{prefix}_{k}"] = mbs.AddSensor(it.SensorNode(
                    nodeNumber=nMass, outputVariableType=output, storeInternal=True, writeToFile=False))
            mbs.AddObject(it.ObjectConnectorSpringDamper(markerNumbers=[previous, mMass], damping=0.0,
                                                         stiffness=c * chain.stiffnesses[k - 1],
                                                         referenceLength=chain.free_lengths[k - 1]))
            previous = mMass
        k_last, l_last = c * chain.stiffnesses[-1], chain.free_lengths[-1]
        mbs.AddObject(it.ObjectConnectorSpringDamper(markerNumbers=[previous, mPin], damping=0.0,
                                                     stiffness=k_last, referenceLength=l_last))
        nLast = model.spring_nodes[-1]
        position = exu.OutputVariableType.Position

        def pin_force(theta, omega, ops):
            # last segment's pull on B, from the last mass's position at this RK stage
            px, py = mbs.GetNodeOutput(nLast, position)[:2]
            bx, by = cam_pin(theta, cam, ops)
            dx, dy = bx - px, by - py
            length = math.sqrt(dx * dx + dy * dy)
            tension = k_last * (length - l_last)
            return -tension * dx / length, -tension * dy / length

        uf = "python" if user_function == "auto" else user_function
    if uf == "symbolic" and (chain is not None or extra_loads is not None):
        raise ValueError("a lumped spring's or the breaker's friction needs the Python user function")
    cam_friction(model, rig, law, pin_force, uf, extra_loads)
    model.nCam, model.oCam = nCam, oCam
    return model

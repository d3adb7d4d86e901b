"""Exudyn model of the whole breaker's closing (paper section 4) and its evaluation.

Coordinates (all minimal, for explicit RK4 without constraints, see exudyn-notes): the cam
angle (``Node1D`` + ``ObjectRotationalMass1D`` at A: the cam-drop model with its closing
springs and shaft friction), the follower angle (the same at the follower pivot), and one
``Node1D`` + ``ObjectMass1D`` per pole sliding on its vertical guide (the translational
joint is the coordinate itself). Connectors, user functions wrapping the pure laws of
:mod:`vcbmodel.breaker` through :class:`BreakerLaws`:

- cam-roller contact: ``ObjectGenericODE2`` on (cam, follower) whose force user function
  returns the contact's torques on both (Hertz + Lankarani-Nikravesh);
- push rods with wipe springs: ``ObjectConnectorSpringDamper`` F -> pole pin;
- pole contacts: ``ObjectConnectorCoordinateSpringDamper`` ground -> pole travel;
- opening spring: a plain ``ObjectConnectorSpringDamper``; closing latch: ``LoadCoordinate``
  on the cam with a time user function; bellows force minus weight: constant ``LoadCoordinate``;
- each contact's impact speed (the damping's reference speed) is latched by a pre-step
  function from the state at the start of the step in which the contact begins.

The shaft friction also sees the roller force and the latch torque (they load the journal).
The follower's own weight is left out (a balanced main shaft).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import cumulative_trapezoid
from scipy.optimize import brentq

from .breaker import (cam_roller_contact, cam_roller_loads, contact_energy, contact_force, latch_torque,
                      output_point, pole_gaps, push_rod_energy, push_rod_force, rest_geometry)
from .errors import SimulationError
from .mechanics import cam_pin, massless_spring_force


@dataclass
class InitialState:
    """Static rest held by the latch: follower angle (rad), pole travels (m) and the latch's
    holding torque on the cam (N m)."""

    follower_angle: float
    pole_travel: list
    holding_torque: float


class BreakerLaws:
    """Every force of the breaker at a state, from :mod:`vcbmodel.breaker`'s laws.

    One object serves the Exudyn user functions, the independent reference solve and the
    evaluation (forces and energies from the recorded states). ``spec`` supplies the
    effect-dependent values ``restitution`` (1 = elastic contacts) and ``bellows_force`` (N).
    """

    def __init__(self, rig, spec):
        self.rig, self.b = rig, rig.breaker
        self.geometry = rest_geometry(self.b, rig.cam.pivot)
        self.gaps = pole_gaps(self.b.poles)
        self.restitution = spec.restitution
        self.pole_load = spec.bellows_force - self.b.poles.moving_mass * rig.gravity  # N, along closing
        fx, fy = self.geometry.output_point
        self.pin_rest = (fx, fy + self.b.poles.push_rod_length)
        self.opening_anchor = (fx, fy - self.b.opening_spring.length)
        o = self.b.opening_spring
        self.opening_free_length = o.length - o.preload / o.stiffness

    # -- cam-roller contact
    def roller(self, theta, omega, phi, phi_dot, impact_speed=0.0):
        """(CamRollerContact, normal force in N)."""
        c = cam_roller_contact(theta, omega, phi, phi_dot, self.b, self.geometry)
        law = self.b.contact
        return c, contact_force(c.penetration, c.penetration_rate, law.cam_roller_stiffness, law.exponent,
                                self.restitution, impact_speed, law.min_impact_speed)

    def roller_loads(self, theta, omega, phi, phi_dot, impact_speed=0.0):
        """(torque on cam N m, torque on follower N m, force on cam Fx, Fy in N)."""
        c, force = self.roller(theta, omega, phi, phi_dot, impact_speed)
        return cam_roller_loads(c, force, self.b, self.geometry)

    # -- push rods and poles
    def pin(self, z):
        return self.pin_rest[0], self.pin_rest[1] + z

    def rod(self, phi, phi_dot, z, z_dot):
        """(compression m, its rate m/s, unit vector F -> pin, compressive force N)."""
        f = self.b.follower
        fx, fy = output_point(phi, f)
        vx = -phi_dot * (fy - f.pivot[1])
        vy = phi_dot * (fx - f.pivot[0])
        px, py = self.pin(z)
        dx, dy = px - fx, py - fy
        length = math.hypot(dx, dy)
        ex, ey = dx / length, dy / length
        rate = -(ex * (0.0 - vx) + ey * (z_dot - vy))
        compression = self.b.poles.push_rod_length - length
        return compression, rate, (ex, ey), push_rod_force(compression, rate, self.b.poles)

    def rod_loads(self, phi, phi_dot, z, z_dot):
        """(force on the pole along closing N, torque on the follower N m)."""
        _, _, (ex, ey), force = self.rod(phi, phi_dot, z, z_dot)
        fx, fy = output_point(phi, self.b.follower)
        pv = self.b.follower.pivot
        # the rod pushes the pin along +e and F along -e
        return force * ey, (fx - pv[0]) * (-force * ey) - (fy - pv[1]) * (-force * ex)

    def pole_contact(self, i, z, z_dot, impact_speed=0.0):
        """Force (N, opening direction) of pole i's fixed contact."""
        law = self.b.contact
        return contact_force(z - self.gaps[i], z_dot, law.pole_stiffness, law.exponent, self.restitution,
                             impact_speed, law.min_impact_speed)

    # -- opening spring
    def opening(self, phi):
        """(tension N, torque on the follower N m)."""
        f = self.b.follower
        fx, fy = output_point(phi, f)
        ox, oy = self.opening_anchor
        L = math.hypot(fx - ox, fy - oy)
        tension = self.b.opening_spring.stiffness * (L - self.opening_free_length)
        gx, gy = -tension * (fx - ox) / L, -tension * (fy - oy) / L
        return tension, (fx - f.pivot[0]) * gy - (fy - f.pivot[1]) * gx

    # -- rest state
    def rod_rest_compression(self):
        """Compression (m) of a rod holding its pole at rest: force m g - bellows."""
        force, p = -self.pole_load, self.b.poles
        s0 = p.wipe_preload / p.rod_stiffness
        return force / p.rod_stiffness if force <= p.wipe_preload else s0 + (force - p.wipe_preload) / p.wipe_rate

    def rest_pole_travel(self, phi):
        """Pole travel z (m) with the rod at its rest compression for follower angle phi."""
        fx, fy = output_point(phi, self.b.follower)
        length = self.b.poles.push_rod_length - self.rod_rest_compression()
        return fy + math.sqrt(length * length - (self.pin_rest[0] - fx) ** 2) - self.pin_rest[1]

    def follower_torque(self, theta, omega, phi, phi_dot, z, z_dot, impact_speed=0.0):
        """Total torque (N m) on the follower and the roller's loads on the cam."""
        t_cam, t_fol, fx, fy = self.roller_loads(theta, omega, phi, phi_dot, impact_speed)
        t_fol += self.opening(phi)[1]
        for zi, zi_dot in zip(z, z_dot):
            t_fol += self.rod_loads(phi, phi_dot, zi, zi_dot)[1]
        return t_fol, (t_cam, fx, fy)

    def initial_state(self, spring_pull) -> InitialState:
        """Static rest at the cam's initial angle; ``spring_pull`` (N, N) is the closing
        springs' pull on pin B there."""
        cam, g = self.rig.cam, self.rig.gravity
        theta = cam.initial_angle
        n = self.b.poles.count

        def torque(phi):
            z = [self.rest_pole_travel(phi)] * n
            return self.follower_torque(theta, 0.0, phi, 0.0, z, [0.0] * n)[0]

        phi_rest = self.geometry.follower_angle
        span = 1e-3
        lo, hi = phi_rest - span, phi_rest + span
        if torque(lo) * torque(hi) > 0:
            raise SimulationError("breaker: no static rest of the follower on the cam: the poles' bellows "
                                  "and rod forces lift it against the opening spring")
        phi = brentq(torque, lo, hi, xtol=1e-15)
        z = [self.rest_pole_travel(phi)] * n
        _, (t_cam, _, _) = self.follower_torque(theta, 0.0, phi, 0.0, z, [0.0] * n)
        bx, by = cam_pin(theta, cam)
        fx, fy = spring_pull
        rgx = cam.com_distance * math.cos(theta - cam.com_angle)
        spring_and_weight = (bx - cam.pivot[0]) * fy - (by - cam.pivot[1]) * fx - cam.mass * g * rgx
        return InitialState(phi, z, -(spring_and_weight + t_cam))

    def latch_impact_speeds(self, impact, theta, omega, phi, phi_dot, z, z_dot):
        """Update ``impact`` ([cam-roller, pole 1..n], m/s) from a state by
        :func:`update_impact_speeds`; returns the cam-roller contact at that state."""
        roller = self.roller(theta, omega, phi, phi_dot)[0]
        state = [(roller.penetration, roller.penetration_rate)]
        state += [(zi - gap, zi_dot) for zi, zi_dot, gap in zip(z, z_dot, self.gaps)]
        update_impact_speeds(impact, state)
        return roller

    def latch(self, t, holding):
        return latch_torque(t, holding, self.b.latch_release_time)


def massless_pull(rig):
    cam, spring = rig.cam, rig.closing_spring
    return massless_spring_force(*cam_pin(cam.initial_angle, cam), spring)


def build_vcb_closing(rig, spec, law, chain=None, user_function="auto", ancf_elements=None):
    """The whole breaker in Exudyn (module docstring); returns the model with ``laws`` and
    ``initial`` attached."""
    from .exudyn_models import _exudyn, build_cam_drop

    exu, it = _exudyn()
    laws = BreakerLaws(rig, spec)
    b = rig.breaker
    initial = laws.initial_state(massless_pull(rig))  # every spring model starts in the same static rest
    n = b.poles.count
    impact = np.zeros(n + 1)  # [cam-roller, pole 1..n] impact speeds (m/s)
    holder = {}

    def follower_state():
        mbs = holder["mbs"]
        nF = holder["nFollower"]
        return (mbs.GetNodeOutput(nF, exu.OutputVariableType.Coordinates),
                mbs.GetNodeOutput(nF, exu.OutputVariableType.Coordinates_t))

    def extra_loads(t, theta, omega):
        phi, phi_dot = follower_state()
        t_cam, _, fx, fy = laws.roller_loads(theta, omega, phi, phi_dot, impact[0])
        return t_cam + laws.latch(t, initial.holding_torque), fx, fy

    uf = "python" if user_function in ("auto", "symbolic") else user_function
    if spec.spring_model == "ancf":
        from .ancf_spring import build_cam_drop_ancf
        model = build_cam_drop_ancf(rig, law, user_function=uf, elements=ancf_elements, extra_loads=extra_loads)
    else:
        model = build_cam_drop(rig, law, chain, uf, extra_loads=extra_loads)
    mbs = model.mbs
    holder["mbs"] = mbs
    f = b.follower
    nFollower = mbs.AddNode(it.Node1D(referenceCoordinates=[0.0], initialCoordinates=[initial.follower_angle],
                                      initialVelocities=[0.0]))
    oFollower = mbs.AddObject(it.ObjectRotationalMass1D(nodeNumber=nFollower, inertia=f.inertia,
                                                        referencePosition=[f.pivot[0], f.pivot[1], 0.0]))
    holder["nFollower"] = nFollower
    mF = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=oFollower, localPosition=[
        f.output_arm * math.cos(f.output_angle), f.output_arm * math.sin(f.output_angle), 0.0]))
    for name, output in (("follower_angle", exu.OutputVariableType.Coordinates),
                         ("follower_velocity", exu.OutputVariableType.Coordinates_t)):
        model.sensors[name] = mbs.AddSensor(it.SensorNode(nodeNumber=nFollower, outputVariableType=output,
                                                          storeInternal=True, writeToFile=False))

    nCam = model.nCam

    def roller_uf(mbs, t, itemNumber, q, q_t):
        t_cam, t_fol, _, _ = laws.roller_loads(q[0], q_t[0], q[1], q_t[1], impact[0])
        return [t_cam, t_fol]

    model.oRoller = mbs.AddObject(it.ObjectGenericODE2(nodeNumbers=[nCam, nFollower], forceUserFunction=roller_uf,
                                                       visualization=it.VObjectGenericODE2(show=False)))
    mbs.AddLoad(it.LoadCoordinate(markerNumber=model.mShaftCoordinate, load=0.0,
                                  loadUserFunction=lambda mbs, t, load: laws.latch(t, initial.holding_torque)))
    ox, oy = laws.opening_anchor
    mOpeningAnchor = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=model.oGround, localPosition=[ox, oy, 0.0]))
    mbs.AddObject(it.ObjectConnectorSpringDamper(markerNumbers=[mOpeningAnchor, mF], stiffness=b.opening_spring.stiffness,
                                                 referenceLength=laws.opening_free_length, damping=0.0))
    vertical = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]  # local x (travel) along global y
    model.pole_nodes = []
    for i in range(n):
        nPole = mbs.AddNode(it.Node1D(referenceCoordinates=[0.0], initialCoordinates=[initial.pole_travel[i]],
                                      initialVelocities=[0.0]))
        oPole = mbs.AddObject(it.ObjectMass1D(nodeNumber=nPole, mass=b.poles.moving_mass,
                                              referencePosition=[laws.pin_rest[0], laws.pin_rest[1], 0.0],
                                              referenceRotation=vertical))
        mPolePin = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=oPole, localPosition=[0.0, 0.0, 0.0]))
        mPoleTravel = mbs.AddMarker(it.MarkerNodeCoordinate(nodeNumber=nPole, coordinate=0))

        def rod_uf(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, force):
            # deltaL = length - rest length: compression is -deltaL; tension positive
            return -push_rod_force(-deltaL, -deltaL_t, b.poles)

        mbs.AddObject(it.ObjectConnectorSpringDamper(markerNumbers=[mF, mPolePin], referenceLength=b.poles.push_rod_length,
                                                     springForceUserFunction=rod_uf))

        def pole_uf(mbs, t, itemNumber, deltaL, deltaL_t, stiffness, damping, offset, i=i):
            return laws.pole_contact(i, deltaL, deltaL_t, impact[i + 1])

        mbs.AddObject(it.ObjectConnectorCoordinateSpringDamper(
            markerNumbers=[model.mGroundCoordinate, mPoleTravel], springForceUserFunction=pole_uf,
            visualization=it.VObjectConnectorCoordinateSpringDamper(show=False)))
        mbs.AddLoad(it.LoadCoordinate(markerNumber=mPoleTravel, load=laws.pole_load))
        for name, output in (("", exu.OutputVariableType.Coordinates), ("_velocity", exu.OutputVariableType.Coordinates_t)):
            model.sensors[f"pole_{i + 1}_travel{name}"] = mbs.AddSensor(it.SensorNode(
                nodeNumber=nPole, outputVariableType=output, storeInternal=True, writeToFile=False))
        model.pole_nodes.append(nPole)

    coordinates, velocities = exu.OutputVariableType.Coordinates, exu.OutputVariableType.Coordinates_t

    def latch_impact_speeds(mbs, t):
        theta, omega = mbs.GetNodeOutput(nCam, coordinates), mbs.GetNodeOutput(nCam, velocities)
        phi, phi_dot = mbs.GetNodeOutput(nFollower, coordinates), mbs.GetNodeOutput(nFollower, velocities)
        z = [mbs.GetNodeOutput(nPole, coordinates) for nPole in model.pole_nodes]
        z_dot = [mbs.GetNodeOutput(nPole, velocities) for nPole in model.pole_nodes]
        laws.latch_impact_speeds(impact, theta, omega, phi, phi_dot, z, z_dot)
        return True

    mbs.SetPreStepUserFunction(latch_impact_speeds)
    model.laws, model.initial, model.nFollower = laws, initial, nFollower
    return model


def update_impact_speeds(impact, state):
    """While contact k is open (penetration <= 0) its impact speed follows the approach speed
    (m/s); once it penetrates, the last open value is kept: the speed at impact."""
    for k, (penetration, rate) in enumerate(state):
        if penetration <= 0.0:
            impact[k] = max(rate, 0.0)


def follower_displacement(phi, follower, phi0):
    """Travel (m) of the output point F along the poles' closing direction (+y) from rest."""
    return np.array([output_point(p, follower)[1] for p in np.atleast_1d(phi)]) - output_point(phi0, follower)[1]


def closing_channels(model, data, rig, spec, step):
    """SimulationResult of a closing: the recorded states and the forces evaluated from them."""
    from .runner import SimulationResult

    laws, b = model.laws, rig.breaker
    t = data["angle"][:, 0]
    ch = {"cam_angle": data["angle"][:, 1], "shaft_velocity": data["velocity"][:, 1],
          "follower_angle": data["follower_angle"][:, 1], "follower_velocity": data["follower_velocity"][:, 1]}
    if "friction_torque" in data:
        ch["friction_torque"] = -data["friction_torque"][:, 1]
    ch["follower_displacement"] = follower_displacement(ch["follower_angle"], b.follower, model.initial.follower_angle)
    n = b.poles.count
    for i in range(n):
        ch[f"pole_{i + 1}_travel"] = data[f"pole_{i + 1}_travel"][:, 1]
        ch[f"pole_{i + 1}_velocity"] = data[f"pole_{i + 1}_travel_velocity"][:, 1]
    for name, d in data.items():
        if name.startswith(("spring_mass_", "spring_velocity_", "ancf_")):
            ch[name + "_x"], ch[name + "_y"] = d[:, 1], d[:, 2]
    ch.update(contact_channels(laws, ch, n))
    return SimulationResult(t, ch, rig.experiment, spec, {"backend": "exudyn", "step": step,
                                                          "initial": model.initial})


def contact_channels(laws, ch, n):
    """Cam-roller force, pole contact forces and rod forces (N), penetrations (m), with the
    impact speeds replayed over the samples (exact when sampled at every step)."""
    m = len(ch["cam_angle"])
    impact = np.zeros(n + 1)
    out = {"cam_roller_force": np.zeros(m), "cam_roller_penetration": np.zeros(m),
           "cam_roller_penetration_rate": np.zeros(m),
           "cam_roller_damping_force": np.zeros(m), "pressure_angle": np.zeros(m)}
    for i in range(n):
        for key in ("contact_force", "contact_damping_force", "rod_force", "rod_compression", "rod_rate"):
            out[f"pole_{i + 1}_{key}"] = np.zeros(m)
    law = laws.b.contact
    for j in range(m):
        th, w, phi, phid = ch["cam_angle"][j], ch["shaft_velocity"][j], ch["follower_angle"][j], ch["follower_velocity"][j]
        zs = [(ch[f"pole_{i + 1}_travel"][j], ch[f"pole_{i + 1}_velocity"][j]) for i in range(n)]
        c = laws.latch_impact_speeds(impact, th, w, phi, phid, [z for z, _ in zs], [zd for _, zd in zs])
        force = laws.roller(th, w, phi, phid, impact[0])[1]
        out["cam_roller_force"][j] = force
        out["cam_roller_penetration"][j] = c.penetration
        out["cam_roller_penetration_rate"][j] = c.penetration_rate
        out["pressure_angle"][j] = c.pressure_angle
        elastic = law.cam_roller_stiffness * max(c.penetration, 0.0) ** law.exponent
        out["cam_roller_damping_force"][j] = force - elastic if force > 0 else 0.0
        for i, (z, zd) in enumerate(zs):
            f = laws.pole_contact(i, z, zd, impact[i + 1])
            pen = z - laws.gaps[i]
            out[f"pole_{i + 1}_contact_force"][j] = f
            out[f"pole_{i + 1}_contact_damping_force"][j] = f - law.pole_stiffness * pen ** law.exponent if f > 0 else 0.0
            s, rate, _, rod = laws.rod(phi, phid, z, zd)
            out[f"pole_{i + 1}_rod_force"][j] = rod
            out[f"pole_{i + 1}_rod_compression"][j] = s
            out[f"pole_{i + 1}_rod_rate"][j] = rate
    return out


def energy_balance(result, rig, chain=None):
    """Energy bookkeeping of a closing (J), from the recorded states (massless or lumped spring).

    Returns a dict of time series: ``kinetic``, ``potential`` (closing springs, cam weight,
    opening spring, push rods and wipe springs, contacts, pole loads), ``dissipated`` (shaft
    friction, contact damping, rod damping), ``latch_work`` and ``residual`` =
    E(t) + dissipated - latch_work - E(0), which is zero for an exact solution.
    """
    ch, t = result.channels, result.t
    laws = BreakerLaws(rig, result.spec)
    b, cam, spring, g = rig.breaker, rig.cam, rig.closing_spring, rig.gravity
    n, c = b.poles.count, spring.count
    th, w, phi, phid = ch["cam_angle"], ch["shaft_velocity"], ch["follower_angle"], ch["follower_velocity"]
    kinetic = 0.5 * cam.inertia_pivot * w**2 + 0.5 * b.follower.inertia * phid**2
    bx, by = cam.pivot[0] + cam.arm_length * np.cos(th), cam.pivot[1] + cam.arm_length * np.sin(th)
    if chain is None:
        length = np.hypot(bx - spring.anchor[0], by - spring.anchor[1])
        springs = 0.5 * c * spring.stiffness * (length - spring.free_length) ** 2
    else:
        pts = [np.stack([np.full_like(th, spring.anchor[0]), np.full_like(th, spring.anchor[1])])]
        for k, m in enumerate(chain.masses, start=1):
            pts.append(np.stack([ch[f"spring_mass_{k}_x"], ch[f"spring_mass_{k}_y"]]))
            kinetic = kinetic + 0.5 * c * m * (ch[f"spring_velocity_{k}_x"] ** 2 + ch[f"spring_velocity_{k}_y"] ** 2)
        pts.append(np.stack([bx, by]))
        springs = sum(0.5 * c * k * (np.hypot(*(p1 - p0)) - l0) ** 2
                      for p0, p1, k, l0 in zip(pts[:-1], pts[1:], chain.stiffnesses, chain.free_lengths))
    cam_weight = cam.mass * g * cam.com_distance * np.sin(th - cam.com_angle)
    opening = np.array([0.5 * b.opening_spring.stiffness * (laws.opening(p)[0] / b.opening_spring.stiffness) ** 2
                        for p in phi])
    law = b.contact
    contacts = np.array([contact_energy(p, law.cam_roller_stiffness, law.exponent) for p in ch["cam_roller_penetration"]])
    rods = np.zeros_like(th)
    poles = np.zeros_like(th)
    dissipation = np.zeros_like(th)
    if "friction_torque" in ch:  # the channel is the friction's torque on the cam (opposes w)
        dissipation -= ch["friction_torque"] * w
    dissipation += ch["cam_roller_damping_force"] * ch["cam_roller_penetration_rate"]
    for i in range(n):
        z, zd = ch[f"pole_{i + 1}_travel"], ch[f"pole_{i + 1}_velocity"]
        kinetic = kinetic + 0.5 * b.poles.moving_mass * zd**2
        rods += np.array([push_rod_energy(s, b.poles) for s in ch[f"pole_{i + 1}_rod_compression"]])
        contacts += np.array([contact_energy(zz - laws.gaps[i], law.pole_stiffness, law.exponent) for zz in z])
        poles -= laws.pole_load * z
        dissipation += ch[f"pole_{i + 1}_contact_damping_force"] * zd
        dissipation += b.poles.rod_damping * ch[f"pole_{i + 1}_rod_rate"] ** 2
    holding = result.info["initial"].holding_torque
    latch_work = cumulative_trapezoid(np.array([laws.latch(tt, holding) for tt in t]) * w, t, initial=0.0)
    potential = springs + cam_weight + opening + rods + contacts + poles
    dissipated = cumulative_trapezoid(dissipation, t, initial=0.0)
    total = kinetic + potential
    return {"t": t, "kinetic": kinetic, "potential": potential, "closing_springs": springs, "opening_spring": opening,
            "wipe_and_rods": rods, "contacts": contacts, "dissipated": dissipated, "latch_work": latch_work,
            "residual": total + dissipated - latch_work - total[0],
            "spring_energy_released": springs[0] - springs}


def figures_of_merit(result, rig):
    """Closing figures of merit from a result (SI units; times from the latch release)."""
    ch, t = result.channels, result.t
    b = rig.breaker
    gaps = pole_gaps(b.poles)
    touches, speeds, bounces, bounce_times = [], [], [], []
    for i, gap in enumerate(gaps):
        z, zd = ch[f"pole_{i + 1}_travel"], ch[f"pole_{i + 1}_velocity"]
        closed = z > gap
        if not closed.any():
            touches.append(None)
            speeds.append(None)
            bounces.append(0)
            bounce_times.append(0.0)
            continue
        k = int(np.argmax(closed))
        frac = (gap - z[k - 1]) / (z[k] - z[k - 1]) if k > 0 else 0.0
        touches.append(float(t[k - 1] + frac * (t[k] - t[k - 1])) if k > 0 else float(t[0]))
        speeds.append(float(zd[k - 1] + frac * (zd[k] - zd[k - 1])) if k > 0 else float(zd[0]))
        opens = np.nonzero(closed[k:-1] & ~closed[k + 1:])[0]  # separations after the first touch
        bounces.append(int(opens.size))
        if opens.size:
            recloses = np.nonzero(~closed[k:-1] & closed[k + 1:])[0]
            bounce_times.append(float(t[k + recloses[-1] + 1] - touches[-1]) if recloses.size else float(t[-1] - touches[-1]))
        else:
            bounce_times.append(0.0)
    travel = ch["follower_displacement"]
    done = [x for x in touches if x is not None]
    at_touch = float(np.interp(min(done), t, travel)) if done else float("nan")
    return {
        "closing_time_s": max(done) if len(done) == len(gaps) else None,
        "first_touch_s": min(done) if done else None,
        "pole_spread_s": (max(done) - min(done)) if len(done) == len(gaps) else None,
        "touch_speed_m_s": float(np.mean([s for s in speeds if s is not None])) if done else None,
        "bounce_count": int(max(bounces)),
        "bounce_duration_s": float(max(bounce_times)),
        "final_travel_m": float(travel[-1]),
        "overtravel_m": float(np.max(travel) - at_touch) if done else None,  # follower travel after first touch
        "overshoot_m": float(np.max(travel) - travel[-1]),
        "peak_cam_roller_force_N": float(np.max(ch["cam_roller_force"])),
        "roller_lift_off_s": float(np.sum(np.diff(t) * (ch["cam_roller_force"][1:] <= 0.0))),
        "max_pressure_angle_deg": float(np.degrees(np.max(ch["pressure_angle"]))),
        "per_pole": {"touch_s": touches, "touch_speed_m_s": speeds, "bounces": bounces, "bounce_duration_s": bounce_times},
    }

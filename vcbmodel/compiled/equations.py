"""The equations of motion of the pendulum and the cam drop, assembled from the law functions.

These are the models the Exudyn builders make (:mod:`vcbmodel.builders.pendulum`,
:mod:`vcbmodel.builders.cam_drop`), written as accelerations of the same coordinates: the shaft
angle (rad) and, for a lumped spring, the chain's mass points (x, y in m). Every force comes
from a function of :mod:`vcbmodel.laws` called with ``ops``, so the compiled code
(:mod:`.codegen`) evaluates exactly what the Exudyn user functions evaluate; what Exudyn adds
itself (the weight loads, the spring connectors, the rotating body's kinematics) is what these
functions state, and the tests compare the two to 1e-9 rad.

Each ``*_equations(t, q, v, inputs, ops)`` returns (accelerations, outputs): ``q``, ``v`` the
coordinates and their speeds, ``inputs`` the objects of :func:`pendulum_inputs` /
:func:`cam_drop_inputs`; outputs are {name: value} recorded beside the state (the friction
torque T_f in N m, the value Exudyn's friction connector reports).
"""
from __future__ import annotations

from ..laws.friction import shaft_friction
from ..laws.mechanics import cam_inertia, cam_loads, cam_pin, link_pull, massless_spring_force, pendulum_loads


def pendulum_inputs(rig, law, chain=None):
    """What the pendulum's equations read."""
    return {"pendulum": rig.pendulum, "gravity": rig.gravity, "law": law}


def pendulum_initial(rig, chain=None):
    """(q0, v0): the release angle (rad) and speed (rad/s)."""
    return [rig.pendulum.initial_angle], [rig.pendulum.initial_velocity]


def pendulum_equations(t, q, v, inputs, ops):
    """Paper eq. 1 with the shaft friction of eq. 2-6: I theta'' = -M g L sin(theta) - T_f."""
    p, law = inputs["pendulum"], inputs["law"]
    theta, omega = q[0], v[0]
    Tc, R0x, R0y, R1x, R1y = pendulum_loads(theta, omega, p.mass, p.com_distance, inputs["gravity"], ops)
    Tf = shaft_friction(omega, Tc, R0x, R0y, R1x, R1y, p.inertia, law, ops)[0]
    return [(Tc - Tf) / p.inertia], {"friction_torque": Tf}


def cam_drop_inputs(rig, law, chain=None):
    """What the cam drop's equations read; ``chain``: the lumped chain (None: massless)."""
    inputs = {"cam": rig.cam, "spring": rig.closing_spring, "gravity": rig.gravity, "law": law}
    if chain is not None:
        inputs["chain"] = {"masses": chain.masses, "stiffnesses": chain.stiffnesses,
                           "free_lengths": chain.free_lengths, "pin_mass": chain.pin_mass}
    return inputs


def cam_drop_initial(rig, chain=None):
    """(q0, v0): the cam's release angle and speed, and the chain's masses at rest on the line
    O-B in static equilibrium (as the Exudyn builder places them)."""
    cam, spring = rig.cam, rig.closing_spring
    q0, v0 = [cam.initial_angle], [cam.initial_velocity]
    if chain is not None:
        bx, by = cam_pin(cam.initial_angle, cam)
        ox, oy = spring.anchor
        for frac in chain.equilibrium_fractions():
            q0 += [ox + frac * (bx - ox), oy + frac * (by - oy)]
            v0 += [0.0, 0.0]
    return q0, v0


def cam_drop_equations(t, q, v, inputs, ops):
    """Paper eq. 9-13: the cam pulled at B by the closing springs (massless, eq. 9-10, or a
    lumped chain, eq. 7-8 generalised), with the shaft friction of eq. 2-6 and eq. 13."""
    cam, spring, g, law = inputs["cam"], inputs["spring"], inputs["gravity"], inputs["law"]
    theta, omega = q[0], v[0]
    bx, by = cam_pin(theta, cam, ops)
    chain = inputs.get("chain")
    accelerations = []
    pin_mass = 0.0
    if chain is None:
        fx, fy = massless_spring_force(bx, by, spring, ops)
    else:
        fx, fy, accelerations = _chain_accelerations(q, bx, by, spring, chain, g, ops)
        pin_mass = spring.count * chain["pin_mass"]
    Tc, R0x, R0y, R1x, R1y = cam_loads(theta, omega, cam, fx, fy, g, ops, pin_mass, spring.weight)
    inertia = cam_inertia(cam, pin_mass)
    Tf = shaft_friction(omega, Tc, R0x, R0y, R1x, R1y, inertia, law, ops)[0]
    return [(Tc - Tf) / inertia] + accelerations, {"friction_torque": Tf}


def _chain_accelerations(q, bx, by, spring, chain, g, ops):
    """The chain O -> masses -> B of ``spring.count`` springs side by side (count times the
    masses and stiffnesses): the last link's pull on B (N) and the masses' accelerations (m/s^2)."""
    c = spring.count
    points = [tuple(spring.anchor)] + [(q[1 + 2 * i], q[2 + 2 * i]) for i in range(len(chain["masses"]))] + [(bx, by)]
    pulls = [link_pull(*points[i], *points[i + 1], c * chain["stiffnesses"][i], chain["free_lengths"][i], ops)
             for i in range(len(points) - 1)]
    accelerations = []
    for i, m in enumerate(chain["masses"]):
        fx = pulls[i][0] - pulls[i + 1][0]  # pulled back by its own link, forward by the next
        fy = pulls[i][1] - pulls[i + 1][1]
        if spring.weight:
            fy = fy - c * m * g
        accelerations += [fx / (c * m), fy / (c * m)]
    return pulls[-1][0], pulls[-1][1], accelerations

"""The equations of motion of the pendulum and the cam drop, assembled from the law functions.

These are the models the Exudyn builders make (:mod:`vcbmodel.builders.pendulum`,
:mod:`vcbmodel.builders.cam_drop`), written as accelerations of the same coordinates: the shaft
angle (rad) and, for a lumped spring, the chain's mass points (x, y in m). Every force comes
from a function of :mod:`vcbmodel.laws` called with ``ops``, so the compiled code
(:mod:`.codegen`) evaluates exactly what the Exudyn user functions evaluate; what Exudyn adds
itself (the weight loads, the spring connectors, the rotating body's kinematics) is what these
functions state, and the tests compare the two to 1e-9 rad.

Each ``*_equations(t, q, v, memory, inputs, ops)`` returns (accelerations, outputs): ``q``, ``v``
the coordinates and their speeds, ``memory`` the values latched at the step's start (the
breaker's impact speeds), ``inputs`` the objects its ``prepare_*`` function gathered; outputs are
{name: value} recorded beside the state (the friction torque T_f in N m, the value Exudyn's
friction connector reports).
"""
from __future__ import annotations

from collections.abc import Sequence

from ..laws.breaker import BreakerLaws, massless_pull, pin_weight_torque
from ..laws.cycle import CycleLaws, closed_state
from ..laws.making_current import MakingLaws
from ..laws.discovered import discovered_torque
from ..laws.friction import shaft_friction
from ..laws.mechanics import (aerodynamic_drag_torque, cam_inertia, cam_loads, cam_pin, cam_pin_velocity, link_pull,
                              massless_spring_force, pendulum_loads)
from ..laws.springs import kelvin_voigt_time
from ..laws.types import Ops, Scalar
from . import OdeSetup

SHAFT = [("angle", "velocity", 1)]


def prepare_pendulum(rig, spec, law, chain=None) -> OdeSetup:
    """The pendulum's inputs and its release angle (rad) and speed (rad/s)."""
    p = rig.pendulum
    inputs = {"pendulum": p, "gravity": rig.gravity, "law": law, "discovered": tuple(spec.discovered)}
    if spec.drag:  # only when carried: the other runs keep their compiled structure
        inputs["drag"] = spec.drag
    return OdeSetup(inputs, [p.initial_angle], [p.initial_velocity], list(SHAFT))


def pendulum_equations(t: Scalar, q: Sequence[Scalar], v: Sequence[Scalar], memory: list, inputs: dict,
                       ops: Ops) -> tuple[list[Scalar], dict[str, Scalar]]:
    """Paper eq. 1 with the shaft friction of eq. 2-6: I theta'' = -M g L sin(theta) + T_d + T_a - T_f,
    T_d a discovered torque (:mod:`vcbmodel.laws.discovered`), T_a air drag
    (:func:`~vcbmodel.laws.mechanics.aerodynamic_drag_torque`); each none unless the model carries it."""
    p, law = inputs["pendulum"], inputs["law"]
    theta, omega = q[0], v[0]
    Tc, R0x, R0y, R1x, R1y = pendulum_loads(theta, omega, p.mass, p.com_distance, inputs["gravity"], ops)
    if inputs.get("discovered"):
        Tc = Tc + discovered_torque(t, theta, omega, inputs["discovered"], ops)
    if "drag" in inputs:
        Tc = Tc + aerodynamic_drag_torque(omega, inputs["drag"], ops)
    Tf = shaft_friction(omega, Tc, R0x, R0y, R1x, R1y, p.inertia, law, ops, t)[0]
    return [(Tc - Tf) / p.inertia], {"friction_torque": Tf}


def prepare_cam_drop(rig, spec, law, chain=None) -> OdeSetup:
    """The cam drop's inputs; the cam's release angle and speed, and the chain's masses at rest
    on the line O-B in static equilibrium (as the Exudyn builder places them)."""
    cam, spring = rig.cam, rig.closing_spring
    inputs = {"cam": cam, "spring": spring, "gravity": rig.gravity, "law": law}
    if spec.discovered:  # only when carried: the other runs keep their compiled structure
        inputs["discovered"] = tuple(spec.discovered)
    if spec.spring_damping:  # Kelvin-Voigt time beta (s) of the springs' internal damping
        inputs["spring_beta"] = kelvin_voigt_time(spec.spring_damping, spring.stiffness, spring.mass)
    q0, v0, layout = [cam.initial_angle], [cam.initial_velocity], list(SHAFT)
    if chain is not None:
        inputs["chain"] = {"masses": chain.masses, "stiffnesses": chain.stiffnesses,
                           "free_lengths": chain.free_lengths, "pin_mass": chain.pin_mass}
        bx, by = cam_pin(cam.initial_angle, cam)
        ox, oy = spring.anchor
        for k, frac in enumerate(chain.equilibrium_fractions()):
            q0 += [ox + frac * (bx - ox), oy + frac * (by - oy)]
            v0 += [0.0, 0.0]
            layout.append((f"spring_mass_{k + 1}", f"spring_velocity_{k + 1}", 2))
    return OdeSetup(inputs, q0, v0, layout)


def cam_drop_equations(t: Scalar, q: Sequence[Scalar], v: Sequence[Scalar], memory: list, inputs: dict,
                       ops: Ops) -> tuple[list[Scalar], dict[str, Scalar]]:
    """Paper eq. 9-13: the cam pulled at B by the closing springs (massless, eq. 9-10, or a
    lumped chain, eq. 7-8 generalised), with the shaft friction of eq. 2-6 and eq. 13; a
    discovered torque T_d (:mod:`vcbmodel.laws.discovered`, N m; none unless the model carries
    one) joins the applied torque about A (a pure torque: no force on the shaft)."""
    extra = (0.0, 0.0, 0.0)
    if inputs.get("discovered"):
        extra = (discovered_torque(t, q[0], v[0], inputs["discovered"], ops), 0.0, 0.0)
    accelerations, Tf = _cam_and_chain(t, q, v, inputs, ops, extra)
    return accelerations, {"friction_torque": Tf}


def _cam_and_chain(t, q, v, inputs, ops, extra):
    """Accelerations of the cam (rad/s^2) and the chain's masses (m/s^2) and the friction torque
    (N m); ``extra`` = (torque about A in N m, Fx, Fy in N): other loads on the cam (the
    breaker's roller and latch), which enter the applied torque and the shaft reaction."""
    cam, spring, g, law = inputs["cam"], inputs["spring"], inputs["gravity"], inputs["law"]
    theta, omega = q[0], v[0]
    bx, by = cam_pin(theta, cam, ops)
    chain = inputs.get("chain")
    accelerations = []
    pin_mass = 0.0
    beta = inputs.get("spring_beta")
    pin_velocity = cam_pin_velocity(theta, omega, cam, ops) if beta is not None else None
    if chain is None and beta is None:
        fx, fy = massless_spring_force(bx, by, spring, ops)
    elif chain is None:
        fx, fy = massless_spring_force(bx, by, spring, ops, beta * spring.count * spring.stiffness, pin_velocity)
    else:
        fx, fy, accelerations = _chain_accelerations(q, v, bx, by, spring, chain, g, ops, beta, pin_velocity)
        pin_mass = spring.count * chain["pin_mass"]
    Tc, R0x, R0y, R1x, R1y = cam_loads(theta, omega, cam, fx, fy, g, ops, pin_mass, spring.weight)
    Tc, R0x, R0y = Tc + extra[0], R0x - extra[1], R0y - extra[2]
    inertia = cam_inertia(cam, pin_mass)
    Tf = shaft_friction(omega, Tc, R0x, R0y, R1x, R1y, inertia, law, ops, t)[0]
    return [(Tc - Tf) / inertia] + accelerations, Tf


def _chain_accelerations(q, v, bx, by, spring, chain, g, ops, beta=None, pin_velocity=None):
    """The chain O -> masses -> B of ``spring.count`` springs side by side (count times the
    masses and stiffnesses): the last link's pull on B (N) and the masses' accelerations (m/s^2).
    ``beta`` (s): each link's Kelvin-Voigt damping beta k_i (None: undamped); ``pin_velocity`` (m/s): B's."""
    c = spring.count
    n = len(chain["masses"])
    points = [tuple(spring.anchor)] + [(q[1 + 2 * i], q[2 + 2 * i]) for i in range(n)] + [(bx, by)]
    if beta is None:
        pulls = [link_pull(*points[i], *points[i + 1], c * chain["stiffnesses"][i], chain["free_lengths"][i], ops)
                 for i in range(len(points) - 1)]
    else:
        speeds = [(0.0, 0.0)] + [(v[1 + 2 * i], v[2 + 2 * i]) for i in range(n)] + [tuple(pin_velocity)]
        pulls = [link_pull(*points[i], *points[i + 1], c * chain["stiffnesses"][i], chain["free_lengths"][i], ops,
                           beta * c * chain["stiffnesses"][i], (*speeds[i], *speeds[i + 1]))
                 for i in range(len(points) - 1)]
    accelerations = []
    for i, m in enumerate(chain["masses"]):
        fx = pulls[i][0] - pulls[i + 1][0]  # pulled back by its own link, forward by the next
        fy = pulls[i][1] - pulls[i + 1][1]
        if spring.weight:
            fy = fy - c * m * g
        accelerations += [fx / (c * m), fy / (c * m)]
    return pulls[-1][0], pulls[-1][1], accelerations

def prepare_closing(rig, spec, law, chain=None) -> OdeSetup:
    """The breaker's inputs (its laws, with the derived geometry, and the latch's holding
    torque) and its static rest held by the latch (:meth:`BreakerLaws.initial_state`), as the
    Exudyn builder computes them; memory: the contacts' impact speeds (m/s), from zero, and with
    a holding latch (``breaker.hold_latch``) its engagement (0 not yet, 1 engaged) after them."""
    laws = BreakerLaws.of_rig(rig, spec)
    pin_mass = chain.pin_mass if chain is not None else 0.0
    initial = laws.initial_state(massless_pull(rig.cam, rig.closing_spring),
                                 pin_weight_torque(rig.cam, rig.closing_spring, pin_mass, rig.gravity))
    cycle = CycleLaws(laws, initial.follower_angle)
    if cycle.commands.start_closed:
        initial = closed_state(laws, cycle, initial)
    setup = prepare_cam_drop(rig, spec, law, chain)
    setup.inputs.update({"laws": vars(laws), "holding": initial.holding_torque})
    if cycle.active:  # only when the rig has cycle parts: the closing keeps its compiled structure
        setup.inputs["cycle"] = dict(vars(cycle), making=vars(cycle.making) if cycle.making is not None else None)
    n, free = rig.breaker.poles.count, laws.free_levers
    setup.q0 += [initial.follower_angle] + list(initial.lever_angles) + list(initial.pole_travel)
    setup.v0 += [0.0] * (1 + len(free) + n)
    setup.layout += [("follower_angle", "follower_velocity", 1)]
    setup.layout += [(f"pole_{j + 1}_lever_angle", f"pole_{j + 1}_lever_velocity", 1) for j in free]
    setup.layout += [(f"pole_{i + 1}_travel", f"pole_{i + 1}_travel_velocity", 1) for i in range(n)]
    setup.memory = [0.0] * (n + 1) + ([0.0] if rig.breaker.hold_latch is not None else [])
    setup.memory += cycle.initial_memory() if cycle.active else []
    setup.info = {"initial": initial}
    return setup


def _breaker_laws(inputs):
    laws = BreakerLaws.__new__(BreakerLaws)  # the traced values, not a recomputed geometry
    laws.__dict__.update(inputs["laws"])
    return laws


def _cycle_laws(inputs) -> CycleLaws | None:
    """The traced :class:`CycleLaws` (None when the rig has no cycle part)."""
    values = inputs.get("cycle")
    if values is None:
        return None
    cycle = CycleLaws.__new__(CycleLaws)
    cycle.__dict__.update(values)
    if values["making"] is not None:
        cycle.making = MakingLaws.__new__(MakingLaws)
        cycle.making.__dict__.update(values["making"])
    return cycle


def _cycle_memory_start(laws) -> int:
    """Where the cycle parts' memory starts: after the impact speeds and the holding latch's engagement."""
    return laws.b.poles.count + 1 + (1 if laws.b.hold_latch is not None else 0)


def _split(q, v, laws):
    """The breaker's part of the state: (index of the follower's angle, (phi, phi'), (free levers'
    angles, speeds), (pole travels, speeds)); the cam and its springs come before it."""
    n_poles, m = laws.b.poles.count, len(laws.free_levers)
    i = len(q) - 1 - m - n_poles
    return i, (q[i], v[i]), (q[i + 1:i + 1 + m], v[i + 1:i + 1 + m]), (q[i + 1 + m:], v[i + 1 + m:])


def closing_equations(t: Scalar, q: Sequence[Scalar], v: Sequence[Scalar], memory: list, inputs: dict,
                      ops: Ops) -> tuple[list[Scalar], dict[str, Scalar]]:
    """The whole breaker (paper section 4): the cam and its springs as in the cam drop, loaded
    by the roller and the latch; the follower (roller contact, opening spring, the drive pole's
    push rod or every rod on a rigid shaft); with a main shaft the other pole levers (their rods,
    the shaft's segments: :meth:`BreakerLaws.lever_torques`); each pole (push rod on its lever,
    fixed contact, bellows force minus weight)."""
    laws, cycle = _breaker_laws(inputs), _cycle_laws(inputs)
    n_poles = laws.b.poles.count
    phi_index, (phi, phi_dot), (psi, psi_dot), (z, z_dot) = _split(q, v, laws)
    theta, omega = q[0], v[0]
    t_fol, t_levers, (t_cam, fx, fy) = laws.lever_torques(theta, omega, phi, phi_dot, psi, psi_dot, z, z_dot,
                                                          memory[0], ops)
    t_close = t
    if cycle is not None:
        touch, trip = cycle.split(memory[_cycle_memory_start(laws):])
        t_close = t - cycle.close_at
        if cycle.trip_latch is not None:  # a tripped trip-free link carries only its share of the roller's push
            drop = 1.0 - cycle.link(t, trip, ops)
            r_cam, r_fol, r_x, r_y = laws.roller_loads(theta, omega, phi, phi_dot, memory[0], ops)
            t_fol, t_cam, fx, fy = t_fol - drop * r_fol, t_cam - drop * r_cam, fx - drop * r_x, fy - drop * r_y
        t_fol = t_fol + cycle.follower_torque(t, phi, phi_dot, trip, ops)
    t_latch, lx, ly = laws.latch_loads(t_close, theta, inputs["holding"], ops)
    engaged = memory[n_poles + 1] if laws.b.hold_latch is not None else 0.0
    loads = laws.with_stops((t_cam + t_latch, fx + lx, fy + ly), theta, omega, engaged, ops)
    cam_chain, Tf = _cam_and_chain(t, q[:phi_index], v[:phi_index], inputs, ops, loads)
    a, a_dot = laws.lever_angles(phi, psi), laws.lever_angles(phi_dot, psi_dot)
    poles = []
    for i in range(n_poles):
        rod_force = laws.rod_loads(a[i], a_dot[i], z[i], z_dot[i], ops)[0]
        contact = laws.pole_contact(i, z[i], z_dot[i], memory[i + 1], ops)
        if cycle is not None and cycle.making is not None:
            contact = contact + cycle.repulsion(i, t, touch, z[i], ops)
        poles.append((rod_force - contact + laws.pole_load) / laws.b.poles.moving_mass)
    levers = [torque / laws.lever_inertia for torque in t_levers]
    return cam_chain + [t_fol / laws.follower_inertia] + levers + poles, {"friction_torque": Tf}


def closing_prestep(t: Scalar, q: Sequence[Scalar], v: Sequence[Scalar], memory: list, inputs: dict, ops: Ops) -> list[Scalar]:
    """The contacts' impact speeds latched from the state at the step's start
    (:meth:`BreakerLaws.latch_impact_speeds`), and the holding latch's engagement
    (:meth:`BreakerLaws.engage`) when the rig has one."""
    laws, cycle = _breaker_laws(inputs), _cycle_laws(inputs)
    n_poles = laws.b.poles.count
    _, (phi, phi_dot), _, (z, z_dot) = _split(q, v, laws)
    impact = list(memory[:n_poles + 1])
    roller = laws.latch_impact_speeds(impact, q[0], v[0], phi, phi_dot, z, z_dot, ops)
    if laws.b.hold_latch is not None:
        impact.append(laws.engage(memory[n_poles + 1], q[0], ops))
    if cycle is not None:
        impact += cycle.update(memory[_cycle_memory_start(laws):], t, phi, z, roller.penetration, ops)
    return impact

"""Exudyn model of the cam drop (paper section 3, eq. 9-13) with massless or lumped closing
springs; :func:`build_cam_drop` also dispatches the ANCF spring (:mod:`.ancf`), so the
spring-model decision is made here once for the cam drop and the whole breaker.

Lumped spring masses are ``MassPoint2D`` joined by ``ObjectConnectorSpringDamper``; the
``count`` identical springs act in the same plane, so one chain with ``count`` times the
masses and stiffnesses represents them.
"""
from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

from ..laws.mechanics import cam_pin, cam_pin_velocity, link_pull, massless_spring_force
from ..laws.springs import kelvin_voigt_time
from .ancf import build_cam_drop_ancf
from .core import ExudynModel, add_cam_body, add_cam_friction, exudyn_modules

if TYPE_CHECKING:
    from ..laws.friction import FrictionLaw
    from ..laws.springs import LumpedChain
    from ..rig.data import Rig
    from ..rig.spring_model import SpringModel
    from .ancf import AncfOptions


def build_cam_drop(rig: Rig, law: FrictionLaw, spring_model: SpringModel, chain: LumpedChain | None = None, user_function: str = "auto",
                   extra_loads: Callable | None = None, ancf_elements: AncfOptions | int | None = None,
                   discovered: tuple = (), spring_damping: float = 0.0) -> ExudynModel:
    """The cam of eq. 11-13 pulled at pin B by the closing springs of ``spring_model``
    (:class:`vcbmodel.rig.spring_model.SpringModel`; ``chain``: the lumped chain,
    :class:`vcbmodel.laws.springs.LumpedChain`; ``ancf_elements``: the ANCF spring's element count
    or :class:`~vcbmodel.builders.ancf.AncfOptions`). ``extra_loads``: see
    :func:`vcbmodel.builders.core.add_cam_friction`. ``discovered``: a discovered torque T_d on the
    cam shaft, ((term, coefficient), ...) (:mod:`vcbmodel.laws.discovered`), part of the applied
    torque the friction law sees. ``spring_damping``: the springs' internal damping, the first surge
    mode's damping ratio (Kelvin-Voigt, :func:`vcbmodel.laws.springs.kelvin_voigt_time`: each
    connector's damping beta times its stiffness; 0: none). Sensors: ``angle``, ``velocity``, ``friction_torque``
    (``discovered_torque`` with T_d), ``spring_mass_k`` and ``spring_velocity_k`` (lumped) or
    ``ancf_node_k`` (ANCF)."""
    if spring_model.kind == "ancf":
        return build_cam_drop_ancf(rig, law, user_function, ancf_elements, extra_loads, discovered, spring_damping)
    exu, it = exudyn_modules()
    cam, spring = rig.cam, rig.closing_spring
    model = ExudynModel()
    mbs = model.mbs
    c = spring.count
    beta = kelvin_voigt_time(spring_damping, spring.stiffness, spring.mass) if spring_damping else 0.0
    body = model.cam_body = add_cam_body(model, rig, c * chain.pin_mass if chain is not None else 0.0)
    if chain is None:
        damping = beta * c * spring.stiffness
        mbs.AddObject(it.ObjectConnectorSpringDamper(markerNumbers=[body.mAnchor, body.mPin], stiffness=c * spring.stiffness,
                                                     referenceLength=spring.free_length, damping=damping))

        def pin_force(theta, omega, ops):
            bx, by = cam_pin(theta, cam, ops)
            if damping:
                return massless_spring_force(bx, by, spring, ops, damping, cam_pin_velocity(theta, omega, cam, ops))
            return massless_spring_force(bx, by, spring, ops)

        # auto: the Python user function. The symbolic one recomputes the pin force and its sqrt at every
        # use (Exudyn's evaluator is a tree interpreter) and measured 4.8x slower here (exudyn-notes)
        uf = "python" if user_function == "auto" else user_function
    else:
        pin_force = _add_chain(model, rig, body, chain, beta)
        uf = "python" if user_function == "auto" else user_function
    if uf == "symbolic" and (chain is not None or extra_loads is not None):
        raise ValueError("a lumped spring's or the breaker's friction needs the Python user function")
    add_cam_friction(model, rig, law, body, pin_force, uf, extra_loads, discovered)
    return model


def _add_chain(model, rig, body, chain, beta=0.0):
    """The lumped chain O -> masses -> B, each link damped by ``beta`` (s) times its stiffness;
    returns the pin-force function for the friction."""
    exu, it = exudyn_modules()
    cam, spring, g = rig.cam, rig.closing_spring, rig.gravity
    mbs, c = model.mbs, spring.count
    bx0, by0 = cam_pin(cam.initial_angle, cam)
    ox, oy = spring.anchor
    previous = body.mAnchor
    nodes = []
    for frac, m in zip(chain.equilibrium_fractions(), chain.masses):
        nMass = mbs.AddNode(it.NodePoint2D(referenceCoordinates=[ox + frac * (bx0 - ox), oy + frac * (by0 - oy)]))
        oMass = mbs.AddObject(it.MassPoint2D(nodeNumber=nMass, mass=c * m))
        mMass = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=oMass, localPosition=[0.0, 0.0, 0.0]))
        if spring.weight:
            mbs.AddLoad(it.LoadForceVector(markerNumber=mMass, loadVector=[0.0, -c * m * g, 0.0]))
        nodes.append(nMass)
        k = len(nodes)
        model.add_sensor(f"spring_mass_{k}", nMass, "Position")
        model.add_sensor(f"spring_velocity_{k}", nMass, "Velocity")
        mbs.AddObject(it.ObjectConnectorSpringDamper(markerNumbers=[previous, mMass], damping=beta * c * chain.stiffnesses[k - 1],
                                                     stiffness=c * chain.stiffnesses[k - 1],
                                                     referenceLength=chain.free_lengths[k - 1]))
        previous = mMass
    k_last, l_last = c * chain.stiffnesses[-1], chain.free_lengths[-1]
    mbs.AddObject(it.ObjectConnectorSpringDamper(markerNumbers=[previous, body.mPin], damping=beta * k_last,
                                                 stiffness=k_last, referenceLength=l_last))
    nLast = nodes[-1]
    position, velocity = exu.OutputVariableType.Position, exu.OutputVariableType.Velocity

    def pin_force(theta, omega, ops):
        # last segment's pull on B, from the last mass's position (and speed) at this RK stage
        px, py = mbs.GetNodeOutput(nLast, position)[:2]
        bx, by = cam_pin(theta, cam, ops)
        if beta:
            vx, vy = mbs.GetNodeOutput(nLast, velocity)[:2]
            return link_pull(px, py, bx, by, k_last, l_last, ops, beta * k_last,
                             (vx, vy, *cam_pin_velocity(theta, omega, cam, ops)))
        return link_pull(px, py, bx, by, k_last, l_last, ops)

    return pin_force

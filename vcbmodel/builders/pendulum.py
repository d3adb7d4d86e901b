"""Exudyn model of the pendulum test (paper section 2, eq. 1, 5, 6)."""
from __future__ import annotations

from typing import TYPE_CHECKING

from ..laws.discovered import discovered_torque
from ..laws.friction import shaft_friction
from ..laws.mechanics import aerodynamic_drag_torque, pendulum_loads
from .core import ExudynModel, add_discovered_torque, add_drag_torque, add_friction_connector, add_shaft
from .exudyn_loader import exudyn_modules

if TYPE_CHECKING:
    from ..laws.friction import FrictionLaw
    from ..rig.data import Rig


def build_pendulum(rig: Rig, law: FrictionLaw, user_function: str = "symbolic", discovered: tuple = (),
                   drag: float = 0.0) -> ExudynModel:
    """Pendulum of eq. 1 on the shaft coordinate; the weight M g acts at distance L.
    ``user_function``: friction connector as 'symbolic' (compiled), 'python' or 'none'.
    ``discovered``: a discovered torque T_d, ((term, coefficient), ...) (:mod:`vcbmodel.laws.discovered`):
    applied by a connector of its own (recorded as ``discovered_torque``, N m, the torque the connector
    applies against the shaft: -T_d) and part of the applied torque the friction law sees. ``drag``: air
    drag c_d (N m s^2/rad^2; :func:`~vcbmodel.builders.core.add_drag_torque`), likewise."""
    exu, it = exudyn_modules()
    p, g = rig.pendulum, rig.gravity
    model = ExudynModel()
    mbs = model.mbs
    shaft = add_shaft(model, p.inertia, p.initial_angle, p.initial_velocity)
    mWeight = mbs.AddMarker(it.MarkerBodyPosition(bodyNumber=shaft.body, localPosition=[0.0, -p.com_distance, 0.0]))
    mbs.AddLoad(it.LoadForceVector(markerNumber=mWeight, loadVector=[0.0, -p.mass * g, 0.0]))
    kind = "symbolic" if user_function == "auto" else user_function

    def friction_of_state(t, theta, omega, ops):
        Tc, R0x, R0y, R1x, R1y = pendulum_loads(theta, omega, p.mass, p.com_distance, g, ops)
        if discovered:
            Tc = Tc + discovered_torque(t, theta, omega, discovered, ops)
        if drag:
            Tc = Tc + aerodynamic_drag_torque(omega, drag, ops)
        return shaft_friction(omega, Tc, R0x, R0y, R1x, R1y, p.inertia, law, ops, t)[0]

    add_discovered_torque(model, shaft, discovered, kind)
    add_drag_torque(model, shaft, drag, kind)
    add_friction_connector(model, shaft, friction_of_state, kind, state_only=True)  # a function of (t, theta, omega)
    return model

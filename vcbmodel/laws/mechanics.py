"""Loads and shaft reactions of the two experiments, as pure functions.

Each function returns the applied torque ``T_c`` (N m, about the shaft, without friction)
and the shaft reaction written as ``R = R0 + R1 theta''`` (R0 in N, R1 in N s^2/rad), the
inputs of :func:`vcbmodel.friction.shaft_friction`. ``ops`` selects float or Exudyn
symbolic arithmetic, so the Exudyn user functions evaluate exactly these formulas.
"""
from __future__ import annotations

from ..parameters import AIR_DENSITY, FLAT_PLATE_DRAG_COEFFICIENT
from .friction import NumericOps
from .types import Ops, Scalar


def pendulum_loads(theta: Scalar, omega: Scalar, mass: Scalar, com_distance: Scalar, gravity: Scalar,
                   ops: Ops = NumericOps) -> tuple[Scalar, Scalar, Scalar, Scalar, Scalar]:
    """Pendulum (paper eq. 1, 5, 6): T_c = -M g L sin(theta).

    The reaction is expressed in the link frame: normal F_om = M g cos(th) + M L th'^2,
    tangential F_ot = M g sin(th) + M L th'' (eq. 6). Returns (T_c, R0x, R0y, R1x, R1y).
    """
    M, L, g = mass, com_distance, gravity
    s, c = ops.sin(theta), ops.cos(theta)
    return -M * g * L * s, M * g * c + M * L * omega * omega, M * g * s, 0.0, M * L


def cam_pin(theta: Scalar, cam, ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
    """Spring pin B = A + l_AB (cos th, sin th) (m)."""
    return (cam.pivot[0] + cam.arm_length * ops.cos(theta),
            cam.pivot[1] + cam.arm_length * ops.sin(theta))


def link_pull(x0: Scalar, y0: Scalar, x1: Scalar, y1: Scalar, stiffness: Scalar, free_length: Scalar, ops: Ops = NumericOps,
              damping: Scalar = 0.0, velocity: tuple | None = None) -> tuple[Scalar, Scalar]:
    """Pull (N) of a straight linear spring from point 0 to point 1 (m) on point 1, towards
    point 0: tension k (L - L0) along the link (an axial spring of stiffness ``stiffness`` in N/m
    and free length ``free_length`` in m; what Exudyn's ``ObjectConnectorSpringDamper`` applies).
    With ``velocity`` = (vx0, vy0, vx1, vy1) (m/s) the tension adds ``damping`` d (N s/m) times the
    link's stretching speed dL/dt = (dx dvx + dy dvy) / L (a Kelvin-Voigt link: the connector's
    ``damping``). Point 0 feels the opposite force."""
    dx, dy = x1 - x0, y1 - y0
    length = ops.sqrt(dx * dx + dy * dy)
    tension = stiffness * (length - free_length)
    if velocity is not None:
        vx0, vy0, vx1, vy1 = velocity
        tension = tension + damping * (dx * (vx1 - vx0) + dy * (vy1 - vy0)) / length
    return -tension * dx / length, -tension * dy / length


def massless_spring_force(bx: Scalar, by: Scalar, spring, ops: Ops = NumericOps, damping: Scalar = 0.0,
                          pin_velocity: tuple | None = None) -> tuple[Scalar, Scalar]:
    """Pull (N) of ``spring.count`` massless tension springs on pin B, along B -> O. With
    ``pin_velocity`` (vx, vy of B, m/s) the springs' internal damping ``damping`` (N s/m, all springs:
    :func:`vcbmodel.laws.springs.kelvin_voigt_time` times count k0) adds to the tension."""
    velocity = None if pin_velocity is None else (0.0, 0.0, pin_velocity[0], pin_velocity[1])
    return link_pull(spring.anchor[0], spring.anchor[1], bx, by, spring.count * spring.stiffness,
                     spring.free_length, ops, damping, velocity)


def cam_pin_velocity(theta: Scalar, omega: Scalar, cam, ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
    """Velocity (m/s) of pin B turning with the cam at ``omega`` (rad/s): omega e_z x (B - A)."""
    return -omega * cam.arm_length * ops.sin(theta), omega * cam.arm_length * ops.cos(theta)


def aerodynamic_drag_torque(omega: Scalar, drag: Scalar, ops: Ops = NumericOps) -> Scalar:
    """Air drag on a body turning with the shaft: T_a = -c_d w|w| (N m), ``drag`` c_d in
    N m s^2/rad^2, ``omega`` w in rad/s (a quadratic drag at Reynolds numbers where Cd is constant;
    for a paddle c_d = 0.5 rho Cd A R^3, :func:`paddle_drag_coefficient`)."""
    return -drag * omega * ops.abs(omega)


def paddle_drag_coefficient(area: float, radius: float, drag_coefficient: float = FLAT_PLATE_DRAG_COEFFICIENT,
                            air_density: float = AIR_DENSITY) -> float:
    """c_d = 0.5 rho Cd A R^3 (N m s^2/rad^2) of a flat paddle of area ``area`` (m^2) whose centre
    turns at ``radius`` (m) from the shaft, broadside to its motion (Cd and rho: vcbmodel.parameters)."""
    return 0.5 * air_density * drag_coefficient * area * radius**3


def cam_weight_torque(theta: Scalar, cam, gravity: Scalar, ops: Ops = NumericOps) -> Scalar:
    """Torque (N m) of the cam's weight about A: -m_c g l_g cos(theta - psi) (eq. 12)."""
    return -cam.mass * gravity * cam.com_distance * ops.cos(theta - cam.com_angle)


def cam_loads(theta: Scalar, omega: Scalar, cam, spring_force_x: Scalar, spring_force_y: Scalar, gravity: Scalar, ops: Ops = NumericOps,
              pin_mass: float = 0.0, pin_weight: bool = False) -> tuple[Scalar, Scalar, Scalar, Scalar, Scalar]:
    """Cam (paper eq. 11-13) with a force (N) on pin B from the closing springs.

    T_c = r_AB x F_s - m_c g l_g cos(th - psi) (eq. 12). The shaft's reaction on the cam is
    R = m_c a_G - F_s - m_c g_vec with a_G = th'' e_z x r_G - th'^2 r_G (eq. 13, with the
    centripetal term th'^2). ``pin_mass`` (kg): the springs' mass riding on pin B (spec
    "lumped_convention"), moving with the cam: it adds m_pin a_B to the reaction and, with
    ``pin_weight``, its weight to the torque and the reaction; its inertia m_pin l_AB^2 belongs
    in the cam's inertia (:func:`cam_inertia`). Returns (T_c, R0x, R0y, R1x, R1y).
    """
    ca, sa = ops.cos(theta), ops.sin(theta)
    rbx, rby = cam.arm_length * ca, cam.arm_length * sa
    phi = theta - cam.com_angle
    rgx, rgy = cam.com_distance * ops.cos(phi), cam.com_distance * ops.sin(phi)
    mc, g = cam.mass, gravity
    torque = rbx * spring_force_y - rby * spring_force_x + cam_weight_torque(theta, cam, g, ops)
    R0x = -mc * omega * omega * rgx - spring_force_x
    R0y = -mc * omega * omega * rgy - spring_force_y + mc * g
    R1x, R1y = -mc * rgy, mc * rgx
    if pin_mass:
        R0x = R0x - pin_mass * omega * omega * rbx
        R0y = R0y - pin_mass * omega * omega * rby
        R1x, R1y = R1x - pin_mass * rby, R1y + pin_mass * rbx
        if pin_weight:
            torque = torque - pin_mass * g * rbx
            R0y = R0y + pin_mass * g
    return torque, R0x, R0y, R1x, R1y


def cam_inertia(cam, pin_mass: float = 0.0) -> float:
    """Inertia (kg m^2) of the cam about A with the springs' pin mass: I_c + m_c l_g^2 + m_pin l_AB^2."""
    return cam.inertia_pivot + pin_mass * cam.arm_length**2


def shaft_torsional_stiffness(diameter: Scalar, shear_modulus: Scalar, bore: Scalar = 0.0) -> Scalar:
    """G J (N m^2) of a round shaft: J = pi (d^4 - d_i^4) / 32 (diameter d and bore d_i in m, G in Pa)."""
    return shear_modulus * 3.141592653589793 * (diameter**4 - bore**4) / 32.0


def main_shaft_twist(pole_torques: list[float], pitch: float, diameter: float, shear_modulus: float,
                     bore: float = 0.0) -> list[float]:
    """Twist (rad) of each pole lever on a main shaft relative to the first lever, the shaft driven at
    the first lever's side (the worst case): the shaft between levers i and i+1 (``pitch`` m apart)
    carries the torques (N m) of the poles beyond it, so it twists by (sum of those) pitch / (G J)
    (:func:`shaft_torsional_stiffness`). A lever's travel error at the pole is its twist times the
    lever arm."""
    gj = shaft_torsional_stiffness(diameter, shear_modulus, bore)
    twist, out = 0.0, [0.0]
    for i in range(1, len(pole_torques)):
        twist += sum(pole_torques[i:]) * pitch / gj
        out.append(twist)
    return out

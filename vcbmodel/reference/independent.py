"""A reference solve of the pendulum and cam-drop experiments that shares no code with the model.

Why this exists
---------------
The Exudyn model (and the older ``reference`` solve, which reuses the model's loads and friction
law) must be checked against something written separately from the equations. This module and its
three parts import nothing from :mod:`vcbmodel` except :class:`vcbmodel.errors.SimulationError`
and each other; they depend only on numpy, scipy and sympy. What they share with the model is
the reading of the spec: the friction law and its values, the planar layout (pivot A, pin B,
spring anchor O, gravity along -y) and a lumped spring chain's numbers (given by the caller).

Modules
-------
* this one: the public API (:func:`pendulum`, :func:`cam_drop`), input checks and the output;
* :mod:`.independent_lagrange`: the sympy Lagrange derivation and the mechanisms (pendulum, cam
  with a spring chain) with their Newton-Euler shaft reactions;
* :mod:`.independent_friction`: the friction law in speed regimes and the friction/acceleration
  coupling (Brent);
* :mod:`.independent_hybrid`: the event-driven hybrid integration (slip regimes, sticking,
  breakaway) and the sampling of its segments.

Units: SI throughout. Lengths in m, masses in kg, inertias in kg m^2, times in s, angles in rad
(counter-clockwise positive), angular velocities in rad/s, torques in N m, forces in N,
stiffnesses in N/m, viscous coefficients in N m s/rad, gravity in m/s^2 (acting along -y).

Method
------
* Equations of motion: Lagrange's equations, derived once per model structure with sympy from the
  kinetic and potential energies in the generalised coordinates (theta, x_1, y_1, ..., x_n, y_n),
  with the shaft friction torque as the generalised force -Tf on theta, then lambdified.
  ``M(q) q'' + h(q, q') = Q`` with ``Q = (-Tf, 0, ..., 0)``.
* Shaft reaction: Newton-Euler on the rotating body, written separately from the Lagrangian
  (pendulum: paper eq. 5-6; cam: sum of forces on cam + pin mass = m_c a_G + m_pin a_B, with the
  spring pull on B, the weights and the bearing force at A). The reaction is linear in theta'':
  F = R0 + R1 theta''.
* Friction/acceleration coupling: Fn = |R0 + R1 theta''| and theta'' depends on Tf(Fn); the scalar
  equation theta'' = a_free - b Tf(Fn(theta'')) is solved with Brent's method on a bracket that is
  guaranteed to contain the unique root when |b mu r R1| < 1 (otherwise the problem is ill-posed
  and SimulationError is raised).
* Friction law (spec "The shaft friction law", passive sticking): an event-driven hybrid
  integration with scipy's DOP853 at tight tolerances.
    - slip mode, sign s = sign(w), in a speed regime: band (|w| <= w0): Tf = mu_s r Fn s;
      Stribeck (w0 < |w| < ws): Tf = (mu_s - (mu_s - mu_k)|w|/ws) r Fn s; kinetic (otherwise):
      Tf = mu_k r Fn s + Cv (w - ws' s), ws' = ws if a Stribeck velocity is given, else 0.
      Regime boundaries are terminal events, so each integration segment has a smooth right-hand
      side (no discontinuity inside a DOP853 step).
    - w reaching 0: the shaft sticks if |Tc| <= mu_s r Fn0 (Fn0: the reaction with w = 0 and
      theta'' = 0); otherwise it continues slipping in the direction of Tc.
    - stuck mode: theta frozen, w = 0 exactly, Tf = Tc (the torque needed to hold it); the spring
      masses (if any) keep moving, and the event |Tc| = mu_s r Fn0 (rising) breaks the shaft away
      in the direction of Tc.
    - starting from rest: stuck if static friction can hold, else break away.
  With this, a stuck shaft does not creep at all and friction never does positive work.

Public API: :func:`pendulum`, :func:`cam_drop`; both return a dict of numpy arrays.
"""
from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np
from numpy.typing import ArrayLike

from vcbmodel.errors import SimulationError

from .independent_friction import FRICTION_KEYS, FrictionLaw, coupled_acceleration
from .independent_hybrid import MAX_SEGMENTS, ConstantSol, Hybrid, Segment
from .independent_lagrange import CamMechanism, Equations, PendulumMechanism, cam_equations, lagrange, pendulum_equations

__all__ = ["pendulum", "cam_drop", "RTOL", "ATOL", "MAX_SEGMENTS", "FRICTION_KEYS", "FrictionLaw",
           "coupled_acceleration", "Hybrid", "Segment", "ConstantSol", "CamMechanism", "PendulumMechanism",
           "Equations", "lagrange", "pendulum_equations", "cam_equations"]

#: Default DOP853 tolerances (relative, absolute). Absolute tolerance applies to every state
#: component (rad, rad/s, m, m/s).
RTOL = 1e-11
ATOL = 1e-12


# ----------------------------------------------------------------------------------------------
# solve and sample
# ----------------------------------------------------------------------------------------------
def _times(t_eval):
    t_eval = np.asarray(t_eval, float).ravel()
    if t_eval.size == 0 or not np.all(np.isfinite(t_eval)) or t_eval[0] < 0.0 or np.any(np.diff(t_eval) < 0.0):
        raise ValueError("independent reference: t_eval must be a non-empty, finite, non-decreasing array of times >= 0")
    return t_eval


def _run(mech, law, q0, qd0, t_eval, rtol, atol):
    t_eval = _times(t_eval)
    hybrid = Hybrid(mech, law, rtol, atol)
    try:
        segments, events = hybrid.run(q0, qd0, float(t_eval[-1]))
        out, Q, QD = hybrid.sample(segments, t_eval)
    except (ArithmeticError, np.linalg.LinAlgError) as exc:
        raise SimulationError(f"independent reference: {type(exc).__name__}: {exc}") from exc
    except ValueError as exc:  # brentq bracket failure (no sign change) from a non-finite state
        raise SimulationError(f"independent reference: {exc}") from exc
    out["events"] = events
    out["segments"] = [(seg.t0, seg.t1, seg.mode if seg.mode == "stuck" else f"slip{seg.s:+d}:{law.kinds[seg.regime]}")
                       for seg in segments]
    return out, Q, QD


# ----------------------------------------------------------------------------------------------
# public API
# ----------------------------------------------------------------------------------------------
def pendulum(mass: float, inertia: float, com_distance: float, gravity: float, radius: float,
             friction: Mapping[str, float] | None, theta0: float, omega0: float, t_eval: ArrayLike, *,
             rtol: float = RTOL, atol: float = ATOL) -> dict[str, Any]:
    """Pendulum test (paper eq. 1, 5, 6): I th'' + M g L sin th + Tf = 0.

    Parameters
    ----------
    mass : M (kg), the swinging mass.
    inertia : I (kg m^2) about the shaft axis.
    com_distance : L (m), shaft axis to centre of mass.
    gravity : g (m/s^2).
    radius : journal radius r (m).
    friction : dict with any of ``mu_s``, ``mu_k`` (-), ``stick_velocity`` w0 (rad/s),
        ``stribeck_velocity`` ws (rad/s), ``viscous`` Cv (N m s/rad) or ``zeta`` (damping ratio,
        Cv = 2 zeta sqrt(I M g L)); missing keys are 0, ``mu_s`` defaults to ``mu_k``.
    theta0, omega0 : initial angle from hanging straight down (rad) and angular velocity (rad/s).
    t_eval : output times (s), non-decreasing, >= 0; the solve starts at t = 0.
    rtol, atol : DOP853 tolerances.

    Returns
    -------
    dict with arrays over ``t`` (s): ``theta`` (rad), ``omega`` (rad/s), ``friction_torque`` Tf
    (N m, the torque in eq. 1, opposing motion), ``stuck`` (bool), ``alpha`` (rad/s^2),
    ``normal_force`` Fn (N), ``applied_torque`` Tc = -M g L sin th (N m); and ``events`` (list of
    dicts: t, kind in start_stuck/start/stick/reversal/restart/breakaway, theta) and ``segments``
    (t0, t1, mode).
    """
    M, I, L, g = float(mass), float(inertia), float(com_distance), float(gravity)
    if not all(math.isfinite(v) and v > 0.0 for v in (M, I, L, g)):
        raise ValueError("independent reference: pendulum mass, inertia, com_distance and gravity must be > 0")
    law = FrictionLaw(friction, radius, zeta_to_viscous=lambda z: 2.0 * z * math.sqrt(I * M * g * L))
    mech = PendulumMechanism(M, I, L, g)
    out, _, _ = _run(mech, law, [float(theta0)], [float(omega0)], t_eval, rtol, atol)
    return out


def cam_drop(cam: Mapping[str, Any], spring: Mapping[str, Any], gravity: float, radius: float,
             friction: Mapping[str, float] | None, t_eval: ArrayLike, *, rtol: float = RTOL,
             atol: float = ATOL) -> dict[str, Any]:
    """Cam drop (paper eq. 9-13, generalised to n spring masses and a pin mass).

    Parameters
    ----------
    cam : dict ``mass`` m_c (kg), ``inertia_com`` I_c (kg m^2, about the centre of mass),
        ``com_distance`` l_g (m), ``com_angle`` psi (rad; centre of mass at A + l_g (cos(th - psi),
        sin(th - psi))), ``pivot`` A (m, (x, y)), ``arm_length`` l_AB (m; pin B = A + l_AB (cos th,
        sin th)), ``initial_angle`` (rad, A->B from +x), ``initial_velocity`` (rad/s, default 0).
    spring : dict ``count`` (identical springs acting in the plane, lumped as one with count times
        stiffnesses and masses), ``anchor`` O (m), ``stiffness`` k0 (N/m) and ``free_length`` (m) of
        each spring for the massless model, ``chain``: None (massless) or a dict ``masses`` (kg, n
        per spring), ``stiffnesses`` (N/m, n+1 per spring, O side first), ``free_lengths`` (m, n+1),
        ``positions`` (n x 2 initial positions, m; masses start at rest), ``pin_mass`` (kg per
        spring, rides on B); ``weight`` (bool, default False): spring and pin masses carry weight.
    gravity : g (m/s^2), along -y.
    radius : journal radius r (m).
    friction : as for :func:`pendulum` (``zeta`` not accepted).
    t_eval : output times (s), non-decreasing, >= 0; the solve starts at t = 0.

    Returns
    -------
    dict as for :func:`pendulum` (``applied_torque`` Tc: spring + gravity torque about A, N m;
    ``normal_force``: bearing force at A, N), plus ``mass_positions`` and ``mass_velocities``
    (len(t) x n x 2; m, m/s).
    """
    try:
        mech = CamMechanism(cam, spring, gravity)
    except KeyError as exc:
        raise ValueError(f"independent reference: cam or spring dict lacks the key {exc}") from None
    law = FrictionLaw(friction, radius)
    n = mech.n
    q0 = [float(cam["initial_angle"])] + mech.initial_positions.ravel().tolist()
    qd0 = [float(cam.get("initial_velocity", 0.0))] + [0.0] * (2 * n)
    out, Q, QD = _run(mech, law, q0, qd0, t_eval, rtol, atol)
    out["mass_positions"] = Q[:, 1:].reshape(len(Q), n, 2)
    out["mass_velocities"] = QD[:, 1:].reshape(len(Q), n, 2)
    return out

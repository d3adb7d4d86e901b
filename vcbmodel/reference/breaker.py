"""An independent solve of the whole breaker's closing, written again from the equations.

Why this exists
---------------
:class:`vcbmodel.reference.solve.BreakerExtension` integrates the model's own
:class:`vcbmodel.laws.breaker.BreakerLaws`: agreement with Exudyn checks only the wiring. This
module and its ``breaker_*`` parts share no code with the model: they import nothing from
``vcbmodel.laws`` (nor from the builders, the other references or the evaluation), only
:mod:`vcbmodel.errors` and each other; the geometry, the contact laws, the friction law and the
equations of motion are written here a second time. It reads the loaded rig's data
(plain attributes) and the model spec's values, and solves the lumped chain from the spring's own
numbers (:mod:`.breaker_chain`, by another method than the model's).

What is different on purpose
----------------------------
* **Exact roller-to-profile distance.** The model takes the penetration of the roller as the
  pitch curve's normal offset at the roller's own polar angle, (rho(u) - rho_C) cos(gamma), exact
  to first order. Here the penetration is the signed minimum distance from the roller centre to
  the cam's pitch curve (the locus of roller centres at zero penetration), found numerically
  (Newton on the stationarity condition), and the force acts along the pitch curve's normal at
  the closest point. ``distance="first_order"`` uses the model's formula instead, to measure
  what the first-order offset costs.
* **Event-driven integration** (scipy's DOP853 on smooth segments): the shaft friction's speed
  regimes, the stuck shaft held by static friction (theta frozen, w = 0, no creep) and its
  breakaway, and the start of each Lankarani-Nikravesh contact (its impact speed is the exact
  approach speed at that instant) are events; the model instead latches impact speeds at the
  start of the RK4 step and catches sticking with a widened band.
* **The friction/reaction coupling** is a root solve for theta'' (Brent), not the model's closed
  form.

Equations (SI units; angles counter-clockwise; gravity along -y)
----------------------------------------------------------------
Coordinates: cam angle theta (direction of A->B), the closing springs' chain points p_k (``count``
identical springs lumped as one chain of ``count`` times the masses and stiffnesses), follower
angle phi (direction pivot->roller centre), pole travels z_i and, with an elastic main shaft
(rig section ``breaker.main_shaft``), the angles psi_j of the pole levers other than the drive
pole's.

* Cam (with the chain's pin mass m_pin riding on B): I_A theta'' = T_c - T_f,
  I_A = I_c + m_c l_g^2 + count m_pin l_AB^2; T_c = r_AB x F_spring + cam and pin weight torques +
  r_C x F_roller-on-cam + latch torque. Shaft reaction R = m_c a_G + count m_pin a_B - (every
  other force on the cam), a_P = theta'' e_z x r_P - theta'^2 r_P, so R = R0 + R1 theta''; the
  friction T_f (spec law with Karnopp band, Stribeck branch, viscous term) takes F_n = |R|.
* Chain point k: m_k p_k'' = (pulls of its two springs) (+ weight if ``closing_spring.weight``).
* Follower: I_f phi'' = torques of the roller force, the opening spring and the push rods.
* Main shaft (when the rig has ``breaker.main_shaft``; :mod:`.breaker_shaft`): pole i's lever
  angle a_i is phi at the drive pole, psi_i elsewhere; the segment between levers j and j+1 acts
  with T = k (a_j - a_{j+1}) + c (a_j' - a_{j+1}') (+T on lever j+1, -T on lever j),
  k = G pi (d^4 - d_i^4) / 32 / pitch. Follower: (I_f - (n-1) I_l) phi'' = roller, opening
  spring, the drive pole's rod and the segment on the drive lever; lever j: I_l psi_j'' = its rod
  + its segments. Without the section every lever is the follower (the rigid shaft, I_f whole).
* Pole i: m z_i'' = (rod force along F->pin)_y - contact force + bellows force - m g.
* Cam profile: pitch radius rho(u) = r_b + r_r + lift s, s the 4-5-6-7 polynomial
  35x^4 - 84x^5 + 70x^6 - 20x^7 on the rise, 1 - s on the return; the roller at polar angle beta
  (from A) sees u = theta - (beta - beta_rest).
* Contacts: Hertz point K delta^n or line K_L delta^(10/9) with Palmgren's K_L for a steel roller
  of length l: delta(mm) = 3.84e-5 Q^0.9 / l(mm)^0.8; damping Lankarani-Nikravesh
  (1 + 3 (1 - e^2)/4 delta'/max(v_impact, v_floor)) or Hunt-Crossley (1 + alpha delta'), clipped
  at zero force.
* Push rod: compression s = L_rod - |pin - F|, F the output point of the pole's own lever (the
  follower's output geometry at the lever's angle); force k_rod s below the wipe preload,
  preload + k_wipe (s - s0) above, plus c_rod s'. Opening spring: from its anchor below F0 to F.
* Latch: torque T_h (1 - t / t_r) for 0 < t < t_r as a force T / arm perpendicular to A->L at the
  latch point L = A + arm (cos(theta + angle), sin(theta + angle)).
* End stop and holding latch (when the rig has them): at arm a on A->B, perpendicular to it, a
  buffer force k d + c d' while its penetration d > 0, never negative; the stop's d = a (theta -
  angle), the latch's d = a (angle - theta) once the cam has reached the latch's angle. The start
  and end of each contact and the latch's engagement are events (the model: its RK4 step meets
  them, and keeps the engagement as memory from the step's start). Shared with the model: this
  reading of the rig's fields, nothing else.
* Start: the static rest held by the latch (follower on the base circle, rods at their rest
  compression, latch torque balancing the cam); with an elastic shaft every free lever in balance
  between its rod and the segments, and the follower's balance with the shaft's torque on the
  drive lever (a fixed point of the static shaft, not the model's initial state). Shared with the
  model for the shaft: the reading of ``breaker.main_shaft`` (linear segments k = G J / pitch
  with J of the hollow circle, damping c per segment, the drive pole's lever rigid with the
  follower, the follower keeping I_f - (n-1) I_l of the whole assembly's inertia, levers in pole
  order ``pole_pitch`` apart), nothing else.

Modules
-------
* this one: :func:`solve_closing`, the public API;
* :mod:`.breaker_geometry`: the cam profile, the follower and the rest geometry (kinematics);
* :mod:`.breaker_distance`: the roller-to-profile distance (exact and first-order);
* :mod:`.breaker_closing`: the closing's parameters, forces, friction coupling and rest state;
* :mod:`.breaker_shaft`: the elastic main shaft between the pole levers (segments, static rest);
* :mod:`.breaker_integration`: the event-driven integration (modes, events, sampling).

Public API: :func:`solve_closing`.
"""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .breaker_closing import PALMGREN, Closing
from .breaker_distance import closest_pitch_angle, first_order_rate, roller_contact
from .breaker_geometry import TWO_PI, Geometry, Profile
from .breaker_integration import MAX_SEGMENTS, ClosingRun, friction_state, rhs

__all__ = ["solve_closing", "Closing", "ClosingRun", "Geometry", "Profile", "roller_contact", "closest_pitch_angle",
           "first_order_rate", "rhs", "friction_state", "PALMGREN", "TWO_PI", "MAX_SEGMENTS"]


def solve_closing(rig: Any, spec: Any, t_eval: ArrayLike, *, distance: str = "exact",
                  rtol: float = 1e-10, atol: float = 1e-13) -> dict[str, Any]:
    """Solve a closing from the latch release (t = 0) without any of the model's code.

    Parameters
    ----------
    rig : a loaded ``vcb_closing`` rig (:func:`vcbmodel.experiments.loading.load_rig`).
    spec : the model spec (:func:`vcbmodel.experiments.simulation.model_spec`): effects, friction
        values (``mu_s``, ``mu_k``, ``stick_velocity``, ``stribeck_velocity``, ``viscous``),
        ``restitution`` and ``bellows_force``; its ``spring_model`` decides the closing springs:
        massless, or a lumped chain that the reference solves itself from the spring's k0, m0 and n
        (:mod:`.breaker_chain`).
    t_eval : output times (s), increasing, from 0.
    distance : ``exact`` (minimum distance to the pitch curve) or ``first_order`` (the model's).
    rtol, atol : DOP853 tolerances (atol scaled per state: 1 for angles and lengths in m).

    Returns
    -------
    dict of arrays over ``t`` (s): ``cam_angle`` (rad), ``shaft_velocity`` (rad/s),
    ``follower_angle`` (rad), ``follower_velocity`` (rad/s), ``follower_displacement`` (m, F's
    travel along +y from rest), ``pole_i_travel`` (m), ``pole_i_velocity`` (m/s),
    ``cam_roller_force`` (N), ``cam_roller_penetration`` (m), ``friction_torque`` (N m),
    ``normal_force`` (N); ``touch_times`` and ``touch_speeds`` (per pole, first contact, from the
    events; s, m/s), ``events`` (list of (t, kind)), ``initial`` (follower angle rad, pole
    travels m, holding torque N m; with an elastic shaft ``lever_angle``, rad per free pole);
    with an elastic main shaft also ``pole_j_lever_angle`` (rad) and ``pole_j_lever_velocity``
    (rad/s) for every pole j but the drive pole (the model's channel names).
    """
    mech = Closing(rig, spec, distance)
    t_eval = _check_times(t_eval)
    run = ClosingRun(mech, float(t_eval[-1]), rtol, atol)  # the latch's rest and the starting mode
    run.integrate()
    return run.output(t_eval)


def _check_times(t_eval: ArrayLike) -> np.ndarray:
    t_eval = np.asarray(t_eval, float)
    if t_eval.ndim != 1 or t_eval[0] < 0 or np.any(np.diff(t_eval) <= 0):
        raise ValueError("t_eval must be increasing times from 0")
    return t_eval

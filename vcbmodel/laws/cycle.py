"""The breaker's cycle parts gathered for one run: closing onto a fault, the trip latch and the
trip-free link, the opening dashpot and stop, and what the run commands.

:class:`CycleLaws` is to these parts what :class:`vcbmodel.laws.breaker.BreakerLaws` is to the
closing: one object, every force at a state, asked by the Exudyn builder
(:mod:`vcbmodel.builders.breaker`), the compiled equations (:mod:`vcbmodel.compiled.equations`)
and the evaluation. Its numbers are floats, so the compiled path traces them as parameters.

Memory (values latched from the state at the start of each step, after the closing's impact
speeds and holding-latch engagement): each pole's first-touch time (s; when the rig has a making
current or a trip latch), then, with a trip latch, the trip time (s), the pawl's engagement (0/1)
and the link's reset (0/1).
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import root

from ..errors import SimulationError
from .breaker import BreakerLaws, InitialState
from .cam_follower import output_point
from .friction import NumericOps
from .making_current import NOT_YET, MakingLaws, update_touch_time
from .opening import (CLOSE, NO_TRIP, dashpot_force, f_travel, link_factor, link_resets, open_stop_force, pawl_engagement,
                      pawl_force, travel_rate)
from .types import Ops, Scalar

#: The closing latch's release time (s) of a run that never closes (an O): far beyond any run
NEVER = 1e6
#: A time beyond any run (s): the "not yet" of a minimum over touch times
LATE = 1e9


class CycleLaws:
    """The cycle parts of a breaker (``laws.b``: its ``making_current``, ``trip_latch``,
    ``opening_dashpot`` and ``commands``) with the derived numbers: F's open-rest height ``y_open``
    (m; ``open_angle``: the follower's static open rest, rad, :meth:`BreakerLaws.initial_state`,
    where the roller presses into the cam under the opening spring), the closing latch's release
    instant ``close_at`` (s: 0, or NEVER for a run that does not close) and the making current's
    :class:`~vcbmodel.laws.making_current.MakingLaws` (a closing's; None for an O)."""

    def __init__(self, laws: BreakerLaws, open_angle: float) -> None:
        b = laws.b
        self.follower, self.gaps, self.n = b.follower, list(laws.gaps), b.poles.count
        self.y_open = float(output_point(open_angle, b.follower)[1])
        self.trip_latch, self.dashpot = b.trip_latch, b.opening_dashpot
        self.commands = b.commands if b.commands is not None else CLOSE
        # the making current flows in a closing: an O starts with its contacts closed, carrying no fault
        closes = b.making_current is not None and self.commands.close
        self.making = MakingLaws(b.making_current) if closes else None
        self.close_at = 0.0 if self.commands.close else NEVER
        self.trip_after_touch = self.commands.trip_after_touch

    @property
    def active(self) -> bool:
        """Whether the rig has any cycle part or the run commands more than a plain closing."""
        return (self.making is not None or self.trip_latch is not None or self.dashpot is not None
                or self.commands != CLOSE)

    @property
    def tracks_touch(self) -> bool:
        """Whether the memory keeps each pole's first-touch time (a making current or a trip latch)."""
        return self.making is not None or self.trip_latch is not None

    def initial_memory(self) -> list[float]:
        """The memory at the start: no pole touched; the trip time the commands set (an O: 0), the
        pawl engaged when the run starts closed, the link not reset."""
        out = [NOT_YET] * self.n if self.tracks_touch else []
        if self.trip_latch is not None:
            out += [float(self.commands.trip_time), 1.0 if self.commands.start_closed else 0.0, 0.0]
        return out

    def split(self, memory: Sequence) -> tuple[list, tuple]:
        """(touch times, (trip time, engaged, reset)) from this part of the memory (empty or 1.0s
        for the parts the rig lacks)."""
        touch = list(memory[:self.n]) if self.tracks_touch else []
        rest = memory[len(touch):]
        trip = (rest[0], rest[1], rest[2]) if self.trip_latch is not None else (NO_TRIP, 0.0, 1.0)
        return touch, trip

    # -- forces
    def travel(self, phi: Scalar, ops: Ops = NumericOps) -> Scalar:
        """F's travel u (m) from the open rest at follower angle phi (rad)."""
        return f_travel(phi, self.follower, self.y_open, ops)

    def link(self, t: Scalar, trip: tuple, ops: Ops = NumericOps) -> Scalar:
        """The trip-free link's share (1 .. 0) of the roller's push reaching the follower."""
        if self.trip_latch is None:
            return 1.0
        return link_factor(t, trip[0], trip[2], self.trip_latch.release_time, ops)

    def follower_force(self, t: Scalar, phi: Scalar, phi_dot: Scalar, trip: tuple, ops: Ops = NumericOps) -> Scalar:
        """Force (N, towards closed) on F of the pawl (held as much as the link), the opening dashpot
        and the open stop, for the parts the rig has."""
        rate = travel_rate(phi, self.follower, ops)
        u, u_dot = self.travel(phi, ops), rate * phi_dot
        force = 0.0
        if self.trip_latch is not None:
            force = force + pawl_force(u, u_dot, trip[1], self.link(t, trip, ops), self.trip_latch, ops)
        if self.dashpot is not None:
            force = force + dashpot_force(u, u_dot, self.dashpot, ops) + open_stop_force(u, u_dot, self.dashpot, ops)
        return force

    def follower_torque(self, t: Scalar, phi: Scalar, phi_dot: Scalar, trip: tuple, ops: Ops = NumericOps) -> Scalar:
        """Torque (N m) on the follower of :meth:`follower_force`: the force times du/dphi."""
        return self.follower_force(t, phi, phi_dot, trip, ops) * travel_rate(phi, self.follower, ops)

    def repulsion(self, i: int, t: Scalar, touch: Sequence, z: Scalar, ops: Ops = NumericOps) -> Scalar:
        """Holm's repulsion (N, along opening) on pole i (0-based) at travel z (m); 0 without a making current."""
        if self.making is None:
            return 0.0
        return self.making.repulsion(t, touch[i], z - self.gaps[i], ops)

    # -- memory
    def update(self, memory: Sequence, t: Scalar, phi: Scalar, z: Sequence, roller_penetration: Scalar,
               ops: Ops = NumericOps) -> list:
        """This part of the memory after a state at time t (s): touch times
        (:func:`update_touch_time`), a trip set ``trip_after_touch`` s after the first touch (a CO),
        the pawl's engagement (:func:`pawl_engagement`) and the link's reset (:func:`link_resets`)."""
        touch, (trip_time, engaged, reset) = self.split(memory)
        touch = [update_touch_time(touch[i], t, z[i] - self.gaps[i], ops) for i in range(len(touch))]
        if self.trip_latch is None:
            return touch
        if self.trip_after_touch >= 0.0:
            first = LATE
            for x in touch:
                first = ops.min(first, ops.where(x < 0.0, LATE, x))
            trip_time = ops.where(trip_time < 0.0, ops.where(first < LATE, first + self.trip_after_touch, NO_TRIP),
                                  trip_time)
        u = self.travel(phi, ops)
        new_reset = link_resets(reset, t, trip_time, u, roller_penetration, self.trip_latch, ops)
        # the reset link re-arms the pawl: not engaged until F passes its travel again
        engaged = ops.where(new_reset > reset, 0.0, pawl_engagement(engaged, u, self.trip_latch, ops))
        return touch + [trip_time, engaged, new_reset]


@dataclass
class ClosedState(InitialState):
    """:class:`InitialState` of a run that starts closed, with the open rest's follower angle (rad)."""

    open_follower_angle: float = 0.0


def open_angle(initial: InitialState) -> float:
    """The follower's open-rest angle (rad) of a run's initial state (closed or open)."""
    return getattr(initial, "open_follower_angle", initial.follower_angle)


def closed_state(laws: BreakerLaws, cycle: CycleLaws, open_state: InitialState) -> ClosedState:
    """The closed breaker at rest held by its trip latch, the closing springs charged (the cam at its
    start angle, held by the closing latch; the roller off the cam): the follower angle, the free
    levers' angles and the pole travels in which every pole rests on its fixed contact pressed by its
    rod, every lever and the follower balance (the pawl holding F), solved by Newton's method
    (scipy ``root``); the closing latch's holding torque is the open rest's less the roller's share
    there. ``open_state``: :meth:`BreakerLaws.initial_state`."""
    latch, theta, n, m = cycle.trip_latch, laws.cam.initial_angle, laws.b.poles.count, len(laws.free_levers)
    phi0 = math.asin((latch.travel + cycle.y_open - laws.b.follower.pivot[1]) / laws.b.follower.output_arm) \
        - laws.b.follower.output_angle
    trip = (NO_TRIP, 1.0, 0.0)

    def residual(x):
        phi, psi, z = x[0], list(x[1:1 + m]), list(x[1 + m:])
        t_fol, t_levers, _ = laws.lever_torques(theta, 0.0, phi, 0.0, psi, [0.0] * m, z, [0.0] * n)
        a = laws.lever_angles(phi, psi)
        poles = [laws.rod_loads(a[i], 0.0, z[i], 0.0)[0] - laws.pole_contact(i, z[i], 0.0) + laws.pole_load
                 for i in range(n)]
        return [(t_fol + cycle.follower_torque(0.0, phi, 0.0, trip)) / 100.0] + [x / 100.0 for x in t_levers] + poles

    x0 = [phi0] + [phi0] * m + [g + 2e-5 for g in laws.gaps]
    sol = root(residual, x0, method="hybr", options={"xtol": 1e-13})
    if not sol.success or np.max(np.abs(residual(sol.x))) > 1e-6:
        raise SimulationError(f"breaker: no closed rest on the trip latch ({sol.message}): check breaker.trip_latch's "
                              "travel against the contacts' gap and the wipe springs")
    phi, psi, z = float(sol.x[0]), [float(v) for v in sol.x[1:1 + m]], [float(v) for v in sol.x[1 + m:]]
    if any(zi <= g for zi, g in zip(z, laws.gaps)):
        raise SimulationError("breaker: with F on the trip latch's travel a pole does not reach its fixed contact: "
                              "breaker.trip_latch.travel must lie beyond the contacts' touch")
    _, _, (t_cam_open, _, _) = laws.rest_torques(theta, open_state.follower_angle, open_state.lever_angles)
    return ClosedState(phi, z, open_state.holding_torque + t_cam_open, psi, open_state.follower_angle)

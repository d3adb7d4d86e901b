"""The opening half of the cycle: the trip latch, the trip-free link, the opening dashpot and stop.

Every force here acts on the follower's output point F along the poles' closing direction (+y)
and is written against F's travel u (m, from the open rest, + towards closed) and its speed u'
(m/s). Its torque on the follower is the force times du/dphi = output_arm cos(phi + output_angle)
(virtual work: F's y coordinate turns with the follower angle phi).

- **Trip latch** (rig section ``breaker.trip_latch``, :class:`TripLatch`): a pawl that drops behind
  the main shaft's latch face once F passes ``travel`` closing, and from then on stops it falling
  back: a one-way stop at ``travel`` with ``stiffness`` and ``damping`` at F (:func:`pawl_force`).
  Whether it has engaged is memory kept from step to step, as the holding latch's is.
- **Trip and the trip-free link.** The pawl holds the main shaft through a toggle (the trip-free
  link between the roller's lever and the main shaft). The trip lets the pawl go, linearly over
  ``release_time`` from the trip instant (:func:`trip_holding`): the pawl's force and the roller's
  push on the follower both fall to zero with it, so a trip during a closing collapses the link and
  the contacts reopen whatever the cam does (IEC 62271-100's trip-free breaker). The link resets
  (the roller lever's return spring snaps the toggle straight) once F is back within
  ``reset_travel`` of open and the roller clears the cam (:func:`link_resets`); the pawl is then
  re-armed (not engaged until F passes ``travel`` again).
- **Opening dashpot** (rig section ``breaker.opening_dashpot``, :class:`OpeningDashpot`): an oil
  dashpot whose piston enters its cylinder ``stroke`` before the open position; it damps only
  the opening motion (a check valve lets it refill on closing) with ``damping`` times the opening
  speed, the damping rising linearly from zero over the first ``ramp`` of its stroke (the piston's
  metering grooves), so its force starts from zero (:func:`dashpot_force`). At the open position
  (u = 0) F meets the open stop (``stop_stiffness``, ``stop_damping``: :func:`open_stop_force`), the
  dashpot's end, beside the roller landing on the cam's base circle.
"""
from __future__ import annotations

from dataclasses import dataclass

from .friction import NumericOps
from .types import Ops, Scalar

#: The trip time before any trip (memory value): any negative number means "no trip yet"
NO_TRIP = -1.0


@dataclass(frozen=True)
class TripLatch:
    """The trip latch (rig section ``breaker.trip_latch``): ``travel`` (m, F's travel from open at
    which the pawl holds the main shaft), ``stiffness`` (N/m) and ``damping`` (N s/m) of the pawl
    at F, ``release_time`` (s, the pawl lets go linearly over it from the trip) and
    ``reset_travel`` (m, F's travel from open below which the tripped link resets)."""

    travel: float  # m
    stiffness: float  # N/m
    damping: float  # N s/m
    release_time: float  # s
    reset_travel: float  # m


@dataclass(frozen=True)
class OpeningDashpot:
    """The opening dashpot and the open stop (rig section ``breaker.opening_dashpot``): ``stroke``
    (m of F's travel before open where the piston enters), ``damping`` (N s/m at F, full),
    ``ramp`` (m over which the damping rises from zero), ``stop_stiffness`` (N/m) and
    ``stop_damping`` (N s/m) of the open stop at F's open position."""

    stroke: float  # m
    damping: float  # N s/m
    ramp: float  # m
    stop_stiffness: float  # N/m
    stop_damping: float  # N s/m


def pawl_force(u: Scalar, u_dot: Scalar, engaged: Scalar, holding: Scalar, latch: TripLatch, ops: Ops = NumericOps) -> Scalar:
    """Force (N, >= 0, towards closed) of the engaged pawl on F at travel ``u`` (m) and speed
    ``u_dot`` (m/s): penetration d = travel - u; k d - c u' while d > 0, clipped at zero, times
    ``engaged`` (0/1) and ``holding`` (1 held .. 0 let go, :func:`trip_holding`)."""
    d = latch.travel - u
    force = ops.where(d <= 0.0, 0.0, ops.max(0.0, latch.stiffness * d - latch.damping * u_dot))
    return ops.where(engaged <= 0.5, 0.0, force * holding)


def pawl_engagement(engaged: Scalar, u: Scalar, latch: TripLatch, ops: Ops = NumericOps) -> Scalar:
    """The pawl's memory (1 engaged, 0 not) after a state with F at travel ``u`` (m): it engages
    once F reaches ``travel`` and stays engaged."""
    return ops.where(u >= latch.travel, 1.0, engaged)


def trip_holding(t: Scalar, trip_time: Scalar, release_time: Scalar, ops: Ops = NumericOps) -> Scalar:
    """How much the tripped pawl and link still hold (1 .. 0) at time ``t`` (s): 1 before the trip
    at ``trip_time`` (s; negative: no trip), then falling linearly to 0 over ``release_time`` (s)."""
    elapsed = t - trip_time
    fraction = ops.min(1.0, ops.max(0.0, elapsed / ops.max(release_time, 1e-300)))
    return ops.where(trip_time < 0.0, 1.0, ops.where(elapsed < 0.0, 1.0, 1.0 - fraction))


def link_factor(t: Scalar, trip_time: Scalar, reset: Scalar, release_time: Scalar, ops: Ops = NumericOps) -> Scalar:
    """The trip-free link's share of the roller's push that reaches the follower (1 .. 0): the
    pawl's :func:`trip_holding` until the link has reset (``reset`` 1), then 1 again."""
    return ops.where(reset > 0.5, 1.0, trip_holding(t, trip_time, release_time, ops))


def link_resets(reset: Scalar, t: Scalar, trip_time: Scalar, u: Scalar, roller_penetration: Scalar, latch: TripLatch,
                ops: Ops = NumericOps) -> Scalar:
    """The link's reset memory (1 reset, 0 not) after a state at time ``t`` (s): it resets once a
    trip has fully let go (t >= trip_time + release_time), F is within ``reset_travel`` of open
    (u m) and the roller clears the cam (``roller_penetration`` m <= 0), and stays reset."""
    let_go = ops.where(trip_time < 0.0, 0.0, ops.where(t >= trip_time + latch.release_time, 1.0, 0.0))
    near_open = ops.where(u <= latch.reset_travel, 1.0, 0.0)
    clear = ops.where(roller_penetration <= 0.0, 1.0, 0.0)
    return ops.where(let_go * near_open * clear > 0.5, 1.0, reset)


def dashpot_force(u: Scalar, u_dot: Scalar, dashpot: OpeningDashpot, ops: Ops = NumericOps) -> Scalar:
    """Force (N, >= 0, towards closed) of the opening dashpot on F at travel ``u`` (m) and speed
    ``u_dot`` (m/s): inside its stroke (depth = stroke - u > 0) the damping rises linearly from 0 to
    ``damping`` over ``ramp`` of depth and multiplies the opening speed max(-u', 0)."""
    depth = dashpot.stroke - u
    share = ops.min(1.0, ops.max(0.0, depth / dashpot.ramp))
    return dashpot.damping * share * ops.max(0.0, -u_dot)


def open_stop_force(u: Scalar, u_dot: Scalar, dashpot: OpeningDashpot, ops: Ops = NumericOps) -> Scalar:
    """Force (N, >= 0, towards closed) of the open stop on F: penetration d = -u (m) beyond the
    open position, k d - c u' while d > 0, clipped at zero (it never pulls)."""
    d = -u
    return ops.where(d <= 0.0, 0.0, ops.max(0.0, dashpot.stop_stiffness * d - dashpot.stop_damping * u_dot))


def travel_rate(phi: Scalar, follower, ops: Ops = NumericOps) -> Scalar:
    """du/dphi (m/rad): how fast F's travel u (its y coordinate) changes with the follower angle
    phi (rad): output_arm cos(phi + output_angle)."""
    return follower.output_arm * ops.cos(phi + follower.output_angle)


def f_travel(phi: Scalar, follower, y_open: Scalar, ops: Ops = NumericOps) -> Scalar:
    """F's travel u (m) from the open rest (F's y coordinate ``y_open`` there) at follower angle phi."""
    return follower.pivot[1] + follower.output_arm * ops.sin(phi + follower.output_angle) - y_open


@dataclass(frozen=True)
class Commands:
    """What one operation's run commands (set by the sequence runner, :mod:`vcbmodel.experiments.sequence`;
    None on a breaker: the plain closing). ``close``: the closing latch is released at t = 0 (C, CO);
    otherwise it holds the cam for the whole run (O). ``start_closed``: the run starts from the closed
    breaker held by its trip latch, the closing springs charged (O). ``trip_time`` (s): when the
    pawl starts letting go (O: 0), or NO_TRIP; ``trip_after_touch`` (s): the pawl starts letting go
    this long after the first pole's touch (CO: the opening release energised at the touch, its
    delay), or NO_TRIP."""

    close: bool
    start_closed: bool
    trip_time: float = NO_TRIP
    trip_after_touch: float = NO_TRIP


#: The plain closing (no trip): the commands of a run whose breaker names none
CLOSE = Commands(close=True, start_closed=False)

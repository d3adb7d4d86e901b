"""What stops the cam after the closing: the closing end stop (a buffer the cam's stop lever meets)
and the holding latch (a pawl that stops the cam turning back), each optional in a rig. Units in
each docstring."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..friction import NumericOps
from ..types import Ops, Scalar


@dataclass(frozen=True)
class EndStop:
    """The closing end stop (rig section ``breaker.end_stop``): a buffer on the frame (a stop
    with a shock absorber) that a stop lever of the cam meets at cam angle ``angle`` (rad, the
    cam angle A->B from +x, counted on from the start and not wrapped: 5.0 rad is 286 deg of the
    first turn). The lever's contact point is at ``arm`` (m) from A along A->B; the buffer pushes
    it back perpendicular to A->B with ``stiffness`` (N/m) times its penetration plus a damping
    coefficient times the penetration's rate, only while in contact and never pulling
    (:func:`end_stop_force`). The damping coefficient rises from zero at contact in proportion to
    the penetration and reaches ``damping`` (N s/m) at ``damping_depth`` (m), so the buffer's force
    rises from zero as a real buffer's does (a Hunt-Crossley-type damping, c d/d_r v, saturated);
    ``damping_depth`` 0: the plain dashpot, full ``damping`` from the first contact (its force
    jumps to damping x speed). Absent (None): not modelled, the cam turns on."""

    angle: float  # rad
    arm: float  # m
    stiffness: float  # N/m
    damping: float  # N s/m
    damping_depth: float = 0.0  # m; 0: the damping acts in full from the first contact


@dataclass(frozen=True)
class HoldLatch:
    """The holding (closing) latch (rig section ``breaker.hold_latch``): a pawl that drops behind
    the cam's latch face once the cam has passed ``angle`` (rad, as :class:`EndStop`'s) going
    forward, and from then on stops it turning back: a one-way stop at ``angle``, acting at
    ``arm`` (m) from A along A->B, with ``stiffness`` (N/m) and ``damping`` (N s/m) like the end
    stop's (:func:`hold_latch_force`). Whether it has engaged is memory kept from step to step
    (:func:`hold_latch_engagement`), as the contacts' impact speeds are. Absent (None): not
    modelled."""

    angle: float  # rad
    arm: float  # m
    stiffness: float  # N/m
    damping: float  # N s/m


def end_stop_damping(penetration: Scalar, stop: EndStop, ops: Ops = NumericOps) -> Scalar:
    """The end stop's damping coefficient (N s/m) at a penetration d (m, > 0): c min(d / d_r, 1)
    with c = ``damping`` and d_r = ``damping_depth``; c throughout when d_r is 0."""
    if stop.damping_depth <= 0.0:
        return stop.damping
    return stop.damping * ops.min(penetration / stop.damping_depth, 1.0)


def end_stop_force(theta: Scalar, omega: Scalar, stop: EndStop, ops: Ops = NumericOps) -> Scalar:
    """Force (N, >= 0) of the end stop on the cam's stop lever at cam angle ``theta`` (rad) and
    speed ``omega`` (rad/s): penetration d = arm (theta - angle) (m), rate arm omega (m/s);
    k d + c(d) d' while d > 0 (:func:`end_stop_damping`: zero at contact, rising to ``damping``
    at ``damping_depth``), clipped at zero (the buffer never pulls the lever back). Continuous at
    contact when ``damping_depth`` > 0."""
    d = stop.arm * (theta - stop.angle)
    force = stop.stiffness * d + end_stop_damping(d, stop, ops) * stop.arm * omega
    return ops.where(d <= 0.0, 0.0, ops.max(0.0, force))


def hold_latch_force(theta: Scalar, omega: Scalar, engaged: Scalar, latch: HoldLatch, ops: Ops = NumericOps) -> Scalar:
    """Force (N, >= 0) of the engaged holding latch on the cam's latch face: penetration
    d = arm (angle - theta) (m) once the cam turns back below ``angle``, rate -arm omega (m/s);
    k d + c d' while d > 0 and ``engaged`` (1: the pawl has dropped, 0: not yet), clipped at zero."""
    d = latch.arm * (latch.angle - theta)
    force = ops.where(d <= 0.0, 0.0, ops.max(0.0, latch.stiffness * d - latch.damping * latch.arm * omega))
    return ops.where(engaged <= 0.5, 0.0, force)


def hold_latch_engagement(engaged: Scalar, theta: Scalar, latch: HoldLatch, ops: Ops = NumericOps) -> Scalar:
    """The latch's memory (1 engaged, 0 not) after a state at cam angle ``theta`` (rad): it
    engages once the cam has reached ``angle`` and stays engaged."""
    return ops.where(theta >= latch.angle, 1.0, engaged)


def one_way_stop_energy(penetration: float | np.ndarray, stiffness: float) -> float | np.ndarray:
    """Elastic energy (J) of a stop's spring at a penetration (m): k d^2 / 2 for d > 0."""
    d = np.maximum(penetration, 0.0)
    return 0.5 * stiffness * d * d

"""The closing latch (paper section 4): it holds the cam at rest until the release, at a latch point
on the cam, and lets go over ``latch_release_time``. Units in each docstring."""
from __future__ import annotations

from dataclasses import dataclass

from ..friction import NumericOps
from ..types import Ops, Scalar


@dataclass(frozen=True)
class LatchPoint:
    """Where the closing latch holds the cam (rig fields ``breaker.latch.arm``, ``angle``): a
    point on the cam at ``arm`` (m) from A, at ``angle`` (rad) from A->B, pushed perpendicular
    to A->point. None for ``arm``: at the spring pin B (arm l_AB, angle 0)."""

    arm: float | None = None
    angle: float = 0.0


def latch_force(torque: Scalar, theta: Scalar, arm: Scalar, angle: Scalar, ops: Ops = NumericOps) -> tuple[Scalar, Scalar]:
    """Force (N, N) on the cam at the latch point that exerts ``torque`` (N m) about A:
    perpendicular to A->point, magnitude torque / arm."""
    a = theta + angle
    f = torque / arm
    return -f * ops.sin(a), f * ops.cos(a)


def latch_torque(t: Scalar, holding_torque: Scalar, release_time: Scalar, ops: Ops = NumericOps) -> Scalar:
    """Torque (N m) of the closing latch on the cam: the holding torque until t = 0, then
    falling linearly to zero over ``release_time`` (s)."""
    return ops.where(t <= 0.0, holding_torque,
                     ops.where(t >= release_time, 0.0, holding_torque * (1.0 - t / ops.max(release_time, 1e-300))))

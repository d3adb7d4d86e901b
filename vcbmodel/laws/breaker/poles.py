"""The poles: each push rod with its wipe (contact-pressure) spring, and where each pole's contacts
meet. Units in each docstring."""
from __future__ import annotations

from ..friction import NumericOps
from ..types import Ops, Scalar


def push_rod_force(compression: Scalar, rate: Scalar, poles, ops: Ops = NumericOps) -> Scalar:
    """Compressive force (N) of one push rod with its wipe spring: stiff (rod_stiffness) until
    the wipe spring's preload is reached, then the wipe spring's rate; structural damping.
    ``compression`` (m) is rod length at rest minus current length (negative: tension)."""
    s0 = poles.wipe_preload / poles.rod_stiffness
    elastic = ops.where(compression <= s0, poles.rod_stiffness * compression,
                        poles.wipe_preload + poles.wipe_rate * (compression - s0))
    return elastic + poles.rod_damping * rate


def push_rod_energy(compression: Scalar, poles, ops: Ops = NumericOps) -> Scalar:
    """Elastic energy (J) of :func:`push_rod_force`'s spring part."""
    s0 = poles.wipe_preload / poles.rod_stiffness
    x = compression - s0
    return ops.where(compression <= s0, 0.5 * poles.rod_stiffness * compression * compression,
                     0.5 * poles.wipe_preload * s0 + poles.wipe_preload * x + 0.5 * poles.wipe_rate * x * x)


def pole_gaps(poles) -> list[float]:
    return [poles.contact_gap + o for o in poles.gap_offsets]

"""How much fault current a breaker can close onto: bisection over the making current's peak.

Two limits of the rig's closing (a C with its ``breaker.making_current`` at other peaks, each run
a full closing to rest on the holding latch):

- **fails to latch**: the smallest peak at which the cam does not reach its holding latch after
  the touch (:func:`latches`);
- **blown open**: the smallest peak at which a closed contact is pushed open by its repulsion: a
  pole's bounces last longer than at zero current by more than ``BLOW_OPEN_MARGIN``, or it reopens
  (:func:`blown_open`).

Each limit is bracketed by a bisection on the peak to ``tolerance`` (A). The repulsion acts only
while the contacts touch (an arc carries the current when they part), so it does work on the
mechanism only over the contacts' elastic compression: it opens contacts long before it can stop
the cam.
"""
from __future__ import annotations

import copy
import json
import tempfile
import logging
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import InputError, SimulationError
from .closing_evaluation import figures_of_merit
from .loading import load_rig
from .sequence import RUN_LENGTH
from .simulation import simulate

log = logging.getLogger("vcbmodel")

if TYPE_CHECKING:
    from ..rig.data import Rig

#: A pole counts as blown open when its bounces last this much longer (s) than at zero current:
#: one sample of a 20 kHz analyser (records.analyser.MIN_BOUNCE)
BLOW_OPEN_MARGIN = 5e-5


def with_peak(rig: Rig, peak: float, folder: Path) -> Rig:
    """The rig with its making current's peak set to ``peak`` (A; 0: no current), as a rig file in
    ``folder`` read back (so every value passes the rig's checks)."""
    data = copy.deepcopy(rig.data)
    if peak <= 0.0:
        data["breaker"].pop("making_current", None)
    else:
        data["breaker"]["making_current"]["peak"] = peak
    path = folder / f"peak_{peak:.0f}.rig.json"
    path.write_text(json.dumps(data))
    return load_rig(path)


def closing_figures(rig: Rig, backend: str) -> dict:
    """The figures of merit of the rig's closing run to rest on its holding latch; a run that ends
    before the cam has reached its latch, turned back or come to rest short of it is a SimulationError
    (neither verdict holds)."""
    f = figures_of_merit(simulate(rig, backend=backend, t_end=RUN_LENGTH["C"]), rig)
    if f["latched"] is None:
        raise SimulationError(f"the closing has neither reached its latch nor stopped short of it by {RUN_LENGTH['C']:g} s "
                              "(or no pole touches, or the rig has no holding latch or end stop): no making limit")
    return f


def latches(f: dict) -> bool:
    """Whether a closing latched: every pole touched and the cam reached its holding latch after the
    first touch (whether the contacts then stay closed is :func:`blown_open`'s question)."""
    return bool(f["latched"]) and f["closing_time_s"] is not None


def blown_open(f: dict, baseline: dict) -> bool:
    """Whether a pole was pushed open under the current: its bounces outlast the current-free
    closing's (``baseline``) by more than BLOW_OPEN_MARGIN, or it reopens."""
    return f["contacts_reopen_s"] is not None or f["bounce_duration_s"] > baseline["bounce_duration_s"] + BLOW_OPEN_MARGIN


def bisect_peak(fails: Callable[[float], bool], low: float, high: float, tolerance: float) -> float | None:
    """The smallest peak (A) in (low, high] at which ``fails``, to ``tolerance``, assuming it holds
    from there up; None when it does not fail at ``high``."""
    if not fails(high):
        return None
    while high - low > tolerance:
        mid = 0.5 * (low + high)
        low, high = (low, mid) if fails(mid) else (mid, high)
    return high


def valid_high(rig: Rig, high: float, folder: Path, backend: str) -> float:
    """The largest of ``high``, high / 2, high / 4, ... (A; not below the rig's own peak) whose closing is
    a valid run: at a current far beyond any rating Holm's force (mega-newtons at 1 MA) makes the fixed
    step unstable, and such a run (its energy check fails) is no evidence of latching either way."""
    while True:
        try:
            closing_figures(with_peak(rig, high, folder), backend)
            return high
        except SimulationError:
            if high / 2.0 < rig.breaker.making_current.peak:
                raise
            log.info("making limit: the closing at %.3g A is not a valid run; searching up to %.3g A", high, high / 2.0)
            high /= 2.0


def making_limits(rig: Rig, high: float = 1e6, tolerance: float = 1e3, backend: str = "fast") -> dict:
    """The making-current limits of the rig's closing (module docstring): ``fails_to_latch_A`` and
    ``blown_open_A`` (None: not up to ``high_A``, the largest current up to ``high`` whose run is valid:
    :func:`valid_high`), ``tolerance_A``, and at
    the rig's own peak whether it latches and its kinetic margin (J)."""
    if rig.breaker is None or rig.breaker.making_current is None:
        raise InputError(rig.path, "breaker.making_current", "missing: the making limit needs the making current's "
                         "shape (frequency, time constant, asymmetry) and the contacts' radii")
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        baseline = closing_figures(with_peak(rig, 0.0, folder), backend)
        own = closing_figures(rig, backend)
        high = valid_high(rig, high, folder, backend)
        latch_fail = bisect_peak(lambda p: not latches(closing_figures(with_peak(rig, p, folder), backend)), 0.0, high,
                                 tolerance)
        blow = bisect_peak(lambda p: blown_open(closing_figures(with_peak(rig, p, folder), backend), baseline), 0.0,
                           high, tolerance)
    return {"rated_peak_A": rig.breaker.making_current.peak, "fails_to_latch_A": latch_fail, "blown_open_A": blow,
            "high_A": high, "tolerance_A": tolerance, "latches_at_rated": latches(own),
            "kinetic_margin_at_rated_J": own["kinetic_margin_J"], "kinetic_margin_without_current_J": baseline["kinetic_margin_J"],
            "bounce_at_rated_s": own["bounce_duration_s"], "bounce_without_current_s": baseline["bounce_duration_s"]}

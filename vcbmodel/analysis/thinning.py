"""A record much denser than its experiment's usual sensor, thinned to about that rate before any fit
(``identify`` and ``diagnose`` alike): every k-th sample kept, times unchanged."""
from __future__ import annotations

import logging
from dataclasses import replace
from typing import TYPE_CHECKING

from ..experiments import experiment_of

if TYPE_CHECKING:
    from ..records.measurement import Measurement
    from ..rig.data import Rig

log = logging.getLogger("vcbmodel")

#: A record sampled more than this many times faster than its experiment's usual sensor is thinned
#: to about that rate before the fit (the motion's frequencies are far below either).
DENSE_FACTOR = 2.0


def usual_rate(pair: tuple[Rig, Measurement], who: str = "fit") -> tuple[Rig, Measurement]:
    """A (rig, measurement) pair thinned to about its experiment's usual sample rate (Hz,
    ``Experiment.sample_rate``) when it is more than :data:`DENSE_FACTOR` times denser: every k-th
    sample is kept, times unchanged (``who``: the command named in the log line). A pendulum swings
    at about 1 Hz, so the usual 1 kHz resolves it many times over; the fit of a full million-sample
    record (100 s at 10 kHz) ran into its step and budget limits and returned wrong values (identify,
    with no warning; diagnose: mu_k 0.139 for 0.12, not explained, after 229 s). Centred means of k
    samples instead of single samples were tried and rejected: the lower noise (0.15 for 0.5 mrad)
    sent the staged fit to a wrong optimum (mu_k 0.137 for 0.12) on a 20 s, 10 kHz record."""
    rig, meas = pair
    usual = experiment_of(rig.experiment).sample_rate
    rate = (meas.t.size - 1) / float(meas.t[-1] - meas.t[0])
    k = int(rate // usual)
    if rate <= DENSE_FACTOR * usual or k < 2:
        return pair
    log.info("%s: %s: %.0f samples/s; every %d-th sample is fitted (%.0f samples/s)", who, meas.path, rate, k, rate / k)
    return rig, replace(meas, t=meas.t[::k], channels={name: v[::k] for name, v in meas.channels.items()},
                        comments=meas.comments + (f"vcbmodel: every {k}-th sample fitted",))

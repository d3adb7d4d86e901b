"""Step 1, align the record: its noise (high-frequency level, a quantised sensor's step), which
channels are fitted and how each is weighted, where the release is (a pre-trigger at rest, a
hand-driven start, or the starting model's own delay), the nuisance's starting values
(:mod:`..nuisance`), and for a free swing the model-free check of the swing's period against the
rig's. Fills the :class:`.context.Context`; nothing is fitted yet."""
from __future__ import annotations

import math
import re

import numpy as np

from ...experiments import experiment_of
from ...experiments.pendulum import decay_split_guesses
from ...records.analyser import channel_setup
from ...records.signals import noise_estimate_floored, quantisation_step
from .. import fit as fitting
from ..fit import Dataset, make_parameters
from ..noise import NoiseModel
from ..nuisance import record_setup, release_from_model, swing_period_mismatch
from .period import imply_period, needs_period


def fitted_channels(rig: object, measurement: object) -> tuple:
    """The record's channels that are fitted: the experiment's measured channel, and any of the
    experiment's extra channels the record carries (a breaker analyser's pole contacts/travels)."""
    rec = experiment_of(rig.experiment)
    chans = [rec.measured_channel]
    for name in measurement.channels:
        if name != rec.measured_channel and any(re.fullmatch(p, name) for p in rec.extra_channels):
            chans.append(name)
    return tuple(chans)


def _release_from_model(ctx, y) -> None:
    """The follower of a closing stays at rest until the cam's rise reaches the roller: place
    the release by the starting model's own delay (one simulation)."""
    rig, rec, measurement = ctx.rig, ctx.record, ctx.measurement
    t = measurement.t
    dt = float(np.median(np.diff(t)))
    grid = np.arange(int(math.ceil((t[-1] - t[0]) / dt)) + 1) * dt
    values = dict(rec.start_guesses(rig, measurement)[0])
    params = make_parameters(rig, rig.model.effects, initial=values)
    job = fitting.SimJob(rig, tuple(rig.model.effects), tuple(sorted((k, p.value) for k, p in params.items())),
                         rig.model.spring_model, (dt, grid.size - 1), (rec.measured_channel,), None, None,
                         fitting.user_function_for(rig))
    res = ctx.pool.run([job])[0]
    if not isinstance(res, Exception):
        release_from_model(ctx.setup, t, y, res["t"], res[rec.measured_channel], ctx.sigma_hf)


def _channels(ctx) -> tuple:
    """The fitted channels, each weighted by its own high-frequency noise."""
    chans = fitted_channels(ctx.rig, ctx.measurement)
    ctx.channel_sigma = {ch: noise_estimate_floored(ctx.measurement.channel(ch)) for ch in chans}
    ctx.channel_sigma[ctx.record.measured_channel] = ctx.sigma_hf
    if len(chans) > 1:
        channel_setup(ctx.rig, ctx.setup, chans, ctx.channel_sigma)
    return chans


def _check_period(ctx, state) -> None:
    """Model-free first: the swing's period against the rig's (a free swing only)."""
    rec = ctx.record
    if not rec.period_fields:
        return
    state.period = swing_period_mismatch(ctx.rig, ctx.measurement.t, ctx.measurement.channel(rec.measured_channel),
                                         ctx.setup.window[0], ctx.sigma_hf)
    if needs_period(ctx, state.period):
        imply_period(ctx, state.period)


def align(ctx, state) -> None:
    """Fill ``ctx`` with the record as the fits see it (see the module docstring)."""
    rig, measurement = ctx.rig, ctx.measurement
    ctx.record = rec = experiment_of(rig.experiment)
    y = measurement.channel(rec.measured_channel)
    ctx.quantisation = quantisation_step(y)
    ctx.sigma_hf = noise_estimate_floored(y, ctx.quantisation)
    ctx.search.noise = NoiseModel.white(ctx.sigma_hf, ctx.quantisation)
    ctx.setup = record_setup(rig, measurement, ctx.sigma_hf)
    chans = _channels(ctx)
    if rec.release_from_model and "release_time" not in ctx.setup.pinned:
        _release_from_model(ctx, y)
    ctx.dataset = Dataset(rig, measurement, ctx.setup, chans)
    window = measurement.window(ctx.setup.window[0], ctx.setup.window[1])
    ctx.guesses = rec.start_guesses(rig, window)
    ctx.valley = decay_split_guesses(rig, window, ctx.options.valley_shares) if rec.free_swing else []
    ctx.uncertain = dict(getattr(rig, "uncertain", None) or {})
    ctx.search.implied = {}
    clock_sd = ctx.uncertain.get("record.time_base")  # the rig says the record's clock is approximate
    ctx.search.time_scale = {"value": 1.0, "sd": clock_sd, "source": "rig (uncertain record.time_base)"} if clock_sd else None
    ctx.coarse_step = 2 * rec.step(rig) if rec.staged_fit else None
    s = ctx.setup
    ctx.say(f"noise {ctx.sigma_hf:.3g} {rec.unit} (high frequencies"
            + (f"; quantised in steps of {ctx.quantisation:.3g}" if ctx.quantisation else "") + "); "
            + "; ".join(s.notes or ["record starts at the release or at rest"]))
    _check_period(ctx, state)

"""Fits of the record, as every step runs them: a model's parameters with the record's nuisance
(release time s, sensor offset in the record's unit and gain, initial angle rad, uncertain rig
values), and one fit (staged for a free swing) on the shared pool within the time budget."""
from __future__ import annotations

import numpy as np

from ...model.effects import parameter_specs
from ...rig.paths import loaded_value
from .. import fit as fitting
from ..fit import FitResult, Parameter, make_parameters
from .at_noise import at_noise
from .time_base import time_scale_parameter


def _sensor_parameters(ctx, add) -> None:
    """Offset (and gain, when the rig says it is uncertain) of each fitted position channel."""
    s = ctx.setup
    for ch in ctx.dataset.fitted_channels:
        if ch.endswith("_contact"):
            continue
        main = ch == ctx.record.measured_channel
        oname = "sensor_offset_0" if main else f"offset_{ch}_0"
        gname = "sensor_gain_0" if main else f"gain_{ch}_0"
        unit = ctx.record.unit if main else "m"
        add(Parameter(oname, s.offset if main else 0.0, vary=not (main and "sensor_offset" in s.pinned),
                      unit=unit, kind="offset", dataset=0))
        # the gain is estimated only when the rig says it is uncertain: a gain error is a
        # proportional change of the motion, which in a cam drop looks like shaft friction
        gain_sd = ctx.uncertain.get("record.sensor_gain") if main and "sensor_gain" not in s.pinned else None
        add(Parameter(gname, s.gain if main else 1.0, 0.8, 1.25, vary=bool(gain_sd), unit="-", kind="gain",
                      dataset=0, prior=(s.gain, gain_sd) if gain_sd else None))


def _rig_parameters(ctx, add) -> None:
    """Rig values marked uncertain (or implied by a period mismatch), each with its prior."""
    for path, rel in {**ctx.uncertain, **ctx.search.implied}.items():
        if path.startswith(("friction.", "record.")):
            continue
        nominal = float(loaded_value(ctx.rig, path))
        sd = abs(rel * nominal)
        lo, hi = nominal - 4 * sd, nominal + 4 * sd
        if nominal > 0:
            lo = max(lo, 0.2 * nominal)
        add(Parameter(f"rig:{path}", nominal, lo, hi, vary=sd > 0, unit="", kind="rig", dataset=0, path=path,
                      prior=(nominal, sd)))


def nuisance_parameters(ctx, previous: dict | None = None) -> dict:
    """The nuisance as fit parameters (values from ``previous`` when given)."""
    s = ctx.setup
    prev = previous or {}
    params = {}

    def add(p):
        if p.name in prev:
            p.value = float(np.clip(prev[p.name], p.min, p.max))
        params[p.name] = p

    add(Parameter("release_time_0", s.release, s.release_bounds[0], s.release_bounds[1],
                  vary="release_time" not in s.pinned, unit="s", kind="release", dataset=0))
    _sensor_parameters(ctx, add)
    if s.initial_angle is not None:
        add(Parameter("initial_angle_0", s.initial_angle, s.initial_angle - 0.1, s.initial_angle + 0.1,
                      vary="initial_angle" not in s.pinned, unit="rad", kind="state", dataset=0,
                      path=ctx.record.initial_angle_field, prior=s.initial_angle_prior))
    if ctx.search.time_scale:  # the record's clock (..time_base)
        add(time_scale_parameter(ctx.search.time_scale["sd"], ctx.search.time_scale["value"]))
    _rig_parameters(ctx, add)
    return params


def parameters(ctx, effects: tuple, previous: dict | None = None, initial: dict | None = None) -> dict:
    """Model parameters of ``effects`` (rig values fixed, uncertain friction values with a
    prior) and the nuisance."""
    params = make_parameters(ctx.rig, effects, initial=initial)
    for path, rel in ctx.uncertain.items():
        name = path.split(".", 1)[1]
        if path.startswith("friction.") and name in params:
            p = params[name]
            nominal = p.value
            p.vary, p.prior = True, (nominal, abs(rel * nominal) or 1e-9)
    for name, v in (previous or {}).items():
        if name in params and params[name].vary:
            params[name].value = float(np.clip(v, params[name].min, params[name].max))
    params.update(nuisance_parameters(ctx, previous))
    return params


def _fresh_bases(ctx, effects, params, new=()):
    """Grid centres for a scan: the current values, and afresh the record's own starting values,
    else the registry's (a model that lacked the new effect has bent its other values to make up
    for it)."""
    fresh = {spec.name: spec.initial for spec in parameter_specs(effects)
             if spec.name in params and params[spec.name].vary}
    fresh.update({k: v for k, v in ctx.guesses[0].items() if k in params and params[k].vary})
    bases = [{}, fresh] if fresh else None
    return bases + valley_bases(ctx, params, new) if bases else bases


def valley_bases(ctx, params: dict, new=("mu_k", "viscous")) -> list:
    """Further grid centres for a free swing when a candidate adds Coulomb or viscous friction
    (``new``: the scanned parameters) and both are then fitted: the decay shared out between them
    (ctx.valley). Reason: the record's own regression of a few span decrements often puts the
    whole decay in Coulomb friction (viscous 0), and a scan of the new parameter around that point
    stays at that end of the valley (a LuGre pendulum with a 12-bit logger: viscous friction not
    named at 3x the noise). A model that fits both already sits on the valley's floor: not then
    (a Stribeck candidate started there ends worse on a LuGre lab pendulum)."""
    if (not ctx.valley or not {"mu_k", "viscous"} & set(new)
            or not all(k in params and params[k].vary for k in ("mu_k", "viscous"))):
        return []
    return [{k: v for k, v in g.items() if k in params and params[k].vary} for g in ctx.valley]


def fit_record(ctx, effects: tuple, spring_model: object, params: dict, label: str, starts: list | None = None,
               scan: dict | None = None, step: float | None = None, should_stop=None,
               new: tuple | None = None) -> FitResult:
    """One fit of the record (staged for a free swing). With a ``scan`` of new parameters,
    the grid is laid around the current values and around the record's own starting values;
    the optimiser runs from the best point, and from the second best when the first does not
    reach the noise. ``should_stop`` (default: the time budget's) aborts it with FitAborted.
    ``new``: the parameters a candidate adds (default: the scanned ones)."""
    ds = [ctx.dataset]
    kw = dict(sigma=ctx.sigma_hf, verbose=False, label=label, pool=ctx.pool, processes=1,
              scales=ctx.scales(), should_stop=should_stop or ctx.stop.is_set, max_starts=ctx.options.max_starts)
    bases = _fresh_bases(ctx, effects, params, tuple(scan) if new is None else new) if scan else None
    if ctx.record.staged_fit:
        r = fitting.staged_fit(ds, effects, spring_model, params, starts=starts, scan=scan,
                               coarse_step=ctx.coarse_step, bases=bases, **kw)
    else:
        if scan:
            starts = fitting.scan_starts(ds, effects, spring_model, params, scan, pool=ctx.pool,
                                         scales=kw["scales"], bases=bases,
                                         step=fitting.scan_step(ctx.rig)) + list(starts or [])
        # a further start is pointless once a residual is at the noise (the one criterion,
        # .at_noise): with correlated noise the rms stays above the white level the fitter's own
        # test uses, and an ANCF start costs half a minute
        r = fitting.fit(ds, effects, spring_model, params, starts=starts, step=step,
                        enough=lambda f: at_noise(ctx, f), **kw)
    r.label = label
    ctx.search.fits += 1
    return r


def refit(ctx, effects: tuple, spring: object, previous: dict, label: str) -> FitResult:
    """A fit of ``effects`` from ``previous`` values."""
    return fit_record(ctx, effects, spring, parameters(ctx, effects, previous), label)

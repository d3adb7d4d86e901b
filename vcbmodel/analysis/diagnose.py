"""The discrepancy workflow: where do model and record disagree, and what is missing?

1. The record's nuisance (:mod:`.nuisance`): where the release is in the record (a pre-trigger
   at rest, or a hand-driven start fitted from the free swing), the actual initial angle, the
   sensor's zero offset and gain, and rig values the rig marks ``uncertain``, all estimated with
   the physics unless the rig's ``record`` section pins them.
2. The starting model (the rig's ``model``) is fitted: its free values and the nuisance. For a
   free swing the period is checked: a model that drifts out of phase with the record (the
   rig's geometry or the record's time base is off) is reported, and the period is fitted as a
   nuisance (the pendulum's inertia) so the search below does not chase it.
3. Forward selection: every registered effect the model lacks (and that applies) is added in
   turn and fitted; the best is kept if it lowers BIC by more than :data:`BIC_MARGIN`; repeat
   until no candidate earns it. ``missing_effects`` lists the kept ones in order.
4. The noise (:mod:`.noise`): an autoregressive model of the best model's residual (level and
   correlation). Every score is computed from the whitened residual, so correlated noise does not
   pass for evidence; the level is floored by the record's own high-frequency content and by a
   quantised sensor's rounding.
5. The verdict: ``explained`` is true only when the final model's residual is what that noise
   alone leaves (whitened residual white, level as the record's); otherwise the report says what
   is left: its window, size and signature.

The loop runs over :data:`vcbmodel.model.effects.EFFECTS`: registering an effect makes it a
candidate with no change here.
"""
from __future__ import annotations

import math
import re
import threading
import time
from concurrent.futures import FIRST_COMPLETED, ThreadPoolExecutor, wait
from dataclasses import dataclass, field, replace

import numpy as np

from ..errors import SimulationError
from ..experiments import experiment_of
from ..model.effects import EFFECTS, parameter_specs
from ..model.values import rig_values
from ..records.analyser import channel_setup
from ..records.signals import disagreement_window, dominant_frequency, lag1_autocorrelation, noise_estimate_floored, quantisation_step, swing_peaks
from ..rig.paths import loaded_value
from . import fit as fitting
from .fit import Dataset, FitAborted, FitResult, Parameter, SimulationPool, make_parameters
from .diagnosis_report import describe_signature, evidence_text, nuisance_report
from .noise import STRUCTURE_TOLERANCE, NoiseModel, consistency, fit_noise, rounding_dominates
from .nuisance import record_setup, release_from_model, swing_period_mismatch
from .progress import progress

#: BIC improvement (in units of chi^2 of the whitened residual) required to name an effect.
#: Kass & Raftery (1995) call a BIC difference above 10 "very strong" evidence.
BIC_MARGIN = 10.0
#: An effect is named only if it also removes at least this fraction of the noise variance from
#: the residual (rms_before^2 - rms_after^2 >= MIN_VARIANCE_GAIN sigma^2). The model's own numerical
#: accuracy against the independent reference is about 0.03 mrad at the pendulum's default step
#: (0.4 % of the potentiometer's noise variance); with n = 6000 samples a systematic difference
#: that small is "significant" by BIC, and an extra parameter can absorb part of it. An effect must
#: explain five times more.
MIN_VARIANCE_GAIN = 0.02
#: Optimiser runs per fit: from the best of its ranked starts (and the next best, when 2 and the
#: first does not reach the noise).
MAX_STARTS = 2
#: Optimiser runs of the wider search before a "not explained" verdict (_search_harder): a free
#: swing's cost is rugged where the stop moves by a half-swing; in the measured case that needed it
#: the grid point that led to the noise-level fit ranked third by its cost (the final fit's own
#: point first, a point of its basin second).
WIDER_STARTS = 3
#: Time budget of one diagnosis (s on its processes: processor seconds of this process and the
#: simulation workers divided by their number, so that a machine shared with other work does
#: not cut the search short). Past 80 % of it no new fit starts; at the budget the running fits
#: stop and the diagnosis reports what it has (``timing.budget_reached``). Four times the budget
#: in wall time stops it in any case.
TIME_BUDGET = 50.0
WALL_FACTOR = 4.0
#: A residual that passes the noise tests is told from a model error only when the noise model
#: fitted to it stays within this factor of the record's high-frequency noise; above it the noise
#: is so correlated that a slow model error passes for it, and pairs of effects are tried too
#: (_noise_separable).
SEPARABLE_NOISE_RATIO = 2.0
#: A period mismatch is reported when the record's swing period differs from the model's by
#: more than this fraction (and by more than 4 standard errors).
PERIOD_TOLERANCE = 0.002


@dataclass
class Candidate:
    effect: str
    fit: FitResult
    delta_bic: float  # BIC(current model) - BIC(with effect), whitened: positive is better
    round: int = 1
    variants: list = None  # spring models tried: (label, rms)

    def summary(self, noise=None):
        r = self.fit
        return {"effect": self.effect, "round": self.round, "delta_bic": round(self.delta_bic, 2),
                "bic": round(r.bic_with(noise) if noise is not None else r.bic, 2), "rms": r.rms,
                "lag1_autocorrelation": round(lag1_autocorrelation(r.residuals[0]), 4),
                "spring_model": r.spring_model_label, "parameters": _rounded(r.model_values), "simulations": r.nfev,
                **({"variants": self.variants} if self.variants else {})}


@dataclass
class Diagnosis:
    rig: object
    measurement: object
    noise_model: NoiseModel
    baseline: FitResult
    candidates: list
    missing_effects: list
    final: FitResult
    window: tuple
    signature: dict
    evidence: str
    stopped: list = None  # candidates not fitted: a simpler one explained the data already
    verdict: dict = field(default_factory=dict)
    nuisance: dict = field(default_factory=dict)
    timing: dict = field(default_factory=dict)
    selection: list = field(default_factory=list)
    #: the starting model with the record's nuisance fitted to it (``baseline`` is the starting
    #: model on the final model's alignment of the record: see _on_final_alignment)
    baseline_own_alignment: FitResult = None

    @property
    def missing_effect(self):
        return self.missing_effects[0] if self.missing_effects else None

    @property
    def noise(self):
        """The noise level (standard deviation of the noise itself, the record's unit)."""
        return self.noise_model.marginal_sd

    @property
    def explained(self):
        return bool(self.verdict.get("explained"))

    @property
    def ambiguous(self):
        """[(kept effect, rival)] the evidence does not separate (BIC within the margin)."""
        return [tuple(t["between"]) for t in self.verdict.get("ambiguous", ())]

    @property
    def unit(self):
        return experiment_of(self.rig.experiment).unit

    def to_json(self):
        b, f = self.baseline, self.final
        sigma = self.noise
        return {
            "missing_effect": self.missing_effect, "missing_effects": list(self.missing_effects),
            "explained": self.explained, "ambiguous": [list(pair) for pair in self.ambiguous],
            "baseline_effects": list(b.effects), "final_effects": list(f.effects),
            "baseline_spring_model": b.spring_model_label, "final_spring_model": f.spring_model_label,
            "simulated_with": f.backend, "rms_before": b.rms, "rms_after": f.rms,
            "rms_before_own_alignment": (self.baseline_own_alignment or b).rms,
            "max_error_before": b.max_error, "max_error_after": f.max_error,
            "gap_ratio": f.rms / b.rms if b.rms > 0 else None,
            # the model-truth gap: residual rms in excess of the noise, sqrt(rms^2 - sigma^2)
            "excess_before": math.sqrt(max(b.rms**2 - sigma**2, 0.0)),
            "excess_after": math.sqrt(max(f.rms**2 - sigma**2, 0.0)),
            "noise_estimate": sigma, "noise_correlation": self.noise_model.lag1,
            "noise": self.noise_model.to_json(),
            "window": list(self.window), "bic_margin": BIC_MARGIN,
            "selection": self.selection,
            "candidates": [c.summary(self.noise_model) for c in self.candidates] + [
                {"effect": name, "delta_bic": None, "status": "stopped: a candidate with no more parameters "
                 "already explains the data within the noise"} for name in self.stopped or []],
            "fitted": _rounded(f.model_values), "fitted_before": _rounded(b.model_values),
            "stderr": {p.name: p.stderr for p in f.parameters.values() if p.vary and p.kind == "model"},
            "fitted_units": {p.name: p.unit or "-" for fit in (b, f) for p in fit.parameters.values()
                             if p.kind == "model"},
            "at_bound": [p.name for p in f.parameters.values() if p.at_bound()],
            "nuisance": self.nuisance, "verdict": self.verdict,
            "signature": self.signature, "evidence": self.evidence, "timing": self.timing,
        }

    def report(self):
        u = self.unit
        nz = self.noise_model
        lines = [f"Diagnosis of {self.measurement.path}",
                 f"  noise {self.noise:.3g} {u} (lag-1 correlation {nz.lag1:.2f}, AR({nz.order})"
                 + (f", quantised in steps of {nz.quantisation:.3g} {u}" if nz.quantisation else "") + ")",
                 f"  baseline {', '.join(self.baseline.effects) or '(none)'} [{self.baseline.spring_model_label}]: "
                 f"rms {self.baseline.rms:.3g} {u}",
                 "  nuisance: " + ", ".join(f"{k} {v:.5g}" for k, v in self.nuisance.get("values", {}).items()),
                 f"  disagreement largest in t = [{self.window[0]:.4g}, {self.window[1]:.4g}] s",
                 "  candidates (delta BIC of the whitened residual, positive = better):"]
        for c in self.candidates:
            lines.append(f"    round {c.round} {c.effect:18s} dBIC {c.delta_bic:12.1f}  rms {c.fit.rms:.3g} {u} "
                         f"[{c.fit.spring_model_label}]")
        for name in self.stopped or []:
            lines.append(f"    {name:18s} stopped: a simpler candidate explains the data within the noise")
        lines.append(f"  missing effects: {', '.join(self.missing_effects) or 'none'}")
        for tie in self.verdict.get("ambiguous", ()):
            lines.append(f"  AMBIGUOUS between {tie['between'][0]} and {tie['between'][1]} (BIC "
                         f"{tie['delta_bic_between']:.1f} apart, margin {BIC_MARGIN:g})")
        lines.append(f"  rms {self.baseline.rms:.3g} -> {self.final.rms:.3g} {u}; explained: {self.explained}")
        lines.append("  " + self.evidence)
        lines.append(self.final.report())
        return "\n".join(lines)


def _rounded(values):
    return {k: float(f"{v:.6g}") for k, v in values.items()}


# --- the record ------------------------------------------------------------------------------------

def fitted_channels(rig, measurement):
    """The record's channels that are fitted: the experiment's measured channel, and any of the
    experiment's extra channels the record carries (a breaker analyser's pole contacts/travels)."""
    rec = experiment_of(rig.experiment)
    chans = [rec.measured_channel]
    for name in measurement.channels:
        if name != rec.measured_channel and any(re.fullmatch(p, name) for p in rec.extra_channels):
            chans.append(name)
    return tuple(chans)


class Context:
    """What every fit of one diagnosis shares: the record, its setup, the pool, the noise."""

    def __init__(self, rig, measurement, pool, verbose, processes):
        self.rig, self.measurement, self.pool, self.verbose = rig, measurement, pool, verbose
        self.processes = processes
        self.record = experiment_of(rig.experiment)
        y = measurement.channel(self.record.measured_channel)
        self.quantisation = quantisation_step(y)
        self.sigma_hf = noise_estimate_floored(y, self.quantisation)
        self.noise = NoiseModel.white(self.sigma_hf, self.quantisation)
        self.setup = record_setup(rig, measurement, self.sigma_hf)
        chans = fitted_channels(rig, measurement)
        self.channel_sigma = {ch: noise_estimate_floored(measurement.channel(ch)) for ch in chans}
        self.channel_sigma[self.record.measured_channel] = self.sigma_hf
        if len(chans) > 1:
            channel_setup(rig, self.setup, chans, self.channel_sigma)
        if self.record.release_from_model and "release_time" not in self.setup.pinned:
            self._release_from_model(measurement, y)
        self.dataset = Dataset(rig, measurement, self.setup, chans)
        windowed = measurement.window(self.setup.window[0], self.setup.window[1])
        self.guesses = self.record.start_guesses(rig, windowed)
        self.uncertain = dict(getattr(rig, "uncertain", None) or {})
        self.implied = {}  # uncertain values the diagnosis added itself (a period mismatch)
        self.coarse_step = 2 * self.record.step(rig) if self.record.staged_fit else None
        self.stop = threading.Event()
        self.spring_final = None  # the spring model the final model is refined with (ANCF)
        self.budget = math.inf
        self.skipped = []  # fits not started for the time budget
        self.fits = 0
        self.started = time.monotonic()

    def used(self):
        """Time used against the budget: processor seconds per process (see TIME_BUDGET)."""
        return (self.pool.cpu_seconds() - self.cpu0) / max(1, self.processes)

    def over(self, fraction=0.8):
        """Past ``fraction`` of the time budget (no new fit should start)?"""
        return (self.stop.is_set() or self.used() > fraction * self.budget
                or time.monotonic() - self.started > WALL_FACTOR * fraction * self.budget)

    def _release_from_model(self, measurement, y):
        """The follower of a closing stays at rest until the cam's rise reaches the roller: place
        the release by the starting model's own delay (one simulation)."""
        t = measurement.t
        dt = float(np.median(np.diff(t)))
        grid = np.arange(int(math.ceil((t[-1] - t[0]) / dt)) + 1) * dt
        values = dict(self.record.start_guesses(self.rig, measurement)[0])
        params = make_parameters(self.rig, self.rig.model.effects, initial=values)
        job = fitting.SimJob(self.rig, tuple(self.rig.model.effects),
                             tuple(sorted((k, p.value) for k, p in params.items())), self.rig.model.spring_model,
                             (dt, grid.size - 1), (self.record.measured_channel,), None, None,
                             fitting.user_function_for(self.rig))
        res = self.pool.run([job])[0]
        if not isinstance(res, Exception):
            release_from_model(self.setup, t, y, res["t"], res[self.record.measured_channel], self.sigma_hf)

    def scales(self):
        """Weights of the residual channels: each channel's high-frequency noise level (the
        weights set only how priors weigh against the data and how channels weigh against each
        other; the evidence is scored with the whitened residual)."""
        return {(0, ch): s for ch, s in self.channel_sigma.items()}

    def nuisance_parameters(self, previous=None):
        """The nuisance as fit parameters (values from ``previous`` when given)."""
        s, rig = self.setup, self.rig
        pinned = s.pinned
        prev = previous or {}
        params = {}

        def add(p):
            if p.name in prev:
                p.value = float(np.clip(prev[p.name], p.min, p.max))
            params[p.name] = p

        add(Parameter("release_time_0", s.release, s.release_bounds[0], s.release_bounds[1],
                      vary="release_time" not in pinned, unit="s", kind="release", dataset=0))
        for ch in self.dataset.fitted_channels:
            if ch.endswith("_contact"):
                continue
            main = ch == self.record.measured_channel
            oname = "sensor_offset_0" if main else f"offset_{ch}_0"
            gname = "sensor_gain_0" if main else f"gain_{ch}_0"
            unit = self.record.unit if main else "m"
            add(Parameter(oname, s.offset if main else 0.0, vary=not (main and "sensor_offset" in pinned),
                          unit=unit, kind="offset", dataset=0))
            # the gain is estimated only when the rig says it is uncertain: a gain error is a
            # proportional change of the motion, which in a cam drop looks like shaft friction
            gain_sd = self.uncertain.get("record.sensor_gain") if main and "sensor_gain" not in pinned else None
            add(Parameter(gname, s.gain if main else 1.0, 0.8, 1.25, vary=bool(gain_sd), unit="-", kind="gain",
                          dataset=0, prior=(s.gain, gain_sd) if gain_sd else None))
        if s.initial_angle is not None:
            fieldname = self.record.initial_angle_field
            add(Parameter("initial_angle_0", s.initial_angle, s.initial_angle - 0.1, s.initial_angle + 0.1,
                          vary="initial_angle" not in pinned, unit="rad", kind="state", dataset=0, path=fieldname,
                          prior=s.initial_angle_prior))
        for path, rel in {**self.uncertain, **self.implied}.items():
            if path.startswith(("friction.", "record.")):
                continue
            nominal = float(loaded_value(rig, path))
            sd = abs(rel * nominal)
            lo, hi = nominal - 4 * sd, nominal + 4 * sd
            if nominal > 0:
                lo = max(lo, 0.2 * nominal)
            add(Parameter(f"rig:{path}", nominal, lo, hi, vary=sd > 0, unit="", kind="rig", dataset=0, path=path,
                          prior=(nominal, sd)))
        return params

    def parameters(self, effects, previous=None, initial=None):
        """Model parameters of ``effects`` (rig values fixed, uncertain friction values with a
        prior) and the nuisance."""
        params = make_parameters(self.rig, effects, initial=initial)
        for path, rel in self.uncertain.items():
            name = path.split(".", 1)[1]
            if path.startswith("friction.") and name in params:
                p = params[name]
                nominal = p.value
                p.vary, p.prior = True, (nominal, abs(rel * nominal) or 1e-9)
        for name, v in (previous or {}).items():
            if name in params and params[name].vary:
                params[name].value = float(np.clip(v, params[name].min, params[name].max))
        params.update(self.nuisance_parameters(previous))
        return params

    def fit(self, effects, spring_model, params, label, starts=None, scan=None, step=None):
        """One fit of the record (staged for a free swing). With a ``scan`` of new parameters,
        the grid is laid around the current values and around the record's own starting values
        (a model without the new effect bends its other values to make up for it); the
        optimiser runs from the best point, and from the second best when the first does not
        reach the noise."""
        ds = [self.dataset]
        kw = dict(sigma=self.sigma_hf, verbose=False, label=label, pool=self.pool, processes=1,
                  scales=self.scales(), should_stop=self.stop.is_set, max_starts=MAX_STARTS)
        bases = None
        if scan:
            # afresh: the record's own starting values, else the registry's (a model that lacked the
            # new effect has bent its other values to make up for it)
            fresh = {spec.name: spec.initial for spec in parameter_specs(effects)
                     if spec.name in params and params[spec.name].vary}
            fresh.update({k: v for k, v in self.guesses[0].items() if k in params and params[k].vary})
            bases = [{}, fresh] if fresh else None
        if self.record.staged_fit:
            r = fitting.staged_fit(ds, effects, spring_model, params, starts=starts, scan=scan,
                                   coarse_step=self.coarse_step, bases=bases, **kw)
        else:
            if scan:
                starts = fitting.scan_starts(ds, effects, spring_model, params, scan, pool=self.pool,
                                             scales=kw["scales"], bases=bases,
                                             step=fitting.scan_step(self.rig)) + list(starts or [])
            # a further start is pointless once a residual is consistent with the noise (level and
            # whiteness under the noise model fitted to it): with correlated noise the rms stays above
            # the white level the fitter's own test uses, and an ANCF start costs half a minute
            r = fitting.fit(ds, effects, spring_model, params, starts=starts, step=step,
                            enough=lambda f: _consistent(self, f), **kw)
        r.label = label
        self.fits += 1
        return r

    def say(self, message):
        if self.verbose:
            progress(f"diagnose: {message}")


# --- candidates ------------------------------------------------------------------------------------

def _candidate_jobs(rig, measurement, baseline, guesses, sigma):
    """(effect name, (effects, spring variants, new-parameter scan), number of parameters the
    effect adds to the fit) for every registered effect the model lacks."""
    given = rig_values(rig)
    jobs = []
    for name, effect in EFFECTS.items():
        if name in baseline.effects or rig.experiment not in effect.experiments:
            continue
        effects = tuple(e for e in EFFECTS if e in baseline.effects or e == name)
        new = [p for p in effect.parameters if p.vary and p.name not in given]
        scan = {p.name: p.scan for p in new if p.scan}
        variants = tuple(effect.variants) if effect.variants and baseline.spring_model.is_massless else ()
        jobs.append((name, (effects, variants, scan), len(new)))
    return jobs


#: Values at which a parameter's effect vanishes (the candidate then equals the model it was
#: added to): a candidate fit is never returned worse than that nested point.
NULL_VALUES = {"mu_k": 0.0, "mu_s": 0.0, "viscous": 0.0, "restitution": 1.0, "bellows_force": 0.0,
               "stribeck_velocity": None}  # None: any value (no effect once mu_s is null)


def _nested(ctx, current, effects, fit):
    """``fit``, or the current model with the new effects at their null values when that is
    better (a fit of a non-smooth cost can end worse than the model it extends)."""
    if fit is not None and fit.chi2 <= current.chi2:
        return fit
    params = dict(fit.parameters) if fit is not None else ctx.parameters(effects, current.values)
    new = {k: p for k, p in params.items() if k not in current.parameters}
    if any(p.vary and k not in NULL_VALUES for k, p in new.items()):
        return fit
    out = replace(current, effects=tuple(effects), parameters={**{k: replace(p) for k, p in current.parameters.items()},
                                                               **{k: replace(p, value=p.value if NULL_VALUES.get(k) is None
                                                                             else NULL_VALUES[k], stderr=None)
                                                                  for k, p in new.items()}})
    out.label = "nested (new effect at its null value)"
    return out


def _fit_candidate(ctx, current, name, effects, variants, scan):
    """The best fit of ``current`` + effect(s) ``name``; for spring_mass the best spring variant.
    Returns (FitResult, variants summary or None)."""
    fit, summary = _fit_candidate_raw(ctx, current, name, effects, variants, scan)
    if not variants:
        fit = _nested(ctx, current, effects, fit)
    return fit, summary


def _fit_candidate_raw(ctx, current, name, effects, variants, scan):
    initial = dict(ctx.guesses[0])
    initial.update(current.model_values)
    # the nuisance starts afresh from the record (the current fit's may have bent to mimic the
    # missing effect); the current fit's values are a second start
    previous = dict(current.model_values)
    if not variants:
        params = ctx.parameters(effects, previous, initial)
        return ctx.fit(effects, current.spring_model, params, f"+{name}", scan=scan), None
    return _fit_spring_variants(ctx, current, effects, variants, previous, initial)


def _pair_jobs(rig, current, singles):
    """Two effects at once, for when no single one earns the evidence (each alone may fit worse
    than neither: Stribeck friction without the viscous term it shares the decay with), or one
    passes for noise only as strongly correlated noise. A pair with the spring's mass searches
    the same spring variants as the single candidate did."""
    names = [name for name, _, _ in singles]
    spring_variants = {name: variants for name, (_, variants, _), _ in singles}
    given = rig_values(rig)
    jobs = []
    for a_i in range(len(names)):
        for b_i in range(a_i + 1, len(names)):
            pair = (names[a_i], names[b_i])
            effects = tuple(e for e in EFFECTS if e in current.effects or e in pair)
            new = [p for e in pair for p in EFFECTS[e].parameters if p.vary and p.name not in given]
            scan = {p.name: p.scan for p in new if p.scan}
            if len(scan) > 2:  # keep the grid small: the two most influential
                scan = dict(list(scan.items())[:2])
            variants = spring_variants[pair[0]] or spring_variants[pair[1]]
            jobs.append(("+".join(pair), (effects, variants, scan), len(new) + (1 if variants else 0)))
    return jobs


def _screen_spring_models(ctx, effects, variants, params, values):
    """chi^2 of each spring model at ``values`` (one simulation each, all at once on the pool; the
    alignment refitted without simulating); inf where the simulation failed."""
    objs = [fitting.Objective([ctx.dataset], effects, v, params, ctx.pool, ctx.scales()) for v in variants]
    costs = []
    for o, res in zip(objs, ctx.pool.run([o.simulation_job(values, 0) for o in objs])):
        if isinstance(res, Exception):
            costs.append(math.inf)
            continue
        cur = fitting.Curves(res)
        r = np.concatenate(o.residual_parts(o.align(values, [cur]), [cur]))
        costs.append(float(np.dot(r, r)))
    return costs


def _fit_spring_variants(ctx, current, effects, variants, previous, initial):
    """Adding the spring's mass is a discrete choice among mass models. Every model is first
    simulated at the current values (one simulation each, all at once on the pool; alignment
    refitted without simulating); the best is fitted. If it leaves more than the noise, the two
    runners-up and the ANCF continuum are refined from its values with its Jacobian (one
    simulation per step: the ANCF spring costs five to ten lumped ones)."""
    params = ctx.parameters(effects, previous, initial)
    ds = [ctx.dataset]
    costs = _screen_spring_models(ctx, effects, variants, params, {p.name: p.value for p in params.values()})
    order = sorted(range(len(variants)), key=lambda i: costs[i])
    fits = {}
    first = variants[order[0]]
    fits[first.label] = ctx.fit(effects, first, ctx.parameters(effects, previous, initial),
                                f"+spring_mass [{first.label}]", starts=[dict(current.values)])
    best = fits[first.label]
    if not _consistent(ctx, best):
        hint = fitting.jacobian_of(best)
        runners = [variants[i] for i in order[1:3] if math.isfinite(costs[i])]
        runners += [v for v in variants if v.kind == "ancf" and v not in runners and v is not first]
        for v in runners:
            p2 = {k: replace(p, stderr=None) for k, p in best.parameters.items()}
            try:
                fits[v.label] = fitting.refine(ds, effects, v, p2, hint, pool=ctx.pool, scales=ctx.scales(),
                                               sigma=ctx.sigma_hf, should_stop=ctx.stop.is_set, label=f"+spring_mass [{v.label}]")
            except SimulationError:
                continue
    chosen = min(fits.values(), key=lambda f: f.chi2)
    lumped = [f for f in fits.values() if f.spring_model.kind == "lumped"]
    if chosen.spring_model.kind != "lumped" and lumped:
        # a cheap stand-in for fitting further effects on top of this spring (refined at the end)
        chosen.stand_in = min(lumped, key=lambda f: f.chi2)
    n = max(1, int(ctx.dataset.mask().sum()))
    summary = [{"spring_model": v.label, "rms_at_current_values": math.sqrt(c / n) * ctx.sigma_hf
                if math.isfinite(c) else None, "rms_fitted": fits[v.label].rms if v.label in fits else None}
               for v, c in zip(variants, costs)]
    return chosen, summary


def _run_candidates(ctx, current, jobs, round_no):
    """Fit the candidates (threads share the simulation pool), simplest first. Once a
    candidate's residual is consistent with the noise, pending candidates with at least as many
    new parameters are not started (they could not beat it by the margin: Occam)."""
    order = sorted(range(len(jobs)), key=lambda i: jobs[i][2])
    results, variants = [None] * len(jobs), [None] * len(jobs)
    winners = []
    threads = max(1, ctx.processes)
    t0 = time.monotonic()
    done_count = 0

    def pruned(i):
        return any(jobs[i][2] >= k for k in winners)

    def run(i):
        name, (effects, var, scan), _ = jobs[i]
        return _fit_candidate(ctx, current, name, effects, var, scan)

    pending = list(order)
    with ThreadPoolExecutor(max_workers=threads) as ex:
        running = {}
        while pending or running:
            while pending and len(running) < threads:
                i = pending.pop(0)
                if ctx.over():
                    ctx.skipped.append(jobs[i][0])
                    continue
                if not pruned(i):
                    running[ex.submit(run, i)] = i
            if not running:
                break
            done, _ = wait(running, return_when=FIRST_COMPLETED)
            for fut in done:
                i = running.pop(fut)
                try:
                    res, var = fut.result()
                except (FitAborted, SimulationError):
                    res, var = None, None
                results[i], variants[i] = res, var
                done_count += 1
                if res is not None and _consistent(ctx, res):
                    winners.append(jobs[i][2])
                elapsed = time.monotonic() - t0
                left = len([j for j in pending if not pruned(j)]) + len(running)
                per = elapsed / done_count
                ctx.say(f"round {round_no}: {done_count}/{done_count + left} candidate fits done "
                        f"({jobs[i][0]}: rms {res.rms if res else float('nan'):.3g} {ctx.record.unit}); "
                        f"about {per * left / max(1, min(threads, left or 1)):.0f} s left in this round, "
                        f"{time.monotonic() - ctx.started:.0f} s so far")
    return results, variants


def _excess_share_left(ctx, current, fit):
    """The share of the current model's residual variance in excess of the noise that ``fit``
    still leaves."""
    floor = ctx.sigma_hf**2
    before = current.rms**2 - floor
    after = max(fit.rms**2 - floor, 0.0)
    return after / before if before > 0 else 0.0


def _min_gain(ctx):
    """The share of the noise variance an effect must remove (MIN_VARIANCE_GAIN; a quantised
    sensor's rounding is deterministic, and a model a little off can follow some of it: there
    an effect must remove STRUCTURE_TOLERANCE, what the verdict tolerates as structure)."""
    return STRUCTURE_TOLERANCE if rounding_dominates(ctx.quantisation, ctx.sigma_hf) else MIN_VARIANCE_GAIN


def _variance_gain(ctx, current, fit):
    """The share of the noise variance a candidate removes from the residual: the drop of the
    white chi^2 (every fitted channel) per sample of the measured channel."""
    def white(f):
        return (float(sum(np.sum(r**2) for r in f.residuals)) / ctx.sigma_hf**2
                + float(sum(np.sum(r**2) for r in f.extra_residuals.values())))
    return (white(current) - white(fit)) / max(1, current.n_data)


def _consistent(ctx, fit, noise=None):
    """Is ``fit``'s residual what the noise alone leaves (``noise``: its noise model, fitted
    here when not given)?"""
    if noise is None:
        noise = fit_noise(fit.residuals, ctx.sigma_hf, ctx.quantisation)
    return consistency(fit.residuals, noise)["consistent"] and fit.rms <= 1.5 * max(ctx.sigma_hf, noise.marginal_sd)


def _noise_separable(ctx, noise):
    """Can a residual consistent with the noise be told from a model error? Not when the noise
    model fitted to that residual (``noise``) is far above the record's own high-frequency noise
    (strongly correlated noise: a slow model error passes for it). Then pairs are tried too."""
    return noise.marginal_sd <= SEPARABLE_NOISE_RATIO * max(ctx.sigma_hf, 1e-300)


# --- the period of a free swing --------------------------------------------------------------------

def period_mismatch(ctx, fit):
    """Compare the extremes of the record's swing with the model's: a steady drift of their
    times means the periods differ. Returns a dict (relative mismatch, its standard error, and
    whether it is significant), or None when the record does not swing."""
    if not ctx.record.period_fields:  # only a free swing has a period to check
        return None
    d = ctx.dataset
    m = d.mask()
    t = d.t[m]
    y = d.y[m]
    model = fit.simulations[0].measured[m]
    tm, am = swing_peaks(t, y)
    ts, as_ = swing_peaks(t, model)
    n = min(tm.size, ts.size)
    if n < 5:
        return None
    # pair extremes by order while both swing clearly
    big = 20 * ctx.sigma_hf
    k = 0
    while k < n and am[k] > big and as_[k] > big:
        k += 1
    if k < 5:
        return None
    dt = tm[:k] - ts[:k]
    idx = np.arange(k)
    A = np.vstack([idx, np.ones(k)]).T
    coef, res, *_ = np.linalg.lstsq(A, dt, rcond=None)
    fitres = dt - A @ coef
    s2 = float(np.sum(fitres**2)) / max(1, k - 2)
    se = math.sqrt(s2 / max(np.sum((idx - idx.mean()) ** 2), 1e-12))
    half = float(np.median(np.diff(ts[:k])))
    rel = float(coef[0] / half)
    rel_se = float(se / half)
    significant = abs(rel) > PERIOD_TOLERANCE and abs(rel) > 4 * rel_se
    return {"relative": rel, "stderr": rel_se, "significant": bool(significant),
            "record_half_period_s": half * (1 + rel), "model_half_period_s": half, "extremes_compared": int(k)}


def _imply_period(ctx, period):
    """A period mismatch the rig does not allow for: fit the period's first field (the
    pendulum's inertia) as a nuisance, with an uncertainty three times the mismatch's."""
    field_name = ctx.record.period_fields[0]
    ctx.implied[field_name] = max(0.02, 3 * abs(2 * period["relative"]))
    ctx.say(f"the record's swing period differs from the rig's by {100 * period['relative']:+.2f} %: "
            f"fitting {field_name} as a nuisance")


def _period_fields_fitted(ctx):
    fields = ctx.record.period_fields
    return any(f in ctx.uncertain or f in ctx.implied for f in fields)


# --- the workflow ----------------------------------------------------------------------------------

def diagnose(rig, measurement, processes=2, verbose=True, time_budget=TIME_BUDGET) -> Diagnosis:
    """Run the workflow of the module docstring on one record (within ``time_budget`` s)."""
    started = time.monotonic()
    with SimulationPool(processes) as pool:
        ctx = Context(rig, measurement, pool, verbose, processes)
        ctx.started = started
        ctx.budget = time_budget
        ctx.cpu0 = pool.cpu_seconds()
        done = threading.Event()

        def watch():
            while not done.wait(0.5):
                if ctx.used() > time_budget or time.monotonic() - started > WALL_FACTOR * time_budget:
                    ctx.stop.set()
                    return

        watcher = threading.Thread(target=watch, daemon=True)
        watcher.start()
        try:
            return _diagnose(ctx, started)
        finally:
            done.set()


def _diagnose(ctx, started):
    rig, rec = ctx.rig, ctx.record
    s = ctx.setup
    ctx.say(f"noise {ctx.sigma_hf:.3g} {rec.unit} (high frequencies"
            + (f"; quantised in steps of {ctx.quantisation:.3g}" if ctx.quantisation else "") + "); "
            + "; ".join(s.notes or ["record starts at the release or at rest"]))
    ctx.say(f"fitting the starting model ({', '.join(rig.model.effects) or 'no effects'}, "
            f"{rig.model.spring_model.label}) with the record's nuisance")
    period = None
    if rec.period_fields:  # model-free first: the swing's period against the rig's
        period = swing_period_mismatch(rig, ctx.measurement.t, ctx.measurement.channel(rec.measured_channel),
                                       ctx.setup.window[0], ctx.sigma_hf)
        if period and period["significant"] and not _period_fields_fitted(ctx):
            _imply_period(ctx, period)
    base_params = ctx.parameters(rig.model.effects, initial=ctx.guesses[0])
    baseline = ctx.fit(rig.model.effects, rig.model.spring_model, base_params, "starting model",
                       starts=ctx.guesses[1:])
    drift = period_mismatch(ctx, baseline)
    if drift and drift["significant"] and not _period_fields_fitted(ctx):
        period = drift
        _imply_period(ctx, period)
        params = ctx.parameters(rig.model.effects, baseline.values)
        baseline = ctx.fit(rig.model.effects, rig.model.spring_model, params, "starting model (period fitted)")
    ctx.noise = fit_noise(baseline.residuals, ctx.sigma_hf, ctx.quantisation)
    ctx.say(f"starting model rms {baseline.rms:.3g} {rec.unit} ({baseline.rms / ctx.sigma_hf:.1f}x the "
            f"high-frequency noise); {time.monotonic() - started:.0f} s")
    all_fits = [baseline]
    candidates, stopped_all, path = [], set(), []
    round_ref = {}
    current = baseline
    round_no = 0
    while True:
        round_no += 1
        round_ref[round_no] = current
        jobs = _candidate_jobs(rig, ctx.measurement, current, ctx.guesses, ctx.sigma_hf)
        if not jobs:
            break
        ctx.say(f"round {round_no}: trying {len(jobs)} candidate effect(s): {', '.join(j[0] for j in jobs)}")
        fits, variants = _run_candidates(ctx, current, jobs, round_no)
        round_cands = []
        for (name, _, _), f, var in zip(jobs, fits, variants):
            if f is None:
                stopped_all.add(name)
                continue
            all_fits.append(f)
            round_cands.append(Candidate(name, f, 0.0, round_no, var))
        if not round_cands:
            break
        ctx.noise = _noise_of_best(ctx, all_fits)
        for c in round_cands:
            c.delta_bic = current.bic_with(ctx.noise) - c.fit.bic_with(ctx.noise)
        candidates.extend(round_cands)
        best = max(round_cands, key=lambda c: c.delta_bic)
        gain = _variance_gain(ctx, current, best.fit)
        weak = best.delta_bic <= BIC_MARGIN or gain < _min_gain(ctx)
        # the best single effect leaves most of the gap: two may be missing together
        partial = _excess_share_left(ctx, current, best.fit) > 0.5
        # the best passes the noise tests only because the noise is so correlated that a slow
        # model error passes for it: a pair may explain the record better
        best_noise = None if weak else fit_noise(best.fit.residuals, ctx.sigma_hf, ctx.quantisation)
        ambiguous = (best_noise is not None and not _noise_separable(ctx, best_noise)
                     and _consistent(ctx, best.fit, best_noise))
        if (weak or partial or ambiguous) and not _consistent(ctx, current) and not ctx.over():
            pairs = _pair_jobs(rig, current, jobs)
            if pairs:
                why = ("no single effect earns the evidence" if weak else
                       "the best single effect leaves most of the gap" if partial else
                       "the best single effect passes for noise only as strongly correlated noise")
                ctx.say(f"round {round_no}: {why} and the model leaves more than the noise: trying {len(pairs)} "
                        f"pair(s): {', '.join(j[0] for j in pairs)}")
                pfits, pvariants = _run_candidates(ctx, current, pairs, round_no)
                for (name, _, _), f, var in zip(pairs, pfits, pvariants):
                    if f is not None:
                        all_fits.append(f)
                        c = Candidate(name, f, 0.0, round_no, var)
                        round_cands.append(c)
                        candidates.append(c)
                ctx.noise = _noise_of_best(ctx, all_fits)
                for c in round_cands:
                    c.delta_bic = current.bic_with(ctx.noise) - c.fit.bic_with(ctx.noise)
                best = max(round_cands, key=lambda c: c.delta_bic)
                gain = _variance_gain(ctx, current, best.fit)
        if best.delta_bic <= BIC_MARGIN or gain < _min_gain(ctx):
            break
        for effect in best.effect.split("+"):
            path.append({"effect": effect, "round": round_no, "delta_bic": best.delta_bic, "rms": best.fit.rms,
                         "spring_model": best.fit.spring_model_label,
                         "with": best.effect if "+" in best.effect else None, "_before": current, "_fit": best.fit})
        current = best.fit
        stand_in = getattr(best.fit, "stand_in", None)
        if stand_in is not None:
            # further effects are searched on the best lumped chain (an ANCF spring costs five to
            # ten times as much); the final model is refined with the continuum at the end
            ctx.spring_final = best.fit.spring_model
            ctx.say(f"round {round_no}: further effects are fitted with {stand_in.spring_model_label} standing in "
                    f"for {best.fit.spring_model_label}")
            current = stand_in
        ctx.say(f"round {round_no}: {best.effect} kept (delta BIC {best.delta_bic:.0f}); rms {current.rms:.3g} "
                f"{rec.unit}; {time.monotonic() - started:.0f} s")
        if _consistent(ctx, current):
            break
        if ctx.over():
            ctx.skipped.append(f"round {round_no + 1} (time budget)")
            break
    current, backward = _backward(ctx, current, path, all_fits)
    if path and not ctx.over() and not _consistent(ctx, current):
        current = _swap(ctx, current, path, all_fits, backward)
    if ctx.spring_final is not None and "spring_mass" in current.effects and not ctx.stop.is_set():
        current = _final_spring(ctx, current, path, all_fits)
    coarse_spring = None
    if not ctx.over() and not _consistent(ctx, current):
        current, coarse_spring = _finer_spring(ctx, current, path, all_fits)
    if not ctx.over() and not _consistent(ctx, current):
        current = _search_harder(ctx, current, path, all_fits)
    final = current
    # the final noise model (from the best residual), every score re-computed with it
    ctx.noise = _noise_of_best(ctx, [final] + [f for f in all_fits if f.rms < final.rms])
    missing = [step["effect"] for step in path]
    for step in path:
        step["delta_bic_final_noise"] = step["_before"].bic_with(ctx.noise) - step["_fit"].bic_with(ctx.noise)
    for b in backward:
        b["delta_bic_final_noise"] = b["_without"].bic_with(ctx.noise) - b["_with"].bic_with(ctx.noise)
    for c in candidates:
        c.delta_bic = round_ref[c.round].bic_with(ctx.noise) - c.fit.bic_with(ctx.noise)
    selection = [{k: v for k, v in step.items() if not k.startswith("_")} for step in path] + [
        {k: v for k, v in b.items() if not k.startswith("_")} for b in backward]
    verdict = _verdict(ctx, final)
    ties = _ties(ctx, path, candidates)
    if ties:
        verdict["ambiguous"] = ties
    if period:
        verdict["period"] = period
    if coarse_spring is not None:
        verdict["spring_model_refined"] = {"from": coarse_spring.spring_model_label, "to": final.spring_model_label,
                                           "delta_bic": coarse_spring.bic_with(ctx.noise) - final.bic_with(ctx.noise)}
    stopped = sorted(stopped_all - {c.effect for c in candidates})
    own_alignment = baseline
    if final is not baseline and not ctx.stop.is_set():
        baseline = _on_final_alignment(ctx, baseline, final)
    window = _window(ctx, baseline)
    signature = describe_signature(ctx, baseline, final)
    nuisance = nuisance_report(ctx, final, period)
    evidence = evidence_text(ctx, baseline, final, missing, window, signature, verdict, period, backward, BIC_MARGIN)
    timing = {"seconds": time.monotonic() - started, "budget_used_s": ctx.used(),
              "simulations": ctx.pool.simulations, "fits": ctx.fits,
              "budget_s": ctx.budget, "budget_reached": bool(ctx.skipped or ctx.stop.is_set()),
              "skipped": list(ctx.skipped)}
    ctx.say(f"missing effects: {', '.join(missing) or 'none'}; rms {baseline.rms:.3g} -> {final.rms:.3g} "
            f"{rec.unit}; explained: {verdict['explained']}; {timing['seconds']:.0f} s, "
            f"{timing['simulations']} simulations")
    return Diagnosis(rig, ctx.measurement, ctx.noise, baseline, candidates, missing, final, window, signature,
                     evidence, stopped, verdict, nuisance, timing, selection, own_alignment)


def _ties(ctx, path, candidates):
    """Selections the evidence does not settle: a kept effect whose runner-up in the same round
    also earned the margin over the model before and trails it by no more than the margin
    (scored with the final noise model). For each: what would separate them, the part of the
    record where the two fitted models differ most."""
    ties = []
    for step in path:
        if step.get("with"):
            continue
        chosen = next((c for c in candidates if c.round == step["round"] and c.effect == step["effect"]), None)
        if chosen is None:
            continue
        rivals = [c for c in candidates if c.round == chosen.round and c is not chosen and "+" not in c.effect
                  and c.delta_bic > BIC_MARGIN and chosen.delta_bic - c.delta_bic <= BIC_MARGIN]
        for rival in sorted(rivals, key=lambda c: -c.delta_bic):
            t = chosen.fit.times[0] if chosen.fit.times else ctx.dataset.t
            difference = np.asarray(chosen.fit.residuals[0]) - np.asarray(rival.fit.residuals[0])
            t0, t1, _ = disagreement_window(t, difference, ctx.noise.marginal_sd)
            ties.append({"between": [chosen.effect, rival.effect], "round": chosen.round,
                         "delta_bic_between": float(chosen.delta_bic - rival.delta_bic),
                         "separate_by": {"window": [float(t0), float(t1)],
                                         "largest_model_difference": float(np.max(np.abs(difference))),
                                         "channel": ctx.record.measured_channel}})
    return ties


def _on_final_alignment(ctx, baseline, final):
    """The starting model on the record as the final model aligns it: its own free values
    refitted with the record's nuisance (release time, initial angle, sensor offset and gain,
    uncertain rig values) held at the final model's estimate. The nuisance belongs to the
    record, and the best model estimates it best; fitted with the starting model it bends to
    hide part of what that model lacks, and the gap would look smaller than it is. Kept only if
    it is not better than the starting model's own fit (a fit can stop short)."""
    params = ctx.parameters(baseline.effects, baseline.values)
    for name, p in params.items():
        if p.kind != "model" and name in final.parameters:
            p.value, p.vary = final.parameters[name].value, False
    try:
        aligned = ctx.fit(baseline.effects, baseline.spring_model, params, "starting model (final alignment)")
    except (FitAborted, SimulationError):
        return baseline
    if aligned.rms <= baseline.rms:
        return baseline
    ctx.say(f"the starting model on the final model's alignment of the record: rms {aligned.rms:.3g} "
            f"(with its own alignment {baseline.rms:.3g})")
    return aligned


def _final_spring(ctx, current, path, all_fits):
    """The selected effects with the spring model chosen for them (ANCF), refined from the
    stand-in's values with its Jacobian; kept if it fits better."""
    ctx.say(f"refining the final model with the {ctx.spring_final.label} spring")
    p2 = {k: replace(p, stderr=None) for k, p in current.parameters.items()}
    try:
        fine = fitting.refine([ctx.dataset], current.effects, ctx.spring_final, p2, fitting.jacobian_of(current),
                              pool=ctx.pool, scales=ctx.scales(), sigma=ctx.sigma_hf, should_stop=ctx.stop.is_set,
                              label=f"final [{ctx.spring_final.label}]")
    except (FitAborted, SimulationError):
        return current
    all_fits.append(fine)
    if fine.chi2 >= current.chi2:
        return current
    _adopt(path, current, fine)
    return fine


def _adopt(path, old, new):
    """Selection steps that ended in fit ``old`` now end in ``new`` (a refinement of it)."""
    for step in path:
        if step["_fit"] is old:
            step["_fit"] = new


def _finer_spring(ctx, current, path, all_fits):
    """A model with the spring's mass whose residual stands above the noise may have too coarse a
    spring model rather than a missing effect (the rig's lumped-2 against a continuum). Each other
    lumped chain of the spring_mass variants is simulated once at the current values (all at once on
    the pool, alignment refitted), the best is refined from the current fit with its Jacobian (one
    simulation per step), and kept if it lowers the whitened BIC by more than the margin. The ANCF
    continuum is not tried here (a closing with it costs 8 s). Returns (fit, the coarser fit it
    replaced or None)."""
    if "spring_mass" not in current.effects or current.spring_model.is_massless:
        return current, None
    variants = [v for v in EFFECTS["spring_mass"].variants if v.kind == "lumped" and v != current.spring_model]
    if not variants:
        return current, None
    ds = [ctx.dataset]
    costs = _screen_spring_models(ctx, current.effects, variants, current.parameters, dict(current.values))
    best_i = min(range(len(variants)), key=lambda i: costs[i])
    if not math.isfinite(costs[best_i]):
        return current, None
    ctx.say(f"the final model leaves more than the noise: refining it with the {variants[best_i].label} spring "
            f"(the best other spring model at its values)")
    p2 = {k: replace(p, stderr=None) for k, p in current.parameters.items()}
    try:
        finer = fitting.refine(ds, current.effects, variants[best_i], p2, fitting.jacobian_of(current), pool=ctx.pool,
                               scales=ctx.scales(), sigma=ctx.sigma_hf, should_stop=ctx.stop.is_set, label=f"final [{variants[best_i].label}]")
    except (FitAborted, SimulationError):
        return current, None
    ctx.fits += 1
    all_fits.append(finer)
    noise = fit_noise(finer.residuals, ctx.sigma_hf, ctx.quantisation)
    gain = current.bic_with(noise) - finer.bic_with(noise)
    if gain <= BIC_MARGIN:
        return current, None
    ctx.say(f"spring model {current.spring_model_label} -> {finer.spring_model_label}: rms {current.rms:.3g} -> "
            f"{finer.rms:.3g} {ctx.record.unit} (delta BIC {gain:.0f})")
    _adopt(path, current, finer)
    return finer, current


def _search_harder(ctx, current, path, all_fits):
    """Before the verdict "not explained": the final model refitted on the whole record from a
    grid of its friction values (at most two parameters, the kept effects' first), the record's
    nuisance starting where the final fit put it, the optimiser run from the WIDER_STARTS best grid
    points until one reaches the noise. A free swing's cost has local minima where a
    stop comes a half-swing earlier or later; the staged fit (swinging part first) can end in one
    when the nuisance's first estimate is off (a pendulum stopped off centre biases the swing's
    centre): a pendulum with viscous friction was left at 3.4x the noise with the right effects,
    and from the grid reached the noise. Kept if it fits better. Only for a free swing (an
    experiment with a period): a cam drop's or a closing's cost has no such stop, and there a grid
    of simulations costs as much as the search so far (the benchmark's closing went 49 -> 71 s)."""
    if not ctx.record.period_fields:
        return current
    kept = [s["effect"] for s in path]
    order = [e for e in kept if e in current.effects] + [e for e in current.effects if e not in kept]
    params = ctx.parameters(current.effects, current.values)  # the nuisance from the final fit, too
    scan = {}
    for e in order:
        for spec in EFFECTS[e].parameters:
            if spec.scan and spec.name in params and params[spec.name].vary and len(scan) < 2:
                scan[spec.name] = spec.scan
    if not scan:
        return current
    ctx.say(f"the final model leaves more than the noise: refitting it from a grid of {', '.join(scan)}")
    try:
        starts = fitting.scan_starts([ctx.dataset], current.effects, current.spring_model, params, scan, keep=WIDER_STARTS,
                                     pool=ctx.pool, scales=ctx.scales(), step=fitting.scan_step(ctx.rig))
        # the grid's friction values only: the nuisance starts from the final fit's (a start's own
        # re-alignment moves the release and the offset into that start's basin)
        starts = [{k: v for k, v in start.items() if k in scan} for start in starts]
        wider = fitting.fit([ctx.dataset], current.effects, current.spring_model, params, starts=starts,
                            sigma=ctx.sigma_hf, verbose=False, pool=ctx.pool, processes=1, scales=ctx.scales(),
                            should_stop=ctx.stop.is_set, max_starts=WIDER_STARTS, enough=lambda f: _consistent(ctx, f))
    except (FitAborted, SimulationError):
        return current
    ctx.fits += 1
    wider.label = "final model (wider search)"
    all_fits.append(wider)
    if wider.chi2 >= current.chi2:
        return current
    ctx.say(f"wider search: rms {current.rms:.3g} -> {wider.rms:.3g} {ctx.record.unit}")
    _adopt(path, current, wider)
    return wider


def _refit(ctx, effects, spring, previous, label):
    """A fit of ``effects`` from ``previous`` values."""
    return ctx.fit(effects, spring, ctx.parameters(effects, previous), label)


def _swap(ctx, current, path, all_fits, records):
    """When the selected model still leaves more than the noise, an effect kept early may stand
    in for another (in a cam drop, viscous friction mimics shaft friction plus the spring's
    mass): each kept effect with parameters is replaced in turn by each applicable effect not in
    the model; the best replacement is taken if it earns the margin."""
    kept = [s["effect"] for s in path if EFFECTS[s["effect"]].parameters and not EFFECTS[s["effect"]].variants]
    others = [name for name, e in EFFECTS.items() if name not in current.effects
              and ctx.rig.experiment in e.experiments and e.parameters and not e.variants]
    best = None
    for old in kept:
        for new in others:
            if ctx.over():
                ctx.skipped.append(f"swap {old} -> {new}")
                continue
            effects = tuple(e for e in EFFECTS if (e in current.effects and e != old) or e == new)
            ctx.say(f"swap: {old} -> {new}")
            try:
                f = _refit(ctx, effects, current.spring_model, {k: v for k, v in current.values.items()},
                           f"{old}->{new}")
            except (FitAborted, SimulationError):
                continue
            all_fits.append(f)
            noise = _noise_of_best(ctx, all_fits)
            gain = current.bic_with(noise) - f.bic_with(noise)
            records.append({"effect": old, "swap_for": new, "delta_bic": gain, "rms": f.rms, "_without": current,
                            "_with": f, "dropped": False, "backward": False})
            if gain > BIC_MARGIN and (best is None or gain > best[0]):
                best = (gain, old, new, f)
    if best is None:
        return current
    gain, old, new, f = best
    ctx.say(f"swap: {old} replaced by {new} (whitened BIC lower by {gain:.0f})")
    for step in path:
        if step["effect"] == old:
            step["effect"], step["swapped_from"] = new, old
        step["_fit"] = f
    records[-1]["dropped"] = True
    return f


def _backward(ctx, current, path, all_fits):
    """Backward elimination after forward selection: an effect kept early may be superseded by
    later ones (viscous friction stands in for shaft friction and spring mass together until
    both are in). Each kept effect is removed in turn and the model refitted; if the others
    explain the record as well (the effect no longer earns the margin), it is dropped.
    Returns (model, records of the removals tried)."""
    records = []
    if len({step["round"] for step in path}) < 2:  # one round (a pair found together): nothing to undo
        return current, records
    for step in list(path):
        if ctx.over():
            ctx.skipped.append(f"backward elimination of {step['effect']}")
            continue
        effect = step["effect"]
        effects = tuple(e for e in current.effects if e != effect)
        spring = ctx.rig.model.spring_model if effect == "spring_mass" else current.spring_model
        ctx.say(f"backward: refitting without {effect}")
        try:
            reduced = _refit(ctx, effects, spring, dict(current.values), f"-{effect}")
        except (FitAborted, SimulationError):
            continue
        all_fits.append(reduced)
        noise = _noise_of_best(ctx, all_fits)
        evidence = reduced.bic_with(noise) - current.bic_with(noise)
        gain = _variance_gain(ctx, reduced, current)
        dropped = bool(evidence <= BIC_MARGIN or gain < _min_gain(ctx))
        records.append({"effect": effect, "backward": True, "delta_bic_without": evidence, "rms_without": reduced.rms,
                        "dropped": dropped, "_without": reduced, "_with": current})
        ctx.say(f"backward: without {effect} the whitened BIC rises by {evidence:.0f} (rms {reduced.rms:.3g}): "
                + ("dropped" if dropped else "kept"))
        if dropped:
            path.remove(step)
            current = reduced
            for other in path:  # the remaining steps lead to this model now
                other["_fit"] = current
    return current, records


def _noise_of_best(ctx, fits):
    """The noise model from the residual of the fit with the smallest residual."""
    best = min(fits, key=lambda f: f.rms)
    return fit_noise(best.residuals, ctx.sigma_hf, ctx.quantisation,
                     source=f"residual of {', '.join(best.effects) or 'no effects'} [{best.spring_model_label}]")


def _verdict(ctx, final):
    """Is the final residual what the noise alone would leave? With what is left if not."""
    noise = fit_noise(final.residuals, ctx.sigma_hf, ctx.quantisation, source="final model's residual")
    lags = 20 if final.n_data > 2000 else 10
    c = consistency(final.residuals, noise, lags=lags)
    # level against the record's own high-frequency noise: a correlated residual must also be
    # explained by a plausible noise process (not by model error dressed up as noise)
    white_equiv = ctx.sigma_hf
    c["rms_over_high_frequency_noise"] = final.rms / white_equiv if white_equiv > 0 else float("nan")
    explained = bool(c["consistent"])
    out = {"explained": explained, "tests": c, "noise_of_final_residual": noise.to_json()}
    if not explained:
        t = final.times[0]
        r = final.residuals[0]
        t0, t1, peak = disagreement_window(t, r, noise.marginal_sd)
        out["left"] = {"window": [t0, t1], "rms": final.rms,
                       "excess": math.sqrt(max(final.rms**2 - ctx.noise.marginal_sd**2, 0.0)),
                       "dominant_frequency_hz": dominant_frequency(t, r), "lag1_autocorrelation":
                       lag1_autocorrelation(r), "peak_running_rms": peak}
    return out


def _window(ctx, fit):
    t0, t1, _ = disagreement_window(fit.times[0], fit.residuals[0], ctx.noise.marginal_sd)
    return (t0, t1)

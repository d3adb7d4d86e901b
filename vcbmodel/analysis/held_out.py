"""Validation on records the fit never saw: whether several records of one rig agree on one set of
values (a likelihood-ratio test), each record fitted alone, and each predicted from the others.

Several records of one rig (release angles, repeats: the paper's friction test used 10 and 15
degrees) share the rig's friction. A law that describes the rig fits them together as well as each
alone, up to the noise; a law that absorbed an effect it does not have fits each record alone to
the noise, but with values that move between records, because the absorbed effect depends on the
swing's amplitude or speed (air drag grows as w|w|, a Stribeck curve of another shape weighs the
slow part of the swing differently, a drifting level depends on how long the record lasts). So:

- each record is fitted *alone*, to convergence: from the joint values and from its own starts (its
  swing's decay), the optimiser run from every start with an absolute chi^2 tolerance
  (:data:`CHI2_TOLERANCE`, as the model forms' fits), the best kept; the joint fit is refined the
  same way, from its own values and from each record's (each record weighted by its own noise);
- *consistency* (the likelihood-ratio, or Chow, test): the joint fit's chi^2 minus the sum of the
  single fits' (each record's residual over its own high-frequency noise) is, when the records share
  their values, chi^2-distributed with (records - 1) x (varied model values) degrees of freedom.
  It is read in the test's F form (divided by the single fits' reduced chi^2, so a noise level
  misjudged or a misfit common to all records does not count as disagreement), after taking off
  :data:`ROUGHNESS_ALLOWANCE` for the cost's rough floor; the records disagree when its p-value is
  below :data:`ALPHA`. Only then is a value said to move: the one whose holding at the joint value
  (each record refitted alone, the other values free) costs the records most chi^2, with its z
  (:func:`held_fits`);
- each record is *held out* in turn: the law fitted to the others (with two records: the other's own
  fit) predicts it; its rms over its noise and its chi^2 above the record's own best fit are
  reported. They carry the trained values' uncertainty (a short record predicts a long one poorly
  and may still agree with it), so they are not judged alone: the consistency test is the verdict.

Residuals in rad (the pendulum's angle), times in s, chi^2 dimensionless.
"""
from __future__ import annotations

import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np
from scipy import stats

from .fit import FitResult, pooled_noise

#: Rms over noise a held-out prediction is reported "at its noise" within (descriptive only: the
#: verdict is the consistency test, which allows for the trained values' uncertainty).
AT_NOISE_RATIO = 1.5
#: Significance level of the consistency test: records of one law are called inconsistent in this
#: share of cases (the floor's roughness aside, below).
ALPHA = 0.01
#: chi^2 units taken off the likelihood-ratio statistic before it is tested: the cost's floor is
#: rough (fixed-step RK4 stick transitions: a stop one step earlier or later), so a converged fit ends
#: a few units above its floor, and the statistic, a difference of such fits, is off by as much.
#: Measured on in-family records (Coulomb + viscous torque truth, 10 and 20 deg, 6 s, 0.5 mrad, 6
#: seeds: 12 records), each fitted alone from the joint values and from each of its own 8 starts, run
#: to convergence as here: the 60 ends in the best one's valley lie above the best by a median 0.4,
#: 90th percentile 3.2, 95th 5.8 and at most 9.7 units. The joint and single fits here are each the
#: best of several such ends, so their error is mostly below the single end's 90th percentile. Only
#: the one joint fit's excess raises the statistic (a single fit above its floor lowers it), so the
#: allowance does not grow with the number of records.
ROUGHNESS_ALLOWANCE = 4.0
#: Levenberg-Marquardt's absolute chi^2 tolerance and iteration limit for the single and joint
#: refits, the relative one off (the model forms' values, :mod:`.model_forms`): the default relative
#: tolerance (2e-3 of the samples: 10 units on a 5 s record) stops at the start, and the test reads
#: differences of a few units.
CHI2_TOLERANCE = 0.5
MAX_ITERATIONS = 15


@dataclass
class HeldOut:
    """The consistency test, each record's own fit, each held-out record's prediction, and the
    value that moves most when the records disagree."""

    predictions: list = field(default_factory=list)  # [{measurement, trained_on, rms, noise, ratio, at_noise, delta_chi2}]
    singles: dict = field(default_factory=dict)  # {parameter: [(value, stderr) per record]}
    consistency: dict = field(default_factory=dict)  # the likelihood-ratio test (:func:`consistency_test`)
    moving: list = field(default_factory=list)  # [{parameter, z, delta_chi2, records, values, message}]: only when it rejects
    needs: dict = field(default_factory=dict)  # {parameter: {delta_chi2, z, values}}: only when it rejects
    first_peaks: list = field(default_factory=list)  # rad, per record

    @property
    def consistent(self) -> bool:
        return bool(self.consistency.get("consistent", True))

    @property
    def predicted_at_noise(self) -> bool:
        return all(p["at_noise"] for p in self.predictions)

    def to_json(self) -> dict:
        return {"consistency": self.consistency, "consistent": self.consistent,
                "predictions": self.predictions, "at_noise_ratio": AT_NOISE_RATIO,
                "predicted_at_noise": self.predicted_at_noise,
                "single_record_fits": {k: [{"value": v, "stderr": s if math.isfinite(s) else None} for v, s in rows]
                                       for k, rows in self.singles.items()},
                "needed_moves": self.needs,
                "first_peaks": self.first_peaks, "moving": self.moving, "missing_effect": not self.consistent}

    def report(self) -> str:
        c = self.consistency
        lines = [f"  Records against one another (likelihood ratio: joint chi2 - sum of single-record chi2 = "
                 f"{c['statistic']:.1f}, less {c['roughness_allowance']:g} for the floor's roughness, over "
                 f"{c['dof']} degrees of freedom, scaled by the single fits' reduced chi2 {c['residual_variance']:.3f}: "
                 f"p = {c['p_value']:.3g}):"
                 + (" CONSISTENT, the records agree on one set of values" if self.consistent
                    else f" INCONSISTENT at the {100 * ALPHA:g} % level")]
        lines.append("  Each record fitted alone (from the joint values and its own starts, to convergence):")
        for name, rows in self.singles.items():
            lines.append(f"    {name:18s} " + ", ".join(f"{v:.5g} +/- {s:.2g}" for v, s in rows))
        lines.append("  Each record predicted by the law fitted to the others (its rms carries the trained values' "
                     "uncertainty; not judged alone):")
        for p in self.predictions:
            lines.append(f"    {p['measurement']}: rms {p['rms']:.3g} rad = {p['ratio']:.2f} x its noise, chi2 "
                         f"{p['delta_chi2']:.1f} above its own fit")
        lines += [f"  MISSING EFFECT: {m['message']}" for m in self.moving]
        if not self.consistent and not self.moving:
            lines.append("  MISSING EFFECT: the records disagree, but no single value's move is resolved by the "
                         "stated errors")
        if self.consistent:
            lines.append("  (agreement within the noise: a move smaller than the records resolve, or an effect that "
                         "acts alike on every record, is not seen)")
        return "\n".join(lines)


#: refit(effects, parameters, extra starts, label, on=datasets, **fit options) -> FitResult
Refit = Callable[..., FitResult]


def _fresh(params: dict, vary: bool | None = None) -> dict:
    return {k: replace(p, stderr=None, stderr_naive=None, vary=p.vary if vary is None else False)
            for k, p in params.items()}


def own_parameters(params: dict, keep: Sequence[int]) -> dict:
    """``params`` for the datasets ``keep`` alone (indices into the full list): the shared ones,
    and each kept record's nuisance renumbered to its place among them (``release_time_2`` of the
    third record becomes ``release_time_0`` when it is fitted alone)."""
    out = {}
    for name, p in params.items():
        if p.dataset is None:
            out[name] = p
        elif p.dataset in keep:
            j = list(keep).index(p.dataset)
            new = re.sub(rf"_{p.dataset}$", f"_{j}", name)
            out[new] = replace(p, name=new, dataset=j)
    return out


def _converged(starts: list) -> dict:
    """Options of a fit run to convergence from its parameters' values and ``starts``: the optimiser
    from every start, absolute tolerance."""
    return {"max_starts": 1 + len(starts), "every_start": True, "chi2_tolerance": CHI2_TOLERANCE,
            "relative_tolerance": 0.0, "max_iterations": MAX_ITERATIONS}


def record_chi2(result: FitResult, sigmas: Sequence[float]) -> list[float]:
    """Each record's chi^2: its residual over its own noise ``sigmas`` (the prior's, if any, to the first)."""
    out = [float(np.sum(r**2)) / s**2 for r, s in zip(result.residuals, sigmas)]
    out[0] += result.prior_chi2
    return out


def single_fits(datasets: Sequence, result: FitResult, refit: Refit, starts: Sequence[list],
                sigmas: Sequence[float]) -> list[FitResult]:
    """Each record fitted alone, from the joint values (the parameters' own) and from its own
    ``starts`` (one list of value dicts per record), every start run to convergence."""
    effects = tuple(result.effects)
    return [refit(effects, own_parameters(_fresh(result.parameters), [k]), list(starts[k]),
                  f"record {k + 1} alone", on=[datasets[k]], sigma=sigmas[k], **_converged(list(starts[k])))
            for k in range(len(datasets))]


def joint_refit(datasets: Sequence, result: FitResult, refit: Refit, singles: Sequence[FitResult],
                sigmas: Sequence[float]) -> FitResult:
    """The joint fit run to convergence with each record weighted by its own noise, from its values
    and from each single fit's model values; the better (in that weighting) of it and ``result``."""
    names = [n for n, p in result.parameters.items() if p.vary and p.kind == "model"]
    starts = [{n: s.parameters[n].value for n in names} for s in singles]
    scales = {(i, ch): s for i, (d, s) in enumerate(zip(datasets, sigmas)) for ch in d.fitted_channels}
    again = refit(tuple(result.effects), _fresh(result.parameters), starts, "all records, refined", on=list(datasets),
                  scales=scales, **_converged(starts))
    return again if sum(record_chi2(again, sigmas)) < sum(record_chi2(result, sigmas)) else result


def consistency_test(joint: FitResult, singles: Sequence[FitResult], sigmas: Sequence[float]) -> dict:
    """The likelihood-ratio (Chow) test of one set of model values for every record, in its F form.

    statistic = chi^2(joint) - sum chi^2(single), each record over its own noise (``sigmas``);
    dof = (records - 1) x the varied model values; the statistic less :data:`ROUGHNESS_ALLOWANCE`,
    over dof and over the single fits' reduced chi^2 (their residual variance in noise units) is F
    with (dof, samples - single fits' varied values) degrees of freedom."""
    per_record = record_chi2(joint, sigmas)
    joint_chi2 = sum(per_record)
    # the joint values are a point of each record's own fit too: a single fit that ended above the
    # joint fit's share of its record stopped short of its floor (its best is at most that share)
    own = [min(record_chi2(s, [sg])[0], j) for s, sg, j in zip(singles, sigmas, per_record)]
    n_model = sum(p.vary for p in joint.parameters.values() if p.kind == "model")
    dof = (len(singles) - 1) * n_model
    statistic = joint_chi2 - sum(own)
    n_data, n_varied = sum(s.n_data for s in singles), sum(s.n_varied for s in singles)
    s2 = sum(own) / max(1, n_data - n_varied)
    f_value = max(statistic - ROUGHNESS_ALLOWANCE, 0.0) / max(dof, 1) / s2
    p_value = float(stats.f.sf(f_value, dof, max(1, n_data - n_varied))) if dof > 0 else 1.0
    return {"statistic": statistic, "dof": dof, "joint_chi2": joint_chi2, "single_chi2": own,
            "roughness_allowance": ROUGHNESS_ALLOWANCE, "residual_variance": s2, "f": f_value,
            "p_value": p_value, "alpha": ALPHA, "consistent": bool(p_value >= ALPHA),
            "noise": list(sigmas)}


def predictions(datasets: Sequence, joint: FitResult, refit: Refit, singles: Sequence[FitResult],
                sigmas: Sequence[float]) -> list[dict]:
    """Each record predicted with the model values fitted to the others (with two records, the
    other's own fit), only its nuisance fitted: rms, over its noise, and its chi^2 above its own fit."""
    n, effects, out = len(datasets), tuple(joint.effects), []
    for k in range(n):
        keep = [j for j in range(n) if j != k]
        if n == 2:
            trained = singles[keep[0]]
        else:
            trained = refit(effects, own_parameters(_fresh(joint.parameters), keep), [], f"all but record {k + 1}",
                            on=[datasets[j] for j in keep], scales={(i, ch): sigmas[j] for i, j in enumerate(keep)
                                                                   for ch in datasets[j].fitted_channels},
                            **_converged([]))
        fixed = own_parameters(_fresh(joint.parameters), [k])
        for name, p in fixed.items():
            if p.kind == "model":
                fixed[name] = replace(p, value=trained.parameters[name].value, vary=False)
        predicted = refit(effects, fixed, [], f"record {k + 1} predicted", on=[datasets[k]], sigma=sigmas[k],
                          **_converged([]))
        ratio = predicted.rms / sigmas[k] if sigmas[k] > 0 else math.inf
        out.append({"measurement": datasets[k].measurement.path,
                    "trained_on": [datasets[j].measurement.path for j in keep], "rms": predicted.rms,
                    "noise": sigmas[k], "ratio": ratio, "at_noise": bool(ratio <= AT_NOISE_RATIO),
                    "delta_chi2": record_chi2(predicted, [sigmas[k]])[0] - record_chi2(singles[k], [sigmas[k]])[0]})
    return out


def held_out_validation(datasets: Sequence, result: FitResult, refit: Refit, first_peaks: Sequence[float],
                        starts: Sequence[list] | None = None) -> HeldOut:
    """Fit each of ``datasets`` alone and test whether they agree on one set of values (the law
    ``result`` fitted to them together, refitted with ``refit``); predict each from the others.
    ``first_peaks``: each record's first peak amplitude (rad); ``starts``: per record, its own
    starting values (value dicts; default none beyond the joint values).

    What it guarantees: records of one law are called inconsistent in about :data:`ALPHA` of cases
    (measured: see the module's tests and docs/findings.md). What it does not: a move smaller than
    the records resolve, or an effect that biases every record alike, passes."""
    n = len(datasets)
    sigmas = [pooled_noise([d]) for d in datasets]
    singles = single_fits(datasets, result, refit, starts or [[] for _ in range(n)], sigmas)
    joint = joint_refit(datasets, result, refit, singles, sigmas)
    out = HeldOut(first_peaks=[float(a) for a in first_peaks])
    out.consistency = consistency_test(joint, singles, sigmas)
    out.predictions = predictions(datasets, joint, refit, singles, sigmas)
    varied = [name for name, p in result.parameters.items() if p.vary and p.kind == "model"]
    for name in varied:
        out.singles[name] = [(float(s.parameters[name].value), _se(s.parameters[name].stderr)) for s in singles]
    if not out.consistent:
        out.needs = held_fits(datasets, joint, refit, singles, varied, sigmas)
        moved = _most_moving(out.needs, out.first_peaks)
        if moved:
            out.moving.append(moved)
    return out


def held_fits(datasets: Sequence, joint: FitResult, refit: Refit, singles: Sequence[FitResult], names: Sequence[str],
              sigmas: Sequence[float]) -> dict:
    """{name: {delta_chi2, z, values}}: how much the records need ``name`` to differ. Each record is
    refitted alone with ``name`` held at the joint fit's value and the other values free (from its
    own fit's); delta_chi2 is the sum over the records of that fit's chi^2 above the record's own
    fit, z its two-sided normal equivalent under a chi^2 with (records - 1) degrees of freedom
    (:func:`_z_of`). A
    value the others can stand in for (the hybrid law's Stribeck fall on a record without one)
    needs nothing; the one the records disagree on needs much. The single fits' stated errors
    cannot say which: where the law's values trade against each other they reach 1e5 and more."""
    out = {}
    for name in names:
        delta = 0.0
        for k, single in enumerate(singles):
            params = own_parameters(_fresh(single.parameters), [0])
            params[name] = replace(params[name], value=joint.parameters[name].value, vary=False)
            r = refit(tuple(joint.effects), params, [], f"record {k + 1}, {name} held", on=[datasets[k]],
                      sigma=sigmas[k], **_converged([]))
            delta += max(record_chi2(r, [sigmas[k]])[0] - record_chi2(single, [sigmas[k]])[0], 0.0)
        out[name] = {"delta_chi2": delta, "z": _z_of(delta, len(singles) - 1),
                     "values": [float(s.parameters[name].value) for s in singles]}
    return out


def _z_of(delta: float, dof: int) -> float:
    """The two-sided normal z of a chi^2 ``delta`` with ``dof`` degrees of freedom (one: its square
    root; where the p-value underflows, the square root too, an upper bound for more: shown, not judged)."""
    p = float(stats.chi2.sf(delta, max(1, dof)))
    return math.sqrt(delta) if dof <= 1 or p <= 0.0 else float(stats.norm.isf(p / 2))


def _se(x: float | None) -> float:
    return float(x) if x is not None and math.isfinite(x) else math.inf


def _most_moving(needs: dict, peaks: list) -> dict | None:
    """The value the records need most to differ (:func:`held_fits`), if any needs more than
    :data:`ROUGHNESS_ALLOWANCE`."""
    name = max(needs, key=lambda n: needs[n]["delta_chi2"], default=None)
    if name is None or needs[name]["delta_chi2"] <= ROUGHNESS_ALLOWANCE:
        return None
    values = needs[name]["values"]
    a, b = int(np.argmin(values)), int(np.argmax(values))
    return {"parameter": name, "z": needs[name]["z"], "delta_chi2": needs[name]["delta_chi2"], "records": [a + 1, b + 1],
            "values": [values[a], values[b]],
            "message": (f"the records disagree, and {name} must move most: held at the joint value it costs the "
                        f"records {needs[name]['delta_chi2']:.1f} in chi2 (z = {needs[name]['z']:.1f}); fitted alone "
                        f"{values[a]:.4g} in record {a + 1} (first peak {math.degrees(peaks[a]):.3g} deg) and "
                        f"{values[b]:.4g} in record {b + 1} ({math.degrees(peaks[b]):.3g} deg): the law lacks an "
                        "effect that depends on the swing's amplitude or speed (air drag, a Stribeck curve of another "
                        "shape, a drifting friction level)")}

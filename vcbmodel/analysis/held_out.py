"""Validation on records the fit never saw: fit on some records of one rig, predict the rest, and fit
each record alone.

Several records of one rig (release angles, repeats: the paper's friction test used 10 and 15
degrees) share the rig's friction. A law that describes the rig predicts a record it was not fitted
to at that record's noise; a law that absorbed an effect it does not have fits each record alone to
the noise, but with values that move between records, because the absorbed effect depends on the
swing's amplitude or speed (air drag grows as w|w|, a Stribeck curve of another shape weighs the
slow part of the swing differently, a drifting level depends on how long the record lasts). So:

- each record is *held out* in turn: the law is fitted to the others and its prediction of the held-out
  record is compared with that record's own noise (rms / noise, the record's high-frequency noise
  estimate); above :data:`AT_NOISE_RATIO` the prediction misses;
- each record is fitted *alone*; a parameter whose values in two records differ by more than
  :data:`MOVE_Z` of their combined stated errors (sqrt(se_a^2 + se_b^2)) names a missing amplitude- or
  speed-dependent effect.

Residuals in rad (the pendulum's angle), times in s.
"""
from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace

from .fit import FitResult, pooled_noise

#: A held-out record is predicted at its noise when its rms residual is within this factor of its
#: own noise estimate (the factor identify warns above for a fitted record).
AT_NOISE_RATIO = 1.5
#: A parameter moves between records when two single-record fits differ by more than this many of
#: their combined stated errors (the two-sided 95 % level).
MOVE_Z = 1.96


@dataclass
class HeldOut:
    """Each held-out record's prediction, each record's own fit, and the parameters that move."""

    predictions: list = field(default_factory=list)  # [{measurement, trained_on, rms, noise, ratio, at_noise}]
    singles: dict = field(default_factory=dict)  # {parameter: [(value, stderr) per record]}
    moving: list = field(default_factory=list)  # [{parameter, z, records, message}]
    first_peaks: list = field(default_factory=list)  # rad, per record

    @property
    def predicted_at_noise(self) -> bool:
        return all(p["at_noise"] for p in self.predictions)

    def to_json(self) -> dict:
        return {"predictions": self.predictions, "at_noise_ratio": AT_NOISE_RATIO,
                "predicted_at_noise": self.predicted_at_noise,
                "single_record_fits": {k: [{"value": v, "stderr": s if math.isfinite(s) else None} for v, s in rows]
                                       for k, rows in self.singles.items()},
                "first_peaks": self.first_peaks, "moving": self.moving,
                "missing_effect": bool(self.moving) or not self.predicted_at_noise}

    def report(self) -> str:
        lines = ["  Held-out validation (fit on the other records, predict this one):"]
        for p in self.predictions:
            lines.append(f"    {p['measurement']}: rms {p['rms']:.3g} rad = {p['ratio']:.2f} x its noise"
                         + ("" if p["at_noise"] else "  NOT PREDICTED at its noise"))
        lines.append("  Each record refitted alone, from the joint values (a move of a few errors can go unseen):")
        for name, rows in self.singles.items():
            lines.append(f"    {name:18s} " + ", ".join(f"{v:.5g} +/- {s:.2g}" for v, s in rows))
        lines += [f"  MISSING EFFECT: {m['message']}" for m in self.moving]
        return "\n".join(lines)


#: refit(effects, parameters, extra starts, label, on=datasets) -> FitResult
Refit = Callable[..., FitResult]


def _fresh(params: dict, vary: bool | None = None) -> dict:
    return {k: replace(p, stderr=None, stderr_naive=None, vary=p.vary if vary is None else False)
            for k, p in params.items()}


def held_out_validation(datasets: Sequence, result: FitResult, refit: Refit, first_peaks: Sequence[float]) -> HeldOut:
    """Hold out each of ``datasets`` in turn (the law ``result`` fitted, refitted to the others with
    ``refit``), and fit each alone; ``first_peaks``: each record's first peak amplitude (rad).

    Each record's own fit starts from the joint values and stops within the fitter's tolerance (a
    fraction of the samples' chi^2): a record whose own optimum lies a few stated errors from the
    joint one may not move, so a small move between records can go unseen, and with two records the
    prediction of one comes from values that have seen it. Large moves (an effect the law lacks) are
    found; small ones are not a proof of agreement."""
    n = len(datasets)
    effects = tuple(result.effects)
    singles = [refit(effects, _fresh(result.parameters), [], f"record {k + 1} alone", on=[datasets[k]])
               for k in range(n)]
    out = HeldOut(first_peaks=[float(a) for a in first_peaks])
    for k in range(n):
        others = [d for j, d in enumerate(datasets) if j != k]
        trained = singles[1 - k] if n == 2 else refit(effects, _fresh(result.parameters), [],
                                                      f"all but record {k + 1}", on=others)
        fixed = {name: replace(p, value=trained.parameters[name].value) for name, p in _fresh(result.parameters, False).items()}
        predicted = refit(effects, fixed, [], f"record {k + 1} predicted", on=[datasets[k]])
        noise = pooled_noise([datasets[k]])
        ratio = predicted.rms / noise if noise > 0 else math.inf
        out.predictions.append({"measurement": datasets[k].measurement.path, "trained_on": [d.measurement.path for d in others],
                                "rms": predicted.rms, "noise": noise, "ratio": ratio,
                                "at_noise": bool(ratio <= AT_NOISE_RATIO)})
    varied = [name for name, p in result.parameters.items() if p.vary and p.kind == "model"]
    for name in varied:
        rows = [(float(s.parameters[name].value), _se(s.parameters[name].stderr)) for s in singles]
        out.singles[name] = rows
        moved = _moves(name, rows, out.first_peaks)
        if moved:
            out.moving.append(moved)
    return out


def _se(x: float | None) -> float:
    return float(x) if x is not None and math.isfinite(x) else math.inf


def _moves(name: str, rows: list, peaks: list) -> dict | None:
    """The largest move of ``name`` between two records in combined stated errors, if beyond MOVE_Z."""
    best = None
    for a in range(len(rows)):
        for b in range(a + 1, len(rows)):
            (va, sa), (vb, sb) = rows[a], rows[b]
            z = abs(va - vb) / math.hypot(sa, sb) if math.isfinite(math.hypot(sa, sb)) else 0.0
            if z > MOVE_Z and (best is None or z > best["z"]):
                best = {"parameter": name, "z": z, "records": [a + 1, b + 1], "values": [va, vb]}
    if best is None:
        return None
    a, b = best["records"]
    best["message"] = (f"{name} moves between records: {best['values'][0]:.4g} in record {a} (first peak "
                       f"{math.degrees(peaks[a - 1]):.3g} deg) and {best['values'][1]:.4g} in record {b} "
                       f"({math.degrees(peaks[b - 1]):.3g} deg), {best['z']:.1f} combined errors apart: the law lacks "
                       "an effect that depends on the swing's amplitude or speed (air drag, a Stribeck curve of "
                       "another shape, a drifting friction level)")
    return best

"""How the diagnosis fares on realistic records: by complication and by friction truth.

Records come from :mod:`vcbmodel.analysis.realistic`: a truth structurally different from every
candidate (friction from the independent event-driven reference, the spring as a converged chain
of 20 equal masses, and a position-dependent friction no registered effect describes), with what
real records carry: a pre-trigger, an initial angle off the rig's nominal, a sensor offset, a
gain error, correlated noise, a hand-driven start, and the "laboratory" combination of an encoder
(0.09 deg steps), an approximate clock and a 2-4 % period error of the rig's geometry. For each
complication group, randomised hidden-effect cases (none, one, two, unregistered) are diagnosed
without knowing the answer. Then the same with friction from outside the fitted family
(:mod:`vcbmodel.reference.truth_friction`: Tustin, LuGre, Dahl, a position-dependent torque), on
pendulums and massless cam drops, and pendulums with air drag on a paddle or a drifting Coulomb level
(:mod:`vcbmodel.reference.torque_truth`).

Scoring (one rule for every record):

- **hit**: the named effects are exactly the expected ones: the hidden ones, or for an
  out-of-family friction the nearest registered ones (``realistic.NEAREST_EXTRA``: Tustin and
  LuGre on a pendulum look like ``stribeck``; an air-drag truth's ``aerodynamic_drag`` may be named
  or not, ``realistic.OPTIONAL_EXTRA``). For an unregistered cause (position-dependent
  friction or torque) a hit is ``explained: false``, or, where the cause leaves nothing above the
  noise (the final rms within RESIDUAL_ABOVE_NOISE of it), the registered part named exactly.
- **verdict right**: for a truth in the fitted family, ``explained: true``. For a truth outside
  it, ``explained`` must say whether the final fit's residual stands above the noise: above when
  its rms exceeds the true noise by more than 5 % (RESIDUAL_ABOVE_NOISE; 5 % of rms is 0.3 sigma of
  excess, several times the rms's own scatter over a record), and then ``explained: false`` is
  right; at or below, ``explained: true`` is. Either way, ``explained: false`` for a model form the
  record prefers (``verdict.rival_form``) is right when a value that form moves (its ``moved`` list:
  beyond ``options.rival_form_errors`` of the stated error) is itself more than EXPLAINED_Z stated
  errors from the truth: the numbers the refusal doubts were wrong (an undeclared artefact such as a
  gain error, a friction law of another shape), and refusing them is what ``explained`` is for. A
  value the rival leaves in place, however wrong, does not make its refusal right.
- **parameter bias against stated error**, and **coverage**: for each fitted parameter whose
  meaning the truth shares, z = (fitted - truth) / stderr with the stderr the diagnosis's final fit
  reports (its JSON ``stderr``), and whether the 95 % interval fitted +- 1.96 stderr holds the
  truth. Comparable: ``viscous`` (the torque's slope C_v at speed, every truth); ``mu_k`` as the
  kinetic level, mu_k - C_v w_s / (r F) with the model's Stribeck shift of the viscous term where
  the fitted model has it and the truth's does not (F: the rig's static load; the shift's own error
  is left out, F varies a few % over a swing); ``mu_s`` (the level at rest) for the hybrid, Tustin,
  LuGre and position-torque truths; ``stribeck_velocity``, ``restitution`` and ``bellows_force``
  for truths in the family only. Not comparable: the Stribeck velocity of another curve's shape,
  Dahl's static level (it has none), and the spring's mass (a discrete choice of spring model,
  the rig gives the mass: no fitted value).

**Model-form coverage** (the same parameters, and a drag or drift the truth has): the 95 % interval
the diagnosis's ``model_forms`` reports (:mod:`vcbmodel.analysis.model_forms`: BIC-weighted forms,
widened to hold every form the record cannot tell apart), against the truth in the quantities'
meanings there: ``mu_k`` the Coulomb level at speed (the truth's mu_k less its own Stribeck shift
C_v w_s / (r F)), ``mu_s`` the level at rest (a truth without a Stribeck fall: its mu_k). "In
family": a hybrid truth with registered effects only. An ``explained`` verdict on an in-family
record should carry no value more than 3 of its stated errors (the model forms' 1-sigma) from the
truth: the count of those that do is listed.

The gap is the rms residual before (starting model) and after (final model) in multiples of the
true noise. The diagnosis runs with its discovery step off (``options.discovery``): discovery
changes no fit, name, verdict or interval scored here (it is reported beside them), it is scored by
``discovery_demo.py``, and on the records left unexplained it was most of this study's time.
Records are made and diagnosed RECORD_WORKERS at a time (a pendulum's diagnosis in one process,
a cam drop's with its pool of simulation processes as alone); the records, their order and the
summary are those of one at a time. Writes results/diagnosis_realism.{json,md,png}.
"""
import math
import multiprocessing
import resource
import tempfile
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from pathlib import Path

import numpy as np
from _common import markdown_table, parse_args, write_json

from vcbmodel.analysis.diagnose import DEFAULT_OPTIONS, diagnose
from vcbmodel.analysis.plausibility import Z95
from vcbmodel.analysis.realistic import (FRICTION_TRUTH_CHOICES, GROUPS, OPTIONAL_EXTRA, TORQUE_TRUTHS, draw_cases,
                                         hidden_answer, realistic_record)
from vcbmodel.app.plots import plt, save
from vcbmodel.experiments.loading import load_pair

RUNS_PER_GROUP = 4
SEED = 11
#: Out-of-family runs per friction truth: complication group -> runs (pendulum and cam cases
#: drawn at random within the group's experiments).
FRICTION_PLAN = {"clean": 3, "correlated": 2, "all_potentiometer": 1, "lab": 1, "all_camera": 1}
FRICTION_SEED = 31
#: The final rms over the true noise above which a residual "stands above the noise".
RESIDUAL_ABOVE_NOISE = 1.05
#: Records made and diagnosed at once (worker processes; each diagnosis's own simulation processes:
#: :func:`diagnosis_processes`). One diagnosis alone keeps about half to three quarters of
#: 2 cores busy (its fits wait on their simulations; benchmark.json: budget_used_s, processor
#: seconds per process, against seconds), so two at a time fill them.
RECORD_WORKERS = 2
#: Parameters whose meaning a truth shares with the model, beyond mu_k and viscous (above).
SHARED = {"hybrid": ("mu_s", "stribeck_velocity", "restitution", "bellows_force"), "tustin": ("mu_s",),
          "lugre": ("mu_s",), "position_torque": ("mu_s",), "dahl": (), "air_drag": ("mu_s", "drag"),
          "drifting_coulomb": ("mu_s", "mu_k_drift")}
#: Out-of-family runs per pendulum truth with an effect the law lacks (air drag, a drifting level).
TORQUE_PLAN = {"clean": 2, "correlated": 1, "all_potentiometer": 1, "lab": 1}
TORQUE_SEED = 71
#: An explained in-family value should lie within this many stated errors of the truth (the study's acceptance criterion, assumed).
EXPLAINED_Z = 3.0
#: Effects whose parameters a truth has (in the family): parameter -> effect.
EFFECT_OF = {"mu_k": "coulomb_friction", "mu_s": "stribeck", "stribeck_velocity": "stribeck",
             "viscous": "viscous_friction", "restitution": "contact_damping", "bellows_force": "bellows_force"}


def truth_value(name, truth, fitted, final_effects):
    """The truth's value of fitted parameter ``name`` in the fitted model's meaning, or None."""
    kind = truth["friction_truth"]
    values = truth.get("truth_friction") or truth.get("truth_values") or {}
    if name not in ("mu_k", "viscous") and name not in SHARED[kind]:
        return None
    if kind == "hybrid" and EFFECT_OF.get(name) not in truth["truth_effects"]:
        return None  # the truth has no such term (its value is unused)
    if name == "mu_s" and kind == "hybrid" and "stribeck" not in final_effects:
        return None
    if name not in values:
        return None
    if name != "mu_k" or truth.get("static_load") is None:
        return float(values[name])

    def shift(vals, effects):
        on = {"stribeck", "viscous_friction"} <= set(effects)
        return vals.get("viscous", 0.0) * vals.get("stribeck_velocity", 0.0) if on else 0.0
    truth_effects = truth["truth_effects"] if kind == "hybrid" else ()
    # the truth's kinetic line written with the fitted model's Stribeck shift of the viscous term
    return float(values["mu_k"] - (shift(values, truth_effects) - shift(fitted, final_effects))
                 / (truth["radius"] * truth["static_load"]))


def comparisons(j, truth):
    """Fitted parameters against the truth: [{parameter, truth, fitted, stderr, z, covered}]."""
    out = []
    for name, se in (j.get("stderr") or {}).items():
        if name not in j["fitted"] or se is None or not math.isfinite(se) or se <= 0:
            continue
        tv = truth_value(name, truth, j["fitted"], j["final_effects"])
        if tv is None:
            continue
        z = (j["fitted"][name] - tv) / se
        out.append({"parameter": name, "truth": tv, "fitted": j["fitted"][name], "stderr": se, "z": z,
                    "covered": bool(abs(z) <= Z95)})
    return out


def form_truth(name, truth):
    """The truth's value of quantity ``name`` in the model forms' meaning (module docstring), or None."""
    kind = truth["friction_truth"]
    values = truth.get("truth_friction") or truth.get("truth_values") or {}
    effects = truth["truth_effects"] if kind == "hybrid" else ("coulomb_friction", "viscous_friction")
    if kind == "dahl" and name == "mu_s":
        return None
    if name == "mu_k" and "mu_k" in values:
        shift = (values.get("viscous", 0.0) * values.get("stribeck_velocity", 0.0)
                 if kind == "hybrid" and {"stribeck", "viscous_friction"} <= set(effects) else 0.0)
        load = truth.get("static_load")
        return float(values["mu_k"] - (shift / (truth["radius"] * load) if shift and load else 0.0))
    if name == "mu_s" and "mu_k" in values:
        has_fall = "stribeck" in effects if kind == "hybrid" else kind not in ("air_drag", "drifting_coulomb")
        return float(values["mu_s"] if has_fall else values["mu_k"])
    if name == "viscous":
        return float(values.get("viscous", 0.0)) if kind != "hybrid" or "viscous_friction" in effects else 0.0
    if name in ("drag", "mu_k_drift"):
        return float(values.get(name, 0.0))
    if name in ("restitution", "bellows_force") and name in values:
        return float(values[name])
    return None


def form_comparisons(j, truth, before):
    """The model forms' quantities against the truth: the parameters of ``before`` (the selected
    fit's comparisons) and the truth's drag or drift: [{parameter, truth, estimate, stderr, low,
    high, z, covered, determined}]."""
    quantities = (j.get("model_forms") or {}).get("quantities") or {}
    names = [c["parameter"] for c in before] + [n for n in ("drag", "mu_k_drift")
                                                  if n in SHARED[truth["friction_truth"]] and n in quantities]
    out = []
    for name in dict.fromkeys(names):
        q, tv = quantities.get(name), form_truth(name, truth)
        if q is None or tv is None:
            continue
        z = (q["estimate"] - tv) / q["stderr"] if q["stderr"] and math.isfinite(q["stderr"]) else 0.0
        out.append({"parameter": name, "truth": tv, "estimate": q["estimate"], "stderr": q["stderr"], "low": q["low"],
                    "high": q["high"], "z": z, "covered": bool(q["low"] <= tv <= q["high"]),
                    "determined": q["determined"]})
    return out


#: The diagnosis as a user runs it, less the discovery step (module docstring).
SCORED_OPTIONS = DEFAULT_OPTIONS.with_(discovery=False)


def run_one(case, seed, complications, folder, t_end=None, friction_truth="hybrid"):
    rig_path, meas_path, truth = realistic_record(case, seed, folder, complications, t_end=t_end,
                                                  friction_truth=friction_truth)
    rig, meas = load_pair(meas_path)
    t0, c0 = time.time(), cpu_seconds()
    d = diagnose(rig, meas, processes=diagnosis_processes(rig), verbose=False, options=SCORED_OPTIONS)
    seconds, cpu = time.time() - t0, cpu_seconds() - c0
    j = d.to_json()
    named = sorted(j["missing_effects"])
    sigma = truth["noise_sigma"]
    after = j["rms_after"] / sigma
    if truth["registered"]:
        optional = set(OPTIONAL_EXTRA.get(friction_truth, ()))
        hit = set(named) - optional == set(truth["answer"]) - optional
    else:  # an unregistered cause: said, or invisible at the noise with the rest named
        hit = not j["explained"] or (after <= RESIDUAL_ABOVE_NOISE and named == hidden_answer(case))
    verdict_right = right_verdict(j, truth["in_family"], after <= RESIDUAL_ABOVE_NOISE, comparisons(j, truth))
    return {"case": case, "seed": seed, "complications": list(complications), "friction_truth": friction_truth,
            "truth": truth, "named": named, "explained": j["explained"], "hit": bool(hit),
            "verdict_right": bool(verdict_right), "rms_before_over_noise": j["rms_before"] / sigma,
            "rms_after_over_noise": after, "noise_estimate": j["noise_estimate"],
            "noise_correlation": j["noise_correlation"], "nuisance": j["nuisance"]["values"],
            "comparisons": comparisons(j, truth), "seconds": seconds, "cpu_seconds": cpu,
            "form_comparisons": form_comparisons(j, truth, comparisons(j, truth)),
            "forms": [{"form": f["form"], "delta_bic": f["delta_bic"], "weight": f["weight"]}
                      for f in (j.get("model_forms") or {}).get("forms", [])],
            "implausible": (j.get("model_forms") or {}).get("plausibility", []),
            "rival_form": (j["verdict"].get("rival_form") or {}).get("form"),
            "rival_moved": rival_moved(j),
            "unresolved_forms": [[u["form"], u["parameter"]] for u in j["verdict"].get("unresolved_forms", [])],
            "simulations": j["timing"]["simulations"], "budget_used_s": j["timing"]["budget_used_s"],
            "budget_reached": j["timing"]["budget_reached"]}


def diagnosis_processes(rig) -> int:
    """Simulation processes of one record's diagnosis: a pendulum's in its own process (its simulations
    take milliseconds: a pool's transfers cost more than its second core gains, vcbmodel.analysis.fit.pool
    .INLINE_BELOW_S, and RECORD_WORKERS records at a time fill the cores; measured: the same verdicts and
    values, 15-30 % less processor time), any other with its pool of 2 as when alone (an ANCF spring's
    simulations take 0.1-0.3 s, and the diagnosis's time budget counts processor time per process)."""
    return 1 if rig.experiment == "pendulum" else 2


def rival_moved(j: dict) -> dict:
    """{parameter: shift in stated errors} of the values the verdict's rival model form moves
    (``verdict.rival_form.moved``; empty without one)."""
    return {m["parameter"]: m["errors"] for m in (j["verdict"].get("rival_form") or {}).get("moved", [])}


def right_verdict(j: dict, in_family: bool, at_noise: bool, selected: list) -> bool:
    """Is the verdict of diagnosis JSON ``j`` right (module docstring)? In the family explained is;
    outside it, explained when the final residual is ``at_noise`` (the true noise's); either way a
    refusal for a rival model form when a value the form moves is one the selected fit states beyond
    EXPLAINED_Z errors of the truth (``selected``: its comparisons)."""
    moved = rival_moved(j)
    refused_rightly = not j["explained"] and any(c["parameter"] in moved and abs(c["z"]) > EXPLAINED_Z
                                                 for c in selected)
    expected = True if in_family else at_noise
    return bool(j["explained"]) == expected or refused_rightly


def cpu_seconds():
    """Processor seconds (user + system) of this process and its finished children (a diagnosis'
    simulation workers are joined when it ends)."""
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def figure(records, path):
    """Per complication group and per friction truth: hits, right verdicts and coverage (bars),
    every run's gap before and after, and every comparison's |z|."""
    fig, (a1, a2, a3) = plt.subplots(3, 1, figsize=(10, 9.5))
    labels = list(dict.fromkeys(f"{r['friction_truth']}:{r['group']}" for r in records))
    x = np.arange(len(labels))
    share = {k: [] for k in ("hit", "verdict_right", "covered")}
    for lab in labels:
        rs = [r for r in records if f"{r['friction_truth']}:{r['group']}" == lab]
        cs = [c for r in rs for c in r["comparisons"]]
        share["hit"].append(np.mean([r["hit"] for r in rs]))
        share["verdict_right"].append(np.mean([r["verdict_right"] for r in rs]))
        share["covered"].append(np.mean([c["covered"] for c in cs]) if cs else np.nan)
    for k, (key, text) in enumerate((("hit", "hit (named the expected effects)"), ("verdict_right", "verdict right"),
                                     ("covered", "95 % interval holds the truth"))):
        a1.bar(x + (k - 1) * 0.27, share[key], 0.27, label=text)
    a1.axhline(0.95, color="k", lw=0.6, ls=":")
    a1.set_ylabel("share")
    a1.set_ylim(0, 1.05)
    a1.legend(fontsize=7, loc="lower left")
    a1.set_title("Diagnosis on realistic SYNTHETIC records, by friction truth : complication group")
    for i, lab in enumerate(labels):
        rs = [r for r in records if f"{r['friction_truth']}:{r['group']}" == lab]
        for k, r in enumerate(rs):
            dx = (k - (len(rs) - 1) / 2) * 0.1
            c = "tab:green" if r["hit"] and r["verdict_right"] else "tab:red"
            a2.plot([i + dx, i + dx], [r["rms_before_over_noise"], r["rms_after_over_noise"]], color=c, lw=1)
            a2.plot(i + dx, r["rms_after_over_noise"], "o", color=c, ms=3)
            for cmp in r["comparisons"]:
                a3.plot(i + dx, max(abs(cmp["z"]), 1e-2), "o" if cmp["parameter"] == "mu_k" else ".",
                        color="tab:blue" if cmp["covered"] else "tab:red", ms=4)
    a2.axhline(1.0, color="k", lw=0.8, ls="--")
    a2.set_yscale("log")
    a2.set_ylabel("rms / true noise\n(line: before -> dot: after)")
    a3.axhline(Z95, color="k", lw=0.8, ls="--")
    a3.set_yscale("log")
    a3.set_ylabel("|fitted - truth| / stderr\n(o: mu_k, .: others)")
    for a in (a1, a2, a3):
        a.set_xticks(x)
        a.set_xticklabels(labels if a is a3 else [], rotation=40, ha="right", fontsize=7)
    save(fig, path)


def plan(quick):
    """[(friction truth, group, [(case, seed)], t_end)] of the run."""
    if quick:
        return [("hybrid", "pre_trigger", [("pend_visc", 1)], 3.0), ("hybrid", "all_camera", [("cam_coul", 2)], None),
                ("tustin", "clean", [("pend_none", 3)], 3.0), ("lugre", "clean", [("cam_none", 4)], None),
                ("air_drag", "clean", [("pend_visc", 5)], 5.0), ("drifting_coulomb", "clean", [("pend_none", 6)], 5.0)]
    out = [("hybrid", g, draw_cases(g, RUNS_PER_GROUP, SEED + k), None) for k, g in enumerate(GROUPS)]
    for i, kind in enumerate(FRICTION_TRUTH_CHOICES[1:]):
        if kind in TORQUE_TRUTHS:
            continue
        for k, (g, n) in enumerate(FRICTION_PLAN.items()):
            out.append((kind, g, draw_cases(g, n, FRICTION_SEED + 10 * i + k, friction_truth=kind), None))
    for i, kind in enumerate(TORQUE_TRUTHS):
        for k, (g, n) in enumerate(TORQUE_PLAN.items()):
            out.append((kind, g, draw_cases(g, n, TORQUE_SEED + 10 * i + k, friction_truth=kind), None))
    return out


def coverage_split(records):
    """Coverage in and out of the family, by the selected fit alone (before) and by the model forms
    (after), and the explained in-family values beyond EXPLAINED_Z stated errors."""
    out = {}
    for label, rs in (("in_family", [r for r in records if r["truth"]["in_family"]]),
                      ("out_of_family", [r for r in records if not r["truth"]["in_family"]])):
        before = [c for r in rs for c in r["comparisons"]]
        after = [c for r in rs for c in r["form_comparisons"]]
        explained = [r for r in rs if r["explained"]]
        out[label] = {"runs": len(rs), "before": {"compared": len(before), "covered": sum(c["covered"] for c in before)},
                      "after": {"compared": len(after), "covered": sum(c["covered"] for c in after)},
                      "explained_beyond_3_before": sum(abs(c["z"]) > EXPLAINED_Z for r in explained
                                                        for c in r["comparisons"]),
                      "explained_beyond_3_after": sum(abs(c["z"]) > EXPLAINED_Z for r in explained
                                                       for c in r["form_comparisons"]),
                      "explained_compared": sum(len(r["form_comparisons"]) for r in explained),
                      "explained_naming_unresolved_form": sum(bool(r["unresolved_forms"]) for r in explained),
                      "explained": len(explained)}
    return out


def summarise(rs):
    """Counts, medians, coverage and the median |z| of a set of runs."""
    cs = [c for r in rs for c in r["comparisons"]]
    return {"runs": len(rs), "hits": sum(r["hit"] for r in rs), "verdict_right": sum(r["verdict_right"] for r in rs),
            "median_rms_before_over_noise": float(np.median([r["rms_before_over_noise"] for r in rs])),
            "median_rms_after_over_noise": float(np.median([r["rms_after_over_noise"] for r in rs])),
            "compared": len(cs), "covered": sum(c["covered"] for c in cs),
            "median_abs_z": float(np.median([abs(c["z"]) for c in cs])) if cs else None,
            "median_seconds": float(np.median([r["seconds"] for r in rs])),
            "max_seconds": float(max(r["seconds"] for r in rs))}


def by_parameter(records):
    """(friction truth, parameter) -> compared, covered, median bias / truth and median |z|."""
    out = {}
    for r in records:
        for c in r["comparisons"]:
            out.setdefault((r["friction_truth"], c["parameter"]), []).append(c)
    return {f"{k}:{p}": {"compared": len(cs), "covered": sum(c["covered"] for c in cs),
                         "median_relative_bias": float(np.median([(c["fitted"] - c["truth"]) / c["truth"] for c in cs])),
                         "median_abs_z": float(np.median([abs(c["z"]) for c in cs]))}
            for (k, p), cs in out.items()}


def _row(name, extra, b):
    cov = f"{b['covered']}/{b['compared']}" if b["compared"] else "-"
    z = f"{b['median_abs_z']:.1f}" if b["median_abs_z"] is not None else "-"
    return [name, *extra, b["runs"], f"{b['hits']}/{b['runs']}", f"{b['verdict_right']}/{b['runs']}",
            f"{b['median_rms_before_over_noise']:.1f}", f"{b['median_rms_after_over_noise']:.2f}", cov, z,
            f"{b['median_seconds']:.1f}", f"{b['max_seconds']:.0f}"]


COLUMNS = ["runs", "hits", "verdict right", "rms before (x noise)", "rms after (x noise)", "95 % covers",
           "median abs(z)", "median time (s)", "max time (s)"]


def write_markdown(out, records, summary):
    n, hits, verdicts = summary["runs"], summary["hits"], summary["verdict_right"]
    cov = summary["coverage"]
    groups = [_row(g, [", ".join(GROUPS[g][0]) or "(none)"], b) for g, b in summary["by_group"].items()]
    truths = [_row(k, [], b) for k, b in summary["by_friction_truth"].items()]
    params = [[k.split(":")[0], k.split(":")[1], f"{b['covered']}/{b['compared']}", f"{100 * b['median_relative_bias']:+.1f} %",
               f"{b['median_abs_z']:.1f}"] for k, b in summary["by_parameter"].items()]
    detail = [[r["friction_truth"], r["group"], r["case"], r["seed"],
               "(unregistered)" if r["truth"]["answer"] is None else ", ".join(r["truth"]["answer"]) or "none",
               ", ".join(r["named"]) or "none", r["explained"], "yes" if r["hit"] else "NO",
               "yes" if r["verdict_right"] else "NO", f"{r['rms_before_over_noise']:.1f}",
               f"{r['rms_after_over_noise']:.2f}",
               "; ".join(f"{c['parameter']} {c['fitted']:.4g}+-{c['stderr']:.2g} ({c['truth']:.4g}, z {c['z']:+.1f})"
                         for c in r["comparisons"]) or "-",
               "; ".join(f"{c['parameter']} [{c['low']:.4g}, {c['high']:.4g}] ({c['truth']:.4g}"
                         + ("" if c["covered"] else ", OUT") + ")" for c in r["form_comparisons"]) or "-",
               f"{r['seconds']:.1f}"] for r in records]
    split = summary["coverage_split"]
    forms_rows = [[label.replace("_", " "), c["runs"], f"{c['before']['covered']}/{c['before']['compared']}",
                   f"{c['after']['covered']}/{c['after']['compared']}",
                   f"{c['explained_beyond_3_before']}", f"{c['explained_beyond_3_after']}"] for label, c in split.items()]
    after = sum(c["after"]["covered"] for c in split.values()), sum(c["after"]["compared"] for c in split.values())
    (out / "diagnosis_realism.md").write_text(
        f"# Diagnosis on realistic records (synthetic): {hits}/{n} hits, verdict right {verdicts}/{n}, "
        f"95 % intervals cover {cov['covered']}/{cov['compared']} (selected fit), {after[0]}/{after[1]} "
        "(model forms)\n\n"
        "Records from `vcbmodel.analysis.realistic` (SYNTHETIC): friction from the fitted family's own law "
        "(`hybrid`, by the independent reference) or from outside it (`tustin`, `lugre`, `dahl`, "
        "`position_torque`; on pendulums also `air_drag` and `drifting_coulomb`). A hit names exactly the "
        "expected effects (an unregistered cause: says "
        "`explained: false`, or leaves nothing above the noise and the rest is named exactly); the verdict is "
        "right when `explained` is true for a truth in the family and, for "
        f"one outside it, says whether the final rms exceeds {RESIDUAL_ABOVE_NOISE:g}x the true noise. Coverage: "
        f"how often fitted +- {Z95:.2f} stderr (the final fit's) holds the truth, over the parameters whose meaning "
        "the truth shares (study docstring); z = (fitted - truth) / stderr. Times: wall seconds of each "
        f"diagnosis, {summary['record_workers']} records diagnosed at once on {summary['cores']} cores (median "
        f"{summary['seconds_median']:.1f} s, max {summary['seconds_max']:.0f} s; processor seconds of the diagnosis and its "
        f"simulation workers: median {summary['cpu_seconds_median']:.1f} s, total {summary['cpu_seconds_total']:.0f} s; "
        "one diagnosis alone: `benchmark.md`).\n\n"
        "## Coverage: the selected fit alone and the model forms\n\n"
        f"The selected fit's 95 % interval (fitted +- {Z95:.2f} stderr) against the model forms' (`model_forms` in the "
        "diagnosis JSON: BIC-weighted forms, the interval holding each form within the evidence margin), each "
        "against the truth in its meaning (study docstring); and how many values of an `explained` verdict lie "
        f"more than {EXPLAINED_Z:g} of their stated errors from the truth.\n\n"
        + markdown_table(["records", "runs", "selected fit covers", "model forms cover",
                          f"explained, beyond {EXPLAINED_Z:g} errors (selected)",
                          f"explained, beyond {EXPLAINED_Z:g} errors (forms)"], forms_rows)
        + "\n## By friction truth\n\n" + markdown_table(["friction truth", *COLUMNS], truths)
        + "\n## By complication (every friction truth)\n\n" + markdown_table(["group", "complications", *COLUMNS], groups)
        + "\n## Parameters against the truth\n\n"
        + markdown_table(["friction truth", "parameter", "95 % covers", "median bias", "median abs(z)"], params)
        + "\n## Every run\n\n"
        + markdown_table(["friction truth", "group", "case", "seed", "expected", "named", "explained", "hit",
                          "verdict right", "rms before", "rms after", "fitted +- stderr (truth, z)",
                          "model forms' 95 % (truth)", "time (s)"], detail))


def _made_and_diagnosed(task):
    """One record of the plan (task: friction truth, group, case, seed, t_end, folder), made and
    diagnosed: run_one's dict with its group."""
    kind, group, case, seed, t_end, folder = task
    r = run_one(case, seed, GROUPS[group][0], folder, t_end, kind)
    r["group"] = group
    return r


def _say(r, done, total):
    print(f"[{done}/{total}] {r['friction_truth']:15s} {r['group']:18s} {r['case']:18s} seed {r['seed']}: named "
          f"{r['named']} explained {r['explained']} -> {'hit' if r['hit'] else 'MISS'}, verdict "
          f"{'right' if r['verdict_right'] else 'WRONG'}; rms {r['rms_before_over_noise']:.1f} -> "
          f"{r['rms_after_over_noise']:.2f} x noise; {sum(c['covered'] for c in r['comparisons'])}/"
          f"{len(r['comparisons'])} covered; {r['seconds']:.1f} s ({r['cpu_seconds']:.1f} s processor)", flush=True)


def diagnose_plan(quick, folder, workers=RECORD_WORKERS):
    """Every record of the plan made and diagnosed, ``workers`` at a time (forked processes; 1: in
    this process, one after another), returned in the plan's order. The out-of-family truths,
    whose pendulum diagnoses run longest, end the plan: they start first, so the workers finish
    close together."""
    tasks = [(kind, group, case, seed, t_end, folder) for kind, group, draws, t_end in plan(quick) for case, seed in draws]
    records = [None] * len(tasks)
    if workers <= 1:
        for i, task in enumerate(tasks):
            records[i] = _made_and_diagnosed(task)
            _say(records[i], i + 1, len(tasks))
        return records
    with ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("fork")) as pool:
        running = {pool.submit(_made_and_diagnosed, tasks[i]): i for i in reversed(range(len(tasks)))}
        while running:
            finished, _ = wait(running, return_when=FIRST_COMPLETED)
            for f in finished:
                i = running.pop(f)
                records[i] = f.result()
                _say(records[i], len(tasks) - len(running), len(tasks))
    return records


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    with tempfile.TemporaryDirectory() as tmp:
        records = diagnose_plan(args.quick, tmp)
    times = [r["seconds"] for r in records]
    cs = [c for r in records for c in r["comparisons"]]
    summary = {"synthetic": True, "realistic": True, "runs": len(records), "hits": sum(r["hit"] for r in records),
               "hit_rate": sum(r["hit"] for r in records) / len(records),
               "verdict_right": sum(r["verdict_right"] for r in records),
               "coverage": {"compared": len(cs), "covered": sum(c["covered"] for c in cs)},
               "residual_above_noise": RESIDUAL_ABOVE_NOISE,
               "seconds_median": float(np.median(times)), "seconds_max": float(max(times)),
               "record_workers": RECORD_WORKERS, "cores": multiprocessing.cpu_count(),
               "cpu_seconds_median": float(np.median([r["cpu_seconds"] for r in records])),
               "cpu_seconds_total": float(sum(r["cpu_seconds"] for r in records)),
               "budget_reached": sum(r["budget_reached"] for r in records),
               "by_friction_truth": {k: summarise([r for r in records if r["friction_truth"] == k])
                                     for k in dict.fromkeys(r["friction_truth"] for r in records)},
               "by_group": {g: summarise([r for r in records if r["group"] == g])
                            for g in dict.fromkeys(r["group"] for r in records)},
               "by_parameter": by_parameter(records), "coverage_split": coverage_split(records), "records": records}
    write_json(out / "diagnosis_realism.json", summary)
    figure(records, out / "diagnosis_realism.png")
    write_markdown(out, records, summary)
    print(f"hits {summary['hits']}/{len(records)}, verdict right {summary['verdict_right']}/{len(records)}, "
          f"covered {summary['coverage']['covered']}/{summary['coverage']['compared']}")
    for label, c in summary["coverage_split"].items():
        print(f"{label}: selected fit covers {c['before']['covered']}/{c['before']['compared']}, model forms "
              f"{c['after']['covered']}/{c['after']['compared']}; explained values beyond {EXPLAINED_Z:g} errors "
              f"{c['explained_beyond_3_before']} -> {c['explained_beyond_3_after']}; explained records naming a form the "
              f"record does not resolve {c['explained_naming_unresolved_form']}/{c['explained']}")


if __name__ == "__main__":
    main()

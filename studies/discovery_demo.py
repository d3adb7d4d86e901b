"""Discovery of what no registry has, on two SYNTHETIC pendulum records (a light pendulum with a flat
paddle of 0.02 m^2 at 0.3 m, released at 1.5 rad, 0.5 mrad potentiometer noise, the rig's model Coulomb +
viscous friction with their values unknown).

Record 1: the truth adds the paddle's air drag, -c w|w| with c = 0.5 rho Cd A R^3 = 3.8e-4 N m s^2/rad^2
(rho 1.2 kg/m^3, Cd 1.17: vcbmodel.parameters). Released at 0.8 rad (4 rad/s) the registered friction
absorbs this drag within the noise; at 1.5 rad the swing reaches 7 rad/s, where the drag is 38 % of the
Coulomb torque. The registry has air drag (``aerodynamic_drag``): the diagnosis names it; discovery
runs on the rig's starting model (without it) and must find the same torque as w|w|, whatever the
diagnosis names. Record 2: the
truth adds a torque in the library's blind spot, a 1.9 Hz forcing (a vibrating floor) at no multiple
of the swing frequency. Both truths are integrated independently of the model (scipy, event sticking:
:mod:`vcbmodel.reference.torque_truth`; they share with the model the pendulum's equation and the
hybrid friction's Coulomb and viscous parts, not its code). Each record is diagnosed (the registered
effects); the forcing record's discover step runs on the diagnosis's final and starting models.

Cam drops (paper section 3; the demo cam of results/synthetic/demo_cam, massless springs, Coulomb
friction mu_k 0.13 unknown to the rig, 2 mrad camera noise at 12 kHz, 35 ms): a profile torque
-A sin(2 theta - phi) (a follower spring on a two-lobed profile: in the library as sin/cos 2 theta),
a 400 Hz forcing (outside the library: the negative control), and a record with no extra torque
(in the fitted family: no false discovery). Truths from :mod:`vcbmodel.reference.cam_torque_truth`
(complex-number Newton-Euler, shares the rig's reading with the model, no code). And a cam drop whose
closing springs damp themselves (Kelvin-Voigt, first surge mode's damping ratio 0.05, the top of the
plausible range) on a rig with lumped springs (8 masses, uniform): the truth a 32-segment damped
continuum (:mod:`vcbmodel.reference.cam_spring_truth`); is it read as shaft viscous friction?
Writes results/discovery.{md,json,png}, results/discovery_cam.png and the rigs
results/synthetic/discovery_{demo,cam,spring}.rig.json. ``--quick``: the drag and the damped-spring
records only (every single term is refitted: the others cost minutes on 2 cores).
"""
import copy
import math
import time
from pathlib import Path

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from _common import markdown_table, parse_args, write_json  # noqa: E402

from vcbmodel.analysis.diagnose import BIC_MARGIN, MIN_VARIANCE_GAIN, diagnose  # noqa: E402
from vcbmodel.analysis.discovery import discover, discover_among, excess  # noqa: E402
from vcbmodel.analysis.discovery.library import model_columns  # noqa: E402
from vcbmodel.analysis.synthetic import write_rig  # noqa: E402
from vcbmodel.experiments.loading import load_rig  # noqa: E402
from vcbmodel.laws.discovered import TERMS  # noqa: E402
from vcbmodel.laws.friction import ArrayOps  # noqa: E402
from vcbmodel.laws.mechanics import paddle_drag_coefficient  # noqa: E402
from vcbmodel.records.measurement import Measurement  # noqa: E402
from vcbmodel.reference.cam_spring_truth import cam_drop_with_damped_spring  # noqa: E402
from vcbmodel.reference.cam_torque_truth import cam_drop_with_torque  # noqa: E402
from vcbmodel.reference.torque_truth import pendulum_with_torque  # noqa: E402

PENDULUM = {"mass": 5.0, "inertia": 0.5, "com_distance": 0.3, "initial_angle": 1.5, "initial_velocity": 0.0}
PADDLE = (0.02, 0.3)  # m^2, m: a flat paddle's area and the radius of its centre
RIG = {"format": "vcb-rig/1", "name": f"discovery demo: light pendulum with a {PADDLE[0]:g} m^2 paddle at {PADDLE[1]:g} m, "
                                     f"{PENDULUM['initial_angle']:g} rad release",
       "experiment": "pendulum",
       "gravity": 9.81, "shaft": {"radius": 0.02}, "pendulum": PENDULUM, "friction": {},
       "model": {"effects": ["coulomb_friction", "viscous_friction"], "spring_model": "massless"}}
FRICTION = {"mu_k": 0.05, "viscous": 0.01}  # truth: mu_k -, Cv N m s/rad
DRAG = paddle_drag_coefficient(*PADDLE)  # truth: 3.8e-4 N m s^2/rad^2; at the swing's 7 rad/s, 19 mN m
DRAG_DURATION = 5.0  # s: over 5 s this truth and the model agree within 2 urad at equal values (16 urad rms over 8 s)
FORCING = (0.1, 1.9)  # truth: N m, Hz
SIGMA = 0.5e-3  # rad
RATE = 1000.0  # Hz: the pendulum records' sample rate


CAM = {"mass": 6.0, "inertia_com": 0.05, "com_distance": 0.02, "com_angle": 0.5, "pivot": [0.4445, 0.0],
       "arm_length": 0.1032, "initial_angle": 0.17453292519943295, "initial_velocity": 0.0}
SPRING = {"count": 2, "stiffness": 24230.0, "mass": 1.0, "free_length": 0.3, "anchor": [0.0, 0.0]}
CAM_RIG = {"format": "vcb-rig/1", "name": "discovery demo: cam drop, massless springs", "experiment": "cam_drop",
           "gravity": 9.81, "shaft": {"radius": 0.02}, "cam": CAM, "closing_spring": SPRING,
           "friction": {"stick_velocity": 0.001}, "model": {"effects": ["coulomb_friction"], "spring_model": "massless"}}
CAM_FRICTION = {"mu_k": 0.13}  # truth
PROFILE = (30.0, 0.6)  # truth: N m, rad (-A sin(2 theta - phi); the springs' torque is about 480 N m at release)
CAM_FORCING = (100.0, 120.0)  # truth: N m, Hz (a mains-fed solenoid's hum)
CAM_SIGMA, CAM_RATE, CAM_DURATION = 2e-3, 12000.0, 0.035  # rad, Hz, s
#: The damped-spring case: the demo cam with lumped closing springs (8 masses, uniform convention: the
#: 32-segment continuum's drop within 1.0 mrad rms, the exact convention's 8 masses 2.9 mrad).
SPRING_RIG = dict(CAM_RIG, name="discovery demo: cam drop, lumped closing springs",
                  model={"effects": ["coulomb_friction", "spring_mass"], "spring_model": "lumped-8",
                         "lumped_convention": "uniform"})
SPRING_DAMPING = 0.05  # truth: first surge mode's damping ratio (the top of SPRING_DAMPING_RATIO_RANGE)
TRUTH_SEGMENTS = 32


def cam_record(kind, seed):
    """(measurement, truth, true extra torque (t, theta, w) -> N m) of a synthetic cam drop."""
    A, phi = PROFILE
    if kind == "spring_damping":
        return spring_record(seed)
    if kind == "profile":
        def extra(t, th, w):
            return -A * math.sin(2 * th - phi)
        truth = {"extra": f"profile torque -{A:g} sin(2 theta - {phi:g}) N m", "sin_2theta": -A * math.cos(phi),
                 "cos_2theta": A * math.sin(phi)}
    elif kind == "forcing":
        def extra(t, th, w):
            return CAM_FORCING[0] * math.sin(2 * math.pi * CAM_FORCING[1] * t)
        truth = {"extra": f"forcing {CAM_FORCING[0]:g} N m at {CAM_FORCING[1]:g} Hz (outside the library)"}
    else:
        def extra(t, th, w):
            return 0.0
        truth = {"extra": "none (in the fitted family)"}
    t = np.arange(int(round(CAM_DURATION * CAM_RATE)) + 1) / CAM_RATE
    theta, _ = cam_drop_with_torque(CAM, SPRING, CAM_RIG["gravity"], CAM_RIG["shaft"]["radius"], CAM_FRICTION, extra, t)
    y = theta + np.random.default_rng(seed).normal(0.0, CAM_SIGMA, t.size)
    meas = Measurement(f"discovery_cam_{kind}.csv", t, {"cam_angle": y},
                       (f"SYNTHETIC: cam drop, Coulomb friction {CAM_FRICTION}, {truth['extra']}, noise {CAM_SIGMA} rad, "
                        f"seed {seed}",))
    return meas, {**truth, "friction": CAM_FRICTION, "noise_rad": CAM_SIGMA, "seed": seed}, extra


def spring_record(seed):
    """(measurement, truth, no extra torque) of the cam drop with self-damping springs."""
    t = np.arange(int(round(CAM_DURATION * CAM_RATE)) + 1) / CAM_RATE
    theta, _ = cam_drop_with_damped_spring(CAM, SPRING, CAM_RIG["gravity"], CAM_RIG["shaft"]["radius"], CAM_FRICTION,
                                           SPRING_DAMPING, t, TRUTH_SEGMENTS)
    y = theta + np.random.default_rng(seed).normal(0.0, CAM_SIGMA, t.size)
    extra = f"closing springs damped inside (Kelvin-Voigt, zeta {SPRING_DAMPING:g})"
    meas = Measurement("discovery_spring.csv", t, {"cam_angle": y},
                       (f"SYNTHETIC: cam drop, Coulomb friction {CAM_FRICTION}, {extra}, {TRUTH_SEGMENTS}-segment "
                        f"continuum, noise {CAM_SIGMA} rad, seed {seed}",))
    truth = {"extra": extra, "damping_ratio": SPRING_DAMPING, "friction": CAM_FRICTION, "noise_rad": CAM_SIGMA,
             "seed": seed}
    return meas, truth, lambda t, th, w: 0.0


def record(kind, duration, seed):
    """(measurement, truth description, true extra torque as a function of (t, theta, w))."""
    if kind == "drag":
        def extra(t, th, w):
            return -DRAG * w * abs(w)
        truth = {"extra": f"air drag -c w abs(w) of a {PADDLE[0]:g} m^2 paddle at {PADDLE[1]:g} m", "c": DRAG,
                 "unit": "N m s^2/rad^2", "w_abs_w": -DRAG, "drag": DRAG}
    else:
        def extra(t, th, w):
            return FORCING[0] * math.sin(2 * math.pi * FORCING[1] * t)
        truth = {"extra": f"forcing {FORCING[0]} N m at {FORCING[1]} Hz (outside the library)"}
    t = np.arange(int(round(duration * RATE)) + 1) / RATE
    theta = pendulum_with_torque(PENDULUM, RIG["gravity"], RIG["shaft"]["radius"], FRICTION, extra, t)
    y = theta + np.random.default_rng(seed).normal(0.0, SIGMA, t.size)
    meas = Measurement(f"discovery_{kind}.csv", t, {"pendulum_angle": y},
                       (f"SYNTHETIC: pendulum, Coulomb + viscous friction {FRICTION}, {truth['extra']}, "
                        f"noise {SIGMA} rad, seed {seed}",))
    return meas, {**truth, "friction": FRICTION, "noise_rad": SIGMA, "seed": seed}, extra


def run_case(rig, kind, duration, seed):
    meas, truth, extra = cam_record(kind, seed) if rig.experiment == "cam_drop" else record(kind, duration, seed)
    t0 = time.monotonic()
    d = diagnose(rig, meas, verbose=False)  # its discover step runs when the registered model leaves a gap
    disc = d.discovery
    if kind == "drag":  # the registry has air drag: discovery on the rig's starting model, without it
        disc = discover(rig, meas, d.baseline_own_alignment, bic_margin=BIC_MARGIN, min_gain=MIN_VARIANCE_GAIN)
    elif disc is None:  # the diagnosis did not search (its verdict, or its time budget): search here, and say so
        print(f"{kind}: the diagnosis did not search ({d.discovered.get('reason')}); discovery run after it")
        disc = discover_among(rig, meas, [d.final, d.baseline_own_alignment], bic_margin=BIC_MARGIN,
                              min_gain=MIN_VARIANCE_GAIN)
    seconds = {"diagnosis with discovery": round(time.monotonic() - t0, 1), "discovery": round(disc.seconds, 1),
               "diagnosis_searched": d.discovery is not None, "diagnosis_discovered": d.discovered}
    return {"kind": kind, "measurement": meas, "truth": truth, "extra": extra, "diagnosis": d, "discovery": disc,
            "seconds": seconds}


def summary(case):
    d, disc = case["diagnosis"], case["discovery"]
    noise = disc.noise
    out = {"truth": case["truth"], "seconds": case["seconds"],
           "diagnosis": {"missing_effects": d.missing_effects, "explained": d.explained, "rms_before": d.baseline.rms,
                         "rms_after": d.final.rms, "fitted": d.final.model_values},
           "discovery": disc.to_json(),
           "gap": {"noise_rad": noise, "rms_registered_rad": disc.rms_before, "rms_discovered_rad": disc.rms_after,
                   "excess_registered_rad": excess(disc.rms_before, noise),
                   "excess_discovered_rad": excess(disc.rms_after, noise)}}
    checks = []
    for t in disc.terms:
        true = case["truth"].get(t.name)
        if true is not None:
            checks.append({"term": t.name, "found": t.coefficient, "stderr": t.stderr, "truth": true,
                           "errors_off": abs(t.coefficient - true) / t.stderr if t.stderr else None,
                           "relative_error": abs(t.coefficient - true) / abs(true)})
        elif t.name.startswith(("sin_", "cos_", "rub_")):  # a term the truth does not hold: its value is the error
            checks.append({"term": t.name, "found": t.coefficient, "stderr": t.stderr, "truth": 0.0,
                           "errors_off": abs(t.coefficient) / t.stderr if t.stderr else None, "relative_error": None})
    if checks:
        out["discovery"]["truth_check"] = checks[0]
        out["discovery"]["truth_checks"] = checks
    out["diagnosis"]["truth_checks"] = registered_checks(d.final, case["truth"])
    js = d.to_json()
    out["diagnosis"]["candidates"] = [{"effect": c["effect"], "delta_bic": c.get("delta_bic"),
                                       "parameters": c.get("parameters")} for c in js["candidates"]]
    out["diagnosis"]["ambiguous"] = js["ambiguous"]
    return out


def registered_checks(fit, truth):
    """Each registered value the diagnosis fitted whose truth is known: value, stated error, truth and
    how many stated errors apart."""
    known = {**truth.get("friction", {}), **{k: truth[k] for k in ("drag", "damping_ratio") if k in truth}}
    out = []
    for name, p in fit.parameters.items():
        if p.kind == "model" and p.vary and name in known:
            out.append({"parameter": name, "value": p.value, "stderr": p.stderr, "truth": known[name],
                        "errors_off": abs(p.value - known[name]) / p.stderr if p.stderr else None})
    return out


def residual_panel(ax, disc, time_scale, time_unit, lw, title, legend_at):
    """The residual of the best registered model and of the model with the discovered torque, with
    the noise band; times scaled by ``time_scale`` into ``time_unit``."""
    for fit, label in ((disc.before, "best registered model"), (disc.after, "with the discovered torque")):
        if fit is not None:
            ax.plot(time_scale * fit.times[0], 1e3 * fit.residuals[0], lw=lw, label=f"{label}: rms {1e3 * fit.rms:.2f} mrad")
    ax.axhspan(-1e3 * disc.noise, 1e3 * disc.noise, color="0.85", label="noise band (1 sigma)")
    ax.set_xlabel(f"t [{time_unit}]")
    ax.set_ylabel("model - record [mrad]")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7, loc=legend_at)


def plot(cases, path):
    fig, axes = plt.subplots(len(cases), 2, figsize=(11, 3.6 * len(cases)))
    for row, case in zip(np.atleast_2d(axes), cases):
        residual_panel(row[0], case["discovery"], 1.0, "s", 0.6, f"{case['truth']['extra']}: residual", "upper right")
        _torque_panel(row[1], case)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _binned(x, y, bins=40):
    edges = np.linspace(x.min(), x.max(), bins + 1)
    idx = np.clip(np.digitize(x, edges) - 1, 0, bins - 1)
    keep = [i for i in range(bins) if np.any(idx == i)]
    return (np.array([x[idx == i].mean() for i in keep]), np.array([y[idx == i].mean() for i in keep]))


def _rebalanced(disc):
    """The missing torque (N m) with the registered model's own values moved as the regression asks
    (its friction bent to mimic the missing torque gives part of it back)."""
    sel, est = disc.selection, disc.estimate
    names = [t.name for t in disc.terms]
    shift = sel.support_fit(names)[2] if names else sel.base_shift
    z_names, Z = model_columns(disc.given, est)
    return est.torque - (Z @ np.array([shift.get(n, 0.0) for n in z_names]) if z_names else 0.0)


def _torque_panel(ax, case):
    """The missing torque the record shows on the best registered model (against speed for the drag,
    against time for the forcing), with the truth's and the discovered form."""
    disc = case["discovery"]
    est = disc.estimate
    used = est.used
    x = est.w if case["kind"] == "drag" else est.t
    torque = _rebalanced(disc)
    ax.plot(x[used], torque[used], ".", ms=1, color="0.75", label="missing torque from the record")
    bx, by = _binned(x[used], torque[used], 40 if case["kind"] == "drag" else 300)
    ax.plot(bx, by, "o", ms=3, color="0.3", label="its mean in bins")
    if case["kind"] == "drag":
        w = np.linspace(bx.min(), bx.max(), 200)
        ax.plot(w, [case["extra"](0.0, 0.0, v) for v in w], "k--", lw=1, label="truth: -c w abs(w)")
        for t in disc.terms:
            form = t.coefficient * np.asarray(TERMS[t.name].value(0.0 * w, 0.0 * w, w, ArrayOps)) * np.ones_like(w)
            ax.plot(w, form, "r", lw=1, label=f"discovered: {t.name} {t.coefficient:.3g} {t.unit}")
        ax.set_xlabel("w [rad/s]")
    else:
        ax.plot(x[used], [case["extra"](v, 0.0, 0.0) for v in x[used]], "k-", lw=0.5, label="truth: the forcing")
        ax.set_xlim(0, 3)
        ax.set_xlabel("t [s] (first 3 s)")
    if not disc.terms:
        ax.set_title("nothing found: no library term earns the evidence", fontsize=9)
    else:
        ax.set_title("missing torque, the registered values re-balanced by the regression", fontsize=9)
    ax.set_ylabel("torque [N m]")
    ax.legend(fontsize=7, loc="lower left")


def cam_plot(cases, path):
    """Residuals (left) and the missing torque against the cam angle with the truth and the
    discovered form (right), one row per cam record."""
    fig, axes = plt.subplots(len(cases), 2, figsize=(11, 3.4 * len(cases)))
    for row, case in zip(np.atleast_2d(axes), cases):
        disc = case["discovery"]
        residual_panel(row[0], disc, 1e3, "ms", 0.7, f"cam drop, {case['truth']['extra']}: residual", "upper left")
        ax = row[1]
        est = disc.estimate
        if est is not None:
            used = est.used
            ax.plot(est.theta[used], _rebalanced(disc)[used], ".", ms=2, color="0.6", label="missing torque from the record")
            th = np.linspace(est.theta[used].min(), est.theta[used].max(), 300)
            if case["kind"] == "profile":
                ax.plot(th, [case["extra"](0.0, v, 1.0) for v in th], "k--", lw=1, label="truth")
            found = sum(t.coefficient * np.asarray(TERMS[t.name].value(0.0 * th, th, 1.0 + 0.0 * th, ArrayOps))
                        for t in disc.terms) if disc.terms else None
            if found is not None:
                ax.plot(th, found, "r", lw=1, label="discovered: " + " + ".join(t.name for t in disc.terms))
        ax.set_xlabel("cam angle [rad]")
        ax.set_ylabel("torque [N m]")
        ax.set_title("missing torque" if disc.terms else "nothing found: no library term earns the evidence", fontsize=9)
        ax.legend(fontsize=7, loc="lower left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def gap_table(cases, summaries):
    """The demo's table, one row per case: the truth's extra torque, what the diagnosis named, the rms
    with the registered effects and with the discovered term against the noise, what was found."""
    rows = []
    for case, s in zip(cases, summaries):
        disc, g = case["discovery"], s["gap"]
        found = "; ".join(f"{t.name} = {t.coefficient:.4g} +- {t.stderr:.2g} {t.unit}" if t.stderr else t.name
                          for t in disc.terms) or "nothing"
        verdict = "explained" if s["diagnosis"]["explained"] else "not explained"
        rows.append([case["truth"]["extra"], (", ".join(s["diagnosis"]["missing_effects"]) or "none") + f" ({verdict})",
                     f"{1e3 * g['rms_registered_rad']:.3f}", f"{1e3 * g['rms_discovered_rad']:.3f}",
                     f"{1e3 * g['noise_rad']:.3f}", found,
                     f"{case['seconds']['diagnosis with discovery']:.0f} ({case['seconds']['discovery']:.0f})"])
    return markdown_table(["truth's extra torque", "registered effects named (verdict)", "rms registered [mrad]",
                           "rms with discovery [mrad]", "noise [mrad]", "discovered (not registered)",
                           "time [s]: diagnosis (discovery)"], rows)


def cam_markdown(cases, summaries):
    md = ["# Discovery on cam drops (SYNTHETIC records)\n",
          f"The demo cam ({CAM['mass']:g} kg, closing springs {SPRING['count']} x {SPRING['stiffness'] / 1e3:.1f} kN/m, "
          f"massless in the truth and the rig's model except on the damped-spring record: there {SPRING['mass']:g} kg "
          f"each, a {TRUTH_SEGMENTS}-segment continuum in the truth, {SPRING_RIG['model']['spring_model']} "
          f"({SPRING_RIG['model']['lumped_convention']}) in the model) released at "
          f"{math.degrees(CAM['initial_angle']):.0f} degrees, Coulomb friction "
          f"mu_k {CAM_FRICTION['mu_k']} unknown to the rig, {1e3 * CAM_SIGMA:g} mrad camera noise at "
          f"{CAM_RATE / 1e3:g} kHz for {1e3 * CAM_DURATION:g} ms. Truths integrated independently "
          "(`vcbmodel/reference/cam_torque_truth.py`; the damped springs: `vcbmodel/reference/cam_spring_truth.py`). "
          "The in-family record is searched although the diagnosis "
          "explains it (a false discovery would show there).\n"]
    md.append(gap_table(cases, summaries))
    for case, s in zip(cases, summaries):
        md.append(f"## cam drop, {case['truth']['extra']}\n\n{case['discovery'].message}\n")
        for check in s["discovery"].get("truth_checks", []):
            md.append(f"- {check['term']}: {check['found']:.4g} +- {check['stderr']:.2g} against the truth "
                      f"{check['truth']:.4g} ({check['errors_off']:.1f} stated errors off)\n")
        md += registered_lines(s)
        md.append("```\n" + case["discovery"].report() + "\n```\n")
    return "\n".join(md)


def registered_lines(s):
    """The diagnosis's fitted values against the truth and, where a candidate tied, the candidates."""
    lines = [f"- registered {c['parameter']}: {c['value']:.4g} +- {c['stderr']:.2g} against the truth {c['truth']:.4g} "
             f"({c['errors_off']:.1f} stated errors off)\n" for c in s["diagnosis"]["truth_checks"] if c["stderr"]]
    if s["diagnosis"]["ambiguous"]:
        cands = ", ".join(f"{c['effect']} {c['delta_bic']:.1f}" for c in s["diagnosis"]["candidates"]
                          if c["delta_bic"] is not None)
        lines.append(f"- the diagnosis calls {' and '.join(' / '.join(a) for a in s['diagnosis']['ambiguous'])} "
                     f"ambiguous; candidates' delta BIC: {cands}\n")
    return lines


def markdown(cases, summaries):
    md = ["# Discovery of what no registry has (SYNTHETIC records)\n",
          f"A light pendulum ({PENDULUM['mass']:g} kg, {PENDULUM['inertia']:g} kg m^2, {PENDULUM['com_distance']:g} m) "
          f"with a flat paddle of {PADDLE[0]:g} m^2 at {PADDLE[1]:g} m (air drag 0.5 rho Cd A R^3 = {DRAG:.3g} "
          f"N m s^2/rad^2), released at {PENDULUM['initial_angle']:g} rad, {1e3 * SIGMA:g} mrad noise at {RATE / 1e3:g} kHz "
          f"(drag record {DRAG_DURATION:g} s); the rig's model is Coulomb + viscous friction with unknown values. The "
          "registry has air drag (`aerodynamic_drag`); on the drag record discovery runs on the rig's starting model, "
          "without it. Truths integrated independently "
          "(`vcbmodel/reference/torque_truth.py`). Evidence threshold: the diagnosis's own "
          f"(BIC margin {BIC_MARGIN:g}, variance gain {MIN_VARIANCE_GAIN:g} of the noise variance).\n"]
    md.append(gap_table(cases, summaries))
    for case, s in zip(cases, summaries):
        named = ", ".join(s["diagnosis"]["missing_effects"]) or "nothing"
        verdict = "explained" if s["diagnosis"]["explained"] else "not explained"
        if case["kind"] == "drag":
            searched = (f"The diagnosis named {named} (verdict: {verdict}). Discovery ran on the rig's starting model "
                        "(Coulomb + viscous friction, without the registered air drag).")
        elif case["seconds"]["diagnosis_searched"]:
            searched = "The diagnosis's discover step ran (its verdict: not explained)."
        else:
            searched = ("The diagnosis called the record explained, so its discover step did not run; discovery was "
                        "run after it on the diagnosis's final and starting models.")
        md.append(f"## {case['truth']['extra']}\n\n{searched}\n\n{case['discovery'].message}\n")
        check = s["discovery"].get("truth_check")
        if check:
            md.append(f"Coefficient {check['found']:.4g} +- {check['stderr']:.2g} against the truth {check['truth']:.4g}: "
                      f"{100 * check['relative_error']:.0f} % off, {check['errors_off']:.1f} stated errors. The stated "
                      "error is the larger of the fit's (its Jacobian) and the chi^2 profile's; Coulomb, viscous and "
                      "speed-squared friction trade against each other along a decaying swing: a long, flat valley "
                      "whose floor the fixed step's kinks make rough, so the refit runs from every start it has and "
                      "keeps the lowest (docs/findings.md, discovery).\n")
        md += registered_lines(s)
        md.append("```\n" + case["discovery"].report() + "\n```\n")
    return "\n".join(md)


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    rig_path = out / "synthetic" / "discovery_demo.rig.json"
    rig_path.parent.mkdir(parents=True, exist_ok=True)
    write_rig(copy.deepcopy(RIG), rig_path)
    rig = load_rig(rig_path)
    duration = 5.0 if args.quick else 8.0
    cases = [run_case(rig, "drag", DRAG_DURATION, 7)] + ([] if args.quick else [run_case(rig, "forcing", duration, 8)])
    summaries = [summary(c) for c in cases]
    cam_path = out / "synthetic" / "discovery_cam.rig.json"
    write_rig(copy.deepcopy(CAM_RIG), cam_path)
    cam_rig = load_rig(cam_path)
    cam_cases = [run_case(cam_rig, kind, CAM_DURATION, seed) for kind, seed in
                 (("profile", 11), ("forcing", 12), ("none", 13))[:0 if args.quick else 3]]
    spring_path = out / "synthetic" / "discovery_spring.rig.json"
    write_rig(copy.deepcopy(SPRING_RIG), spring_path)
    cam_cases.append(run_case(load_rig(spring_path), "spring_damping", CAM_DURATION, 14))
    cam_summaries = [summary(c) for c in cam_cases]
    write_json(out / "discovery.json", {"synthetic": True, "cases": summaries, "cam_cases": cam_summaries})
    plot(cases, out / "discovery.png")
    cam_plot(cam_cases, out / "discovery_cam.png")
    text = markdown(cases, summaries) + "\n" + cam_markdown(cam_cases, cam_summaries)
    (out / "discovery.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()

"""Paper section 3 / Fig. 7-10: closing-spring models compared on the cam drop, and their
convergence to the continuum.

The "measurement" is SYNTHETIC: the reference cam rig (parameters.REFERENCE_CAM) with
Coulomb + Stribeck shaft friction and the spring as the ANCF continuum (8 elements, end ties
extrapolated to rigid), plus camera noise (2 mrad at 12 kHz). The truth's own error is
estimated first (ties, mesh, what Euler-Bernoulli leaves out); every model is then scored
against the truth curve (model error) and against the noisy record.
Writes results/cam_drop_fig9a.png, cam_drop_fig9b.png, spring_convergence.png,
spring_fidelity.{json,md}, spring_modes.{json,md}, spring_shapes_fig10.png, spring_lateral.png,
cam_drop.gif and results/synthetic/cam_drop_m0_*.{csv,rig.json}.
"""
import copy
import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
from _common import markdown_table, parse_args, write_json

from vcbmodel import parameters as P
from vcbmodel.analysis.synthetic import write_rig
from vcbmodel.app.plots import plt, save
from vcbmodel.builders.ancf import AncfOptions, ancf_fixed_fixed_frequencies
from vcbmodel.experiments.loading import rig_from_data
from vcbmodel.experiments.simulation import output_times, simulate, simulate_rigid_ties
from vcbmodel.experiments import experiment_of
from vcbmodel.laws.coil import (EXTENSION_BODY_FRACTION, coil_bending_stiffness, coil_geometry, coil_shear_stiffness,
                               wire_strength)
from vcbmodel.laws.mechanics import cam_pin
from vcbmodel.laws.springs import fixed_fixed_frequencies, lumped_chain, string_frequencies
from vcbmodel.records.measurement import Measurement, write_measurement

FRICTION = ("coulomb_friction", "stribeck")
EFFECTS = FRICTION + ("spring_mass",)
CONVENTIONS = ("exact", "paper", "uniform")
TABLE_NS = (1, 2, 3, 5, 10, 20)  # the numbers of lumped masses the pages' tables show
SHAPE_TIMES = (0.011, 0.0165, 0.029)  # s, the paper's Fig. 10 frames
NOISE_SEED = 3
#: rad, Hz: the synthetic record's camera (the cam-drop experiment's sensor: noise sigma and rate)
NOISE_RAD, CAMERA_RATE = experiment_of("cam_drop").noise_sigma, experiment_of("cam_drop").sample_rate
#: N: the paper's closing springs' charged pull (section 1), at which the coil's stress and the string mode are taken
CHARGED_PULL = 6000.0
PAPER_F0_HZ = 85.83  # Hz: the paper's f0 of the closing spring (eq. 8)


def rig_variant(out, mass, name):
    d = copy.deepcopy(P.REFERENCE_CAM)
    d["closing_spring"]["mass"] = mass
    d["name"] = name
    path = out / "synthetic" / f"{name}.rig.json"
    write_rig(d, path)
    return rig_from_data(d, str(path))


def rms(a, b):
    return float(np.sqrt(np.mean((np.asarray(a) - np.asarray(b)) ** 2)))


def euler_bernoulli_factor(spring, tensions=(1000.0, 6000.0), modes=(1, 2, 3)):
    """The smallest equivalent factor on EI that reproduces the lateral frequencies of a
    preloaded helical spring with coil shear flexibility (Haringx) and rotary inertia
    (coil radius of gyration^2 = D^2/8) in an Euler-Bernoulli string-beam: pinned-pinned,
    mu w^2 = k^2 [T + EI k^2 / (1 + EI k^2 / (GA - T))] / (1 + r^2 k^2)."""
    g = coil_geometry(spring)
    factors = []
    for T in tensions:
        L = spring.free_length + T / spring.stiffness
        mu = spring.mass / L
        EI = coil_bending_stiffness(spring) * L / spring.free_length
        GA = coil_shear_stiffness(spring, L)
        r2 = g.coil_diameter**2 / 8
        for n in modes:
            k = n * math.pi / L
            w2 = k**2 * (T + EI * k**2 / (1 + EI * k**2 / (GA - T))) / (mu * (1 + r2 * k**2))
            factors.append((mu * w2 / k**2 - T) / k**2 / EI)
    return min(factors)


def truth_of(rig, t, quick):
    """The continuum truth (rigid-tie extrapolation, 8 elements) and its error budget (rad rms):
    ties (two extrapolations), mesh (8 vs 16 elements), Euler-Bernoulli (EI x the Haringx /
    rotary-inertia factor)."""
    truth = simulate_rigid_ties(rig, EFFECTS, sample_times=t)
    budget = {}
    stiffer = simulate_rigid_ties(rig, EFFECTS, sample_times=t, stiffnesses=(1e9, 1e10)) if not quick else None
    budget["ties_rad"] = rms(truth.measured, stiffer.measured) if stiffer else None
    finer = simulate_rigid_ties(rig, EFFECTS, sample_times=t, ancf=AncfOptions(elements=16)) if not quick else None
    budget["mesh_8_vs_16_rad"] = rms(truth.measured, finer.measured) if finer else None
    factor = euler_bernoulli_factor(rig.closing_spring)
    softer = simulate_rigid_ties(rig, EFFECTS, sample_times=t, ancf=AncfOptions(
        bending_stiffness=factor * coil_bending_stiffness(rig.closing_spring)))
    budget["euler_bernoulli_rad"] = rms(truth.measured, softer.measured)
    budget["euler_bernoulli_ei_factor"] = factor
    budget["total_rad"] = math.sqrt(sum(v**2 for k, v in budget.items() if k.endswith("_rad") and v is not None))
    return truth, budget


def chain_rows(k0, m0, L, data):
    """The lumped chains' and the ANCF spring's rows of the modes table (their figures go to ``data``)."""
    rows = []
    for conv in CONVENTIONS:
        for n in TABLE_NS:
            c = lumped_chain(n, k0, m0, L, conv)
            f = c.natural_frequencies()[:3] / (2 * math.pi)
            key = f"lumped-{n} ({conv})"
            data["models"][key] = {"frequencies_hz": f.tolist(), "masses_kg": c.masses.tolist(),
                                   "stiffnesses_n_per_m": c.stiffnesses.tolist(), "pin_mass_kg": c.pin_mass,
                                   "anchor_mass_kg": c.anchor_mass, "total_mass_over_m0": c.total_mass / m0,
                                   "quasi_static_pin_mass_over_m0": c.quasi_static_pin_mass / m0}
            rows.append([key, ", ".join(f"{x:.1f}" for x in f), f"{c.masses.sum() / m0:.3f}", f"{c.pin_mass / m0:.3f}",
                         f"{c.total_mass / m0:.3f}", f"{c.quasi_static_pin_mass / m0:.3f}"])
    for ne in (4, 8, 16):
        f = np.asarray(ancf_fixed_fixed_frequencies(k0, m0, L, ne, count=3))
        data["models"][f"ancf-{ne}"] = {"frequencies_hz": f.tolist()}
        rows.append([f"ANCF, {ne} elements (axial)", ", ".join(f"{x:.1f}" for x in f), "distributed", "", "1", "1/3"])
    return rows


def coil_geometries(k0, m0, L):
    """The derived coil of each spring mass (m0 and HEAVY_SPRING_MASS) and its stress at CHARGED_PULL."""
    geometry = {}
    for mass in (m0, P.HEAVY_SPRING_MASS):
        spring = SimpleNamespace(stiffness=k0, mass=mass, free_length=L, wire_diameter=None, coil_diameter=None,
                                 active_coils=None, shear_modulus=None)
        g = coil_geometry(spring)
        allowable = EXTENSION_BODY_FRACTION * wire_strength(g.wire_diameter)
        geometry[f"{mass:g} kg"] = {"wire_diameter_m": g.wire_diameter, "coil_diameter_m": g.coil_diameter,
                                    "active_coils": g.active_coils, "shear_stress_at_6000N_Pa": g.shear_stress(CHARGED_PULL),
                                    "allowable_extension_body_Pa": allowable,
                                    "bending_stiffness_free_N_m2": coil_bending_stiffness(spring),
                                    "euler_bernoulli_ei_factor": euler_bernoulli_factor(spring)}
    return geometry


def modes_note(data, k0, m0):
    """The modes page's prose, every number from ``data`` (the table's figures)."""
    models, g0 = data["models"], data["coil_geometry"][f"{m0:g} kg"]
    paper = [models[f"lumped-{n} (paper)"] for n in (2, 20)]
    exact_third = all(abs(models[f"lumped-{n} (exact)"]["quasi_static_pin_mass_over_m0"] - 1 / 3) < 1e-9
                      for n in TABLE_NS)
    f_eq8, f_lat = models["lumped-1 (paper)"]["frequencies_hz"][0], data["lateral_string_hz_at_6000N"][0]
    stress_ratio = g0["shear_stress_at_6000N_Pa"] / g0["allowable_extension_body_Pa"]
    return (
        f"The paper quotes f0 = {PAPER_F0_HZ} Hz. A spring fixed at both ends has f_n = (n/2) sqrt(k0/m0) = n x "
        f"{data['continuum_axial_hz'][0]:.1f} Hz for k0 = {k0:g} N/m and m0 = {m0:g} kg; the paper's eq. 8 "
        f"(w1 = 2 sqrt(k0/m0)) gives {f_eq8:.1f} Hz ({100 * (f_eq8 / PAPER_F0_HZ - 1):+.1f} % from the paper's), and "
        f"the preloaded spring's first lateral string mode {f_lat:.1f} Hz ({100 * (f_lat / PAPER_F0_HZ - 1):+.1f} %).\n\n"
        "Where the spring's mass sits (conventions, spec 'lumped_convention'): `exact` chains match the "
        "continuum's first n axial frequencies and put the mass they lack at the ends, so that the total is m0 and a "
        "slowly moving pin feels Rayleigh's m0/3 (last column"
        + (": 1/3 for every n" if exact_third else "") + "); `uniform` chains put half a "
        "segment at each end and approach m0/3 from above as 1/(6 (n+1)^2); the paper's convention puts nothing at "
        "the ends and carries more and more mass as n grows "
        f"({paper[0]['total_mass_over_m0']:.2f} m0 at n = 2, {paper[1]['total_mass_over_m0']:.2f} m0 at n = 20; "
        f"quasi-static pin mass {paper[0]['quasi_static_pin_mass_over_m0']:.2f} -> "
        f"{paper[1]['quasi_static_pin_mass_over_m0']:.2f} m0): it does not converge to the continuum.\n\n"
        f"Coil geometry (derived, spring index {P.SPRING_INDEX:g}): d = {1e3 * g0['wire_diameter_m']:.2f} mm, "
        f"D = {1e3 * g0['coil_diameter_m']:.1f} mm, {g0['active_coils']:.1f} active coils; at {CHARGED_PULL:g} N the "
        f"wire would see {1e-9 * g0['shear_stress_at_6000N_Pa']:.1f} GPa (Wahl), {stress_ratio:.1f}x the "
        f"{EXTENSION_BODY_FRACTION:g} S_ut an extension spring's body allows (chromium-silicon wire of that size, "
        "Shigley): "
        + ("no steel spring has the paper's k0, m0 and force at once (parameters.py)." if stress_ratio > 1 else
           "this coil carries it."))


def modes_table(out):
    """spring_modes.{json,md}: the natural frequencies and the mass distribution of every spring model."""
    s = P.REFERENCE_CAM["closing_spring"]
    k0, m0, L = s["stiffness"], s["mass"], s["free_length"]
    cont = fixed_fixed_frequencies(k0, m0) / (2 * math.pi)
    data = {"continuum_axial_hz": cont.tolist(), "paper_f0_hz": PAPER_F0_HZ, "models": {}}
    rows = chain_rows(k0, m0, L, data)
    B0 = cam_pin(P.REFERENCE_CAM["cam"]["initial_angle"], SimpleNamespace(**dict(P.REFERENCE_CAM["cam"], pivot=tuple(
        P.REFERENCE_CAM["cam"]["pivot"]))))
    length = math.hypot(*B0)
    lat = string_frequencies(CHARGED_PULL, m0, length) / (2 * math.pi)
    data["lateral_string_hz_at_6000N"] = lat.tolist()
    rows.append(["continuum, axial (fixed-fixed)", ", ".join(f"{x:.1f}" for x in cont), "", "", "1", "0.333"])
    rows.append([f"continuum, lateral (string, {CHARGED_PULL:g} N, {length:.3f} m)", ", ".join(f"{x:.1f}" for x in lat),
                 "", "", "", ""])
    data["coil_geometry"] = coil_geometries(k0, m0, L)
    note = modes_note(data, k0, m0)
    data["note"] = note
    write_json(out / "spring_modes.json", data)
    (out / "spring_modes.md").write_text(
        "# The closing-spring models: natural frequencies (fixed-fixed) and where the mass sits\n\n"
        + markdown_table(["model", "first frequencies (Hz)", "chain mass / m0", "pin mass / m0", "total mass / m0",
                          "quasi-static pin mass / m0"], rows) + "\n" + note + "\n")


def convergence(rig, truth, t, ns):
    """rms error (rad) against the truth for each convention and n."""
    out = {}
    for conv in CONVENTIONS:
        out[conv] = [rms(simulate(rig, EFFECTS, spring_model=f"lumped-{n}:{conv}", sample_times=t).measured,
                         truth.measured) for n in ns]
    return out


def observed_order(ns, errors, n_min=3):
    """Slope of log(error) against log(n) over n >= n_min (negative: converging)."""
    ns, errors = np.asarray(ns, float), np.asarray(errors)
    keep = ns >= n_min
    return float(np.polyfit(np.log(ns[keep]), np.log(errors[keep]), 1)[0]) if keep.sum() >= 2 else float("nan")


def noisy_record(out, label, t, truth):
    """The truth plus camera noise (NOISE_RAD, seed NOISE_SEED), written to ``out``/synthetic: (noise, record)."""
    noisy = truth.measured + np.random.default_rng(NOISE_SEED).normal(0.0, NOISE_RAD, t.size)
    meas = Measurement(str(out / "synthetic" / f"{label}.csv"), t, {"cam_angle": noisy}, (
        "SYNTHETIC: truth effects coulomb_friction,stribeck,spring_mass, spring model ancf (8 elements, rigid ties "
        f"extrapolated), noise sigma {NOISE_RAD:g} rad, seed {NOISE_SEED}",))
    write_measurement(meas, meas.path)
    return noisy, meas


def score_models(rig, t, truth, noisy, label, case):
    """Every spring model (and the massless one without friction) against the truth and the noisy
    record: (the error table's rows, {model: its simulation}, the frictionless simulation)."""
    rows, curves = [], {}
    models = [("massless", "massless")] + [(f"lumped-{n}:{c}", f"lumped-{n} ({c})") for c in CONVENTIONS
                                          for n in (1, 2, 3)] + [("ancf", "ancf (1e8 N/m ties, no extrapolation)")]
    for spring, key in models:
        eff = EFFECTS if spring != "massless" else FRICTION
        sim = simulate(rig, eff, spring_model=spring, sample_times=t)
        curves[key] = sim
        err, err_meas = rms(sim.measured, truth.measured), rms(sim.measured, noisy)
        case["models"][key] = {"rms_vs_truth_rad": err, "rms_vs_measurement_rad": err_meas,
                               "max_vs_truth_rad": float(np.max(np.abs(sim.measured - truth.measured)))}
        rows.append([label, key, f"{1e3 * err:.2f}", f"{1e3 * err_meas:.2f}"])
    nofric = simulate(rig, (), {}, spring_model="massless", sample_times=t)
    case["models"]["massless, no friction"] = {"rms_vs_truth_rad": rms(nofric.measured, truth.measured)}
    rows.append([label, "massless, no friction", f"{1e3 * rms(nofric.measured, truth.measured):.2f}",
                 f"{1e3 * rms(nofric.measured, noisy):.2f}"])
    return rows, curves, nofric


def convergence_case(ax_conv, rig, truth, t, ns, label, mass, case):
    """The lumped conventions' convergence on one case: into ``case``, onto ``ax_conv``; the table's rows."""
    errs = convergence(rig, truth, t, ns)
    case["convergence"] = {"n": list(ns), "rms_vs_truth_rad": errs,
                           "observed_order": {c: observed_order(ns, errs[c]) for c in CONVENTIONS}}
    rows = []
    for conv in CONVENTIONS:
        ax_conv.loglog(ns, 1e3 * np.array(errs[conv]), "o-", ms=3, label=f"{conv} (order {case['convergence']['observed_order'][conv]:.2f})")
        rows.append([label, conv] + [f"{1e3 * errs[conv][ns.index(n)]:.2f}" if n in ns else "" for n in TABLE_NS]
                    + [f"{case['convergence']['observed_order'][conv]:.2f}"])
    ax_conv.axhline(1e3 * case["truth_uncertainty"]["total_rad"], color="k", ls=":", lw=1, label="truth's own uncertainty")
    ax_conv.axhline(1e3 * NOISE_RAD, color="0.5", ls="--", lw=1, label=f"camera noise ({1e3 * NOISE_RAD:g} mrad)")
    ax_conv.set_xlabel("lumped masses n")
    ax_conv.set_title(f"m0 = {mass:g} kg")
    ax_conv.legend(fontsize=7)
    return rows


def fidelity_page(out, fidelity, rows, conv_rows):
    """spring_fidelity.{json,md}."""
    write_json(out / "spring_fidelity.json", fidelity)
    budget_rows = [[label, *(f"{1e3 * c['truth_uncertainty'][k]:.4f}" if c["truth_uncertainty"][k] is not None else "n/a"
                             for k in ("ties_rad", "mesh_8_vs_16_rad", "euler_bernoulli_rad", "total_rad"))]
                   for label, c in fidelity["cases"].items()]
    (out / "spring_fidelity.md").write_text(
        "# Spring-model fidelity on the cam drop (SYNTHETIC measurement)\n\n"
        "Truth: the ANCF continuum (8 elements, end ties extrapolated to rigid) with Coulomb + Stribeck shaft friction; "
        f"the measurement adds {1e3 * NOISE_RAD:g} mrad camera noise. Every model runs with the same friction.\n\n"
        "## The truth's own uncertainty (mrad rms of the cam angle)\n\n"
        + markdown_table(["case", "end ties (1e8/1e9 vs 1e9/1e10 extrapolation)", "mesh (8 vs 16 elements)",
                          "Euler-Bernoulli (coil shear + rotary inertia)", "total"], budget_rows)
        + "\nA model within these numbers of the truth cannot be ranked against another one that is.\n\n"
        "## Errors of the spring models (mrad rms)\n\n"
        + markdown_table(["case", "spring model (convention)", "vs truth", "vs noisy measurement"], rows)
        + "\n## Convergence with the number of masses (mrad rms vs truth; order = slope of log error vs log n, n >= 3)\n\n"
        + markdown_table(["case", "convention", f"n = {TABLE_NS[0]}", *map(str, TABLE_NS[1:]), "observed order"], conv_rows))


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    (out / "synthetic").mkdir(exist_ok=True)
    modes_table(out)
    ns = (1, 2, 3, 5) if args.quick else tuple(range(1, 11)) + (12, 14, 16, 18, 20)
    fidelity = {"synthetic": True, "truth": "ANCF, 8 elements, end ties extrapolated to rigid (1e8, 1e9 N/m)",
                "truth_friction": P.REFERENCE_CAM["friction"], "noise_rad": NOISE_RAD, "cases": {}}
    rows, conv_rows, fig_data = [], [], {}
    fig_conv, axes_conv = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    for ax_conv, (mass, label) in zip(axes_conv, ((P.REFERENCE_CAM["closing_spring"]["mass"], "cam_drop_m0_0.336kg"),
                                                  (P.HEAVY_SPRING_MASS, "cam_drop_m0_1kg"))):
        rig = rig_variant(out, mass, label)
        t = output_times(rig, P.CAM_T_END)
        truth, budget = truth_of(rig, t, args.quick)
        noisy, meas = noisy_record(out, label, t, truth)
        case = fidelity["cases"][label] = {"truth_uncertainty": budget, "models": {}}
        case_rows, curves, nofric = score_models(rig, t, truth, noisy, label, case)
        rows += case_rows
        conv_rows += convergence_case(ax_conv, rig, truth, t, ns, label, mass, case)
        fig_data[label] = (rig, meas, truth, curves, nofric, mass)
    axes_conv[0].set_ylabel("cam angle rms error vs continuum (mrad)")
    fig_conv.suptitle("Convergence of the lumped closing-spring conventions to the continuum "
                      f"(cam drop, {1e3 * P.CAM_T_END:g} ms)")
    save(fig_conv, out / "spring_convergence.png")
    fidelity_page(out, fidelity, rows, conv_rows)
    heavy = fig_data["cam_drop_m0_1kg"]
    figures(out, *heavy, args.quick)


def figures(out, rig, meas, truth, curves, nofric, mass, quick):
    tms, y = meas.t * 1e3, meas.channels["cam_angle"]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(tms, y, ".", ms=2, color="0.5", label=f"SYNTHETIC measurement ({CAMERA_RATE / 1e3:g} kHz camera stand-in)")
    ax.plot(tms, curves["massless"].measured, label="massless spring, with shaft friction")
    ax.plot(tms, nofric.measured, "--", label="massless spring, no shaft friction")
    ax.set_xlabel("t (ms)"); ax.set_ylabel("cam angle (rad)"); ax.legend(fontsize=8)
    ax.set_title(f"Fig. 9(a): ideal spring vs measurement ({mass:g} kg spring)")
    save(fig, out / "cam_drop_fig9a.png")
    fig, (ax, axr) = plt.subplots(2, 1, figsize=(7, 6.5), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    ax.plot(tms, y, ".", ms=2, color="0.5", label="SYNTHETIC measurement")
    keys = ["lumped-1 (exact)", "lumped-2 (exact)", "lumped-3 (exact)", "lumped-2 (paper)", "lumped-3 (paper)"]
    for key in keys:
        ax.plot(tms, curves[key].measured, lw=1, label=key)
        axr.plot(tms, 1e3 * (curves[key].measured - truth.measured), lw=0.8, label=key)
    ax.set_ylabel("cam angle (rad)"); ax.legend(fontsize=8)
    ax.set_title(f"Fig. 9(b): lumped spring models ({mass:g} kg spring)")
    axr.set_xlabel("t (ms)"); axr.set_ylabel("model - continuum truth (mrad)")
    save(fig, out / "cam_drop_fig9b.png")
    shapes(out, rig, curves, quick)


def spring_points(result, rig, i):
    """Chain points O, masses..., B at sample i (m)."""
    names = sorted({k.rsplit("_", 1)[0] for k in result.channels if k.startswith(("spring_mass_", "ancf_node_"))},
                   key=lambda s: int(s.rsplit("_", 1)[1]))
    pts = [rig.closing_spring.anchor] + [(result.channels[n + "_x"][i], result.channels[n + "_y"][i]) for n in names]
    pts.append(cam_pin(result.measured[i], rig.cam))
    return np.array(pts)


def lateral_deflection(result, rig):
    """Largest distance (m) of the spring's points from the straight line O-B, over time."""
    out = np.zeros(result.t.size)
    for i in range(result.t.size):
        p = spring_points(result, rig, i)
        d = p[-1] - p[0]
        n = np.array([-d[1], d[0]]) / np.linalg.norm(d)
        out[i] = np.max(np.abs((p[1:-1] - p[0]) @ n)) if len(p) > 2 else 0.0
    return out


def shapes(out, rig, curves, quick):
    keys = ["lumped-2 (paper)", "lumped-3 (exact)", "ancf (1e8 N/m ties, no extrapolation)"]
    fig, axes = plt.subplots(1, len(SHAPE_TIMES), figsize=(12, 3.6), sharey=True)
    for ax, ts in zip(axes, SHAPE_TIMES):
        for key in keys:
            r = curves[key]
            i = int(np.argmin(np.abs(r.t - ts)))
            p = spring_points(r, rig, i)
            d = p[-1] - p[0]
            n = np.array([-d[1], d[0]]) / np.linalg.norm(d)
            along = (p - p[0]) @ (d / np.linalg.norm(d))
            ax.plot(along, 1e3 * ((p - p[0]) @ n), "o-", ms=3, label=key.split(" (1e8")[0])
        ax.set_title(f"t = {1e3 * ts:.1f} ms")
        ax.set_xlabel("along O-B (m)")
    axes[0].set_ylabel("lateral offset from line O-B (mm)")
    axes[0].legend(fontsize=8)
    save(fig, out / "spring_shapes_fig10.png")
    fig, ax = plt.subplots(figsize=(7, 3.8))
    for key in keys:
        ax.plot(1e3 * curves[key].t, 1e3 * lateral_deflection(curves[key], rig), label=key.split(" (1e8")[0])
    ax.set_xlabel("t (ms)"); ax.set_ylabel("largest lateral deflection (mm)"); ax.legend(fontsize=8)
    ax.set_title(f"Lateral motion of the closing spring during the drop ({rig.closing_spring.mass:g} kg spring)")
    save(fig, out / "spring_lateral.png")
    animate(out / "cam_drop.gif", rig, curves[keys[-1]], "ancf", frames=8 if quick else 36)


def animate(path, rig, result, label, frames):
    from matplotlib.animation import FuncAnimation, PillowWriter
    fig, ax = plt.subplots(figsize=(4.6, 3.2))
    cam = rig.cam
    idx = np.linspace(0, result.t.size - 1, frames).astype(int)
    line, = ax.plot([], [], "o-", ms=3, color="tab:blue")
    arm, = ax.plot([], [], "-", lw=3, color="tab:red")
    title = ax.set_title("")
    ax.set_xlim(-0.05, 0.6); ax.set_ylim(-0.2, 0.2); ax.set_aspect("equal")
    ax.plot(*cam.pivot, "ks"); ax.plot(*rig.closing_spring.anchor, "k^")

    def draw(k):
        i = idx[k]
        p = spring_points(result, rig, i)
        line.set_data(p[:, 0], p[:, 1])
        arm.set_data([cam.pivot[0], p[-1, 0]], [cam.pivot[1], p[-1, 1]])
        title.set_text(f"{label}: t = {1e3 * result.t[i]:.1f} ms")
        return line, arm, title

    anim = FuncAnimation(fig, draw, frames=len(idx), blit=False)
    anim.save(path, writer=PillowWriter(fps=8), dpi=60)
    plt.close(fig)


if __name__ == "__main__":
    main()

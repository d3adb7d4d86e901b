"""Design sensitivity of the reference breaker's closing: which uncertain input moves the closing
time, every pole's zone speed, the pole spread, the bounce and the kinetic margin after the touch
(the cam's least kinetic energy from the first touch to its holding latch; 0 for a build whose cam
turns back short of it), one at a time (tornado chart) and
all at once (variance-based Sobol indices with bootstrap confidence intervals, SALib); and the main
shaft's sizing checked across gap patterns and restitutions.

The breaker is vcbmodel.parameters.REFERENCE_BREAKER. It has no viscous shaft friction; the
viscous term is varied over the bearing estimate (parameters.VISCOUS_BEARING_ESTIMATE, Petroff),
and the contact restitution over its published range (parameters.RESTITUTION_RANGE), so that the
restitution's share of the bounce shows. The uncertain inputs and their ranges are
vcbmodel.analysis.design.breaker_factors (TOLERANCES and RANGES, each with its source, stated in
the outputs): the closing-spring preload is varied through the springs' free length at fixed
stiffness. The tornado's centre is each range's middle. The shaft check closes the breaker with main
shafts of 40-80 mm (damping kept at 2 % of critical, lever inertia as the reference's) for every gap
pattern of parameters.GAP_PATTERNS at restitutions 0.5, 0.8 and 0.9: the worst pole's bounce. All
runs go through the sweep (vcbmodel.analysis.sweep) on all cores.
Writes design_sensitivity_tornado.png, design_sensitivity_sobol.png, design_sensitivity.{json,md}.
"""
from pathlib import Path

import numpy as np
from _common import markdown_table, parse_args, write_json
from SALib.analyze import sobol as sobol_analyze
from SALib.sample import sobol as sobol_sample

from vcbmodel import parameters as P
from vcbmodel.analysis.design import (breaker_factors, closing_poles, json_ready, pole_columns, runs_of,
                                      with_viscous_shaft)
from vcbmodel.analysis.sweep import sweep
from vcbmodel.app.plots import plt, save
from vcbmodel.experiments.loading import rig_from_data

#: (column, label, unit, display scale)
OUTPUTS = [("closing_time_s", "closing time", "ms", 1e3),
           ("zone_speed_min_m_s", "slowest pole's zone speed", "m/s", 1.0),
           ("zone_speed_max_m_s", "fastest pole's zone speed", "m/s", 1.0),
           ("pole_spread_s", "pole spread", "ms", 1e3),
           ("bounce_duration_s", "bounce duration (worst pole)", "ms", 1e3),
           ("bounce_count", "bounces (worst pole)", "-", 1.0),
           ("kinetic_margin_J", "kinetic margin after touch", "J", 1.0)]
#: Each closing runs until the cam rests on its holding latch, so that its kinetic margin is known.
T_END = P.BREAKER_REST_T_END
SEED = 2002  # the Sobol sequence's scramble and the bootstrap
#: Sobol base samples N (runs: N (k + 2) for k factors, first-order and total indices)
N_FULL, N_QUICK = 128, 2
#: The shaft check: diameters (m) and restitutions; quick: fewer of each and two gap patterns.
SHAFT_FULL = ((0.04, 0.05, 0.06, 0.07, 0.08), (0.5, 0.8, 0.9))
SHAFT_QUICK = ((0.04, 0.06), (0.8,))
#: The bounce limit the shaft was sized against (s): the reference breaker's, assumed (parameters.REFERENCE_LIMITS).
BOUNCE_LIMIT = 1e-3 * P.REFERENCE_LIMITS["bounce_duration"]["max"]
#: The Sobol indices' bootstrap: resamples and confidence level (SALib.analyze.sobol's).
RESAMPLES, CONF_LEVEL = 200, 0.95


def with_margin_of_failures(df):
    """The runs with a cam that turned back short of its latch given a kinetic margin of 0 (it used
    its margin up; the evaluation leaves it empty); a run that ended first stays empty."""
    return df.assign(kinetic_margin_J=df["kinetic_margin_J"].where(df["latched"] != 0.0, 0.0))


def tornado(df, factors):
    """Output changes (from the nominal run 1) at each factor's low and high value."""
    df = with_margin_of_failures(df)
    base = df.iloc[0]
    out = {}
    for col, *_ in OUTPUTS:
        rows = []
        for i, f in enumerate(factors):
            lo, hi = df.iloc[1 + 2 * i], df.iloc[2 + 2 * i]
            rows.append({"factor": f.key, "label": f.label, "low": f.low, "high": f.high,
                         "output_low": lo[col], "output_high": hi[col],
                         "change_low": lo[col] - base[col], "change_high": hi[col] - base[col]})
        rows.sort(key=lambda r: -np.nan_to_num(abs(r["change_high"] - r["change_low"])))
        out[col] = {"nominal": base[col], "bars": rows}
    return out


def sobol(df, problem, n):
    df = with_margin_of_failures(df)
    out = {"builds_not_latched": int((df["latched"] == 0.0).sum())}
    for col, *_ in OUTPUTS:
        y = df[col].to_numpy(float)
        bad = ~np.isfinite(y)
        if bad.all():
            out[col] = {"error": "no run gave this output"}
            continue
        y = np.where(bad, np.nanmean(y), y)  # failed runs (if any) at the mean: stated in the outputs
        si = sobol_analyze.analyze(problem, y, calc_second_order=False, seed=SEED, num_resamples=RESAMPLES,
                                   conf_level=CONF_LEVEL)
        out[col] = {"mean": float(np.mean(y)), "sd": float(np.std(y)), "failed_runs_set_to_mean": int(bad.sum()),
                    "indices": [{"factor": name, "S1": float(si["S1"][j]), "S1_conf": float(si["S1_conf"][j]),
                                 "ST": float(si["ST"][j]), "ST_conf": float(si["ST_conf"][j])}
                                for j, name in enumerate(problem["names"])]}
    return out


def plot_tornado(result, factors, path):
    labels = {f.key: f.label for f in factors}
    fig, axes = plt.subplots(2, 4, figsize=(21, 9.5))
    axes.flat[-1].set_visible(False)
    for ax, (col, name, unit, scale) in zip(axes.flat, OUTPUTS):
        bars = result[col]["bars"][::-1]
        y = np.arange(len(bars))
        ax.barh(y, [scale * b["change_low"] for b in bars], color="tab:blue", label="factor at its low value")
        ax.barh(y, [scale * b["change_high"] for b in bars], color="tab:orange", alpha=0.8, label="factor at its high value")
        ax.set_yticks(y, [labels[b["factor"]] for b in bars], fontsize=8)
        ax.axvline(0, color="k", lw=0.8)
        ax.set_xlabel(f"change of {name} ({unit})\nnominal {scale * result[col]['nominal']:.4g} {unit}")
        ax.set_title(f"{name}: one factor at a time", fontsize=9)
    axes.flat[0].legend(fontsize=8, loc="lower left")
    save(fig, path)


def plot_sobol(result, factors, path, n, runs):
    labels = {f.key: f.label for f in factors}
    fig, axes = plt.subplots(2, 4, figsize=(21, 9.5), sharey=True)
    axes.flat[-1].set_visible(False)
    for ax, (col, name, unit, scale) in zip(axes.flat, OUTPUTS):
        if "indices" not in result[col]:
            ax.set_title(f"{name}: {result[col]['error']}")
            continue
        idx = result[col]["indices"]
        y = np.arange(len(idx))
        ax.barh(y - 0.2, [i["S1"] for i in idx], 0.4, xerr=[i["S1_conf"] for i in idx], color="tab:blue",
                capsize=2, label="first order S1")
        ax.barh(y + 0.2, [i["ST"] for i in idx], 0.4, xerr=[i["ST_conf"] for i in idx], color="tab:red",
                capsize=2, label="total ST")
        ax.set_yticks(y, [labels[i["factor"]] for i in idx], fontsize=8)
        ax.invert_yaxis()
        ax.axvline(0, color="k", lw=0.6)
        ax.set_xlabel(f"Sobol index (share of the variance), {100 * CONF_LEVEL:g} % bootstrap interval")
        ax.set_title(f"{name}: sd {scale * result[col]['sd']:.3g} {unit}", fontsize=9)
    axes.flat[0].legend(fontsize=8, loc="lower right")
    fig.suptitle(f"Global sensitivity (Saltelli/Sobol, N = {n}, {runs} closings, uniform over the ranges)", fontsize=10)
    save(fig, path)


def fmt(v, scale=1.0):
    return "-" if v is None or not np.isfinite(v) else f"{scale * v:.4g}"


def shaft_runs(diameters, restitutions, patterns):
    """Override dicts of the shaft check: every diameter x gap pattern x restitution, the shaft's damping
    kept at the reference's share of critical (c ~ sqrt(k) ~ d^2)."""
    ref = P.MAIN_SHAFT_SECTION
    runs = []
    for d in diameters:
        for name in patterns:
            for e in restitutions:
                o = {"breaker.main_shaft.diameter": d, "breaker.main_shaft.damping": ref["damping"] * (d / ref["diameter"]) ** 2,
                     "breaker.contact.restitution": e}
                o.update({f"breaker.poles.gap_offsets.{i}": v for i, v in enumerate(P.GAP_PATTERNS[name])})
                runs.append(o)
    return runs


def shaft_check(quick, columns):
    """The worst pole's bounce (count, s) for every main-shaft diameter, gap pattern and restitution, and
    what it says of the sizing: whether the bounce falls with the diameter for every pattern, and the
    diameters that keep it within BOUNCE_LIMIT for every pattern at each restitution."""
    diameters, restitutions = SHAFT_QUICK if quick else SHAFT_FULL
    ref = P.MAIN_SHAFT_SECTION
    patterns = list(P.GAP_PATTERNS)[:2] if quick else list(P.GAP_PATTERNS)
    df = sweep(P.REFERENCE_BREAKER, runs=shaft_runs(diameters, restitutions, patterns), evaluate=closing_poles,
               columns=columns, label="main shaft across gap patterns")
    rows, i = [], 0
    for d in diameters:
        for name in patterns:
            for e in restitutions:
                r = df.iloc[i]
                rows.append({"diameter_m": d, "pattern": name, "restitution": e, "bounces": r["bounce_count"],
                             "bounce_s": r["bounce_duration_s"], "status": r["status"]})
                i += 1
    verdict = {}
    for e in restitutions:
        worst = {d: max(x["bounce_s"] for x in rows if x["diameter_m"] == d and x["restitution"] == e) for d in diameters}
        monotone = {}
        for name in patterns:
            b = [next(x["bounce_s"] for x in rows if x["diameter_m"] == d and x["pattern"] == name and x["restitution"] == e)
                 for d in diameters]
            monotone[name] = all(b0 >= b1 for b0, b1 in zip(b[:-1], b[1:]))
        verdict[str(e)] = {"worst_over_patterns_s": worst, "falls_with_diameter": monotone,
                           "within_limit_for_every_pattern": [d for d in diameters if worst[d] <= BOUNCE_LIMIT]}
    return {"diameters_m": list(diameters), "restitutions": list(restitutions), "patterns": {p: P.GAP_PATTERNS[p] for p in patterns},
            "damping": (f"the reference's share of critical at every diameter ({ref['damping']:g} N m s/rad x "
                        f"(d / {1e3 * ref['diameter']:g} mm)^2, parameters.MAIN_SHAFT_SECTION)"),
            "limit_s": BOUNCE_LIMIT, "runs": rows, "verdict": verdict}


def shaft_report(shaft):
    """The shaft check's section of design_sensitivity.md."""
    ds = shaft["diameters_m"]
    md = ["\n## The main shaft across gap patterns\n",
          f"The worst pole's bounce (ms, with its count) for main shafts of {', '.join(f'{1e3 * d:g}' for d in ds)} mm "
          f"({shaft['damping']}), for each gap pattern (offsets of poles 1/2/3) and restitution:\n"]
    for e in shaft["restitutions"]:
        rows = [[name] + [next(f"{1e3 * x['bounce_s']:.2f} ({x['bounces']:.0f})" for x in shaft["runs"]
                               if x["pattern"] == name and x["diameter_m"] == d and x["restitution"] == e) for d in ds]
                for name in shaft["patterns"]]
        v = shaft["verdict"][str(e)]
        md.append(f"**restitution {e:g}**\n")
        md.append(markdown_table(["gap pattern", *(f"{1e3 * d:g} mm" for d in ds)], rows))
        falls = [p for p, ok in v["falls_with_diameter"].items() if not ok]
        within = v["within_limit_for_every_pattern"]
        md.append("\nWorst over the patterns: " + ", ".join(f"{1e3 * d:g} mm {1e3 * b:.2f} ms" for d, b in
                                                            v["worst_over_patterns_s"].items())
                  + (f". The bounce does not fall with the diameter for {', '.join(falls)}" if falls else
                     ". The bounce falls with the diameter for every pattern")
                  + (f"; within {1e3 * shaft['limit_s']:g} ms for every pattern: "
                     f"{', '.join(f'{1e3 * d:g} mm' for d in within)}." if within else
                     f"; no diameter keeps it within {1e3 * shaft['limit_s']:g} ms for every pattern.") + "\n")
    return md


def one_at_a_time(data, rig, factors, columns):
    """The tornado: the nominal closing and each factor at its low and high value (sweep)."""
    nominal = [f.nominal for f in factors]
    oat = [nominal]
    for i, f in enumerate(factors):
        for v in (f.low, f.high):
            row = list(nominal)
            row[i] = v
            oat.append(row)
    df_oat = sweep(data, runs=runs_of(factors, oat, rig), evaluate=closing_poles, columns=columns, t_end=T_END,
                   label="tornado (one factor at a time)")
    return tornado(df_oat, factors), df_oat


def all_at_once(data, rig, factors, columns, n):
    """The Sobol indices from N = ``n`` Saltelli samples (sweep): (indices, the sweep's table, the samples)."""
    problem = {"num_vars": len(factors), "names": [f.key for f in factors], "bounds": [[f.low, f.high] for f in factors]}
    x = sobol_sample.sample(problem, n, calc_second_order=False, seed=SEED)
    df_sobol = sweep(data, runs=runs_of(factors, x, rig), evaluate=closing_poles, columns=columns, t_end=T_END,
                     label=f"Sobol (N = {n})")
    return sobol(df_sobol, problem, n), df_sobol, x


def tornado_report(tor):
    """The one-factor-at-a-time section of design_sensitivity.md."""
    md = ["\n## One factor at a time (tornado, `design_sensitivity_tornado.png`)\n"]
    for col, name, unit, scale in OUTPUTS:
        t = tor[col]
        md.append(f"**{name}** (nominal {fmt(t['nominal'], scale)} {unit}): change at low / high value\n")
        md.append(markdown_table(["factor", f"low ({unit})", f"high ({unit})"],
                                 [[b["label"], fmt(b["change_low"], scale), fmt(b["change_high"], scale)] for b in t["bars"]]))
    return md


def sobol_report(sob, summary, factors):
    """The Sobol section of design_sensitivity.md."""
    n, runs = summary["sobol"]["N"], summary["sobol"]["runs"]
    md = [f"\n## Variance-based (Sobol) indices (`design_sensitivity_sobol.png`)\n\n"
          f"{summary['sobol']['method']}. N = {n}: {runs} closings, {summary['sobol']['failed_runs']} failed. "
          "S1: the share of the output's variance a factor causes alone; ST: with its interactions. Intervals "
          "that include 0 mean 'not distinguishable from no effect at this N'. The kinetic margin of a build "
          f"whose cam turns back short of its latch is taken as 0 ({sob['builds_not_latched']} of the "
          f"{runs} builds); a run that ended before its latch would be set to the mean and counted.\n"]
    for col, name, unit, scale in OUTPUTS:
        s = sob[col]
        if "indices" not in s:
            md.append(f"**{name}**: {s['error']}\n")
            continue
        ranked = sorted(s["indices"], key=lambda i: -i["ST"])
        md.append(f"**{name}**: mean {fmt(s['mean'], scale)} {unit}, sd {fmt(s['sd'], scale)} {unit}; largest total "
                  f"index: {next(f.label for f in factors if f.key == ranked[0]['factor'])}\n")
        md.append(markdown_table(["factor", "S1", "ST"],
                                 [[next(f.label for f in factors if f.key == i["factor"]),
                                   f"{i['S1']:.3f} +- {i['S1_conf']:.3f}", f"{i['ST']:.3f} +- {i['ST_conf']:.3f}"]
                                  for i in ranked]))
    return md


def page(summary, rig, factors, quick):
    """design_sensitivity.md."""
    md = ["# Design sensitivity of the closing (reference breaker)\n",
          f"Model: `REFERENCE_BREAKER` ({', '.join(rig.model.effects)}; spring {rig.model.spring_model.label}); its "
          "viscous shaft friction is varied over the bearing estimate and the contact restitution over its published "
          "range. The paper gives no tolerances: each range below names its source; the closing-spring preload is "
          "varied through the springs' free length at fixed stiffness. The tornado's centre is each range's middle."
          + (" **Quick mode: too few runs for the indices to mean anything.**" if quick else "") + "\n",
          markdown_table(["factor", "centre", "range", "unit", "source"],
                         [[f.label, f"{f.nominal:.4g}", f"{f.low:.4g} .. {f.high:.4g}", f.unit, f.basis] for f in factors])]
    md += tornado_report(summary["tornado"])
    md += sobol_report(summary["sobol"]["outputs"], summary, factors)
    md += shaft_report(summary["shaft_across_gap_patterns"])
    return "\n".join(md)


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    data = with_viscous_shaft(P.REFERENCE_BREAKER)
    rig = rig_from_data(data, "REFERENCE_BREAKER")
    factors = breaker_factors(rig)
    columns = pole_columns(rig.breaker.poles.count)
    tor, df_oat = one_at_a_time(data, rig, factors, columns)
    n = N_QUICK if args.quick else N_FULL
    sob, df_sobol, x = all_at_once(data, rig, factors, columns, n)
    shaft = shaft_check(args.quick, columns)
    plot_tornado(tor, factors, out / "design_sensitivity_tornado.png")
    plot_sobol(sob, factors, out / "design_sensitivity_sobol.png", n, len(x))
    summary = {
        "breaker": "vcbmodel.parameters.REFERENCE_BREAKER (viscous shaft friction listed, varied over the bearing "
                   "estimate)",
        "model": {"effects": list(rig.model.effects), "spring_model": rig.model.spring_model.label},
        "preload_realised_by": "closing_spring.free_length at fixed closing_spring.stiffness",
        "factors": [{"key": f.key, "label": f.label, "unit": f.unit, "nominal": f.nominal, "low": f.low, "high": f.high,
                     "source": f.basis} for f in factors],
        "shaft_across_gap_patterns": shaft,
        "tornado": tor,
        "sobol": {"method": "Saltelli sampling (SALib.sample.sobol, scrambled Sobol sequence) and SALib.analyze.sobol: "
                            f"first-order and total indices, {100 * CONF_LEVEL:g} % bootstrap intervals ({RESAMPLES} "
                            "resamples); factors uniform over their ranges, independent",
                  "N": n, "runs": int(len(x)), "failed_runs": int((df_sobol.status != "ok").sum()), "seed": SEED,
                  "outputs": sob},
        "quick": bool(args.quick),
        "sweep_wall_s": {"tornado": df_oat.attrs["wall_s"], "sobol": df_sobol.attrs["wall_s"]},
    }
    write_json(out / "design_sensitivity.json", json_ready(summary))
    md = page(summary, rig, factors, args.quick)
    (out / "design_sensitivity.md").write_text(md)
    print(md)


if __name__ == "__main__":
    main()

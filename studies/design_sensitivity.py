"""Design sensitivity of the reference breaker's closing: which uncertain parameter moves the
closing time, the touch speed and the pole spread, one at a time (tornado chart) and all at
once (variance-based Sobol indices with bootstrap confidence intervals, SALib).

The breaker is vcbmodel.parameters.REFERENCE_BREAKER. It has no viscous shaft friction; the
viscous term is varied from 0 to the value the pendulum test identifies (REFERENCE_PENDULUM_TRUTH),
so that all friction terms can be ranked. The uncertain parameters and their ranges are
vcbmodel.analysis.design.breaker_factors / TOLERANCES (assumptions, stated in the outputs): the
closing-spring preload is varied through the springs' free length at fixed stiffness. All runs
go through the sweep (vcbmodel.analysis.sweep) on all cores.
Writes design_sensitivity_tornado.png, design_sensitivity_sobol.png, design_sensitivity.{json,md}.
"""
from pathlib import Path

import numpy as np
from _common import markdown_table, parse_args, write_json
from SALib.analyze import sobol as sobol_analyze
from SALib.sample import sobol as sobol_sample

from vcbmodel import parameters as P
from vcbmodel.analysis.design import breaker_factors, json_ready, runs_of, with_viscous_shaft
from vcbmodel.analysis.sweep import sweep
from vcbmodel.app.plots import plt, save
from vcbmodel.experiments.loading import rig_from_data

#: (column, label, unit, display scale)
OUTPUTS = [("closing_time_s", "closing time", "ms", 1e3), ("touch_speed_m_s", "touch speed", "m/s", 1.0),
           ("pole_spread_s", "pole spread", "ms", 1e3)]
SEED = 2002  # the Sobol sequence's scramble and the bootstrap
#: Sobol base samples N (runs: N (k + 2) for k factors, first-order and total indices)
N_FULL, N_QUICK = 128, 2


def tornado(df, factors):
    """Output changes (from the nominal run 1) at each factor's low and high value."""
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
    out = {}
    for col, *_ in OUTPUTS:
        y = df[col].to_numpy(float)
        bad = ~np.isfinite(y)
        if bad.all():
            out[col] = {"error": "no run gave this output"}
            continue
        y = np.where(bad, np.nanmean(y), y)  # failed runs (if any) at the mean: stated in the outputs
        si = sobol_analyze.analyze(problem, y, calc_second_order=False, seed=SEED, num_resamples=200)
        out[col] = {"mean": float(np.mean(y)), "sd": float(np.std(y)), "failed_runs_set_to_mean": int(bad.sum()),
                    "indices": [{"factor": name, "S1": float(si["S1"][j]), "S1_conf": float(si["S1_conf"][j]),
                                 "ST": float(si["ST"][j]), "ST_conf": float(si["ST_conf"][j])}
                                for j, name in enumerate(problem["names"])]}
    return out


def plot_tornado(result, factors, path):
    labels = {f.key: f.label for f in factors}
    fig, axes = plt.subplots(1, 3, figsize=(15, 5.2))
    for ax, (col, name, unit, scale) in zip(axes, OUTPUTS):
        bars = result[col]["bars"][::-1]
        y = np.arange(len(bars))
        ax.barh(y, [scale * b["change_low"] for b in bars], color="tab:blue", label="factor at its low value")
        ax.barh(y, [scale * b["change_high"] for b in bars], color="tab:orange", alpha=0.8, label="factor at its high value")
        ax.set_yticks(y, [labels[b["factor"]] for b in bars], fontsize=8)
        ax.axvline(0, color="k", lw=0.8)
        ax.set_xlabel(f"change of {name} ({unit}); nominal {scale * result[col]['nominal']:.4g} {unit}")
        ax.set_title(f"{name}: one factor at a time")
    axes[0].legend(fontsize=8, loc="lower left")
    save(fig, path)


def plot_sobol(result, factors, path, n, runs):
    labels = {f.key: f.label for f in factors}
    fig, axes = plt.subplots(1, 3, figsize=(15, 5.2), sharey=True)
    for ax, (col, name, unit, scale) in zip(axes, OUTPUTS):
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
        ax.set_xlabel("Sobol index (share of the variance), 95 % bootstrap interval")
        ax.set_title(f"{name}: sd {scale * result[col]['sd']:.3g} {unit}")
    axes[0].legend(fontsize=8, loc="lower right")
    fig.suptitle(f"Global sensitivity (Saltelli/Sobol, N = {n}, {runs} closings, uniform over the ranges)", fontsize=10)
    save(fig, path)


def fmt(v, scale=1.0):
    return "-" if v is None or not np.isfinite(v) else f"{scale * v:.4g}"


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    data = with_viscous_shaft(P.REFERENCE_BREAKER)
    rig = rig_from_data(data, "REFERENCE_BREAKER")
    factors = breaker_factors(rig, viscous_upper=P.REFERENCE_PENDULUM_TRUTH["viscous"])
    k = len(factors)

    nominal = [f.nominal for f in factors]
    oat = [nominal]
    for i, f in enumerate(factors):
        for v in (f.low, f.high):
            row = list(nominal)
            row[i] = v
            oat.append(row)
    df_oat = sweep(data, runs=runs_of(factors, oat, rig), label="tornado (one factor at a time)")
    tor = tornado(df_oat, factors)

    n = N_QUICK if args.quick else N_FULL
    problem = {"num_vars": k, "names": [f.key for f in factors], "bounds": [[f.low, f.high] for f in factors]}
    x = sobol_sample.sample(problem, n, calc_second_order=False, seed=SEED)
    df_sobol = sweep(data, runs=runs_of(factors, x, rig), label=f"Sobol (N = {n})")
    sob = sobol(df_sobol, problem, n)

    plot_tornado(tor, factors, out / "design_sensitivity_tornado.png")
    plot_sobol(sob, factors, out / "design_sensitivity_sobol.png", n, len(x))

    summary = {
        "breaker": "vcbmodel.parameters.REFERENCE_BREAKER (viscous shaft friction listed, at the rig's value)",
        "model": {"effects": list(rig.model.effects), "spring_model": rig.model.spring_model.label},
        "preload_realised_by": "closing_spring.free_length at fixed closing_spring.stiffness",
        "factors": [{"key": f.key, "label": f.label, "unit": f.unit, "nominal": f.nominal, "low": f.low, "high": f.high,
                     "assumption": f.basis} for f in factors],
        "tornado": tor,
        "sobol": {"method": "Saltelli sampling (SALib.sample.sobol, scrambled Sobol sequence) and SALib.analyze.sobol: "
                            "first-order and total indices, 95 % bootstrap intervals (200 resamples); factors uniform "
                            "over their ranges, independent",
                  "N": n, "runs": int(len(x)), "failed_runs": int((df_sobol.status != "ok").sum()), "seed": SEED,
                  "outputs": sob},
        "quick": bool(args.quick),
        "sweep_wall_s": {"tornado": df_oat.attrs["wall_s"], "sobol": df_sobol.attrs["wall_s"]},
    }
    write_json(out / "design_sensitivity.json", json_ready(summary))

    md = ["# Design sensitivity of the closing (reference breaker)\n",
          f"Model: `REFERENCE_BREAKER` ({', '.join(rig.model.effects)}; spring {rig.model.spring_model.label}); its "
          "viscous shaft friction is varied from 0 (the reference) to the pendulum-identified value. Every range "
          "below is an **assumption** "
          "(the paper gives no tolerances); the closing-spring preload is varied through the springs' free length at "
          "fixed stiffness." + (" **Quick mode: too few runs for the indices to mean anything.**" if args.quick else "") + "\n",
          markdown_table(["factor", "nominal", "range", "unit", "assumption"],
                         [[f.label, f"{f.nominal:.4g}", f"{f.low:.4g} .. {f.high:.4g}", f.unit, f.basis] for f in factors]),
          "\n## One factor at a time (tornado, `design_sensitivity_tornado.png`)\n"]
    for col, name, unit, scale in OUTPUTS:
        t = tor[col]
        md.append(f"**{name}** (nominal {fmt(t['nominal'], scale)} {unit}): change at low / high value\n")
        md.append(markdown_table(["factor", f"low ({unit})", f"high ({unit})"],
                                 [[b["label"], fmt(b["change_low"], scale), fmt(b["change_high"], scale)] for b in t["bars"]]))
    md.append(f"\n## Variance-based (Sobol) indices (`design_sensitivity_sobol.png`)\n\n"
              f"{summary['sobol']['method']}. N = {n}: {len(x)} closings, {summary['sobol']['failed_runs']} failed. "
              "S1: the share of the output's variance a factor causes alone; ST: with its interactions. Intervals "
              "that include 0 mean 'not distinguishable from no effect at this N'.\n")
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
    (out / "design_sensitivity.md").write_text("\n".join(md))
    print("\n".join(md))


if __name__ == "__main__":
    main()

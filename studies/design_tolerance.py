"""Tolerance study of the reference breaker's closing: 1000 closings (quick: 20) with the
manufacturing tolerances and the uncertain inputs of vcbmodel.analysis.design (TOLERANCES and
RANGES, each with its source) drawn by Latin hypercube sampling, through the sweep on all cores;
histograms of the figures of merit against stated limits, the fraction of breakers out of limits
with 95 % Wilson intervals, and the bounce as count and duration distributions.

Draws: closing-spring free length (the preload's tolerance at fixed stiffness) and stiffness,
spring mass, shaft friction mu_k (mu_s kept >= mu_k), viscous shaft friction (uniform over the
bearing estimate: the reference breaker has none), opening-spring preload, pole moving mass,
contact restitution (uniform over the published range), and each pole's gap offset (around 0; the
reference breaker's largest offset taken as the +-3 sigma assembly tolerance). Normal
distributions with +-tolerance = +-3 sigma unless said. Limits are on the quantities the
reference breaker is specified on: every pole's closing speed over the analyser's zone, the pole
spread and every pole's bounce; and the kinetic margin after the touch (the cam's least kinetic
energy from the first touch to its holding latch): its distribution and the fraction of builds whose
cam does not reach its latch (a failed closing). The same draws are closed twice more, with no viscous friction and
with the viscous range the studies drew before (0 to the pendulum's Cv), to show what the viscous
assumption does to the fractions; and the mean's distance from the nominal closing is split
among the inputs (analysis.design.mean_shift).
Writes design_tolerance.png, design_tolerance.{json,md} and design_tolerance_runs.csv (the table).
"""
from pathlib import Path

import numpy as np
from _common import markdown_table, parse_args, write_json

from vcbmodel import parameters as P
from vcbmodel.analysis.design import (breaker_factors, closing_poles, json_ready, mean_shift, pole_columns, wilson,
                                      with_viscous_shaft)
from vcbmodel.analysis.sweep import DEFAULT_SEED, SAMPLING, design, sweep
from vcbmodel.app.plots import plt, save
from vcbmodel.experiments.loading import rig_from_data

RUNS_FULL, RUNS_QUICK = 1000, 20
#: Each closing runs until the cam has come to rest on its holding latch (parameters.BREAKER_REST_T_END),
#: so that a build's kinetic margin is known: a run that ends before the cam reaches its latch or turns
#: back is counted as not latching, and counted apart.
T_END = P.BREAKER_REST_T_END
#: Spring-rate tolerance of the closing springs (+-, relative, read as 3 sigma): an assumption
#: (helical-spring rate tolerances of a few percent, EN 15800 grades).
STIFFNESS_TOLERANCE = 0.05

#: Limits: (low, high, display scale, unit, where the limit comes from), the reference breaker's
#: acceptance limits (parameters.REFERENCE_LIMITS, the rig's breaker.limits): ASSUMPTIONS, stated as such.
_SPEED, _SPREAD, _BOUNCE = (P.REFERENCE_LIMITS[k] for k in ("closing_speed", "pole_spread", "bounce_duration"))
LIMITS = {
    "zone_speed": (_SPEED["min"], _SPEED["max"], 1.0, "m/s",
                   f"every pole's closing speed over the analyser's zone (breaker.speed_zone: the last "
                   f"{1e3 * P.SPEED_ZONE[0]:g} mm before its touch) within {_SPEED['min']:g}-{_SPEED['max']:g} m/s: the reference breaker's limit "
                   f"(parameters.REFERENCE_LIMITS: {_SPEED['source']}); IEC 62271-100 prescribes no contact speed, the "
                   "manufacturer states it and checks it with travel curves over such a zone"),
    "pole_spread_s": (None, 1e-3 * _SPREAD["max"], 1e3, "ms",
                      f"<= {_SPREAD['max']:g} ms: {_SPREAD['source']}. IEC 62271-100 has a requirement on the simultaneity "
                      "of poles when closing which, as we read it, allows up to a quarter cycle of the rated frequency "
                      "(5 ms at 50 Hz) unless otherwise specified: the tighter, assumed limit is used"),
    "bounce_duration_s": (None, 1e-3 * _BOUNCE["max"], 1e3, "ms",
                          f"every pole's closing bounce <= {_BOUNCE['max']:g} ms: {_BOUNCE['source']}. The duration is "
                          "quantised by the bounce count (the durations of each count are in the bounce section), so a "
                          "limit can cut through the poles of one count: the count is reported beside it"),
    "latches": (0.0, None, 1.0, "J",
                "the cam reaches its holding latch after the touch: a kinetic margin (its least kinetic energy from the "
                "first touch to the latch) above 0. A cam that stops short runs back and the contacts reopen: the "
                "closing fails (a run that ended before the cam reached its latch or turned back is counted here too)"),
}
#: A worst pole's bounce count reported as "many" (the count's own cluster, beyond the limit's)
MANY_BOUNCES = 3
_REF = P.REFERENCE_BREAKER
#: Histograms: (column, label, scale, unit)
PANELS = [("closing_time_s", "closing time", 1e3, "ms"), ("zone_speed_min_m_s", "slowest pole's zone speed", 1.0, "m/s"),
          ("zone_speed_max_m_s", "fastest pole's zone speed", 1.0, "m/s"), ("pole_spread_s", "pole spread", 1e3, "ms"),
          ("kinetic_margin_J", "kinetic margin after touch", 1.0, "J"), ("bounce_duration_s", "bounce duration (worst pole)", 1e3, "ms"),
          ("bounce_count", "bounces (worst pole)", 1.0, "-"), ("peak_cam_roller_force_N", "peak cam-roller force", 1e-3, "kN")]
#: Figures whose mean is compared with the nominal closing (and the shift explained).
SHIFTED = [("closing_time_s", 1e3, "ms"), ("closing_speed_m_s", 1.0, "m/s"), ("bounce_duration_s", 1e3, "ms")]


def limit_text(col):
    lo, hi, scale, unit, _ = LIMITS[col]
    if hi is None:
        return f"> {scale * lo:g} {unit}"
    return f"{scale * lo:g}-{scale * hi:g} {unit}" if lo is not None else f"<= {scale * hi:g} {unit}"


def tolerance_design(rig, factors, n, seed):
    """The draws: the sweep's Latin hypercube over the distributions, then the ties (mu_s >=
    mu_k, the ranges' ends) applied to each drawn row; with each drawn path's source."""
    s = rig.closing_spring
    specs, ties, sources = [], {}, {}
    for f in factors:
        if f.key == "gap_spread":
            continue  # drawn per pole below
        if f.kind == "preload":  # the preload's tolerance as free length at fixed stiffness
            specs.append(f"closing_spring.free_length=normal:{s.free_length!r}:{f.sd / s.stiffness!r}")
        elif f.distribution == "uniform":
            specs.append(f"{f.path or 'friction.mu_k'}=uniform:{f.low!r}:{f.high!r}")
        else:
            specs.append(f"{f.path or 'friction.mu_k'}=normal:{f.nominal!r}:{f.sd!r}")
        path = specs[-1].split("=")[0]
        ties[path], sources[path] = f, f.basis
    specs.append(f"closing_spring.stiffness=normal:{s.stiffness!r}:{STIFFNESS_TOLERANCE * s.stiffness / 3!r}")
    sources["closing_spring.stiffness"] = (f"+-{100 * STIFFNESS_TOLERANCE:.0f} % (3 sigma): helical-spring rate "
                                           "tolerances of a few percent, assumed")
    gap = next(f for f in factors if f.key == "gap_spread")
    for i in range(rig.breaker.poles.count):
        specs.append(f"breaker.poles.gap_offsets.{i}=normal:0.0:{gap.nominal / 3!r}")
        sources[f"breaker.poles.gap_offsets.{i}"] = (f"each pole's gap offset about the nominal gap, +-{1e3 * gap.nominal:g} mm "
                                                     "(3 sigma): the assembly tolerance (parameters.py)")
    table = design(specs, samples=n, seed=seed)
    for path, f in ties.items():
        if f.kind != "preload":
            table[path] = table[path].clip(f.lower, f.upper)
    if "friction.mu_k" in table:
        table["friction.mu_s"] = np.maximum(rig.friction.get("mu_s", 0.0), table["friction.mu_k"])
    return table, specs, sources


def out_of_limits(df, count):
    """{limit: boolean array of the runs out of it} (a run that failed or never closed is out of each)."""
    failed = (df.status != "ok").to_numpy()
    speeds = np.column_stack([df[f"pole_{i + 1}_zone_speed_m_s"].to_numpy(float) for i in range(count)])
    bounce = np.column_stack([df[f"pole_{i + 1}_bounce_s"].to_numpy(float) for i in range(count)])
    lo, hi = LIMITS["zone_speed"][:2]
    spread = df["pole_spread_s"].to_numpy(float)
    latched = df["latched"].to_numpy(float)
    return {"zone_speed": failed | np.any(~np.isfinite(speeds) | (speeds < lo) | (speeds > hi), axis=1),
            "pole_spread_s": failed | ~np.isfinite(spread) | (spread > LIMITS["pole_spread_s"][1]),
            "bounce_duration_s": failed | np.any(~np.isfinite(bounce) | (bounce > LIMITS["bounce_duration_s"][1]), axis=1),
            "latches": failed | (latched != 1.0)}


def fractions(bad):
    """{limit: out, of, fraction, 95 % Wilson interval} and the same for any limit."""
    n = len(next(iter(bad.values())))
    out = {col: {"out": int(b.sum()), "of": n, "fraction": float(b.mean()), "fraction_95ci": wilson(int(b.sum()), n)}
           for col, b in bad.items()}
    every = np.any(np.column_stack(list(bad.values())), axis=1)
    out["any"] = {"out": int(every.sum()), "of": n, "fraction": float(every.mean()),
                  "fraction_95ci": wilson(int(every.sum()), n)}
    return out


def bounce_distributions(ok, count):
    """The bounce as a spring maker's analyser reports it: how many closings' worst pole bounces
    n times, and every pole's bounce durations grouped by its bounce count (s)."""
    worst = ok["bounce_count"].to_numpy(float)
    counts = {int(c): int((worst == c).sum()) for c in np.unique(worst[np.isfinite(worst)])}
    n = np.concatenate([ok[f"pole_{i + 1}_bounces"].to_numpy(float) for i in range(count)])
    d = np.concatenate([ok[f"pole_{i + 1}_bounce_s"].to_numpy(float) for i in range(count)])
    by_count = {}
    for c in np.unique(n[np.isfinite(n)]):
        v = d[n == c]
        by_count[int(c)] = {"poles": int(v.size), "min": float(v.min()), "median": float(np.median(v)), "max": float(v.max())}
    three = int(np.sum(worst >= MANY_BOUNCES))
    return {"worst_pole_count": counts, "duration_by_count": by_count,
            "three_or_more": {"out": three, "of": int(worst.size), "fraction": three / max(worst.size, 1),
                              "fraction_95ci": wilson(three, int(worst.size))}}


def cluster_text(by_count):
    """Where the bounce limit falls among the counts' durations (the bounce section's first line)."""
    limit = 1e-3 * _BOUNCE["max"]
    bouncing = {c: v for c, v in by_count.items() if c > 0}  # a pole that does not bounce has no duration
    if not bouncing:
        return f"No pole bounces: the {_BOUNCE['max']:g} ms limit cuts nothing.\n"
    spans = ", ".join(f"{1e3 * v['min']:.2f}-{1e3 * v['max']:.2f} ms with {c}" for c, v in bouncing.items())
    cut = [str(c) for c, v in bouncing.items() if v["min"] <= limit < v["max"]]
    below = [c for c, v in bouncing.items() if v["max"] <= limit]
    above = [c for c, v in bouncing.items() if v["min"] > limit]
    if cut:
        where = f"cuts through the poles with {' and '.join(cut)} bounce(s)."
    elif not above:
        where = "lies above every count's durations: no pole goes over it."
    elif not below:
        where = "lies below every count's durations: every pole that bounces goes over it."
    else:
        where = f"falls between the poles with {max(below)} and with {min(above)} bounce(s)."
    return f"A pole's bounce lasts {spans} bounce(s); the {_BOUNCE['max']:g} ms limit {where}\n"


def bounce_by_restitution(ok, count):
    """Fraction of closings with a pole over the bounce limit in each third of the restitution's range."""
    e = ok["breaker.contact.restitution"].to_numpy(float)
    bounce = np.max(np.column_stack([ok[f"pole_{i + 1}_bounce_s"].to_numpy(float) for i in range(count)]), axis=1)
    lo, hi = P.RESTITUTION_RANGE
    edges = np.linspace(lo, hi, 4)
    rows = []
    for a, b in zip(edges[:-1], edges[1:]):
        sel = (e >= a) & (e <= b)
        k = int((bounce[sel] > LIMITS["bounce_duration_s"][1]).sum())
        rows.append({"restitution": [float(a), float(b)], "closings": int(sel.sum()), "over": k,
                     "fraction_95ci": wilson(k, int(sel.sum()))})
    return rows


def margin_summary(df, nominal):
    """The kinetic margin after the touch over the draws: the nominal build's (J, and of its energy at
    the touch), its distribution over the builds that latch (J), and how many builds do not latch:
    turned back short of the latch (with the largest shortfall, deg), ended before it, failed."""
    latched = df["latched"].to_numpy(float)
    margin = df["kinetic_margin_J"].to_numpy(float)[latched == 1.0]
    short = int(np.sum((latched == 0.0) & (df.status == "ok").to_numpy()))
    unknown = int(np.sum(~np.isfinite(latched) & (df.status == "ok").to_numpy()))
    out = {"nominal_J": nominal["kinetic_margin_J"], "nominal_at_touch_J": nominal["kinetic_at_touch_J"],
           "latched": int(margin.size), "turned_back_short": short, "run_ended_first": unknown,
           "failed_or_not_closed": int((df.status != "ok").sum()), "of": int(len(df))}
    if margin.size:
        out.update({"min_J": float(margin.min()), "p0.5_J": float(np.percentile(margin, 0.5)),
                    "p5_J": float(np.percentile(margin, 5)), "median_J": float(np.median(margin)),
                    "max_J": float(margin.max())})
    return out


def margin_text(m, fr):
    """The kinetic margin's paragraph of design_tolerance.md."""
    spread = (f"over the {m['latched']} builds that latch it is {m['min_J']:.1f} J at least, {m['p0.5_J']:.1f} J at the "
              f"0.5 % point, {m['p5_J']:.1f} J at the 5 % point, median {m['median_J']:.1f} J"
              if m["latched"] else "no build latches")
    return (f"The nominal build keeps {m['nominal_J']:.1f} J of the {m['nominal_at_touch_J']:.0f} J its cam holds at the "
            f"first touch; {spread}. Builds that do not reach their latch: {pct(fr['latches'])} "
            f"({m['turned_back_short']} turned back short of it, {m['run_ended_first']} ended the "
            f"{1e3 * T_END:g} ms run before it, {m['failed_or_not_closed']} failed or never closed).")


def viscous_range(data, table, columns, count, fr):
    """The same draws closed with the viscous friction at the bearing estimate's two ends and over the
    range the studies drew before (the pendulum's Cv), each draw mapped along its range: their fractions
    out of limits, the main run's interval half-widths, and whether the two ends differ by less."""
    lo, hi = P.VISCOUS_BEARING_ESTIMATE
    old_lo, old_hi = P.VISCOUS_PENDULUM_RANGE
    ends = {f"Cv {lo:g} N m s/rad (the bearing estimate's low end)": table.assign(**{"friction.viscous": lo}),
            f"Cv {hi:g} N m s/rad (its high end)": table.assign(**{"friction.viscous": hi})}
    variants = dict(ends, **{f"Cv {old_lo:g}-{old_hi:g} N m s/rad (the pendulum's Cv, drawn before)":
                             table.assign(**{"friction.viscous": old_lo + (table["friction.viscous"] - lo) / (hi - lo)
                                             * (old_hi - old_lo)})})
    viscous = {f"Cv {lo:g}-{hi:g} N m s/rad (bearing estimate, this study)": fr}
    for name, t in variants.items():
        d = sweep(data, runs=t, evaluate=closing_poles, columns=columns, t_end=T_END, label=f"tolerance study, {name}")
        viscous[name] = fractions(out_of_limits(d, count))
    half = {k: 0.5 * (v["fraction_95ci"][1] - v["fraction_95ci"][0]) for k, v in fr.items()}
    low, high = (viscous[name] for name in ends)
    return {"fractions": viscous, "interval_half_widths": half,
            "ends_within_the_intervals": {k: abs(high[k]["fraction"] - low[k]["fraction"]) <= half[k] for k in fr}}


def nominal_vector(rig, table):
    """The nominal value of every drawn path (the rig's; viscous 0: the reference has none)."""
    values = {"closing_spring.free_length": rig.closing_spring.free_length, "closing_spring.mass": rig.closing_spring.mass,
              "friction.mu_k": rig.friction["mu_k"], "friction.viscous": rig.friction.get("viscous", 0.0),
              "breaker.opening_spring.preload": rig.breaker.opening_spring.preload,
              "breaker.poles.moving_mass": rig.breaker.poles.moving_mass,
              "breaker.contact.restitution": rig.breaker.contact.restitution,
              "closing_spring.stiffness": rig.closing_spring.stiffness}
    values.update({f"breaker.poles.gap_offsets.{i}": o for i, o in enumerate(rig.breaker.poles.gap_offsets)})
    return [c for c in table.columns if c in values], [values[c] for c in table.columns if c in values]


def plot(ok, fr, n, path):
    fig, axes = plt.subplots(2, 4, figsize=(18, 7.5))
    for ax, (col, label, scale, unit) in zip(axes.flat, PANELS):
        v = scale * ok[col].to_numpy(float)
        v = v[np.isfinite(v)]
        if col == "bounce_count":
            values, counts = np.unique(v, return_counts=True)
            ax.bar(values, counts, color="tab:blue", alpha=0.8)
        else:
            ax.hist(v, bins=max(8, min(50, int(np.sqrt(max(v.size, 1))) * 2)), color="tab:blue", alpha=0.8)
        ax.set_xlabel(f"{label} ({unit})")
        ax.set_ylabel("closings")
        key = {"zone_speed_min_m_s": "zone_speed", "zone_speed_max_m_s": "zone_speed",
               "kinetic_margin_J": "latches"}.get(col, col)
        if key in LIMITS:
            lo, hi, s, _, _ = LIMITS[key]
            for lim in (lo, hi):
                if lim is not None:
                    ax.axvline(s * lim, color="tab:red", lw=1.5)
            ax.set_title(f"{label}: limit {limit_text(key)}; {100 * fr[key]['fraction']:.1f} % out", fontsize=9)
        else:
            ax.set_title(f"{label} (no limit stated)", fontsize=9)
    fig.suptitle(f"Tolerance study: {n} closings of the reference breaker (Latin hypercube); "
                 f"{100 * fr['any']['fraction']:.1f} % out of at least one limit (red lines: ASSUMED limits)", fontsize=10)
    save(fig, path)


def viscous_text(v, nominal):
    """Whether the fractions hold over the bearing estimate's range, from the two ends' closings
    (``nominal``: the nominal closing's figures)."""
    moved = [k for k, ok in v["ends_within_the_intervals"].items() if not ok]
    names = list(v["fractions"])
    low, high = v["fractions"][names[1]], v["fractions"][names[2]]
    diffs = ", ".join(f"{k} {100 * (high[k]['fraction'] - low[k]['fraction']):+.1f} points (half-width "
                      f"{100 * v['interval_half_widths'][k]:.1f})" for k in v["interval_half_widths"])
    if not moved:
        return (f"From the low to the high end of the bearing estimate every fraction moves by less than its interval's "
                f"half-width ({diffs}): the viscous friction does not decide them.")
    return (f"From the low to the high end of the bearing estimate {', '.join(moved)} move by more than the interval's "
            f"half-width ({diffs}): within the justified range the viscous friction still decides "
            + ("them" if len(moved) > 1 else "it") + ". The zone speed's fraction measures how close the nominal breaker "
            f"sits to the window's top: its fastest pole closes at {nominal['zone_speed_max_m_s']:.3f} m/s over the zone "
            f"(slowest {nominal['zone_speed_min_m_s']:.3f}) against {LIMITS['zone_speed'][1]:g} m/s, so any drag on the "
            "shaft moves the fraction.")


def pct(o):
    return (f"{o['out']}/{o['of']} ({100 * o['fraction']:.1f} %, {100 * o['fraction_95ci'][0]:.1f}-"
            f"{100 * o['fraction_95ci'][1]:.1f} %)")


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    data = with_viscous_shaft(P.REFERENCE_BREAKER)
    rig = rig_from_data(data, "REFERENCE_BREAKER")
    count = rig.breaker.poles.count
    factors = breaker_factors(rig)
    n = RUNS_QUICK if args.quick else RUNS_FULL
    table, specs, sources = tolerance_design(rig, factors, n, DEFAULT_SEED)
    columns = pole_columns(count)
    df = sweep(data, runs=table, evaluate=closing_poles, columns=columns, output=str(out / "design_tolerance_runs.csv"),
               force=True, t_end=T_END, label=f"tolerance study ({n} closings)")
    ok = df[df.status == "ok"]
    fr = fractions(out_of_limits(df, count))

    nominal = closing_poles(rig, t_end=T_END)
    paths, nominal_values = nominal_vector(rig, table)
    shifts = {}
    for col, scale, unit in SHIFTED:
        y = df[col].to_numpy(float)
        m = mean_shift(table[paths].to_numpy(float), y, nominal_values, nominal[col])
        shifts[col] = {"nominal": nominal[col], "mean": float(np.nanmean(y)), **m,
                       "shares_by_input": dict(zip(paths, m["shares"]))}

    summary = {
        "breaker": "vcbmodel.parameters.REFERENCE_BREAKER (viscous shaft friction listed, drawn over the bearing estimate)",
        "model": {"effects": list(rig.model.effects), "spring_model": rig.model.spring_model.label},
        "runs": int(len(df)), "failed_runs": int(df.status.str.startswith("failed").sum()),
        "not_closed_runs": int((df.status == "not_closed").sum()),
        "sampling": f"{SAMPLING['lhs']}, seed {DEFAULT_SEED}; ties applied after the draw: mu_s >= mu_k, the ranges' ends",
        "draws": specs, "sources": sources, "stiffness_tolerance": STIFFNESS_TOLERANCE,
        "limits": {col: {"low": lo_, "high": hi_, "unit_of_limits": "SI", "source": why, **fr[col]}
                   for col, (lo_, hi_, _, _, why) in LIMITS.items()},
        "out_of_any_limit": fr["any"],
        "viscous_range": viscous_range(data, table, columns, count, fr),
        "kinetic_margin": margin_summary(df, nominal),
        "bounce": {**bounce_distributions(ok, count), "over_limit_by_restitution": bounce_by_restitution(ok, count)},
        "mean_against_nominal": shifts, "nominal": nominal,
        "statistics": {}, "quick": bool(args.quick), "sweep_wall_s": df.attrs["wall_s"],
    }
    for col, label, scale, unit in PANELS:
        v = ok[col].to_numpy(float)
        v = v[np.isfinite(v)]
        if v.size:
            summary["statistics"][col] = {"mean": float(v.mean()), "sd": float(v.std(ddof=1)) if v.size > 1 else 0.0,
                                          "p0.5": float(np.percentile(v, 0.5)), "p50": float(np.median(v)),
                                          "p99.5": float(np.percentile(v, 99.5)), "min": float(v.min()), "max": float(v.max())}
    plot(ok, fr, len(df), out / "design_tolerance.png")
    write_json(out / "design_tolerance.json", json_ready(summary))
    md = report(summary, rig, factors, specs, sources, len(df), args.quick, paths)
    (out / "design_tolerance.md").write_text(md)
    print(md)


def draw_text(draw):
    """A draw as a reader takes it: ``uniform:0.0040000000000000036:0.097`` -> ``uniform 0.004-0.097``,
    ``normal:0.3:0.0020635`` -> ``normal 0.3, sd 0.002064`` (the table of runs keeps full precision)."""
    kind, a, b = draw.split(":")
    a, b = float(a), float(b)
    return f"uniform {a:.4g}-{b:.4g}" if kind == "uniform" else f"{kind} {a:.4g}, sd {b:.4g}"


def report(summary, rig, factors, specs, sources, n, quick, paths):
    """design_tolerance.md from the summary."""
    fr = summary["limits"]
    md = ["# Tolerance study of the closing (reference breaker)\n",
          f"{n} closings ({summary['sampling']}){'; **quick mode: too few for the fractions to mean much**' if quick else ''}. "
          f"{summary['failed_runs']} runs failed, {summary['not_closed_runs']} never closed "
          f"(both counted out of limits). Model: {', '.join(rig.model.effects)}; spring "
          f"{rig.model.spring_model.label}. Where each distribution comes from:\n",
          markdown_table(["parameter", "draw", "source"], [[s.split("=")[0], draw_text(s.split("=")[1]),
                                                            sources[s.split("=")[0]]] for s in specs]),
          "\n## Against the limits (on every pole; where each comes from)\n",
          markdown_table(["limit", "value", "out of it (95 % Wilson interval)", "source"],
                         [[col, limit_text(col), pct(fr[col]), fr[col]["source"]] for col in LIMITS]),
          f"\nOut of at least one limit (a failed run counts as out): {pct(summary['out_of_any_limit'])}.\n",
          "## The kinetic margin after the touch\n",
          margin_text(summary["kinetic_margin"], fr) + "\n",
          "## The viscous range\n",
          "The same draws closed with the viscous shaft friction of each row (the other inputs unchanged):\n",
          markdown_table(["viscous friction", *LIMITS, "any"],
                         [[name, *(pct(v[k]) for k in (*LIMITS, "any"))] for name, v in summary["viscous_range"]["fractions"].items()]),
          "\n" + viscous_text(summary["viscous_range"], summary["nominal"]) + "\n",
          "## Bounce: count and duration\n",
          markdown_table(["worst pole's bounces", "closings"],
                         [[c, k] for c, k in summary["bounce"]["worst_pole_count"].items()]),
          "\n" + markdown_table(["a pole's bounces", "poles", "duration min / median / max (ms)"],
                                [[c, v["poles"], f"{1e3 * v['min']:.2f} / {1e3 * v['median']:.2f} / {1e3 * v['max']:.2f}"]
                                 for c, v in summary["bounce"]["duration_by_count"].items()]),
          "\n" + cluster_text(summary["bounce"]["duration_by_count"]),
          f"A count limit does not cut a cluster: closings whose worst pole bounces {MANY_BOUNCES} times or more: "
          f"{pct(summary['bounce']['three_or_more'])}.\n",
          "\nClosings with a pole over the bounce limit, by restitution (the contacts' restitution decides it):\n",
          markdown_table(["restitution", "closings", f"over {_BOUNCE['max']:g} ms (95 % interval)"],
                         [[f"{r['restitution'][0]:.2f}-{r['restitution'][1]:.2f}", r["closings"],
                           f"{r['over']} ({100 * r['fraction_95ci'][0]:.0f}-{100 * r['fraction_95ci'][1]:.0f} %)"]
                          for r in summary["bounce"]["over_limit_by_restitution"]]),
          "\n## The mean against the nominal closing\n",
          "The draws' mean is not the nominal breaker: the viscous friction and the restitution are drawn over ranges, "
          f"not around the reference's values ({_REF['friction'].get('viscous', 0.0):g} and "
          f"{_REF['breaker']['contact']['restitution']:g}), and the gap offsets around equal gaps, not the reference's "
          + "/".join(f"{1e3 * g:+g}" for g in _REF["breaker"]["poles"]["gap_offsets"])
          + " mm. Each input's share of the shift is its slope (a linear fit over the draws) "
          "times its mean draw's distance from the nominal; the rest is the response's curvature:\n"]
    for col, scale, unit in SHIFTED:
        s = summary["mean_against_nominal"][col]
        top = sorted(s["shares_by_input"].items(), key=lambda kv: -abs(kv[1]))[:3]
        md.append(f"- {col}: nominal {scale * s['nominal']:.4g} {unit}, mean {scale * s['mean']:.4g} {unit} "
                  f"(shift {scale * s['shift']:+.3g}); largest shares " + ", ".join(f"{p} {scale * v:+.3g}" for p, v in top)
                  + f"; curvature {scale * s['curvature']:+.3g} {unit} (linear fit R^2 {s['r2']:.2f})")
    md += ["\n## Figures of merit (`design_tolerance.png`)\n",
           markdown_table(["figure", "mean", "sd", "0.5 %", "median", "99.5 %"],
                          [[f"{label} ({unit})", *(f"{scale * summary['statistics'][col][k]:.4g}"
                                                   for k in ("mean", "sd", "p0.5", "p50", "p99.5"))]
                           for col, label, scale, unit in PANELS if col in summary["statistics"]])]
    return "\n".join(md) + "\n"


if __name__ == "__main__":
    main()

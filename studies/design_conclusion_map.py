"""The paper's conclusion as a map: where does the shaft friction matter more than the closing
spring's motion?

At each point of a grid of closing-spring mass (0.2-1.5 kg; the paper: "each spring about 1 kg")
and shaft friction mu_k (0.05-0.2), the reference breaker closes three times
(vcbmodel.analysis.design.conclusion_effects): the full model (shaft friction + lumped-2 spring in
the `exact` convention, the reference breaker's, as studies/vcb_closing.py), without the shaft friction,
and with a massless spring. The ratio (effect of dropping the friction) / (effect of a massless spring) is
taken on the follower displacement (rms change against the full model over the closing) and on
the closing time (|change|); ratio > 1: friction matters more, as the paper concludes. mu_s
follows mu_k where it would fall below it. All runs go through the sweep on all cores.
Writes design_conclusion_map.png and design_conclusion_map.{json,md}.
"""
import copy
from pathlib import Path

import numpy as np
from _common import markdown_table, parse_args, write_json
from matplotlib.colors import LogNorm

from vcbmodel import parameters as P
from vcbmodel.analysis.design import CONCLUSION_COLUMNS, conclusion_effects, json_ready
from vcbmodel.analysis.sweep import design, sweep
from vcbmodel.app.plots import plt, save
from vcbmodel.experiments.loading import rig_from_data

MASS = (0.2, 1.5)  # kg, each closing spring
MU_K = (0.05, 0.2)
#: Closings per point of the map (vcbmodel.analysis.design.conclusion_effects: full, no friction, massless spring).
CLOSINGS_PER_POINT = 3
_MU_K_REF = P.REFERENCE_BREAKER["friction"]["mu_k"]
#: Where each axis's range comes from (written into the outputs).
SOURCES = {"closing_spring.mass": f"{MASS[0]:g}-{MASS[1]:g} kg: brackets the paper's chain parameter m0 = "
                                  f"{P.REFERENCE_CAM['closing_spring']['mass']:g} kg (eq. 8), the settled active mass "
                                  f"{P.PAPER_SPRING_MASS:.2f} kg (pi^2/4 m0) and the text's 'each spring about 1 kg'; a "
                                  "spring of the reference's rate that passes the extension-spring checks weighs 1.9 kg "
                                  "(plug ends, parameters.py), beyond the map",
           "friction.mu_k": f"{MU_K[0]:g}-{MU_K[1]:g}: the example pendulum records' 0.09-0.16 (about +-25 % around the "
                            f"reference's {_MU_K_REF:g}) widened to a well-greased and a dry journal; mu_s follows mu_k "
                            "where it would fall below it; the viscous term stays off (the reference breaker has none)"}
GRID_FULL, GRID_QUICK = (8, 7), (3, 3)  # (masses, mu_k values)
RATIOS = [("ratio_rms", "follower displacement (rms change)"), ("ratio_closing_time", "closing time (|change|)")]


def base_rig():
    """The reference breaker with the full model of the closing study: lumped-2, exact convention."""
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    effects = list(data["model"]["effects"])
    if "spring_mass" not in effects:
        effects.append("spring_mass")
    data["model"] = {"effects": effects, "spring_model": "lumped-2", "lumped_convention": "exact"}
    return data


def boundary(masses, mus, ratio):
    """For each mu_k: the spring mass where the ratio crosses 1 (linear in log ratio), or None."""
    out = []
    for j, mu in enumerate(mus):
        r = np.log(np.clip(ratio[:, j], 1e-6, 1e6))
        cross = None
        for i in range(len(masses) - 1):
            if np.isfinite(r[i]) and np.isfinite(r[i + 1]) and (r[i] > 0) != (r[i + 1] > 0):
                cross = float(masses[i] + (masses[i + 1] - masses[i]) * r[i] / (r[i] - r[i + 1]))
                break
        out.append({"mu_k": float(mu), "spring_mass_at_ratio_1_kg": cross,
                    "friction_matters_more_everywhere": bool(np.all(r > 0)),
                    "spring_matters_more_everywhere": bool(np.all(r < 0))})
    return out


def ratio_grids(data, rig, nm, nk):
    """The map through the sweep: (spring masses, mu_k values, {column: grid (mass x mu_k)}, the table)."""
    table = design([f"closing_spring.mass={MASS[0]}:{MASS[1]}:{nm}", f"friction.mu_k={MU_K[0]}:{MU_K[1]}:{nk}"])
    table["friction.mu_s"] = np.maximum(rig.friction.get("mu_s", 0.0), table["friction.mu_k"])
    df = sweep(data, runs=table, evaluate=conclusion_effects, columns=CONCLUSION_COLUMNS,
               label=f"conclusion map ({nm} x {nk} points, {CLOSINGS_PER_POINT} closings each)")
    masses = np.unique(table["closing_spring.mass"])
    mus = np.unique(table["friction.mu_k"])

    def grid(col):
        g = np.full((len(masses), len(mus)), np.nan)
        for _, r in df.iterrows():
            g[np.searchsorted(masses, r["closing_spring.mass"]), np.searchsorted(mus, r["friction.mu_k"])] = r[col]
        return g

    return masses, mus, {col: grid(col) for col in CONCLUSION_COLUMNS}, df


def figure(path, masses, mus, grids, ref):
    """design_conclusion_map.png: each ratio over (spring mass, mu_k), the line where it is 1."""
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.2))
    M, K = np.meshgrid(masses, mus, indexing="ij")
    for ax, (col, name) in zip(axes, RATIOS):
        z = np.clip(grids[col], 1e-2, 1e2)
        z = np.where(np.isfinite(z), z, 1e2)
        m = max(np.nanmax(z), 1 / np.nanmin(z), 2.0)  # symmetric in log: white at ratio 1
        lo, hi = 1 / m, m
        cf = ax.contourf(M, K, z, levels=np.geomspace(lo, hi, 15), norm=LogNorm(lo, hi), cmap="RdBu_r")
        fig.colorbar(cf, ax=ax, label="friction effect / spring-motion effect", format="%.2g")
        cs = ax.contour(M, K, z, levels=[1.0], colors="k", linewidths=2)
        ax.clabel(cs, fmt={1.0: "ratio = 1"}, fontsize=8)
        ax.plot(M.ravel(), K.ravel(), ".", color="0.3", ms=3)
        ax.plot(ref["spring_mass_kg"], ref["mu_k"], "k*", ms=12, label="reference breaker")
        ax.axvline(P.HEAVY_SPRING_MASS, color="0.3", ls=":", label="the paper's 'about 1 kg' spring")
        ax.set_xlabel("closing-spring mass, each (kg)")
        ax.set_ylabel("shaft friction mu_k")
        ax.set_title(f"{name}: red = friction matters more", fontsize=10)
        ax.legend(fontsize=8, loc="upper right")
    save(fig, path)


def ratio_section(name, g, b, frac):
    """One ratio's section of the page: where friction matters more, and the line where the ratio is 1."""
    return [f"## {name}\n\nFriction matters more (ratio > 1) on {100 * frac:.0f} % of the map.\n",
            markdown_table(["mu_k", "spring mass where ratio = 1 (kg)", "ratio at the lightest spring",
                            "ratio at the heaviest spring"],
                           [[f"{x['mu_k']:.3f}",
                             f"{x['spring_mass_at_ratio_1_kg']:.2f}" if x["spring_mass_at_ratio_1_kg"] is not None
                             else ("none: friction matters more everywhere" if x["friction_matters_more_everywhere"]
                                   else "none: spring motion matters more everywhere"
                                   if x["spring_matters_more_everywhere"] else "none"),
                             f"{g[0, j]:.2f}", f"{g[-1, j]:.2f}"] for j, x in enumerate(b)])]


def where_it_holds(grids):
    """Where the conclusion holds, in words: 'left of the black line (lighter springs, more friction)' only
    where every computed ratio falls with the spring's mass and rises with mu_k."""
    def monotone(g, axis, sign):  # at least one computed step along the axis: a grid of failed runs orders nothing
        d = sign * np.diff(g, axis=axis)
        d = d[np.isfinite(d)]
        return bool(d.size) and bool(np.all(d > 0))

    if all(monotone(grids[col], 0, -1) and monotone(grids[col], 1, 1) for col, _ in RATIOS):
        return "left of the black line (lighter springs, more friction; red in the figure)"
    return "red in the figure (the ratio does not fall with the spring's mass and rise with mu_k everywhere)"


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    data = base_rig()
    rig = rig_from_data(data, "REFERENCE_BREAKER (lumped-2, exact)")
    nm, nk = GRID_QUICK if args.quick else GRID_FULL
    masses, mus, grids, df = ratio_grids(data, rig, nm, nk)
    ref = {"spring_mass_kg": rig.closing_spring.mass, "mu_k": rig.friction["mu_k"]}
    figure(out / "design_conclusion_map.png", masses, mus, grids, ref)
    summary = {"model": {"effects": list(rig.model.effects), "spring_model": rig.model.spring_model.label},
               "grid": {"spring_mass_kg": masses.tolist(), "mu_k": mus.tolist()},
               "grid_sources": SOURCES, "reference": ref, "runs": int(len(df)),
               "closings": CLOSINGS_PER_POINT * int(len(df)),
               "failed": int((df.status != "ok").sum()), "quick": bool(args.quick),
               "definition": "ratio = (change when the shaft friction is dropped) / (change when the spring is made "
                             "massless), each against the full model (friction + lumped-2 exact)",
               "maps": {col: grids[col].tolist() for col in CONCLUSION_COLUMNS}, "holds": {}}
    md = ["# The paper's conclusion as a map\n",
          f"{summary['definition']}; on the follower displacement (rms over the {1e3 * P.BREAKER_T_END:.0f} ms run) and on the closing time. "
          f"Grid: {len(masses)} spring masses x {len(mus)} mu_k, {summary['closings']} closings "
          f"({summary['failed']} points failed).{' **Quick mode: a coarse grid.**' if args.quick else ''}\n",
          markdown_table(["axis", "range and where it comes from"], [[k, v] for k, v in SOURCES.items()])]
    for col, name in RATIOS:
        g = grids[col]
        frac = float(np.mean(g[np.isfinite(g)] > 1)) if np.isfinite(g).any() else float("nan")
        b = boundary(masses, mus, g)
        summary["holds"][col] = {"fraction_of_map_where_friction_matters_more": frac, "boundary": b}
        md += ratio_section(name, g, b, frac)
    md.append("\nRows are mu_k; the paper's conclusion ('friction matters more than spring motion') holds where the "
              f"ratio is above 1: {where_it_holds(grids)}. "
              "Full maps: `design_conclusion_map.json`, figure `design_conclusion_map.png`.\n")
    write_json(out / "design_conclusion_map.json", json_ready(summary))
    (out / "design_conclusion_map.md").write_text("\n".join(md))
    print("\n".join(md))


if __name__ == "__main__":
    main()

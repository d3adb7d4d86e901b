"""The closing spring with the least stored energy that still closes at a target touch speed,
with the pole spread, the bounce and the spring's own pull within limits.

Design variables: each closing spring's stiffness k and its charged pull (preload) F0, set
through the free length (L_free = L_charged - F0 / k). Stored energy: count F0^2 / (2 k). A
grid over (k, F0) through the sweep (all cores) maps the touch speed and the constraints; then
scipy.optimize runs the model itself: for each k a secant search finds the F0 that gives the
target touch speed, and a bounded Brent search over k minimises the stored energy, constraint
violations penalised. Limits (assumptions, as in studies/design_tolerance.py): pole spread
<= 2 ms, bounce duration <= 2 ms, and the springs' smallest pull during the run at least
MIN_PULL_FRACTION of the preload (a tension spring must stay taut). The target touch speed is
the middle of the assumed 1.0-1.3 m/s window.
Writes design_optimum.png and design_optimum.{json,md}.
"""
import copy
from pathlib import Path

import numpy as np
from _common import markdown_table, parse_args, write_json
from scipy.optimize import minimize_scalar, root_scalar

from vcbmodel import parameters as P
from vcbmodel.analysis.design import (DESIGN_COLUMNS, closing_design, free_length_for, json_ready, preload,
                                      stored_energy)
from vcbmodel.analysis.sweep import sweep
from vcbmodel.app.plots import plt, save
from vcbmodel.experiments.loading import rig_from_data

TARGET_TOUCH_SPEED = 1.15  # m/s: middle of the assumed 1.0-1.3 m/s window (studies/design_tolerance.py)
LIMITS = {"pole_spread_s": 2e-3, "bounce_duration_s": 2e-3}  # s, assumed (see design_tolerance.py)
MIN_PULL_FRACTION = 0.1  # the springs' smallest pull during the run / preload: an assumed margin
K_RANGE = (0.6, 1.4)  # x the reference stiffness
F_RANGE = (0.5, 1.3)  # x the reference preload
GRID_FULL, GRID_QUICK = (7, 9), (3, 4)


class Model:
    """The closing at (k, F0), evaluated in this process and remembered."""

    def __init__(self, data):
        self.data = data
        self.rig = rig_from_data(data, "REFERENCE_BREAKER")
        self.cache = {}

    def overrides(self, k, f0):
        return {"closing_spring.stiffness": float(k), "closing_spring.free_length": free_length_for(self.rig, f0, k)}

    def __call__(self, k, f0):
        key = (round(float(k), 6), round(float(f0), 6))
        if key not in self.cache:
            d = copy.deepcopy(self.data)
            d["closing_spring"].update({"stiffness": float(k), "free_length": free_length_for(self.rig, f0, k)})
            try:
                self.cache[key] = closing_design(rig_from_data(d, "REFERENCE_BREAKER"))
            except Exception as e:  # noqa: BLE001 -- an infeasible design (e.g. an uncharged spring) is a point too
                self.cache[key] = {"error": str(e)}
        return self.cache[key]


def violation(r):
    """Sum of relative constraint violations (0: feasible); a closing that does not close: 1."""
    if "error" in r or r.get("touch_speed_m_s") is None or r.get("closing_time_s") is None:
        return 1.0
    v = sum(max(0.0, (r[c] - lim) / lim) for c, lim in LIMITS.items())
    return v + max(0.0, (MIN_PULL_FRACTION * r["preload_N"] - r["min_spring_force_N"]) / r["preload_N"])


def speed(r):
    v = r.get("touch_speed_m_s")
    return float("nan") if v is None else v


def preload_for_target(model, k, f_guess, xtol, maxiter):
    """F0 giving the target touch speed at stiffness k (secant on the model), or None."""
    def g(f):
        return speed(model(k, f)) - TARGET_TOUCH_SPEED

    try:
        sol = root_scalar(g, x0=f_guess, x1=f_guess * 1.03, method="secant", xtol=xtol, maxiter=maxiter)
    except (ValueError, RuntimeError, ZeroDivisionError):
        return None
    return float(sol.root) if np.isfinite(sol.root) and sol.root > 0 else None


def binding(opt, k0):
    """Which limit holds the optimum where it is (within 5 % of it), in words."""
    if opt is None:
        return []
    out = []
    for c, lim in LIMITS.items():
        if opt.get(c) is not None and opt[c] > 0.95 * lim:
            out.append(f"{c} at its limit")
    if opt.get("min_spring_force_N") is not None and opt["min_spring_force_N"] < 1.05 * MIN_PULL_FRACTION * opt["preload_N"]:
        out.append("the springs' smallest pull at the slack-spring margin")
    for end, name in ((K_RANGE[0], "lower"), (K_RANGE[1], "upper")):
        if abs(opt["stiffness_N_m"] / k0 - end) < 0.01:
            out.append(f"the stiffness at the {name} end of the searched range")
    return out


def summary_ref(reference, k0, f00, e0):
    return {**reference, "stiffness_N_m": k0, "preload_N": f00, "stored_energy_J": e0}


def equal_speed(opt, at_target, reference):
    """The optimum against the reference stiffness at the same touch speed (stored and released
    energy, J), and how much of the gain over the reference springs at their own speed the lower
    speed alone explains (energy scales about as the speed squared)."""
    if opt is None or at_target is None:
        return None
    v_ref = reference.get("touch_speed_m_s") or float("nan")
    out = {"stored_gain_percent": 100 * (1 - opt["stored_energy_J"] / at_target["stored_energy_J"]),
           "reference_at_target_within_limits": at_target["violation"] == 0,
           "gain_at_own_speed_percent": 100 * (1 - opt["stored_energy_J"] / reference["stored_energy_J"]),
           "speed_squared_share_percent": 100 * (1 - (TARGET_TOUCH_SPEED / v_ref) ** 2)}
    if opt.get("released_to_touch_J") and at_target.get("released_to_touch_J"):
        out["released_gain_percent"] = 100 * (1 - opt["released_to_touch_J"] / at_target["released_to_touch_J"])
    return out


def comparison_text(c, evaluated=()):
    """The like-with-like statement of the optimum's gain; without an optimum, which limit the designs
    on the target speed broke (``evaluated``: the optimiser's designs with their figures)."""
    if c is None:
        on_target = [e for e in evaluated if e.get("preload_N") is not None]
        if not on_target:
            return "No design reached the target speed in the searched range.\n"
        broken = {name: min(e[name] for e in on_target if e.get(name) is not None) for name in LIMITS
                  if all(e.get(name) is not None and e[name] > LIMITS[name] for e in on_target)}
        return (f"No design within the limits: {len(on_target)} designs reached the target speed, and every one of them "
                + ("broke " + ", ".join(f"{name} <= {1e3 * LIMITS[name]:g} ms (the best: {1e3 * v:.2f} ms)"
                                        for name, v in broken.items()) if broken else "broke one limit or another")
                + ". The closing springs cannot mend it: see what sets that figure in `vcb_closing.md`.\n")
    gain, share = c["gain_at_own_speed_percent"], c["speed_squared_share_percent"]
    text = (f"Against the reference springs at their own touch speed the optimum stores {abs(gain):.0f} % "
            f"{'less' if gain >= 0 else 'more'} energy, but that compares different speeds: the "
            f"{'lower' if share >= 0 else 'higher'} target speed alone (energy about as speed squared) accounts for "
            f"{abs(share):.1f} points {'less' if share >= 0 else 'more'}. At equal touch speed "
            f"({TARGET_TOUCH_SPEED} m/s) the reference stiffness with its preload set for that speed stores "
            f"{'more' if c['stored_gain_percent'] > 0 else 'less'} than the optimum: the optimum's gain is "
            f"{c['stored_gain_percent']:+.1f} % in stored energy")
    if "released_gain_percent" in c:
        text += f" and {c['released_gain_percent']:+.1f} % in the energy released up to the first touch"
    text += "."
    if not c["reference_at_target_within_limits"]:
        text += (" The reference stiffness at that speed is outside the limits (its springs go slack before the "
                 "end of the run), so the optimum is the lowest-energy design that stays within them, not a saving "
                 "over an equal design.")
    if abs(c["stored_gain_percent"]) < 2:
        text += " At equal speed the gain is about 1 %: within the assumed margins, not a design result."
    return text + "\n"


def reading(map_curve, opt, rig, k0):
    """The trade-off in words, from the numbers."""
    c = [x for x in map_curve if x["stored_energy_J"] is not None]
    text = []
    if len(c) >= 2:
        falls = c[-1]["stored_energy_J"] < c[0]["stored_energy_J"]
        text.append(f"On the target-speed line the stored energy {'falls' if falls else 'rises'} with stiffness, from "
                    f"{c[0]['stored_energy_J']:.0f} J at {c[0]['stiffness_N_m'] / 1e3:.1f} kN/m to "
                    f"{c[-1]['stored_energy_J']:.0f} J at {c[-1]['stiffness_N_m'] / 1e3:.1f} kN/m (the preload needed "
                    f"goes from {c[0]['preload_N']:.0f} N to {c[-1]['preload_N']:.0f} N): a stiffer spring's pull falls "
                    "more over the stroke, so the same closing takes a different charged energy.")
    b = binding(opt, k0)
    if opt is not None:
        text.append("What holds the optimum where it is: " + ("; ".join(b) if b else "none of the limits (an interior "
                    "minimum of the stored energy)") + ".")
    return " ".join(text) + "\n"


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    model = Model(data)
    rig = model.rig
    s = rig.closing_spring
    k0, f00, e0 = s.stiffness, preload(rig), stored_energy(rig)

    # 1. the map (sweep, all cores)
    nk, nf = GRID_QUICK if args.quick else GRID_FULL
    ks = k0 * np.linspace(*K_RANGE, nk)
    fs = f00 * np.linspace(*F_RANGE, nf)
    runs = [model.overrides(k, f) for k in ks for f in fs]
    df = sweep(data, runs=runs, evaluate=closing_design, columns=DESIGN_COLUMNS, label=f"design map ({nk} x {nf})")
    shape = (nk, nf)
    grid = {c: df[c].to_numpy(float).reshape(shape) for c in ("touch_speed_m_s", "stored_energy_J", "min_spring_force_N",
                                                             "pole_spread_s", "bounce_duration_s", "closing_time_s")}
    grid["feasible"] = np.array([violation({**r, "touch_speed_m_s": r["touch_speed_m_s"]
                                            if np.isfinite(r["touch_speed_m_s"]) else None,
                                            "closing_time_s": r["closing_time_s"] if np.isfinite(r["closing_time_s"]) else None})
                                 == 0 if r["status"] == "ok" else False for _, r in df.iterrows()]).reshape(shape)
    for (i, j), ok in np.ndenumerate(grid["feasible"]):  # the grid points join the optimiser's memory
        r = df.iloc[i * nf + j]
        if r["status"] == "ok":
            model.cache[(round(float(ks[i]), 6), round(float(fs[j]), 6))] = {
                c: (None if not np.isfinite(r[c]) else float(r[c])) for c in DESIGN_COLUMNS}

    # trade-off from the map: for each k the F0 on the target speed (interpolated along F0)
    def f_on_target(i):
        v = grid["touch_speed_m_s"][i]
        good = np.isfinite(v)
        if good.sum() < 2 or not (np.nanmin(v) <= TARGET_TOUCH_SPEED <= np.nanmax(v)):
            return None
        order = np.argsort(v[good])
        return float(np.interp(TARGET_TOUCH_SPEED, v[good][order], fs[good][order]))

    # the springs' shortening from the charged state to their shortest over a run: pull = F0 - k * this
    ok = df[df.status == "ok"]
    shortening = float(np.median((ok["preload_N"] - ok["min_spring_force_N"]) / ok["closing_spring.stiffness"])) \
        if len(ok) else float("nan")
    map_curve = []
    for i, k in enumerate(ks):
        f = f_on_target(i)
        pull = None if f is None else f - k * shortening
        map_curve.append({"stiffness_N_m": float(k), "preload_N": f,
                          "stored_energy_J": None if f is None else s.count * f * f / (2 * k),
                          "smallest_pull_N": pull,
                          "spring_stays_taut": None if f is None else bool(pull >= MIN_PULL_FRACTION * f)})

    # 2. the optimum on the model (scipy.optimize)
    xtol = 20.0 if args.quick else 2.0  # N
    inner_iter = 3 if args.quick else 12
    guesses = [(c["stiffness_N_m"], c["preload_N"]) for c in map_curve if c["preload_N"] is not None]
    evaluated = []

    def objective(k):
        f_guess = float(np.interp(k, [g[0] for g in guesses], [g[1] for g in guesses])) if guesses else f00
        f = preload_for_target(model, k, f_guess, xtol, inner_iter)
        if f is None:
            evaluated.append({"stiffness_N_m": k, "preload_N": None, "stored_energy_J": None, "violation": 1.0})
            return 10 * e0
        r = model(k, f)
        e = s.count * f * f / (2 * k)
        v = violation(r)
        evaluated.append({"stiffness_N_m": float(k), "preload_N": f, "stored_energy_J": e, "violation": v,
                          "touch_speed_m_s": speed(r), **{name: r.get(name) for name in LIMITS}})
        return e * (1 + 10 * v)

    res = minimize_scalar(objective, bounds=(K_RANGE[0] * k0, K_RANGE[1] * k0), method="bounded",
                          options={"xatol": (0.05 if args.quick else 0.005) * k0, "maxiter": 3 if args.quick else 20})
    best = min((e for e in evaluated if e["preload_N"] is not None and e["violation"] == 0),
               key=lambda e: e["stored_energy_J"], default=None)
    opt = None
    if best is not None:
        r = model(best["stiffness_N_m"], best["preload_N"])
        opt = {**{c: r.get(c) for c in DESIGN_COLUMNS}, **best,
               "free_length_m": free_length_for(rig, best["preload_N"], best["stiffness_N_m"]),
               "energy_saved_vs_reference_percent": 100 * (1 - best["stored_energy_J"] / e0)}
    reference = model(k0, f00)
    # like with like: the reference stiffness brought to the target touch speed by its preload alone
    f_ref = preload_for_target(model, k0, f00 * (TARGET_TOUCH_SPEED / max(speed(reference), 1e-9)), xtol, inner_iter)
    at_target = None
    if f_ref is not None:
        r = model(k0, f_ref)
        at_target = {**{c: r.get(c) for c in DESIGN_COLUMNS}, "stiffness_N_m": k0, "preload_N": f_ref,
                     "stored_energy_J": s.count * f_ref * f_ref / (2 * k0), "violation": violation(r)}

    # figure
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5.4))
    K, F = np.meshgrid(ks / 1e3, fs / 1e3, indexing="ij")
    v = grid["touch_speed_m_s"]
    if np.isfinite(v).sum() >= 4:
        cf = ax1.contourf(K, F, np.where(np.isfinite(v), v, np.nanmin(v)), levels=12, cmap="viridis")
        fig.colorbar(cf, ax=ax1, label="touch speed (m/s)")
        ax1.contour(K, F, np.where(np.isfinite(v), v, np.nanmin(v)), levels=[TARGET_TOUCH_SPEED], colors="w",
                    linewidths=2)
    ce = ax1.contour(K, F, grid["stored_energy_J"], levels=8, colors="0.85", linewidths=0.7, linestyles="--")
    ax1.clabel(ce, fmt="%.0f J", fontsize=7)
    bad = ~grid["feasible"]
    ax1.plot(K[bad], F[bad], "rx", ms=6, label="out of limits (spread, bounce, slack spring) or no closing")
    ax1.plot(K[~bad], F[~bad], "w.", ms=4)
    ax1.plot(k0 / 1e3, f00 / 1e3, "k*", ms=12, label="reference springs")
    if opt:
        ax1.plot(opt["stiffness_N_m"] / 1e3, opt["preload_N"] / 1e3, "r*", ms=14, label="optimum")
    ax1.set_xlabel("closing-spring stiffness k (kN/m, each)")
    ax1.set_ylabel("preload F0 (kN, each)")
    ax1.set_title(f"touch speed; white line: target {TARGET_TOUCH_SPEED} m/s; dashed: stored energy", fontsize=9)
    ax1.legend(fontsize=7, loc="upper left")
    mc = [c for c in map_curve if c["preload_N"] is not None]
    ax2.plot([c["stiffness_N_m"] / 1e3 for c in mc], [c["stored_energy_J"] for c in mc], "-", color="0.5")
    ax2.plot([c["stiffness_N_m"] / 1e3 for c in mc if c["spring_stays_taut"]],
             [c["stored_energy_J"] for c in mc if c["spring_stays_taut"]], "o", color="0.5",
             label="on the target speed, from the map (interpolated)")
    ax2.plot([c["stiffness_N_m"] / 1e3 for c in mc if not c["spring_stays_taut"]],
             [c["stored_energy_J"] for c in mc if not c["spring_stays_taut"]], "o", mfc="none", color="0.5",
             label=f"same, springs below {100 * MIN_PULL_FRACTION:.0f} % pull (slack)")
    ev = sorted((e for e in evaluated if e["preload_N"] is not None), key=lambda e: e["stiffness_N_m"])
    ax2.plot([e["stiffness_N_m"] / 1e3 for e in ev if e["violation"] == 0],
             [e["stored_energy_J"] for e in ev if e["violation"] == 0], "bs", label="model, within limits")
    ax2.plot([e["stiffness_N_m"] / 1e3 for e in ev if e["violation"] > 0],
             [e["stored_energy_J"] for e in ev if e["violation"] > 0], "rx", label="model, out of limits")
    if opt:
        ax2.plot(opt["stiffness_N_m"] / 1e3, opt["stored_energy_J"], "r*", ms=14, label="optimum")
    ax2.axhline(e0, color="k", ls=":", label=f"reference springs ({e0:.0f} J, {speed(reference):.2f} m/s)")
    ax2.set_xlabel("closing-spring stiffness k (kN/m, each)")
    ax2.set_ylabel("stored energy, all closing springs (J)")
    ax2.set_title(f"trade-off: energy needed for {TARGET_TOUCH_SPEED} m/s against stiffness", fontsize=9)
    ax2.legend(fontsize=7)
    save(fig, out / "design_optimum.png")

    summary = {"target_touch_speed_m_s": TARGET_TOUCH_SPEED, "limits": {**LIMITS, "min_pull_fraction": MIN_PULL_FRACTION},
               "assumptions": "target = middle of the assumed 1.0-1.3 m/s window; limits as in design_tolerance.py; "
                              "the springs must keep MIN_PULL_FRACTION of their preload during the run",
               "reference": {**{c: reference.get(c) for c in DESIGN_COLUMNS},
                             "stiffness_N_m": k0, "preload_N": f00, "stored_energy_J": e0},
               "grid": {"stiffness_N_m": ks.tolist(), "preload_N": fs.tolist(),
                        **{c: np.where(np.isfinite(g), g, None).tolist() if g.dtype != bool else g.tolist()
                           for c, g in grid.items()}},
               "trade_off_from_map": map_curve, "optimiser_evaluations": evaluated,
               "optimiser": {"method": "scipy.optimize.minimize_scalar (bounded Brent) over k; root_scalar (secant) "
                                       "for F0 on the target speed; violations penalised",
                             "closings_run_by_the_optimiser": len(model.cache) - int((df.status == "ok").sum()),
                             "message": str(getattr(res, "message", ""))},
               "reference_at_target_speed": at_target, "equal_speed_comparison": equal_speed(opt, at_target, summary_ref(
                   reference, k0, f00, e0)),
               "optimum": opt, "binding": binding(opt, k0), "quick": bool(args.quick)}
    write_json(out / "design_optimum.json", json_ready(summary))

    md = ["# The least stored energy for a target touch speed\n",
          f"Target touch speed {TARGET_TOUCH_SPEED} m/s (middle of the assumed 1.0-1.3 m/s window); limits (assumed): pole "
          f"spread <= {1e3 * LIMITS['pole_spread_s']:g} ms, bounce <= {1e3 * LIMITS['bounce_duration_s']:g} ms, the "
          f"springs keep at least {100 * MIN_PULL_FRACTION:.0f} % of their preload during the run. Variables: each "
          "closing spring's stiffness and preload (free length = charged length - preload / stiffness)."
          + (" **Quick mode: coarse map, loose tolerances.**" if args.quick else "") + "\n",
          markdown_table(["design", "stiffness (kN/m)", "preload (N)", "stored energy (J)", "released to touch (J)",
                          "touch speed (m/s)", "closing time (ms)", "pole spread (ms)", "bounce (ms)", "smallest pull (N)"],
                         [[name, f"{d['stiffness_N_m'] / 1e3:.2f}", f"{d['preload_N']:.0f}", f"{d['stored_energy_J']:.0f}",
                           f"{d['released_to_touch_J']:.0f}" if d.get("released_to_touch_J") is not None else "-",
                           f"{d['touch_speed_m_s']:.3f}" if d.get("touch_speed_m_s") is not None else "-",
                           f"{1e3 * d['closing_time_s']:.2f}" if d.get("closing_time_s") is not None else "-",
                           f"{1e3 * d['pole_spread_s']:.3f}" if d.get("pole_spread_s") is not None else "-",
                           f"{1e3 * d['bounce_duration_s']:.2f}" if d.get("bounce_duration_s") is not None else "-",
                           f"{d['min_spring_force_N']:.0f}" if d.get("min_spring_force_N") is not None else "-"]
                          for name, d in (("reference springs (their own touch speed)", summary["reference"]),
                                          ("reference stiffness, preload for the target speed", at_target),
                                          ("optimum", opt)) if d]),
          "\n" + comparison_text(summary["equal_speed_comparison"], evaluated),
          "\n## Trade-off (`design_optimum.png`)\n",
          "Stored energy on the target-speed line against stiffness (from the map; right panel):\n",
          markdown_table(["stiffness (kN/m)", "preload on target (N)", "stored energy (J)", "smallest pull (N)"],
                         [[f"{c['stiffness_N_m'] / 1e3:.2f}", "-" if c["preload_N"] is None else f"{c['preload_N']:.0f}",
                           "-" if c["stored_energy_J"] is None else f"{c['stored_energy_J']:.0f}",
                           "-" if c["smallest_pull_N"] is None else f"{c['smallest_pull_N']:.0f}"
                           + ("" if c["spring_stays_taut"] in (None, True) else " (slack)")] for c in map_curve]),
          "\n" + reading(map_curve, opt, rig, k0)
          + (" Quick mode: the search stops after a few steps, so this optimum is rough.\n" if args.quick else "")]
    (out / "design_optimum.md").write_text("\n".join(md))
    print("\n".join(md))


if __name__ == "__main__":
    main()

"""The closing spring with the least stored energy that still closes at a target zone speed,
with every pole's zone speed, the pole spread and the spring's own pull within limits; then the
optimum and the reference stiffness at the same speed checked for bounce across gap patterns and
restitutions, and their energy gap across the viscous friction's range.

Design variables: each closing spring's stiffness k and its charged pull (preload) F0, set
through the free length (L_free = L_charged - F0 / k). Stored energy: count F0^2 / (2 k). A
grid over (k, F0) through the sweep (all cores) maps the zone speed and the constraints; then
scipy.optimize runs the model itself: for each k a secant search finds the F0 that gives the
target zone speed (the poles' mean over the analyser's zone), and a bounded Brent search over k
minimises the stored energy, constraint violations penalised. Limits (assumptions, as in
studies/design_tolerance.py): every pole's zone speed within the reference's window, pole spread <= 2 ms, and
the springs' smallest pull during the run at least MIN_PULL_FRACTION of the preload (a tension
spring must stay taut), and the cam must reach its holding latch after the touch (a kinetic margin
above 0: a cam that stops short runs back and the contacts reopen); every closing runs to
parameters.BREAKER_REST_T_END so that it does. The target is the middle of the reference breaker's
closing-speed window (parameters.REFERENCE_LIMITS). The bounce is not a constraint: it is decided
by the contacts' restitution and the poles' gap pattern, not by the closing spring
(design_sensitivity.md), so both designs' bounce is reported over parameters.GAP_PATTERNS at
restitutions 0.5, 0.8 and 0.9 instead.
Writes design_optimum.png and design_optimum.{json,md}.
"""
import copy
from pathlib import Path

import numpy as np
from _common import markdown_table, parse_args, write_json
from scipy.optimize import minimize_scalar, root_scalar

from vcbmodel import parameters as P
from vcbmodel.analysis.design import (DESIGN_COLUMNS, closing_design, free_length_for, json_ready, preload,
                                      stored_energy, with_viscous_shaft)
from vcbmodel.analysis.sweep import sweep
from vcbmodel.app.plots import plt, save
from vcbmodel.experiments.loading import rig_from_data

#: m/s, every pole: the reference breaker's closing-speed limit (parameters.REFERENCE_LIMITS, assumed)
ZONE_WINDOW = (P.REFERENCE_LIMITS["closing_speed"]["min"], P.REFERENCE_LIMITS["closing_speed"]["max"])
TARGET_ZONE_SPEED = 0.5 * (ZONE_WINDOW[0] + ZONE_WINDOW[1])  # m/s: the window's middle
SPEED = "closing_speed_m_s"  # the poles' mean closing speed over the analyser's zone
LIMITS = {"pole_spread_s": 1e-3 * P.REFERENCE_LIMITS["pole_spread"]["max"]}  # s, assumed (parameters.REFERENCE_LIMITS)
BOUNCE_LIMIT = 1e-3 * P.REFERENCE_LIMITS["bounce_duration"]["max"]  # s, assumed; reported, not a constraint
RESTITUTIONS_FULL, RESTITUTIONS_QUICK = (0.5, 0.8, 0.9), (0.8,)
MIN_PULL_FRACTION = 0.1  # the springs' smallest pull during the run / preload: an assumed margin
#: %: an equal-speed gain under this is not claimed as a design result: it is of the order of what the
#: assumed limits (the slack-spring margin, the window) and the secant's tolerance on the preload move
EQUAL_SPEED_RESOLUTION_PERCENT = 2.0
K_RANGE = (0.6, 1.4)  # x the reference stiffness
F_RANGE = (0.5, 1.3)  # x the reference preload
GRID_FULL, GRID_QUICK = (7, 9), (3, 4)
#: Each closing runs until the cam rests on its holding latch, so that whether it latches is known.
T_END = P.BREAKER_REST_T_END


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
                self.cache[key] = closing_design(rig_from_data(d, "REFERENCE_BREAKER"), t_end=T_END)
            except Exception as e:  # noqa: BLE001 -- an infeasible design (e.g. an uncharged spring) is a point too
                self.cache[key] = {"error": str(e)}
        return self.cache[key]


def violation(r):
    """Sum of relative constraint violations (0: feasible); a closing that does not close, or whose cam
    does not reach its latch: 1."""
    if "error" in r or r.get(SPEED) is None or r.get("closing_time_s") is None or r.get("zone_speed_min_m_s") is None:
        return 1.0
    if r.get("latched") is not None and not r["latched"]:
        return 1.0
    v = sum(max(0.0, (r[c] - lim) / lim) for c, lim in LIMITS.items())
    lo, hi = ZONE_WINDOW
    v += max(0.0, (lo - r["zone_speed_min_m_s"]) / lo) + max(0.0, (r["zone_speed_max_m_s"] - hi) / hi)
    return v + max(0.0, (MIN_PULL_FRACTION * r["preload_N"] - r["min_spring_force_N"]) / r["preload_N"])


def limit_name(column):
    """A figure's column (``pole_spread_s``) as the page names it (``pole spread``)."""
    return column.removesuffix("_s").replace("_", " ")


def broken_limits(r):
    """The limits a closing breaks, in words (empty: within them all, or not known)."""
    if "error" in r or r.get(SPEED) is None or r.get("zone_speed_min_m_s") is None:
        return ["no closing"]
    out = [f"{limit_name(c)} over {1e3 * lim:g} ms" for c, lim in LIMITS.items() if r.get(c) is not None and r[c] > lim]
    if r["zone_speed_min_m_s"] < ZONE_WINDOW[0] or r["zone_speed_max_m_s"] > ZONE_WINDOW[1]:
        out.append("a pole's zone speed outside the window")
    if r.get("min_spring_force_N") is not None and r["min_spring_force_N"] < MIN_PULL_FRACTION * r["preload_N"]:
        out.append(f"its springs' pull below {100 * MIN_PULL_FRACTION:.0f} % of the preload (slack) during the run")
    if r.get("latched") is not None and not r["latched"]:
        out.append("its cam short of the latch")
    return out


def margin_text(r):
    """A design's kinetic margin after the touch for the table: J, 'not latched', or '-' (not known)."""
    if r.get("kinetic_margin_J") is not None and np.isfinite(r["kinetic_margin_J"]):
        return f"{r['kinetic_margin_J']:.1f} of {r['kinetic_at_touch_J']:.0f}"
    return "not latched" if r.get("latched") is not None and not r["latched"] else "-"


def speed(r):
    v = r.get(SPEED)
    return float("nan") if v is None else v


def preload_for_target(model, k, f_guess, xtol, maxiter):
    """F0 giving the target zone speed at stiffness k (secant on the model), or None."""
    def g(f):
        return speed(model(k, f)) - TARGET_ZONE_SPEED

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
    if opt.get("zone_speed_max_m_s") is not None and opt["zone_speed_max_m_s"] > 0.99 * ZONE_WINDOW[1]:
        out.append("the fastest pole's zone speed at the window's top")
    if opt.get("zone_speed_min_m_s") is not None and opt["zone_speed_min_m_s"] < 1.01 * ZONE_WINDOW[0]:
        out.append("the slowest pole's zone speed at the window's bottom")
    if opt.get("min_spring_force_N") is not None and opt["min_spring_force_N"] < 1.05 * MIN_PULL_FRACTION * opt["preload_N"]:
        out.append("the springs' smallest pull at the slack-spring margin")
    for end, name in ((K_RANGE[0], "lower"), (K_RANGE[1], "upper")):
        if abs(opt["stiffness_N_m"] / k0 - end) < 0.01:
            out.append(f"the stiffness at the {name} end of the searched range")
    return out


def summary_ref(reference, k0, f00, e0):
    return {**reference, "stiffness_N_m": k0, "preload_N": f00, "stored_energy_J": e0}


def equal_speed(opt, at_target, reference):
    """The optimum against the reference stiffness at the same zone speed (stored and released
    energy, J), and how much of the gain over the reference springs at their own speed the lower
    speed alone explains (energy scales about as the speed squared)."""
    if opt is None or at_target is None:
        return None
    v_ref = reference.get(SPEED) or float("nan")
    out = {"stored_gain_percent": 100 * (1 - opt["stored_energy_J"] / at_target["stored_energy_J"]),
           "reference_at_target_within_limits": at_target["violation"] == 0,
           "reference_at_target_breaks": broken_limits(at_target),
           "gain_at_own_speed_percent": 100 * (1 - opt["stored_energy_J"] / reference["stored_energy_J"]),
           "speed_squared_share_percent": 100 * (1 - (TARGET_ZONE_SPEED / v_ref) ** 2)}
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
                + ("broke " + ", ".join(f"{limit_name(name)} <= {1e3 * LIMITS[name]:g} ms (the best: {1e3 * v:.2f} ms)"
                                        for name, v in broken.items()) if broken else "broke one limit or another")
                + ". The closing springs cannot mend it: see what sets that figure in `vcb_closing.md`.\n")
    gain, share = c["gain_at_own_speed_percent"], c["speed_squared_share_percent"]
    text = (f"Against the reference springs at their own zone speed the optimum stores {abs(gain):.0f} % "
            f"{'less' if gain >= 0 else 'more'} energy, but that compares different speeds: the "
            f"{'lower' if share >= 0 else 'higher'} target speed alone (energy about as speed squared) accounts for "
            f"{abs(share):.1f} points {'less' if share >= 0 else 'more'}. At equal zone speed "
            f"({TARGET_ZONE_SPEED} m/s) the reference stiffness with its preload set for that speed stores "
            f"{'more' if c['stored_gain_percent'] > 0 else 'less'} than the optimum: the optimum's gain is "
            f"{c['stored_gain_percent']:+.1f} % in stored energy")
    if "released_gain_percent" in c:
        text += f" and {c['released_gain_percent']:+.1f} % in the energy released up to the first touch"
    text += "."
    if not c["reference_at_target_within_limits"]:
        text += (" The reference stiffness at that speed is outside the limits ("
                 + (", ".join(c["reference_at_target_breaks"]) or "a limit") + "), so the optimum is the lowest-energy "
                 "design that stays within them, not a saving over an equal design.")
    gain = c["stored_gain_percent"]
    if abs(gain) < EQUAL_SPEED_RESOLUTION_PERCENT:  # a loss is not printed as a gain of its size
        said = f"the gain is {gain:.1f} %" if gain >= 0 else f"the optimum stores {-gain:.1f} % more than the reference"
        text += (f" At equal speed {said}, under {EQUAL_SPEED_RESOLUTION_PERCENT:g} %: within the assumed margins, "
                 "not a design result.")
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


def bounce_across(designs, rig, quick):
    """The worst pole's bounce (s, count) of each design ({name: (k, F0)}) for every gap pattern and
    restitution (parameters.GAP_PATTERNS; quick: two patterns and one restitution), through the sweep."""
    patterns = list(P.GAP_PATTERNS)[:2] if quick else list(P.GAP_PATTERNS)
    restitutions = RESTITUTIONS_QUICK if quick else RESTITUTIONS_FULL
    keys = [(name, p, e) for name in designs for p in patterns for e in restitutions]
    runs = [{"closing_spring.stiffness": designs[name][0],
             "closing_spring.free_length": free_length_for(rig, designs[name][1], designs[name][0]),
             "breaker.contact.restitution": e, **{f"breaker.poles.gap_offsets.{i}": v for i, v in enumerate(P.GAP_PATTERNS[p])}}
            for name, p, e in keys]
    df = sweep(P.REFERENCE_BREAKER, runs=runs, evaluate=closing_design, columns=DESIGN_COLUMNS, t_end=T_END,
               label="bounce across gap patterns")
    rows = [{"design": name, "pattern": p, "restitution": e, "bounce_s": df.iloc[i]["bounce_duration_s"],
             "bounces": df.iloc[i]["bounce_count"]} for i, (name, p, e) in enumerate(keys)]
    worst = {name: {str(e): max(r["bounce_s"] for r in rows if r["design"] == name and r["restitution"] == e)
                    for e in restitutions} for name in designs}
    return {"patterns": patterns, "restitutions": list(restitutions), "runs": rows, "worst": worst}


def gain_across_viscous(data, k_opt, k0, quick, xtol, inner_iter):
    """The optimum's stored-energy gain over the reference stiffness at equal zone speed, each design's
    preload found again on the target speed with the shaft's viscous friction at the two ends of the
    bearing estimate (parameters.VISCOUS_BEARING_ESTIMATE)."""
    out = {}
    for cv in P.VISCOUS_BEARING_ESTIMATE:
        d = with_viscous_shaft(data)
        d["friction"]["viscous"] = cv
        m = Model(d)
        count, f0 = m.rig.closing_spring.count, preload(m.rig)
        energies = {}
        for name, k in (("optimum", k_opt), ("reference stiffness", k0)):
            f = preload_for_target(m, k, f0, xtol, inner_iter)
            energies[name] = None if f is None else count * f * f / (2 * k)
        gain = (100 * (1 - energies["optimum"] / energies["reference stiffness"])
                if None not in energies.values() else None)
        out[str(cv)] = {"stored_energy_J": energies, "gain_percent": gain}
    return out


def robustness(data, opt, at_target, quick, xtol, inner_iter):
    """The optimum against the reference stiffness at the target speed: their bounce across gap patterns
    and restitutions, and their energy gap across the viscous friction's range (None without both)."""
    if opt is None or at_target is None:
        return None
    rig = rig_from_data(data, "REFERENCE_BREAKER")
    designs = {"optimum": (opt["stiffness_N_m"], opt["preload_N"]),
               "reference stiffness at the target speed": (at_target["stiffness_N_m"], at_target["preload_N"])}
    return {"bounce": bounce_across(designs, rig, quick),
            "gain_across_viscous": gain_across_viscous(data, opt["stiffness_N_m"], at_target["stiffness_N_m"], quick,
                                                       xtol, inner_iter)}


def robustness_report(rob):
    """The robustness section of design_optimum.md."""
    if rob is None:
        return "\nNo optimum and equal-speed reference to compare across gap patterns.\n"
    b = rob["bounce"]
    md = ["\n## Across gap patterns, restitutions and the viscous friction\n",
          "Worst pole's bounce (ms, count) of each design at the target speed, for every gap pattern and restitution:\n"]
    for e in b["restitutions"]:
        rows = [[p] + [next(f"{1e3 * r['bounce_s']:.2f} ({r['bounces']:.0f})" for r in b["runs"]
                            if r["design"] == name and r["pattern"] == p and r["restitution"] == e) for name in b["worst"]]
                for p in b["patterns"]]
        md.append(f"**restitution {e:g}**\n\n" + markdown_table(["gap pattern", *b["worst"]], rows))
    over = {name: [e for e, v in w.items() if v > BOUNCE_LIMIT] for name, w in b["worst"].items()}
    names = list(b["worst"])
    gap = max(abs(r["bounce_s"] - next(q["bounce_s"] for q in b["runs"] if q["design"] == names[1]
                                       and q["pattern"] == r["pattern"] and q["restitution"] == r["restitution"]))
              for r in b["runs"] if r["design"] == names[0])
    spread = max(r["bounce_s"] for r in b["runs"]) - min(r["bounce_s"] for r in b["runs"])
    md.append(f"The two designs' bounce differs by at most {1e3 * gap:.2f} ms in any one case, against "
              f"{1e3 * spread:.2f} ms between the cases (patterns and restitutions). Over "
              f"{1e3 * BOUNCE_LIMIT:g} ms for some pattern at restitution: "
              + "; ".join(f"{name}: {', '.join(v) if v else 'none'}" for name, v in over.items()) + ".\n")
    g = rob["gain_across_viscous"]
    md.append("The optimum's stored-energy gain at equal zone speed with the shaft's viscous friction at the bearing "
              "estimate's ends: " + ", ".join(f"Cv {cv} N m s/rad: " + ("-" if v["gain_percent"] is None else
                                                                         f"{v['gain_percent']:+.1f} %")
                                               for cv, v in g.items()) + ".\n")
    return "\n".join(md)


def tolerances(quick):
    """(xtol (N), iterations) of the secant search for the preload on the target speed."""
    return (20.0, 3) if quick else (2.0, 12)


def design_map(model, k0, f00, quick):
    """The (k, F0) grid through the sweep (all cores): (ks, fs, the sweep's table, {column: grid} with
    the feasibility); the grid's closings join the optimiser's memory."""
    nk, nf = GRID_QUICK if quick else GRID_FULL
    ks = k0 * np.linspace(*K_RANGE, nk)
    fs = f00 * np.linspace(*F_RANGE, nf)
    runs = [model.overrides(k, f) for k in ks for f in fs]
    df = sweep(model.data, runs=runs, evaluate=closing_design, columns=DESIGN_COLUMNS, t_end=T_END,
               label=f"design map ({nk} x {nf})")
    shape = (nk, nf)
    grid = {c: df[c].to_numpy(float).reshape(shape) for c in (SPEED, "stored_energy_J", "min_spring_force_N",
                                                             "pole_spread_s", "bounce_duration_s", "closing_time_s")}
    grid["feasible"] = np.array([violation({k: (None if isinstance(v, float) and not np.isfinite(v) else v)
                                            for k, v in r.items()}) == 0 if r["status"] == "ok" else False
                                 for _, r in df.iterrows()]).reshape(shape)
    for (i, j), ok in np.ndenumerate(grid["feasible"]):  # the grid points join the optimiser's memory
        r = df.iloc[i * nf + j]
        if r["status"] == "ok":
            model.cache[(round(float(ks[i]), 6), round(float(fs[j]), 6))] = {
                c: (None if not np.isfinite(r[c]) else float(r[c])) for c in DESIGN_COLUMNS}
    return ks, fs, df, grid


def f_on_target(grid, fs, i):
    """The preload on the target speed at the map's i-th stiffness (interpolated along F0), or None."""
    v = grid[SPEED][i]
    good = np.isfinite(v)
    if good.sum() < 2 or not (np.nanmin(v) <= TARGET_ZONE_SPEED <= np.nanmax(v)):
        return None
    order = np.argsort(v[good])
    return float(np.interp(TARGET_ZONE_SPEED, v[good][order], fs[good][order]))


def trade_off(df, grid, ks, fs, count):
    """The trade-off from the map: for each k the F0 on the target speed, its stored energy (``count``
    springs) and the springs' smallest pull (F0 - k x the springs' median shortening over a run)."""
    ok = df[df.status == "ok"]
    shortening = float(np.median((ok["preload_N"] - ok["min_spring_force_N"]) / ok["closing_spring.stiffness"])) \
        if len(ok) else float("nan")
    map_curve = []
    for i, k in enumerate(ks):
        f = f_on_target(grid, fs, i)
        pull = None if f is None else f - k * shortening
        map_curve.append({"stiffness_N_m": float(k), "preload_N": f,
                          "stored_energy_J": None if f is None else count * f * f / (2 * k),
                          "smallest_pull_N": pull,
                          "spring_stays_taut": None if f is None else bool(pull >= MIN_PULL_FRACTION * f)})
    return map_curve


def optimise(model, map_curve, k0, f00, e0, quick):
    """The optimum on the model (scipy.optimize): a bounded Brent search over k, the preload on the
    target speed by secant at each k, violations penalised. (the optimum or None, every evaluated
    design, scipy's result)."""
    xtol, inner_iter = tolerances(quick)
    count = model.rig.closing_spring.count
    guesses = [(c["stiffness_N_m"], c["preload_N"]) for c in map_curve if c["preload_N"] is not None]
    evaluated = []

    def objective(k):
        f_guess = float(np.interp(k, [g[0] for g in guesses], [g[1] for g in guesses])) if guesses else f00
        f = preload_for_target(model, k, f_guess, xtol, inner_iter)
        if f is None:
            evaluated.append({"stiffness_N_m": k, "preload_N": None, "stored_energy_J": None, "violation": 1.0})
            return 10 * e0
        r = model(k, f)
        e = count * f * f / (2 * k)
        v = violation(r)
        evaluated.append({"stiffness_N_m": float(k), "preload_N": f, "stored_energy_J": e, "violation": v,
                          SPEED: speed(r), **{name: r.get(name) for name in LIMITS}})
        return e * (1 + 10 * v)

    res = minimize_scalar(objective, bounds=(K_RANGE[0] * k0, K_RANGE[1] * k0), method="bounded",
                          options={"xatol": (0.05 if quick else 0.005) * k0, "maxiter": 3 if quick else 20})
    best = min((e for e in evaluated if e["preload_N"] is not None and e["violation"] == 0),
               key=lambda e: e["stored_energy_J"], default=None)
    opt = None
    if best is not None:
        r = model(best["stiffness_N_m"], best["preload_N"])
        opt = {**{c: r.get(c) for c in DESIGN_COLUMNS}, **best,
               "free_length_m": free_length_for(model.rig, best["preload_N"], best["stiffness_N_m"]),
               "energy_saved_vs_reference_percent": 100 * (1 - best["stored_energy_J"] / e0)}
    return opt, evaluated, res


def reference_at_target(model, reference, k0, f00, quick):
    """Like with like: the reference stiffness brought to the target zone speed by its preload alone,
    or None."""
    xtol, inner_iter = tolerances(quick)
    f_ref = preload_for_target(model, k0, f00 * (TARGET_ZONE_SPEED / max(speed(reference), 1e-9)), xtol, inner_iter)
    if f_ref is None:
        return None
    r = model(k0, f_ref)
    return {**{c: r.get(c) for c in DESIGN_COLUMNS}, "stiffness_N_m": k0, "preload_N": f_ref,
            "stored_energy_J": model.rig.closing_spring.count * f_ref * f_ref / (2 * k0), "violation": violation(r)}


def plot_map(ax1, fig, ks, fs, grid, opt, k0, f00):
    """The left panel: the zone speed over (k, F0), the target line, the stored energy, the points."""
    K, F = np.meshgrid(ks / 1e3, fs / 1e3, indexing="ij")
    v = grid[SPEED]
    if np.isfinite(v).sum() >= 4:
        cf = ax1.contourf(K, F, np.where(np.isfinite(v), v, np.nanmin(v)), levels=12, cmap="viridis")
        fig.colorbar(cf, ax=ax1, label="zone speed, mean of the poles (m/s)")
        ax1.contour(K, F, np.where(np.isfinite(v), v, np.nanmin(v)), levels=[TARGET_ZONE_SPEED], colors="w",
                    linewidths=2)
    ce = ax1.contour(K, F, grid["stored_energy_J"], levels=8, colors="0.85", linewidths=0.7, linestyles="--")
    ax1.clabel(ce, fmt="%.0f J", fontsize=7)
    bad = ~grid["feasible"]
    ax1.plot(K[bad], F[bad], "rx", ms=6, label="out of limits (zone speed, spread, slack spring) or no closing")
    ax1.plot(K[~bad], F[~bad], "w.", ms=4)
    ax1.plot(k0 / 1e3, f00 / 1e3, "k*", ms=12, label="reference springs")
    if opt:
        ax1.plot(opt["stiffness_N_m"] / 1e3, opt["preload_N"] / 1e3, "r*", ms=14, label="optimum")
    ax1.set_xlabel("closing-spring stiffness k (kN/m, each)")
    ax1.set_ylabel("preload F0 (kN, each)")
    ax1.set_title(f"zone speed; white line: target {TARGET_ZONE_SPEED} m/s; dashed: stored energy", fontsize=9)
    ax1.legend(fontsize=7, loc="upper left")


def plot_trade_off(ax2, map_curve, evaluated, opt, e0, reference):
    """The right panel: the stored energy on the target-speed line against the stiffness."""
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
    ax2.set_title(f"trade-off: energy needed for {TARGET_ZONE_SPEED} m/s against stiffness", fontsize=9)
    ax2.legend(fontsize=7)


def figure(path, ks, fs, grid, map_curve, evaluated, opt, reference, k0, f00, e0):
    """design_optimum.png: the map and the trade-off."""
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(13, 5.4))
    plot_map(ax1, fig, ks, fs, grid, opt, k0, f00)
    plot_trade_off(ax2, map_curve, evaluated, opt, e0, reference)
    save(fig, path)


def design_row(name, d):
    """One design's row of the page's first table."""
    return [name, f"{d['stiffness_N_m'] / 1e3:.2f}", f"{d['preload_N']:.0f}", f"{d['stored_energy_J']:.0f}",
            f"{d['released_to_touch_J']:.0f}" if d.get("released_to_touch_J") is not None else "-",
            f"{d[SPEED]:.3f} ({d['zone_speed_min_m_s']:.3f}-{d['zone_speed_max_m_s']:.3f})"
            if d.get(SPEED) is not None and d.get("zone_speed_min_m_s") is not None else "-",
            f"{1e3 * d['closing_time_s']:.2f}" if d.get("closing_time_s") is not None else "-",
            f"{1e3 * d['pole_spread_s']:.3f}" if d.get("pole_spread_s") is not None else "-",
            f"{1e3 * d['bounce_duration_s']:.2f}" if d.get("bounce_duration_s") is not None else "-",
            f"{d['min_spring_force_N']:.0f}" if d.get("min_spring_force_N") is not None else "-",
            margin_text(d)]


def page(summary, evaluated, map_curve, rig, k0, quick):
    """design_optimum.md."""
    designs = (("reference springs (their own zone speed)", summary["reference"]),
               ("reference stiffness, preload for the target speed", summary["reference_at_target_speed"]),
               ("optimum", summary["optimum"]))
    md = ["# The least stored energy for a target zone speed\n",
          f"Target zone speed {TARGET_ZONE_SPEED} m/s (the poles' mean closing speed over the analyser's zone; the "
          f"middle of the assumed {ZONE_WINDOW[0]:g}-{ZONE_WINDOW[1]:g} m/s window); limits (assumed): every pole's zone "
          f"speed within the window, pole spread <= {1e3 * LIMITS['pole_spread_s']:g} ms, the springs keep at least "
          f"{100 * MIN_PULL_FRACTION:.0f} % of their preload during the run, the cam reaches its holding latch (a "
          "kinetic margin after the touch above 0). The bounce is not a constraint: the "
          "contacts' restitution and the gap pattern decide it (below). Variables: each closing spring's stiffness and "
          "preload (free length = charged length - preload / stiffness)."
          + (" **Quick mode: coarse map, loose tolerances.**" if quick else "") + "\n",
          markdown_table(["design", "stiffness (kN/m)", "preload (N)", "stored energy (J)", "released to touch (J)",
                          "zone speed, mean (slowest-fastest pole) (m/s)", "closing time (ms)", "pole spread (ms)",
                          "bounce (ms)", "smallest pull (N)", "kinetic margin after touch (J)"],
                         [design_row(name, d) for name, d in designs if d]),
          "\n" + comparison_text(summary["equal_speed_comparison"], evaluated),
          "\n## Trade-off (`design_optimum.png`)\n",
          "Stored energy on the target-speed line against stiffness (from the map; right panel):\n",
          markdown_table(["stiffness (kN/m)", "preload on target (N)", "stored energy (J)", "smallest pull (N)"],
                         [[f"{c['stiffness_N_m'] / 1e3:.2f}", "-" if c["preload_N"] is None else f"{c['preload_N']:.0f}",
                           "-" if c["stored_energy_J"] is None else f"{c['stored_energy_J']:.0f}",
                           "-" if c["smallest_pull_N"] is None else f"{c['smallest_pull_N']:.0f}"
                           + ("" if c["spring_stays_taut"] in (None, True) else " (slack)")] for c in map_curve]),
          "\n" + reading(map_curve, summary["optimum"], rig, k0)
          + (" Quick mode: the search stops after a few steps, so this optimum is rough.\n" if quick else ""),
          robustness_report(summary["robustness"])]
    return "\n".join(md)


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    model = Model(data)
    rig = model.rig
    k0, f00, e0 = rig.closing_spring.stiffness, preload(rig), stored_energy(rig)
    ks, fs, df, grid = design_map(model, k0, f00, args.quick)
    map_curve = trade_off(df, grid, ks, fs, rig.closing_spring.count)
    opt, evaluated, res = optimise(model, map_curve, k0, f00, e0, args.quick)
    reference = model(k0, f00)
    at_target = reference_at_target(model, reference, k0, f00, args.quick)
    figure(out / "design_optimum.png", ks, fs, grid, map_curve, evaluated, opt, reference, k0, f00, e0)
    xtol, inner_iter = tolerances(args.quick)
    summary = {"target_zone_speed_m_s": TARGET_ZONE_SPEED, "limits": {**LIMITS, "min_pull_fraction": MIN_PULL_FRACTION},
               "assumptions": f"target = middle of the assumed {ZONE_WINDOW[0]:g}-{ZONE_WINDOW[1]:g} m/s window; limits as in design_tolerance.py; "
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
               "optimum": opt, "binding": binding(opt, k0), "quick": bool(args.quick),
               "robustness": robustness(data, opt, at_target, args.quick, xtol, inner_iter)}
    write_json(out / "design_optimum.json", json_ready(summary))
    md = page(summary, evaluated, map_curve, rig, k0, args.quick)
    (out / "design_optimum.md").write_text(md)
    print(md)


if __name__ == "__main__":
    main()

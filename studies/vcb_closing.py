"""The whole breaker's closing (paper section 4, Fig. 12) and its figures of merit.

The reference 12 kV / 40 kA breaker (vcbmodel/parameters.py) closes with five models: the
full model (shaft friction + lumped-2 spring, `exact` convention), without shaft friction,
with a massless spring, with the ANCF spring, and with neither. The "measurement" is
SYNTHETIC: the full model with an ANCF spring (16 elements; 8 with --quick) at the 12 kHz camera
rate plus 0.05 mm noise. Also: why the reference breaker is sized as it is (the paper's springs under
the flywheel reading against the settled one: buildable springs, an energy budget a real mechanism could
have, the `exact` chain), the opening spring and rise that keep the roller on the cam (a follower jump on
the flywheel reading's springs and cam), the cam-roller contact's law and damping choices, the independent solve
(vcbmodel/reference/breaker.py) against the Exudyn model, energy balance, step convergence,
pressure angle, the main shaft's twist between the pole levers and the pole spread it makes (rigid shaft,
reference shaft, driven at the middle pole, the first estimate's 40 mm).
Writes results/vcb_closing_fig12.png, vcb_closing_detail.png, vcb_closing_analyser.png (the full model's
closing as a breaker analyser draws it, its report in the .md), vcb_closing.{md,json} and
results/synthetic/vcb_closing.{csv,rig.json}.
"""
import copy
import math
from pathlib import Path

import numpy as np
from _common import markdown_table, parse_args, write_json

from vcbmodel import parameters as P
from vcbmodel.analysis.synthetic import synthetic_measurement, write_rig
from vcbmodel.app.closing_plot import closing_figure
from vcbmodel.app.plots import plt, save
from vcbmodel.experiments.closing_evaluation import SPLIT_TERMS, energy_balance, energy_split, figures_of_merit
from vcbmodel.experiments.closing_evaluation import main_shaft_twist as twist_of_run
from vcbmodel.experiments.loading import load_rig, rig_from_data
from vcbmodel.experiments.report import report_text
from vcbmodel.experiments.simulation import model_spec, simulate
from vcbmodel.experiments.summaries import closing_report
from vcbmodel.laws.breaker import BreakerLaws, massless_pull, pressure_angle_curve
from vcbmodel.laws.coil import spring_check
from vcbmodel.laws.contact import LINE_EXPONENT, johnson_line_approach, palmgren_line_stiffness
from vcbmodel.laws.friction import band_width
from vcbmodel.laws.mechanics import cam_pin, main_shaft_twist
from vcbmodel.records.measurement import write_measurement
from vcbmodel.reference.breaker import solve_closing
from vcbmodel.reference.breaker_closing import Closing

FRICTION = ("coulomb_friction", "stribeck")
#: m/s: the closing speeds of 12 kV vacuum breakers (parameters.py, the note on REFERENCE_LIMITS' closing
#: speed), against which the former rise's speed is read
VACUUM_CLOSING_SPEEDS = (0.6, 1.5)


def models(rig):
    full = tuple(rig.model.effects)
    no_friction = tuple(e for e in full if e not in FRICTION)
    return {  # label: (effects, spring model)
        "full model (friction + lumped-2)": (full, "lumped-2"),
        "without shaft friction": (no_friction, "lumped-2"),
        "massless spring": (tuple(e for e in full if e != "spring_mass"), "massless"),
        "ANCF spring (8 elements)": (full, "ancf"),
        "neither (massless, no friction)": (tuple(e for e in no_friction if e != "spring_mass"), "massless"),
    }


def energy_split_figure(rig, result, rest, summary, out):
    """Where the springs' energy went at the first touch and at rest (``rest``: the same closing run
    on to the cam's rest on the holding latch): a figure and table rows."""
    fom = figures_of_merit(result, rig)
    splits = {"first touch": energy_split(result, rig, fom["first_touch_s"]), "at rest": energy_split(rest, rig, rest.t[-1])}
    summary["energy_split"] = splits
    fig, ax = plt.subplots(figsize=(9, 4.8))
    names = [(key, label) for key, label in SPLIT_TERMS if any(abs(sp[key]) > 0.5 for sp in splits.values())]
    y = np.arange(len(names))
    for j, (when, sp) in enumerate(splits.items()):
        ax.barh(y + 0.4 * j - 0.2, [sp[k] for k, _ in names], height=0.38,
                label=f"{when} (t = {1e3 * sp['t_s']:.1f} ms): springs gave up {sp['released']:.0f} J")
    ax.set_yticks(y, [label for _, label in names], fontsize=8)
    ax.invert_yaxis()
    ax.set_xlabel("energy (J)")
    ax.set_title("where the closing springs' energy went (full model, reference breaker)", fontsize=10)
    ax.legend(fontsize=8)
    save(fig, out / "vcb_closing_energy_split.png")
    rows = [[label, f"{splits['first touch'][k]:.1f}", f"{splits['at rest'][k]:.1f}"] for k, label in SPLIT_TERMS]
    rows += [["released by the closing springs", f"{splits['first touch']['released']:.1f}",
              f"{splits['at rest']['released']:.1f}"],
             ["unaccounted (the balance's residual)", f"{splits['first touch']['unaccounted']:.2f}",
              f"{splits['at rest']['unaccounted']:.2f}"]]
    return rows


def energy_row(label, rig, result):
    e = energy_balance(result, rig)
    released = float(np.max(e["spring_energy_released"]))
    # each term's change since the release (the opening spring's preload energy is not the closing's work),
    # as the energy split's table counts them
    laws_end = {k: float(e[k][-1] - e[k][0]) for k in ("kinetic", "opening_spring", "wipe_and_rods", "contacts",
                                                       "dissipated")}
    return {"model": label, "spring_energy_released_max_J": released,
            "residual_max_J": float(np.max(np.abs(e["residual"]))),
            "residual_percent_of_released": 100 * float(np.max(np.abs(e["residual"]))) / released, **laws_end}


CONTACT_FIELDS = ("cam_roller_law", "roller_width", "cam_roller_damping", "cam_roller_damping_factor")


def former_breaker(preload=1200.0):
    """A breaker that jumps: the springs and cam of the flywheel reading (FORMER_REFERENCE_BREAKER),
    40-220 deg rise, 1200 N opening spring, Hertz point contact with
    Lankarani-Nikravesh damping (latch at the pin, the default)."""
    d = copy.deepcopy(P.FORMER_REFERENCE_BREAKER)
    b = d["breaker"]
    b["cam_profile"].update(rise_start=0.6981, rise_end=3.8397, return_start=5.7, return_end=6.4)
    b["opening_spring"]["preload"] = preload
    for key in CONTACT_FIELDS:
        b["contact"].pop(key)
    b["latch"] = {"release_time": 0.002}
    return d


def with_contact(d, law, damping, alpha=0.2):
    """A copy of rig dict ``d`` with the cam-roller contact law and damping law given."""
    d = copy.deepcopy(d)
    c = d["breaker"]["contact"]
    for key in CONTACT_FIELDS:
        c.pop(key, None)
    c["cam_roller_law"], c["cam_roller_damping"] = law, damping
    if law == "line":
        c["roller_width"] = 0.02
    if damping == "hunt_crossley":
        c["cam_roller_damping_factor"] = alpha
    return d


def fom_row(label, f, extra=()):
    ms = (lambda v: "-" if v is None else f"{1e3 * v:.2f}")
    zone = f.get("closing_speed_m_s")
    return [label, ms(f["closing_time_s"]), "-" if zone is None else f"{zone:.3f}", ms(f["pole_spread_s"]), f["bounce_count"],
            ms(f["bounce_duration_s"]), ms(f["wipe_m"]), ms(f["overtravel_m"]), f"{1e-3 * f['peak_cam_roller_force_N']:.1f}",
            ms(f["roller_lift_off_s"]), ms(f["roller_first_lift_off_s"]),
            f"{1e-3 * f['min_cam_roller_force_before_touch_N']:.2f}",
            "-" if f["kinetic_margin_J"] is None else f"{f['kinetic_margin_J']:.1f} of {f['kinetic_at_touch_J']:.0f}", *extra]


FOM_HEADERS = ["closing time (ms)", "closing speed over the zone (m/s)", "pole spread (ms)", "bounces", "bounce duration (ms)",
               "wipe (mm)", "overtravel (mm)", "peak cam-roller force (kN)", "roller off the cam (ms)",
               "first lift-off - first touch (ms)", "least roller force before touch (kN)",
               "kinetic margin after touch, of at touch (J)"]


def contact_choices(base, t_end):
    """Figures of merit for each cam-roller law and damping law on a breaker (rig dict ``base``),
    plus the largest dashpot force of the contact and the energy its damping dissipates."""
    rows, out = [], {}
    for law, damping, alpha in (("hertz_point", "lankarani_nikravesh", None), ("hertz_point", "hunt_crossley", 0.2),
                                ("line", "lankarani_nikravesh", None), ("line", "hunt_crossley", 0.08),
                                ("line", "hunt_crossley", 0.2), ("line", "hunt_crossley", 0.32)):
        rig = rig_from_data(with_contact(base, law, damping, alpha))
        r = simulate(rig, t_end=t_end)
        f = figures_of_merit(r, rig)
        ch = r.channels
        dashpot = ch["cam_roller_damping_force"]
        lost = float(np.trapezoid(dashpot * ch["cam_roller_penetration_rate"], r.t))
        label = f"{law}, {damping}" + (f" alpha {alpha:g} s/m" if alpha else " (floor 0.05 m/s)")
        out[label] = {"figures_of_merit": f, "dashpot_max_N": float(dashpot.max()), "dashpot_min_N": float(dashpot.min()),
                      "dissipated_J": lost}
        rows.append(fom_row(label, f, (f"{1e-3 * dashpot.max():+.2f} / {1e-3 * dashpot.min():+.2f}", f"{lost:.3f}")))
    return rows, out


def passive_stick_band(rig) -> list[float]:
    """The passive stuck state's stick band (rad/s, :func:`vcbmodel.laws.friction.band_width` at the rig's step)
    while the latch lets the cam go: the smallest and largest over the latch's release, with the shaft's
    reaction and the cam's inertia of the independent solve's rest state (:class:`Closing`)."""
    spec = model_spec(rig)
    law = spec.friction_law(rig.shaft_radius, P.BREAKER_STEP)
    closing = Closing(rig, spec)
    phi, z, _, levers = closing.rest()
    y = closing.initial_vector(phi, z, levers)
    bands = [band_width(law, math.hypot(*closing.cam_applied(t, y)[1]), closing.IA)
             for t in np.linspace(0.0, rig.breaker.latch_release_time, 21)]
    return [float(min(bands)), float(max(bands))]


def independent_agreement(rig, t_end):
    """The Exudyn model against the independent solve (vcbmodel/reference/breaker.py): literal and
    passive stick band, and what the model's first-order penetration costs."""
    spec = model_spec(rig)
    out = {}
    for sticking in ("literal", "passive"):
        a = simulate(rig, t_end=t_end, sticking=sticking)
        t = a.t[::10]
        ref = solve_closing(rig, spec, t)
        f = figures_of_merit(a, rig)
        out[sticking] = {
            "touch_time_difference_s": float(np.max(np.abs(np.array(f["per_pole"]["touch_s"]) - np.array(ref["touch_times"])))),
            "touch_speed_difference_m_s": float(np.max(np.abs(np.array(f["per_pole"]["touch_speed_m_s"])
                                                              - np.array(ref["touch_speeds"])))),
            **{f"max_{k}_difference": float(np.max(np.abs(a.channels[k][::10] - ref[k])))
               for k in ("follower_displacement", "cam_angle", "pole_1_travel", "cam_roller_force")}}
    out["passive_stick_band_rad_s"] = passive_stick_band(rig)
    first = solve_closing(rig, spec, t, distance="first_order")
    out["first_order_penetration_cost"] = {
        "follower_displacement_m": float(np.max(np.abs(first["follower_displacement"] - ref["follower_displacement"]))),
        "penetration_m": float(np.max(np.abs(first["cam_roller_penetration"] - ref["cam_roller_penetration"]))),
        "touch_time_s": float(np.max(np.abs(np.array(first["touch_times"]) - np.array(ref["touch_times"])))),
        "cam_angle_rad": float(np.max(np.abs(first["cam_angle"] - ref["cam_angle"])))}
    out["reference_touch_times_s"] = ref["touch_times"]
    out["reference_touch_speeds_m_s"] = [float(v) for v in ref["touch_speeds"]]
    return out


def breaker_budget(rig, result):
    """A breaker's energy budget and figures: stored, released to the first touch, the cam's share
    there, the spring's stress at the charged pull (laws.coil.spring_check)."""
    f = figures_of_merit(result, rig)
    split = energy_split(result, rig, f["first_touch_s"])
    pull = float(np.hypot(*rig_pull(rig)))
    check = spring_check(rig.closing_spring, pull)
    cam = split["kinetic_cam"] + split["pin_on_cam"]
    return {"figures_of_merit": f, "stored_J": stored(rig),
            "released_to_touch_J": split["released"], "cam_at_touch_J": cam, "cam_share_at_touch": cam / split["released"],
            "charged_pull_per_spring_N": pull, "shear_stress_Pa": check["shear_stress_Pa"],
            "allowable_extension_Pa": check["allowable_Pa"], "allowable_compression_Pa": check["allowable_compression_Pa"],
            "spring_mass_kg": rig.closing_spring.mass, "cam_inertia_kg_m2": rig.cam.inertia_pivot}


def rig_pull(rig):
    """Pull (N, N) of one closing spring on its pin at the start (massless springs)."""
    fx, fy = massless_pull(rig.cam, rig.closing_spring)
    return fx / rig.closing_spring.count, fy / rig.closing_spring.count


def stored(rig):
    """Energy (J) the closing springs hold at the start above their free length."""
    s = rig.closing_spring
    bx, by = cam_pin(rig.cam.initial_angle, rig.cam)
    stretch = np.hypot(bx - s.anchor[0], by - s.anchor[1]) - s.free_length
    return float(s.count * 0.5 * s.stiffness * stretch**2)


def sizing_rows(rig, result):
    """The paper's springs under the flywheel reading (FORMER_REFERENCE_BREAKER) and the reference
    breaker: figures of merit, energy budget, spring stress."""
    old_rig = rig_from_data(copy.deepcopy(P.FORMER_REFERENCE_BREAKER))
    old = breaker_budget(old_rig, simulate(old_rig, t_end=0.045))
    new = breaker_budget(rig, result)
    rows = []
    for label, b in ((f"flywheel reading ({breaker_label(old_rig)}, lumped-2 paper)", old),
                     (f"reference ({breaker_label(rig)} shaft, lumped-2 exact)", new)):
        f = b["figures_of_merit"]
        rows.append([label, f"{1e3 * f['closing_time_s']:.2f}", f"{f['closing_speed_m_s']:.3f}",
                     f"{f['zone_speed_min_m_s']:.3f}-{f['zone_speed_max_m_s']:.3f}",
                     f"{b['stored_J']:.0f}", f"{b['released_to_touch_J']:.0f}", f"{b['cam_at_touch_J']:.0f}",
                     f"{100 * b['cam_share_at_touch']:.0f}", f"{b['charged_pull_per_spring_N']:.0f}",
                     f"{b['shear_stress_Pa'] / 1e9:.2f}",
                     f"{b['allowable_extension_Pa'] / 1e9:.2f} / {b['allowable_compression_Pa'] / 1e9:.2f}"])
    return rows, {"flywheel_reading": old, "reference": new}


def breaker_label(rig):
    """'2 x 3000 N, 0.83 kg springs, 0.020 kg m^2 cam': a breaker's springs and cam, from the rig."""
    s = rig.closing_spring
    return (f"{s.count} x {round(float(np.hypot(*rig_pull(rig))), -2):.0f} N, {s.mass:.2f} kg springs, "
            f"{rig.cam.inertia_pivot:.3f} kg m^2 cam")


SIZING_HEADERS = ["breaker", "closing time (ms)", "closing speed over the zone (m/s)", "slowest-fastest pole (m/s)",
                   "springs store (J)", "released to first touch (J)", "cam shaft holds at touch (J)",
                   "cam's share (%)", "pull per spring (N)", "wire shear stress (GPa)",
                   "allowable extension / compression (GPa)"]


def end_stop_rows(rig, rest):
    """How the end stop and the holding latch bring the cam to rest (a closing run on to the rest):
    when and how fast the cam meets the stop, how far it runs in, the buffer's largest force, when
    and where the cam rests, what the follower does meanwhile."""
    b, ch, t = rig.breaker, rest.channels, rest.t
    stop, latch = b.end_stop, b.hold_latch
    th, w = ch["cam_angle"], ch["shaft_velocity"]
    pen = stop.arm * (th - stop.angle)
    hit = int(np.argmax(pen > 0))
    force = np.where(pen > 0, np.maximum(stop.stiffness * pen + stop.damping * stop.arm * w, 0.0), 0.0)
    moving = np.nonzero(np.abs(w) > 0.5)[0]
    travel = ch["follower_displacement"]
    out = {"meets_stop_s": float(t[hit]), "speed_at_lever_m_s": float(w[hit] * stop.arm),
           "kinetic_at_stop_J": float(0.5 * rig.cam.inertia_pivot * w[hit] ** 2),
           "into_stop_deg": float(np.degrees(th.max() - stop.angle)), "largest_stop_force_N": float(force.max()),
           "rests_from_s": float(t[moving[-1] + 1]) if moving.size else 0.0,
           "rest_angle_deg": float(np.degrees(th[-1])), "latch_angle_deg": float(np.degrees(latch.angle)),
           "follower_travel_range_after_stop_m": float(np.ptp(travel[hit:])), "final_travel_m": float(travel[-1])}
    rows = [["cam meets the stop", f"{1e3 * out['meets_stop_s']:.1f} ms, {out['speed_at_lever_m_s']:.2f} m/s at the lever, "
             f"{out['kinetic_at_stop_J']:.0f} J in the cam shaft"],
            ["runs into the buffer", f"{out['into_stop_deg']:.2f} deg, largest force {1e-3 * out['largest_stop_force_N']:.1f} kN"],
            ["comes to rest", f"from {1e3 * out['rests_from_s']:.1f} ms at {out['rest_angle_deg']:.2f} deg, on the holding "
             f"latch ({out['latch_angle_deg']:.0f} deg)"],
            ["follower meanwhile", f"moves {1e6 * out['follower_travel_range_after_stop_m']:.2f} um (the roller is on the "
             f"dwell); final travel {1e3 * out['final_travel_m']:.4f} mm"]]
    return rows, out


def shaft_twist(rig, result, fom):
    """The main shaft's twist between the pole levers (laws.mechanics.main_shaft_twist, shaft
    MAIN_SHAFT): from the push-rod forces before the first touch (the poles' inertia and bellows)
    and under the wipe (after the first touch, and at the end of the run), as travel at the pole
    (m) against the gap spread."""
    ms, ch, t = P.MAIN_SHAFT, result.channels, result.t
    n = rig.breaker.poles.count
    rods = np.array([ch[f"pole_{i + 1}_rod_force"] for i in range(n)])
    windows = {"before the first touch": t < fom["first_touch_s"],
               "first touch to the last pole's touch": (t >= fom["first_touch_s"]) & (t <= fom["closing_time_s"]),
               "closed (end of the run)": t >= t[-1] - 1e-9}
    out = {}
    for label, w in windows.items():
        twists = [main_shaft_twist(list(ms["lever_arm"] * rods[:, k]), ms["pole_pitch"], ms["diameter"], ms["shear_modulus"])[-1]
                  for k in np.nonzero(w)[0]]
        k = int(np.argmax(np.abs(twists)))
        twist = float(twists[k])
        out[label] = {"largest_twist_rad": twist, "travel_at_pole_m": twist * ms["lever_arm"],
                      "rod_forces_N": [float(v) for v in rods[:, np.nonzero(w)[0][k]]]}
    return out


def shaft_variants(rig_dict):
    """Rig dicts of the reference breaker with its main shaft rigid, as in parameters.py (driven at the
    first pole's side), driven at the middle pole, and as thin as first estimated (the review's 40 mm,
    the other values kept): like with like (same springs, cam, poles and total inertia of the shaft
    assembly, ``follower.inertia``)."""
    shaft = rig_dict["breaker"].get("main_shaft")
    if shaft is None:
        return {}
    middle = (rig_dict["breaker"]["poles"]["count"] + 1) // 2

    def variant(**changes):
        d = copy.deepcopy(rig_dict)
        if changes.get("rigid"):
            d["breaker"].pop("main_shaft")
        else:
            d["breaker"]["main_shaft"].update(changes)
        return d

    d_mm, first = 1e3 * shaft["diameter"], P.MAIN_SHAFT_FIRST_ESTIMATE_DIAMETER
    return {"rigid main shaft (the model before)": variant(rigid=True),
            f"{d_mm:.0f} mm shaft, driven at pole {shaft['drive_pole']} (reference)": variant(),
            f"{d_mm:.0f} mm shaft, driven at pole {middle} (middle)": variant(drive_pole=middle),
            f"{1e3 * first:.0f} mm shaft, driven at pole {shaft['drive_pole']} (the first estimate)": variant(diameter=first)}


def pole_spread_rows(rig_dict, t_end):
    """The pole spread with an elastic main shaft (rig section ``breaker.main_shaft``) against a rigid
    one: per-pole touch times and speeds, spread, and the levers' twist."""
    rows, out = [], {}
    for label, d in shaft_variants(rig_dict).items():
        rig = rig_from_data(d)
        r = simulate(rig, t_end=t_end)
        f = figures_of_merit(r, rig)
        arm = rig.breaker.follower.output_arm
        run = twist_of_run(r, rig) or {"before_touch_rad": 0.0, "largest_rad": 0.0, "end_rad": 0.0}
        tw = {"before": run["before_touch_rad"], "largest": run["largest_rad"], "end": run["end_rad"]}
        per = f["per_pole"]
        closed = [float(r.channels[f"pole_{i + 1}_rod_force"][-1]) for i in range(rig.breaker.poles.count)]
        out[label] = {"figures_of_merit": f, "largest_twist_rad": tw, "travel_at_pole_m": {k: v * arm for k, v in tw.items()},
                      "closed_rod_forces_N": closed}
        ms = (lambda v: "-" if v is None else f"{1e3 * v:.3f}")
        rows.append([label, " / ".join(ms(v) for v in per["touch_s"]), ms(f["pole_spread_s"]),
                     " / ".join("-" if v is None else f"{v:.3f}" for v in per["touch_speed_m_s"]),
                     f"{f['closing_speed_m_s']:.3f}"]
                    + [f"{1e3 * tw[k]:.2f} ({1e3 * tw[k] * arm:.2f})" for k in ("before", "largest", "end")]
                    + [" / ".join(f"{1e-3 * v:.2f}" for v in closed),
                       " / ".join(f"{1e3 * v:.2f}" for v in per["bounce_duration_s"])])
    return rows, out


def gap_text(poles) -> str:
    """The poles' gaps as the rig gives them: '11 mm + 0 / +0.3 / -0.3 mm'."""
    return (f"{1e3 * poles.contact_gap:g} mm + "
            + " / ".join("0" if o == 0 else f"{1e3 * o:+g}" for o in poles.gap_offsets) + " mm")


def gap_tolerance_text(poles) -> str:
    """The largest offset of a pole's gap from the nominal: '+-0.3 mm'."""
    return f"+-{1e3 * max(abs(o) for o in poles.gap_offsets):g} mm"


def far_poles_text(rigid, ref, drive_pole) -> str:
    """What the elastic shaft does to the poles away from the drive (1-based ``drive_pole``), said only where the
    runs show it: their bounce against the rigid shaft's, and the weakest pole's closed push-rod force."""
    far = [i for i in range(len(ref["closed_rod_forces_N"])) if i != drive_pole - 1]
    bounce = lambda run: run["figures_of_merit"]["per_pole"]["bounce_duration_s"]  # noqa: E731
    longer = [i for i in far if bounce(ref)[i] > bounce(rigid)[i]]
    ring = ("the far levers ring at the shaft's torsional modes and lengthen their poles' bounce (the last column)"
            if longer else "the far levers ring at the shaft's torsional modes without lengthening their poles' "
            "bounce (the last column)")
    weakest = int(np.argmin(ref["closed_rod_forces_N"]))
    kept, stiff = ref["closed_rod_forces_N"][weakest], rigid["closed_rod_forces_N"][weakest]
    wipe = ("the far poles keep less of their wipe" if weakest in far and kept < stiff
            else "the poles keep their wipe as on a rigid shaft" if kept >= stiff else "the drive pole keeps the least")
    return (f"{ring}, and {wipe}: closed, the push rod of pole {weakest + 1} (its contact force) carries "
            f"{1e-3 * kept:.2f} kN against {1e-3 * stiff:.2f} kN on a rigid shaft "
            f"({P.REFERENCE_LIMITS['contact_force_closed']['source']}, `parameters.py`)")


def pole_spread_sentence(spread, poles, drive_pole):
    """What the elastic main shaft does to the pole spread, in one sentence from the study's numbers
    (``poles``: the rig's, for the gap tolerance; ``drive_pole``: where the reference shaft is driven)."""
    (rigid_label, rigid), (ref_label, ref) = list(spread.items())[:2]
    a, b = rigid["figures_of_merit"], ref["figures_of_merit"]
    if a["pole_spread_s"] is None or b["pole_spread_s"] is None:
        return "Not every pole touched in one of the runs: see the table."
    order = lambda f: "-".join(str(i + 1) for i in np.argsort(f["per_pole"]["touch_s"]))  # noqa: E731
    return (f"With the reference shaft the pole spread is {1e3 * b['pole_spread_s']:.2f} ms against "
            f"{1e3 * a['pole_spread_s']:.2f} ms for a rigid one (poles touch in the order {order(b)}, rigid "
            f"{order(a)}); the closing time moves by {1e3 * (b['closing_time_s'] - a['closing_time_s']):+.2f} ms and "
            f"the closing speed by {b['closing_speed_m_s'] - a['closing_speed_m_s']:+.3f} m/s. Under the wipe the "
            f"levers twist {1e3 * ref['travel_at_pole_m']['largest']:.2f} mm apart at the pole (the gap tolerance is "
            f"{gap_tolerance_text(poles)}), {far_poles_text(rigid, ref, drive_pole)}. A real breaker's pole spread and "
            "each pole's contact force depend on its shaft's stiffness and where it is driven.")


def static_check_sentence(static, spread):
    """The static twist estimate against the elastic model's levers (the reference shaft's run)."""
    ref = list(spread.values())[1]["largest_twist_rad"]
    closed, before = abs(static["closed (end of the run)"]["largest_twist_rad"]), abs(static["before the first touch"]["largest_twist_rad"])
    return (f"Closed, the static estimate ({1e3 * closed:.2f} mrad) and the elastic model's levers at rest "
            f"({1e3 * ref['end']:.2f} mrad) differ by {100 * abs(ref['end'] - closed) / closed:.1f} % (the formula "
            "shares the model's G J / pitch reading, not its "
            f"lever dynamics). Before the touch the model's levers twist {1e3 * ref['before']:.2f} mrad "
            f"against the static {1e3 * before:.2f} mrad"
            + (": the levers' own inertia and the shaft's torsional modes (`laws.breaker.torsional_frequencies`) add "
               "to the quasi-static twist." if abs(ref["before"]) > before else
               ", less than the quasi-static twist."))


POLE_SPREAD_HEADERS = ["main shaft", "touch times, poles 1/2/3 (ms)", "pole spread (ms)", "touch speeds (m/s)",
                       "closing speed (m/s)", "twist before touch, mrad (mm at pole)",
                       "largest twist, mrad (mm)", "twist at the end, mrad (mm)", "closed push-rod forces (kN)",
                       "bounce per pole (ms)"]


def md_models(rows, truth_elements):
    return ["# The whole breaker's closing (paper section 4, Fig. 12)\n",
            "Reference breaker: `vcbmodel/parameters.py` (REFERENCE_BREAKER). The measurement is SYNTHETIC "
            f"(full model with a {truth_elements}-element ANCF spring, 12 kHz, noise 0.05 mm): a stand-in for the "
            "paper's camera record, not a test.\n",
            "## Figures of merit\n",
            markdown_table(["model", *FOM_HEADERS, "rms vs measurement (mm)"], rows),
            "\nClosing time: latch release to the last pole's touch. Closing speed: each pole's mean speed over the "
            "analyser's zone (breaker.speed_zone, the last 4 mm before its touch), the poles' mean (each pole's, and its "
            "speed at the touch instant, in the analyser's report at the end). Wipe: follower travel after the first "
            "touch, to its final position; overtravel: its largest travel beyond "
            "the final position (analysers' definitions; without an end stop in the rig nothing stops the cam, so it is "
            "the cam's geometry). Roller off the cam: total time with no "
            "cam-roller force; first lift-off - first touch: when the roller first leaves the cam, negative before the "
            "contacts touch (a follower jump), '-' if it never leaves; least roller force before touch: the margin "
            "against a jump.\n"]


def md_energy_split(split_rows, stop_rows):
    return ["## Where the closing springs' energy goes (`vcb_closing_energy_split.png`)\n",
            markdown_table(["where", "at the first touch (J)", "at rest (J)"], split_rows),
            "\nAt the first touch the cam shaft still holds most of what the springs gave up, as in a real spring "
            "mechanism, whose closing springs are sized with a margin and whose cam hands its remaining energy to a "
            "closing damper or stop at the end of the stroke. Here that is the end stop (a buffer at 250 deg, past "
            "the rise's end) and the holding latch (248 deg) of `parameters.py`; 'at rest' is the same closing run "
            f"on to {1e3 * P.BREAKER_REST_T_END:.0f} ms, with the cam at rest on the latch.\n",
            "## The end stop and the holding latch\n",
            markdown_table(["", "the reference breaker"], stop_rows),
            "\nThe stop sits on the dwell, so the contacts keep their full stroke while the cam is stopped: the "
            "follower's overtravel is the wipe the profile gives, and the poles' bounce comes from their own "
            "dynamics; the cam's own overtravel into the buffer and its rebound onto the latch come from the stop's "
            "stiffness and damping.\n"]


def coil_claim(reading):
    """Whether a steel coil of the reading's mass carries its pull, from its wire stress and the
    allowable (Pa), in words."""
    stress, allowed = reading["shear_stress_Pa"], reading["allowable_extension_Pa"]
    return (f"which {'no' if stress > allowed else 'a'} steel coil of that mass carries (`spring_reading.md`: wire "
            f"shear stress {stress / 1e9:.2f} GPa against the {allowed / 1e9:.2f} GPa allowed)")


def md_sizing(rig, rows, sizing):
    """Why the reference breaker is sized as it is: the paper's springs under two readings."""
    old, new = sizing["flywheel_reading"], sizing["reference"]
    f = new["figures_of_merit"]
    speed_times_time = f["closing_speed_m_s"] * f["closing_time_s"]
    s = rig.closing_spring
    return ["## Why the reference breaker is sized as it is: the paper's springs read two ways\n",
            markdown_table(SIZING_HEADERS, rows),
            f"\nRead as {old['spring_mass_kg']:.2f} kg and {round(old['charged_pull_per_spring_N'], -2):.0f} N each, "
            f"the paper's springs store {old['stored_J']:.0f} J, {coil_claim(old)}, on a "
            f"{old['cam_inertia_kg_m2']:.3f} kg m^2 cam: a "
            f"flywheel. The reference breaker takes the settled reading ({s.mass:.2f} kg, "
            f"{round(new['charged_pull_per_spring_N'], -2):.0f} N each; the pair stores {new['stored_J']:.0f} J), its "
            f"cam shaft sized for that energy ({new['cam_inertia_kg_m2']:.3f} kg m^2), the rise ending at "
            f"{np.degrees(rig.breaker.profile.rise_end):.0f} deg so that the cam completes it, and the `exact` chain. "
            "With these springs and this cam law the closing speed times the closing time is set by the shapes "
            "(spring pull against angle, profile, gap), not by the inertia: a closing speed within the reference's "
            f"window ({P.REFERENCE_LIMITS['closing_speed']['min']:g}-{P.REFERENCE_LIMITS['closing_speed']['max']:g} "
            f"m/s, parameters.REFERENCE_LIMITS) over the zone ({f['closing_speed_m_s']:.2f} m/s) takes "
            f"{1e3 * f['closing_time_s']:.0f} ms from the latch release, against the paper's 'about 30 ms' (which, at "
            f"the same product, would need about {speed_times_time / 0.030:.1f} m/s).\n"]


def drive_side(pole: int, count: int) -> str:
    """Where a main shaft is driven, in words: "the first pole's side", "the middle pole", "pole 3"."""
    return ("the first pole's side" if pole == 1 else "the middle pole" if 2 * pole == count + 1
            else "the last pole's side" if pole == count else f"pole {pole}")


def md_main_shaft(spread_rows, spread, twist, rig):
    return ["## The main shaft's twist between the pole levers\n",
            f"The reference breaker's main shaft (rig section `breaker.main_shaft`, `MAIN_SHAFT_SECTION` in "
            f"`parameters.py`, sized there with this table): {1e3 * P.MAIN_SHAFT['diameter']:.0f} mm "
            + ("solid" if P.MAIN_SHAFT["bore"] == 0 else f"hollow ({1e3 * P.MAIN_SHAFT['bore']:g} mm bore)") + " steel, pole "
            f"levers {1e3 * P.MAIN_SHAFT['pole_pitch']:.0f} mm apart and {1e3 * P.MAIN_SHAFT['lever_arm']:.0f} mm long, "
            f"driven at {drive_side(P.MAIN_SHAFT['drive_pole'], rig.breaker.poles.count)}. "
            "Each pole lever turns on its own, tied to its neighbours by the shaft's "
            "torsional stiffness and damping; the drive pole's lever turns with the roller's follower. The closing to "
            f"the cam's rest on the holding latch ({1e3 * P.BREAKER_REST_T_END:.0f} ms), full model, the same breaker "
            "with the shaft rigid, driven at the middle pole, and as thin as first estimated (equal springs, cam, poles "
            "and total inertia of the shaft assembly). Twist: the largest angle between any two pole levers, and the "
            "travel it makes at the pole:\n",
            markdown_table(POLE_SPREAD_HEADERS, spread_rows),
            f"\nPole gaps are {gap_text(rig.breaker.poles)}. "
            + pole_spread_sentence(spread, rig.breaker.poles, rig.breaker.main_shaft.drive_pole) + "\n",
            "A static check of the twist (`laws.mechanics.main_shaft_twist`: each segment carries the push-rod "
            "torques of the poles beyond it, quasi-static, no lever inertia), loaded by the push-rod forces of the "
            "elastic full model:\n",
            markdown_table(["when", "push-rod forces there (N)", "twist (mrad)", "travel at the pole (mm)"],
                           [[k, " / ".join(f"{v:.0f}" for v in w["rod_forces_N"]), f"{1e3 * w['largest_twist_rad']:.2f}",
                             f"{1e3 * w['travel_at_pole_m']:.3f}"] for k, w in twist.items()]),
            "\n" + static_check_sentence(twist, spread) + "\n"]


def rise_speed_text(speed):
    """Where a closing speed (m/s) lies against :data:`VACUUM_CLOSING_SPEEDS`, in words."""
    lo, hi = VACUUM_CLOSING_SPEEDS
    side = "above" if speed > hi else "below" if speed < lo else "within"
    return f"{speed:.2f} m/s over the zone, {side} the {lo:g}-{hi:g} m/s of 12 kV vacuum breakers"


def jump_text(weak, strong):
    """Whether the roller leaves the cam before the touch with the former opening spring, and with the
    stronger one (``opening_preload_N`` of each run, N)."""
    fw, fs = weak["figures_of_merit"], strong["figures_of_merit"]
    lift = fw["roller_first_lift_off_s"]  # s from the first touch; negative: before it
    if lift is None or lift >= 0:
        return "the roller stays on the cam up to the touch. "
    stronger = fs["roller_first_lift_off_s"] is None or fs["roller_first_lift_off_s"] >= 0
    return (f"the roller leaves the cam {1e3 * -lift:.2f} ms before the contacts touch: in the rise's deceleration "
            f"the {weak['opening_preload_N']:.0f} N opening spring cannot hold the follower and the poles (at "
            f"{strong['opening_preload_N']:.0f} N it {'can' if stronger else 'still cannot'}). ")


def md_opening_spring_and_rise(rows, runs):
    """A follower jump and what stops it, on the flywheel reading's springs and cam."""
    (weak_label, weak), (strong_label, strong), (now_label, now) = runs.items()
    fn = now["figures_of_merit"]
    held = lambda f: f["roller_first_lift_off_s"] is None  # noqa: E731
    return ["## Keeping the roller on the cam: the opening spring and the rise\n",
            "On the springs and cam of the flywheel reading (the table above): the former rise over "
            f"{weak['rise_span_deg']:.0f} deg of cam angle with two opening springs, and the rise and contact it was "
            "given:\n",
            markdown_table(["breaker", *FOM_HEADERS], rows),
            f"\nWith the former rise the poles close at {rise_speed_text(weak['figures_of_merit']['closing_speed_m_s'])}, "
            "and " + jump_text(weak, strong)
            + "With the closing springs and the cam unchanged, the touch speed is the cam's speed times the output "
            f"point's travel per cam angle: spreading the rise over {now['rise_span_deg']:.0f} deg brings the closing "
            f"speed to {fn['closing_speed_m_s']:.2f} m/s and the closing time to {1e3 * fn['closing_time_s']:.1f} ms"
            + (f", and the {now['opening_preload_N']:.0f} N opening spring keeps the roller on the cam with "
               f"{1e-3 * fn['min_cam_roller_force_before_touch_N']:.2f} kN to spare.\n" if held(fn)
               else ", but the roller still leaves the cam.\n")]


CONTACT_HEADERS = ["cam-roller law, damping", *FOM_HEADERS, "dashpot force max / min (kN)", "dissipated by the dashpot (J)"]


#: The roller loads (N) over which Palmgren's line law is compared with Johnson's cylinder formula
JOHNSON_LOADS = (1e3, 3e3, 1e4, 2e4, 4e4)


def johnson_over_palmgren(rig) -> tuple[float, float]:
    """Johnson's approach of two steel cylinders (the roller on the cam's base circle) over Palmgren's line law's,
    the smallest and largest over :data:`JOHNSON_LOADS`, for the rig's roller width and radii."""
    b = rig.breaker
    width = b.cam_roller.roller_width
    k = palmgren_line_stiffness(width)
    ratios = [johnson_line_approach(f, width, b.roller_radius, b.profile.base_radius) / (f / k) ** (1 / LINE_EXPONENT)
              for f in JOHNSON_LOADS]
    return min(ratios), max(ratios)


def md_contact(choice_rows, former_rows, rig):
    low, high = johnson_over_palmgren(rig)
    return ["## The cam-roller contact: law and damping\n",
            "A cylindrical roller on a cam is a line contact: Palmgren's steel law, force ~ delta^(10/9) with the "
            f"stiffness from the roller's {1e3 * rig.breaker.cam_roller.roller_width:g} mm width (Johnson's cylinder "
            f"formula is {100 * (low - 1):.0f}-{100 * (high - 1):.0f} % more compliant over "
            f"{1e-3 * min(JOHNSON_LOADS):g}-{1e-3 * max(JOHNSON_LOADS):g} kN), instead of Hertz's point contact (delta^1.5). "
            "The contact is preloaded from the first instant "
            "to the last, so it has no impact speed: Lankarani-Nikravesh damping then runs on its 0.05 m/s floor, an "
            "arbitrary dashpot; Hunt-Crossley with a fixed factor alpha (0.08-0.32 s/m for steel) is meant for "
            "persistent contacts. The reference breaker uses the line contact with Hunt-Crossley, alpha = 0.2 s/m.\n",
            "Reference breaker:\n",
            markdown_table(CONTACT_HEADERS, choice_rows),
            "\nThe breaker with the former rise and 1200 N opening spring (the roller jumps and lands again; there "
            "the damping law matters):\n",
            markdown_table(CONTACT_HEADERS, former_rows)]


def md_independent(agreement, t_end):
    cost, band = agreement["first_order_penetration_cost"], agreement["passive_stick_band_rad_s"]
    return ["\n## Independent evidence: the model against a solve written again from the equations\n",
            "`vcbmodel/reference/breaker.py` shares no code with the model: geometry, contact and friction laws and "
            "the equations of motion are written again; the roller's penetration is the exact minimum distance to the "
            "cam's pitch curve (Newton), the friction's stuck state, regime changes and each contact's start are "
            "events of an adaptive DOP853 solve (rtol 1e-10). Against the Exudyn model (full model, "
            f"{t_end * 1e3:.0f} ms, RK4 at {P.BREAKER_STEP:g} s):\n",
            markdown_table(["stick band", "touch times (ns)", "touch speeds (m/s)", "follower displacement (um)",
                            "cam angle (mrad)", "pole 1 travel (um)", "cam-roller force (N)"],
                           [[k, f"{1e9 * a['touch_time_difference_s']:.1f}", f"{a['touch_speed_difference_m_s']:.1e}",
                             f"{1e6 * a['max_follower_displacement_difference']:.3f}",
                             f"{1e3 * a['max_cam_angle_difference']:.4f}", f"{1e6 * a['max_pole_1_travel_difference']:.2f}",
                             f"{a['max_cam_roller_force_difference']:.0f}"]
                            for k, a in ((k, agreement[k]) for k in ("literal", "passive"))]),
            "\nLargest differences over the closing. With the literal stick band the two agree to a few ns in the "
            "touch times; what is left is the model's fixed step: the pole travels differ during the bounces because "
            "the model takes each impact speed at the start of the step in which the contact begins (first order in "
            "the step), and the touch speeds because the figures of merit interpolate the velocity over that step. "
            "The default passive stuck state widens the stick band with the step (2 h mu_s r F_n / I, "
            f"{band[0]:.3f}-{band[1]:.3f} rad/s at {P.BREAKER_STEP:g} s while the latch lets go), which delays the "
            "breakaway by microseconds. The model's first-order penetration (the pitch "
            "curve's normal offset) against the exact distance costs "
            f"{1e6 * cost['follower_displacement_m']:.3f} um of follower displacement, {1e9 * cost['penetration_m']:.2f} "
            f"nm of penetration and {1e9 * cost['touch_time_s']:.1f} ns in the touch times.\n"]


def md_conclusion(summary):
    """The paper's conclusion in numbers, the energy balance, step convergence and pressure angle."""
    c, conv = summary["paper_conclusion"], summary["step_convergence"]
    ratio, fr, ms = c["friction_over_spring_motion"], c["without shaft friction"], c["massless spring"]
    return ["## The paper's conclusion, in numbers\n",
            f"Leaving out the shaft friction changes the follower displacement by "
            f"{1e3 * fr['rms_change_of_displacement_m']:.2f} mm rms and the closing time by "
            f"{1e3 * fr['closing_time_change_s']:+.2f} ms; making the spring massless changes them by "
            f"{1e3 * ms['rms_change_of_displacement_m']:.2f} mm rms and {1e3 * ms['closing_time_change_s']:+.2f} ms. "
            + (f"Friction matters {ratio:.1f}x more than spring motion (paper: 'much more').\n" if ratio >= 1 else
               f"Spring motion matters {1 / ratio:.1f}x more than friction: on this breaker the paper's conclusion "
               "does not hold.\n"),
            "## Energy balance (J, at the end of the closing)\n",
            markdown_table(["model", "largest spring energy released", "kinetic", "opening spring", "wipe springs and rods",
                            "contacts", "dissipated", "largest residual", "residual (% of released)"],
                           [[e["model"], f"{e['spring_energy_released_max_J']:.1f}", f"{e['kinetic']:.1f}",
                             f"{e['opening_spring']:.2f}", f"{e['wipe_and_rods']:.2f}", f"{e['contacts']:.3f}",
                             f"{e['dissipated']:.1f}", f"{e['residual_max_J']:.3g}",
                             f"{e['residual_percent_of_released']:.4f}"] for e in summary["energy_balance"]]),
            "\nEach column is the change since the latch release (the opening spring's preload energy at the release is "
            "not counted, as in the energy split above). Residual = kinetic + potential + dissipated (shaft friction, "
            "contact hysteresis, rod damping) - latch work - initial energy, at every step.\n",
            "## Step convergence and cam profile\n",
            f"Halving the step ({P.BREAKER_STEP:g} s) changes the follower displacement by at most "
            f"{1e6 * conv['max_displacement_difference_m']:.2f} um and the closing time by "
            f"{1e6 * conv['closing_time_difference_s']:.2f} us (the passive stick band's share: it widens with the step). "
            f"Largest pressure angle: {summary['max_pressure_angle_closing_deg']:.1f} deg while the roller rises, "
            f"{summary['max_pressure_angle_deg']:.1f} deg over a whole cam turn (the return; limit for roller followers "
            "about 30 deg).\n"]


def md_analyser(report):
    return ["\n## The analyser's report of the full model (`vcb_closing_analyser.png`)\n",
            "What `vcbmodel simulate` prints for the reference breaker: each pole against the rig's limits "
            "(`breaker.limits`, from `parameters.py`).\n", "```\n" + report_text(report) + "\n```\n"]



FULL = "full model (friction + lumped-2)"


def closing_models(rig, meas, t_end):
    """Each model of ``models`` closing the reference breaker: results, table rows, and per model
    its effects, spring model, rms against the synthetic measurement (m) and figures of merit."""
    y_meas = meas.channels["follower_displacement"]
    results, rows, summary = {}, [], {}
    for label, (effects, spring) in models(rig).items():
        r = simulate(rig, effects, spring_model=spring, t_end=t_end)
        results[label] = r
        fom = figures_of_merit(r, rig)
        rms = float(np.sqrt(np.mean((r.resample(meas.t).channels["follower_displacement"] - y_meas) ** 2)))
        summary[label] = {"effects": list(effects), "spring_model": spring, "rms_vs_measurement_m": rms,
                          "figures_of_merit": fom}
        rows.append(fom_row(label, fom, (f"{1e3 * rms:.3f}",)))
    return results, rows, summary


def paper_conclusion(results, models_summary):
    """The paper's conclusion in numbers: how far leaving out the shaft friction, or the spring's mass,
    moves the full model's follower displacement (rms, m) and closing time (s)."""
    full = results[FULL]
    y_full = full.channels["follower_displacement"]
    closing = {label: m["figures_of_merit"]["closing_time_s"] for label, m in models_summary.items()}

    def change(label):
        r = results[label]
        d = np.interp(full.t, r.t, r.channels["follower_displacement"]) - y_full
        return {"rms_change_of_displacement_m": float(np.sqrt(np.mean(d**2))),
                "closing_time_change_s": closing[label] - closing[FULL]}

    out = {"without shaft friction": change("without shaft friction"), "massless spring": change("massless spring")}
    out["friction_over_spring_motion"] = (out["without shaft friction"]["rms_change_of_displacement_m"]
                                          / out["massless spring"]["rms_change_of_displacement_m"])
    return out


def step_convergence(rig, full, full_fom, t_end):
    """What halving the breaker's step (P.BREAKER_STEP) changes in the full model's closing."""
    fine = simulate(rig, spring_model="lumped-2", t_end=t_end, step=P.BREAKER_STEP / 2)
    y_full = full.channels["follower_displacement"]
    return {"step_s": [P.BREAKER_STEP, P.BREAKER_STEP / 2],
            "max_displacement_difference_m": float(np.max(np.abs(
                np.interp(full.t, fine.t, fine.channels["follower_displacement"]) - y_full))),
            "closing_time_difference_s": abs(figures_of_merit(fine, rig)["closing_time_s"] - full_fom["closing_time_s"])}


def pressure_angles(rig):
    """Cam angles (rad) over one turn from the start and the pressure angle there (deg)."""
    laws = BreakerLaws.of_rig(rig, model_spec(rig))
    thetas = np.linspace(rig.cam.initial_angle, rig.cam.initial_angle + 2 * np.pi, 721)
    return thetas, np.degrees(pressure_angle_curve(rig.breaker, laws.geometry, thetas))


def opening_spring_and_rise(t_end):
    """The flywheel reading's breaker with the former rise and opening spring (1200 N, 2400 N) and
    with the rise and contact it was given: figures of merit, table rows, rise spans (deg)."""
    variants = {"former (40-220 deg rise, 1200 N opening spring, Hertz point, LN damping)": former_breaker(1200.0),
                "former with a 2400 N opening spring": former_breaker(2400.0),
                "12-285 deg rise, 2000 N opening spring, line contact, Hunt-Crossley":
                    copy.deepcopy(P.FORMER_REFERENCE_BREAKER)}
    rows, out = [], {}
    for label, d in variants.items():
        r = rig_from_data(d)
        f = figures_of_merit(simulate(r, t_end=t_end), r)
        profile = d["breaker"]["cam_profile"]
        out[label] = {"figures_of_merit": f, "opening_preload_N": float(d["breaker"]["opening_spring"]["preload"]),
                      "rise_span_deg": float(np.degrees(profile["rise_end"] - profile["rise_start"]))}
        rows.append(fom_row(label, f))
    return rows, out


def closing_figures(rig, meas, results, full_fom, pressure_curve, out):
    """The Fig. 12 stand-in (every model against the synthetic measurement) and the full model's detail
    (poles, forces, and the pressure angle ``pressure_curve``: :func:`pressure_angles`' cam angles and
    angles)."""
    y_meas = meas.channels["follower_displacement"]
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 7), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
    ax1.plot(1e3 * meas.t, 1e3 * y_meas, ".", ms=2, color="0.55", label="SYNTHETIC measurement (camera stand-in)")
    for label, r in results.items():
        ax1.plot(1e3 * r.t, 1e3 * r.channels["follower_displacement"], lw=1.3, label=label)
        ax2.plot(1e3 * meas.t, 1e3 * (r.resample(meas.t).channels["follower_displacement"] - y_meas), lw=0.9)
    ax1.set_ylabel("follower displacement (mm)")
    ax1.set_title("Closing of the reference breaker (paper Fig. 12 stand-in)")
    ax1.legend(fontsize=8, loc="upper left")
    ax2.set_xlabel("t after latch release (ms)")
    ax2.set_ylabel("model - measurement (mm)")
    save(fig, out / "vcb_closing_fig12.png")

    thetas, pressure = pressure_curve
    fig, axes = plt.subplots(2, 2, figsize=(10, 7))
    ch, t = results[FULL].channels, 1e3 * results[FULL].t
    touch = 1e3 * full_fom["first_touch_s"]
    window = (t > touch - 1.5) & (t < touch + 5)
    for i in range(rig.breaker.poles.count):
        axes[0, 0].plot(t[window], 1e3 * ch[f"pole_{i + 1}_travel"][window], label=f"pole {i + 1}")
        axes[0, 1].plot(t[window], 1e-3 * ch[f"pole_{i + 1}_contact_force"][window], label=f"pole {i + 1} contact")
    axes[1, 0].plot(t, 1e-3 * ch["cam_roller_force"], label="cam-roller")
    axes[1, 0].plot(t, 1e-3 * ch["pole_1_rod_force"], label="push rod, pole 1")
    for ax, ylabel in ((axes[0, 0], "moving contact travel (mm)"), (axes[0, 1], "contact force (kN)"),
                       (axes[1, 0], "force (kN)")):
        ax.set_ylabel(ylabel)
        ax.set_xlabel("t (ms)")
        ax.legend(fontsize=8)
    poles = rig.breaker.poles
    axes[0, 0].set_title(f"touch and bounce (gap {1e3 * poles.contact_gap:g} mm +- "
                         f"{1e3 * max(abs(o) for o in poles.gap_offsets):g} mm)")
    axes[1, 1].plot(np.degrees(thetas), pressure)
    axes[1, 1].set_xlabel("cam angle (deg)")
    axes[1, 1].set_ylabel("pressure angle (deg)")
    axes[1, 1].set_title(f"cam profile: max {pressure.max():.1f} deg")
    save(fig, out / "vcb_closing_detail.png")


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    (out / "synthetic").mkdir(exist_ok=True)
    rig_dict = copy.deepcopy(P.REFERENCE_BREAKER)
    rig_path = out / "synthetic" / "vcb_closing.rig.json"
    write_rig(rig_dict, rig_path)
    rig = load_rig(rig_path)
    t_end = P.BREAKER_T_END
    truth_elements = 8 if args.quick else 16
    meas = synthetic_measurement(rig, rig.model.effects, {}, spring_model="ancf", seed=12, t_end=t_end,
                                 path=out / "synthetic" / "vcb_closing.csv", ancf_elements=truth_elements)
    write_measurement(meas, meas.path)

    results, rows, models_summary = closing_models(rig, meas, t_end)
    full = results[FULL]
    full_fom = models_summary[FULL]["figures_of_merit"]
    thetas, pressure = pressure_angles(rig)
    summary = {"synthetic_measurement": str(Path("synthetic") / "vcb_closing.csv"),
               "truth": f"full model, ANCF spring with {truth_elements} elements, noise 0.05 mm",
               "models": models_summary, "paper_conclusion": paper_conclusion(results, models_summary),
               "energy_balance": [energy_row(label, rig, results[label]) for label in
                                  (FULL, "massless spring", "neither (massless, no friction)")],
               "step_convergence": step_convergence(rig, full, full_fom, t_end),
               "max_pressure_angle_deg": float(pressure.max()),
               "max_pressure_angle_closing_deg": float(pressure[thetas <= rig.breaker.profile.rise_end].max())}
    sizing, summary["sizing"] = sizing_rows(rig, full)
    summary["main_shaft_twist"] = shaft_twist(rig, full, full_fom)
    spread_rows, summary["pole_spread_main_shaft"] = pole_spread_rows(rig_dict, P.BREAKER_REST_T_END)
    rise_rows, summary["opening_spring_and_rise"] = opening_spring_and_rise(t_end)
    choice_rows, summary["contact_choices"] = contact_choices(P.REFERENCE_BREAKER, t_end)
    former_rows, summary["contact_choices_former_breaker"] = contact_choices(former_breaker(1200.0), t_end)
    summary["independent_reference"] = independent_agreement(rig, t_end)

    closing_figures(rig, meas, results, full_fom, (thetas, pressure), out)
    report = closing_report(full, rig)
    save(closing_figure(full, rig, f"{rig.name}: full model (lumped-2)", report), out / "vcb_closing_analyser.png",
         tight=False)
    rest = simulate(rig, t_end=P.BREAKER_REST_T_END)
    split_rows = energy_split_figure(rig, full, rest, summary, out)
    stop_rows, summary["end_stop"] = end_stop_rows(rig, rest)
    write_json(out / "vcb_closing.json", summary)
    md = (md_models(rows, truth_elements) + md_energy_split(split_rows, stop_rows)
          + md_sizing(rig, sizing, summary["sizing"])
          + md_main_shaft(spread_rows, summary["pole_spread_main_shaft"], summary["main_shaft_twist"], rig)
          + md_opening_spring_and_rise(rise_rows, summary["opening_spring_and_rise"])
          + md_contact(choice_rows, former_rows, rig) + md_independent(summary["independent_reference"], t_end)
          + md_conclusion(summary) + md_analyser(report))
    (out / "vcb_closing.md").write_text("\n".join(md))
    print("\n".join(md))


if __name__ == "__main__":
    main()

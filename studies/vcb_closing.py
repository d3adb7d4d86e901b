"""The whole breaker's closing (paper section 4, Fig. 12) and its figures of merit.

The reference 12 kV / 40 kA breaker (vcbmodel/parameters.py) closes with five models: the
full model (shaft friction + lumped-2 spring, paper convention), without shaft friction,
with a massless spring, with the ANCF spring, and with neither. The "measurement" is
SYNTHETIC: the full model with an ANCF spring (16 elements) at the 12 kHz camera rate plus
0.05 mm noise. Also: energy balance, step convergence, pressure angle.
Writes results/vcb_closing_fig12.png, vcb_closing_detail.png, vcb_closing.{md,json} and
results/synthetic/vcb_closing.{csv,rig.json}.
"""
import copy
from pathlib import Path

import numpy as np
from _common import markdown_table, parse_args, write_json

from vcbmodel import parameters as P
from vcbmodel.laws.breaker import pressure_angle_curve
from vcbmodel.laws.breaker import BreakerLaws
from vcbmodel.experiments.closing_evaluation import energy_balance, figures_of_merit
from vcbmodel.app.plots import plt, save
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import model_spec, simulate
from vcbmodel.analysis.synthetic import synthetic_measurement, write_rig
from vcbmodel.records.measurement import write_measurement

FRICTION = ("coulomb_friction", "stribeck")


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


def energy_row(label, rig, result):
    e = energy_balance(result, rig)
    released = float(np.max(e["spring_energy_released"]))
    laws_end = {k: float(e[k][-1]) for k in ("kinetic", "opening_spring", "wipe_and_rods", "contacts", "dissipated")}
    return {"model": label, "spring_energy_released_max_J": released,
            "residual_max_J": float(np.max(np.abs(e["residual"]))),
            "residual_percent_of_released": 100 * float(np.max(np.abs(e["residual"]))) / released, **laws_end}


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    (out / "synthetic").mkdir(exist_ok=True)
    rig_dict = copy.deepcopy(P.REFERENCE_BREAKER)
    rig_path = out / "synthetic" / "vcb_closing.rig.json"
    write_rig(rig_dict, rig_path)
    rig = load_rig(rig_path)
    t_end = P.BREAKER_T_END
    meas = synthetic_measurement(rig, rig.model.effects, {}, spring_model="ancf", seed=12, t_end=t_end,
                                 path=out / "synthetic" / "vcb_closing.csv", ancf_elements=16)
    write_measurement(meas, meas.path)
    y_meas = meas.channels["follower_displacement"]

    results, rows, summary = {}, [], {"synthetic_measurement": str(Path("synthetic") / "vcb_closing.csv"),
                                      "truth": "full model, ANCF spring with 16 elements, noise 0.05 mm", "models": {}}
    for label, (effects, spring) in models(rig).items():
        r = simulate(rig, effects, spring_model=spring, t_end=t_end)
        results[label] = r
        fom = figures_of_merit(r, rig)
        rms = float(np.sqrt(np.mean((r.resample(meas.t).channels["follower_displacement"] - y_meas) ** 2)))
        summary["models"][label] = {"effects": list(effects), "spring_model": spring, "rms_vs_measurement_m": rms,
                                    "figures_of_merit": fom}
        rows.append([label, f"{1e3 * fom['closing_time_s']:.2f}", f"{1e3 * fom['pole_spread_s']:.2f}",
                     f"{fom['touch_speed_m_s']:.2f}", fom["bounce_count"], f"{1e3 * fom['bounce_duration_s']:.2f}",
                     f"{1e3 * fom['final_travel_m']:.2f}", f"{1e3 * fom['overtravel_m']:.2f}",
                     f"{1e-3 * fom['peak_cam_roller_force_N']:.1f}", f"{1e3 * fom['roller_lift_off_s']:.2f}",
                     f"{1e3 * rms:.3f}"])

    # the paper's conclusion: how much does each omission move the closing away from the full model?
    full = results["full model (friction + lumped-2)"]
    y_full = full.channels["follower_displacement"]

    def change(label):
        r = results[label]
        d = np.interp(full.t, r.t, r.channels["follower_displacement"]) - y_full
        return {"rms_change_of_displacement_m": float(np.sqrt(np.mean(d**2))),
                "closing_time_change_s": summary["models"][label]["figures_of_merit"]["closing_time_s"]
                - summary["models"]["full model (friction + lumped-2)"]["figures_of_merit"]["closing_time_s"]}

    conclusion = {"without shaft friction": change("without shaft friction"), "massless spring": change("massless spring")}
    ratio = (conclusion["without shaft friction"]["rms_change_of_displacement_m"]
             / conclusion["massless spring"]["rms_change_of_displacement_m"])
    conclusion["friction_over_spring_motion"] = ratio
    summary["paper_conclusion"] = conclusion

    energy = [energy_row(label, rig, results[label]) for label in
              ("full model (friction + lumped-2)", "massless spring", "neither (massless, no friction)")]
    summary["energy_balance"] = energy

    fine = simulate(rig, spring_model="lumped-2", t_end=t_end, step=P.BREAKER_STEP / 2)
    fom_fine = figures_of_merit(fine, rig)
    conv = {"step_s": [P.BREAKER_STEP, P.BREAKER_STEP / 2],
            "max_displacement_difference_m": float(np.max(np.abs(
                np.interp(full.t, fine.t, fine.channels["follower_displacement"]) - y_full))),
            "closing_time_difference_s": abs(fom_fine["closing_time_s"]
                                             - summary["models"]["full model (friction + lumped-2)"]["figures_of_merit"]["closing_time_s"])}
    summary["step_convergence"] = conv

    laws = BreakerLaws.of_rig(rig, model_spec(rig))
    thetas = np.linspace(rig.cam.initial_angle, rig.cam.initial_angle + 2 * np.pi, 721)
    pressure = np.degrees(pressure_angle_curve(rig.breaker, laws.geometry, thetas))
    summary["max_pressure_angle_deg"] = float(pressure.max())

    # Fig. 12 stand-in
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

    # detail of the full model: poles, forces, pressure angle
    fig, axes = plt.subplots(2, 2, figsize=(10, 7))
    ch, t = full.channels, 1e3 * full.t
    touch = summary["models"]["full model (friction + lumped-2)"]["figures_of_merit"]["first_touch_s"] * 1e3
    window = (t > touch - 1.5) & (t < touch + 5)
    for i in range(rig.breaker.poles.count):
        axes[0, 0].plot(t[window], 1e3 * ch[f"pole_{i + 1}_travel"][window], label=f"pole {i + 1}")
        axes[0, 1].plot(t[window], 1e-3 * ch[f"pole_{i + 1}_contact_force"][window], label=f"pole {i + 1} contact")
    axes[0, 0].set_ylabel("moving contact travel (mm)")
    axes[0, 0].set_xlabel("t (ms)")
    axes[0, 0].legend(fontsize=8)
    axes[0, 0].set_title("touch and bounce (gap 11 mm +- 0.3 mm)")
    axes[0, 1].set_ylabel("contact force (kN)")
    axes[0, 1].set_xlabel("t (ms)")
    axes[0, 1].legend(fontsize=8)
    axes[1, 0].plot(t, 1e-3 * ch["cam_roller_force"], label="cam-roller")
    axes[1, 0].plot(t, 1e-3 * ch["pole_1_rod_force"], label="push rod, pole 1")
    axes[1, 0].set_ylabel("force (kN)")
    axes[1, 0].set_xlabel("t (ms)")
    axes[1, 0].legend(fontsize=8)
    axes[1, 1].plot(np.degrees(thetas), pressure)
    axes[1, 1].set_xlabel("cam angle (deg)")
    axes[1, 1].set_ylabel("pressure angle (deg)")
    axes[1, 1].set_title(f"cam profile: max {pressure.max():.1f} deg")
    save(fig, out / "vcb_closing_detail.png")

    write_json(out / "vcb_closing.json", summary)
    md = ["# The whole breaker's closing (paper section 4, Fig. 12)\n",
          "Reference breaker: `vcbmodel/parameters.py` (REFERENCE_BREAKER). The measurement is SYNTHETIC "
          "(full model with a 16-element ANCF spring, 12 kHz, noise 0.05 mm): a stand-in for the paper's camera "
          "record, not a test.\n",
          "## Figures of merit\n",
          markdown_table(["model", "closing time (ms)", "pole spread (ms)", "touch speed (m/s)", "bounces",
                          "bounce duration (ms)", "final travel (mm)", "overtravel (mm)", "peak cam-roller force (kN)",
                          "roller lift-off (ms)", "rms vs measurement (mm)"], rows),
          "\nClosing time: latch release to the last pole's touch. Touch speed: mean over the poles. Overtravel: "
          "follower travel after the first touch (the wipe). Roller lift-off: time the roller spends off the cam.\n",
          "## The paper's conclusion, in numbers\n",
          f"Leaving out the shaft friction changes the follower displacement by "
          f"{1e3 * conclusion['without shaft friction']['rms_change_of_displacement_m']:.2f} mm rms and the closing time by "
          f"{1e3 * conclusion['without shaft friction']['closing_time_change_s']:+.2f} ms; making the spring massless changes "
          f"them by {1e3 * conclusion['massless spring']['rms_change_of_displacement_m']:.2f} mm rms and "
          f"{1e3 * conclusion['massless spring']['closing_time_change_s']:+.2f} ms. Friction matters "
          f"{ratio:.1f}x more than spring motion (paper: 'much more').\n",
          "## Energy balance (J, at the end of the closing)\n",
          markdown_table(["model", "largest spring energy released", "kinetic", "opening spring", "wipe springs and rods",
                          "contacts", "dissipated", "largest residual", "residual (% of released)"],
                         [[e["model"], f"{e['spring_energy_released_max_J']:.1f}", f"{e['kinetic']:.1f}",
                           f"{e['opening_spring']:.2f}", f"{e['wipe_and_rods']:.2f}", f"{e['contacts']:.3f}",
                           f"{e['dissipated']:.1f}", f"{e['residual_max_J']:.3g}",
                           f"{e['residual_percent_of_released']:.4f}"] for e in energy]),
          "\nResidual = kinetic + potential + dissipated (shaft friction, contact hysteresis, rod damping) - latch work "
          "- initial energy, at every step.\n",
          "## Step convergence and cam profile\n",
          f"Halving the step ({P.BREAKER_STEP:g} s) changes the follower displacement by at most "
          f"{1e6 * conv['max_displacement_difference_m']:.2f} um and the closing time by "
          f"{1e6 * conv['closing_time_difference_s']:.2f} us. Largest pressure angle over a cam turn: "
          f"{pressure.max():.1f} deg (limit for roller followers: about 30 deg).\n"]
    (out / "vcb_closing.md").write_text("\n".join(md))
    print("\n".join(md))


if __name__ == "__main__":
    main()

"""Paper section 2 / Fig. 5: shaft friction identified from two pendulum tests.

The "measurements" are SYNTHETIC: the documented truth (parameters.REFERENCE_PENDULUM_TRUTH,
the hybrid law) simulated for the 10 deg test and the short-link 15 deg test, plus
potentiometer noise (0.5 mrad at 1 kHz). Both laws of the paper are fitted to both tests at
once: case 1 hybrid, case 2 stick-slip only. Writes results/friction_identification.{png,json,md}
and the synthetic measurement files under results/synthetic/.
"""
import math
import time
from pathlib import Path

from _common import markdown_table, parse_args, write_json

from vcbmodel import parameters as P
from vcbmodel.analysis.identify import identify
from vcbmodel.experiments import experiment_of
from vcbmodel.app.plots import plt, save
from vcbmodel.experiments.loading import load_rig
from vcbmodel.analysis.synthetic import synthetic_measurement, write_rig
from vcbmodel.records.measurement import write_measurement

TRUTH_EFFECTS = ("coulomb_friction", "stribeck", "viscous_friction")
#: The paper's largest error of each law's fit, % of the first peak (Ahn & Kim 2002, Fig. 5: case 1, case 2)
PAPER_MAX_ERROR_PERCENT = {"hybrid": 8, "stick-slip": 13}
#: rad: the synthetic records' potentiometer noise (the pendulum experiment's sensor)
NOISE_RAD = experiment_of("pendulum").noise_sigma


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    (out / "synthetic").mkdir(exist_ok=True)
    t_end = 1.5 if args.quick else 6.0
    pairs = []
    for name, rig_dict, seed in (("pendulum_10deg", P.REFERENCE_PENDULUM, 10), ("pendulum_15deg", P.REFERENCE_PENDULUM_15, 11)):
        rig_path = out / "synthetic" / f"{name}.rig.json"
        write_rig(rig_dict, rig_path)
        rig = load_rig(rig_path)
        meas = synthetic_measurement(rig, TRUTH_EFFECTS, P.REFERENCE_PENDULUM_TRUTH, seed=seed, t_end=t_end,
                                     path=out / "synthetic" / f"{name}.csv")
        write_measurement(meas, meas.path)
        pairs.append((rig, meas))
    fits, timing = {}, {}
    for law in ("hybrid", "stick-slip"):
        t0 = time.time()
        fits[law] = identify(pairs, law, polish=not args.quick)
        timing[law] = time.time() - t0

    fig, axes = plt.subplots(2, 2, figsize=(11, 6.5), sharex="col", gridspec_kw={"height_ratios": [2, 1]})
    for j, (rig, meas) in enumerate(pairs):
        ax, axr = axes[0, j], axes[1, j]
        ax.plot(meas.t, meas.channels["pendulum_angle"], ".", ms=1.5, color="0.55", label="synthetic measurement")
        for law, style in (("hybrid", "-"), ("stick-slip", "--")):
            f = fits[law]
            ax.plot(meas.t, f.fit.simulations[j].measured, style, lw=1.1,
                    label=f"{law} fit (max error {100 * abs(f.fit.residuals[j]).max() / f.first_peaks[j]:.1f} %)")
            axr.plot(meas.t, f.fit.residuals[j], style, lw=0.8, label=law)
        ax.set_title(rig.name)
        ax.set_ylabel("pendulum angle (rad)")
        ax.legend(fontsize=8)
        axr.set_xlabel("t (s)")
        axr.set_ylabel("fit - measurement (rad)")
        axr.legend(fontsize=8)
    save(fig, out / "friction_identification.png")

    rows, table = [], {"truth": dict(P.REFERENCE_PENDULUM_TRUTH), "synthetic": True,
                       "paper_max_error_percent": PAPER_MAX_ERROR_PERCENT, "fits": {}}
    for law, f in fits.items():
        j = f.to_json()
        j["seconds"] = round(timing[law], 1)
        table["fits"][law] = j
        rows.append([law, f"{j['mu_k']:.4f}", f"{j['mu_s']:.4f}", f"{j['stick_velocity']:.2e}",
                     f"{j['stribeck_velocity']:.3f}", f"{j['viscous']:.3f}", f"{j['zeta']:.4f}",
                     f"{1e3 * j['rms']:.2f}", f"{j['max_error_percent']:.1f}", PAPER_MAX_ERROR_PERCENT[law]])
    truth = P.REFERENCE_PENDULUM_TRUTH
    rows.append(["truth (synthetic data)", truth["mu_k"], truth["mu_s"], truth["stick_velocity"],
                 truth["stribeck_velocity"], truth["viscous"], "", f"{1e3 * NOISE_RAD:.2f} (noise)", "", ""])
    write_json(out / "friction_identification.json", table)
    degrees = " + ".join(f"{math.degrees(rig.pendulum.initial_angle):.0f} deg" for rig, _ in pairs)
    md = (f"# Friction identification (paper Fig. 5), synthetic pendulum tests {degrees}\n\n"
          f"Both laws fitted to both tests at once. Measurements are synthetic (truth + {1e3 * NOISE_RAD:g} mrad noise).\n\n"
          + markdown_table(["law", "mu_k", "mu_s", "w0 (rad/s)", "ws (rad/s)", "Cv (N m s/rad)", "zeta",
                            "rms (mrad)", "max error (% of first peak)", "paper (%)"], rows))
    (out / "friction_identification.md").write_text(md)
    print(md)


if __name__ == "__main__":
    main()

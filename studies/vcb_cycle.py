"""The reference breaker's whole operating cycle: IEC 62271-100's O - 0.3 s - CO on the breaker with
its trip latch, opening dashpot, releases and rated making current (parameters.REFERENCE_CYCLE_BREAKER),
the kinetic margin after the touch, and the making currents at which it fails.

Writes results/synthetic/vcb_cycle.rig.json (the rig, from parameters.py), vcb_cycle.json and
vcb_cycle.md. The sequence runs on Exudyn (the model) and on the compiled path (their figures side by
side); the making limits on the compiled path (a bisection of closings to rest).
"""
import copy
import json
from pathlib import Path

from _common import markdown_table, parse_args, write_json

from vcbmodel import parameters as P
from vcbmodel.app.plots import plt, save
from vcbmodel.laws.breaker import pole_gaps
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.making import making_limits
from vcbmodel.experiments.sequence import run_sequence

SEQUENCE = "O-0.3s-CO"


def write_rig(path: Path) -> None:
    data = copy.deepcopy(P.REFERENCE_CYCLE_BREAKER)
    data = {"_comment": "written by studies/vcb_cycle.py from vcbmodel/parameters.py (REFERENCE_CYCLE_BREAKER): "
                        "every value's source is there", **data}
    path.write_text(json.dumps(data, indent=2) + "\n")


def ms(x):
    return "-" if x is None else f"{1e3 * x:.2f}"


def rows(report):
    out = []
    for e in report["operations"]:
        coil_close = e.get("closing_time_from_coil_range_s")
        coil_open = e.get("opening_time_from_coil_range_s")
        out.append([e["op"], f"{e['command_s']:g}",
                    f"{ms(e.get('closing_time_from_coil_s'))} ({ms(coil_close[0])}-{ms(coil_close[1])})" if coil_close else "-",
                    ms(e.get("closing_time_from_latch_s")),
                    f"{e['bounce_count']} / {ms(e['bounce_duration_s'])}" if "bounce_count" in e else "-",
                    f"{e['kinetic_margin_J']:.1f} of {e['kinetic_at_touch_J']:.1f}" if e.get("kinetic_margin_J") else "-",
                    f"{ms(e.get('opening_time_from_coil_s'))} ({ms(coil_open[0])}-{ms(coil_open[1])})" if coil_open else "-",
                    ms(e.get("opening_time_from_pawl_s")),
                    f"{e['opening_speed_m_s']:.3f}" if e.get("opening_speed_m_s") else "-",
                    f"{1e3 * e['opening_rebound_m']:.3f}" if e.get("opening_rebound_m") is not None else "-",
                    ms(e.get("close_open_time_s"))])
    return out


HEADERS = ["op", "command (s)", "closing time from coil, ms (IEC corners)", "closing from latch (ms)",
           "bounces / duration (ms)", "kinetic margin of at touch (J)", "opening time from coil, ms (IEC corners)",
           "parting after pawl (ms)", "opening speed (m/s)", "rebound (mm)", "close-open (ms)"]


def plot_sequence(report, runs, rig, path):
    """F's travel and each pole's travel over each operation (ms from its release's command), the
    poles' gaps dashed, the making current's repulsion on the CO's poles below."""
    fig, axes = plt.subplots(2, len(runs), figsize=(5.5 * len(runs), 6.5), sharex="col",
                             gridspec_kw={"height_ratios": [3, 1.4]}, squeeze=False)
    gaps = pole_gaps(rig.breaker.poles)
    for k, (entry, r) in enumerate(zip(report["operations"], runs)):
        t = 1e3 * (r.t + (entry["release_delay_s"] or 0.0))
        top, bottom = axes[0, k], axes[1, k]
        top.plot(t, 1e3 * r.channels["f_travel"], color="k", lw=1.2, label="F (follower output)")
        for i, gap in enumerate(gaps, start=1):
            line, = top.plot(t, 1e3 * r.channels[f"pole_{i}_travel"], lw=0.9, label=f"pole {i}")
            top.axhline(1e3 * gap, color=line.get_color(), ls="--", lw=0.6)
        top.set_title(f"{entry['op']} at {entry['command_s']:g} s")
        top.set_ylabel("travel from open (mm)")
        top.legend(fontsize=7, loc="best")
        for i in range(1, len(gaps) + 1):
            force = r.channels.get(f"pole_{i}_repulsion_force")
            if force is not None:
                bottom.plot(t, 1e-3 * force, lw=0.8, label=f"pole {i}")
        bottom.plot(t, 1e-3 * r.channels["follower_cycle_force"], color="k", lw=0.8, label="pawl, dashpot, stop on F")
        bottom.set_ylabel("force (kN)")
        bottom.set_xlabel("time from the command, coil energised (ms)")
        bottom.legend(fontsize=7, loc="best")
    fig.suptitle(f"{report['sequence']} on the reference cycle breaker (SIMULATED)")
    save(fig, path)


def main():
    args = parse_args(__doc__)
    out = Path(args.out)
    (out / "synthetic").mkdir(exist_ok=True)
    rig_path = out / "synthetic" / "vcb_cycle.rig.json"
    write_rig(rig_path)
    rig = load_rig(rig_path)
    runs = []
    reports = {backend: run_sequence(rig, SEQUENCE, backend=backend, results=runs if backend == "exudyn" else None)
               for backend in ("exudyn", "compiled")}
    plot_sequence(reports["exudyn"], runs, rig, out / "vcb_cycle.png")
    # searched up to five times the rated making current (beyond any vacuum breaker's rating: 63 kA breaking,
    # 164 kA making); at a mega-ampere Holm's force makes the run unstable (making.valid_high)
    limits = making_limits(rig, high=2e5 if args.quick else 5e5, tolerance=5e3 if args.quick else 1e3, backend="compiled")
    write_json(out / "vcb_cycle.json", {"sequence": reports, "making_limits": limits})
    text = [f"# The reference breaker's operating cycle: {SEQUENCE}", "",
            "Rig: `synthetic/vcb_cycle.rig.json` (parameters.REFERENCE_CYCLE_BREAKER: the reference breaker with its "
            f"trip latch, opening dashpot, releases and the rated making current, {limits['rated_peak_A'] / 1e3:g} kA "
            "peak). SIMULATED, not measured.", ""]
    for backend, report in reports.items():
        text += [f"## {backend}", "", markdown_table(HEADERS, rows(report))]
        text += [f"- {n}" for n in report["notes"]] + [""]
        text.append("Dead time bound (O's last parting to CO's first touch): "
                    + ", ".join(f"{1e3 * d:.1f} ms" for d in report["dead_times_s"] if d is not None) + "\n")
    fail = limits["fails_to_latch_A"]
    text += ["## Closing onto a fault", "",
             f"- kinetic margin after the touch: {limits['kinetic_margin_without_current_J']:.1f} J without current, "
             f"{limits['kinetic_margin_at_rated_J']:.1f} J at the rated {limits['rated_peak_A'] / 1e3:g} kA peak",
             f"- fails to latch at: {'not up to %g kA' % (limits['high_A'] / 1e3) if fail is None else '%.1f kA' % (fail / 1e3)}"
             f" (bisection to {limits['tolerance_A'] / 1e3:g} kA)",
             "- contacts blown open (a pole's bounce outlasts the current-free closing's) from: "
             + ("-" if limits["blown_open_A"] is None else f"{limits['blown_open_A'] / 1e3:.1f} kA"), ""]
    (out / "vcb_cycle.md").write_text("\n".join(text) + "\n")


if __name__ == "__main__":
    main()

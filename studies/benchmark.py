"""Speed and memory benchmark (targets from the issues); writes results/benchmark.json.

Wall times are medians of several runs on this machine; tests never assert them.
"""
import copy
import os
import platform
import resource
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np
from _common import markdown_table, parse_args, write_json

from vcbmodel import parameters as P
from vcbmodel.analysis.diagnose import diagnose
from vcbmodel.analysis.identify import identify
from vcbmodel.analysis.realistic import realistic_record
from vcbmodel.analysis.sweep import figures_of_merit, sweep
from vcbmodel.analysis.synthetic import synthetic_measurement, write_rig
from vcbmodel.builders.pendulum import build_pendulum
from vcbmodel.experiments import experiment_of
from vcbmodel.experiments.loading import load_pair, load_rig, rig_from_data
from vcbmodel.experiments.simulation import model_spec, output_times, simulate, simulate_rigid_ties

HYBRID = ("coulomb_friction", "stribeck", "viscous_friction")


def median_time(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


def interleaved(variants, repeats):
    """{name: median seconds}: every variant once per round, the order rotated each round, so slow
    phases of a shared machine hit all variants alike; ratios are taken within one run."""
    names = list(variants)
    times = {n: [] for n in names}
    for r in range(repeats):
        for n in names[r % len(names):] + names[:r % len(names)]:
            t0 = time.perf_counter()
            variants[n]()
            times[n].append(time.perf_counter() - t0)
    return {n: statistics.median(v) for n, v in times.items()}


def speed_targets(prig, crig, brig, law, h, repeats):
    """The speed issue's table (issue 18): each workload against its target, measured interleaved
    (every variant once per round), on Exudyn and on the compiled path (the same laws traced to C,
    what fits, sweeps and design studies run), each row with its ratio to a floor in the same run."""
    rows = {}
    pend = interleaved({"exudyn_no_friction": lambda: build_pendulum(prig, law, "none").solve(6.0, h, 1e-3),
                        "exudyn_symbolic": lambda: build_pendulum(prig, law, "symbolic").solve(6.0, h, 1e-3),
                        "exudyn_python": lambda: build_pendulum(prig, law, "python").solve(6.0, h, 1e-3),
                        "compiled": lambda: simulate(prig, HYBRID, P.REFERENCE_PENDULUM_TRUTH, t_end=6.0,
                                                     step=h, backend="compiled")}, repeats)
    rows["pendulum_6s_compiled_friction_over_no_friction"] = {
        "seconds": pend, "now": pend["exudyn_symbolic"] / pend["exudyn_no_friction"], "target": 2.5, "unit": "ratio",
        "compiled_over_exudyn_no_friction": pend["compiled"] / pend["exudyn_no_friction"]}
    fric = ("coulomb_friction", "stribeck", "spring_mass")
    cam = interleaved({"exudyn": lambda: simulate(crig, fric, spring_model="lumped-2", t_end=0.035),
                       "exudyn_without_friction": lambda: simulate(crig, ("spring_mass",), spring_model="lumped-2",
                                                                   t_end=0.035),
                       "compiled": lambda: simulate(crig, fric, spring_model="lumped-2", t_end=0.035,
                                                    backend="compiled")}, repeats)
    rows["cam_drop_35ms_lumped2_with_friction"] = {"seconds": cam, "now": cam["compiled"], "target": 0.040,
                                                   "unit": "s", "exudyn_s": cam["exudyn"]}
    massless = ("coulomb_friction", "stribeck")
    m = interleaved({uf: (lambda uf=uf: simulate(crig, massless, spring_model="massless", t_end=0.035, user_function=uf))
                     for uf in ("auto", "python", "symbolic")}, repeats)
    # auto runs the Python user function itself: the ratio is 1 but for timing noise (5 % allowed)
    rows["cam_drop_35ms_massless_simulate_auto_over_python_uf"] = {"seconds": m, "now": m["auto"] / m["python"],
                                                                  "target": 1.05, "unit": "ratio"}
    eff = tuple(e for e in brig.model.effects if e != "spring_mass") + ("spring_mass",)
    closing = interleaved({"exudyn": lambda: simulate(brig, eff, spring_model="lumped-2"),
                           "compiled": lambda: simulate(brig, eff, spring_model="lumped-2", backend="compiled")},
                          max(3, repeats // 2))
    rows["vcb_closing_45ms_lumped2"] = {"seconds": closing, "now": closing["compiled"], "target": 0.15, "unit": "s",
                                        "exudyn_s": closing["exudyn"]}
    for row in rows.values():
        row["met"] = bool(row["now"] <= row["target"])
    return rows


#: The rows of the speed table: (key in issue18_targets, workload, format of "now")
TABLE_ROWS = (
    ("pendulum_6s_compiled_friction_over_no_friction", "6 s pendulum: Exudyn symbolic friction / Exudyn without friction", "{:.1f}x"),
    ("cam_drop_35ms_lumped2_with_friction", "35 ms cam drop, lumped-2, with friction", "{:.4f} s"),
    ("cam_drop_35ms_massless_simulate_auto_over_python_uf", "35 ms massless cam drop, simulate() auto / Python UF", "{:.2f}x"),
    ("vcb_closing_45ms_lumped2", "45 ms closing, lumped-2", "{:.4f} s"),
    ("one_diagnosis_realism_median", "one diagnosis, realistic records: median", "{:.1f} s"),
    ("one_diagnosis_realism_max", "one diagnosis, realistic records: max", "{:.1f} s"),
    ("tolerance_study_10000_closings_2_cores", "10 000-closing tolerance study, 2 cores (estimate)", "{:.1f} min"),
)


def speed_table(targets):
    """The speed issue's table as Markdown (README quotes it): each workload on Exudyn and on the
    compiled path, against its target."""
    rows = []
    for key, what, fmt in TABLE_ROWS:
        row = targets.get(key)
        if row is None:
            continue
        seconds = row.get("seconds", {})
        exudyn = row.get("exudyn_s")
        extra = ""
        if "compiled_over_exudyn_no_friction" in row:
            extra = f"compiled path: {row['compiled_over_exudyn_no_friction']:.2f}x Exudyn without friction"
        elif exudyn is not None:
            extra = f"Exudyn {exudyn:.3f} s ({exudyn / row['now']:.0f}x slower)"
        elif "how" in row:
            extra = row["how"]
        elif seconds:
            extra = ", ".join(f"{k} {v:.4f} s" for k, v in seconds.items())
        unit = {"ratio": "x", "s": " s", "min": " min"}[row["unit"]]
        rows.append([what, fmt.format(row["now"]), f"{row['target']:g}{unit}", "met" if row["met"] else "missed", extra])
    head = ("# Speed (studies/benchmark.py; medians of interleaved repeats, one run)\n\n"
            "'now' is the compiled path where the row names no backend (what fits, sweeps and design studies "
            "run); Exudyn remains the reference model.\n\n")
    return head + markdown_table(["workload", "now", "target", "", "beside it"], rows) + "\n"


def rss_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def main():
    args = parse_args(__doc__)
    repeat = 1 if args.quick else 3
    out = Path(args.out)
    tmp = Path(tempfile.mkdtemp())
    write_rig(P.REFERENCE_PENDULUM, tmp / "p.rig.json")
    write_rig(P.REFERENCE_CAM, tmp / "c.rig.json")
    prig, crig = load_rig(tmp / "p.rig.json"), load_rig(tmp / "c.rig.json")
    truth = P.REFERENCE_PENDULUM_TRUTH
    h = experiment_of("pendulum").step(prig)
    law = model_spec(prig, HYBRID, truth).friction_law(prig.shaft_radius, h)
    t_end = 6.0
    res = {"machine": {"python": platform.python_version(), "processor": platform.processor() or platform.machine()},
           "pendulum_6s": {"step_s": h}}
    pend = res["pendulum_6s"]
    for name, uf in (("floor_no_friction", "none"), ("symbolic_user_function", "symbolic"), ("python_user_function", "python")):
        pend[name + "_s"] = median_time(lambda: build_pendulum(prig, law, uf).solve(t_end, h, 1e-3), repeat)
    pend["scipy_reference_dop853_s"] = median_time(
        lambda: simulate(prig, HYBRID, truth, t_end=t_end, backend="reference"), 1)
    pend["compiled_over_floor"] = pend["symbolic_user_function_s"] / pend["floor_no_friction_s"]
    pend["target_compiled_over_floor"] = 2.0
    pend["target_met"] = pend["compiled_over_floor"] <= 2.0
    print(pend, flush=True)

    cam = res["cam_drop_35ms"] = {}
    models = ["massless", "lumped-1", "lumped-2", "lumped-3"]
    for m in models:
        eff = ("coulomb_friction", "stribeck") + (("spring_mass",) if m != "massless" else ())
        cam[m + "_s"] = median_time(lambda: simulate(crig, eff, spring_model=m, t_end=0.035), repeat)
    cam["target_lumped_s"] = 0.5
    cam["lumped_target_met"] = all(cam[m + "_s"] <= 0.5 for m in models[1:])
    eff = ("coulomb_friction", "stribeck", "spring_mass")
    for ne in (4, 8, 16):
        cam[f"ancf_{ne}_s"] = median_time(lambda: simulate(crig, eff, spring_model="ancf", ancf_elements=ne,
                                                            t_end=0.035), repeat)
    cam["target_ancf_8_s"] = 5.0
    cam["ancf_8_target_met"] = cam["ancf_8_s"] <= 5.0
    # the spring studies' truth: two tie stiffnesses extrapolated to rigid ties (12 kHz samples)
    cam["ancf_8_rigid_ties_s"] = median_time(lambda: simulate_rigid_ties(
        crig, eff, sample_times=output_times(crig, 0.035)), 1)
    print(cam, flush=True)

    write_rig(P.REFERENCE_BREAKER, tmp / "b.rig.json")
    brig = load_rig(tmp / "b.rig.json")
    closing = res["vcb_closing_45ms"] = {}
    for m in ("massless", "lumped-2", "ancf"):
        eff = tuple(e for e in brig.model.effects if e != "spring_mass") + (("spring_mass",) if m != "massless" else ())
        closing[m.replace("-", "") + "_s"] = median_time(lambda: simulate(brig, eff, spring_model=m), repeat)
    closing["target_lumped2_s"] = 10.0
    closing["lumped2_target_met"] = closing["lumped2_s"] <= 10.0
    print(closing, flush=True)

    res["issue18_targets"] = speed_targets(prig, crig, brig, law, h, 3 if args.quick else 7)
    print(res["issue18_targets"], flush=True)
    res["identification"] = identification_cost(tmp, truth, args.quick)
    print(res["identification"], flush=True)
    if not args.quick:
        pairs = []
        for i, rd in enumerate((P.REFERENCE_PENDULUM, P.REFERENCE_PENDULUM_15)):
            write_rig(rd, tmp / f"id{i}.rig.json")
            r = load_rig(tmp / f"id{i}.rig.json")
            pairs.append((r, synthetic_measurement(r, HYBRID, truth, seed=20 + i)))
        t0 = time.perf_counter()
        identify(pairs, "hybrid", verbose=False)
        res["hybrid_identification_two_measurements_s"] = time.perf_counter() - t0
        res["hybrid_identification_target_s"] = 60.0
        res["diagnosis_s"] = diagnosis_times(tmp)
        print(res["diagnosis_s"], flush=True)
        d = res["diagnosis_s"]
        res["issue18_targets"]["one_diagnosis_realism_median"] = {"now": d["median_s"], "target": 4.0, "unit": "s",
                                                                  "met": d["median_s"] <= 4.0}
        res["issue18_targets"]["one_diagnosis_realism_max"] = {"now": d["max_s"], "target": 15.0, "unit": "s",
                                                               "met": d["max_s"] <= 15.0}

    # memory: repeated build + solve with symbolic user functions (exudyn-notes: leaks without SC.Reset)
    before = rss_mb()
    for _ in range(10 if args.quick else 100):
        build_pendulum(prig, law, "symbolic").solve(0.5, h, 1e-3)
    res["memory"] = {"peak_rss_mb": rss_mb(), "rss_growth_over_builds_mb": rss_mb() - before,
                     "builds": 10 if args.quick else 100}
    res["sweep_scaling"] = sweep_scaling(args.quick)
    minutes = res["sweep_scaling"]["estimate_10000_runs"]["2_cores_min"]
    res["issue18_targets"]["tolerance_study_10000_closings_2_cores"] = {
        "now": minutes, "target": 30.0, "unit": "min", "met": minutes <= 30.0,
        "how": "estimated from this run's closings per core-second in a 2-worker sweep (sweep_scaling)"}
    write_json(out / "benchmark.json", res)
    (out / "benchmark.md").write_text(speed_table(res["issue18_targets"]))
    print(res)


def identification_cost(tmp, truth, quick):
    """Issue 10: one hybrid identification of one 6 s pendulum record, in single simulations of
    that record (wall time, measured in this run: the median of five simulations before and five
    after; the machine's load changes both alike). Target 20, moonshot 8."""
    write_rig(P.REFERENCE_PENDULUM, tmp / "id1.rig.json")
    rig = load_rig(tmp / "id1.rig.json")
    out = {"record_s": 6.0, "target_ratio": 20.0, "moonshot_ratio": 8.0, "runs": []}
    seeds = (31,) if quick else (31, 32, 33)
    for seed in seeds:
        meas = synthetic_measurement(rig, HYBRID, truth, seed=seed)
        single = [median_time(lambda: simulate(rig, HYBRID, truth, sample_times=meas.t), 5)]
        t0 = time.perf_counter()
        r = identify([(rig, meas)], "hybrid", verbose=False)
        seconds = time.perf_counter() - t0
        single.append(median_time(lambda: simulate(rig, HYBRID, truth, sample_times=meas.t), 5))
        one = statistics.median(single)
        out["runs"].append({"seed": seed, "identification_s": seconds, "single_simulation_s": one,
                            "ratio": seconds / one, "simulations": r.fit.nfev,
                            "mu_k": r.values["mu_k"], "viscous": r.values["viscous"], "rms": r.fit.rms})
    out["ratio"] = statistics.median(x["ratio"] for x in out["runs"])
    out["target_met"] = out["ratio"] <= out["target_ratio"]
    return out


def diagnosis_times(tmp):
    """Issue 11: one diagnosis of each kind of realistic record (vcbmodel.analysis.realistic),
    wall time on 2 cores; target 60 s. Also the time against the diagnosis' own budget
    (processor seconds per process) and the simulations it ran."""
    cases = [("pend_visc", 41, ("pre_trigger", "offset", "initial_angle")), ("pend_none", 42, ("correlated",)),
             ("pend_two", 4, ()), ("pend_unregistered", 5, ()), ("pend_visc", 9, ("quantised", "time_base", "period")),
             ("pend_none", 8, ("hand_start",)), ("cam_mass", 6, ("pre_trigger", "offset")),
             ("cam_none", 43, ("correlated",)), ("closing_damping", 44, ())]
    out = {"target_s": 60.0, "cases": []}
    for case, seed, comps in cases:
        rp, mp, truth = realistic_record(case, seed, tmp, comps)
        rig, meas = load_pair(mp)
        t0 = time.perf_counter()
        d = diagnose(rig, meas, verbose=False)
        seconds = time.perf_counter() - t0
        out["cases"].append({"case": case, "complications": list(comps), "seconds": seconds,
                             "budget_used_s": d.timing["budget_used_s"], "simulations": d.timing["simulations"],
                             "named": d.missing_effects, "answer": truth["answer"], "explained": d.explained})
    out["max_s"] = max(c["seconds"] for c in out["cases"])
    out["median_s"] = statistics.median(c["seconds"] for c in out["cases"])
    out["target_met"] = out["max_s"] <= out["target_s"]
    return out


def sweep_scaling(quick):
    """Design studies at scale (vcbmodel sweep): the same sweep of reference-breaker closings on
    1 process (in this one) and on 2 local worker processes (the pool, started by the sweep):
    parallel efficiency T1 / (2 T2); one run's parts (rig load, run: simulation, channels and
    figures of merit) measured in this process; throughput in closings per core-minute; and an
    estimate of a 10 000-run tolerance study on 2, 16 and 256 cores."""
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    parts = {"load_s": [], "run_s": []}
    for _ in range(2 if quick else 5):
        t0 = time.perf_counter()
        rig = rig_from_data(copy.deepcopy(data))
        parts["load_s"].append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        figures_of_merit(rig)
        parts["run_s"].append(time.perf_counter() - t0)
    one = {k: statistics.median(v) for k, v in parts.items()}
    one["simulated_with"] = simulate(rig, backend="fast", t_end=1e-3).info["backend"]

    n = 4 if quick else 16
    runs = [{"friction.mu_k": float(m)} for m in np.linspace(0.10, 0.16, n)]
    load_before = os.getloadavg()
    c0 = time.process_time()
    t1 = sweep(data, runs=runs, workers=1, verbose=False).attrs["wall_s"]
    cpu_serial = time.process_time() - c0
    t2 = {}
    for start in ("cold", "warm"):  # cold: the first pool of this process (imports, if not done yet)
        c0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        two = sweep(data, runs=runs, workers=2, verbose=False)
        t2[start] = time.perf_counter() - t0
        c1 = resource.getrusage(resource.RUSAGE_CHILDREN)  # the pool's workers, joined at its end
        cpu_workers = (c1.ru_utime + c1.ru_stime) - (c0.ru_utime + c0.ru_stime)
    per_run = t1 / n
    efficiency = t1 / (2 * t2["warm"])
    busy = sum(two.attrs["run_s"]) / (2 * t2["warm"])  # the workers' time in runs / their wall time
    result = {
        "closings": n, "one_run": one, "sweep_1_worker_s": t1, "sweep_2_workers_s": t2["warm"],
        "sweep_2_workers_first_pool_s": t2["cold"],
        "parallel_efficiency": efficiency, "parallel_efficiency_first_pool": t1 / (2 * t2["cold"]),
        "target_parallel_efficiency": 0.8, "target_met": efficiency >= 0.8,
        # CPU seconds of the 1-process sweep and of the 2 workers (more: each run slower when both cores work)
        "worker_utilisation_2_workers": busy, "cpu_s_serial": cpu_serial, "cpu_s_2_workers": cpu_workers,
        # cores the two workers actually got (under 2: other jobs on a shared machine took the rest)
        "cores_used_by_2_workers": cpu_workers / t2["warm"],
        "sweep_overhead_per_run_s": per_run - one["run_s"] - one["load_s"],
        "simulated_with": two.attrs["simulated_with"],
        "closings_per_core_minute": {"1_worker": 60 * n / t1, "2_workers": 60 * n / (2 * t2["warm"])},
        "load_average_before_after": [load_before, os.getloadavg()],
        "note": "a shared 2-core machine: other work changes these numbers by tens of percent",
    }
    # a 10 000-run tolerance study on cores of its own: one run's time as measured in this process, the
    # workers' utilisation (time in runs / wall time: other jobs on a shared machine slow both alike,
    # unlike the speed-up) at most 0.95, the Dask scheduler's time per task (3 ms measured here with
    # empty tasks: it only limits when the cores finish runs faster than it hands them out), plus the
    # workers' start-up (imports, about 10 s)
    run_time, eff, per_task = one["run_s"] + one["load_s"], min(busy, 0.95), 0.003
    result["estimate_10000_runs"] = {
        f"{cores}_cores_min": (max(10000 * run_time / (cores * eff), 10000 * per_task) + 10.0) / 60
        for cores in (2, 16, 256)}
    result["estimate_10000_runs"]["assumptions"] = (
        f"{run_time:.2f} s per closing (one run on this machine), efficiency {eff:.2f} (worker utilisation, at "
        f"most 0.95), {1e3 * per_task:g} ms of scheduler time per run (Dask, empty tasks), 10 s worker start-up")
    print({"sweep_scaling": result}, flush=True)
    return result


if __name__ == "__main__":
    main()

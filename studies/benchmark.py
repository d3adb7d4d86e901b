"""Speed and memory benchmark (targets from the issues); writes results/benchmark.json.

Wall times are medians of several runs on this machine; tests never assert them.
"""
import platform
import resource
import statistics
import tempfile
import time
from pathlib import Path

from _common import parse_args, write_json

from vcbmodel import parameters as P
from vcbmodel.analysis.diagnose import diagnose
from vcbmodel.analysis.identify import identify
from vcbmodel.analysis.synthetic import random_case, synthetic_measurement, write_rig
from vcbmodel.builders.pendulum import build_pendulum
from vcbmodel.experiments import experiment_of
from vcbmodel.experiments.loading import load_record, load_rig
from vcbmodel.experiments.simulation import model_spec, simulate

HYBRID = ("coulomb_friction", "stribeck", "viscous_friction")


def median_time(fn, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times)


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
    law = model_spec(prig, HYBRID, truth).friction_law(prig.shaft_radius)
    h = experiment_of("pendulum").step(prig, law)
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
        diag = res["diagnosis_s"] = {}
        for case in ("pend_visc", "cam_mass"):
            rp, mp, _ = random_case(case, 7, tmp)
            rig = load_rig(rp)
            t0 = time.perf_counter()
            diagnose(rig, load_record(mp, rig), verbose=False)
            diag[case] = time.perf_counter() - t0
        diag["target_s"] = 120.0
        print(res, flush=True)

    # memory: repeated build + solve with symbolic user functions (exudyn-notes: leaks without SC.Reset)
    before = rss_mb()
    for _ in range(10 if args.quick else 100):
        build_pendulum(prig, law, "symbolic").solve(0.5, h, 1e-3)
    res["memory"] = {"peak_rss_mb": rss_mb(), "rss_growth_over_builds_mb": rss_mb() - before,
                     "builds": 10 if args.quick else 100}
    write_json(out / "benchmark.json", res)
    print(res)


if __name__ == "__main__":
    main()

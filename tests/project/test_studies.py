"""Every study script runs (quick mode) and writes its outputs: build, run, plot, save."""
import importlib.util
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

STUDIES = Path(__file__).resolve().parents[2] / "studies"

EXPECTED = {
    "friction_identification.py": ["friction_identification.png", "friction_identification.json",
                                   "synthetic/pendulum_10deg.csv"],
    "spring_models.py": ["cam_drop_fig9a.png", "cam_drop_fig9b.png", "spring_modes.md", "spring_fidelity.json",
                         "spring_convergence.png", "spring_shapes_fig10.png", "spring_lateral.png", "cam_drop.gif",
                         "synthetic/cam_drop_m0_1kg.csv"],
    "discrepancy_demo.py": ["discrepancy_demo_cam.png", "discrepancy_demo_pendulum.png", "discrepancy_demo.json",
                            "synthetic/held_out_10deg.csv", "synthetic/held_out_15deg.csv"],
    "discovery_demo.py": ["discovery.png", "discovery_cam.png", "discovery.json", "discovery.md",
                          "synthetic/discovery_demo.rig.json", "synthetic/discovery_cam.rig.json",
                          "synthetic/discovery_spring.rig.json"],
    "diagnosis_sweep.py": ["diagnosis_sweep.json", "diagnosis_sweep.md"],
    "diagnosis_realism.py": ["diagnosis_realism.json", "diagnosis_realism.md", "diagnosis_realism.png"],
    "benchmark.py": ["benchmark.json", "benchmark.md"],
    "spring_reading.py": ["spring_reading.json", "spring_reading.md"],
    "vcb_closing.py": ["vcb_closing_fig12.png", "vcb_closing_detail.png", "vcb_closing_energy_split.png",
                       "vcb_closing_analyser.png", "vcb_closing.json", "vcb_closing.md",
                       "synthetic/vcb_closing.csv"],
    "vcb_cycle.py": ["vcb_cycle.json", "vcb_cycle.md", "vcb_cycle.png", "synthetic/vcb_cycle.rig.json"],
    "design_sensitivity.py": ["design_sensitivity_tornado.png", "design_sensitivity_sobol.png",
                              "design_sensitivity.json", "design_sensitivity.md"],
    "design_tolerance.py": ["design_tolerance.png", "design_tolerance.json", "design_tolerance.md",
                            "design_tolerance_runs.csv"],
    "design_conclusion_map.py": ["design_conclusion_map.png", "design_conclusion_map.json", "design_conclusion_map.md"],
    "design_optimum.py": ["design_optimum.png", "design_optimum.json", "design_optimum.md"],
}


#: Smoke runs over half a minute each on 2 cores: run with plain `python -m pytest` (CI keeps the default
#: suite within 4 minutes; `studies/run_all.py` runs every study, the sweep machinery is tested in
#: test_sweep.py, the spring models and the closing by tests/models, discovery by tests/workflows).
SLOW = {"design_sensitivity.py", "design_tolerance.py", "design_optimum.py", "benchmark.py", "spring_models.py",
        "vcb_closing.py", "discovery_demo.py"}


@pytest.mark.parametrize("script", [pytest.param(s, marks=pytest.mark.slow) if s in SLOW else s for s in sorted(EXPECTED)])
def test_study_runs_and_writes_outputs(script, tmp_path):
    p = subprocess.run([sys.executable, str(STUDIES / script), "--quick", "--out", str(tmp_path)],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr[-2000:]
    for name in EXPECTED[script]:
        f = tmp_path / name
        assert f.exists() and f.stat().st_size > 100, name
    for f in tmp_path.glob("*.json"):
        json.loads(f.read_text())
    for f in tmp_path.glob("*.png"):
        assert f.stat().st_size < 500_000  # small enough to commit


def test_every_study_is_smoke_tested():
    scripts = {p.name for p in STUDIES.glob("*.py") if not p.name.startswith("_") and p.name != "run_all.py"}
    assert scripts == set(EXPECTED)


def _load_study(name):
    spec = importlib.util.spec_from_file_location(name, STUDIES / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_run_all_runs_every_study_once_and_the_benchmark_alone():
    run_all = _load_study("run_all")
    assert sorted(run_all.STUDIES) == sorted(EXPECTED)
    assert len(set(run_all.STUDIES)) == len(run_all.STUDIES)
    assert "benchmark.py" in run_all.ALONE and "benchmark.py" not in run_all.QUEUE  # its wall times are the speed evidence
    assert run_all.QUEUE[0] == "diagnosis_realism.py"  # the longest first


def test_run_all_lanes_drain_one_queue_each_study_once():
    import threading
    run_all = _load_study("run_all")
    ran, lock, rest_done = [], threading.Lock(), threading.Event()

    class Fake:
        take = run_all.Runner.take

        def run(self, script):  # the long study lasts until the other lane has run the rest (at most 10 s)
            if script == "long":
                rest_done.wait(timeout=10)
            with lock:
                ran.append((script, threading.current_thread().name))
                if sum(s != "long" for s, _ in ran) == 8:
                    rest_done.set()

    queue = ["long"] + [f"s{i}" for i in range(8)]
    threads = [threading.Thread(target=Fake().take, args=(queue, lock), name=f"lane{k}") for k in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert sorted(s for s, _ in ran) == sorted(["long"] + [f"s{i}" for i in range(8)]) and not queue
    long_lane = next(lane for s, lane in ran if s == "long")
    assert all(lane != long_lane for s, lane in ran if s != "long")  # the other lane took the rest meanwhile


#: Run in a fresh process (the study forks its record workers; a test worker may run threads): the
#: realism study's plan replaced by six tasks whose results come back in another order than the plan's.
ORDER_SCRIPT = """
import json, sys, time
sys.path.insert(0, sys.argv[1])
import diagnosis_realism as S
S.plan = lambda quick: [("hybrid", "clean", [("pend_none", k) for k in range(6)], None)]
def fake(task):
    kind, group, case, seed, t_end, folder = task
    time.sleep(0.05 * (seed % 3))
    return {"friction_truth": kind, "group": group, "case": case, "seed": seed, "named": [], "explained": True,
            "hit": True, "verdict_right": True, "rms_before_over_noise": 1.0, "rms_after_over_noise": 1.0,
            "comparisons": [], "seconds": 0.0, "cpu_seconds": 0.0}
S._made_and_diagnosed = fake
print(json.dumps([[r["seed"] for r in S.diagnose_plan(True, "unused", workers=w)] for w in (1, 2, 3)]))
"""


FAKE_STUDY = """import sys, time
from pathlib import Path
out = Path(sys.argv[sys.argv.index("--out") + 1])
for k in range(300):
    print(f"NAME: progress line {k}", {"a": k})  # chatter, a raw dict: the log's, not the console's
time.sleep(PAUSE)
(out / "NAME.json").write_text("{}")
(out / "synthetic").mkdir(exist_ok=True)
(out / "synthetic" / "NAME.csv").write_text("t,x")
(out / "shared_figure_FIGURE.png").write_text("png")
sys.exit(STATUS)
"""


def fake_run_all(tmp_path, monkeypatch, statuses):
    """run_all over fake studies (two lanes and one alone): its console and its log."""
    run_all = _load_study("run_all")
    folder = tmp_path / "studies"
    folder.mkdir()
    for k, (name, status) in enumerate(statuses.items()):
        text = FAKE_STUDY.replace("NAME", name).replace("PAUSE", str(1.5 if k == 0 else 0.05))
        (folder / f"{name}.py").write_text(text.replace("STATUS", str(status)).replace("FIGURE", str(k)))
    names = [f"{n}.py" for n in statuses]
    monkeypatch.setattr(run_all, "HERE", folder)
    monkeypatch.setattr(run_all, "QUEUE", names[:-1])
    monkeypatch.setattr(run_all, "ALONE", names[-1:])
    monkeypatch.setattr(run_all, "STUDIES", names)
    out, log = tmp_path / "out", tmp_path / "run.log"
    out.mkdir()
    monkeypatch.setattr(sys, "argv", ["run_all.py", "--quick", "--out", str(out), "--log", str(log)])
    return run_all, out, log


def test_run_all_prints_one_line_per_study_with_its_files_and_logs_the_rest(tmp_path, monkeypatch, capsys):
    run_all, out, log = fake_run_all(tmp_path, monkeypatch, {"long_one": 0, "alpha": 0, "beta": 0, "bench": 0})
    run_all.main()
    lines = capsys.readouterr().out.strip().splitlines()
    assert len(lines) == 6 and lines[0].startswith("run_all: 4 studies") and str(log) in lines[-1]
    by_study = {line.split()[0]: line for line in lines[1:-1]}
    assert set(by_study) == {"long_one.py", "alpha.py", "beta.py", "bench.py"}
    assert "progress line" not in "\n".join(lines) and "{" not in "\n".join(lines)
    for name, k in (("alpha", 1), ("beta", 2), ("bench", 3)):
        files = by_study[f"{name}.py"].split("processor)", 1)[1]
        assert f"{name}.json" in files and f"synthetic/{name}.csv" in files and f"shared_figure_{k}.png" in files
        assert "long_one" not in files
    assert "long_one.json" in by_study["long_one.py"] and "alpha" not in by_study["long_one.py"]
    text = log.read_text()
    assert text.count("progress line 299") == 4 and "== beta.py (exit status 0" in text
    assert json.loads((out / "run_all_timing.json").read_text())["quick"] is True


def test_run_all_shows_a_failed_studys_last_lines(tmp_path, monkeypatch, capsys):
    run_all, _, log = fake_run_all(tmp_path, monkeypatch, {"long_one": 0, "broken": 3, "never": 0})
    with pytest.raises(SystemExit) as e:
        run_all.main()
    printed = capsys.readouterr().out
    assert "broken.py" in str(e.value) and str(log) in str(e.value)
    assert "FAILED (exit status 3)" in printed and "   | broken: progress line 299" in printed
    assert "never.py" not in printed  # no study starts after a failure


def test_realism_study_records_come_back_in_the_plan_order_from_its_workers():
    p = subprocess.run([sys.executable, "-c", ORDER_SCRIPT, str(STUDIES)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr[-2000:]
    one, two, three = json.loads(p.stdout.strip().splitlines()[-1])
    assert one == two == three == list(range(6))


def test_closing_study_compares_main_shafts_like_with_like():
    """The pole-spread variants differ from the reference breaker only in their main shaft: rigid (the
    section removed), the middle drive, the first estimate's thinner shaft; springs, cam, poles and follower.inertia equal."""
    from vcbmodel import parameters as P
    sys.path.insert(0, str(STUDIES))
    try:
        study = _load_study("vcb_closing")
    finally:
        sys.path.remove(str(STUDIES))
    variants = list(study.shaft_variants(P.REFERENCE_BREAKER).values())
    assert len(variants) == 4
    rigid, ref, middle, thin = variants
    assert "main_shaft" not in rigid["breaker"] and ref["breaker"]["main_shaft"] == P.MAIN_SHAFT_SECTION
    assert middle["breaker"]["main_shaft"]["drive_pole"] == 2
    assert thin["breaker"]["main_shaft"]["diameter"] == P.MAIN_SHAFT_FIRST_ESTIMATE_DIAMETER < P.MAIN_SHAFT_SECTION["diameter"]
    for d in variants:
        rest = {k: v for k, v in d["breaker"].items() if k != "main_shaft"}
        assert rest == {k: v for k, v in P.REFERENCE_BREAKER["breaker"].items() if k != "main_shaft"}
        assert {k: v for k, v in d.items() if k != "breaker"} == {k: v for k, v in P.REFERENCE_BREAKER.items() if k != "breaker"}
    assert P.REFERENCE_BREAKER["breaker"]["main_shaft"]["drive_pole"] == 1  # the source dict is not changed


def test_run_all_refuses_a_log_option_without_a_file_in_one_line():
    run_all = _load_study("run_all")
    assert run_all.split_log(["--quick", "--log", "x.log"])[0] == ["--quick"]
    with pytest.raises(SystemExit, match="--log needs a file name"):
        run_all.split_log(["--quick", "--log"])


def test_the_tolerance_study_prints_its_draws_to_four_figures(monkeypatch):
    monkeypatch.syspath_prepend(str(STUDIES))  # the studies import their _common
    draw_text = _load_study("design_tolerance").draw_text
    assert draw_text("uniform:0.0040000000000000036:0.097") == "uniform 0.004-0.097"
    assert draw_text("uniform:0.5:0.8999999999999999") == "uniform 0.5-0.9"
    assert draw_text("normal:0.3:0.002063532571516432") == "normal 0.3, sd 0.002064"


def test_the_tolerance_study_counts_a_build_that_does_not_latch_as_out(monkeypatch):
    """A build whose cam turns back short of its latch (latched 0), or whose run ends first (empty),
    is out of the latching limit, as a failed run is; the kinetic margin's spread is over the builds
    that latch."""
    monkeypatch.syspath_prepend(str(STUDIES))
    study = _load_study("design_tolerance")
    poles = {f"pole_{i}_{k}": [1.2] * 4 if k == "zone_speed_m_s" else [1e-3] * 4
             for i in (1, 2, 3) for k in ("zone_speed_m_s", "bounce_s")}
    df = pd.DataFrame({"status": ["ok", "ok", "ok", "failed: x"], "pole_spread_s": [1e-4] * 4,
                       "latched": [1.0, 0.0, np.nan, np.nan], "kinetic_margin_J": [50.0, np.nan, np.nan, np.nan],
                       **poles})
    bad = study.out_of_limits(df, 3)
    assert list(bad["latches"]) == [False, True, True, True] and not bad["zone_speed"][:3].any()
    m = study.margin_summary(df, {"kinetic_margin_J": 78.5, "kinetic_at_touch_J": 282.0})
    assert (m["latched"], m["turned_back_short"], m["run_ended_first"], m["failed_or_not_closed"]) == (1, 1, 1, 1)
    assert m["min_J"] == m["median_J"] == 50.0


def test_the_optimum_must_latch(monkeypatch):
    """A design whose cam turns back short of its latch is infeasible whatever its speed; one whose run
    ended before the latch is not judged on it; the table says which."""
    monkeypatch.syspath_prepend(str(STUDIES))
    study = _load_study("design_optimum")
    ok = {"closing_speed_m_s": 1.25, "closing_time_s": 0.04, "zone_speed_min_m_s": 1.24, "zone_speed_max_m_s": 1.26,
          "pole_spread_s": 5e-4, "preload_N": 3000.0, "min_spring_force_N": 500.0, "latched": True,
          "kinetic_margin_J": 60.0, "kinetic_at_touch_J": 270.0}
    assert study.violation(ok) == 0.0 and study.margin_text(ok) == "60.0 of 270"
    short = dict(ok, latched=False, kinetic_margin_J=None)
    assert study.violation(short) == 1.0 and study.margin_text(short) == "not latched"
    assert study.violation(dict(short, latched=0.0)) == 1.0  # as read back from a sweep's table
    assert study.violation(dict(short, latched=None)) == 0.0 and study.margin_text(dict(short, latched=None)) == "-"


def test_run_all_prints_a_study_only_when_no_running_study_overlaps_it(tmp_path, capsys):
    """A study that ran beside one still running may yet lose files to it: its line waits until the
    other finishes, so each file is attributed with both studies' changes known."""
    run_all = _load_study("run_all")
    runner = run_all.Runner([], tmp_path, tmp_path / "log")
    for name, span, files in (("short_one.py", (1.0, 2.0), {"shared.csv", "long_one.json"}),
                              ("long_one.py", (0.5, 3.0), {"shared.csv", "long_one.json"})):
        runner.span[name], runner.changed[name] = span, files
        runner.status[name], runner.wall[name], runner.cpu[name] = "ok", span[1] - span[0], 0.0
    runner.running = {"long_one.py": 0.5}
    runner.pending = ["short_one.py"]
    runner.flush()
    assert capsys.readouterr().out == ""  # long_one is still running beside it
    runner.running = {}
    runner.pending.append("long_one.py")
    runner.flush()
    lines = capsys.readouterr().out.strip().splitlines()
    assert [line.split()[0] for line in lines] == ["short_one.py", "long_one.py"]
    assert "long_one.json" not in lines[0] and "shared.csv" in lines[0] and "long_one.json" in lines[1]


def _states(procs, want):
    """The processes' states (/proc: T stopped, S sleeping) once all read ``want`` or after 5 s."""
    import time
    for _ in range(100):
        states = [Path(f"/proc/{p.pid}/stat").read_text().rsplit(")", 1)[1].split()[0] for p in procs]
        if all(x == want for x in states):
            break
        time.sleep(0.05)
    return states


def test_benchmark_freezes_the_clusters_it_is_not_timing(tmp_path, monkeypatch):
    """While one variant is timed every other cluster is stopped (an idle Dask cluster takes processor time
    from the measured sweep); the one timed is running again, and a frozen cluster still ends on exit."""
    monkeypatch.syspath_prepend(str(STUDIES))  # the studies import their _common
    benchmark = _load_study("benchmark")

    class Sleeping(benchmark.DaskCluster):  # the benchmark's cluster with `sleep` in place of dask's processes
        def __enter__(self):
            self.procs = [subprocess.Popen(["sleep", "60"], start_new_session=True) for _ in range(2)]
            return self

    clusters = [Sleeping(tmp_path / str(w), w).__enter__() for w in (1, 2)]
    try:
        benchmark.only_running(clusters, None)  # a local sweep: all frozen
        assert _states([p for c in clusters for p in c.procs], "T") == ["T"] * 4
        benchmark.only_running(clusters, clusters[1])  # Dask on the second: it runs, the first stays frozen
        assert _states(clusters[1].procs, "S") == ["S", "S"]
        assert _states(clusters[0].procs, "T") == ["T", "T"]
    finally:
        for c in clusters:
            c.__exit__(None, None, None)
    assert all(p.poll() is not None for c in clusters for p in c.procs)


def test_the_benchmark_counts_one_worker_in_the_singular(monkeypatch):
    """benchmark.md read '1 workers 2.8 %' for the idle 1-worker cluster."""
    monkeypatch.syspath_prepend(str(STUDIES))  # the studies import their _common
    table = _load_study("benchmark").scaling_table(
        {"weak_scaling": [], "closings_per_worker": 10, "simulated_with": "the compiled path", "rounds": 3, "cores": 2,
         "load_average_before_after": [[1.0], [1.0]], "idle_cluster_processor_share": {"1": 0.028, "2": 0.043}})
    assert "idle, each took this share of one core (its scheduler and workers, nannies not counted): " \
           "1 worker 2.8 %, 2 workers 4.3 %." in table


def test_benchmark_sweeps_run_each_in_a_process_of_its_own(tmp_path, monkeypatch):
    """The benchmark's timed sweeps: each in a child the sweep server forks after its imports (a process of its
    own: its pid is new each time, the server's stays), every run done; a failing sweep is an error naming
    its cause, and the server goes on; closing the server's input ends it."""
    monkeypatch.syspath_prepend(str(STUDIES))
    benchmark = _load_study("benchmark")
    from vcbmodel import parameters as P

    rig = tmp_path / "breaker.rig.json"
    rig.write_text(json.dumps(P.REFERENCE_BREAKER))
    runs = tmp_path / "runs.json"
    runs.write_text(json.dumps([{"friction.mu_k": 0.12}, {"friction.mu_k": 0.14}]))
    with benchmark.SweepServer() as server:
        first = server.timed_sweep(rig, runs, workers=1)
        with pytest.raises(RuntimeError, match="(?s)timed sweep failed.*no_such_runs"):
            server.timed_sweep(rig, tmp_path / "no_such_runs.json", workers=1)
        second = server.timed_sweep(rig, runs, workers=1)
        assert first["ok"] == second["ok"] == first["runs"] == 2
        assert first["wall_s"] > 0 and first["cpu_s"] > 0
        assert first["pid"] != second["pid"] and server.proc.pid not in (first["pid"], second["pid"])
        proc = server.proc
    assert proc.poll() is not None

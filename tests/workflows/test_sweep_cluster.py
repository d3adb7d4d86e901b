"""A sweep on a real cluster and the local pool's workers (docs/cli.md, "vcbmodel sweep"): a Dask
scheduler and workers started as separate processes with the ``dask scheduler`` / ``dask worker``
command lines give the local rows; a worker that lacks Exudyn or a C compiler is refused before any
run, in one line naming it; a points-file cam travels inside the task; runs go in chunks sized from
measured run times; a local sweep's workers die with it after ``kill -9``."""
import copy
import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from vcbmodel import parameters as P
from vcbmodel.analysis import sweep as S
from vcbmodel.analysis.sweep import executors
from vcbmodel.app.cli import main
from vcbmodel.compiled import compiler_works

distributed = pytest.importorskip("distributed")
ROOT = Path(__file__).resolve().parents[2]


def pendulum_rig(folder):
    path = Path(folder) / "p.rig.json"
    path.write_text(json.dumps(dict(copy.deepcopy(P.REFERENCE_PENDULUM), friction=dict(P.REFERENCE_PENDULUM_TRUTH))))
    return str(path)


def points_file_rig(folder):
    """The reference breaker with its 4-5-6-7 cam given as a points file beside the rig (the pitch
    radius every 2 degrees, in mm)."""
    from vcbmodel.experiments.loading import rig_from_data
    from vcbmodel.laws.cam_follower import TWO_PI, pitch_radius

    data = copy.deepcopy(P.REFERENCE_BREAKER)
    breaker = rig_from_data(copy.deepcopy(data)).breaker
    angles = np.linspace(0.0, TWO_PI, 181)[:-1]
    radii = [pitch_radius(float(a), breaker.profile, breaker.roller_radius)[0] for a in angles]
    lines = ["angle_deg,radius_mm"] + [f"{float(np.degrees(a))!r},{1e3 * float(r)!r}" for a, r in zip(angles, radii)]
    (Path(folder) / "cam.csv").write_text("\n".join(lines) + "\n")
    data["breaker"]["cam_profile"] = {"points_file": "cam.csv"}
    path = Path(folder) / "b.rig.json"
    path.write_text(json.dumps(data))
    return str(path)


def dask_command(*args):
    return [sys.executable, "-m", "dask", *args]


def environment(base, changes):
    """``base`` with ``changes`` applied; a change to None removes the variable."""
    env = dict(base)
    for k, v in changes.items():
        env.pop(k, None) if v is None else env.__setitem__(k, v)
    return env


def start_cluster(folder, workers):
    """``dask scheduler`` and ``dask worker`` processes (one thread each); returns (address, processes)."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    address_file = folder / "scheduler.json"
    base = dict(os.environ, PYTHONPATH=str(ROOT), DASK_DISTRIBUTED__WORKER__DAEMON="False")
    procs = [subprocess.Popen(dask_command("scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                                           "--scheduler-file", str(address_file)),
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=base, start_new_session=True)]
    for extra in workers:
        procs.append(subprocess.Popen(dask_command("worker", "--scheduler-file", str(address_file), "--nworkers", "1",
                                                   "--nthreads", "1", "--no-dashboard", "--host", "127.0.0.1"),
                                      stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=environment(base, extra),
                                      cwd=folder, start_new_session=True))
    deadline = time.time() + 60
    while not address_file.exists() and time.time() < deadline:
        time.sleep(0.2)
    address = json.loads(address_file.read_text())["address"]
    with distributed.Client(address, timeout=30) as client:
        client.wait_for_workers(len(workers), timeout=60)
    return address, procs


def stop(procs):
    for p in procs:
        try:
            os.killpg(p.pid, signal.SIGTERM)
        except ProcessLookupError:
            pass
    for p in procs:
        try:
            p.wait(timeout=10)
        except subprocess.TimeoutExpired:
            os.killpg(p.pid, signal.SIGKILL)


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    address, procs = start_cluster(tmp_path_factory.mktemp("cluster"), [{}, {}])
    yield address
    stop(procs)


def rows(table):
    return table.reset_index(drop=True)


def test_a_cluster_of_separate_processes_gives_the_local_rows(cluster, tmp_path, capsys):
    rig = pendulum_rig(tmp_path)
    vary = ["friction.mu_k=0.08:0.16:5"]
    local = S.sweep(rig, vary, workers=1, t_end=1.0, verbose=False)
    remote = S.sweep(rig, vary, scheduler=cluster, t_end=1.0, verbose=False)
    pd.testing.assert_frame_equal(rows(remote), rows(local))
    assert remote.attrs["scheduler"] == cluster and remote.attrs["workers"] is None
    out = tmp_path / "remote.csv"
    assert main(["sweep", rig, "--vary", "friction.mu_k=0.08:0.16:3", "--scheduler", cluster, "-o", str(out)]) == 0
    assert [r.split(",")[-1] for r in out.read_text().splitlines() if not r.startswith("#")][1:] == ["ok"] * 3
    assert f"on Dask cluster {cluster}" in capsys.readouterr().err


@pytest.mark.slow  # 21 s on a busy 2-core machine: two command-line sweeps on Exudyn
def test_an_interrupted_cluster_sweep_cancels_its_tasks_and_resumes(cluster, tmp_path):
    """SIGTERM while the cluster works: the rows so far stay, no task is left running on the workers,
    and --resume on the same cluster adds the rest (each run once, in run order)."""
    rig = pendulum_rig(tmp_path)
    out = tmp_path / "t.csv"
    # on Exudyn (a tenth of a second a run) the signal lands while the runs go
    args = ["sweep", rig, "--vary", "friction.mu_k=0.05:0.2:30", "--scheduler", cluster, "-o", str(out),
            "--backend", "exudyn"]
    p = subprocess.Popen([sys.executable, "-m", "vcbmodel", *args], stderr=subprocess.PIPE, text=True,
                         env=dict(os.environ, PYTHONPATH=str(ROOT)))
    deadline = time.time() + 120
    while time.time() < deadline and not (out.exists() and out.read_text().count("\n") >= 3):
        time.sleep(0.1)
    p.send_signal(signal.SIGTERM)
    p.wait(timeout=60)
    err = p.stderr.read()
    assert p.returncode == 128 + signal.SIGTERM and "Traceback" not in err and "--resume" in err
    assert 0 < len([r for r in out.read_text().splitlines() if not r.startswith("#")]) - 1 < 30  # rows so far
    with distributed.Client(cluster) as client:
        deadline = time.time() + 20
        while time.time() < deadline and any(client.processing().values()):
            time.sleep(0.2)
        assert not any(client.processing().values())
    assert main([*args, "--resume"]) == 0
    rows = [r for r in out.read_text().splitlines() if not r.startswith("#")][1:]  # the rig's fingerprint, the header
    assert [int(r.split(",")[0]) for r in rows] == list(range(1, 31)) and all(r.endswith(",ok") for r in rows)


def test_a_points_file_cam_travels_inside_the_task(cluster, tmp_path):
    """The file is read once where the sweep starts: the runs need no copy of it (here: run after it
    is deleted) and the cluster's rows are the local ones."""
    rig = points_file_rig(tmp_path)
    runs = [{"friction.mu_k": 0.12}, {"friction.mu_k": 0.14}]
    plan = S.plan(rig, runs=runs)
    assert "points_file" not in plan.shipped["breaker"]["cam_profile"]
    assert "points_file" in plan.data["breaker"]["cam_profile"]  # the rig as given is not changed
    local = S.sweep(rig, runs=runs, workers=1, verbose=False)
    remote = S.sweep(rig, runs=runs, scheduler=cluster, verbose=False)
    assert list(local.status) == ["ok", "ok"]
    pd.testing.assert_frame_equal(rows(remote), rows(local))
    job = S.SweepJob(plan.shipped, plan.rig_path)
    before = S.run_chunk(job, [(1, runs[0])])
    (tmp_path / "cam.csv").unlink()
    after = S.run_chunk(job, [(1, runs[0])])
    assert after[0][2] == "ok" and after[0][1] == before[0][1]


SITE_WITHOUT_EXUDYN = """
import importlib.abc, sys
class _NoExudyn(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name == "exudyn" or name.startswith("exudyn."):
            raise ImportError("libGL.so.1: cannot open shared object file: No such file or directory")
sys.meta_path.insert(0, _NoExudyn())
"""


@pytest.mark.parametrize("lack", ["exudyn", "compiler"])
def test_a_worker_without_exudyn_or_a_compiler_is_refused_before_any_run(lack, tmp_path, capsys):
    if lack == "exudyn":
        site = tmp_path / "site"
        site.mkdir()
        (site / "sitecustomize.py").write_text(textwrap.dedent(SITE_WITHOUT_EXUDYN))
        env = {"PYTHONPATH": f"{site}{os.pathsep}{ROOT}"}
    else:  # no gcc/cc on PATH and no CC: only the Python interpreter's own folder
        if not compiler_works():
            pytest.skip("no C compiler here: the sweep runs on Exudyn and needs none on its workers")
        env = {"PATH": str(Path(sys.executable).parent), "CC": None}
    address, procs = start_cluster(tmp_path / "cluster", [env])
    try:
        with distributed.Client(address) as client:
            bad = list(client.scheduler_info()["workers"])[0]
        rig = pendulum_rig(tmp_path)
        out = tmp_path / "never.csv"
        t0 = time.perf_counter()
        code = main(["sweep", rig, "--vary", "friction.mu_k=0.08:0.16:3", "--scheduler", address, "-o", str(out)])
        seconds = time.perf_counter() - t0
    finally:
        stop(procs)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and not out.exists()
    assert bad in err[0] and "no run was started" in err[0]
    assert ("lacks Exudyn" in err[0] and "libGL" in err[0]) if lack == "exudyn" else "lacks a C compiler" in err[0]
    assert seconds < 30, seconds  # "in seconds": the check, not a failed run, refuses it


def test_chunks_are_sized_from_the_measured_run_time():
    jobs = [(i, {}) for i in range(1, 1001)]
    chunker = executors.Chunker(jobs, workers=2)
    assert len(chunker.take()) == 1  # nothing measured yet
    chunker.record([0.01] * 5)
    assert len(chunker.take()) == round(executors.TASK_SECONDS / 0.01)
    chunker.record([0.5] * 400)  # slower runs: fewer per chunk (the median of the latest)
    assert len(chunker.take()) == round(executors.TASK_SECONDS / 0.5)
    chunker.record([1e-4] * 400)
    left = len(jobs) - chunker.taken
    assert len(chunker.take()) == -(-left // (executors.IN_FLIGHT * 2))  # near the end: the rest shared out
    while chunker.take():
        pass
    assert chunker.taken == len(jobs)


def children_of(pid):
    out = subprocess.run(["ps", "-o", "pid=", "--ppid", str(pid)], capture_output=True, text=True).stdout
    return [int(x) for x in out.split()]


def alive(pid):
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_the_workers_of_a_local_sweep_die_with_it_after_kill_9(tmp_path):
    rig = pendulum_rig(tmp_path)
    out = tmp_path / "killed.csv"
    p = subprocess.Popen([sys.executable, "-m", "vcbmodel", "sweep", rig, "--vary", "friction.mu_k=0.05:0.2:400",
                          "--workers", "2", "-o", str(out)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                         env=dict(os.environ, PYTHONPATH=str(ROOT)))
    workers = []
    try:
        deadline = time.time() + 60
        while time.time() < deadline and (not out.exists() or
                                          len([r for r in out.read_text().splitlines() if not r.startswith("#")]) < 2):
            time.sleep(0.1)
        workers = children_of(p.pid)
        assert len(workers) >= 2 and all(alive(w) for w in workers)
        os.kill(p.pid, signal.SIGKILL)
        p.wait(timeout=10)
        deadline = time.time() + 10
        while time.time() < deadline and any(alive(w) for w in workers):
            time.sleep(0.1)
        assert not any(alive(w) for w in workers)
    finally:
        if p.poll() is None:
            p.kill()
        for w in workers:  # a failing run leaves none behind
            if alive(w):
                os.kill(w, signal.SIGKILL)

"""Ctrl-C in a terminal, and a batch system's SIGTERM, reach every process of the command: the fit pool's
workers leave both to the parent (which prints one line and stops the pool) instead of printing their own
tracebacks or dying while they send a result (docs/cli.md, "Exit status")."""
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from vcbmodel.analysis.fit import Dataset, Objective, SimulationPool, make_parameters, run_job
from vcbmodel.analysis.synthetic import synthetic_measurement

EFFECTS = ("coulomb_friction",)


@pytest.fixture
def jobs(pendulum_rig):
    meas = synthetic_measurement(pendulum_rig, EFFECTS, {"mu_k": 0.11, "stick_velocity": 1e-3}, seed=0, t_end=0.5)
    params = make_parameters(pendulum_rig, EFFECTS)
    obj = Objective([Dataset(pendulum_rig, meas)], EFFECTS, pendulum_rig.model.spring_model, params)
    values = obj.values(obj.x0())
    return [obj.simulation_job({**values, "mu_k": mu_k}, 0) for mu_k in (0.09, 0.12)]


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except FileNotFoundError:
        return False


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="reads the workers' state from /proc")
def test_the_workers_leave_ctrl_c_and_sigterm_to_the_parent(jobs):
    pool = SimulationPool(2, kept_bytes=0)
    try:
        workers = list(pool.pool._processes)
        assert len(workers) == 2
        for pid in workers:
            os.kill(pid, signal.SIGINT)
            os.kill(pid, signal.SIGTERM)
        time.sleep(0.5)
        assert all(_alive(pid) for pid in workers)
        out = pool.run(jobs)  # the pool still answers: no worker died mid-result
        for got, job in zip(out, jobs):
            np.testing.assert_array_equal(got["pendulum_angle"], run_job(job)["pendulum_angle"])
    finally:
        pool.close()


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the kernel's parent-death signal (prctl)")
def test_the_workers_end_with_their_parent_even_on_kill_9():
    """Ignoring SIGTERM must not leave orphans: a parent killed with SIGKILL takes its workers with it."""
    script = ("import os, signal, sys\n"
              "from vcbmodel.analysis.fit import SimulationPool\n"
              "pool = SimulationPool(2)\n"
              "print(' '.join(str(p) for p in pool.pool._processes), flush=True)\n"
              "sys.stdin.read()\n")
    parent = subprocess.Popen([sys.executable, "-c", script], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
    try:
        workers = [int(p) for p in parent.stdout.readline().split()]
        assert len(workers) == 2 and all(_alive(pid) for pid in workers)
        parent.kill()
        parent.wait(timeout=10)
        deadline = time.monotonic() + 5
        while any(_alive(pid) for pid in workers) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not any(_alive(pid) for pid in workers)
    finally:
        parent.kill()

"""A badly wrong trial's arithmetic (a runaway simulation, its Jacobian, its covariance) overflows to
inf or nan without numpy's RuntimeWarning lines on stderr (vcbmodel/analysis/fit/arithmetic.py),
and the values stay what they were: a non-finite objective is still a failed trial."""
import copy
import subprocess
import sys
import warnings

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.analysis.fit.covariance import parameter_covariance
from vcbmodel.analysis.fit.optimisers import levenberg_marquardt
from vcbmodel.experiments.loading import load_rig
from vcbmodel.experiments.simulation import simulate

from conftest import write_rig


class RunawayTrial:
    """A residual of 1e160 (x - 1): finite, but its square and J^T J overflow (a trial whose
    simulation diverged to enormous but finite numbers)."""

    def residual(self, x):
        return 1e160 * (np.asarray(x, float) - 1.0)

    def jacobian(self, x, scale=1.0):
        return 1e160 * np.eye(len(x))

    def prior_jacobian_fix(self, J, x):
        return J


def test_a_runaway_trial_overflows_without_a_warning_and_stays_a_failed_trial():
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any RuntimeWarning fails the test
        x, cost, J, _, message = levenberg_marquardt(RunawayTrial(), np.array([2.0, 3.0]), np.full(2, -10.0),
                                                     np.full(2, 10.0), 10)
    # the overflowed chi^2 is inf, as before: no step is accepted from it (a failed trial, not a fit)
    assert cost == np.inf and list(x) == [2.0, 3.0] and "no further descent" in message
    assert np.all(np.isfinite(J))


def test_a_runaway_jacobians_covariance_has_no_warning():
    rng = np.random.default_rng(0)
    J, r = 1e200 * rng.normal(size=(400, 2)), rng.normal(size=400)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        cov = parameter_covariance(["a", "b"], J, r, [400], 398)
    assert cov.naive.shape == cov.covering.shape == (2, 2)


@pytest.mark.slow
def test_diagnose_of_a_record_in_degrees_prints_no_runtime_warning(tmp_path):
    """A 2.5 deg release recorded in degrees without its unit, its rig saying 2 deg (so the degrees
    check, which needs the first sample within 10 % of the rig's start, lets it through): the fits run
    away (the discovered drag term's refit reaches residuals of 1e108; measured 17 RuntimeWarning lines
    from the optimisers, the covariance and scipy's fftconvolve before the fix). The command ends with
    its verdict and nothing from numpy (about 35 s on 2 cores)."""
    data = copy.deepcopy(P.REFERENCE_PENDULUM)
    data["pendulum"]["initial_angle"] = np.radians(2.5)
    data["friction"] = {"mu_k": 0.13, "mu_s": 0.2, "viscous": 0.6, "stribeck_velocity": 0.01}
    truth = load_rig(write_rig(tmp_path, data, "truth"))
    run = simulate(truth, backend="compiled", sample_times=np.arange(0, 6.0, 1e-3))
    noise = np.random.default_rng(1).normal(0.0, 0.03, run.t.size)
    record = tmp_path / "deg.csv"
    record.write_text("t,pendulum_angle\n" + "".join(f"{t:.7f},{np.degrees(a) + e:.5f}\n"
                                                      for t, a, e in zip(run.t, run.measured, noise)))
    data["friction"], data["pendulum"]["initial_angle"] = {}, np.radians(2.0)
    write_rig(tmp_path, data, "deg")
    p = subprocess.run([sys.executable, "-m", "vcbmodel", "diagnose", str(record), "-q"], capture_output=True,
                       text=True, timeout=600)
    assert p.returncode == 0, p.stderr[-2000:]
    assert "Warning" not in p.stderr, p.stderr[-2000:]
    assert "explained" in p.stdout

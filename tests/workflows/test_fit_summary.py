"""The fit's own summary (``[[Fit]]`` in ``diagnose``'s report): its numbers agree with each other on a
record of several channels (a breaker analyser's: the drive's travel, each pole's travel and contact)."""
import math

import numpy as np
import pytest

from vcbmodel.analysis.fit import FitResult, Parameter
from vcbmodel.analysis.fit.profile import scale_factor
from vcbmodel.rig.spring_model import SpringModel

SIGMA = 1e-5
N = 661


def test_reduced_chi2_counts_every_channel_it_sums():
    """chi^2 sums the measured channel's residual and the other channels' (each scaled by its noise);
    the reduced chi^2 divided it by the measured channel's samples alone, so a closing record with its
    three poles' travels at the noise read 'reduced chi2 4.235' beside 'rms 1.0x the noise'."""
    rng = np.random.default_rng(3)
    extra = {(0, f"pole_{k}_travel"): rng.normal(0.0, 1.0, N) for k in (1, 2, 3)}  # scaled: unit variance
    params = {"mu_k": Parameter("mu_k", 0.13), "release_time": Parameter("release_time", 0.0, kind="offset")}
    fit = FitResult(("coulomb_friction",), SpringModel(), params, [rng.normal(0.0, SIGMA, N)], [], SIGMA,
                    extra_residuals=extra)
    assert fit.n_varied == 2
    assert abs(fit.reduced_chi2 - 1.0) < 0.1, fit.reduced_chi2
    alone = FitResult(("coulomb_friction",), SpringModel(), params, fit.residuals, [], SIGMA)
    assert abs(alone.reduced_chi2 - 1.0) < 0.15 and fit.n_data == alone.n_data == N


def test_the_profile_scales_a_chi2_rise_by_the_covariance_s_residual_variance():
    """A profile puts a refit's chi^2 rise on the stated error's scale with se_naive^2 / s^2 = the
    Jacobian's (J^T J)^-1 diagonal (vcbmodel/analysis/fit/profile.py). The covariance's s^2 is the
    residual's over every fitted sample (the pole channels' too); the profile's divided the same chi^2 by
    the measured channel's samples alone, so on a three-pole record its rise read four times too small
    and the profile kept values the record rejects (an interval too wide, 'does not resolve')."""
    rng = np.random.default_rng(5)
    extra = {(0, f"pole_{k}_travel"): rng.normal(0.0, 1.0, N) for k in (1, 2, 3)}
    residual = rng.normal(0.0, SIGMA, N)
    dof = 4 * N - 1
    s2 = (float(np.sum(residual**2)) / SIGMA**2 + sum(float(np.sum(r**2)) for r in extra.values())) / dof
    bread, stated = 0.04, 0.3  # (J^T J)^-1 diagonal; a stated (covering) error wider than the naive one
    mu = Parameter("mu_k", 0.13, stderr=stated, stderr_naive=math.sqrt(bread * s2))
    fit = FitResult(("coulomb_friction",), SpringModel(), {"mu_k": mu}, [residual], [], SIGMA, extra_residuals=extra)
    assert scale_factor(fit, "mu_k") == pytest.approx(bread / stated**2, rel=1e-9)

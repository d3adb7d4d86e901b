"""The fit package's seams (issue 21): the options object, the abort callback, the objective
and the optimiser on their own, and the rooms' size and import order."""
import ast
import threading
from pathlib import Path

import numpy as np
import pytest

import vcbmodel.analysis.fit as fitpkg
from vcbmodel.analysis.fit import (Curves, Dataset, FitAborted, FitOptions, Objective, fit, levenberg_marquardt,
                                   make_parameters, refine, run_job, staged_fit)
from vcbmodel.analysis.synthetic import synthetic_measurement

MU_K = 0.11
EFFECTS = ("coulomb_friction",)
ROOMS = ["arithmetic", "parameters", "options", "dataset", "pool", "objective", "optimisers", "covariance", "result", "starts",
         "minimizer", "profile"]


@pytest.fixture
def short_swing(pendulum_rig):
    """One second of a synthetic free swing with Coulomb friction mu_k = MU_K."""
    meas = synthetic_measurement(pendulum_rig, EFFECTS, {"mu_k": MU_K, "stick_velocity": 1e-3}, seed=0, t_end=1.0)
    return Dataset(pendulum_rig, meas)


class CountingPool:
    """Runs jobs in this process and counts them (a stand-in for SimulationPool)."""

    def __init__(self):
        self.simulations = 0

    def run(self, jobs):
        jobs = list(jobs)
        self.simulations += len(jobs)
        return [run_job(j) for j in jobs]


# --- options ------------------------------------------------------------------------------------

def test_options_reject_an_unknown_option():
    with pytest.raises(TypeError, match="max_startz"):
        FitOptions.build(max_startz=3)


def test_fit_rejects_an_unknown_keyword_before_simulating(short_swing):
    pool = CountingPool()
    with pytest.raises(TypeError, match="stop"):
        fit([short_swing], EFFECTS, pool=pool, stop=threading.Event())  # the old keyword is gone
    assert pool.simulations == 0


def test_options_build_replaces_only_the_given_ones():
    base = FitOptions(label="a", max_starts=3, chi2_tolerance=0.5)
    opts = FitOptions.build(base, label="b")
    assert (opts.label, opts.max_starts, opts.chi2_tolerance) == ("b", 3, 0.5)
    assert base.label == "a"  # the given object is not changed
    assert FitOptions.build() == FitOptions()


# --- the abort callback ----------------------------------------------------------------------------

def test_should_stop_aborts_a_fit_before_its_next_simulation(short_swing, pendulum_rig):
    """The callback is asked before every batch of simulations: once it says stop, not one more
    simulation runs (a Levenberg-Marquardt iteration needs at least one batch)."""
    pool = CountingPool()
    params = make_parameters(pendulum_rig, EFFECTS, initial={"mu_k": 0.05})
    with pytest.raises(FitAborted):
        fit([short_swing], EFFECTS, params=params, pool=pool, verbose=False, should_stop=lambda: pool.simulations >= 1)
    assert pool.simulations == 1


def test_an_event_stops_a_fit_and_an_unset_one_does_not(short_swing, pendulum_rig):
    stop = threading.Event()
    stop.set()
    pool = CountingPool()
    with pytest.raises(FitAborted):
        fit([short_swing], EFFECTS, params=make_parameters(pendulum_rig, EFFECTS, initial={"mu_k": 0.05}), pool=pool,
            verbose=False, should_stop=stop.is_set)
    assert pool.simulations == 0
    r = fit([short_swing], EFFECTS, params=make_parameters(pendulum_rig, EFFECTS, initial={"mu_k": 0.05}), pool=pool,
            verbose=False, should_stop=threading.Event().is_set)
    assert r.parameters["mu_k"].value == pytest.approx(MU_K, rel=0.02)
    assert pool.simulations > 2


@pytest.mark.parametrize("entry", ["staged_fit", "refine"])
def test_every_entry_point_passes_the_callback_down(entry, short_swing, pendulum_rig):
    pool = CountingPool()
    params = make_parameters(pendulum_rig, EFFECTS, initial={"mu_k": 0.05})
    with pytest.raises(FitAborted):
        if entry == "staged_fit":
            staged_fit([short_swing], EFFECTS, None, params, pool=pool, verbose=False, should_stop=lambda: True)
        else:
            refine([short_swing], EFFECTS, pendulum_rig.model.spring_model, params, (None, None), pool=pool,
                   should_stop=lambda: True)
    assert pool.simulations == 0


# --- the objective alone ---------------------------------------------------------------------------

def test_objective_alone_scores_the_truth_at_the_noise(short_swing, pendulum_rig):
    params = make_parameters(pendulum_rig, EFFECTS, initial={"mu_k": MU_K})
    sigma = float(np.std(short_swing.y - _truth(short_swing, pendulum_rig)))
    obj = Objective([short_swing], EFFECTS, pendulum_rig.model.spring_model, params, scales={(0, "pendulum_angle"): sigma})
    assert [p.name for p in obj.varied] == ["mu_k"]
    x_true = obj.x0()
    r_true = obj.residual(x_true)
    assert r_true.shape == (short_swing.t.size,)
    assert float(np.dot(r_true, r_true)) / r_true.size == pytest.approx(1.0, rel=0.1)
    r_wrong = obj.residual(x_true * 0.5)
    assert float(np.dot(r_wrong, r_wrong)) > 100 * float(np.dot(r_true, r_true))
    assert obj.nfev == 2 and obj.best[0] == pytest.approx(float(np.dot(r_true, r_true)))
    obj.residual(x_true)
    assert obj.nfev == 2  # the same point again comes from the cache
    J = obj.jacobian(x_true)
    assert J.shape == (r_true.size, 1) and np.any(J != 0.0)
    h = obj.diff_step(0, x_true[0])
    fd = (obj.residual(x_true + h) - r_true) / h
    assert np.allclose(J[:, 0], fd)


def _truth(dataset, rig):
    """The noiseless model at mu_k = MU_K on the record's times."""
    obj = Objective([dataset], EFFECTS, rig.model.spring_model, make_parameters(rig, EFFECTS, initial={"mu_k": MU_K}))
    cur = obj.curves([obj.values(obj.x0())])[0][0]
    return cur.data["pendulum_angle"]


def test_curves_spline_through_the_samples():
    t = np.linspace(0.0, 1.0, 11)
    c = Curves({"t": t, "a": t**2})
    assert np.allclose(c.spline("a")(t), t**2)
    assert c.spline("a") is c.spline("a")  # built once


# --- the optimiser alone ---------------------------------------------------------------------------

class LinearObjective:
    """r = A x - b: Levenberg-Marquardt must land on the (bounded) least-squares solution."""

    def __init__(self, A, b):
        self.A, self.b = A, b

    def residual(self, x):
        return self.A @ x - self.b

    def jacobian(self, x, scale=1.0):
        return self.A.copy()

    def prior_jacobian_fix(self, J, x):
        return J


def test_levenberg_marquardt_solves_a_linear_problem_and_holds_a_bound():
    rng = np.random.default_rng(1)
    A = rng.normal(size=(40, 2))
    b = A @ np.array([1.5, -0.5]) + rng.normal(0.0, 0.01, 40)
    obj = LinearObjective(A, b)
    free = np.linalg.lstsq(A, b, rcond=None)[0]
    x, cost, J, ok, _ = levenberg_marquardt(obj, np.zeros(2), np.full(2, -10.0), np.full(2, 10.0), 50,
                                            chi2_tolerance=1e-12)
    assert ok and np.allclose(x, free, atol=1e-4) and J.shape == (40, 2)
    x, _, _, _, _ = levenberg_marquardt(obj, np.zeros(2), np.array([-10.0, 0.0]), np.full(2, 10.0), 50,
                                        chi2_tolerance=1e-12)
    assert x[1] == 0.0  # held at its lower bound
    # the bounded optimum, to the tolerance of a chi^2 that is not scaled by the noise here
    assert x[0] == pytest.approx(np.linalg.lstsq(A[:, :1], b, rcond=None)[0][0], rel=0.01)


@pytest.mark.parametrize("final_jacobian", [True, False])
def test_levenberg_marquardt_reaches_the_floor_of_a_narrow_valley(final_jacobian):
    """Two nearly collinear columns (as a swing's Coulomb, viscous and drag friction with its release
    time), started far along the valley: the first damped step predicts a chi^2 change under the
    tolerance while the Gauss-Newton step predicts 400; the fit must go on to the floor, to within the
    tolerance (2e-3 of the samples: 4) and one standard error."""
    rng = np.random.default_rng(2)
    u, v = rng.normal(size=2000), rng.normal(size=2000)
    A = np.column_stack([u, u + 3e-3 * v])
    b = A @ np.array([1.0, 1.0]) + rng.normal(size=2000)  # unit noise: the residual is already scaled
    obj = LinearObjective(A, b)
    best = np.linalg.lstsq(A, b, rcond=None)[0]
    floor = float(np.sum((A @ best - b) ** 2))
    x0 = np.array([151.0, -149.0])
    assert float(np.sum(obj.residual(x0) ** 2)) > floor + 400
    x, cost, _, ok, _ = levenberg_marquardt(obj, x0, np.full(2, -1e3), np.full(2, 1e3), 14,
                                            final_jacobian=final_jacobian)
    assert ok and cost <= floor + 4.0
    d = x - best
    assert d @ (A.T @ A) @ d <= 1.0  # within one standard error (Mahalanobis) of the least-squares point


# --- the rooms -------------------------------------------------------------------------------------

def _imports(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return {node.module for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) and node.level == 1}


def test_rooms_import_only_earlier_rooms_and_stay_small():
    folder = Path(fitpkg.__file__).parent
    assert sorted(p.stem for p in folder.glob("*.py")) == sorted(ROOMS + ["__init__"])
    for k, room in enumerate(ROOMS):
        path = folder / f"{room}.py"
        assert _imports(path) <= set(ROOMS[:k]), room
        assert len(path.read_text().splitlines()) <= 450, room
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef):
                assert _code_lines(node) <= 60, f"{room}.{node.name}"


def _code_lines(node):
    """Lines of a function after its docstring."""
    body = node.body[1:] if ast.get_docstring(node) is not None else node.body
    return node.end_lineno - body[0].lineno + 1 if body else 0

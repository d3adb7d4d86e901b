"""A simulation pool answers a job asked again from the results it keeps: never a result of other
effects, values, rig values or output grid, the same numbers as a fresh run, and a fit through it
ends where a fit that keeps nothing ends."""
import pickle
from dataclasses import replace

import numpy as np
import pytest

from vcbmodel.analysis.fit import Dataset, Objective, SimulationPool, fit, make_parameters, run_job
from vcbmodel.analysis.synthetic import synthetic_measurement
from vcbmodel.records import signals
from vcbmodel.rig.paths import loaded_value, loaded_with

EFFECTS = ("coulomb_friction",)


@pytest.fixture
def swing(pendulum_rig):
    meas = synthetic_measurement(pendulum_rig, EFFECTS, {"mu_k": 0.11, "stick_velocity": 1e-3}, seed=0, t_end=1.0)
    return Dataset(pendulum_rig, meas)


def _job(dataset, effects=EFFECTS, **values):
    """The simulation job of ``dataset`` at the parameters' own values changed by ``values``."""
    params = make_parameters(dataset.rig, effects)
    obj = Objective([dataset], effects, dataset.rig.model.spring_model, params)
    vals = obj.values(obj.x0())
    vals.update(values)
    return obj.simulation_job(vals, 0)


def _same(a, b) -> bool:
    return a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)


def test_a_job_asked_again_is_answered_without_a_simulation(swing):
    job = _job(swing)
    pool = SimulationPool(1)
    first = pool.run([job])[0]
    again = pool.run([job, job])
    assert pool.simulations == 1 and pool.reused == 2
    assert all(_same(r, first) for r in again)
    assert _same(first, run_job(job))  # what a fresh run gives


def test_a_records_times_travel_as_plain_floats_in_its_jobs(swing):
    """A record without a detected release gives its jobs its own times: as floats, the same values,
    pickled (the job's cache key, what a worker receives) in 9 bytes a sample; numpy scalars took about 19
    and were most of an identification's time."""
    job = _job(swing)
    assert job.sample_times is not None and all(type(t) is float for t in job.sample_times)
    assert np.array_equal(np.asarray(job.sample_times), swing.t)
    assert len(pickle.dumps(job.sample_times, protocol=pickle.HIGHEST_PROTOCOL)) <= 10 * swing.t.size


def test_other_values_effects_rig_values_or_grid_are_simulated(swing):
    job = _job(swing)
    start = loaded_value(swing.rig, "pendulum.initial_angle")
    others = [_job(swing, mu_k=job_value(job, "mu_k") * (1 + 1e-12)),  # a value a hair away
              _job(swing, ("coulomb_friction", "viscous_friction")),  # another model
              replace(job, rig=loaded_with(swing.rig, {"pendulum.initial_angle": 0.9 * start})),  # another start
              replace(job, sample_times=job.sample_times[:-1])]  # another output grid
    pool = SimulationPool(1)
    pool.run([job])
    results = pool.run(others)
    assert pool.simulations == 1 + len(others) and pool.reused == 0
    for other, r in zip(others, results):
        assert _same(r, run_job(other))
    assert not _same(results[0], run_job(job))  # the hair's difference shows: it was not the kept result


def job_value(job, name):
    return dict(job.values)[name]


def test_kept_results_are_read_only_and_bounded(swing):
    pool = SimulationPool(1, kept_bytes=1.5 * sum(v.nbytes for v in run_job(_job(swing)).values()))
    r = pool.run([_job(swing)])[0]
    with pytest.raises(ValueError):
        r["t"][0] = 1.0  # a caller cannot change what another caller receives
    pool.run([_job(swing, mu_k=0.2)])  # the first result is dropped to keep within the bound
    assert len(pool.results) == 1 and pool.kept_now <= pool.kept
    pool.run([_job(swing)])
    assert pool.simulations == 3


def test_a_fit_through_kept_results_ends_where_one_without_ends(swing):
    def one(pool):
        params = make_parameters(swing.rig, EFFECTS)
        params["mu_k"].value = 0.08
        return fit([swing], EFFECTS, params=params, pool=pool, verbose=False, processes=1)

    keeping, plain = SimulationPool(1), SimulationPool(1, kept_bytes=0)
    a, b = one(keeping), one(plain)
    assert a.values == b.values and a.chi2 == b.chi2
    ran = keeping.simulations
    again = one(keeping)  # the same fit from the same start: every simulation is kept
    assert again.values == a.values and keeping.simulations == ran and keeping.reused >= ran
    assert plain.reused == 0 and not plain.results


def test_ar_autocorrelation_remembered_is_the_computed_one():
    a = np.array([0.6, -0.25])

    def computed(coefficients):  # the computation itself, not the remembered value
        return signals._ar_autocorrelation.__wrapped__(tuple(coefficients), 4)
    first = signals.ar_autocorrelation(a, 4)
    assert np.array_equal(first, computed(a))
    first[0] = 7.0  # a copy: the remembered value is not changed by its caller
    assert np.array_equal(signals.ar_autocorrelation(a, 4), computed(a))
    assert not np.array_equal(signals.ar_autocorrelation(np.array([0.6, -0.2]), 4), computed(a))


def test_fast_simulations_run_in_this_process_and_slow_ones_on_the_workers(swing, monkeypatch):
    """A pool of 2 runs a batch here once its simulations are known to take less than INLINE_BELOW_S
    (the same results as on the workers); a slow mean sends batches back to the workers."""
    from vcbmodel.analysis.fit import pool as pool_module
    jobs = [_job(swing, mu_k=v) for v in (0.10, 0.11, 0.12, 0.13)]
    with SimulationPool(2, kept_bytes=0) as pool:
        assert not pool.runs_here()  # nothing measured yet: the workers
        on_workers = pool.run(jobs)
        assert pool.seconds_per_simulation is not None
        monkeypatch.setattr(pool_module, "INLINE_BELOW_S", 10.0)
        assert pool.runs_here()

        def not_the_workers(*a, **k):
            raise AssertionError("a fast batch was sent to the workers")
        workers = pool.pool
        monkeypatch.setattr(workers, "map", not_the_workers)
        monkeypatch.setattr(workers, "submit", not_the_workers)
        here = pool.run(jobs)
        monkeypatch.undo()
        assert all(_same(a, b) for a, b in zip(here, on_workers))
        with pool.inline_lock:  # another fit's batch runs here: this one goes to the workers
            assert all(_same(a, b) for a, b in zip(pool.run(jobs), on_workers))
        monkeypatch.setattr(pool_module, "INLINE_BELOW_S", 0.0)
        assert not pool.runs_here()

"""The per-process setup caches a sweep leans on (a spring's lumped chain, a geometry's reachable travel)
never hand a run another run's value: a sweep in one process, whose runs revisit and leave values, gives
each run the row it gets when run alone with the caches emptied; a field changed in place, a number of
another type, many threads and more inputs than the caches keep give what a fresh solve gives."""
import copy
import sys
import threading
from types import SimpleNamespace

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.analysis import sweep as S
from vcbmodel.experiments import experiment_of
from vcbmodel.experiments.loading import rig_from_data
from vcbmodel.laws import springs
from vcbmodel.laws.springs import CHAINS_KEPT, chain_for, lumped_chain
from vcbmodel.rig import plausibility
from vcbmodel.rig.plausibility import reachable_travel, travel_curve
from vcbmodel.rig.spring_model import SpringModel

BREAKER = P.REFERENCE_BREAKER


def empty_caches():
    springs._kept_chain.cache_clear()
    plausibility._kept_travel.cache_clear()


def alone(overrides):
    """One run, a sweep of its own, with nothing kept from any other: (figures, status)."""
    empty_caches()
    return sweep_rows([overrides])[0]


def sweep_rows(runs):
    df = S.sweep(copy.deepcopy(BREAKER), runs=runs, workers=1, verbose=False)
    columns = experiment_of("vcb_closing").figure_columns
    return [({c: row[c] for c in columns}, row["status"]) for _, row in df.iterrows()]


def same(a, b):
    return all((x is None or (isinstance(x, float) and np.isnan(x))) and (y is None or (isinstance(y, float) and np.isnan(y)))
               or x == y for x, y in ((a[k], b.get(k)) for k in a))


def test_a_sweep_over_the_closing_spring_gives_every_run_its_own_spring():
    """Stiffness and coil mass revisited in one process (the chain of run 1 kept while runs 2-4 use others):
    every row is the row of that run alone, and the runs that differ in the spring differ in the closing."""
    k0, m0 = BREAKER["closing_spring"]["stiffness"], BREAKER["closing_spring"]["mass"]
    runs = [{"closing_spring.stiffness": k0}, {"closing_spring.stiffness": 1.06 * k0},
            {"closing_spring.stiffness": k0, "closing_spring.mass": 1.3 * m0}, {"closing_spring.stiffness": k0},
            {"closing_spring.stiffness": 1.06 * k0}]
    empty_caches()
    rows = sweep_rows(runs)
    for (values, status), overrides in zip(rows, runs):
        fresh, fresh_status = alone(overrides)
        assert status == fresh_status == "ok"
        assert same(values, fresh), overrides
    times = [v["closing_time_s"] for v, _ in rows]
    assert times[0] == times[3] and times[1] == times[4]
    assert len({times[0], times[1], times[2]}) == 3


def test_a_sweep_over_the_cam_lift_refuses_exactly_the_lifts_that_cannot_close():
    """The reachable travel is kept per geometry: a lift too small to move the poles through their gap is
    refused each time it comes back, between lifts that close, as when run alone."""
    runs = [{"breaker.cam_profile.lift": lift} for lift in (0.0094, 0.0068, 0.0080, 0.0068, 0.0094)]
    empty_caches()
    rows = sweep_rows(runs)
    statuses = [status for _, status in rows]
    assert [s == "ok" for s in statuses] == [True, False, True, False, True]
    assert "never close" in statuses[1] or "could never" in statuses[1], statuses[1]
    for (values, status), overrides in zip(rows, runs):
        fresh, fresh_status = alone(overrides)
        assert status == fresh_status and same(values, fresh), overrides


def reference_geometry():
    rig = rig_from_data(copy.deepcopy(BREAKER), "reference")
    b = rig.breaker
    follower = SimpleNamespace(**{k: getattr(b.follower, k) for k in b.follower.__dataclass_fields__})
    mutable = SimpleNamespace(follower=follower, profile=b.profile, roller_radius=b.roller_radius)
    return mutable, SimpleNamespace(pivot=rig.cam.pivot, initial_angle=rig.cam.initial_angle)


def fresh_travel(b, cam):
    return float(np.max(travel_curve(b, cam, cam.initial_angle + np.linspace(0.0, 2 * np.pi, 361))))


def test_a_geometry_changed_in_place_gets_its_own_travel():
    """A breaker whose follower is changed in place after its travel was kept (a caller that edits a mutable
    object between runs) gets the travel of what it is now, not of what it was."""
    b, cam = reference_geometry()
    before = reachable_travel(b, cam)
    assert before == fresh_travel(b, cam)
    b.follower.output_arm *= 0.8
    after = reachable_travel(b, cam)
    assert after == fresh_travel(b, cam) and after == pytest.approx(0.8 * before, rel=0.02)
    cam.initial_angle += 0.1
    assert reachable_travel(b, cam) == fresh_travel(b, cam)


def test_chains_are_the_fresh_solve_whatever_the_number_type_and_however_many():
    """An integer stiffness and its float share one chain of float arrays (the fresh float solve); more springs
    than are kept, asked from several threads at once, each get their own chain (equal to a fresh solve) and
    the kept ones stay bounded."""
    uniform = SpringModel("lumped", 3, "uniform")
    as_int = chain_for(SimpleNamespace(stiffness=24230, mass=1, free_length=0.3), uniform)
    as_float = chain_for(SimpleNamespace(stiffness=24230.0, mass=1.0, free_length=0.3), uniform)
    fresh = lumped_chain(3, 24230.0, 1.0, 0.3, "uniform")
    assert as_int is as_float and as_int.stiffnesses.dtype == np.float64
    assert np.array_equal(as_int.stiffnesses, fresh.stiffnesses) and np.array_equal(as_int.masses, fresh.masses)

    stiffnesses = [20000.0 + 10.0 * i for i in range(CHAINS_KEPT + 100)]
    wrong, errors = [], []

    def ask(offset):
        try:
            for j in range(3 * len(stiffnesses)):
                k = stiffnesses[(7 * j + offset) % len(stiffnesses)]
                chain = chain_for(SimpleNamespace(stiffness=k, mass=0.8, free_length=0.3), uniform)
                if not np.array_equal(chain.stiffnesses, np.full(4, 4 * k)):
                    wrong.append(k)
        except Exception as e:  # noqa: BLE001 -- a race's error is what the test looks for
            errors.append(e)

    threads = [threading.Thread(target=ask, args=(i,)) for i in range(6)]
    interval = sys.getswitchinterval()
    sys.setswitchinterval(1e-6)  # threads switch often: a race shows (a dict evicted by two threads raised)
    try:
        for t in threads:
            t.start()
        for t in threads:
            t.join()
    finally:
        sys.setswitchinterval(interval)
    assert not errors and not wrong
    assert springs._kept_chain.cache_info().currsize <= CHAINS_KEPT

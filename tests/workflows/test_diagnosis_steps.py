"""The diagnosis' steps one by one (vcbmodel/analysis/diagnosis): the pipeline's order, each step
on a small case, and each heuristic of the search with the one-line reason its docstring gives.
Most tests feed hand-made fits (real FitResult objects with chosen residuals, no simulation), so a
wrong rule fails here without a whole diagnosis; the align and start steps run on a synthetic cam
drop."""
import math
import re
import threading
import time
from dataclasses import fields
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from vcbmodel.analysis.diagnosis import discover as discover_step
from vcbmodel.analysis.diagnosis import judge as judge_step
from vcbmodel.analysis.diagnosis import refine as refine_step
from vcbmodel.analysis.diagnosis import springs as springs_step
from vcbmodel.analysis.diagnosis.align import align, fitted_channels
from vcbmodel.analysis.diagnosis.candidates import NULL_VALUES, nested, pair_jobs
from vcbmodel.analysis.diagnosis.context import Budget, Context, Search
from vcbmodel.analysis.diagnosis.fits import _fresh_bases, valley_bases
from vcbmodel.analysis.diagnosis.period import period_mismatch, needs_period
from vcbmodel.analysis.diagnosis.pipeline import STEPS, Step, run_steps
from vcbmodel.analysis.diagnosis.report import timing, window
from vcbmodel.analysis.diagnosis.at_noise import at_noise
from vcbmodel.analysis.diagnosis.options import DEFAULT_OPTIONS
from vcbmodel.analysis.diagnosis.scores import earns_margin, excess_share_left, noise_separable
from vcbmodel.analysis.diagnosis.select import pair_reason
from vcbmodel.analysis.diagnosis import side_by_side
from vcbmodel.analysis.diagnosis.side_by_side import cannot_win, pruned
from vcbmodel.analysis.diagnosis.start import fit_start
from vcbmodel.analysis.diagnosis.evidence import evidence_text
from vcbmodel.analysis.diagnosis.result import Diagnosis
from vcbmodel.analysis.diagnosis.state import Candidate, SelectionStep, State, Verdict, adopt
from vcbmodel.analysis.fit import FitAborted, FitResult, Parameter, SimulationPool
from vcbmodel.analysis.noise import NoiseModel
from vcbmodel.analysis.synthetic import random_case
from vcbmodel.experiments.cam_drop import CAM_DROP
from vcbmodel.experiments.loading import load_record, load_rig
from vcbmodel.experiments.pendulum import decay_split_guesses, start_guesses
from vcbmodel.model.effects import parameter_specs
from vcbmodel.rig.spring_model import SpringModel

BIC_MARGIN = DEFAULT_OPTIONS.bic_margin
SIGMA = 1e-3
N = 4000
T = np.arange(N) * 1e-3


def noise(seed=1, n=N):
    return np.random.default_rng(seed).normal(0.0, SIGMA, n)


def fit_of(residual, effects=(), varied=(), spring=None, nuisance=()):
    """A FitResult with the given residual (rad) and parameters ``varied`` (name -> value)."""
    params = {name: Parameter(name, value) for name, value in dict(varied).items()}
    params.update({name: Parameter(name, value, kind="offset") for name, value in dict(nuisance).items()})
    return FitResult(tuple(effects), spring or SpringModel(), params, [np.asarray(residual, float)], [], SIGMA,
                     times=[T[: len(residual)]])


def record_of(**kw):
    return SimpleNamespace(**{"period_fields": (), "measured_channel": "angle", "natural_frequency": None, "unit": "rad",
                              **kw})


SEARCH_FIELDS = {f.name for f in fields(Search)}


def ctx_of(**kw):
    """A stand-in context: the record's fields as keywords, the search's (noise, implied, fits,
    spring_final, ...) into ``search``."""
    search = Search(noise=NoiseModel.white(SIGMA), **{k: kw.pop(k) for k in list(kw) if k in SEARCH_FIELDS})
    out = SimpleNamespace(sigma_hf=SIGMA, quantisation=0.0, over=lambda f=0.8: False, search=search,
                          skipped=[], say=lambda m: None, valley=[], record=record_of(),
                          stop=SimpleNamespace(is_set=lambda: False), options=DEFAULT_OPTIONS, held_out=(),
                          dataset=SimpleNamespace(t=T), rig=SimpleNamespace(experiment="cam_drop", provides=CAM_DROP.provides, record={}),
                          setup=SimpleNamespace(release=0.0, still_start=False, hand_start=False),
                          measurement=SimpleNamespace(t=T, channel=lambda name: np.zeros_like(T)))
    out.__dict__.update(kw)
    return out


def bump(centre=2.0, width=0.2, size=5e-3):
    return size * np.exp(-((T - centre) / width) ** 2)


def explained_verdict(ctx):
    out = judge_step.verdict(ctx, fit_of(noise(7)))
    assert out.explained
    return out


# --- the pipeline ---------------------------------------------------------------------------------

def test_the_pipeline_is_the_named_steps_in_order_each_its_own_module():
    assert [s.name for s in STEPS] == ["align the record", "fit the starting model", "select effects",
                                       "refine the selection", "judge the residual", "discover", "report"]
    assert len({s.run.__module__ for s in STEPS}) == len(STEPS)


ROOT = Path(__file__).resolve().parents[2]


def listed_steps(text):
    """(number, name) of the numbered bold items ``1. **name**`` in ``text`` (whitespace folded)."""
    return re.findall(r"(\d+)\. \*\*([^*]+)\*\*", " ".join(text.split()))


def test_readme_and_findings_list_the_pipelines_steps_one_to_one():
    names = [s.name for s in STEPS]
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    bullet = readme.split("- `diagnose` fits", 1)[1].split("\n- `", 1)[0]
    assert listed_steps(bullet) == [(str(i + 1), name) for i, name in enumerate(names)]
    findings = (ROOT / "docs" / "findings.md").read_text(encoding="utf-8")
    section = findings.split("## The diagnosis", 1)[1].split("\n## ", 1)[0]
    listed = listed_steps(section)
    assert [(n, name.lower()) for n, name in listed] == [(str(i + 1), name) for i, name in enumerate(names)]
    modules = re.findall(r"\d+\. \*\*[^*]+\*\* \(`(\w+)\.py`", " ".join(section.split()))
    assert modules == [s.run.__module__.rsplit(".", 1)[1] for s in STEPS]


def test_run_steps_runs_every_step_once_in_order_on_one_state():
    seen = []
    steps = tuple(Step(name, lambda ctx, state, name=name: seen.append((name, id(state)))) for name in "abc")
    state = State()
    assert run_steps(None, state, steps) is state
    assert seen == [(name, id(state)) for name in "abc"]


# --- scores -------------------------------------------------------------------------------------

def test_at_noise_accepts_noise_and_refuses_a_slow_model_error():
    ctx = ctx_of()
    assert at_noise(ctx, fit_of(noise()))
    assert not at_noise(ctx, fit_of(noise() + bump()))


def test_an_effect_must_earn_the_margin_and_remove_enough_variance():
    ctx = ctx_of()
    before, after = fit_of(noise() + bump()), fit_of(noise())
    assert earns_margin(ctx, before, after, BIC_MARGIN + 1)
    assert not earns_margin(ctx, before, after, BIC_MARGIN)  # the margin is strict
    # a BIC gain with next to no variance removed (a tiny systematic difference) is not enough
    almost = fit_of(noise() + bump() * 0.999)
    assert not earns_margin(ctx, before, almost, 1e3)


def test_excess_share_left_and_separable_noise():
    ctx = ctx_of()
    before = fit_of(noise() + bump())
    assert excess_share_left(ctx, before, fit_of(noise())) < 0.05
    assert excess_share_left(ctx, before, fit_of(noise() + 0.9 * bump())) > 0.5
    assert noise_separable(ctx, NoiseModel.white(1.5 * SIGMA))
    assert not noise_separable(ctx, NoiseModel.white(3 * SIGMA))


# --- select effects: when pairs are tried ---------------------------------------------------------

def correlated_noise(phi=0.97, seed=1):
    e = np.random.default_rng(seed).normal(0.0, SIGMA, N)
    r = np.zeros(N)
    for i in range(1, N):
        r[i] = phi * r[i - 1] + e[i]
    return r


def test_pair_reason_names_each_of_its_three_reasons():
    ctx = ctx_of()
    current = fit_of(noise() + bump())
    assert pair_reason(ctx, current, Candidate("a", fit_of(noise()), 5.0)) == "no single effect earns the evidence"
    assert pair_reason(ctx, current, Candidate("a", fit_of(noise() + 0.9 * bump()), 50.0)) == \
        "the best single effect leaves most of the gap"
    big = fit_of(noise(2) + 10 * bump())
    assert pair_reason(ctx, big, Candidate("a", fit_of(correlated_noise()), 1e4)) == \
        "the best single effect passes for noise only as strongly correlated noise"
    assert pair_reason(ctx, current, Candidate("a", fit_of(noise()), 1e3)) is None


def test_pair_jobs_are_every_pair_of_the_singles_with_the_spring_variants(cam_rig):
    singles = [("coulomb_friction", ((), (), {}), 1), ("viscous_friction", ((), (), {}), 1),
               ("spring_mass", ((), ("lumped-1",), {}), 0)]
    jobs = pair_jobs(cam_rig, fit_of(noise()), singles)
    names = [name for name, _, _ in jobs]
    assert names == ["coulomb_friction+viscous_friction", "coulomb_friction+spring_mass",
                     "viscous_friction+spring_mass"]
    variants = {name: v for name, (_, v, _), _ in jobs}
    assert variants["coulomb_friction+spring_mass"] == ("lumped-1",)
    assert variants["coulomb_friction+viscous_friction"] == ()


def test_occam_prunes_candidates_with_more_parameters_than_one_that_reached_the_noise():
    # one with as many parameters is still fitted: the choice between two equal candidates must not
    # depend on which finished first (under load an air drag once pruned the viscous friction)
    assert pruned(2, [1]) and not pruned(1, [1])
    assert not pruned(0, [1]) and not pruned(3, [])
    # running ones are cancelled only with strictly more parameters (an equal one may still win)
    assert cannot_win(2, [1]) and not cannot_win(1, [1]) and not cannot_win(3, [])


def test_running_candidates_that_cannot_win_are_cancelled(monkeypatch):
    """Three candidates start together: ``a`` (no new parameter) reaches the noise at once; ``b``
    (one parameter) is cancelled while it runs; ``c`` (no new parameter, like ``a``) runs to its
    end; ``d`` (two parameters), still pending, is never started."""
    started = []

    def fake(ctx, current, name, effects, variants, scan, should_stop):
        started.append(name)
        if name == "a":
            return fit_of(noise()), None
        deadline = time.monotonic() + (0.5 if name == "c" else 10.0)
        while time.monotonic() < deadline:
            if should_stop():
                raise FitAborted()
            time.sleep(0.01)
        return fit_of(noise(2)), None

    monkeypatch.setattr(side_by_side, "fit_candidate", fake)
    said = []
    ctx = ctx_of(processes=3, stop=threading.Event(), record=record_of(unit="rad"),
                 budget=SimpleNamespace(started=time.monotonic()), say=said.append)
    jobs = [(name, ((), (), {}), k) for name, k in (("a", 0), ("b", 1), ("c", 0), ("d", 2))]
    fits, _ = side_by_side.run_candidates(ctx, fit_of(noise() + bump()), jobs, 1)
    assert fits[0] is not None and fits[2] is not None  # a, and c with as many parameters
    assert fits[1] is None and fits[3] is None
    assert "d" not in started
    # the progress says the cancelled one was cancelled, not that it left an rms of nan
    done = [m for m in said if "candidate fits done" in m]
    assert any("(b: cancelled)" in m for m in done) and not any("nan" in m for m in done), done


def test_a_candidate_is_never_worse_than_its_nested_model():
    ctx = ctx_of()
    current = fit_of(noise(), effects=("coulomb_friction",), varied={"mu_k": 0.1})
    worse = fit_of(noise() + bump(), effects=("coulomb_friction", "viscous_friction"),
                   varied={"mu_k": 0.12, "viscous": 0.3})
    current.jacobian = (("mu_k",), np.ones((N, 1)))
    out = nested(ctx, current, worse.effects, worse)
    assert out.values == {"mu_k": 0.1, "viscous": NULL_VALUES["viscous"]}
    assert out.jacobian == (None, None) and out.stand_in is None  # the current fit's Jacobian lacks viscous
    assert out.chi2 == current.chi2 and out.effects == worse.effects
    better = fit_of(0.5 * noise(), effects=worse.effects, varied={"mu_k": 0.1, "viscous": 0.3})
    assert nested(ctx, current, better.effects, better) is better


def test_a_scan_is_centred_on_the_current_values_and_afresh_on_the_records_guesses():
    effects = ("coulomb_friction", "viscous_friction")
    registry = {spec.name: spec.initial for spec in parameter_specs(effects)}
    params = {"mu_k": Parameter("mu_k", 0.3), "viscous": Parameter("viscous", 0.9),
              "stick_velocity": Parameter("stick_velocity", 1e-3, vary=False)}
    bases = _fresh_bases(ctx_of(guesses=[{"mu_k": 0.2}]), effects, params)
    assert bases == [{}, {"mu_k": 0.2, "viscous": registry["viscous"]}]
    frozen = {name: Parameter(name, 0.1, vary=False) for name in params}
    assert _fresh_bases(ctx_of(guesses=[{"mu_k": 0.2}]), effects, frozen) is None


def test_a_free_swing_scan_is_also_centred_along_the_coulomb_viscous_valley():
    """The decay shared out between Coulomb and viscous friction gives further grid centres, only
    when a candidate adds one of them and both are then fitted; each share is that share of the
    decay read as Coulomb friction."""
    t = np.arange(0, 6, 1e-3)
    span_rate, lam = 0.02, 0.15  # rad/s of Coulomb decrement, 1/s viscous
    amp = np.maximum(0.2 * np.exp(-lam * t) - span_rate * t / 2, 0)
    y = amp * np.cos(2 * np.pi * 1.05 * t) + np.random.default_rng(2).normal(0, 2e-4, t.size)
    meas = SimpleNamespace(t=t, channel=lambda name: y)
    rig = SimpleNamespace(pendulum=SimpleNamespace(com_distance=0.2, inertia=0.05), shaft_radius=0.01)
    shares = (0.8, 0.5)
    valley = decay_split_guesses(rig, meas, shares)
    assert [g["mu_k"] for g in valley] == pytest.approx([s / shares[0] * valley[0]["mu_k"] for s in shares])
    assert valley[0]["viscous"] < valley[1]["viscous"]  # less Coulomb, more viscous
    guesses = start_guesses(rig, meas)
    assert valley[0]["mu_k"] == pytest.approx(0.8 * guesses[1]["mu_k"])  # a share of "all as Coulomb"
    effects = ("coulomb_friction", "viscous_friction")
    params = {"mu_k": Parameter("mu_k", 0.3), "viscous": Parameter("viscous", 0.9)}
    bases = _fresh_bases(ctx_of(guesses=[{"mu_k": 0.2}], valley=valley), effects, params, ("viscous",))
    assert bases[2:] == [{"mu_k": g["mu_k"], "viscous": g["viscous"]} for g in valley]
    assert valley_bases(ctx_of(valley=valley), params, ("mu_s",)) == []  # both fitted already: on the floor
    params["viscous"].vary = False  # only one of the two fitted: no valley to spread along
    assert valley_bases(ctx_of(valley=valley), params) == []


# --- refine the selection -------------------------------------------------------------------------

def step(effect, round_no, fit, before=None):
    return SelectionStep(effect, round_no, 20.0, fit.rms, "massless", before, fit)


def test_refinements_run_in_their_documented_order():
    names = [f.__name__ for f in refine_step.REFINEMENTS]
    assert names == ["backward_elimination", "swap_effects", "final_spring", "finer_spring", "search_harder"]
    doc = refine_step.__doc__
    assert [doc.index(name) for name in names] == sorted(doc.index(name) for name in names)


def test_backward_elimination_drops_an_effect_the_others_make_up_for(monkeypatch):
    current = fit_of(noise(), effects=("coulomb_friction", "viscous_friction"), varied={"mu_k": 0.1, "viscous": 0.2})
    refits = []

    def refit(ctx, effects, spring, previous, label):
        refits.append(effects)
        worse = "coulomb_friction" not in effects  # without coulomb: the bump comes back
        return fit_of(noise() + (bump() if worse else 0), effects=effects)

    monkeypatch.setattr(refine_step, "refit", refit)
    state = State(current=current, all_fits=[current],
                  path=[step("viscous_friction", 1, current), step("coulomb_friction", 2, current)])
    refine_step.backward_elimination(ctx_of(), state)
    # the second removal is tried on the model the first one left
    assert refits == [("coulomb_friction",), ()]
    assert [s.effect for s in state.path] == ["coulomb_friction"]
    assert state.current.effects == ("coulomb_friction",) and state.path[0].fit is state.current
    assert [b.dropped for b in state.backward] == [True, False]


def test_backward_elimination_leaves_a_single_round_alone(monkeypatch):
    monkeypatch.setattr(refine_step, "refit", lambda *a: pytest.fail("refitted"))
    current = fit_of(noise(), effects=("coulomb_friction", "viscous_friction"))
    state = State(current=current, path=[step("coulomb_friction", 1, current), step("viscous_friction", 1, current)])
    refine_step.backward_elimination(ctx_of(), state)
    assert state.current is current and len(state.path) == 2


def test_swap_replaces_a_kept_effect_by_one_that_explains_the_record(monkeypatch):
    current = fit_of(noise() + bump(), effects=("viscous_friction",), varied={"viscous": 0.5})

    def refit(ctx, effects, spring, previous, label):
        return fit_of(noise() + (0 if "coulomb_friction" in effects else bump()), effects=effects)

    monkeypatch.setattr(refine_step, "refit", refit)
    state = State(current=current, all_fits=[current], path=[step("viscous_friction", 1, current)])
    refine_step.swap_effects(ctx_of(), state)
    assert state.current.effects == ("coulomb_friction",)
    assert state.path[0].effect == "coulomb_friction" and state.path[0].swapped_from == "viscous_friction"
    assert {b.swap_for for b in state.backward} == {"coulomb_friction", "stribeck"}
    # the record of the swap taken (not merely the last one tried) says so, and the evidence words it
    assert [b.swap_for for b in state.backward if b.dropped] == ["coulomb_friction"]
    ctx = ctx_of(record=record_of(unit="rad"), implied={})
    text = evidence_text(ctx, current, state.current, ["coulomb_friction"], (0.0, 1.0), {}, explained_verdict(ctx),
                         None, state.backward)
    assert "viscous_friction was kept on the way but replaced by coulomb_friction" in text


def test_swap_and_search_harder_leave_a_model_at_the_noise_alone(monkeypatch):
    monkeypatch.setattr(refine_step, "refit", lambda *a: pytest.fail("refitted"))
    monkeypatch.setattr(refine_step, "_wider_fit", lambda *a: pytest.fail("searched"))
    current = fit_of(noise(), effects=("viscous_friction",))
    state = State(current=current, path=[step("viscous_friction", 1, current)])
    ctx = ctx_of(record=record_of(period_fields=("pendulum.inertia",)))
    refine_step.swap_effects(ctx, state)
    refine_step.search_harder(ctx, state)
    assert state.current is current


def test_search_harder_only_for_a_free_swing(monkeypatch):
    monkeypatch.setattr(refine_step, "_wider_fit", lambda *a: pytest.fail("searched"))
    current = fit_of(noise() + bump(), effects=("viscous_friction",))
    state = State(current=current, path=[step("viscous_friction", 1, current)])
    refine_step.search_harder(ctx_of(), state)  # a cam drop: no period fields
    assert state.current is current


def test_spring_refinements_need_the_springs_mass():
    current = fit_of(noise() + bump(), effects=("coulomb_friction",))
    state = State(current=current)
    springs_step.final_spring(ctx_of(spring_final=SpringModel()), state)
    springs_step.finer_spring(ctx_of(), state)
    assert state.current is current and state.coarse_spring is None


def test_adopt_moves_only_the_steps_that_ended_in_the_old_fit():
    old, other, new = fit_of(noise()), fit_of(noise()), fit_of(noise())
    path = [step("a", 1, old), step("b", 2, other)]
    adopt(path, old, new)
    assert path[0].fit is new and path[1].fit is other


# --- judge the residual ----------------------------------------------------------------------------

def test_the_verdict_explains_noise_and_locates_what_is_left():
    ctx = ctx_of()
    assert judge_step.verdict(ctx, fit_of(noise())).explained
    out = judge_step.verdict(ctx, fit_of(noise() + bump(centre=3.0)))
    assert not out.explained
    t0, t1 = out.left["window"]
    assert t0 <= 3.0 <= t1 and out.left["excess"] > SIGMA


def test_the_disagreement_window_has_a_width_or_the_evidence_says_nothing_stands_out():
    """A residual at its noise has no stretch above twice the noise: its window is the running rms's
    own span around the peak (it was [t, t]) and the evidence says nothing stands out; a bump is
    located, its window covering it."""
    ctx = ctx_of(record=record_of(unit="rad"), implied={})
    quiet = fit_of(noise(3))
    t0, t1 = window(ctx, quiet)
    assert t1 - t0 >= (N // 50 - 1) * 1e-3  # at least the running window (2 % of the record)
    text = evidence_text(ctx, quiet, quiet, [], (t0, t1), {}, explained_verdict(ctx), None)
    assert "nowhere standing out" in text and "largest in t" not in text
    loud = fit_of(noise(3) + bump(centre=3.0))
    t0, t1 = window(ctx, loud)
    assert t0 < 3.0 - 0.1 and t1 > 3.0 + 0.1
    text = evidence_text(ctx, loud, quiet, [], (t0, t1), {}, explained_verdict(ctx), None)
    assert f"largest in t = [{t0:.4g}, {t1:.4g}] s" in text
    # the report's line says the same
    for fit, words in ((quiet, "disagreement: nowhere standing out"), (loud, f"disagreement largest in t = [{t0:.4g}")):
        d = Diagnosis(None, None, NoiseModel.white(SIGMA), fit, [], [], fit, window(ctx, fit), {}, "")
        assert d.disagreement_line().strip().startswith(words)


def test_a_pair_kept_together_is_no_tie():
    kept = Candidate("a+b", fit_of(noise()), 40.0)
    rival = Candidate("c", fit_of(noise() + bump()), 38.0)
    path = [SelectionStep("a", 1, 40.0, 0.0, "massless", None, kept.fit, "a+b"),
            SelectionStep("b", 1, 40.0, 0.0, "massless", None, kept.fit, "a+b")]
    assert judge_step.ties(ctx_of(), path, [kept, rival]) == []


# --- discover, report ---------------------------------------------------------------------------

def test_discover_searches_only_an_unexplained_record_and_changes_no_fit(monkeypatch):
    current, start = fit_of(noise() + bump()), fit_of(noise() + 2 * bump())
    seen = {}

    class Found:
        message = "discovered, not registered: ..."

        def to_json(self):
            return {"found": True, "terms": [{"term": "w_abs_w"}]}

        def report(self):
            return "  discovery: ..."

    def step(rig, measurement, final, starting, explained, **options):
        seen.update(final=final, starting=starting, margin=options["bic_margin"], gain=options["min_gain"])
        return Found()

    monkeypatch.setattr(discover_step, "discovery_step", step)
    state = State(current=current, final=current, baseline=start, verdict=explained_verdict(ctx_of()))
    pendulum = SimpleNamespace(experiment="pendulum")
    discover_step.discover(ctx_of(measurement=None, rig=pendulum), state)
    assert not state.discovery["attempted"] and not seen  # explained: nothing to look for
    state.verdict = Verdict(False, None)
    closing = SimpleNamespace(experiment="vcb_closing")
    discover_step.discover(ctx_of(measurement=None, pool=None, rig=closing), state)  # a closing: no search
    assert not state.discovery["attempted"] and "does not search vcb_closing" in state.discovery["reason"] and not seen
    discover_step.discover(ctx_of(measurement=None, pool=None, rig=pendulum), state)
    assert state.discovery["attempted"] and state.discovery["found"] and state.discovery["report"]
    seen_before, state.discovery = dict(seen), {}
    seen.clear()
    off = ctx_of(measurement=None, pool=None, rig=pendulum, options=DEFAULT_OPTIONS.with_(discovery=False))
    discover_step.discover(off, state)  # switched off: not searched, and said so
    assert not state.discovery["attempted"] and "options.discovery" in state.discovery["reason"] and not seen
    seen.update(seen_before)
    assert seen["final"] is current and seen["starting"] is start  # both bases, the diagnosis's threshold
    assert seen["margin"] == DEFAULT_OPTIONS.bic_margin and seen["gain"] > 0
    assert state.final is current
    monkeypatch.setattr(discover_step, "discovery_step", lambda *a, **k: (_ for _ in ()).throw(ValueError("no")))
    discover_step.discover(ctx_of(measurement=None, pool=None, rig=pendulum), state)
    assert not state.discovery["attempted"] and "failed" in state.discovery["reason"]
    state.discovery = {}
    discover_step.discover(ctx_of(measurement=None, over=lambda f=0.8: True, rig=pendulum), state)
    assert state.discovery["reason"] == "time budget"


def test_report_window_and_timing():
    ctx = ctx_of(pool=SimpleNamespace(simulations=7, cpu_seconds=lambda: 0.0), fits=2)
    ctx.budget = Budget(ctx.pool, 1, 10.0)
    t0, t1 = window(ctx, fit_of(noise() + bump(centre=1.0)))
    assert t0 <= 1.0 <= t1
    spent = timing(ctx)
    assert spent["simulations"] == 7 and spent["fits"] == 2 and not spent["budget_reached"]
    ctx.budget.skipped.append("swap a -> b")
    assert timing(ctx)["budget_reached"]


# --- the period of a free swing ---------------------------------------------------------------------

def test_a_period_mismatch_is_found_from_the_drift_of_the_extremes():
    t = np.arange(0, 10, 1e-3)
    record = 0.3 * np.cos(2 * np.pi * t / 1.01) * np.exp(-0.4 * t)  # 1 % longer period, dies out
    model = 0.3 * np.cos(2 * np.pi * t) * np.exp(-0.4 * t)
    ctx = SimpleNamespace(record=SimpleNamespace(period_fields=("pendulum.inertia",)), sigma_hf=SIGMA,
                          dataset=SimpleNamespace(t=t, y=record, mask=lambda: np.ones(t.size, bool)),
                          uncertain={}, search=Search(), options=DEFAULT_OPTIONS)
    fit = SimpleNamespace(simulations=[SimpleNamespace(measured=model)])
    out = period_mismatch(ctx, fit)
    assert out["relative"] == pytest.approx(0.01, abs=0.002) and out["significant"]
    assert needs_period(ctx, out)
    ctx.uncertain["pendulum.inertia"] = 0.05  # the rig allows for it already
    assert not needs_period(ctx, out)
    assert period_mismatch(ctx, SimpleNamespace(simulations=[SimpleNamespace(measured=record)]))["significant"] is False


@pytest.mark.parametrize("t_end", [7.3, 7.45, 5.25])  # ends rising to an extreme, just past one, mid-swing
@pytest.mark.parametrize("error", [0.01, -0.006])
def test_a_record_ending_mid_swing_gives_the_period_mismatch_unbiased(t_end, error):
    """The record's and the model's largest samples sit at the record's end when it ends mid-swing:
    that pair said "no drift" and pulled the mismatch toward zero (0.0058 for a true 0.01 at 7.3 s).
    Only extremes the record holds whole count now, each timed by a parabola through its top."""
    rng = np.random.default_rng(5)
    t = np.arange(0, t_end, 1e-3)
    model = 0.3 * np.cos(2 * np.pi * t) * np.exp(-0.2 * t)
    record = 0.3 * np.cos(2 * np.pi * t / (1 + error)) * np.exp(-0.2 * t) + SIGMA * rng.standard_normal(t.size)
    ctx = SimpleNamespace(record=SimpleNamespace(period_fields=("pendulum.inertia",)), sigma_hf=SIGMA,
                          dataset=SimpleNamespace(t=t, y=record, mask=lambda: np.ones(t.size, bool)),
                          uncertain={}, search=Search(), options=DEFAULT_OPTIONS)
    out = period_mismatch(ctx, SimpleNamespace(simulations=[SimpleNamespace(measured=model)]))
    assert out["significant"] and out["relative"] == pytest.approx(error, abs=max(1e-4, 4 * out["stderr"]))
    assert abs(out["relative"] - error) < 0.05 * abs(error)


# --- align the record, fit the starting model (a synthetic cam drop) -------------------------------

def test_align_then_start_on_a_synthetic_cam_drop(tmp_path):
    rig_path, meas_path, _ = random_case("cam_none", 5, tmp_path)
    rig = load_rig(rig_path)
    measurement = load_record(meas_path, rig)
    with SimulationPool(1) as pool:
        ctx = Context(rig, measurement, pool, Budget(pool, 1, 50.0), verbose=False, processes=1)
        state = State()
        align(ctx, state)
        assert ctx.sigma_hf == pytest.approx(2e-3, rel=0.15)  # the camera's noise (synthetic.py)
        assert fitted_channels(rig, measurement) == (ctx.record.measured_channel,)
        assert ctx.dataset is not None and ctx.guesses and ctx.search.fits == 0
        assert state.period is None  # a cam drop has no period
        fit_start(ctx, state)
    assert state.baseline is state.current and state.all_fits == [state.baseline]
    assert state.baseline.effects == tuple(rig.model.effects) and ctx.search.fits == 1
    assert state.baseline.rms < 1.2 * ctx.sigma_hf  # the starting model is the truth's family
    assert math.isfinite(ctx.search.noise.marginal_sd)


@pytest.mark.parametrize("finer", [True, False])
def test_the_evidence_calls_a_spring_model_too_coarse_only_when_the_new_one_is_finer(finer):
    """The spring-model refinement tries the best other lumped chain, which can have fewer masses
    (a closing record went lumped-2 -> lumped-1 and read "lumped-2 was too coarse")."""
    current = fit_of(noise(), effects=("coulomb_friction",))
    ctx = ctx_of(record=record_of(unit="m"), implied={})
    to = "lumped-3 (paper)" if finer else "lumped-1 (paper)"
    verdict = explained_verdict(ctx)
    verdict.spring_model_refined = {"from": "lumped-2 (paper)", "to": to, "delta_bic": 143.0, "finer": finer}
    text = evidence_text(ctx, current, current, [], (0.0, 1.0), {}, verdict, None)
    assert ("lumped-2 (paper) was too coarse" in text) == finer
    assert f"with {to} the whitened BIC drops by 143" in text

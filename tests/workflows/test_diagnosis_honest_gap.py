"""One honest gap (issue 28 item 4): each model at its own best alignment, one criterion for "at
the noise", the thresholds in one value written into the report, and an AT BOUND flag that means
what it says. Also: the diagnosis's state holds no dicts with private keys (issue 32 item 2)."""
import ast
import json
from pathlib import Path

import pytest

from vcbmodel.analysis.diagnose import diagnose
from vcbmodel.analysis.diagnosis.options import DEFAULT_OPTIONS, DiagnosisOptions
from vcbmodel.analysis.fit.parameters import Parameter
from vcbmodel.experiments.loading import load_record, load_rig

ROOT = Path(__file__).resolve().parents[2]
DIAGNOSIS = ROOT / "vcbmodel" / "analysis" / "diagnosis"


def test_the_shipped_closing_record_gets_nothing_named():
    """Its truth (the reference breaker with a 16-element ANCF spring) has no viscous friction and
    the starting model (lumped-2) fits it at the noise: nothing is searched, nothing named (it
    named viscous_friction at delta BIC 11, flagged AT BOUND 3.8 errors from the bound, with a
    "before" measured on the final model's alignment)."""
    rig = load_rig(ROOT / "results" / "synthetic" / "vcb_closing.rig.json")
    d = diagnose(rig, load_record(ROOT / "results" / "synthetic" / "vcb_closing.csv", rig), verbose=False)
    j = d.to_json()
    assert j["missing_effects"] == [] and j["explained"] and j["start_at_noise"]
    assert j["candidates"] == [] and j["at_bound"] == []
    assert j["rms_before"] == j["rms_after"] == d.baseline.rms
    assert j["verdict"]["noise_confirmed"] is True
    assert "no effect is searched" in d.evidence
    assert j["options"] == DEFAULT_OPTIONS.to_json()
    json.dumps(j)


def test_the_options_carry_every_threshold_and_refuse_unknown_ones():
    o = DEFAULT_OPTIONS
    assert o.bic_margin == 10.0 and o.min_variance_gain == 0.02 and o.max_starts == 2
    changed = o.with_(bic_margin=6.0)
    assert changed.bic_margin == 6.0 and o.bic_margin == 10.0  # frozen: a copy
    with pytest.raises(ValueError, match="unknown diagnosis option"):
        o.with_(bic_marg=6.0)
    assert json.loads(json.dumps(changed.to_json()))["bic_margin"] == 6.0
    with pytest.raises(AttributeError):
        o.bic_margin = 1.0  # type: ignore[misc]
    assert isinstance(o, DiagnosisOptions)


def module_constants(path):
    """UPPER_CASE names assigned at a module's top level."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return {t.id for node in tree.body if isinstance(node, ast.Assign) for t in node.targets
            if isinstance(t, ast.Name) and t.id.isupper()}


def test_the_search_steps_hold_no_threshold_of_their_own():
    """The thresholds the search and the verdict decide by are the options' fields, not module
    constants of the steps (the artefacts' own detection settings live with each artefact)."""
    steps = ("align", "candidates", "context", "discover", "fits", "judge", "period", "pinned", "refine", "scores",
             "select", "side_by_side", "springs", "start", "witnesses", "time_base")
    found = {name: module_constants(DIAGNOSIS / f"{name}.py") for name in steps}
    allowed = {"candidates": {"NULL_VALUES"}, "refine": {"REFINEMENTS"}, "witnesses": {"GUARD_SAMPLES", "MIN_SAMPLES", "KINK_FACTOR"},
               "time_base": {"GRID_TOLERANCE"}}
    assert {k: v - allowed.get(k, set()) for k, v in found.items() if v - allowed.get(k, set())} == {}


def test_at_bound_means_the_bound_holds_the_value():
    """Within 1e-3 of the span from a bound but several stated errors away: not at the bound."""
    p = Parameter("viscous", 0.0126, 0.0, 20.0, stderr=0.0033)
    assert not p.at_bound()
    assert Parameter("viscous", 0.0001, 0.0, 20.0, stderr=0.0033).at_bound()
    assert Parameter("viscous", 0.0, 0.0, 20.0).at_bound()


def private_keys(path):
    """String keys starting with "_" in dict literals and subscripts of a module."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        keys = node.keys if isinstance(node, ast.Dict) else [node.slice] if isinstance(node, ast.Subscript) else []
        out += [k.value for k in keys if isinstance(k, ast.Constant) and isinstance(k.value, str) and k.value.startswith("_")]
    return out


def test_no_diagnosis_state_dict_has_private_keys():
    """The diagnosis's state is typed (SelectionStep, Refinement, Verdict): no dict carries fits or
    working parts under keys starting with "_" (they were rewritten by four modules and stripped
    before JSON)."""
    found = {p.name: private_keys(p) for p in DIAGNOSIS.rglob("*.py")}
    assert {k: v for k, v in found.items() if v} == {}


def test_only_align_writes_the_context_the_search_writes_its_own_state():
    """``Context`` is what is fixed for a run: its record fields are set by the align step alone;
    what the steps change as the search goes is ``ctx.search`` (``Search``)."""
    fixed = {"record", "quantisation", "sigma_hf", "setup", "channel_sigma", "dataset", "guesses", "valley",
             "uncertain", "coarse_step", "rig", "measurement", "pool", "budget", "options", "held_out", "search"}
    writes = {}
    for path in DIAGNOSIS.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            targets = node.targets if isinstance(node, ast.Assign) else [node.target] if isinstance(
                node, (ast.AugAssign, ast.AnnAssign)) else []
            for t in targets:
                if (isinstance(t, ast.Attribute) and isinstance(t.value, ast.Name) and t.value.id == "ctx"
                        and t.attr in fixed):
                    writes.setdefault(path.name, set()).add(t.attr)
    assert set(writes) <= {"align.py"}, writes


def function_lengths(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    return {f"{path.name}:{n.name}": n.end_lineno - n.lineno + 1 for n in ast.walk(tree)
            if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))}


def test_the_diagnosis_functions_stay_short():
    lengths = {k: v for p in DIAGNOSIS.rglob("*.py") for k, v in function_lengths(p).items()}
    assert {k: v for k, v in lengths.items() if v > 60} == {}


def judgement(checks, at_noise=True):
    from vcbmodel.analysis.diagnosis.at_noise import NoiseJudgement
    holds = True if any(c["holds"] for c in checks) else None
    return NoiseJudgement(at_noise, {}, None, {"holds": holds, "decided_by": [], "checks": checks}, (), (), 0.0)


def test_a_starting_model_is_settled_only_on_a_confirmed_level():
    """The high-frequency witness alone allows up to 2x its level (correlated noise): a residual at
    1.47x it (a cam drop hiding viscous friction, cam_visc seed 12) is at the noise for the verdict,
    but not settled, so its starting model is still searched; within 1.15x it, or with a pre-trigger
    or stated level that holds, it is."""
    hf = {"witness": "high_frequency", "bounds_whole_level": False, "holds": True}
    assert judgement([{**hf, "rms_ratio": 1.04}]).settled
    assert not judgement([{**hf, "rms_ratio": 1.47}]).settled
    pre = {"witness": "pre_trigger", "bounds_whole_level": True, "holds": True, "rms_ratio": 1.3}
    assert judgement([{**hf, "rms_ratio": 1.47}, pre]).settled
    assert not judgement([{**hf, "rms_ratio": 1.04}], at_noise=False).settled

"""Step 3, select effects (forward selection): a starting model already at the noise, its level
confirmed by a witness (:mod:`.at_noise`, the criterion the verdict uses), gets nothing named.
Otherwise every registered effect the model lacks (and that applies) is added in turn and fitted;
the best is kept if it lowers the whitened BIC by more than the options' ``bic_margin`` and removes
enough of the noise variance (with held-out records, their predictions' evidence counts too:
:mod:`.held_out`); repeat until no candidate earns it or the model reaches the noise. Pairs are
tried when single effects fall short (:func:`pair_reason`). The loop runs over
:data:`vcbmodel.model.effects.EFFECTS`: registering an effect makes it a candidate with no change
here."""
from __future__ import annotations

import time

from ..noise import fit_noise
from .candidates import candidate_jobs, pair_jobs
from .at_noise import at_noise, judge_noise
from .held_out import held_out_at_noise, held_out_evidence, held_out_share_left
from .scores import earns, excess_share_left, noise_of_best, noise_separable
from .side_by_side import run_candidates
from .state import Candidate, SelectionStep


def pair_reason(ctx, current: object, best: Candidate) -> str | None:
    """Why a round should try pairs of effects too, or None: no single effect earns the evidence
    (each alone may fit worse than neither), the best leaves most of the gap (two may be missing
    together: more than the options' ``pair_share_left``), or the best passes the noise tests
    only as strongly correlated noise (a slow model error passes for it). None, with held-out
    records, when the best single effect brings the record and every held-out record to the noise
    (the simplest model that predicts them all: the held-out records chose among the candidates,
    so a pair's extra values would be fitted to them)."""
    if ctx.held_out and at_noise(ctx, best.fit) and held_out_at_noise(ctx, best.fit):
        return None
    if not earns(ctx, current, best):
        return "no single effect earns the evidence"
    if gap_share_left(ctx, current, best) > ctx.options.pair_share_left:
        return "the best single effect leaves most of the gap"
    noise = fit_noise(best.fit.residuals, ctx.sigma_hf, ctx.quantisation)
    if not noise_separable(ctx, noise) and at_noise(ctx, best.fit):
        return "the best single effect passes for noise only as strongly correlated noise"
    return None


def gap_share_left(ctx, current: object, best: Candidate) -> float:
    """The share of the gap the best single effect leaves: of the current model's residual variance
    in excess of the noise; or, where the current model fits its own record at the noise and
    held-out records are what show the gap, of theirs."""
    if ctx.held_out and at_noise(ctx, current):
        return held_out_share_left(ctx, current, best.fit)
    return excess_share_left(ctx, current, best.fit)


def _score(ctx, state, current, round_cands) -> Candidate:
    """Every candidate of the round scored with the noise model of the best residual so far;
    returns the best."""
    ctx.search.noise = noise_of_best(ctx, state.all_fits)
    for c in round_cands:
        c.delta_bic = current.bic_with(ctx.search.noise) - c.fit.bic_with(ctx.search.noise)
        if ctx.held_out:
            c.held_out_delta, c.held_out_gain = held_out_evidence(ctx, current, c.fit)
    return max(round_cands, key=lambda c: c.evidence)


def _singles(ctx, state, current, jobs, round_no) -> list:
    fits, variants = run_candidates(ctx, current, jobs, round_no)
    out = []
    for (name, _, _), f, var in zip(jobs, fits, variants):
        if f is None:
            state.stopped.add(name)
            continue
        state.all_fits.append(f)
        out.append(Candidate(name, f, 0.0, round_no, var))
    return out


def _pairs(ctx, state, current, jobs, round_no, why, round_cands) -> bool:
    """The round's pairs fitted and added to ``round_cands`` (and the state's candidates); False
    when there are none."""
    pairs = pair_jobs(ctx.rig, current, jobs)
    if not pairs:
        return False
    ctx.say(f"round {round_no}: {why} and the model leaves more than the noise: trying {len(pairs)} "
            f"pair(s): {', '.join(j[0] for j in pairs)}")
    pfits, pvariants = run_candidates(ctx, current, pairs, round_no)
    for (name, _, _), f, var in zip(pairs, pfits, pvariants):
        if f is not None:
            state.all_fits.append(f)
            c = Candidate(name, f, 0.0, round_no, var)
            round_cands.append(c)
            state.candidates.append(c)
    return True


def _keep(ctx, state, best, round_no) -> None:
    """``best`` joins the selection path; the search goes on from its fit (or its stand-in)."""
    current = state.current
    for effect in best.effect.split("+"):
        state.path.append(SelectionStep(effect, round_no, best.delta_bic, best.fit.rms, best.fit.spring_model_label,
                                        current, best.fit, best.effect if "+" in best.effect else None))
    state.current = best.fit
    stand_in = best.fit.stand_in
    if stand_in is not None:
        # further effects are searched on the best lumped chain (an ANCF spring costs five to
        # ten times as much); the final model is refined with the continuum at the end
        ctx.search.spring_final = best.fit.spring_model
        ctx.say(f"round {round_no}: further effects are fitted with {stand_in.spring_model_label} standing in "
                f"for {best.fit.spring_model_label}")
        state.current = stand_in
    ctx.say(f"round {round_no}: {best.effect} kept (delta BIC {best.delta_bic:.0f}); rms {state.current.rms:.3g} "
            f"{ctx.record.unit}; {time.monotonic() - ctx.budget.started:.0f} s")


def select_round(ctx, state, round_no: int) -> bool:
    """One round of forward selection; True when an effect was kept."""
    current = state.current
    state.round_ref[round_no] = current
    jobs = candidate_jobs(ctx.rig, ctx.measurement, current, ctx.guesses, ctx.sigma_hf)
    if not jobs:
        return False
    ctx.say(f"round {round_no}: trying {len(jobs)} candidate effect(s): {', '.join(j[0] for j in jobs)}")
    round_cands = _singles(ctx, state, current, jobs, round_no)
    if not round_cands:
        return False
    best = _score(ctx, state, current, round_cands)
    state.candidates.extend(round_cands)
    why = pair_reason(ctx, current, best)
    if why and not at_noise(ctx, current) and not ctx.over() and _pairs(ctx, state, current, jobs, round_no, why,
                                                                          round_cands):
        best = _score(ctx, state, current, round_cands)
    if not earns(ctx, current, best):
        return False
    _keep(ctx, state, best, round_no)
    return True


def select_effects(ctx, state) -> None:
    """Forward selection from ``state.current`` (see the module docstring)."""
    if judge_noise(ctx, state.current).settled:
        if held_out_at_noise(ctx, state.current):
            state.start_at_noise = True
            ctx.say("the starting model is at the noise: no effect is searched")
            return
        ctx.say("the starting model fits its record at the noise but mispredicts a held-out record: "
                "searching with the held-out records' evidence")
    round_no = 0
    while True:
        round_no += 1
        if not select_round(ctx, state, round_no):
            return
        if at_noise(ctx, state.current) and held_out_at_noise(ctx, state.current):
            return
        if ctx.over():
            ctx.skipped.append(f"round {round_no + 1} (time budget)")
            return

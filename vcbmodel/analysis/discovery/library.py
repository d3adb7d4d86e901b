"""The candidate terms of a discovered torque: their names, columns on a measured state, physical
readings, and the directions the fitted model itself can still move in.

The terms are the law's (:data:`vcbmodel.laws.discovered.TERMS`): a column is a term evaluated
with :class:`~vcbmodel.laws.friction.ArrayOps` on the smoothed record, so the regression sees
exactly the function the refitted model then integrates.
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from ...laws.discovered import TERMS, term
from ...laws.friction import ArrayOps
from .force import ForceEstimate, model_acceleration

#: The library discovery searches on a pendulum record: the law's terms but the position windows
#: (a swing covers under a third of a turn, where the harmonics and the angle's powers already
#: describe a torque of the angle).
DEFAULT_LIBRARY = tuple(name for name in TERMS if not name.startswith("rub_"))
#: The library on a cam drop: the cam turns one way at up to hundreds of rad/s through most of a
#: turn, so the terms are the speed's (w|w| drag, w^3), the angle's (harmonics: a cam's unbalance
#: or profile; the angle and its cube: a spring; position windows: a localized rub), a constant and
#: a drift. The sign_exp terms are left out: their Stribeck speeds (0.05-0.5 rad/s) are passed within
#: the first tenth of a millisecond, before the samples the regression uses (faster than 5 % of the
#: peak speed), so on a drop they are a constant. The springs' state adds nothing for the massless
#: springs (a function of the angle) and the chain's is not measured (the model's is used, :mod:`.force`).
CAM_LIBRARY = tuple(name for name in TERMS if not name.startswith("sign_exp_"))
#: The library by experiment.
LIBRARIES = {"pendulum": DEFAULT_LIBRARY, "cam_drop": CAM_LIBRARY}


def library_for(experiment: str) -> tuple:
    """The terms discovery searches on a record of ``experiment`` (its :data:`LIBRARIES` entry)."""
    return LIBRARIES.get(experiment, DEFAULT_LIBRARY)
#: Relative step of the finite differences of the model's torque in its own parameters.
PARAMETER_STEP = 1e-4


def columns(names: Sequence[str], est: ForceEstimate) -> np.ndarray:
    """(samples, terms) matrix: each term (its unit's torque per unit coefficient) on the estimate's state."""
    cols = []
    with np.errstate(all="ignore"):
        for name in names:
            v = term(name).value(est.t, est.theta, est.w, ArrayOps)
            cols.append(np.broadcast_to(np.asarray(v, float), est.t.shape))
    return np.column_stack(cols) if cols else np.zeros((est.t.size, 0))


def reading(name: str, coefficient: float | None = None) -> str:
    """What a torque of this term's form usually is (a physical reading). With the fitted
    ``coefficient``: a ``sign_exp`` term adds to the applied torque, so only a negative one opposes
    the motion near zero speed (a breakaway peak); a positive one aids it there, which the reading says."""
    text = term(name).reading
    if name.startswith("sign_exp_") and coefficient is not None and coefficient > 0:
        speed = name.removeprefix("sign_exp_")
        text = (f"with this sign, friction lower near zero speed than above {speed} rad/s (the term aids the "
                "motion there: no breakaway peak; it offsets another term or the registered friction)")
    return text


def unit(name: str) -> str:
    """The unit of the term's coefficient (coefficient x term is N m)."""
    return term(name).unit


def model_columns(fit, est: ForceEstimate) -> tuple[list[str], np.ndarray]:
    """(names, (samples, k) matrix): how the model's torque I alpha_model (N m) changes per unit of
    each of its varied parameters, on the estimate's state. A missing torque is regressed with
    these free (the refit moves the model's values too), so a term is not credited with what a
    registered parameter already does (viscous friction's w, Coulomb's sign(w))."""
    names, cols = [], []
    base = model_acceleration(est.rig, fit, est.t, est.theta, est.w, chain=est.chain)
    for p in fit.parameters.values():
        if p.kind != "model" or not p.vary:
            continue
        h = PARAMETER_STEP * max(abs(p.value), 1e-3)
        moved = replace(fit, parameters={**fit.parameters, p.name: replace(p, value=p.value + h)})
        acc = model_acceleration(est.rig, moved, est.t, est.theta, est.w, chain=est.chain)
        names.append(p.name)
        cols.append(est.inertia * (acc - base) / h)
    return names, (np.column_stack(cols) if cols else np.zeros((est.t.size, 0)))

"""Design-study helpers on top of :mod:`vcbmodel.analysis.sweep`: the closing springs' preload
and stored energy, and run evaluations beyond the figures of merit.

The evaluations are top-level functions ``f(rig, t_end) -> dict`` with their ``..._COLUMNS``:
the sweep's workers import them by name (nothing Exudyn-side is pickled).
"""
from __future__ import annotations

import copy
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import parameters as P
from ..experiments import experiment_of
from ..experiments.simulation import simulate
from ..laws.friction import ArrayOps
from ..laws.mechanics import cam_pin

if TYPE_CHECKING:
    from ..rig.data import Rig

#: The shaft friction's effects: "dropping the friction" turns all of them off.
FRICTION_EFFECTS = ("coulomb_friction", "stribeck", "viscous_friction")


# --- the closing springs ---------------------------------------------------------------------------

def spring_length(rig: Rig, theta: float | np.ndarray) -> float | np.ndarray:
    """Pin-to-anchor length (m) of a closing spring at cam angle(s) ``theta`` (rad)."""
    bx, by = cam_pin(np.asarray(theta, float), rig.cam, ArrayOps)
    length = np.hypot(bx - rig.closing_spring.anchor[0], by - rig.closing_spring.anchor[1])
    return float(length) if length.ndim == 0 else length


def charged_length(rig: Rig) -> float:
    """Length (m) of a closing spring when charged (the cam at its initial angle)."""
    return float(spring_length(rig, rig.cam.initial_angle))


def preload(rig: Rig) -> float:
    """Pull (N) of one closing spring when charged: k0 (L_charged - L_free)."""
    s = rig.closing_spring
    return s.stiffness * (charged_length(rig) - s.free_length)


def stored_energy(rig: Rig) -> float:
    """Energy (J) stored in all closing springs when charged: count * F0^2 / (2 k0)."""
    s = rig.closing_spring
    return s.count * 0.5 * s.stiffness * (charged_length(rig) - s.free_length) ** 2


def free_length_for(rig: Rig, pull: float, stiffness: float | None = None) -> float:
    """Free length (m) that gives one spring the charged pull ``pull`` (N) at ``stiffness``
    (N/m, default the rig's): the way a design study sets the preload."""
    k = rig.closing_spring.stiffness if stiffness is None else stiffness
    return charged_length(rig) - pull / k


# --- evaluations ---------------------------------------------------------------------------------

#: Columns of :func:`closing_design`: the closing's figures of merit (the slowest and fastest
#: pole's zone speed among them), the springs' charged pull and stored energy, their smallest static
#: pull during the run and the energy they give up to the first touch.
DESIGN_COLUMNS = experiment_of("vcb_closing").figure_columns + ("latched", "preload_N", "stored_energy_J",
                                                                  "min_spring_force_N", "released_to_touch_J")


def closing_design(rig: Rig, t_end: float | None = None) -> dict:
    """A closing's figures of merit plus the closing springs' preload (N, one spring), stored
    energy (J, all springs) and smallest static pull k0 (L(theta) - L_free) over the run (N; a
    tension spring must stay stretched: below zero it would push)."""
    record = experiment_of(rig.experiment)
    result = simulate(rig, t_end=t_end, backend="fast")
    fom = record.figures_of_merit(result, rig)
    out = {k: fom.get(k) for k in experiment_of(rig.experiment).figure_columns}
    out["latched"] = fom.get("latched")  # the cam reached its latch (True), turned back (False), run too short (None)
    s = rig.closing_spring
    lengths = spring_length(rig, result.channels["cam_angle"])
    out.update(preload_N=preload(rig), stored_energy_J=stored_energy(rig),
               min_spring_force_N=float(s.stiffness * (np.min(lengths) - s.free_length)),
               released_to_touch_J=released_to_touch(rig, result, fom.get("first_touch_s")))
    return out


def pole_columns(count: int) -> tuple:
    """Columns of :func:`closing_poles` for a breaker of ``count`` poles."""
    per = tuple(f"pole_{i + 1}_{name}" for i in range(count) for name in ("zone_speed_m_s", "bounces", "bounce_s"))
    return experiment_of("vcb_closing").figure_columns + ("latched",) + per


def closing_poles(rig: Rig, t_end: float | None = None) -> dict:
    """A closing's figures of merit with every pole's own: its closing speed over the analyser's zone
    (m/s), its bounce count and bounce duration (s); and ``latched``: whether the cam reached its
    holding latch after the touch (True), turned back short of it (False: the closing fails), or the
    run ended first (None: give a longer ``t_end``)."""
    result = simulate(rig, t_end=t_end, backend="fast")
    fom = experiment_of(rig.experiment).figures_of_merit(result, rig)
    out = {k: fom.get(k) for k in experiment_of(rig.experiment).figure_columns}
    out["latched"] = fom.get("latched")
    per = fom.get("per_pole", {})
    for i, (v, n, d) in enumerate(zip(per.get("closing_speed_m_s", []), per.get("bounces", []),
                                      per.get("bounce_duration_s", []))):
        out.update({f"pole_{i + 1}_zone_speed_m_s": v, f"pole_{i + 1}_bounces": n, f"pole_{i + 1}_bounce_s": d})
    return out


def released_to_touch(rig: Rig, result, first_touch: float | None) -> float | None:
    """Energy (J) all closing springs give up from the charged state to the first pole's touch:
    count (F0^2 - F_touch^2) / (2 k0), F_touch their pull at the cam angle of the touch; None if no
    pole touches. What a design spends to close, where the stored energy also counts the pull the
    springs keep."""
    if first_touch is None:
        return None
    s = rig.closing_spring
    theta = float(np.interp(first_touch, result.t, result.channels["cam_angle"]))
    pull = s.stiffness * (spring_length(rig, theta) - s.free_length)
    return float(s.count * (preload(rig) ** 2 - pull**2) / (2 * s.stiffness))


#: Columns of :func:`conclusion_effects`.
CONCLUSION_COLUMNS = ("closing_time_s", "rms_no_friction_m", "rms_massless_m", "closing_change_no_friction_s",
                      "closing_change_massless_s", "ratio_rms", "ratio_closing_time")


def _closing_time(rig, result):
    return experiment_of(rig.experiment).figures_of_merit(result, rig)["closing_time_s"]


def conclusion_effects(rig: Rig, t_end: float | None = None) -> dict[str, float]:
    """The paper's conclusion at one design point: how far the closing moves when the shaft
    friction is dropped (all of :data:`FRICTION_EFFECTS` off) and when the spring is made
    massless, each against the rig's full model.

    Returns the rms change of the follower displacement (m, over the run) and the closing
    time's change (s) for each, and their ratios friction / spring motion (> 1: friction
    matters more). A closing time that is not reached is NaN."""
    full = simulate(rig, t_end=t_end, backend="fast")
    no_friction = simulate(rig, tuple(e for e in rig.model.effects if e not in FRICTION_EFFECTS), t_end=t_end,
                           backend="fast")
    massless = simulate(rig, spring_model="massless", t_end=t_end, backend="fast")
    y = full.channels["follower_displacement"]

    def rms(r):
        return float(np.sqrt(np.mean((np.interp(full.t, r.t, r.channels["follower_displacement"]) - y) ** 2)))

    def change(r):
        a, b = _closing_time(rig, r), _closing_time(rig, full)
        return float("nan") if a is None or b is None else a - b

    t0 = _closing_time(rig, full)
    out = {"closing_time_s": float("nan") if t0 is None else t0,
           "rms_no_friction_m": rms(no_friction), "rms_massless_m": rms(massless),
           "closing_change_no_friction_s": change(no_friction), "closing_change_massless_s": change(massless)}
    out["ratio_rms"] = out["rms_no_friction_m"] / out["rms_massless_m"] if out["rms_massless_m"] > 0 else math.inf
    a, b = abs(out["closing_change_no_friction_s"]), abs(out["closing_change_massless_s"])
    out["ratio_closing_time"] = a / b if b > 0 else (math.inf if a > 0 else float("nan"))
    return out


# --- the uncertain parameters of a breaker -------------------------------------------------------

@dataclass(frozen=True)
class Factor:
    """An uncertain design parameter: ``nominal`` +- ``tolerance`` (absolute, read as +-3 sigma
    of a manufacturing scatter, or as the range of a sensitivity study), kept within
    [``lower``, ``upper``]. ``kind`` says how a value becomes rig overrides (:meth:`overrides`):
    ``path`` sets ``path``; ``preload`` sets the closing springs' free length at fixed
    stiffness; ``mu_k`` sets friction.mu_k and keeps friction.mu_s >= mu_k; ``gap_spread`` sets
    every pole's gap offset to value * its nominal pattern (max |offset| = value)."""

    key: str
    label: str
    unit: str
    nominal: float
    tolerance: float
    basis: str
    kind: str = "path"
    path: str = ""
    lower: float = -math.inf
    upper: float = math.inf
    display: float = 1.0  # plot scale (1e3: mm or ms)
    pattern: tuple = ()
    distribution: str = "normal"  # of a tolerance study: normal (sd = tolerance / 3) or uniform (low..high)

    @property
    def low(self) -> float:
        return max(self.nominal - self.tolerance, self.lower)

    @property
    def high(self) -> float:
        return min(self.nominal + self.tolerance, self.upper)

    @property
    def sd(self) -> float:
        return self.tolerance / 3.0

    def clip(self, value: float) -> float:
        return float(min(max(value, self.lower), self.upper))

    def overrides(self, value: float, rig: Rig) -> dict[str, float]:
        value = self.clip(value)
        if self.kind == "preload":
            return {"closing_spring.free_length": free_length_for(rig, value)}
        if self.kind == "mu_k":
            return {"friction.mu_k": value, "friction.mu_s": max(rig.friction.get("mu_s", value), value)}
        if self.kind == "gap_spread":
            return {f"breaker.poles.gap_offsets.{i}": value * p for i, p in enumerate(self.pattern)}
        return {self.path: value}


def with_viscous_shaft(data: dict) -> dict:
    """A copy of a rig's JSON object whose model lists the shaft's viscous friction, at the
    rig's value or 0 (the same closing), so that its uncertainty can be varied."""
    out = copy.deepcopy(data)
    out.setdefault("friction", {}).setdefault("viscous", 0.0)
    if "viscous_friction" not in out["model"]["effects"]:
        out["model"]["effects"] = list(out["model"]["effects"]) + ["viscous_friction"]
    return out


#: Assumed tolerances, relative to the nominal value unless stated (+-, read as +-3 sigma).
#: Assumptions, not data: the paper gives none; each has its reason in ``basis``. The viscous shaft
#: friction and the restitution are not tolerances but ranges with a source (:data:`RANGES`).
TOLERANCES = {
    "preload": (0.05, "helical-spring load tolerances of a few percent (quality grades as in DIN 2097 / EN 15800); "
                      "assumed +-5 %, set through the free length at fixed stiffness"),
    "spring_mass": (0.05, "wire diameter and coil count tolerances; assumed +-5 %"),
    "mu_k": (0.25, "shaft friction scatter between units and with lubrication and wear; the example pendulum "
                   "records span mu_k 0.09-0.16 (about +-25 % around 0.13)"),
    "viscous": (0.5, "a rig's own viscous term, poorly identified and temperature dependent; assumed +-50 %"),
    "opening_preload": (0.10, "opening spring load tolerance; assumed +-10 %"),
    "moving_mass": (0.05, "moving contact, stem and terminal mass; assumed +-5 %"),
    "gap_spread": (0.5, "assembly spread of the poles' gaps (largest |offset|); assumed +-50 % of the nominal "
                        "spread (parameters.py: +-0.3 mm assembly tolerance)"),
}


#: Inputs drawn uniform over a range with a source rather than around a nominal (parameters.py):
#: {key: ((low, high), source)}.
RANGES = {
    "viscous": (P.VISCOUS_BEARING_ESTIMATE,
                "bearing estimate (parameters.VISCOUS_BEARING_ESTIMATE): Petroff's law for the cam shaft's two greased "
                "30 mm journals of 20 mm radius, 12.5-37.5 um radial clearance (40 H7/f7), grease viscosity 0.05-0.4 Pa s: "
                "Cv = 2 x 2 pi mu r^3 L / c; not the pendulum's Cv, which is fitted at 0.5 rad/s, not at the cam's "
                "100-200 rad/s"),
    "restitution": (P.RESTITUTION_RANGE,
                    "published metal-on-metal restitution at 0.3-3 m/s, 0.5-0.95 (Goldsmith, Impact, 1960; Johnson, "
                    "Contact Mechanics, 1985, sec. 11.4): Cu-Cr between copper and steel, 0.5-0.9 "
                    "(parameters.RESTITUTION_RANGE); no measurement of Cu-Cr vacuum contacts found"),
}


def breaker_factors(rig: Rig, viscous_range: tuple[float, float] | None = None,
                    viscous_basis: str | None = None) -> list[Factor]:
    """The uncertain parameters of a ``vcb_closing`` rig (loaded; its model should list
    ``viscous_friction`` for the viscous factor: :func:`with_viscous_shaft`), nominal values
    read from the rig, tolerances from :data:`TOLERANCES`. A rig without a viscous term
    (``friction.viscous`` 0) gets the viscous factor uniform over ``viscous_range`` (N m s/rad,
    default the bearing estimate of :data:`RANGES`, its source ``viscous_basis``); the contact
    restitution is uniform over its range (:data:`RANGES`), whatever the rig's value. Each factor's
    ``basis`` names where its distribution comes from."""
    s, b, f = rig.closing_spring, rig.breaker, rig.friction
    offsets = np.asarray(b.poles.gap_offsets, float)
    spread = float(np.max(np.abs(offsets)))
    if spread > 0:
        pattern = tuple(float(o / spread) for o in offsets)
    else:  # no nominal spread: poles alternate around the first
        pattern = tuple(float((-1) ** (i + 1) * (i > 0)) for i in range(len(offsets)))
        spread = 1e-4  # 0.1 mm: the spread the assembly tolerance allows, as a nominal to vary about
    gap_floor = -(b.poles.contact_gap * 0.5)

    def rel(key, nominal):
        return TOLERANCES[key][0] * abs(nominal), TOLERANCES[key][1]

    factors = []
    tol, why = rel("preload", preload(rig))
    factors.append(Factor("preload", "closing-spring preload (free length)", "N", preload(rig), tol, why,
                          kind="preload", lower=1.0))
    tol, why = rel("spring_mass", s.mass)
    factors.append(Factor("spring_mass", "closing-spring mass", "kg", s.mass, tol, why, path="closing_spring.mass",
                          lower=1e-3))
    tol, why = rel("mu_k", f["mu_k"])
    factors.append(Factor("mu_k", "shaft friction mu_k", "-", f["mu_k"], tol, why, kind="mu_k", lower=0.0))
    if f.get("viscous", 0.0) > 0:
        tol, why = rel("viscous", f["viscous"])
        factors.append(Factor("viscous", "shaft viscous friction Cv", "N m s/rad", f["viscous"], tol, why,
                              path="friction.viscous", lower=0.0))
    elif "viscous" in f:
        (lo, hi), why = RANGES["viscous"]
        if viscous_range is not None:
            (lo, hi), why = viscous_range, viscous_basis or "given range"
        factors.append(Factor("viscous", "shaft viscous friction Cv", "N m s/rad", 0.5 * (lo + hi), 0.5 * (hi - lo),
                              f"the rig has none; uniform {lo:g}-{hi:g} N m s/rad: {why}", path="friction.viscous",
                              lower=lo, upper=hi, distribution="uniform"))
    tol, why = rel("opening_preload", b.opening_spring.preload)
    factors.append(Factor("opening_preload", "opening-spring preload", "N", b.opening_spring.preload, tol, why,
                          path="breaker.opening_spring.preload", lower=0.0))
    tol, why = rel("moving_mass", b.poles.moving_mass)
    factors.append(Factor("moving_mass", "pole moving mass", "kg", b.poles.moving_mass, tol, why,
                          path="breaker.poles.moving_mass", lower=1e-3))
    if b.contact.restitution is not None:
        (lo, hi), why = RANGES["restitution"]
        factors.append(Factor("restitution", "contact restitution e", "-", 0.5 * (lo + hi), 0.5 * (hi - lo),
                              f"uniform {lo:g}-{hi:g} (the rig's {b.contact.restitution:g} is inside): {why}",
                              path="breaker.contact.restitution", lower=lo, upper=hi, distribution="uniform"))
    tol, why = rel("gap_spread", spread)
    factors.append(Factor("gap_spread", "pole gap spread (largest offset)", "m", spread, tol, why,
                          kind="gap_spread", lower=0.0, upper=-gap_floor, display=1e3, pattern=pattern))
    return factors


def runs_of(factors: Sequence[Factor], values: np.ndarray, rig: Rig) -> list[dict[str, float]]:
    """Override dicts, one per row of ``values`` (rows x factors), for :func:`sweep`'s ``runs``."""
    runs = []
    for row in np.atleast_2d(values):
        o = {}
        for factor, v in zip(factors, row):
            o.update(factor.overrides(float(v), rig))
        runs.append(o)
    return runs


def json_ready(obj: Any) -> Any:
    """``obj`` with every non-finite float (NaN: not reached or failed) as None, numpy scalars
    and arrays as Python numbers and lists: strict JSON for the studies' outputs."""
    if isinstance(obj, dict):
        return {str(k): json_ready(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple, np.ndarray)):
        return [json_ready(v) for v in obj]
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    return obj


# --- statistics of the studies ---------------------------------------------------------------------

def wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """95 % (z = 1.96) Wilson score interval of a fraction k / n; NaN for n = 0."""
    if n == 0:
        return (float("nan"), float("nan"))
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0.0, c - h), min(1.0, c + h))


def mean_shift(draws: np.ndarray, y: np.ndarray, nominal: np.ndarray, y_nominal: float) -> dict:
    """Why a tolerance study's mean differs from its nominal run: ``y`` (runs) regressed linearly on
    the ``draws`` (runs x inputs) by least squares; each input's share of the shift is its slope times
    (its mean draw - its ``nominal``); what the line leaves is the response's curvature (and the
    regression's error). Returns ``shift`` (mean(y) - y_nominal), ``shares`` (per input, in y's unit),
    ``curvature`` (the rest) and ``r2`` of the fit."""
    x = np.asarray(draws, float)
    y = np.asarray(y, float)
    good = np.isfinite(y) & np.all(np.isfinite(x), axis=1)
    x, y = x[good], y[good]
    a = np.column_stack([np.ones(len(y)), x])
    coef, *_ = np.linalg.lstsq(a, y, rcond=None)
    fit = a @ coef
    shares = coef[1:] * (x.mean(axis=0) - np.asarray(nominal, float))
    shift = float(y.mean() - y_nominal)
    total = float(np.sum((y - y.mean()) ** 2))
    return {"shift": shift, "shares": [float(v) for v in shares], "curvature": shift - float(np.sum(shares)),
            "r2": 1.0 - float(np.sum((y - fit) ** 2)) / total if total > 0 else float("nan")}

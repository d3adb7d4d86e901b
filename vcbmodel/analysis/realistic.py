"""Realistic synthetic records: what comes off a rig, from a truth the diagnosis does not fit with.

:mod:`.synthetic` makes records from the fitted model family itself, at the model's t = 0, with
white noise: the diagnosis is right on those by construction. The records here carry what real
records carry, and their truth is structurally different from every candidate model:

- **friction** from the independent reference (:mod:`vcbmodel.reference.independent`: sympy
  Lagrange equations, event-driven sticking, DOP853), not the Exudyn model the diagnosis fits;
- **the spring's mass** as a converged chain of twenty equal masses (``lumped-20:uniform``) or the
  ANCF continuum with 16 elements, while the candidates are lumped-1..3 chains (``exact`` and
  ``paper``) and the 8-element ANCF spring;
- an **unregistered effect**: position-dependent journal friction (a bearing with a defect:
  mu_k (1 + a sin(2 pi theta / lambda))), integrated here with its own event-driven sticking;
  no registered effect has this form;
- optionally (``friction_truth``) **friction from outside the fitted family** for the pendulum
  and the massless cam drop (:mod:`vcbmodel.reference.truth_friction`): Tustin's exponential
  Stribeck curve, LuGre (micrometres of pre-sliding), Dahl, or Coulomb and viscous friction with a
  position-dependent (cogging) torque. The default ``hybrid`` is the fitted law itself, from the
  independent reference; its records are those of earlier versions, seed for seed;
- or (``friction_truth``, pendulums only) Coulomb and viscous friction with an effect outside the
  fitted law (:data:`TORQUE_TRUTHS`, solved by :mod:`vcbmodel.reference.torque_truth`): air drag on
  a paddle of physical size, -c w|w| with c = 0.5 rho Cd A R^3, or a Coulomb level drifting in time
  as a bearing warms, mu_k + a t.

Complications (each drawn at random within the stated range, or chosen):

==================  ===========================================================================
``pre_trigger``     the record starts before the release, the shaft at rest: 0-200 ms (pendulum),
                    0-3 ms (camera)
``initial_angle``   the true release angle is off the rig's nominal by up to 1 deg
``offset``          sensor zero offset up to 5 mrad (0.2 mm for the follower)
``gain``            sensor gain off by up to 3 %
``correlated``      low-pass filtered noise, lag-1 correlation 0-0.95 (AR(1))
``hand_start``      pendulum: the record starts while a hand moves the pendulum to the release
                    angle (and may hold it there), then lets go
``quantised``       an encoder: readings rounded to 0.09 deg, no other noise
``time_base``       the record's clock runs 0.1-0.3 % fast, with 20 us jitter
``period``          the rig's nominal inertia is off: the period differs by 2-4 %
``mains``           mains pickup on the sensor's lead: a 50 or 60 Hz line of 0.2-0.5 mrad (0.2-0.5 of
                    the camera's noise for a cam drop), steady through the record (in true time)
``logger_12bit``    a 12-bit data logger reads the (noisy) potentiometer: readings rounded to the
                    logger's step, :data:`LOGGER_STEP` (the sensor's noise stays)
==================  ===========================================================================

Hidden effects: none, one (``coulomb_friction``, ``viscous_friction``, ``stribeck``,
``spring_mass``), two (``viscous_friction`` + ``stribeck`` for a pendulum, ``coulomb_friction`` +
``spring_mass`` for a cam drop), or ``unregistered``.
"""
from __future__ import annotations

import copy
import json
import math
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

from .. import parameters as P
from ..experiments import experiment_of
from ..experiments.loading import rig_from_data
from ..experiments.simulation import simulate
from ..laws.breaker import pole_gaps
from ..records.analyser import figures_of_merit as analyser_figures
from ..records.measurement import Measurement, write_measurement
from ..model.effects import EFFECTS
from ..reference.torque_truth import pendulum_with_torque
from ..reference.truths import FRICTION_TRUTHS, friction_truth_angle, position_dependent_pendulum, static_load

COMPLICATIONS = ("pre_trigger", "initial_angle", "offset", "gain", "correlated", "hand_start", "quantised",
                 "time_base", "period", "mains", "logger_12bit")
#: Hidden-effect cases: name -> (experiment, starting effects, truth effects).
HIDDEN = {
    "pend_none": ("pendulum", ("coulomb_friction", "viscous_friction"), ("coulomb_friction", "viscous_friction")),
    "pend_visc": ("pendulum", ("coulomb_friction",), ("coulomb_friction", "viscous_friction")),
    "pend_coul": ("pendulum", ("viscous_friction",), ("coulomb_friction", "viscous_friction")),
    "pend_strib": ("pendulum", ("coulomb_friction", "viscous_friction"),
                   ("coulomb_friction", "stribeck", "viscous_friction")),
    "pend_two": ("pendulum", ("coulomb_friction",), ("coulomb_friction", "stribeck", "viscous_friction")),
    "pend_unregistered": ("pendulum", ("coulomb_friction", "viscous_friction"),
                          ("coulomb_friction", "viscous_friction", "position_dependent_friction")),
    "cam_none": ("cam_drop", ("coulomb_friction",), ("coulomb_friction",)),
    "cam_coul": ("cam_drop", (), ("coulomb_friction",)),
    "cam_mass": ("cam_drop", ("coulomb_friction",), ("coulomb_friction", "spring_mass")),
    "cam_two": ("cam_drop", (), ("coulomb_friction", "spring_mass")),
}
#: Friction truths: ``hybrid`` (the fitted law, by the independent reference) or one from outside
#: the family (:data:`vcbmodel.reference.truths.FRICTION_TRUTHS`).
#: Pendulum truths with an effect the fitted law lacks (Coulomb and viscous friction besides):
#: air drag, a drifting Coulomb level.
TORQUE_TRUTHS = ("air_drag", "drifting_coulomb")
FRICTION_TRUTH_CHOICES = ("hybrid",) + FRICTION_TRUTHS + TORQUE_TRUTHS
#: Registered effects an out-of-family pendulum truth resembles beyond Coulomb and viscous
#: friction (the diagnosis' nearest right answer): the fall from mu_s to mu_k of Tustin's and
#: LuGre's curves is what ``stribeck`` describes. Dahl has no static peak; the position torque
#: resembles nothing registered. A cam drop passes the Stribeck range within its first
#: microseconds: its nearest answer is the case's own.
NEAREST_EXTRA = {"tustin": ("stribeck",), "lugre": ("stribeck",), "dahl": (), "position_torque": (),
                 "air_drag": (), "drifting_coulomb": ()}
#: Registered effects a truth has that its record may not show: named or not, the diagnosis is right
#: (a real paddle's drag, 4e-4 to 5e-3 N m s^2/rad^2, is often below what a swing's record resolves).
OPTIONAL_EXTRA = {"air_drag": tuple(e for e in ("aerodynamic_drag",) if e in EFFECTS)}
QUANTUM = math.radians(0.09)  # encoder step (4000 counts per revolution)
#: A 12-bit logger's step on a single-turn potentiometer: the pot's 340 deg electrical span over
#: the logger's full scale of 4096 counts (1.45 mrad, about three times a pendulum pot's noise).
LOGGER_STEP = math.radians(340.0) / 4096
#: Whole-breaker closings recorded as a breaker analyser gives them: the follower's travel (a
#: camera, 0.05 mm) and one 0/1 contact channel per pole (optionally each pole's travel, 0.02 mm).
#: Start effects, truth effects; the rig gives every value but the hidden effects'. Truth
#: spring: the ANCF continuum with 16 elements (the rig's model: lumped-2, paper).
CLOSING = {
    "closing_none": (("coulomb_friction", "stribeck", "spring_mass", "contact_damping", "bellows_force"),
                     ("coulomb_friction", "stribeck", "spring_mass", "contact_damping", "bellows_force")),
    "closing_damping": (("coulomb_friction", "stribeck", "spring_mass", "bellows_force"),
                        ("coulomb_friction", "stribeck", "spring_mass", "contact_damping", "bellows_force")),
    "closing_friction": (("spring_mass", "contact_damping", "bellows_force"),
                         ("coulomb_friction", "spring_mass", "contact_damping", "bellows_force")),
}
for _name, (_start, _truth) in CLOSING.items():
    HIDDEN[_name] = ("vcb_closing", _start, _truth)


def hidden_answer(case: str, friction_truth: str = "hybrid") -> list[str] | None:
    """The effects the diagnosis should name, in no particular order (None: an unregistered one).
    With an out-of-family ``friction_truth``, the nearest registered ones (:data:`NEAREST_EXTRA`)."""
    experiment, start, truth = HIDDEN[case]
    if "position_dependent_friction" in truth or friction_truth == "position_torque":
        return None
    shown = set(truth)
    if friction_truth != "hybrid" and experiment == "pendulum":
        shown |= set(NEAREST_EXTRA[friction_truth])
    return sorted(e for e in shown if e not in start)


def friction_truth_cases(friction_truth: str) -> list[str]:
    """The hidden-effect cases a friction truth applies to: every case for ``hybrid``; else the
    pendulum's and the massless cam drop's (not the unregistered friction, the spring's mass or
    the closing)."""
    if friction_truth not in FRICTION_TRUTH_CHOICES:
        raise ValueError(f"unknown friction truth {friction_truth!r} (known: {', '.join(FRICTION_TRUTH_CHOICES)})")
    if friction_truth in TORQUE_TRUTHS:  # Coulomb and viscous friction besides: no Stribeck fall in the truth
        return [c for c, (e, _, truth) in HIDDEN.items() if e == "pendulum" and set(truth) <= {
            "coulomb_friction", "viscous_friction"}]
    return [c for c, (e, _, truth) in HIDDEN.items() if friction_truth == "hybrid" or (
        e in ("pendulum", "cam_drop") and not {"position_dependent_friction", "spring_mass"} & set(truth))]


def _draw_complications(record, rng, complications):
    """Values of the chosen complications (dict name -> value), by the experiment's usual sensor."""
    c = {}
    camera = record.sensor == "camera"
    for name in complications:
        if name == "pre_trigger":
            c[name] = float(rng.uniform(0.0005, 0.003) if camera else rng.uniform(0.02, 0.2))
        elif name == "initial_angle":
            c[name] = float(np.radians(rng.uniform(0.3, 1.0)) * rng.choice([-1, 1]))
        elif name == "offset":
            c[name] = float(rng.uniform(1e-3, 5e-3) * rng.choice([-1, 1]))
        elif name == "gain":
            c[name] = float(1 + rng.uniform(0.01, 0.03) * rng.choice([-1, 1]))
        elif name == "correlated":
            c[name] = float(rng.uniform(0.5, 0.95) if not camera else rng.uniform(0.5, 0.9))
        elif name == "hand_start":
            c[name] = {"ramp_s": float(rng.uniform(0.2, 0.5)), "hold_s": float(rng.choice([0.0, rng.uniform(0.1, 0.4)])),
                       "from_fraction": float(rng.uniform(0.3, 0.8)), "record_from": float(rng.uniform(0.0, 0.15))}
        elif name == "quantised":
            c[name] = QUANTUM
        elif name == "time_base":
            c[name] = float(rng.uniform(0.001, 0.003))
        elif name == "period":
            c[name] = float(rng.uniform(0.02, 0.04) * rng.choice([-1, 1]))
        elif name == "mains":
            scale = record.noise_sigma / 5e-4  # 0.2-0.5 of the sensor's noise level
            c[name] = {"frequency_hz": float(rng.choice([50.0, 60.0])), "amplitude": float(rng.uniform(2e-4, 5e-4) * scale),
                       "phase": float(rng.uniform(0.0, 2 * math.pi))}
        elif name == "logger_12bit":
            c[name] = LOGGER_STEP
        else:
            raise ValueError(f"unknown complication {name!r} (known: {', '.join(COMPLICATIONS)})")
    return c


def realistic_closing(case: str, seed: int, folder: str | Path, complications: Sequence[str] = (),
                      analyser: bool = True, travels: bool = False,
                      values: Mapping[str, Any] | None = None) -> tuple[Path, Path, dict]:
    """A closing record as a breaker analyser gives it (follower travel from a camera, one 0/1
    contact channel per pole, optionally each pole's travel), from a truth with a 16-element ANCF
    spring.
    Complications: ``pre_trigger`` (0.5-3 ms), ``offset`` (up to 0.2 mm), ``correlated``.
    Returns (rig path, record path, truth dict)."""
    rng = np.random.default_rng(seed)
    _, start, truth_effects = HIDDEN[case]
    folder = Path(folder)
    rig, truth_values = _closing_rig(rng, start)
    drawn = _draw_closing_complications(rng, complications)
    drawn.update(values or {})
    rig["name"] = _record_name(case, seed, complications)
    trig = _closing_truth_rig(rig, truth_values, folder)
    rec = experiment_of("vcb_closing")
    dt = 1.0 / rec.sample_rate
    pre = drawn.get("pre_trigger", 0.0)
    t_end = P.BREAKER_T_END
    n = int(round((t_end + pre) / dt)) + 1
    t_rec = np.arange(n) * dt
    tau_grid = np.arange(int(math.ceil((t_end + 2 * dt) / dt)) + 1) * dt
    res = simulate(trig, truth_effects, truth_values, spring_model="ancf", ancf_elements=16, sample_times=tau_grid)
    tau = np.clip(t_rec - pre, 0.0, None)
    channels, gaps = _analyser_channels(rng, res, trig, tau, tau_grid, rec.noise_sigma, drawn, analyser, travels)
    rig_path, meas_path = _write_record(folder, rig, t_rec, channels,
                                        f"SYNTHETIC (realistic closing): case {case}, seed {seed}, complications "
                                        f"{json.dumps(drawn, default=float)}")
    figs = analyser_figures(tau_grid, [(res.channels[f"pole_{i}_travel"] > g).astype(float) for i, g in
                                       enumerate(gaps, start=1)], res.channels["follower_displacement"])
    truth = {"case": case, "answer": hidden_answer(case), "truth_effects": list(truth_effects),
             "truth_values": truth_values, "truth_spring_model": "ancf (16 elements)", "complications": drawn,
             "release_time": pre, "noise_sigma": rec.noise_sigma, "registered": True, "figures_of_merit": figs,
             "friction_truth": "hybrid", "in_family": True}
    return rig_path, meas_path, truth


def _closing_rig(rng: np.random.Generator, start: Sequence[str]) -> tuple[dict, dict]:
    """The reference breaker's rig file with the drawn friction (mu_k 0.10-0.16, mu_s 1.4-1.7
    mu_k, Stribeck velocity 0.08-0.12 rad/s), restitution (0.45-0.85) and bellows force (100-250
    N), the values of effects not in ``start`` left out; and the truth's values."""
    rig = copy.deepcopy(P.REFERENCE_BREAKER)
    rig["friction"] = {"mu_k": float(rng.uniform(0.1, 0.16)), "stick_velocity": 1e-3,
                       "stribeck_velocity": float(rng.uniform(0.08, 0.12))}
    rig["friction"]["mu_s"] = rig["friction"]["mu_k"] * float(rng.uniform(1.4, 1.7))
    truth_values = dict(rig["friction"])
    restitution = float(rng.uniform(0.45, 0.85))
    bellows = float(rng.uniform(100.0, 250.0))
    truth_values.update(restitution=restitution, bellows_force=bellows)
    rig["breaker"]["contact"]["restitution"] = restitution
    rig["breaker"]["poles"]["bellows_force"] = bellows
    if "contact_damping" not in start:
        rig["breaker"]["contact"].pop("restitution")
    if "coulomb_friction" not in start:
        rig["friction"] = {"stick_velocity": 1e-3}
    rig["model"] = {"effects": list(start), "spring_model": "lumped-2", "lumped_convention": "paper"}
    return rig, truth_values


def _draw_closing_complications(rng: np.random.Generator, complications: Sequence[str]) -> dict:
    """Values of a closing record's complications: pre-trigger 0.5-3 ms (s), follower offset
    0.05-0.2 mm (m, either sign), noise lag-1 correlation 0.5-0.9."""
    drawn = {}
    for name in complications:
        if name == "pre_trigger":
            drawn[name] = float(rng.uniform(0.0005, 0.003))
        elif name == "offset":
            drawn[name] = float(rng.uniform(5e-5, 2e-4) * rng.choice([-1, 1]))
        elif name == "correlated":
            drawn[name] = float(rng.uniform(0.5, 0.9))
        else:
            raise ValueError(f"complication {name!r} does not apply to a closing record")
    return drawn


def _closing_truth_rig(rig: dict, truth_values: Mapping[str, float], folder: Path):
    """The loaded rig as it really is: the rig file with the truth's restitution and bellows force."""
    truth_rig = copy.deepcopy(rig)
    truth_rig["breaker"]["contact"]["restitution"] = truth_values["restitution"]
    truth_rig["breaker"]["poles"]["bellows_force"] = truth_values["bellows_force"]
    return rig_from_data(truth_rig, str(folder / "truth.rig.json"))


def _analyser_channels(rng, res, trig, tau, tau_grid, sigma, drawn, analyser, travels) -> tuple[dict, list]:
    """(channels, pole gaps m): the follower's travel from the camera (m, with offset and noise of
    ``sigma`` m), one 0/1 contact channel per pole and, with ``travels``, each pole's travel (m,
    0.02 mm noise), sampled at record times ``tau`` (s from the release)."""
    n = len(tau)
    channels = {"follower_displacement": np.interp(tau, tau_grid, res.channels["follower_displacement"])
                + drawn.get("offset", 0.0) + _noise(rng, n, sigma, drawn.get("correlated", 0.0))}
    gaps = pole_gaps(trig.breaker.poles)
    if analyser:
        for i, gap in enumerate(gaps, start=1):
            z = np.interp(tau, tau_grid, res.channels[f"pole_{i}_travel"])
            channels[f"pole_{i}_contact"] = (z > gap).astype(float)
            if travels:
                channels[f"pole_{i}_travel"] = z - res.channels[f"pole_{i}_travel"][0] + rng.normal(0, 2e-5, n)
    return channels, gaps


def _record_name(case: str, seed: int, complications: Sequence[str]) -> str:
    return f"{case}-{seed}" + ("+" + "+".join(complications) if complications else "")


def _write_record(folder: Path, rig: dict, t_rec: np.ndarray, channels: dict, header: str) -> tuple[Path, Path]:
    """Write ``<name>.rig.json`` and ``<name>.csv`` (one header line) into ``folder``."""
    rig_path = folder / f"{rig['name']}.rig.json"
    rig_path.write_text(json.dumps(rig, indent=2) + "\n")
    meas_path = folder / f"{rig['name']}.csv"
    write_measurement(Measurement(str(meas_path), t_rec, channels, (header,)), meas_path)
    return rig_path, meas_path


def _noise(rng, n, sigma, phi):
    u = rng.normal(0.0, sigma * math.sqrt(1 - phi**2), n)
    e = np.empty(n)
    e[0] = rng.normal(0.0, sigma)
    for i in range(1, n):
        e[i] = phi * e[i - 1] + u[i]
    return e


def realistic_record(case: str, seed: int, folder: str | Path, complications: Sequence[str] = (),
                     t_end: float | None = None, values: Mapping[str, Any] | None = None,
                     small: bool = False, friction_truth: str = "hybrid") -> tuple[Path, Path, dict]:
    """A rig file and a realistic record for hidden-effect ``case`` (:data:`HIDDEN`) with the
    listed ``complications`` (:data:`COMPLICATIONS`; random values from the seed, or ``values``
    name -> value). ``small``: a small laboratory pendulum (``Experiment.random_rig``, 20 s).
    ``friction_truth``: :data:`FRICTION_TRUTH_CHOICES` (:func:`friction_truth_cases` says where).
    Returns (rig path, record path, truth dict)."""
    experiment, start, truth_effects = HIDDEN[case]
    if case not in friction_truth_cases(friction_truth):
        raise ValueError(f"no {friction_truth} friction truth for case {case!r} "
                         f"(it applies to {', '.join(friction_truth_cases(friction_truth))})")
    rec = experiment_of(experiment)
    if rec.random_rig is None:  # no rig to draw: the reference breaker, recorded by an analyser
        return realistic_closing(case, seed, folder, complications, values=values)
    rng = np.random.default_rng(seed)
    folder = Path(folder)
    drawn = _draw_complications(rec, rng, complications)
    drawn.update(values or {})
    friction = _draw_friction(rng)
    if small and not rec.free_swing:
        raise ValueError(f"a small laboratory rig is a free swing, not a {experiment} test")
    rig = rec.random_rig(rng, friction, start, "small" if small else "realistic")
    t_end = t_end or (20.0 if small else rec.default_duration)
    rig["model"] = {"effects": list(start), "spring_model": "massless"}
    rig["name"] = _record_name(case, seed, complications)
    truth_rig = _truth_rig(rec, rig, drawn)  # the rig as it really is
    t_rec, tau, tau_grid, lead = _record_times(rng, rec, drawn, t_end)
    if friction_truth == "hybrid":
        theta, spring = _true_angle(rng, truth_rig, folder, friction, truth_effects, tau_grid, drawn)
    elif friction_truth in TORQUE_TRUTHS:
        law_values = _torque_truth_values(friction_truth, friction, truth_effects, seed)
        theta, spring = _torque_truth_angle(friction_truth, truth_rig, law_values, tau_grid), None
    else:
        law_values = _friction_truth_values(friction_truth, friction, truth_effects, truth_rig, seed)
        theta, spring = friction_truth_angle(friction_truth, truth_rig, law_values, tau_grid), None
    y = np.interp(np.clip(tau, 0.0, None), tau_grid, theta)
    if drawn.get("hand_start"):
        _hand_start(y, tau, drawn["hand_start"], truth_rig["pendulum"]["initial_angle"])
    y, sigma_used = _sensor(rng, y, drawn, rec.noise_sigma, tau + lead)
    law = "" if friction_truth == "hybrid" else f", friction truth {friction_truth}"
    rig_path, meas_path = _write_record(folder, rig, t_rec, {rec.measured_channel: y},
                                        f"SYNTHETIC (realistic): case {case}, seed {seed}{law}, complications "
                                        f"{json.dumps(drawn, default=float)}")
    answer = hidden_answer(case, friction_truth)
    truth = {"case": case, "answer": answer, "truth_effects": list(truth_effects),
             "truth_friction": friction if friction_truth == "hybrid" else law_values,
             "truth_spring_model": spring or "massless", "complications": drawn, "release_time": lead,
             "noise_sigma": sigma_used, "registered": answer is not None, "friction_truth": friction_truth,
             "in_family": answer is not None and friction_truth == "hybrid",
             "static_load": static_load(truth_rig), "radius": truth_rig["shaft"]["radius"]}
    return rig_path, meas_path, truth


def _torque_truth_values(kind: str, friction: Mapping[str, float], truth_effects: Sequence[str], seed: int) -> dict:
    """An air-drag or drifting truth's values: the drawn mu_k (static level the same: no Stribeck fall),
    the viscous coefficient where the case's truth has viscous friction, and the drag coefficient
    (N m s^2/rad^2) or the drift (1/s) from its own stream of ``seed`` in the ranges of
    :mod:`vcbmodel.parameters`."""
    values = {"mu_k": friction["mu_k"], "mu_s": friction["mu_k"],
              "viscous": friction["viscous"] if "viscous_friction" in truth_effects else 0.0}
    rng = np.random.default_rng([seed, FRICTION_TRUTH_CHOICES.index(kind)])
    if kind == "air_drag":
        area, radius = float(rng.uniform(*P.DRAG_TRUTH_AREA)), float(rng.uniform(*P.DRAG_TRUTH_RADIUS))
        values.update(drag=0.5 * P.AIR_DENSITY * P.FLAT_PLATE_DRAG_COEFFICIENT * area * radius**3, paddle_area=area,
                      paddle_radius=radius)
    else:
        values["mu_k_drift"] = float(rng.uniform(*P.DRIFT_TRUTH_RATE) * rng.choice([-1.0, 1.0]))
    return values


def _torque_truth_angle(kind: str, rig: dict, values: Mapping[str, float], t_eval: np.ndarray) -> np.ndarray:
    """The pendulum's angle (rad) over ``t_eval`` (s) with Coulomb and viscous friction and the air
    drag -c w|w| or the drifting Coulomb level's extra torque -a t r F_n sign(w), by the independent
    torque truth (F_n its own reaction)."""
    p, r, g = rig["pendulum"], rig["shaft"]["radius"], rig["gravity"]
    if kind == "air_drag":
        c = values["drag"]

        def extra(t, th, w):
            return -c * w * abs(w)
    else:
        a, M, inertia, L = values["mu_k_drift"], p["mass"], p["inertia"], p["com_distance"]

        def extra(t, th, w):
            acc = -M * g * L * math.sin(th) / inertia
            fn = M * math.hypot(g * math.cos(th) + L * w * w, g * math.sin(th) + L * acc)
            return -a * t * r * fn * math.copysign(1.0, w) if w != 0.0 else 0.0
    return pendulum_with_torque(p, g, r, {"mu_k": values["mu_k"], "viscous": values["viscous"]}, extra, t_eval)


def _friction_truth_values(kind: str, friction: Mapping[str, float], truth_effects: Sequence[str], truth_rig: dict,
                           seed: int) -> dict:
    """The out-of-family law's values: the drawn mu_s, mu_k and Stribeck (Tustin: decay) velocity,
    the viscous coefficient where the case's truth has viscous friction, the bristles' from
    :mod:`vcbmodel.parameters`, and the position torque drawn from its own stream of ``seed`` (the
    record's other draws are those of the hybrid truth)."""
    values = {"mu_s": friction["mu_s"], "mu_k": friction["mu_k"], "stribeck_velocity": friction["stribeck_velocity"],
              "viscous": friction["viscous"] if "viscous_friction" in truth_effects else 0.0}
    if kind == "lugre":
        values.update(sigma0=P.LUGRE_SIGMA0, sigma1=P.LUGRE_SIGMA1)
    elif kind == "dahl":
        values.update(sigma0=P.DAHL_SIGMA0)
    elif kind == "position_torque":
        rng = np.random.default_rng([seed, FRICTION_TRUTH_CHOICES.index(kind)])
        fraction = float(rng.uniform(*P.POSITION_TORQUE_FRACTION))
        torque = friction["mu_k"] * truth_rig["shaft"]["radius"] * static_load(truth_rig)
        values.update(amplitude=fraction * torque, phase=float(rng.uniform(0.0, 2 * math.pi)),
                      wavenumber=float(rng.integers(P.POSITION_TORQUE_WAVENUMBER[0], P.POSITION_TORQUE_WAVENUMBER[1] + 1)))
    return values


def _draw_friction(rng: np.random.Generator) -> dict:
    """The truth's friction: mu_k 0.09-0.16, mu_s 1.8-2.0 mu_k, Stribeck velocity 0.09-0.15 rad/s,
    stick velocity 1e-3 rad/s."""
    friction = {"mu_k": float(rng.uniform(0.09, 0.16)), "stick_velocity": 1e-3,
                "stribeck_velocity": float(rng.uniform(0.09, 0.15))}
    friction["mu_s"] = friction["mu_k"] * float(rng.uniform(1.8, 2.0))
    return friction


def _truth_rig(rec, rig: dict, drawn: dict) -> dict:
    """The rig as it really is: its release angle off by ``initial_angle`` (rad) and, with
    ``period``, its inertia such that the rig file's nominal one (changed here) is off by the
    period factor (the sign of ``period`` flips if the nominal inertia would fall below M L^2)."""
    truth_rig = copy.deepcopy(rig)
    section, field = rec.initial_angle_field.split(".")
    truth_rig[section][field] += drawn.get("initial_angle", 0.0)
    if "period" in drawn:  # the rig file's inertia is nominal: the true period differs by the factor
        p = rig["pendulum"]
        floor = 1.0 * p["mass"] * p["com_distance"] ** 2
        true_inertia = max(p["inertia"], 1.1 * floor)
        if true_inertia / (1 + drawn["period"]) ** 2 < floor:
            drawn["period"] = -drawn["period"]
        truth_rig["pendulum"]["inertia"] = true_inertia
        p["inertia"] = true_inertia / (1 + drawn["period"]) ** 2
    return truth_rig


def _record_times(rng: np.random.Generator, rec, drawn: Mapping[str, Any], t_end: float):
    """(record times s, model times tau s, model sampling grid s, release time s): the record
    leads the release by the pre-trigger or the hand start, its clock runs ``time_base`` fast
    with 20 us jitter."""
    dt = 1.0 / rec.sample_rate
    pre = drawn.get("pre_trigger", 0.0)
    hand = drawn.get("hand_start")
    lead = pre
    if hand:
        lead = hand["ramp_s"] + hand["hold_s"] - hand["record_from"]
    n = int(round((t_end + lead) / dt)) + 1
    t_rec = np.arange(n) * dt
    clock = drawn.get("time_base", 0.0)
    jitter = drawn.get("jitter", 2e-5) if clock else 0.0  # s (a value "jitter" may set it, 0: none)
    t_true = t_rec * (1 + clock) + (rng.normal(0.0, jitter, n) if jitter else 0.0)
    tau = t_true - lead  # model time
    tau_grid = np.arange(int(math.ceil((tau[-1] + 2 * dt) / dt)) + 1) * dt
    return t_rec, tau, tau_grid, lead


def _true_angle(rng, truth_rig: dict, folder: Path, friction: Mapping[str, float], truth_effects: Sequence[str],
                tau_grid: np.ndarray, drawn: dict):
    """(the true angle over ``tau_grid`` rad, the truth's spring model or None): the position-
    dependent friction's own solve (defect drawn into ``drawn``), a 20-mass chain, or the
    independent reference."""
    model_effects = tuple(e for e in truth_effects if e != "position_dependent_friction")
    truth_values = {k: v for k, v in friction.items()}
    trig = rig_from_data(truth_rig, str(folder / "truth.rig.json"))
    if "position_dependent_friction" in truth_effects:
        defect = {"amplitude": 0.5, "wavelength": float(rng.uniform(0.05, 0.09)), "phase": float(rng.uniform(0, 6.28))}
        fr = {"mu_k": friction["mu_k"], "viscous": friction["viscous"] if "viscous_friction" in truth_effects else 0.0}
        theta = position_dependent_pendulum(truth_rig["pendulum"], truth_rig["gravity"], truth_rig["shaft"]["radius"],
                                            fr, defect["amplitude"], defect["wavelength"], defect["phase"], tau_grid)
        drawn["defect"] = defect
        return theta, None
    if "spring_mass" in truth_effects:
        spring = "lumped-20:uniform"
        return simulate(trig, model_effects, truth_values, spring_model=spring, sample_times=tau_grid).measured, spring
    return simulate(trig, model_effects, truth_values, sample_times=tau_grid, backend="reference").measured, None


def _hand_start(y: np.ndarray, tau: np.ndarray, hand: Mapping[str, float], th0: float) -> None:
    """Before the release (tau < 0), a hand brings the pendulum from ``from_fraction`` of the
    release angle ``th0`` (rad) to it (quintic ramp of ``ramp_s`` s), holds it ``hold_s`` s, with
    a 7 Hz, 0.2 mrad tremor; in place."""
    start_angle = hand["from_fraction"] * th0
    before = tau < 0
    s = np.clip((tau[before] + hand["ramp_s"] + hand["hold_s"]) / hand["ramp_s"], 0.0, 1.0)
    y[before] = start_angle + (th0 - start_angle) * (10 * s**3 - 15 * s**4 + 6 * s**5)
    y[before] += 2e-4 * np.sin(2 * math.pi * 7.0 * tau[before])  # hand tremor


def _sensor(rng: np.random.Generator, y: np.ndarray, drawn: Mapping[str, Any], sigma: float,
            t_true: np.ndarray | None = None):
    """(reading, its noise sigma): gain and offset, then an encoder's rounding or (correlated)
    noise of ``sigma``; mains pickup (a line in true time ``t_true``, s) on the sensor's lead, and
    a logger's rounding of the noisy reading."""
    y = drawn.get("gain", 1.0) * y + drawn.get("offset", 0.0)
    if "quantised" in drawn:
        y = np.round(y / drawn["quantised"]) * drawn["quantised"]
        return y, drawn["quantised"] / math.sqrt(12)
    y = y + _noise(rng, len(y), sigma, drawn.get("correlated", 0.0))
    mains = drawn.get("mains")
    if mains:
        t = np.arange(len(y)) if t_true is None else t_true
        y = y + mains["amplitude"] * np.sin(2 * math.pi * mains["frequency_hz"] * t + mains["phase"])
    if "logger_12bit" in drawn:
        y = np.round(y / drawn["logger_12bit"]) * drawn["logger_12bit"]
        sigma = math.sqrt(sigma**2 + drawn["logger_12bit"] ** 2 / 12)
    return y, sigma


#: Complication groups of the realism study: name -> (complications, experiments it applies to).
GROUPS = {
    "clean": ((), ("pendulum", "cam_drop")),
    "pre_trigger": (("pre_trigger",), ("pendulum", "cam_drop")),
    "initial_angle": (("initial_angle",), ("pendulum", "cam_drop")),
    "offset": (("offset",), ("pendulum", "cam_drop")),
    "gain": (("gain",), ("pendulum",)),
    "correlated": (("correlated",), ("pendulum", "cam_drop")),
    "hand_start": (("hand_start",), ("pendulum",)),
    "lab": (("quantised", "time_base", "period", "hand_start", "gain"), ("pendulum",)),
    "all_camera": (("pre_trigger", "initial_angle", "offset", "correlated"), ("cam_drop",)),
    "all_potentiometer": (("pre_trigger", "initial_angle", "offset", "correlated"), ("pendulum",)),
}


def draw_cases(group: str, n: int, seed: int, include_unregistered: bool = True,
               friction_truth: str = "hybrid") -> list[tuple[str, int]]:
    """``n`` (case, seed) draws for a complication group: hidden-effect cases of the group's
    experiments that ``friction_truth`` applies to, cycled in a seeded random order (the
    unregistered effect among them)."""
    _, experiments = GROUPS[group]
    allowed = friction_truth_cases(friction_truth)
    cases = [c for c, (e, _, truth) in HIDDEN.items() if e in experiments and c in allowed
             and (include_unregistered or "position_dependent_friction" not in truth)]
    rng = np.random.default_rng(seed)
    order = list(rng.permutation(cases))
    return [(order[k % len(order)], int(seed * 1000 + k)) for k in range(n)]

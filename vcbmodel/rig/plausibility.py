"""A rig's values against what a breaker mechanism or its test rig can have: the designer's and the
typist's check (docs/rig-format.md 3.11).

Three kinds of check, each naming the rig file and the field:

- :func:`plausibility`: every field of :data:`vcbmodel.parameters.PLAUSIBLE` against its range. A
  value no mechanism can have, that a unit slip gives (grams typed as kg, mm as m, GPa as Pa), is
  refused (InputError) with the slip named; a merely unusual one is returned as a warning.
- :func:`reachable_travel`: a closing whose cam cannot lift the poles through their gap (a lift in
  metres under a millimetre header) is refused: it could never close.
- :func:`step_limits`: the fixed RK4 step integrates a spring or damper only while h |lambda| stays
  below :data:`vcbmodel.parameters.STABLE_STEP_PRODUCT`; a stiffer one makes the run create energy.
  Refused before the run, naming the field and the largest value the step integrates.
"""
from __future__ import annotations

import functools
import math
import pickle
from collections.abc import Iterator
from types import SimpleNamespace
from typing import TYPE_CHECKING

import numpy as np

from .. import parameters as P
from ..errors import ImpossibleValue, InputError
from ..laws.breaker import segment_stiffness
from ..laws.cam_follower import TWO_PI, follower_displacement, kinematic_follower_angle, rest_geometry
from ..laws.springs import chain_for
from .paths import get_path
from .reader import Reader

if TYPE_CHECKING:
    from .data import Breaker, Cam, Rig
    from .spring_model import SpringModel


def _numbers(data: dict, path: str) -> Iterator[tuple[str, float]]:
    """(dotted path, value) of the number at ``path``, or of each number of a list there ([x, y])."""
    try:
        value = get_path(data, path)
    except (KeyError, ValueError):
        return
    items = list(enumerate(value)) if isinstance(value, list) else [(None, value)]
    for i, v in items:
        if isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v):
            yield (path if i is None else f"{path}.{i}"), float(v)


def plausibility(rd: Reader, data: dict) -> tuple[str, ...]:
    """Check each field of ``PLAUSIBLE`` the rig gives: refuse (:class:`ImpossibleValue`) a value beyond the
    refusal limits, naming the unit slip that gives it; return one warning per merely unusual value
    (``FIELD: VALUE UNIT is unusual ...``)."""
    warnings = []
    for path, (no_low, low, high, no_high, unit, slip_low, slip_high) in P.PLAUSIBLE.items():
        for name, v in _numbers(data, path):
            size = abs(v)
            usual = f"usual {_span(low, high, unit)}"
            if no_high is not None and size > no_high:
                raise ImpossibleValue(rd.path, name, f"{v:g} {unit} is impossible here (at most {no_high:g} {unit}; "
                                      f"{usual}): {slip_high}")
            if no_low is not None and 0.0 < size < no_low:
                raise ImpossibleValue(rd.path, name, f"{v:g} {unit} is impossible here (at least {no_low:g} {unit}; "
                                      f"{usual}): {slip_low}")
            if (high is not None and size > high) or (low is not None and 0.0 < size < low):
                warnings.append(f"{name}: {v:g} {unit} is unusual ({usual}); check its unit")
    return tuple(warnings)


def _span(low: float | None, high: float | None, unit: str) -> str:
    if low is None:
        return f"up to {high:g} {unit}"
    if high is None:
        return f"from {low:g} {unit}"
    return f"{low:g} to {high:g} {unit}"


def travel_curve(b: Breaker, cam: Cam, thetas: np.ndarray) -> np.ndarray:
    """The travel (m) of the follower's output point, and so of the poles, at each cam angle of
    ``thetas`` (rad, increasing from the start): the roller kept on the pitch curve (kinematics only)."""
    geometry = rest_geometry(b, cam.pivot)
    phi, out = geometry.follower_angle, []
    for theta in thetas:
        phi = kinematic_follower_angle(theta, b, geometry, phi)
        out.append(float(follower_displacement(phi, b.follower, geometry.follower_angle)[0]))
    return np.array(out)


#: How many reachable travels :func:`reachable_travel` keeps per process (least recently used dropped
#: first): a sweep loads one breaker per run, the geometry the same in all (a tolerance study draws
#: springs, masses, friction and gaps), and the kinematics over a turn were a fifth of its processor time.
TRAVELS_KEPT = 64


@functools.lru_cache(maxsize=TRAVELS_KEPT)
def _kept_travel(geometry: bytes) -> float:
    """The reachable travel (m) of a pickled geometry (:func:`reachable_travel`), computed from the key
    alone (unpickled here), so a kept value is always the one its key gives. ``functools.lru_cache``:
    bounded and safe to call from several threads."""
    follower, profile, roller_radius, pivot, initial_angle = pickle.loads(geometry)
    return _travel_over_turn(SimpleNamespace(follower=follower, profile=profile, roller_radius=roller_radius),
                             pivot, initial_angle)


def _travel_over_turn(b, pivot: tuple, initial_angle: float) -> float:
    """The largest travel (m) over a turn from ``initial_angle`` of a breaker's follower, profile and roller
    (``b``: anything with those three) on a cam turning about ``pivot``."""
    cam = SimpleNamespace(pivot=pivot, initial_angle=initial_angle)
    return float(np.max(travel_curve(b, cam, initial_angle + np.linspace(0.0, TWO_PI, 361))))


def reachable_travel(b: Breaker, cam: Cam) -> float:
    """The largest travel (m) of the poles over a turn of the cam from its start (:func:`travel_curve`), once
    per geometry and process: everything it depends on (the follower, the cam profile, the roller radius, the
    cam's pivot and initial angle), pickled, is the key of :func:`_kept_travel`. A field changed in place
    changes the key; a geometry that does not pickle is computed each time."""
    parts = (b.follower, b.profile, b.roller_radius, tuple(cam.pivot), cam.initial_angle)
    try:
        key = pickle.dumps(parts, protocol=pickle.HIGHEST_PROTOCOL)
    except (pickle.PicklingError, TypeError, AttributeError):
        return _travel_over_turn(b, tuple(cam.pivot), cam.initial_angle)
    return _kept_travel(key)


def check_reachable(rd: Reader, b: Breaker, cam: Cam, profile_field: str) -> None:
    """Refuse a breaker whose cam cannot move every pole through its gap: it could never close
    (a lift in metres under a points file's millimetre header, a gap in mm typed as m)."""
    travel = reachable_travel(b, cam)
    gap = max(b.poles.contact_gap + o for o in b.poles.gap_offsets)
    if travel < gap:
        rd.fail(profile_field, f"the cam's lift ({1e3 * b.profile.lift:.3g} mm) moves the poles at most "
                f"{1e3 * travel:.3g} mm, less than their gap (breaker.poles.contact_gap and gap_offsets: up to "
                f"{1e3 * gap:.3g} mm): the breaker could never close. Is a lift in metres under a millimetre "
                "header, or the gap in the wrong unit?")


def _limit_line(field: str, value: float, unit: str, what: str, rate: float, step: float, spring: bool) -> str:
    """The refusal of an element whose eigenvalue ``rate`` (rad/s or 1/s) is too fast for ``step``."""
    ratio = P.STABLE_STEP_PRODUCT / (step * rate)
    largest = value * (ratio**2 if spring else ratio)
    how = (f"oscillates at {rate / (2 * math.pi):.3g} Hz" if spring else f"relaxes at {rate:.3g} 1/s")
    return (f"{value:g} {unit} on {what} {how}: the fixed RK4 step of {step:g} s integrates it only up to "
            f"{largest:.3g} {unit} (step x rate below {P.STABLE_STEP_PRODUCT:g}); beyond, the run creates energy. "
            "Is it in the wrong unit? A stiffer part is not more accurate here: give at most that")


def _elements(rig: Rig, spring_model: SpringModel) -> Iterator[tuple]:
    """(field, value, unit, what it moves, eigenvalue, spring?) of each linear spring and damper."""
    spring = rig.closing_spring
    if spring is not None and spring_model.kind == "lumped":
        chain = chain_for(spring, spring_model)
        ks = list(chain.stiffnesses)
        for i, m in enumerate(chain.masses):
            rate = math.sqrt((ks[i] + ks[i + 1]) / m)
            yield ("closing_spring.stiffness", spring.stiffness, "N/m",
                   f"the spring's lumped mass of {m:.3g} kg ({spring_model.label})", rate, True)
    if rig.pendulum is not None and rig.friction.get("viscous"):
        c = rig.friction["viscous"]
        yield "friction.viscous", c, "N m s/rad", "the pendulum", c / rig.pendulum.inertia, False
    b = rig.breaker
    if b is None:
        return
    inertia = rig.cam.inertia_pivot
    for key, part in (("end_stop", b.end_stop), ("hold_latch", b.hold_latch)):
        if part is not None:
            what = f"the cam's {inertia:.3g} kg m^2 at the {1e3 * part.arm:g} mm arm"
            yield (f"breaker.{key}.stiffness", part.stiffness, "N/m", what,
                   math.sqrt(part.stiffness * part.arm**2 / inertia), True)
            yield f"breaker.{key}.damping", part.damping, "N s/m", what, part.damping * part.arm**2 / inertia, False
    yield from _pole_elements(b)


def _pole_elements(b: Breaker) -> Iterator[tuple]:
    """The push rods (rod and wipe spring, the rod's damper) between a pole and its lever, and the main
    shaft's segments between the pole levers."""
    poles, f, shaft = b.poles, b.follower, b.main_shaft
    lever = (shaft.lever_inertia if shaft is not None else f.inertia) / f.output_arm**2  # kg at the rod
    mass = 1.0 / (1.0 / poles.moving_mass + 1.0 / lever)
    what = f"a pole's {poles.moving_mass:g} kg against its lever ({mass:.3g} kg together)"
    yield "breaker.poles.rod_stiffness", poles.rod_stiffness, "N/m", what, math.sqrt(poles.rod_stiffness / mass), True
    yield "breaker.poles.rod_damping", poles.rod_damping, "N s/m", what, poles.rod_damping / mass, False
    if shaft is not None and poles.count > 1:
        what = f"a pole lever's {shaft.lever_inertia:g} kg m^2"
        k = segment_stiffness(shaft)
        yield "breaker.main_shaft.diameter", shaft.diameter, "m", what, math.sqrt(4.0 * k / shaft.lever_inertia), None
        yield ("breaker.main_shaft.damping", shaft.damping, "N m s/rad", what, 4.0 * shaft.damping / shaft.lever_inertia,
               False)


def step_limits(rig: Rig, spring_model: SpringModel, step: float) -> None:
    """Refuse (InputError naming the rig file and the field) a spring or damper too stiff for the
    fixed RK4 ``step`` (s): h |lambda| above ``STABLE_STEP_PRODUCT`` on the lightest body it moves.
    A shaft segment too stiff names the diameter (its stiffness goes with d^4)."""
    for field, value, unit, what, rate, spring in _elements(rig, spring_model):
        if step * rate <= P.STABLE_STEP_PRODUCT:
            continue
        if spring is None:  # the main shaft: k = G J / pitch, J ~ d^4
            largest = value * (P.STABLE_STEP_PRODUCT / (step * rate)) ** 0.5
            raise InputError(rig.path, field, f"{1e3 * value:g} mm makes the shaft's segments oscillate on {what} at "
                             f"{rate / (2 * math.pi):.3g} Hz: the fixed RK4 step of {step:g} s integrates at most "
                             f"{1e3 * largest:.3g} mm with this shear modulus and pitch; is it in millimetres?")
        raise InputError(rig.path, field, _limit_line(field, value, unit, what, rate, step, spring))


def shaft_twist(b: Breaker) -> float:
    """The main shaft's twist (rad) between the drive and the far levers under the wipe springs'
    preload on every other pole (``wipe_preload`` at ``output_arm``): the segment next to the drive
    carries them all, the others less (an upper estimate, statics only)."""
    shaft, poles = b.main_shaft, b.poles
    torque = poles.wipe_preload * b.follower.output_arm
    far = max(shaft.drive_pole - 1, poles.count - shaft.drive_pole)
    return sum(torque * (far - j) for j in range(far)) / segment_stiffness(shaft)


def check_shaft(rd: Reader, b: Breaker) -> tuple[str, ...]:
    """Refuse a main shaft that would twist more than ``SHAFT_TWIST_LIMITS[1]`` under the poles' wipe
    preload (a diameter in the wrong unit, a modulus in GPa that passed as a soft material: no pole
    lever could hold its rod); warn above ``SHAFT_TWIST_LIMITS[0]``."""
    if b.main_shaft is None or b.poles.count < 2:
        return ()
    twist = shaft_twist(b)
    unusual, refused = P.SHAFT_TWIST_LIMITS
    shaft = b.main_shaft
    field = ("breaker.main_shaft.shear_modulus" if shaft.shear_modulus < P.PLAUSIBLE["breaker.main_shaft.shear_modulus"][1]
             else "breaker.main_shaft.diameter")
    what = (f"a {1e3 * shaft.diameter:g} mm shaft of {shaft.shear_modulus / 1e9:.3g} GPa, levers {1e3 * shaft.pole_pitch:g} "
            f"mm apart, twists about {math.degrees(twist):.3g} deg under the poles' wipe preload")
    if twist > refused:
        rd.fail(field, f"{what}: no pole lever could hold its rod (at most {math.degrees(refused):.0f} deg); is the "
                "diameter in mm or the modulus in GPa?")
    return (f"{field}: {what} (usual below {math.degrees(unusual):.0f} deg)",) if twist > unusual else ()


def check_rig(rd: Reader, data: dict, sections: dict) -> tuple[str, ...]:
    """The checks a loaded rig's sections need beyond their readers': a closing whose cam cannot
    close its poles is refused (:func:`check_reachable`), a main shaft too soft to hold its levers
    (:func:`check_shaft`). Returns the warnings, for the loader to add to :func:`plausibility`'s."""
    b = sections.get("breaker")
    if b is None:
        return ()
    cp = data["breaker"]["cam_profile"]
    key = next((k for k in ("points_file", "points", "radius_points") if k in cp), "lift")
    check_reachable(rd, b, sections["cam"], f"breaker.cam_profile.{key}")
    return check_shaft(rd, b)

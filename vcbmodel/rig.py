"""Reading and checking rig files (``vcb-rig/1``) and measurement files (``NAME.csv``).

Everything is validated on load; any fault raises :class:`~vcbmodel.errors.InputError`
naming the file and the field (or line). Units are SI throughout (m, kg, s, N, rad).
"""
from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from .errors import InputError

FORMAT = "vcb-rig/1"
EXPERIMENTS = ("pendulum", "cam_drop", "vcb_closing")
CHANNEL_OF_EXPERIMENT = {"pendulum": "pendulum_angle", "cam_drop": "cam_angle",
                         "vcb_closing": "follower_displacement"}
UNIT_OF_EXPERIMENT = {"pendulum": "rad", "cam_drop": "rad", "vcb_closing": "m"}
KNOWN_CHANNELS = ("pendulum_angle", "cam_angle", "follower_displacement")
FRICTION_KEYS = ("mu_s", "mu_k", "stick_velocity", "stribeck_velocity", "viscous", "zeta")
LUMPED_CONVENTIONS = ("exact", "paper", "uniform")


@dataclass(frozen=True)
class Pendulum:
    """Pendulum test of the paper's section 2 (eq. 1, 5, 6)."""

    mass: float  # M (kg), the swinging weight
    inertia: float  # I (kg m^2) about the shaft axis: cam + link + weight
    com_distance: float  # L (m), shaft axis to centre of mass
    initial_angle: float  # rad, from hanging straight down
    initial_velocity: float = 0.0  # rad/s


@dataclass(frozen=True)
class Cam:
    """Cam on its shaft (paper eq. 11-13)."""

    mass: float  # m_c (kg)
    inertia_com: float  # I_c (kg m^2) about the centre of mass
    com_distance: float  # l_g (m)
    com_angle: float  # psi (rad): centre of mass at angle theta - psi from A
    pivot: tuple  # A (m), shaft axis
    arm_length: float  # l_AB (m), moment arm to the spring pin B
    initial_angle: float  # rad, of A->B from +x
    initial_velocity: float = 0.0  # rad/s

    @property
    def inertia_pivot(self):
        """I_c + m_c l_g^2 (kg m^2), the inertia about the shaft (eq. 12)."""
        return self.inertia_com + self.mass * self.com_distance**2


@dataclass(frozen=True)
class ClosingSpring:
    """Each of ``count`` identical closing springs (tension springs), anchor O -> pin B."""

    count: int
    stiffness: float  # k0 (N/m), static stiffness
    mass: float  # m0 (kg), active coil mass
    free_length: float  # m
    anchor: tuple  # O (m)
    wire_diameter: float | None = None  # m (ANCF bending stiffness), defaults in parameters.py
    coil_diameter: float | None = None  # m, mean coil diameter
    active_coils: float | None = None
    shear_modulus: float | None = None  # Pa
    weight: bool = False  # spring masses carry their weight (spec: no, unless said)


@dataclass(frozen=True)
class ModelChoice:
    """The analyst's model: effect names, spring model and lumped convention."""

    effects: tuple
    spring_model: str = "massless"
    lumped_convention: str = "exact"


@dataclass(frozen=True)
class Rig:
    path: str
    name: str
    experiment: str
    gravity: float
    shaft_radius: float
    friction: dict  # the friction values the rig gives (subset of FRICTION_KEYS)
    model: ModelChoice
    pendulum: Pendulum | None = None
    cam: Cam | None = None
    closing_spring: ClosingSpring | None = None
    breaker: object = None  # vcbmodel.breaker.Breaker (experiment vcb_closing)

    def with_model(self, effects=None, spring_model=None, lumped_convention=None):
        m = self.model
        return replace(self, model=ModelChoice(
            tuple(effects) if effects is not None else m.effects,
            spring_model or m.spring_model,
            lumped_convention or m.lumped_convention))


@dataclass(frozen=True)
class Measurement:
    """A measured (or synthetic) time series: ``t`` in s, channels in rad or m."""

    path: str
    t: np.ndarray
    channels: dict
    comments: tuple = ()

    def channel(self, name):
        return self.channels[name]


def _spring_mass_count(spring_model):
    """Number of lumped masses (0 massless, -1 ancf) or None if the name is unknown."""
    if spring_model == "massless":
        return 0
    if spring_model == "ancf":
        return -1
    m = re.fullmatch(r"lumped-([1-9][0-9]?)", spring_model)
    return int(m.group(1)) if m else None


def valid_spring_model(spring_model):
    return isinstance(spring_model, str) and _spring_mass_count(spring_model) is not None


def lumped_mass_count(spring_model):
    """Masses in a ``lumped-n`` model, 0 for ``massless``, -1 for ``ancf``."""
    n = _spring_mass_count(spring_model)
    if n is None:
        raise ValueError(f"unknown spring model {spring_model!r}")
    return n


class _Reader:
    """Typed access into the parsed JSON with errors naming the dotted field."""

    def __init__(self, path):
        self.path = path

    def fail(self, fieldname, message):
        raise InputError(self.path, fieldname, message)

    def section(self, obj, key, prefix=""):
        name = prefix + key
        if key not in obj:
            self.fail(name, "missing")
        if not isinstance(obj[key], dict):
            self.fail(name, "must be an object")
        return obj[key]

    def number(self, obj, key, prefix="", *, positive=False, nonnegative=False, default=None):
        name = prefix + key
        if key not in obj:
            if default is not None:
                return default
            self.fail(name, "missing")
        v = obj[key]
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            self.fail(name, f"must be a number, got {json.dumps(v)}")
        v = float(v)
        if not math.isfinite(v):
            self.fail(name, "must be finite")
        if positive and not v > 0:
            self.fail(name, f"must be positive, got {v:g}")
        if nonnegative and v < 0:
            self.fail(name, f"must not be negative, got {v:g}")
        return v

    def point(self, obj, key, prefix=""):
        name = prefix + key
        if key not in obj:
            self.fail(name, "missing")
        v = obj[key]
        if (not isinstance(v, list) or len(v) != 2
                or any(isinstance(x, bool) or not isinstance(x, (int, float)) for x in v)):
            self.fail(name, "must be a list of two numbers [x, y]")
        if not all(math.isfinite(x) for x in v):
            self.fail(name, "must be finite")
        return (float(v[0]), float(v[1]))


def _parse_json(path):
    try:
        text = Path(path).read_text()
    except OSError as e:
        raise InputError(path, "file", f"cannot read: {e.strerror}") from None
    try:
        # NaN / Infinity are not JSON: refuse them instead of reading them as floats
        def bad_constant(name):
            raise ValueError(f"{name} is not a valid JSON number")
        return json.loads(text, parse_constant=bad_constant)
    except json.JSONDecodeError as e:
        raise InputError(path, f"line {e.lineno}", f"malformed JSON: {e.msg}") from None
    except ValueError as e:
        raise InputError(path, "JSON", str(e)) from None


def load_rig(path) -> Rig:
    """Read and check a ``vcb-rig/1`` file (see the spec ``rig-and-measurement.md``)."""
    path = str(path)
    data = _parse_json(path)
    rd = _Reader(path)
    if not isinstance(data, dict):
        rd.fail("(top level)", "must be a JSON object")
    if data.get("format") != FORMAT:
        rd.fail("format", f"must be {FORMAT!r}, got {json.dumps(data.get('format'))}")
    experiment = data.get("experiment")
    if experiment not in EXPERIMENTS:
        rd.fail("experiment", f"must be one of {', '.join(EXPERIMENTS)}, got {json.dumps(experiment)}")
    gravity = rd.number(data, "gravity", nonnegative=True, default=9.81)
    shaft = rd.section(data, "shaft")
    radius = rd.number(shaft, "radius", "shaft.", nonnegative=True)

    friction_in = data.get("friction", {})
    if not isinstance(friction_in, dict):
        rd.fail("friction", "must be an object")
    friction = {}
    for key, value in friction_in.items():
        if key not in FRICTION_KEYS:
            rd.fail(f"friction.{key}", f"unknown field (known: {', '.join(FRICTION_KEYS)})")
        friction[key] = rd.number(friction_in, key, "friction.", nonnegative=True)
    if "mu_s" in friction and "mu_k" in friction and friction["mu_s"] < friction["mu_k"]:
        rd.fail("friction.mu_s", "must not be smaller than friction.mu_k")

    model = _read_model(rd, data, experiment)

    pendulum = cam = spring = None
    if experiment == "pendulum":
        p = rd.section(data, "pendulum")
        pendulum = Pendulum(
            mass=rd.number(p, "mass", "pendulum.", positive=True),
            inertia=rd.number(p, "inertia", "pendulum.", positive=True),
            com_distance=rd.number(p, "com_distance", "pendulum.", positive=True),
            initial_angle=rd.number(p, "initial_angle", "pendulum."),
            initial_velocity=rd.number(p, "initial_velocity", "pendulum.", default=0.0))
        if pendulum.inertia < 0.99 * pendulum.mass * pendulum.com_distance**2:  # 1 %: rounded data
            rd.fail("pendulum.inertia", "smaller than mass * com_distance^2: not a physical body")
        if model.spring_model != "massless":
            rd.fail("model.spring_model", "a pendulum test has no closing spring: use 'massless'")
    else:
        c = rd.section(data, "cam")
        cam = Cam(
            mass=rd.number(c, "mass", "cam.", positive=True),
            inertia_com=rd.number(c, "inertia_com", "cam.", nonnegative=True),
            com_distance=rd.number(c, "com_distance", "cam.", nonnegative=True),
            com_angle=rd.number(c, "com_angle", "cam.", default=0.0),
            pivot=rd.point(c, "pivot", "cam."),
            arm_length=rd.number(c, "arm_length", "cam.", positive=True),
            initial_angle=rd.number(c, "initial_angle", "cam."),
            initial_velocity=rd.number(c, "initial_velocity", "cam.", default=0.0))
        if cam.inertia_pivot <= 0:
            rd.fail("cam.inertia_com", "the cam has no inertia about its shaft")
        s = rd.section(data, "closing_spring")
        count = rd.number(s, "count", "closing_spring.", positive=True, default=2.0)
        if count != int(count):
            rd.fail("closing_spring.count", "must be a whole number")
        opt = {k: rd.number(s, k, "closing_spring.", positive=True)
               for k in ("wire_diameter", "coil_diameter", "active_coils", "shear_modulus") if k in s}
        weight = s.get("weight", False)
        if not isinstance(weight, bool):
            rd.fail("closing_spring.weight", "must be true or false")
        spring = ClosingSpring(
            count=int(count),
            stiffness=rd.number(s, "stiffness", "closing_spring.", positive=True),
            mass=rd.number(s, "mass", "closing_spring.", positive=True),
            free_length=rd.number(s, "free_length", "closing_spring.", positive=True),
            anchor=rd.point(s, "anchor", "closing_spring."), weight=weight, **opt)
        ax, ay = cam.pivot
        bx = ax + cam.arm_length * math.cos(cam.initial_angle)
        by = ay + cam.arm_length * math.sin(cam.initial_angle)
        if math.hypot(bx - spring.anchor[0], by - spring.anchor[1]) <= spring.free_length:
            rd.fail("closing_spring.free_length", "the spring is not stretched at the start: a tension spring must be charged")
    breaker = None
    if experiment == "vcb_closing":
        from .breaker import read_breaker
        breaker = read_breaker(rd, data)
        _check_breaker_rest(rd, cam, breaker)
    name = data.get("name", Path(path).name.replace(".rig.json", ""))
    if not isinstance(name, str):
        rd.fail("name", "must be a string")
    return Rig(path=path, name=name, experiment=experiment, gravity=gravity, shaft_radius=radius,
               friction=friction, model=model, pendulum=pendulum, cam=cam, closing_spring=spring, breaker=breaker)


def _check_breaker_rest(rd, cam, breaker):
    from .breaker import pitch_radius, rest_geometry

    try:
        rest_geometry(breaker, cam.pivot)
    except ValueError as e:
        rd.fail("breaker.follower.pivot", str(e))
    p = breaker.profile
    if pitch_radius(cam.initial_angle, p, breaker.roller_radius)[0] > p.base_radius + breaker.roller_radius + 1e-12:
        rd.fail("cam.initial_angle", "the roller is not on the cam's base circle at the start (breaker open)")


def _read_model(rd, data, experiment):
    from .effects import EFFECTS

    m = rd.section(data, "model")
    effects = m.get("effects", [])
    if not isinstance(effects, list) or not all(isinstance(e, str) for e in effects):
        rd.fail("model.effects", "must be a list of effect names")
    for e in effects:
        if e not in EFFECTS:
            rd.fail("model.effects", f"unknown effect {e!r} (known: {', '.join(EFFECTS)})")
        if experiment not in EFFECTS[e].experiments:
            rd.fail("model.effects", f"effect {e!r} does not apply to a {experiment} test")
    if len(set(effects)) != len(effects):
        rd.fail("model.effects", "lists an effect twice")
    spring_model = m.get("spring_model", "massless")
    if not valid_spring_model(spring_model):
        rd.fail("model.spring_model", f"must be massless, lumped-N (N = 1..99) or ancf, got {json.dumps(spring_model)}")
    convention = m.get("lumped_convention", "exact")
    if convention not in LUMPED_CONVENTIONS:
        rd.fail("model.lumped_convention", f"must be exact, paper or uniform, got {json.dumps(convention)}")
    if ("spring_mass" in effects) != (spring_model != "massless"):
        rd.fail("model.effects", "'spring_mass' must be listed exactly when spring_model is not 'massless'")
    return ModelChoice(tuple(effects), spring_model, convention)


def check_effects(effects, source="--effects"):
    """Check a list of effect names given on the command line."""
    from .effects import EFFECTS

    for e in effects:
        if e not in EFFECTS:
            raise InputError(source, "effects", f"unknown effect {e!r} (known: {', '.join(EFFECTS)})")
    return tuple(effects)


def load_measurement(path, experiment=None) -> Measurement:
    """Read and check ``NAME.csv``: ``#`` comments, a header starting with ``t``, numbers."""
    path = str(path)
    try:
        lines = Path(path).read_text().splitlines()
    except OSError as e:
        raise InputError(path, "file", f"cannot read: {e.strerror}") from None
    comments, rows, header, header_line = [], [], None, 0
    for i, line in enumerate(lines, start=1):
        s = line.strip()
        if not s:
            continue
        if s.startswith("#"):
            comments.append(s[1:].strip())
            continue
        cells = [c.strip() for c in s.split(",")]
        if header is None:
            header, header_line = cells, i
            if header[0] != "t":
                raise InputError(path, f"line {i}", f"the first column must be 't', got {header[0]!r}")
            for col in header[1:]:
                if col not in KNOWN_CHANNELS:
                    raise InputError(path, f"column {col!r}", f"unknown channel (known: {', '.join(KNOWN_CHANNELS)})")
            if len(set(header)) != len(header):
                raise InputError(path, f"line {i}", "a column is named twice")
            if len(header) < 2:
                raise InputError(path, f"line {i}", "no measured channel after 't'")
            continue
        if len(cells) != len(header):
            raise InputError(path, f"line {i}", f"has {len(cells)} values, the header has {len(header)}")
        try:
            values = [float(c) for c in cells]
        except ValueError:
            raise InputError(path, f"line {i}", "a value is not a number") from None
        for col, v in zip(header, values):
            if not math.isfinite(v):
                raise InputError(path, f"line {i}, column {col!r}", "value is not finite (NaN or inf)")
        rows.append(values)
    if header is None:
        raise InputError(path, "header", "missing (no line other than comments)")
    if len(rows) < 3:
        raise InputError(path, "data", f"needs at least 3 samples, has {len(rows)}")
    arr = np.array(rows)
    t = arr[:, 0]
    dt = np.diff(t)
    bad = np.nonzero(dt <= 0)[0]
    if bad.size:
        raise InputError(path, f"column 't' near t = {t[bad[0] + 1]:g}", "time is not strictly increasing")
    channels = {col: arr[:, j] for j, col in enumerate(header) if j > 0}
    if experiment is not None:
        want = CHANNEL_OF_EXPERIMENT[experiment]
        if want not in channels:
            raise InputError(path, f"line {header_line}", f"a {experiment} measurement needs the column {want!r}")
    return Measurement(path=path, t=t, channels=channels, comments=tuple(comments))


def sibling_rig_path(measurement_path):
    p = Path(measurement_path)
    name = p.name[:-4] if p.name.endswith(".csv") else p.stem
    return str(p.with_name(name + ".rig.json"))

"""The rig's data: one frozen dataclass per section of a rig file (units in the comments).

A :class:`Rig` holds the sections every experiment shares (gravity, shaft, friction, model)
and the experiment's own sections by name (``pendulum``; ``cam`` and ``closing_spring``;
``breaker``). Which sections an experiment reads is its record's business
(:mod:`vcbmodel.experiments`).
"""
from __future__ import annotations

from dataclasses import dataclass, field

from .. import parameters as P
from ..laws.breaker import CamRollerLaw, EndStop, HoldLatch, LatchPoint, MainShaft
from ..laws.making_current import MakingCurrent
from ..laws.opening import Commands, OpeningDashpot, TripLatch
from ..laws.release import Release
from .spring_model import ModelChoice


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
    def inertia_pivot(self) -> float:
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
    density: float | None = None  # kg/m^3 of the wire (a datasheet spring's mass; steel when not given)
    damping_ratio: float | None = None  # internal damping: first surge mode's damping ratio (effect spring_damping)
    ends: str | None = None  # "hooks" or "plugs" (screwed-in plug ends): what `check` checks besides the body
    from_datasheet: tuple = ()  # the fields derived from the datasheet (stiffness, mass), for reports


# --- the whole breaker (experiment vcb_closing) -------------------------------------------------

@dataclass(frozen=True)
class CamProfile:
    """Closing cam: pitch curve rho(u) = base_radius + roller_radius + lift s(u) (see
    :mod:`vcbmodel.laws.breaker`). Lengths in m, angles in rad of cam rotation."""

    base_radius: float  # base circle of the cam surface (m)
    lift: float  # rise of the roller centre (m)
    rise_start: float
    rise_end: float
    return_start: float
    return_end: float
    table: tuple = ()  # a profile given by points: the pitch radius table (laws.cam_follower.profile_table)


@dataclass(frozen=True)
class Follower:
    """Oscillating roller follower (the paper's revolute joint B to ground)."""

    pivot: tuple  # (m) follower's fixed pivot
    inertia: float  # kg m^2 about the pivot (follower, main shaft and pole levers)
    roller_arm: float  # m, pivot to roller centre
    output_arm: float  # m, pivot to the output point F that drives the push rods
    output_angle: float  # rad, angle of pivot->F relative to pivot->roller
    rest_angle: float  # rad, about the angle of pivot->roller when open (picks the branch)


@dataclass(frozen=True)
class Poles:
    """The moving contacts, one body per pole, each on its own push rod and wipe spring."""

    count: int
    moving_mass: float  # kg per pole (moving contact, stem, terminal, push rod share)
    contact_gap: float  # m, open gap of the vacuum interrupter
    gap_offsets: tuple  # m per pole, assembly spread added to contact_gap
    push_rod_length: float  # m, F to the moving contact's pin at rest
    wipe_preload: float  # N, wipe spring preload against its stop
    wipe_rate: float  # N/m, wipe spring rate
    rod_stiffness: float  # N/m, push rod and stop below the preload
    rod_damping: float  # N s/m, structural damping along the rod
    bellows_force: float | None  # N, atmospheric pressure on the bellows (effect `bellows_force`)


@dataclass(frozen=True)
class OpeningSpring:
    """Tension spring pulling F straight down (towards open); charged while closing."""

    stiffness: float  # N/m
    preload: float  # N in the open position
    length: float  # m, anchor (below F) to F in the open position


@dataclass(frozen=True)
class ContactLaw:
    """Hertz contacts with Lankarani-Nikravesh damping (:mod:`vcbmodel.laws.contact`)."""

    cam_roller_stiffness: float  # N/m^exponent
    pole_stiffness: float  # N/m^exponent, moving on fixed contact
    exponent: float  # Hertz exponent (1.5)
    restitution: float | None  # e of both contacts (effect `contact_damping`); None: not given
    min_impact_speed: float  # m/s, floor of the impact speed in the damping term


@dataclass(frozen=True)
class Breaker:
    profile: CamProfile
    roller_radius: float  # m
    follower: Follower
    poles: Poles
    opening_spring: OpeningSpring
    contact: ContactLaw
    latch_release_time: float  # s: the latch's holding torque falls linearly to 0 over it
    cam_roller: CamRollerLaw = CamRollerLaw()  # the cam-roller contact's law (breaker.contact)
    latch_point: LatchPoint = LatchPoint()  # where the latch holds the cam (breaker.latch)
    speed_zone: tuple = P.SPEED_ZONE  # m before touch: the travel zone of the closing speed (breaker.speed_zone)
    end_stop: EndStop | None = None  # the closing end stop (breaker.end_stop); None: not modelled
    hold_latch: HoldLatch | None = None  # the holding latch (breaker.hold_latch); None: not modelled
    main_shaft: MainShaft | None = None  # the pole levers' shaft (breaker.main_shaft); None: rigid, not modelled
    limits: tuple = ()  # the acceptance limits (breaker.limits: vcbmodel.rig.limits.Limit); (): none given
    making_current: MakingCurrent | None = None  # closing onto a fault (breaker.making_current); None: no current
    trip_latch: TripLatch | None = None  # the trip latch and trip-free link (breaker.trip_latch); None: not modelled
    opening_dashpot: OpeningDashpot | None = None  # opening dashpot and open stop (breaker.opening_dashpot)
    closing_release: Release | None = None  # the closing coil and its armature (breaker.closing_release)
    opening_release: Release | None = None  # the opening (trip) coil and its armature (breaker.opening_release)
    opening_speed_zone: tuple = (0.0, 0.004)  # m after parting: the opening speed's zone (breaker.opening_speed_zone)
    commands: Commands | None = None  # what the run commands (the sequence runner sets it); None: a plain closing


# --- the rig ------------------------------------------------------------------------------------

@dataclass(frozen=True)
class Rig:
    """A loaded, checked rig file. ``friction``: the friction values the rig gives (N m s/rad
    for ``viscous``, rad/s for the velocities); ``sections``: the experiment's own sections
    by name; ``data``: the file's JSON object (for parameter studies that edit it)."""

    path: str
    name: str
    experiment: str
    gravity: float  # m/s^2
    shaft_radius: float  # m, journal radius r
    friction: dict
    model: ModelChoice
    sections: dict = field(default_factory=dict)
    data: dict = field(default_factory=dict, repr=False, compare=False)
    #: facts about the record the diagnosis would otherwise estimate (section ``record``):
    #: ``release_time`` (s), ``initial_angle`` (rad), ``sensor_offset`` (rad or m), ``sensor_gain`` (-),
    #: ``sensor_noise`` (rad or m: the sensor's noise level, standard deviation; never defaulted)
    record: dict = field(default_factory=dict)
    #: rig values known only approximately (section ``uncertain``): dotted path -> relative sd
    uncertain: dict = field(default_factory=dict)
    #: values that are unusual but possible, one line each (``FIELD: ...``; vcbmodel.rig.plausibility)
    warnings: tuple = ()
    #: what the experiment's model carries that effects act on (its record's ``provides``; an effect
    #: applies when all it needs is there)
    provides: tuple = ()

    @property
    def pendulum(self) -> Pendulum | None:
        return self.sections.get("pendulum")

    @property
    def cam(self) -> Cam | None:
        return self.sections.get("cam")

    @property
    def closing_spring(self) -> ClosingSpring | None:
        return self.sections.get("closing_spring")

    @property
    def breaker(self) -> Breaker | None:
        return self.sections.get("breaker")

"""The registry of model effects (spec "Effect names").

Each effect is a component with an *on* and an *off* variant; the model is assembled by
visiting every registered effect in order and letting the chosen variant contribute its
part (PyBaMM-style: "off" is a real component that contributes zero, not an ``if`` in a
builder). The diagnosis loops over :data:`EFFECTS`, so a new effect is one entry here.

Parameters are described by :class:`ParameterSpec`; a fit turns them into
:class:`vcbmodel.fitting.Parameter` objects (value, bounds, vary, stderr).
"""
from __future__ import annotations

from dataclasses import dataclass

from .friction import FrictionLaw
from .parameters import DEFAULT_STICK_VELOCITY, DEFAULT_SPRING_MASS_MODEL


@dataclass(frozen=True)
class ParameterSpec:
    name: str
    initial: float  # starting guess for a fit
    min: float
    max: float
    unit: str
    vary: bool = True  # varied by the diagnosis unless the rig gives the value
    log: bool = False  # fit on a log scale (positive, spans decades)
    scan: tuple = ()  # coarse values tried before a fit when the effect is newly added


@dataclass
class ModelSpec:
    """What one simulation needs beyond the rig: the friction law and the spring model."""

    mu_s: float = 0.0
    mu_k: float = 0.0
    stick_velocity: float = DEFAULT_STICK_VELOCITY
    stribeck_velocity: float = 0.0
    viscous: float = 0.0
    spring_model: str = "massless"
    lumped_convention: str = "exact"
    restitution: float = 1.0  # whole breaker: contacts' coefficient of restitution (1: elastic)
    bellows_force: float = 0.0  # whole breaker: atmospheric force on each pole's bellows (N)

    def friction_law(self, radius):
        return FrictionLaw(mu_s=max(self.mu_s, self.mu_k), mu_k=self.mu_k,
                           stick_velocity=self.stick_velocity,
                           stribeck_velocity=self.stribeck_velocity,
                           viscous=self.viscous, radius=radius)


class Effect:
    """An effect component: ``parameters`` it owns, and what it contributes when on/off."""

    name = ""
    description = ""
    parameters: tuple = ()
    experiments = ("pendulum", "cam_drop", "vcb_closing")

    def on(self, spec: ModelSpec, values: dict, rig) -> None:
        raise NotImplementedError

    def off(self, spec: ModelSpec, values: dict, rig) -> None:
        raise NotImplementedError


class CoulombFriction(Effect):
    name = "coulomb_friction"
    description = "dry shaft friction mu_k r Fn with a Karnopp stick band"
    parameters = (ParameterSpec("mu_k", 0.1, 0.0, 1.0, "-", scan=(0.03, 0.08, 0.15, 0.3)),
                  ParameterSpec("stick_velocity", DEFAULT_STICK_VELOCITY, 2e-4, 0.02, "rad/s",
                                vary=False, log=True))

    def on(self, spec, values, rig):
        spec.mu_k = values["mu_k"]
        spec.mu_s = values["mu_k"]
        spec.stick_velocity = values.get("stick_velocity", DEFAULT_STICK_VELOCITY)

    def off(self, spec, values, rig):
        spec.mu_k = spec.mu_s = 0.0


class Stribeck(Effect):
    name = "stribeck"
    description = "static friction mu_s > mu_k, falling linearly to mu_k at the Stribeck velocity"
    parameters = (ParameterSpec("mu_s", 0.2, 0.0, 1.5, "-", scan=(0.15, 0.25, 0.4)),
                  ParameterSpec("stribeck_velocity", 0.1, 0.003, 2.0, "rad/s", log=True, scan=(0.03, 0.1, 0.3)))

    def on(self, spec, values, rig):
        spec.mu_s = max(values["mu_s"], spec.mu_k)
        spec.stribeck_velocity = values["stribeck_velocity"]

    def off(self, spec, values, rig):
        spec.mu_s = spec.mu_k
        spec.stribeck_velocity = 0.0


class ViscousFriction(Effect):
    name = "viscous_friction"
    description = "viscous shaft torque Cv w"
    parameters = (ParameterSpec("viscous", 0.3, 0.0, 20.0, "N m s/rad", scan=(0.1, 0.4, 1.2, 4.0)),)

    def on(self, spec, values, rig):
        spec.viscous = values["viscous"]

    def off(self, spec, values, rig):
        spec.viscous = 0.0


class SpringMass(Effect):
    name = "spring_mass"
    description = "the closing spring's own inertia (surge, lateral motion) as a mass model"
    parameters = ()
    experiments = ("cam_drop", "vcb_closing")
    #: mass models the diagnosis tries when adding this effect (a discrete choice, no fitted
    #: parameter), as "spring_model" or "spring_model:convention"; the best by BIC is kept.
    #: Cheapest first: a candidate that explains the data within the noise stops the rest.
    variants = ("lumped-1", "lumped-2", "lumped-3", "lumped-1:paper", "lumped-2:paper", "lumped-3:paper", "ancf")

    def on(self, spec, values, rig):
        chosen = rig.model.spring_model
        spec.spring_model = chosen if chosen != "massless" else DEFAULT_SPRING_MASS_MODEL
        spec.lumped_convention = rig.model.lumped_convention

    def off(self, spec, values, rig):
        spec.spring_model = "massless"


class ScalarEffect(Effect):
    """An effect that sets one model field from its one parameter; off sets ``off_value``."""

    field = ""
    off_value = 0.0

    def on(self, spec, values, rig):
        setattr(spec, self.field, values[self.field])

    def off(self, spec, values, rig):
        setattr(spec, self.field, self.off_value)


class ContactDamping(ScalarEffect):
    name = "contact_damping"
    description = ("energy lost in the cam-roller and pole contact impacts: Lankarani-Nikravesh hysteresis "
                   "damping with restitution e < 1 (off: elastic Hertz contacts)")
    parameters = (ParameterSpec("restitution", 0.8, 0.3, 1.0, "-", scan=(0.5, 0.7, 0.9)),)
    experiments = ("vcb_closing",)
    field, off_value = "restitution", 1.0


class BellowsForce(ScalarEffect):
    name = "bellows_force"
    description = ("atmospheric pressure on each vacuum interrupter's bellows, pushing the moving contact closed "
                   "(100-400 N for medium-voltage interrupters)")
    parameters = (ParameterSpec("bellows_force", 150.0, 0.0, 600.0, "N", scan=(50.0, 150.0, 300.0)),)
    experiments = ("vcb_closing",)
    field = "bellows_force"


# Order matters: Stribeck's "off" copies mu_k, so Coulomb comes first.
EFFECTS = {e.name: e for e in (CoulombFriction(), Stribeck(), ViscousFriction(), SpringMass(), ContactDamping(),
                               BellowsForce())}


def parameter_specs(effects):
    """The parameter specs owned by the listed effects, in registry order."""
    return [p for name, e in EFFECTS.items() if name in effects for p in e.parameters]


def assemble(rig, effects, values) -> ModelSpec:
    """Visit every registered effect; the on/off variant contributes its part."""
    spec = ModelSpec(lumped_convention=rig.model.lumped_convention)
    for name, effect in EFFECTS.items():
        (effect.on if name in effects else effect.off)(spec, values, rig)
    return spec


"""The registry of model effects (spec "Effect names").

Each effect is a component with an *on* and an *off* variant that contributes its part of the
model (PyBaMM-style: "off" is a real component that contributes zero, not an ``if`` in a
builder). Each effect owns its contract (:class:`Effect`): what of an experiment's model it needs
(an experiment record says what it provides), its parameters (:class:`ParameterSpec`: fit bounds
and start, and the rig field a value may come from), the model fields it sets and those of other
effects it reads (so the model is assembled in no particular order), and, for ``spring_mass``, the
variants the diagnosis tries. The diagnosis loops over :data:`EFFECTS`, so a new effect is one
entry here.
"""
from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from ..errors import InputError
from ..laws.discovered import term
from ..laws.friction import FrictionLaw, effective_static, viscous_from_zeta
from ..laws.friction_forms import FORMS, FormLaw
from ..parameters import DEFAULT_STICK_VELOCITY
from ..rig.spring_model import MASS_VARIANTS, SpringModel

if TYPE_CHECKING:
    from ..rig.data import Rig


@dataclass(frozen=True)
class ParameterSpec:
    name: str
    initial: float  # starting guess for a fit (fits only: never a model value)
    min: float
    max: float
    unit: str
    rig_field: str  # dotted path of the rig field that may give the value
    vary: bool = True  # varied by the diagnosis unless the rig gives the value
    log: bool = False  # fit on a log scale (positive, spans decades)
    scan: tuple = ()  # coarse values tried before a fit when the effect is newly added
    default: float | None = None  # documented value used when the rig gives none (None: required)


@dataclass
class ModelSpec:
    """What one simulation runs with beyond the rig: the effects, the friction law's values,
    the spring model (the run's :class:`~vcbmodel.rig.spring_model.ModelChoice`'s, as it is) and the
    breaker's effect values."""

    effects: tuple = ()
    mu_s: float = 0.0  # -
    mu_k: float = 0.0  # -
    stick_velocity: float = DEFAULT_STICK_VELOCITY  # rad/s
    stribeck_velocity: float = 0.0  # rad/s
    viscous: float = 0.0  # N m s/rad
    spring_model: SpringModel = field(kw_only=True)  # the run's model choice's, never a default
    sticking: str = "passive"  # passive | literal (spec "Sticking is passive")
    restitution: float = 1.0  # whole breaker: contacts' coefficient of restitution (1: elastic)
    bellows_force: float = 0.0  # whole breaker: atmospheric force on each pole's bellows (N)
    #: a discovered torque on the shaft: ((library term, coefficient), ...) (laws.discovered; N m)
    discovered: tuple = ()
    drag: float = 0.0  # air drag c_d on the swinging body (N m s^2/rad^2; laws.mechanics.aerodynamic_drag_torque)
    #: the closing spring's internal damping: its first surge mode's damping ratio (-; 0: none;
    #: laws.springs.kelvin_voigt_time)
    spring_damping: float = 0.0
    #: the friction law's form (:mod:`vcbmodel.laws.friction_forms`; ``hybrid``: the spec's law) and
    #: its own values, in the order of its parameters
    friction_form: str = "hybrid"
    form_values: tuple = ()

    def friction_law(self, radius: float, step: float = 0.0) -> FrictionLaw | FormLaw:
        """The shaft friction law with journal radius ``radius`` (m), for an integrator with
        fixed step ``step`` (s; 0: adaptive); a :class:`FormLaw` when the model carries a form."""
        if self.friction_form != "hybrid":
            return FormLaw(self.friction_form, mu_s=self.mu_s, mu_k=self.mu_k, stick_velocity=self.stick_velocity,
                           stribeck_velocity=self.stribeck_velocity, viscous=self.viscous, radius=radius, step=step,
                           sticking=self.sticking, extra=tuple(self.form_values))
        return FrictionLaw(mu_s=self.mu_s, mu_k=self.mu_k, stick_velocity=self.stick_velocity,
                           stribeck_velocity=self.stribeck_velocity, viscous=self.viscous, radius=radius, step=step,
                           sticking=self.sticking)


class Effect:
    """An effect component. It declares what it needs and what it sets, so that the model is
    assembled in no particular order (:func:`assemble`):

    - ``needs``: what of an experiment's model it acts on; it applies to an experiment whose record
      provides them all (``Experiment.provides``, carried by the loaded rig as ``Rig.provides``):
      ``journal`` (a shaft turning in a journal bearing: the friction law acts there),
      ``swinging_body`` (a body swinging through air), ``closing_spring`` (the closing springs as
      modelled bodies), ``breaker`` (the whole breaker's contacts and poles);
    - ``parameters``: the values it owns (:class:`ParameterSpec`: fit bounds and start, the rig field a
      value may come from);
    - ``sets``: the :class:`ModelSpec` fields it sets, on and off; ``reads``: the fields set by other
      effects that its part depends on (Stribeck friction's static coefficient falls to the kinetic one);
    - :meth:`on` / :meth:`off`: its part, ``{field: value}`` for every field of ``sets``.
    """

    name = ""
    description = ""
    parameters: tuple = ()
    needs: tuple = ("journal",)
    sets: tuple = ()
    reads: tuple = ()
    variants: tuple = ()  # alternative model structures the diagnosis tries (spring models)

    def acts_on(self, provides) -> bool:
        """Whether an experiment that provides ``provides`` carries this effect."""
        return set(self.needs) <= set(provides)

    def applies_to(self, provides, spring_model: SpringModel) -> bool:
        """Whether the diagnosis may propose this effect for a model of an experiment that provides
        ``provides``, with ``spring_model``."""
        return self.acts_on(provides)

    def on(self, values: dict, model: dict) -> dict:
        """Its part when on, from its ``values`` and the fields it ``reads`` (``model``)."""
        raise NotImplementedError

    def off(self, model: dict) -> dict:
        """Its part when off (a real component that contributes nothing)."""
        raise NotImplementedError

    @property
    def rig_fields(self) -> tuple:
        """The rig fields (dotted paths) this effect reads: a model without the effect ignores them."""
        return tuple(p.rig_field for p in self.parameters) + self.extra_rig_fields

    extra_rig_fields: tuple = ()  # rig fields read besides the parameters' own

    def rig_values(self, rig) -> dict:
        """The values of this effect's parameters that the rig gives (by ``rig_field``)."""
        out = {}
        for p in self.parameters:
            section, _, key = p.rig_field.rpartition(".")
            if section == "friction" and key in rig.friction:
                out[p.name] = rig.friction[key]
        return out


def _friction(name, initial, lo, hi, unit, **kw):
    return ParameterSpec(name, initial, lo, hi, unit, f"friction.{name}", **kw)


class CoulombFriction(Effect):
    name = "coulomb_friction"
    description = "dry shaft friction mu_k r Fn with a stick band (passive sticking)"
    parameters = (_friction("mu_k", 0.1, 0.0, 1.0, "-", scan=(0.03, 0.08, 0.15, 0.3)),
                  _friction("stick_velocity", DEFAULT_STICK_VELOCITY, 2e-4, 0.02, "rad/s", vary=False, log=True,
                            default=DEFAULT_STICK_VELOCITY))
    sets = ("mu_k", "stick_velocity")

    def on(self, values: dict, model: dict) -> dict:
        return {"mu_k": values["mu_k"], "stick_velocity": values["stick_velocity"]}

    def off(self, model: dict) -> dict:
        return {"mu_k": 0.0, "stick_velocity": DEFAULT_STICK_VELOCITY}


class Stribeck(Effect):
    name = "stribeck"
    description = "static friction mu_s > mu_k, falling linearly to mu_k at the Stribeck velocity"
    parameters = (_friction("mu_s", 0.2, 0.0, 1.5, "-", scan=(0.15, 0.25, 0.4)),
                  _friction("stribeck_velocity", 0.1, 0.003, 2.0, "rad/s", log=True, scan=(0.03, 0.1, 0.3)))
    sets = ("mu_s", "stribeck_velocity")
    reads = ("mu_k",)

    def on(self, values: dict, model: dict) -> dict:
        return {"mu_s": effective_static(values["mu_s"], model["mu_k"]), "stribeck_velocity": values["stribeck_velocity"]}

    def off(self, model: dict) -> dict:
        return {"mu_s": model["mu_k"], "stribeck_velocity": 0.0}


class ViscousFriction(Effect):
    name = "viscous_friction"
    description = "viscous shaft torque Cv w"
    parameters = (_friction("viscous", 0.3, 0.0, 20.0, "N m s/rad", scan=(0.1, 0.4, 1.2, 4.0)),)
    extra_rig_fields = ("friction.zeta",)
    sets = ("viscous",)

    def on(self, values: dict, model: dict) -> dict:
        return {"viscous": values["viscous"]}

    def off(self, model: dict) -> dict:
        return {"viscous": 0.0}

    def rig_values(self, rig: Rig) -> dict:
        """``viscous``, or for a pendulum its damping ratio ``zeta`` (Cv = 2 zeta sqrt(I M g L))."""
        out = super().rig_values(rig)
        if "zeta" in rig.friction and "viscous" not in out:
            if rig.pendulum is None:
                raise InputError(rig.path, "friction.zeta", "a damping ratio applies to pendulum rigs only: "
                                 "give friction.viscous (N m s/rad)")
            p = rig.pendulum
            out["viscous"] = viscous_from_zeta(rig.friction["zeta"], p.inertia, p.mass, rig.gravity, p.com_distance)
        return out


class AerodynamicDrag(Effect):
    name = "aerodynamic_drag"
    description = ("air drag on the swinging body (a paddle, the link): torque -c_d w|w|, c_d = 0.5 rho Cd A R^3 "
                   "for a paddle of area A at radius R")
    # c_d from 0 (no drag) to 1 N m s^2/rad^2 (a 0.1 m^2 plate at 1.2 m); a 0.02 m^2 paddle at 0.3 m: 3.8e-4
    parameters = (_friction("drag", 1e-3, 0.0, 1.0, "N m s^2/rad^2", scan=(1e-4, 1e-3, 1e-2)),)
    #: a swinging body only (the pendulum): a cam's windage is orders below its friction (a 0.1 m cam
    #: of 5e-3 m^2 has c_d ~ 3e-6 N m s^2/rad^2: 0.03 N m at 100 rad/s against tens of N m of journal friction)
    needs = ("swinging_body",)
    sets = ("drag",)

    def on(self, values: dict, model: dict) -> dict:
        return {"drag": values["drag"]}

    def off(self, model: dict) -> dict:
        return {"drag": 0.0}


class SpringDamping(Effect):
    name = "spring_damping"
    description = ("internal damping of the closing springs (material hysteresis, coil rubbing) as a Kelvin-Voigt "
                   "material: a damper beta k on every part of stiffness k, the first surge mode's damping ratio zeta")
    parameters = (ParameterSpec("damping_ratio", 0.01, 0.0, 0.3, "-", "closing_spring.damping_ratio",
                                scan=(0.003, 0.01, 0.03, 0.1)),)
    needs = ("closing_spring",)
    sets = ("spring_damping",)

    def applies_to(self, provides, spring_model: SpringModel) -> bool:
        """Proposed only where the springs have mass: its signature is the surge's decay. On massless
        springs it is a dashpot along the spring, whose force in phase with the pin's speed a viscous
        term or a bent friction value mimics (on a massless cam drop with a profile torque it was named
        with zeta 0.12, above any spring's, mu_k 0.01 for 0.13). A rig may still list it there."""
        return self.acts_on(provides) and not spring_model.is_massless

    def on(self, values: dict, model: dict) -> dict:
        return {"spring_damping": values["damping_ratio"]}

    def off(self, model: dict) -> dict:
        return {"spring_damping": 0.0}

    def rig_values(self, rig: Rig) -> dict:
        spring = rig.closing_spring
        value = None if spring is None else spring.damping_ratio
        return {} if value is None else {"damping_ratio": value}


class SpringMass(Effect):
    """The spring's inertia. It sets no field: the spring model is the run's model choice's
    (:mod:`.choice`), and ``spring_mass`` is listed exactly when that model has mass."""

    name = "spring_mass"
    description = "the closing spring's own inertia (surge, lateral motion) as a mass model"
    parameters = ()
    extra_rig_fields = ("closing_spring.mass",)
    needs = ("closing_spring",)
    variants = MASS_VARIANTS  # the mass models the diagnosis tries when adding this effect

    def on(self, values: dict, model: dict) -> dict:
        return {}

    def off(self, model: dict) -> dict:
        return {}


class BreakerScalarEffect(Effect):
    """A whole-breaker effect that sets one model field from its one parameter, whose value
    a rig may give in its ``breaker`` section; off sets ``off_value``."""

    field = ""
    off_value = 0.0
    needs = ("breaker",)

    @property
    def sets(self) -> tuple:
        return (self.field,)

    def on(self, values: dict, model: dict) -> dict:
        return {self.field: values[self.field]}

    def off(self, model: dict) -> dict:
        return {self.field: self.off_value}

    def rig_values(self, rig: Rig) -> dict:
        obj = rig.breaker
        for key in self.parameters[0].rig_field.split(".")[1:]:
            obj = getattr(obj, key, None)
        return {} if obj is None else {self.field: obj}


class ContactDamping(BreakerScalarEffect):
    name = "contact_damping"
    description = ("energy lost in the cam-roller and pole contact impacts: Lankarani-Nikravesh hysteresis "
                   "damping with restitution e < 1 (off: elastic Hertz contacts)")
    parameters = (ParameterSpec("restitution", 0.8, 0.3, 1.0, "-", "breaker.contact.restitution", scan=(0.5, 0.7, 0.9)),)
    field, off_value = "restitution", 1.0


class BellowsForce(BreakerScalarEffect):
    name = "bellows_force"
    description = ("atmospheric pressure on each vacuum interrupter's bellows, pushing the moving contact closed "
                   "(100-400 N for medium-voltage interrupters)")
    parameters = (ParameterSpec("bellows_force", 150.0, 0.0, 600.0, "N", "breaker.poles.bellows_force",
                                scan=(50.0, 150.0, 300.0)),)
    field = "bellows_force"


#: The registry, in the order reports and the diagnosis list effects (the model's assembly does not
#: depend on it: :func:`assembly_order`).
EFFECTS = {e.name: e for e in (CoulombFriction(), Stribeck(), ViscousFriction(), AerodynamicDrag(), SpringMass(),
                               SpringDamping(), ContactDamping(), BellowsForce())}


class DiscoveredTorque:
    """The machinery that carries a discovered torque (:mod:`vcbmodel.laws.discovered`): not an
    effect of the registry (the diagnosis never proposes it; discovery adds it with the terms it
    found). Its parameters are the terms' coefficients, named ``discovered:<term>`` (each in its
    term's unit); listing ``discovered_torque`` among a run's effects switches it on."""

    name = "discovered_torque"
    prefix = "discovered:"
    needs = ("shaft_torque",)  # an experiment whose equations carry a further torque on the shaft

    def acts_on(self, provides) -> bool:
        """Whether an experiment that provides ``provides`` carries the torque."""
        return set(self.needs) <= set(provides)

    def terms(self, values: dict) -> tuple:
        """((term name, coefficient), ...) from ``values``' ``discovered:<term>`` entries, sorted."""
        out = []
        for key in sorted(values):
            if key.startswith(self.prefix):
                name = key[len(self.prefix):]
                term(name)  # ValueError for a name the library does not have
                out.append((name, float(values[key])))
        return tuple(out)

    def on(self, spec: ModelSpec, values: dict, rig: Rig) -> None:
        if not self.acts_on(rig.provides):
            raise ValueError(f"a discovered torque needs equations that carry a torque on the shaft: "
                             f"not a {rig.experiment} test")
        spec.discovered = self.terms(values)


class FrictionFormSwitch:
    """The machinery that runs the shaft friction in another form than the hybrid law's
    (:mod:`vcbmodel.laws.friction_forms`): not an effect of the registry (the diagnosis never names
    it; :mod:`vcbmodel.analysis.model_forms` fits the forms a record cannot tell apart). Listing the
    form's ``effect`` name among a run's effects switches it on; the hybrid law's values keep their
    meaning and come from the registered effects; the form's own values are named as its parameters."""

    experiments = ("pendulum", "cam_drop", "vcb_closing")

    def __init__(self, form):
        self.form = form
        self.name = form.effect
        self.prefix = tuple(p.name for p in form.parameters) or (form.effect + ":",)

    def on(self, spec: ModelSpec, values: dict, rig: Rig) -> None:
        if spec.friction_form != "hybrid":
            raise ValueError(f"two friction forms in one model: {spec.friction_form} and {self.form.name}")
        missing = [p.name for p in self.form.parameters if p.name not in values]
        if missing:
            raise ValueError(f"the {self.form.name} friction form needs {', '.join(missing)}")
        spec.friction_form = self.form.name
        spec.form_values = tuple(float(values[p.name]) for p in self.form.parameters)


#: Model parts that are not effects of the registry (the diagnosis's candidates): discovery's torque,
#: the friction forms.
MACHINERY = {m.name: m for m in (DiscoveredTorque(), *(FrictionFormSwitch(f) for f in FORMS.values() if f.effect))}


def effect_reading(path: str, registry: dict[str, Effect] | None = None) -> str | None:
    """The name of the effect that reads rig field ``path``, or None (a field every model uses)."""
    for name, effect in (registry or EFFECTS).items():
        if path in effect.rig_fields:
            return name
    return None


def parameter_specs(effects: Iterable[str], registry: dict[str, Effect] | None = None) -> list[ParameterSpec]:
    """The parameter specs owned by the listed effects, in registry order."""
    return [p for name, e in (registry or EFFECTS).items() if name in effects for p in e.parameters]


def assembly_order(registry: dict[str, Effect]) -> tuple[Effect, ...]:
    """The effects so that each comes after those that set the fields it reads; whatever the
    registry's order, the model is the same. Refuses (ValueError) a field two effects set, a field
    read that no effect sets, and effects that read each other's fields in a circle."""
    setter = {}
    for effect in registry.values():
        for f in effect.sets:
            if f in setter:
                raise ValueError(f"model field {f!r} is set by two effects: {setter[f]!r} and {effect.name!r}")
            setter[f] = effect.name
    unset = [(e.name, f) for e in registry.values() for f in e.reads if f not in setter]
    if unset:
        raise ValueError(f"effect {unset[0][0]!r} reads model field {unset[0][1]!r}, which no effect sets")
    order, placed, pending = [], set(), list(registry.values())
    while pending:
        ready = [e for e in pending if all(setter[f] in placed for f in e.reads)]
        if not ready:
            raise ValueError(f"effects read each other's fields in a circle: {', '.join(e.name for e in pending)}")
        order += ready
        placed |= {e.name for e in ready}
        pending = [e for e in pending if e.name not in placed]
    return tuple(order)


def assemble(rig, choice, values) -> ModelSpec:
    """The model of a run with model choice ``choice`` (:class:`~vcbmodel.rig.spring_model.ModelChoice`):
    every registered effect contributes its on or off part (the fields it declares it ``sets``),
    in :func:`assembly_order`; then the machinery the run lists (a discovered torque)."""
    effects = choice.effects
    fields = {}
    for effect in assembly_order(EFFECTS):
        model = {f: fields[f] for f in effect.reads}
        part = effect.on(values, model) if effect.name in effects else effect.off(model)
        if set(part) != set(effect.sets):
            raise ValueError(f"effect {effect.name!r} set {sorted(part)}, not the fields it declares {sorted(effect.sets)}")
        fields.update(part)
    spec = ModelSpec(effects=tuple(effects), spring_model=choice.spring_model, sticking=rig.friction.get("sticking", "passive"),
                     **fields)
    for name, machinery in MACHINERY.items():
        if name in effects:
            machinery.on(spec, values, rig)
    return spec

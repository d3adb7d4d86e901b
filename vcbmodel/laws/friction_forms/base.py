"""What a friction form is, its law value, and the registry the form files fill.

A *form* is a shaft friction law with the hybrid law's meaning of its values (``mu_k`` the kinetic
level at speed, ``mu_s`` the level at rest, ``viscous`` a torque C_v w, ``stribeck_velocity`` the
speed scale of the fall between them) but another shape between rest and sliding, or levels that
change in time. A form states only its *slip level*: the friction law at shaft speed w (rad/s) and
model time t (s), given as the values of the hybrid law (:class:`~vcbmodel.laws.friction.FrictionLaw`)
that hold at that instant (:meth:`FrictionForm.instant`). The stick band, the passive stuck state
and the reaction solved together with the acceleration (paper eq. 2-6, 13) are the hybrid law's own
(:func:`~vcbmodel.laws.friction.shaft_friction`), so every form sticks and breaks away the same way
and no part of the law is written twice. Each form's ``instant`` takes an ``ops`` namespace: Python,
numpy, Exudyn's symbolic user functions and the compiled path evaluate one source.

Units: speeds rad/s, time s, coefficients dimensionless, C_v N m s/rad, radius m, inertia kg m^2.
"""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, fields

from ..friction import FrictionLaw, effective_static
from ..types import Ops, Scalar
from ...parameters import STICK_TIME


@dataclass(frozen=True)
class FormParameter:
    """A value a form has beyond the hybrid law's: name, fit start, bounds, unit, what it is, and
    further fit starts (``scan``: a fit from the start alone can stop in a valley the form shares
    with the other friction values)."""

    name: str
    initial: float
    min: float
    max: float
    unit: str
    description: str = ""
    scan: tuple = ()


@dataclass(frozen=True)
class FrictionForm:
    """One friction form.

    name : registry key (``tustin``).
    effect : what a model lists among its effects to switch the form on (``tustin_friction``);
        empty for the hybrid law itself (the model's default, :class:`FrictionLaw` directly).
    description : the law in words, with its source.
    instant : ``(law: FormLaw, w, t, ops) -> {FrictionLaw field: value}``: the hybrid law's
        ``mu_s``, ``mu_k``, ``stribeck_velocity`` and ``viscous`` that hold at speed w (rad/s) and
        time t (s); every value may depend on w and t (branch on them only through ``ops.where``).
    parameters : the form's own values (:class:`FormParameter`), read from ``FormLaw.extra`` in order.
    needs : registered effects that must be on for the form to differ from the hybrid law
        (``stribeck``: a curve between mu_s and mu_k needs both).
    """

    name: str
    effect: str
    description: str
    instant: Callable[..., dict]
    parameters: tuple = ()
    needs: tuple = ()


#: The registry, by name; filled by the form files as the package is imported (one file per form).
FORMS: dict[str, FrictionForm] = {}


def register(form: FrictionForm) -> FrictionForm:
    """Add ``form`` to :data:`FORMS` (a name or effect used twice is refused)."""
    if form.name in FORMS or (form.effect and any(f.effect == form.effect for f in FORMS.values())):
        raise ValueError(f"friction form {form.name!r} (effect {form.effect!r}) is registered twice")
    FORMS[form.name] = form
    return form


@dataclass(frozen=True)
class InstantLaw(FrictionLaw):
    """The hybrid law's values at one instant of a form: like :class:`FrictionLaw`, but its values
    may be expressions of the state (the static level is not re-clamped: :class:`FormLaw` clamps
    its own values once)."""

    def __post_init__(self):
        pass


@dataclass(frozen=True)
class FormLaw:
    """A friction form's law with its values (the model's counterpart of :class:`FrictionLaw`).

    form : a key of :data:`FORMS`.
    mu_s, mu_k : static and kinetic coefficients (-); mu_s is never below mu_k.
    stick_velocity, stribeck_velocity : w0 and the form's speed scale (rad/s).
    viscous : C_v (N m s/rad); radius : journal radius r (m).
    sticking, stick_time, step : as :class:`FrictionLaw`.
    extra : the form's own values, in the order of its ``parameters``.
    """

    form: str
    mu_s: float = 0.0
    mu_k: float = 0.0
    stick_velocity: float = 1e-3
    stribeck_velocity: float = 0.0
    viscous: float = 0.0
    radius: float = 0.02
    sticking: str = "passive"
    stick_time: float = STICK_TIME
    step: float = 0.0
    extra: tuple = ()

    def __post_init__(self):
        if self.form not in FORMS:
            raise ValueError(f"unknown friction form {self.form!r} (known: {', '.join(FORMS)})")
        object.__setattr__(self, "mu_s", effective_static(self.mu_s, self.mu_k))

    def value(self, name: str) -> Scalar:
        """The form's own value ``name`` (its unit: the :class:`FormParameter`'s)."""
        names = [p.name for p in FORMS[self.form].parameters]
        return self.extra[names.index(name)]

    def at(self, w: Scalar, t: Scalar, ops: Ops) -> InstantLaw:
        """The hybrid law that holds at speed ``w`` (rad/s) and time ``t`` (s)."""
        common = {f.name: getattr(self, f.name) for f in fields(FrictionLaw) if f.name not in
                  ("mu_s", "mu_k", "stribeck_velocity", "viscous")}
        return InstantLaw(**common, **FORMS[self.form].instant(self, w, t, ops))


def hybrid_values(law: FormLaw) -> dict:
    """The law's own values as the hybrid law reads them (no change with speed or time)."""
    return {"mu_s": law.mu_s, "mu_k": law.mu_k, "stribeck_velocity": law.stribeck_velocity, "viscous": law.viscous}

"""The model choice (effects, spring model, lumped convention) of a run: the rig's
(:func:`vcbmodel.rig.spring_model.read_model` read it from the rig file) unless a run overrides it,
by one rule (:func:`choose`: the command line's ``--effects`` / ``--spring-model`` and
:func:`vcbmodel.experiments.simulation.simulate`'s arguments). The result is one
:class:`~vcbmodel.rig.spring_model.ModelChoice` that every layer below reads as it is.
"""
from __future__ import annotations

from collections.abc import Sequence

from ..errors import InputError
from ..rig.data import Rig
from ..rig.spring_model import ModelChoice, SpringModel, check_effect_names
from .effects import EFFECTS


def applicable(record: object) -> dict[str, bool]:
    """Every registered effect's name (in the registry's order) and whether it applies to an
    experiment of kind ``record``: the record provides all the effect needs."""
    return {name: effect.acts_on(record.provides) for name, effect in EFFECTS.items()}


def parse_effects_option(text: str, record: object, source: str = "--effects") -> tuple[str, ...]:
    """Effects given on the command line for an experiment of kind ``record``: comma-separated, spaces allowed."""
    effects = [e.strip() for e in text.split(",") if e.strip()]

    def fail(message):
        raise InputError(source, "effects", message)

    check_effect_names(effects, applicable(record), record.name, fail)
    return tuple(effects)


def consistent_effects(effects: Sequence[str], spring_model: SpringModel) -> tuple[str, ...]:
    """``effects`` with ``spring_mass`` listed exactly when the spring model is not massless
    (spec "Effect names"), in registry order (names the registry does not hold, such as
    ``discovered_torque``, after them)."""
    wanted = set(effects) - {"spring_mass"} | ({"spring_mass"} if not spring_model.is_massless else set())
    return tuple(e for e in EFFECTS if e in wanted) + tuple(e for e in effects if e not in EFFECTS)


def choose(rig: Rig, effects: Sequence[str] | None = None, spring_model: str | SpringModel | None = None) -> ModelChoice:
    """The model of a run: the rig's ``model`` unless ``effects`` or ``spring_model`` override it.

    - A named ``spring_model`` (text such as ``lumped-2:paper``, the rig's lumped convention where
      the text names none, or a :class:`SpringModel`) decides ``spring_mass``: it is listed exactly
      when the spring has mass, whatever ``effects`` says (:func:`consistent_effects`).
    - ``effects`` named alone decide whether the spring has mass: without ``spring_mass`` it is
      massless (the rig's convention kept); with it, the rig's spring model, which must then have
      mass (a massless rig's spring model is not replaced by a default: ValueError).

    Raises ValueError with a message fit for a one-line error.
    """
    m = rig.model
    if spring_model is not None:
        spring = SpringModel.parse(spring_model, m.spring_model.convention)
        return ModelChoice(consistent_effects(m.effects if effects is None else effects, spring), spring)
    if effects is None:
        return m
    effects = tuple(effects)
    if "spring_mass" not in effects:
        return ModelChoice(effects, SpringModel.parse("massless", m.spring_model.convention))
    if m.spring_model.is_massless:
        raise ValueError("'spring_mass' is listed but the rig's spring model is massless: name the spring model "
                         "(lumped-N or ancf) with it")
    return ModelChoice(effects, m.spring_model)

"""The model choice (effects, spring model, lumped convention), decided here and nowhere else:
the rig's ``model`` section (:func:`read_model`) and a run's overrides (:func:`choose`: the command
line's ``--effects`` / ``--spring-model`` and :func:`vcbmodel.experiments.simulation.simulate`'s
arguments) become one :class:`~vcbmodel.rig.data.ModelChoice` that every layer below reads as it is.
"""
from __future__ import annotations

import json
from collections.abc import Callable, Sequence

from ..errors import InputError
from ..rig.data import ModelChoice, Rig
from ..rig.reader import Reader, did_you_mean
from ..rig.spring_model import SpringModel
from .effects import EFFECTS

MODEL_KEYS = ("effects", "spring_model", "lumped_convention")


def check_effect_names(effects: Sequence[str], record: object, fail: Callable[[str], None]) -> None:
    """Refuse unknown, inapplicable (the experiment ``record`` does not provide what the effect
    needs) or repeated effect names through ``fail(message)``."""
    for e in effects:
        if e not in EFFECTS:
            fail(f"unknown effect {e!r}{did_you_mean(e, EFFECTS)} (known: {', '.join(EFFECTS)})")
        if not EFFECTS[e].acts_on(record.provides):
            fail(f"effect {e!r} does not apply to a {record.name} test")
    if len(set(effects)) != len(effects):
        fail("lists an effect twice")


def read_model(rd: Reader, data: dict, record: object) -> ModelChoice:
    """The rig's ``model`` (for an experiment of kind ``record``): a :class:`vcbmodel.rig.data.ModelChoice`."""
    m = rd.section(data, "model")
    rd.known_keys(m, MODEL_KEYS, "model.")
    effects = m.get("effects", [])
    if not isinstance(effects, list) or not all(isinstance(e, str) for e in effects):
        rd.fail("model.effects", "must be a list of effect names")
    check_effect_names(effects, record, lambda msg: rd.fail("model.effects", msg))
    convention = m.get("lumped_convention", "exact")
    if not isinstance(convention, str) or ":" in convention:
        rd.fail("model.lumped_convention", f"must be exact, paper or uniform, got {json.dumps(convention)}")
    try:
        SpringModel.parse("massless", convention)
    except ValueError:
        rd.fail("model.lumped_convention", f"must be exact, paper or uniform, got {json.dumps(convention)}")
    text = m.get("spring_model", "massless")
    try:
        if not isinstance(text, str) or ":" in text:
            raise ValueError(f"must be massless, lumped-N (N = 1..99) or ancf, got {json.dumps(text)}")
        spring_model = SpringModel.parse(text, convention)
    except ValueError as e:
        rd.fail("model.spring_model", str(e))
    if ("spring_mass" in effects) != (not spring_model.is_massless):
        rd.fail("model.effects", "'spring_mass' must be listed exactly when spring_model is not 'massless'")
    return ModelChoice(tuple(effects), spring_model)


def parse_effects_option(text: str, record: object, source: str = "--effects") -> tuple[str, ...]:
    """Effects given on the command line for an experiment of kind ``record``: comma-separated, spaces allowed."""
    effects = [e.strip() for e in text.split(",") if e.strip()]

    def fail(message):
        raise InputError(source, "effects", message)

    check_effect_names(effects, record, fail)
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

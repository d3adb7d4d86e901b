"""The closing-spring model as one value, parsed in one place, and the model choice it is part of
(:class:`ModelChoice`: the effects and the spring model), read here from a rig file's ``model``
section (:func:`read_model`); a run's overrides of it are :func:`vcbmodel.model.choice.choose`'s.

Text forms: ``massless``, ``lumped-N`` (N = 1..99) optionally with a convention
``lumped-N:paper`` / ``:exact`` / ``:uniform``, and ``ancf``. The convention is carried for
every model (it applies when a lumped chain is built, e.g. when the diagnosis adds
``spring_mass`` to a massless model).
"""
from __future__ import annotations

import json
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from .reader import did_you_mean

if TYPE_CHECKING:
    from .reader import Reader

LUMPED_CONVENTIONS = ("exact", "paper", "uniform")
KINDS = ("massless", "lumped", "ancf")
_LUMPED = re.compile(r"lumped-([1-9][0-9]?)")


@dataclass(frozen=True)
class SpringModel:
    """``kind``: massless | lumped | ancf; ``masses``: n of a lumped chain (0 otherwise);
    ``convention``: exact | paper | uniform (spec "lumped_convention")."""

    kind: str = "massless"
    masses: int = 0
    convention: str = "exact"

    @classmethod
    def parse(cls, text, convention=None) -> "SpringModel":
        """Parse ``text`` (see module docstring); ``convention`` applies when the text names
        none (a :class:`SpringModel` is returned as it is). Raises ``ValueError`` with a message fit for a one-line error."""
        if isinstance(text, SpringModel):
            return text
        if not isinstance(text, str):
            raise ValueError(f"must be massless, lumped-N (N = 1..99) or ancf, got {text!r}")
        name, _, named_convention = text.strip().partition(":")
        conv = named_convention or convention or "exact"
        if conv not in LUMPED_CONVENTIONS:
            raise ValueError(f"unknown lumped convention {conv!r} (known: {', '.join(LUMPED_CONVENTIONS)})")
        if name in ("massless", "ancf"):
            if named_convention:
                raise ValueError(f"a convention applies to lumped-N models only, got {text!r}")
            return cls(name, 0, conv)
        m = _LUMPED.fullmatch(name)
        if not m:
            raise ValueError(f"must be massless, lumped-N (N = 1..99) or ancf, got {text!r}")
        return cls("lumped", int(m.group(1)), conv)

    def with_convention(self, convention: str) -> SpringModel:
        return replace(self, convention=convention)

    @property
    def is_massless(self) -> bool:
        return self.kind == "massless"

    @property
    def name(self) -> str:
        """The spec's ``spring_model`` text: ``massless``, ``lumped-N`` or ``ancf``."""
        return f"lumped-{self.masses}" if self.kind == "lumped" else self.kind

    @property
    def label(self) -> str:
        """For reports: the name, with the convention for a lumped chain."""
        return f"{self.name} ({self.convention})" if self.kind == "lumped" else self.name

    def __str__(self):
        return self.name


#: The mass models the diagnosis tries when it adds the spring's inertia (effect ``spring_mass``: a
#: discrete choice, no fitted parameter; the best by BIC is kept). Cheapest first: a candidate that
#: explains the record within the noise stops the rest.
MASS_VARIANTS = tuple(SpringModel.parse(s) for s in ("lumped-1", "lumped-2", "lumped-3", "lumped-1:paper",
                                                     "lumped-2:paper", "lumped-3:paper", "ancf"))


@dataclass(frozen=True)
class ModelChoice:
    """The analyst's model: effect names and the closing-spring model (with its lumped
    convention), decided once (here for a rig file, :func:`vcbmodel.model.choice.choose` for a
    run's overrides) and read as it is by every layer."""

    effects: tuple
    spring_model: SpringModel


MODEL_KEYS = ("effects", "spring_model", "lumped_convention")


def check_effect_names(effects: Sequence[str], applicable: Mapping[str, bool], experiment: str,
                       fail: Callable[[str], None]) -> None:
    """Refuse unknown, inapplicable or repeated effect names through ``fail(message)``.
    ``applicable``: every registered effect's name, in the registry's order, and whether it applies
    to a test of kind ``experiment`` (:func:`vcbmodel.model.choice.applicable`: what the effect
    needs against what the experiment provides)."""
    for e in effects:
        if e not in applicable:
            fail(f"unknown effect {e!r}{did_you_mean(e, applicable)} (known: {', '.join(applicable)})")
        if not applicable[e]:
            fail(f"effect {e!r} does not apply to a {experiment} test")
    if len(set(effects)) != len(effects):
        fail("lists an effect twice")


def read_model(rd: Reader, data: dict, applicable: Mapping[str, bool], experiment: str) -> ModelChoice:
    """The rig file's ``model`` section as a :class:`ModelChoice` (``applicable`` and ``experiment``
    as :func:`check_effect_names` takes them); every fault is one line naming the field."""
    m = rd.section(data, "model")
    rd.known_keys(m, MODEL_KEYS, "model.")
    effects = m.get("effects", [])
    if not isinstance(effects, list) or not all(isinstance(e, str) for e in effects):
        rd.fail("model.effects", "must be a list of effect names")
    check_effect_names(effects, applicable, experiment, lambda msg: rd.fail("model.effects", msg))
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

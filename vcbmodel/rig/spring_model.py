"""The closing-spring model as one value, parsed in one place.

Text forms: ``massless``, ``lumped-N`` (N = 1..99) optionally with a convention
``lumped-N:paper`` / ``:exact`` / ``:uniform``, and ``ancf``. The convention is carried for
every model (it applies when a lumped chain is built, e.g. when the diagnosis adds
``spring_mass`` to a massless model).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, replace

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

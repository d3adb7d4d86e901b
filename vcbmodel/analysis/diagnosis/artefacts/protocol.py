"""The protocol every sensor artefact follows: what it fits, what it removes from the record's
residual, and how it is reported. The verdict and the search's test of "at the noise"
(:mod:`..at_noise`) set aside every registered artefact (:data:`ARTEFACTS`, in increasing
``order``) before they judge what remains: the physics is judged on the residual without the
sensor's artefacts. A new artefact is one module in this folder that calls :func:`register`
(the folder's modules are imported with it). Units: s, Hz, the record's unit (rad or m)."""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Protocol, runtime_checkable

import numpy as np


@dataclass(frozen=True)
class ResidualView:
    """What an artefact sees: the measured channel's residual (model - record, the record's unit)
    at record times ``t`` (s), the model's reading there (None: not known), the record's
    high-frequency noise level and quantisation step (the record's unit; 0: not on a grid), and
    the upper edge of the mechanism's own band (Hz; None: no line test for this experiment)."""

    t: np.ndarray
    residual: np.ndarray
    model: np.ndarray | None = None
    sigma_hf: float = 0.0
    quantisation: float = 0.0
    band_hz: float | None = None

    def with_residual(self, residual: np.ndarray) -> ResidualView:
        return replace(self, residual=np.asarray(residual, float))


@runtime_checkable
class Artefact(Protocol):
    """A sensor artefact. ``name``: its key under the report's ``nuisance`` and the verdict's
    ``sensor_artefacts``; ``order``: artefacts are set aside in increasing order (each sees the
    residual the ones before it left)."""

    name: str
    order: int

    def fit(self, view: ResidualView) -> Any | None:
        """Its estimate from the residual (and the record's noise), or None when it is not there."""

    def remove(self, view: ResidualView, found: Any) -> np.ndarray:
        """The residual with the artefact ``found`` removed (the same residual when nothing of it
        can be removed and it counts only as noise)."""

    def report(self, found: Any, unit: str) -> tuple[Any, str]:
        """(its JSON for the report, a sentence for the evidence: '' for none)."""


@dataclass(frozen=True)
class Found:
    """An artefact found in one residual: which (``name``), its estimate, its JSON and sentence."""

    name: str
    estimate: Any
    json: Any
    sentence: str


#: The registered artefacts by name.
ARTEFACTS: dict[str, Artefact] = {}


def register(artefact: Artefact) -> Artefact:
    """Add ``artefact`` (an object following :class:`Artefact`) to :data:`ARTEFACTS`; returns it."""
    if not isinstance(artefact, Artefact):
        raise TypeError(f"{artefact!r} does not follow the Artefact protocol (name, order, fit, remove, report)")
    ARTEFACTS[artefact.name] = artefact
    return artefact


def set_aside(view: ResidualView, unit: str = "") -> tuple[np.ndarray, list[Found]]:
    """The residual with every registered artefact found in it removed, and what was found."""
    residual = np.asarray(view.residual, float)
    found = []
    for artefact in sorted(ARTEFACTS.values(), key=lambda a: a.order):
        here = view.with_residual(residual)
        estimate = artefact.fit(here)
        if estimate is None:
            continue
        residual = np.asarray(artefact.remove(here, estimate), float)
        data, sentence = artefact.report(estimate, unit)
        found.append(Found(artefact.name, estimate, data, sentence))
    return residual, found


def found_named(found: list[Found], name: str) -> Found | None:
    """The artefact ``name`` among ``found``, or None."""
    return next((f for f in found if f.name == name), None)

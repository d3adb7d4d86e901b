"""A sensor artefact (:mod:`.protocol`): an ADC's or an encoder's quantisation. A 12-bit data
logger reads a potentiometer's 340 degrees in 4096 steps (1.45 mrad); an encoder counts in whole
steps. The readings then lie on a grid of step q (found from the record by
:func:`vcbmodel.records.signals.quantisation_step` when the record is aligned), and their rounding
is noise of q / sqrt(12), not a torque: it is counted in the noise the residual is judged against
(the noise model's floor, and where the rounding rules the noise, the rounding band instead of
whiteness: :func:`vcbmodel.analysis.noise.consistency`). Nothing of it can be removed from the
residual: the reading before the rounding is not known.

Units: the record's (rad or m).
"""
from __future__ import annotations

import math

import numpy as np

from .protocol import ResidualView, register

#: The rounding rules the noise when its noise, q / sqrt(12), is at least this share of the
#: record's high-frequency level (the same test as :func:`vcbmodel.analysis.noise.rounding_dominates`).
DOMINATES_SHARE = 0.5


def quantisation_nuisance(step: float, sigma_hf: float) -> dict | None:
    """A quantised sensor's rounding as a nuisance for the report (None when the record is not
    on a grid): the step, its rounding noise q / sqrt(12) (the record's unit), and whether the
    rounding rules the noise (at least half the record's high-frequency level)."""
    if not step:
        return None
    rounding = step / math.sqrt(12.0)
    return {"step": float(step), "rounding_noise": rounding,
            "rounding_dominates": bool(rounding >= DOMINATES_SHARE * sigma_hf),
            "reading": "readings on a grid: an encoder's count or a data logger's step"}


class Quantisation:
    """The artefact: the record's grid step, counted as noise (see the module docstring)."""

    name = "quantisation"
    order = 30

    def fit(self, view: ResidualView) -> dict | None:
        return quantisation_nuisance(view.quantisation, view.sigma_hf)

    def remove(self, view: ResidualView, found: dict) -> np.ndarray:
        return np.asarray(view.residual, float)

    def report(self, found: dict, unit: str) -> tuple[dict, str]:
        text = (f" The readings lie on a grid of {found['step']:.3g} {unit} (an ADC's or an encoder's step): its "
                f"rounding, {found['rounding_noise']:.3g} {unit}, is counted as noise"
                + (" and rules it, so the residual is judged by the rounding band." if found["rounding_dominates"]
                   else "."))
        return found, text


register(Quantisation())

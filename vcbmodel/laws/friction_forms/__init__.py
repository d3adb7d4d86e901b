"""Friction forms: shaft friction laws beside the hybrid one, for the forms a record cannot tell
apart (:mod:`vcbmodel.analysis.model_forms`).

One file per form, each registering a :class:`.base.FrictionForm` in :data:`FORMS` when the package
is imported (every module here but ``base`` is imported below, so a new form is its file and its
test, ``tests/laws/test_friction_form_<name>.py``; ``tests/laws/test_friction_forms.py`` checks every
registered form against the Exudyn model and for a test of its own). A model switches a form on by
listing its ``effect`` name (:data:`vcbmodel.model.effects.MACHINERY`).

Registered: ``hybrid`` (the spec's law), ``tustin`` (exponential Stribeck), ``power`` (a Stribeck fall with a
free exponent), ``gaussian`` (the LuGre
model's steady state), ``drifting`` (levels drifting linearly in time).

Not a form here: Dahl's model and LuGre's bristle dynamics. Their state, the bristles' deflection z
(micrometres), relaxes at the rate sigma0 |v| / mu_k, about 1e5-1e6 per second at a shaft's sliding
speeds (sigma0 ~ 1e5-1e6 1/m per unit load, v ~ 0.02 m/s): the fixed-step RK4 of the compiled path
and of the Exudyn models (steps of 0.5 ms) cannot carry such a stiff first-order state, and both
integrate second-order coordinates only. Once sliding, Dahl's friction is its Coulomb level
(the hybrid law without Stribeck) and LuGre's is :mod:`.gaussian`; what neither form carries is the
pre-sliding of micrometres at the reversals.
"""
from __future__ import annotations

import importlib
import pkgutil

from .base import FORMS, FormLaw, FormParameter, FrictionForm, InstantLaw, register

for _module in pkgutil.iter_modules(__path__):
    if _module.name != "base":
        importlib.import_module(f"{__name__}.{_module.name}")

__all__ = ["FORMS", "FormLaw", "FormParameter", "FrictionForm", "InstantLaw", "register", "form_of_effect"]


def form_of_effect(effect: str) -> FrictionForm | None:
    """The form an effect name switches on, or None."""
    return next((f for f in FORMS.values() if f.effect and f.effect == effect), None)

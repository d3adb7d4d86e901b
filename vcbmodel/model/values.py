"""The one rule for model values: given > rig > (fits only) the registry's starting guess.

A value an effect needs that neither the caller nor the rig gives is refused with one line
naming the rig field (no silent default), except a parameter whose :class:`ParameterSpec`
states a documented ``default`` (the stick band w0). Fits ask with ``for_fit=True``: their
starting guesses come from the registry and are never used as model values otherwise.
"""
from __future__ import annotations

from ..errors import InputError
from .effects import EFFECTS, MACHINERY, parameter_specs


def rig_values(rig) -> dict:
    """Every effect parameter value the rig gives (whichever effects the model lists)."""
    out = {}
    for effect in EFFECTS.values():
        if effect.acts_on(rig.provides):
            out.update(effect.rig_values(rig))
    return out


def owner_of(parameter_name: str) -> str:
    return next((e.name for e in EFFECTS.values() if any(p.name == parameter_name for p in e.parameters)), "?")


def model_values(rig, effects, values=None, *, for_fit=False) -> dict:
    """All parameter values the effects need (see module docstring)."""
    given, from_rig = dict(values or {}), rig_values(rig)
    out = {}
    for p in parameter_specs(effects):
        if p.name in given:
            out[p.name] = given[p.name]
        elif p.name in from_rig:
            out[p.name] = from_rig[p.name]
        elif p.default is not None:
            out[p.name] = p.default
        elif for_fit:
            out[p.name] = p.initial
        else:
            raise InputError(rig.path, p.rig_field, f"missing: the model's effect {owner_of(p.name)!r} needs it "
                             "(give it in the rig, or let identify/diagnose fit it)")
    for name, machinery in MACHINERY.items():  # a discovered torque's coefficients, as given
        if name in effects:
            out.update({k: v for k, v in given.items() if k.startswith(machinery.prefix)})
    return out

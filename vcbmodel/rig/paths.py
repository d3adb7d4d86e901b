"""Dotted paths into a rig's JSON object (``friction.mu_k``, ``breaker.poles.gap_offsets.1``: list
items by index) and into a loaded rig (:func:`loaded_value`, :func:`loaded_with`). One
implementation for every layer that names a rig field by its path: sweeps, the rig's
``uncertain`` section, nuisance estimates and fits."""
from __future__ import annotations

import copy
from dataclasses import replace
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .data import Rig


def path_keys(path: str) -> list[str | int]:
    """``a.b.2.c`` -> ["a", "b", 2, "c"] (digits index lists)."""
    keys = path.split(".")
    if any(k == "" for k in keys):
        raise ValueError("empty component")
    return [int(k) if k.isdigit() else k for k in keys]


def get_path(data: dict, path: str) -> Any:
    """The value at ``path``; KeyError if absent."""
    obj = data
    for k in path_keys(path):
        if isinstance(k, int) and isinstance(obj, list) and k < len(obj):
            obj = obj[k]
        elif isinstance(k, str) and isinstance(obj, dict) and k in obj:
            obj = obj[k]
        else:
            raise KeyError(path)
    return obj


def set_path(data: dict, path: str, value: Any) -> None:
    """Set ``path`` in ``data`` (in place), creating missing objects on the way."""
    keys = path_keys(path)
    obj = data
    for k, nxt in zip(keys[:-1], keys[1:]):
        if isinstance(obj, list):
            if not isinstance(k, int) or k >= len(obj):
                raise KeyError(path)
            obj = obj[k]
            continue
        if not isinstance(obj, dict) or isinstance(k, int):
            raise KeyError(path)
        if k not in obj:
            obj[k] = {}
        obj = obj[k]
    last = keys[-1]
    if isinstance(obj, list) and isinstance(last, int) and last < len(obj):
        obj[last] = value
    elif isinstance(obj, dict) and isinstance(last, str):
        obj[last] = value
    else:
        raise KeyError(path)


def with_overrides(data: dict, overrides: dict[str, Any]) -> dict:
    """A copy of the rig's JSON object with ``overrides`` ({path: value}) set."""
    out = copy.deepcopy(data)
    for path, value in overrides.items():
        set_path(out, path, float(value))
    return out


def numeric_at(data: dict, path: str) -> float | None:
    """The number at ``path`` (not a bool), or None when absent or not a number."""
    try:
        value = get_path(data, path)
    except (KeyError, ValueError):
        return None
    return value if isinstance(value, (int, float)) and not isinstance(value, bool) else None


def loaded_value(rig: Rig, path: str) -> float:
    """A numeric rig value by its dotted path (``pendulum.inertia``, ``shaft.radius``, ``gravity``,
    ``friction.mu_k``, ``breaker.poles.moving_mass``)."""
    if path == "gravity":
        return rig.gravity
    if path == "shaft.radius":
        return rig.shaft_radius
    head, _, rest = path.partition(".")
    if head == "friction":
        return rig.friction.get(rest)
    obj = rig.sections.get(head)
    for key in path_keys(rest):
        obj = obj[key] if isinstance(key, int) else getattr(obj, key)
    return obj


def loaded_with(rig: Rig, overrides: dict[str, float]) -> Rig:
    """A copy of ``rig`` with numeric fields replaced (dotted paths, see :func:`loaded_value`;
    ``friction.*`` values are passed to the simulation as values instead)."""
    if not overrides:
        return rig
    sections = dict(rig.sections)
    top = {}
    for path, value in overrides.items():
        if path == "gravity":
            top["gravity"] = float(value)
            continue
        if path == "shaft.radius":
            top["shaft_radius"] = float(value)
            continue
        head, _, rest = path.partition(".")
        if head == "friction":
            continue
        keys = path_keys(rest)

        def put(obj, keys):
            if len(keys) == 1:
                return replace(obj, **{keys[0]: float(value)})
            return replace(obj, **{keys[0]: put(getattr(obj, keys[0]), keys[1:])})

        sections[head] = put(sections[head], keys)
    return replace(rig, sections=sections, **top)

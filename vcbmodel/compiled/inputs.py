"""The numbers a compiled model reads at run time, and the structure it was compiled for.

The equations read rig sections, the friction law and the lumped chain: frozen dataclasses,
tuples and arrays of floats. :func:`flatten` lists their floats (the parameter vector ``p``, in a
fixed order) and their other values (ints, bools, strings, None: the *structure*, part of the
compiled code's key); :func:`parametrize` rebuilds the same objects with every float replaced
by a traced parameter, in the same order, so ``p[i]`` is the i-th float :func:`flatten` lists.
"""
from __future__ import annotations

import dataclasses

import numpy as np


def _walk(obj, path, leaf, structure):
    """Rebuild ``obj`` with each float ``x`` at ``path`` replaced by ``leaf(path, x)``; other
    values go to ``structure`` as (path, value)."""
    if isinstance(obj, bool) or obj is None or isinstance(obj, (int, str)):
        structure.append((path, obj))
        return obj
    if isinstance(obj, (float, np.floating)):
        structure.append((path, "float"))
        return leaf(path, float(obj))
    if isinstance(obj, np.ndarray):
        obj = tuple(obj.tolist())
    if isinstance(obj, (tuple, list)):
        structure.append((path, f"{type(obj).__name__}[{len(obj)}]"))
        return tuple(_walk(v, f"{path}[{i}]", leaf, structure) for i, v in enumerate(obj))
    if isinstance(obj, dict):
        structure.append((path, f"dict{sorted(obj)}"))
        return {k: _walk(obj[k], f"{path}.{k}", leaf, structure) for k in sorted(obj)}
    if dataclasses.is_dataclass(obj):
        structure.append((path, type(obj).__qualname__))
        fields = [f.name for f in dataclasses.fields(obj) if f.init]
        new = {name: _walk(getattr(obj, name), f"{path}.{name}", leaf, structure) for name in fields}
        return new
    raise TypeError(f"{path}: a {type(obj).__name__} cannot be an input of compiled equations")


def flatten(inputs: dict):
    """(p: float array, structure: tuple) of ``inputs`` ({name: object})."""
    values, structure = [], []

    def leaf(path, x):
        values.append(x)
        return x

    _walk(inputs, "", leaf, structure)
    return np.asarray(values, float), tuple(structure)


def parametrize(inputs: dict, graph):
    """``inputs`` with every float a traced parameter of ``graph`` (``p[i]`` in :func:`flatten`'s
    order); dataclasses are rebuilt through their constructor, so derived fields (e.g. the
    friction law's effective static coefficient) are traced too."""
    def leaf(path, x):
        return graph.param(path, x)

    rebuilt = _walk(inputs, "", leaf, [])
    return _reassemble(inputs, rebuilt)


def _reassemble(original, rebuilt):
    if isinstance(original, dict):
        return {k: _reassemble(original[k], rebuilt[k]) for k in original}
    if dataclasses.is_dataclass(original) and not isinstance(original, type):
        fields = {f.name: _reassemble(getattr(original, f.name), rebuilt[f.name])
                  for f in dataclasses.fields(original) if f.init}
        return dataclasses.replace(original, **fields)
    if isinstance(original, (tuple, list, np.ndarray)) and isinstance(rebuilt, tuple):
        return tuple(_reassemble(o, r) for o, r in zip(original, rebuilt))
    return rebuilt

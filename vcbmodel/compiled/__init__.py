"""A compiled path for fits and sweeps: the laws traced through ``ops`` into C (no second copy
of an equation), compiled with cffi, integrated with the RK4 of the Exudyn models.

Exudyn builds every model and stays the reference: the tests compare this path with the Exudyn
models to 1e-9 rad; it covers the pendulum and the cam drop with a massless or lumped spring
(the ANCF spring and the whole breaker stay on Exudyn). Results it produces say so
(``info["backend"]``).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import Callable

import numpy as np

from .solve import BACKEND_NAME, CompilerUnavailable, compiled_system, integrate

__all__ = ["BACKEND_NAME", "CompilerUnavailable", "OdeModel", "compiler_works", "solve_ode_model"]

log = logging.getLogger("vcbmodel")
_WORKS = []


def compiler_works() -> bool:
    """Whether a trivial system compiles and runs here (checked once per process; the reason it
    does not is logged once)."""
    if not _WORKS:
        try:
            system, p = compiled_system("probe", _probe_equations, {"k": 1.0}, [1.0], [0.0])
            rows = integrate(system, p, [1.0], [0.0], 0.1, 0.01)
            _WORKS.append(bool(abs(rows[-1, 1] - np.cos(0.1)) < 1e-8))
        except (CompilerUnavailable, OSError, ImportError) as e:
            log.warning("the compiled backend is unavailable here (%s): fits and sweeps run on Exudyn", e)
            _WORKS.append(False)
    return _WORKS[0]


def _probe_equations(t, q, v, inputs, ops):
    return [-inputs["k"] * q[0]], {}


@dataclass(frozen=True)
class OdeModel:
    """An experiment's equations for the compiled path: ``inputs(rig, law, chain)`` -> objects
    the equations read, ``initial(rig, chain)`` -> (q0, v0), ``equations(t, q, v, inputs, ops)``
    -> (accelerations, {output: value}). Coordinates after the shaft angle are the lumped
    chain's (x, y) pairs, recorded as ``spring_mass_<k>`` and ``spring_velocity_<k>``."""

    kind: str
    inputs: Callable
    initial: Callable
    equations: Callable


def solve_ode_model(model: OdeModel, rig, law, chain, t_end, step, period=None):
    """Sensor rows as the Exudyn models give them: {name: array (t, values...)}."""
    inputs = model.inputs(rig, law, chain)
    q0, v0 = model.initial(rig, chain)
    system, p = compiled_system(model.kind, model.equations, inputs, q0, v0)
    rows = integrate(system, p, q0, v0, t_end, step, period)
    n, t = system.n, rows[:, :1]
    data = {"angle": np.hstack([t, rows[:, 1:2]]), "velocity": np.hstack([t, rows[:, 1 + n:2 + n]])}
    for j, name in enumerate(system.outputs):
        data[name] = np.hstack([t, rows[:, 1 + 2 * n + j: 2 + 2 * n + j]])
    zero = np.zeros_like(t)
    for k in range((n - 1) // 2):
        qx = 2 + 2 * k
        data[f"spring_mass_{k + 1}"] = np.hstack([t, rows[:, qx:qx + 2], zero])
        data[f"spring_velocity_{k + 1}"] = np.hstack([t, rows[:, n + qx:n + qx + 2], zero])
    return data

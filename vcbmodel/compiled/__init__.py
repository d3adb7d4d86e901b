"""A compiled path for fits, sweeps and design studies: the laws traced through ``ops`` into C
(no second copy of an equation), compiled with cffi, integrated with the RK4 of the Exudyn
models.

Exudyn builds every model and stays the reference: the tests compare this path with the Exudyn
models to 1e-9 rad (1e-9 m); it covers the pendulum, the cam drop and the whole breaker's
closing with a massless or lumped spring (the ANCF spring stays on Exudyn; :mod:`.function` compiles
the law its Python friction callback evaluates). Results it produces say so (``info["backend"]``).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .solve import BACKEND_NAME, CompilerUnavailable, compiled_system, compiler_problem, integrate

__all__ = ["BACKEND_NAME", "CompilerUnavailable", "OdeModel", "OdeSetup", "compiler_problem", "compiler_works", "solve_ode_model"]

log = logging.getLogger("vcbmodel")
_WORKS = []


@dataclass
class OdeSetup:
    """One run's inputs: ``inputs`` (objects the equations read: their floats are the run-time
    parameters), the initial coordinates ``q0`` and speeds ``v0``, ``layout`` [(position sensor,
    velocity sensor, width)] naming the coordinates in order as the Exudyn model's sensors do,
    the initial ``memory`` (values latched by the pre-step function) and ``info`` for the result."""

    inputs: dict
    q0: list
    v0: list
    layout: list
    memory: list = field(default_factory=list)
    info: dict = field(default_factory=dict)


@dataclass(frozen=True)
class OdeModel:
    """An experiment's equations for the compiled path.

    - ``prepare(rig, spec, law, chain) -> OdeSetup``;
    - ``equations(t, q, v, memory, inputs, ops) -> (accelerations, {output: value})``;
    - ``prestep(t, q, v, memory, inputs, ops) -> memory``: values latched at the start of each
      step from the state there (Exudyn's pre-step function), or None.
    """

    kind: str
    prepare: Callable
    equations: Callable
    prestep: Callable | None = None


def solve_ode_model(model: OdeModel, rig, spec, law, chain, t_end, step, period=None):
    """(sensor rows as the Exudyn models give them: {name: array (t, values...)}, info)."""
    setup = model.prepare(rig, spec, law, chain)
    system, p = compiled_system(model.kind, model.equations, model.prestep, setup)
    rows = integrate(system, p, setup, t_end, step, period)
    t, width = rows[:, :1], len(setup.q0)
    data, k = {}, 0
    for position, velocity, size in setup.layout:
        pad = [np.zeros_like(t)] if size == 2 else []  # a 2-D point's Position has a z component
        data[position] = np.hstack([t, rows[:, 1 + k:1 + k + size]] + pad)
        data[velocity] = np.hstack([t, rows[:, 1 + width + k:1 + width + k + size]] + pad)
        k += size
    for j, name in enumerate(system.outputs):
        data[name] = np.hstack([t, rows[:, 1 + 2 * width + j:2 + 2 * width + j]])
    return data, setup.info


def compiler_works() -> bool:
    """Whether a trivial system compiles and runs here (checked once per process; the reason it
    does not is logged once)."""
    if not _WORKS:
        try:
            setup = OdeSetup({"k": 1.0}, [1.0], [0.0], [("x", "v", 1)])
            system, p = compiled_system("probe", _probe_equations, None, setup)
            rows = integrate(system, p, setup, 0.1, 0.01)
            _WORKS.append(bool(abs(rows[-1, 1] - np.cos(0.1)) < 1e-8))
        except (CompilerUnavailable, OSError, ImportError) as e:
            log.warning("the compiled backend is unavailable here (%s): fits and sweeps run on Exudyn", e)
            _WORKS.append(False)
    return _WORKS[0]


def _probe_equations(t, q, v, memory, inputs, ops):
    return [-inputs["k"] * q[0]], {}

"""Arithmetic on a fit's trial: numpy's floating-point warnings kept off the user's stderr.

A badly wrong trial (a start far from the record, a discovered term's refit that runs away) can
give a simulation that diverges to finite but enormous numbers (1e100 rad), and then a residual,
a Jacobian, a chi^2 or a covariance that overflows to inf or nan. The fit already reads those as a
failed trial: a chi^2 that is not lower (nan or inf included) is rejected by the optimisers, a
failed simulation scores ``FAILED`` per sample, a stated error that is not finite says the record
does not determine the value. numpy's ``RuntimeWarning: overflow encountered ...`` lines add
nothing to that and only reach stderr among the command's one-line messages, so the arithmetic of
a trial runs with them silenced. Only the warnings: every value stays what it was (inf and nan
included, so a non-finite objective is still a failed trial), and exceptions (a SimulationError,
an InputError, FitAborted) go on as before.
"""
from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, TypeVar

import numpy as np

F = TypeVar("F", bound=Callable)


def trial_arithmetic() -> np.errstate:
    """A context for a trial's arithmetic: overflow, invalid values and division by zero give inf
    or nan without a warning (underflow already does). A new context per use: numpy's are not
    re-entrant."""
    return np.errstate(over="ignore", invalid="ignore", divide="ignore")


def quiet_trial(function: F) -> F:
    """``function`` run in :func:`trial_arithmetic` (a decorator for the fit's trial evaluations)."""
    @functools.wraps(function)
    def quiet(*args: Any, **kwargs: Any) -> Any:
        with trial_arithmetic():
            return function(*args, **kwargs)
    return quiet  # type: ignore[return-value]

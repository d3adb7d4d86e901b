"""How a fit runs (:class:`FitOptions`), built once from :func:`~.minimizer.fit`'s keywords and
passed down, and how it is stopped from outside (``should_stop``, :class:`FitAborted`)."""
from __future__ import annotations

from dataclasses import dataclass, fields, replace
from typing import Callable


class FitAborted(Exception):
    """Raised inside a fit when its ``should_stop`` callback returns True (e.g. another
    candidate already won, or the time budget is spent)."""


@dataclass(frozen=True)
class FitOptions:
    """The options of a fit.

    Parameters
    ----------
    method : str
        ``"least_squares"`` (bounded Levenberg-Marquardt) or ``"nelder-mead"`` (the paper's simplex).
    starts : list of dict, optional
        Starting values (each parameter's unit) tried besides the parameters' own.
    sigma : float, optional
        White noise level for chi^2, AIC, BIC (the measured channel's unit: rad, or m; default:
        estimated from the data, :func:`~.parameters.pooled_noise`).
    verbose : bool
        Report each start's rms.
    label : str
        The fit's name in reports.
    max_simulations : int, optional
        Budget of the simplex (default 150 per varied parameter).
    processes : int
        Processes of the fit's own pool when ``pool`` is None and a pool would help.
    pool : SimulationPool, optional
        A pool to run simulations on.
    step : float, optional
        Integration step override (s).
    scales : dict, optional
        (dataset, channel) -> residual weight (the channel's unit; default: ``sigma``).
    should_stop : callable, optional
        Called before every batch of simulations; True aborts the fit with :class:`FitAborted`.
    max_iterations : int, optional
        Levenberg-Marquardt's iteration limit (default 10 + 2 per varied parameter).
    chi2_tolerance : float
        Levenberg-Marquardt's absolute chi^2 tolerance (dimensionless).
    relative_tolerance : float, optional
        Its tolerance as a fraction of the chi^2 noise alone would leave (default
        ``optimisers.RELATIVE_TOLERANCE``; 0: ``chi2_tolerance`` alone, for fits whose chi^2 is
        compared with another model's to within a few units).
    final_jacobian : bool
        Whether a converged Levenberg-Marquardt run ends on a fresh Jacobian.
    max_starts : int
        The optimiser runs from this many of the best-ranked starts.
    enough : callable, optional
        A test of a :class:`~.result.FitResult`; once the best so far passes it, no further start runs.
    every_start : bool
        Run the optimiser from each of the ``max_starts`` best starts even when one already ends at the
        noise level (models compared by chi^2 to a few units: a second valley can lie a few units lower).
    """

    method: str = "least_squares"
    starts: list | None = None
    sigma: float | None = None
    verbose: bool = True
    label: str = ""
    max_simulations: int | None = None
    processes: int = 2
    pool: object = None
    step: float | None = None
    scales: dict | None = None
    should_stop: Callable[[], bool] | None = None
    max_iterations: int | None = None
    chi2_tolerance: float = 0.1
    relative_tolerance: float | None = None
    final_jacobian: bool = True
    max_starts: int = 1
    enough: Callable[[object], bool] | None = None
    every_start: bool = False

    @classmethod
    def build(cls, options: FitOptions | None = None, **keywords) -> FitOptions:
        """``options`` (default: all defaults) with ``keywords`` replaced; an unknown keyword
        raises TypeError naming it."""
        known = {f.name for f in fields(cls)}
        unknown = sorted(set(keywords) - known)
        if unknown:
            raise TypeError(f"unknown fit option(s): {', '.join(unknown)} (known: {', '.join(sorted(known))})")
        return replace(options or cls(), **keywords)

"""Fitting model parameters to records (paper section 2.2), reported like lmfit.

A fit varies :class:`Parameter` objects (value, bounds, vary, stderr, optional Gaussian prior)
so that the model matches one or more records in the least-squares sense. Parameters are of
two sorts:

- *simulation* parameters change the simulation: the effects' values (``kind="model"``), a
  record's initial angle (``"state"``), rig values marked uncertain (``"rig"``);
- *alignment* parameters only move the simulation onto the record (:mod:`..nuisance`): the
  release time within the record (``"release"``), the sensor offset (``"offset"``) and gain
  (``"gain"``). Their derivatives are analytic.

The optimiser is a bounded Levenberg-Marquardt (:func:`levenberg_marquardt`) with a Jacobian
assembled by the :class:`Objective`: forward differences for the simulation parameters, one
simulation each, run in parallel on a process pool (:class:`SimulationPool`), and the analytic
columns of the alignment parameters. A fit of k simulation parameters therefore costs 1 + k
simulations per iteration, k of them in parallel; it stops when the next step would change
chi^2 by less than a small fraction of the noise's chi^2. Several starts are simulated once each
(in parallel) and the optimiser runs from the best. ``method="nelder-mead"`` keeps the paper's
simplex for a polish.

A dataset without a :class:`~..nuisance.RecordSetup` is fitted as before: the model starts at
the record's t = 0 with the rig's initial state, the sensor reads the model channel itself.

Rooms, each importing only the ones before it: :mod:`.arithmetic` (trial arithmetic with numpy's
floating-point warnings silenced), :mod:`.parameters` (parameters, noise level),
:mod:`.options` (:class:`FitOptions`, :class:`FitAborted`), :mod:`.dataset` (records and the
analyser's channels), :mod:`.pool` (simulations on worker processes), :mod:`.objective`
(residuals and Jacobian), :mod:`.optimisers` (Levenberg-Marquardt, Nelder-Mead),
:mod:`.covariance` (the parameters' errors: stated ones covering model-form error, and the
white-noise ones), :mod:`.result` (:class:`FitResult`), :mod:`.starts` (start ranking, grid
scans), :mod:`.minimizer` (:func:`fit`, :func:`staged_fit`, :func:`refine`) and :mod:`.profile` (how far
the record lets one parameter move, by refits with it held: the model forms' check of a stated error).
"""
from .covariance import Covariance, parameter_covariance
from .dataset import AlignedModel, Dataset, truncated
from .minimizer import fit, noise_scales, refine, staged_fit
from .objective import Curves, Objective
from .optimisers import levenberg_marquardt, nelder_mead
from .options import FitAborted, FitOptions
from .parameters import Parameter, make_parameters, pooled_noise
from .pool import SimJob, SimulationPool, dataset_pool, fit_step, run_job, scan_step, user_function_for
from .result import FitResult, jacobian_of
from .starts import scan_starts

__all__ = ["AlignedModel", "Covariance", "Curves", "Dataset", "FitAborted", "FitOptions", "FitResult", "Objective", "Parameter",
           "SimJob", "SimulationPool", "dataset_pool", "fit", "fit_step", "jacobian_of",
           "levenberg_marquardt", "make_parameters", "nelder_mead", "noise_scales", "parameter_covariance", "pooled_noise", "refine",
           "run_job", "scan_starts", "scan_step", "staged_fit", "truncated", "user_function_for"]

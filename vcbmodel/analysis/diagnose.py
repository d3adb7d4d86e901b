"""The discrepancy workflow's entry point: :func:`diagnose` runs the pipeline of
:mod:`.diagnosis.pipeline` on one record (align the record, fit the starting model, select
effects, refine the selection, judge the residual, discover, report; each step its own module in
:mod:`vcbmodel.analysis.diagnosis`). This module only re-exports the names other modules, studies
and tests import from here."""
from __future__ import annotations

from .diagnosis.align import fitted_channels
from .diagnosis.candidates import NULL_VALUES, candidate_jobs as _candidate_jobs
from .diagnosis.context import TIME_BUDGET, WALL_FACTOR
from .diagnosis.fits import MAX_STARTS
from .diagnosis.judge import ties as _ties
from .diagnosis.period import PERIOD_TOLERANCE, period_mismatch
from .diagnosis.pipeline import STEPS, diagnose
from .diagnosis.refine import WIDER_STARTS
from .diagnosis.result import Diagnosis
from .diagnosis.scores import BIC_MARGIN, MIN_VARIANCE_GAIN, SEPARABLE_NOISE_RATIO
from .diagnosis.state import Candidate

__all__ = ["BIC_MARGIN", "MAX_STARTS", "MIN_VARIANCE_GAIN", "NULL_VALUES", "PERIOD_TOLERANCE", "SEPARABLE_NOISE_RATIO",
           "STEPS", "TIME_BUDGET", "WALL_FACTOR", "WIDER_STARTS", "Candidate", "Diagnosis", "_candidate_jobs", "_ties",
           "diagnose", "fitted_channels", "period_mismatch"]

"""The discrepancy workflow's entry point: :func:`diagnose` runs the pipeline of
:mod:`.diagnosis.pipeline` on one record (align the record, fit the starting model, select
effects, refine the selection, judge the residual, discover, report; each step its own module in
:mod:`vcbmodel.analysis.diagnosis`). This module only re-exports the names other modules, studies
and tests import from here. Every threshold is in :class:`.diagnosis.options.DiagnosisOptions`."""
from __future__ import annotations

from .diagnosis.align import fitted_channels
from .diagnosis.candidates import NULL_VALUES, candidate_jobs as _candidate_jobs
from .diagnosis.judge import ties as _ties
from .diagnosis.options import DEFAULT_OPTIONS, DiagnosisOptions
from .diagnosis.period import period_mismatch
from .diagnosis.pipeline import STEPS, diagnose
from .diagnosis.result import Diagnosis
from .diagnosis.state import Candidate

#: The default evidence margin and variance gain (:class:`DiagnosisOptions`), for the studies and
#: the discovery demo that score by the diagnosis's rule.
BIC_MARGIN = DEFAULT_OPTIONS.bic_margin
MIN_VARIANCE_GAIN = DEFAULT_OPTIONS.min_variance_gain

__all__ = ["BIC_MARGIN", "DEFAULT_OPTIONS", "MIN_VARIANCE_GAIN", "NULL_VALUES", "STEPS", "Candidate", "Diagnosis",
           "DiagnosisOptions", "_candidate_jobs", "_ties", "diagnose", "fitted_channels", "period_mismatch"]

"""The discrepancy workflow as a pipeline of named steps (:mod:`.pipeline`): align the record,
fit the starting model, select effects, refine the selection, judge the residual, discover,
report. :func:`vcbmodel.analysis.diagnose.diagnose` is the entry point."""

"""Fitting, identification and diagnosis on measurements, and synthetic records. The diagnosis is
a pipeline of named steps, one module each, in ``diagnosis/`` (entry point: ``diagnose.diagnose``).

May import: ``vcbmodel.experiments`` and everything below it.
"""

"""Fitting, identification and diagnosis on measurements, and synthetic records. The diagnosis is
a pipeline of named steps, one module each, in ``diagnosis/`` (entry point: ``diagnose.diagnose``).

May import: ``vcbmodel.experiments`` and everything below it.

Inside, each folder or module imports only from those listed before it (tests/project checks it):
``progress``, ``noise``, ``plausibility``, ``thinning`` (helpers) -> ``fit``, ``nuisance``, ``sweep`` (fits, a
record's nuisance, parameter sweeps) -> ``release``, ``discovery``, ``held_out``, ``model_forms``
(what fits find) -> ``diagnosis``, ``identify`` (the two workflows) -> ``diagnose``, ``design``,
``realistic``, ``synthetic`` (entry points, design studies' evaluations, synthetic records for tests
and studies: nothing in the package imports them).
"""

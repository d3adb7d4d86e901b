"""Step 6, discover: when the best registered model leaves a structured residual, look for the
missing term outside the registry. A slot for now: it runs after the judge and reports that no
discovery was attempted, so the steps before and after it are wired already (issue 20, item 4:
sparse regression over a library of candidate terms goes here)."""
from __future__ import annotations

#: What the step reports while it has no method.
NO_DISCOVERY = {"attempted": False, "reason": "no discovery method is wired in yet"}


def discover(ctx, state) -> None:
    """Sets ``state.discovery`` (today always :data:`NO_DISCOVERY`); changes no fit."""
    state.discovery = dict(NO_DISCOVERY)

"""A slowly drifting Coulomb level: the hybrid law with its friction levels moving linearly in
time, mu_k(t) = mu_k + a t and mu_s(t) = mu_s + a t (a in 1/s; ``mu_k`` is the level at the
release, t = 0), as a bearing's boundary film warms or its grease redistributes during a test.

Why time and not dissipated energy: a record lasts 10-20 s, far shorter than a shaft and housing's
thermal time constant (minutes), so any smooth drift is linear in time to first order; a drift in
the energy dissipated would need the experiment's potential energy (not the friction law's to know)
or an extra state, and over one decaying swing the two differ only in how the drift is spread
between the first and the last swings. The level is kept at or above zero."""
from __future__ import annotations

from ..types import Ops, Scalar
from .base import FormParameter, FrictionForm, register, FormLaw

DRIFT = FormParameter("mu_k_drift", 0.0, -0.01, 0.01, "1/s",
                      "rate of change of the friction levels mu_k and mu_s with time", scan=(-1e-3, 1e-3))


def instant(law: FormLaw, w: Scalar, t: Scalar, ops: Ops) -> dict:
    """The hybrid law's values with both levels moved by a t (-)."""
    shift = law.value(DRIFT.name) * t
    return {"mu_s": ops.max(law.mu_s + shift, 0.0), "mu_k": ops.max(law.mu_k + shift, 0.0),
            "stribeck_velocity": law.stribeck_velocity, "viscous": law.viscous}


FORM = register(FrictionForm(
    "drifting", "drifting_coulomb_friction", "the hybrid law with its friction levels drifting linearly in time, "
    "mu_k + a t (a bearing warming during the test)", instant, parameters=(DRIFT,)))

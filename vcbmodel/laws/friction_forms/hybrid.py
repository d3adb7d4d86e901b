"""The hybrid law itself (paper eq. 2-4: Karnopp band, a linear Stribeck fall from mu_s to mu_k over
w_s, Coulomb, a viscous term shifted by w_s) as a form: the model's default. A model runs it as
:class:`~vcbmodel.laws.friction.FrictionLaw` directly; as a :class:`.base.FormLaw` it gives the
same torque (the registry's test checks it), the reference the other forms are compared with."""
from __future__ import annotations

from ..types import Ops, Scalar
from .base import FrictionForm, hybrid_values, register, FormLaw


def instant(law: FormLaw, w: Scalar, t: Scalar, ops: Ops) -> dict:
    """The hybrid law's values: constant."""
    return hybrid_values(law)


FORM = register(FrictionForm(
    "hybrid", "", "the spec's hybrid law: Karnopp band, linear Stribeck fall from mu_s to mu_k over the Stribeck "
    "velocity, Coulomb mu_k, viscous C_v (w - w_s sign w) (Ahn & Kim 2002, eq. 2-4)", instant))

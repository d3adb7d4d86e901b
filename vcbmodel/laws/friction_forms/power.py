"""A Stribeck fall with a free exponent (the generalised Stribeck curve of Armstrong-Helouvry,
Dupont & Canudas de Wit, Automatica 30, 1994, eq. 5; Bo & Pavelescu, Wear 82, 1982, report
exponents 0.5 to 1 for lubricated journals): in slip, T_f = [mu_k + (mu_s - mu_k) exp(-(|w|/w_s)^d)]
r F_n sign(w) + C_v w, with the hybrid law's stick band and passive stuck state (:mod:`.base`).
d = 1 is Tustin's curve, d = 2 LuGre's steady (Gaussian) one; a fall slower than either (d below 1:
a long tail through the swing's speeds) is in neither. ``stribeck_velocity`` is w_s (rad/s); the
viscous term is not shifted."""
from __future__ import annotations

import math

from ..types import Ops, Scalar
from .base import FormParameter, FrictionForm, register, FormLaw

EXPONENT = FormParameter("stribeck_exponent", 1.0, 0.3, 3.0, "-",
                         "the exponent d of the fall exp(-(|w|/w_s)^d) (1: Tustin, 2: Gaussian)", scan=(0.5,))


def instant(law: FormLaw, w: Scalar, t: Scalar, ops: Ops) -> dict:
    """mu(w) = mu_k + (mu_s - mu_k) exp(-(|w| / w_s)^d) as the kinetic level of the moment (-)."""
    ws = law.stribeck_velocity
    level = law.mu_k
    if ws > 0.0:
        level = law.mu_k + (law.mu_s - law.mu_k) * ops.pow(math.e, -ops.pow(ops.abs(w) / ws, law.value(EXPONENT.name)))
    return {"mu_s": law.mu_s, "mu_k": level, "stribeck_velocity": 0.0, "viscous": law.viscous}


FORM = register(FrictionForm(
    "power", "power_stribeck_friction", "a Stribeck fall with a free exponent, mu_k + (mu_s - mu_k) "
    "exp(-(|w|/w_s)^d), viscous C_v w (Armstrong-Helouvry et al., Automatica 30, 1994)", instant,
    parameters=(EXPONENT,), needs=("stribeck",)))

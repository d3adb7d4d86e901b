"""Tustin's exponential Stribeck curve (Tustin 1947; Armstrong-Helouvry, Dupont & Canudas de Wit,
Automatica 30, 1994): in slip, T_f = [mu_k + (mu_s - mu_k) exp(-|w|/w_s)] r F_n sign(w) + C_v w,
with the hybrid law's stick band and passive stuck state (:mod:`.base`). ``stribeck_velocity`` is
the decay speed w_s (rad/s); the viscous term is not shifted. Without a Stribeck velocity (the
``stribeck`` effect off) the curve is Coulomb's, as the hybrid law's."""
from __future__ import annotations

import math

from ..types import Ops, Scalar
from .base import FrictionForm, register, FormLaw


def instant(law: FormLaw, w: Scalar, t: Scalar, ops: Ops) -> dict:
    """mu(w) = mu_k + (mu_s - mu_k) exp(-|w| / w_s) as the kinetic level of the moment (-)."""
    ws = law.stribeck_velocity
    level = law.mu_k
    if ws > 0.0:
        level = law.mu_k + (law.mu_s - law.mu_k) * ops.pow(math.e, -ops.abs(w) / ws)
    return {"mu_s": law.mu_s, "mu_k": level, "stribeck_velocity": 0.0, "viscous": law.viscous}


FORM = register(FrictionForm(
    "tustin", "tustin_friction", "Tustin's exponential Stribeck curve mu_k + (mu_s - mu_k) exp(-|w|/w_s), viscous "
    "C_v w (Tustin 1947; Armstrong-Helouvry et al., Automatica 30, 1994)", instant, needs=("stribeck",)))

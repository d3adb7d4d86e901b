"""The LuGre model's steady state (Canudas de Wit, Olsson, Astrom & Lischinsky, IEEE TAC 40, 1995):
once the bristles have deflected (micrometres, microseconds at a shaft's speeds) LuGre's friction
is its level function g(w) = mu_k + (mu_s - mu_k) exp(-(w/w_s)^2) (a Gaussian Stribeck curve) plus
C_v w. Here in slip, with the hybrid law's stick band and passive stuck state (:mod:`.base`) in
place of the bristles' pre-sliding. ``stribeck_velocity`` is w_s (rad/s)."""
from __future__ import annotations

import math

from ..types import Ops, Scalar
from .base import FrictionForm, register, FormLaw


def instant(law: FormLaw, w: Scalar, t: Scalar, ops: Ops) -> dict:
    """g(w) = mu_k + (mu_s - mu_k) exp(-(w / w_s)^2) as the kinetic level of the moment (-)."""
    ws = law.stribeck_velocity
    level = law.mu_k
    if ws > 0.0:
        x = w / ws
        level = law.mu_k + (law.mu_s - law.mu_k) * ops.pow(math.e, -(x * x))
    return {"mu_s": law.mu_s, "mu_k": level, "stribeck_velocity": 0.0, "viscous": law.viscous}


FORM = register(FrictionForm(
    "gaussian", "lugre_steady_friction", "the LuGre model's steady state: a Gaussian Stribeck curve mu_k + "
    "(mu_s - mu_k) exp(-(w/w_s)^2), viscous C_v w (Canudas de Wit et al., IEEE TAC 40, 1995)", instant,
    needs=("stribeck",)))

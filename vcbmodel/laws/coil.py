"""Helical-spring formulas for the closing spring's continuum model (ANCF).

The equivalent bending stiffness of a helical spring (Timoshenko & Gere, Theory of Elastic
Stability, sec. 2.19): ``EI_eq = 2 E I_w L / (pi n_a D (2 + nu))`` with wire second moment
I_w = pi d^4 / 64, mean coil diameter D, active coils n_a (from k0 = G d^4 / (8 D^3 n_a) if
not given), length L and nu = E / (2 G) - 1.
"""
from __future__ import annotations

import math

from .. import parameters as P


def coil_bending_stiffness(spring):
    """Equivalent bending stiffness EI_eq (N m^2) of one helical spring (module docstring).

    ``spring`` has ``stiffness`` (N/m), ``free_length`` (m) and optional ``wire_diameter``,
    ``coil_diameter`` (m), ``active_coils``, ``shear_modulus`` (Pa); missing ones take the
    documented defaults of :mod:`vcbmodel.parameters`.
    """
    d = spring.wire_diameter or P.DEFAULT_WIRE_DIAMETER
    D = spring.coil_diameter or P.DEFAULT_COIL_DIAMETER
    G = spring.shear_modulus or P.DEFAULT_SHEAR_MODULUS
    E = P.DEFAULT_YOUNGS_MODULUS
    n_active = spring.active_coils or G * d**4 / (8 * D**3 * spring.stiffness)
    nu = E / (2 * G) - 1
    I_w = math.pi * d**4 / 64
    return 2 * E * I_w * spring.free_length / (math.pi * n_active * D * (2 + nu))

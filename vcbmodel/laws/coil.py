"""Helical-spring formulas for the closing spring's continuum model (ANCF).

Geometry (Wahl, Mechanical Springs, 1963; Shigley, Mechanical Engineering Design, ch. 10): wire
diameter d, mean coil diameter D, active coils n_a, spring index C = D/d;
k0 = G d^4 / (8 D^3 n_a) and the active coils' mass m0 = rho (pi d^2 / 4) pi D n_a. Given k0, m0
and C, d^4 = 32 C^2 k0 m0 / (rho pi^2 G). Shear stress under a force F with Wahl's correction:
tau = K_W 8 F D / (pi d^3), K_W = (4C - 1)/(4C - 4) + 0.615/C.

Equivalent beam of the coil (Timoshenko & Gere, Theory of Elastic Stability, sec. 2.20;
Haringx, Philips Res. Rep. 3-4, 1948-49): bending stiffness EI_eq = 2 E I_w L / (pi n_a D (2 + nu))
and shear stiffness GA_eq = 8 E I_w L / (pi n_a D^3) = (E/G) k0 L, with wire second moment
I_w = pi d^4 / 64, length L and nu = E / (2 G) - 1. Exudyn's cable takes curvature per reference
(free) length, so its EI input is the free-length value.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .. import parameters as P


@dataclass(frozen=True)
class CoilGeometry:
    wire_diameter: float  # d (m)
    coil_diameter: float  # D (m), mean
    active_coils: float  # n_a
    shear_modulus: float  # G (Pa)

    @property
    def index(self):
        return self.coil_diameter / self.wire_diameter

    def wahl_factor(self):
        c = self.index
        return (4 * c - 1) / (4 * c - 4) + 0.615 / c

    def shear_stress(self, force):
        """Wahl-corrected shear stress (Pa) of the wire under an axial force (N)."""
        return self.wahl_factor() * 8 * force * self.coil_diameter / (math.pi * self.wire_diameter**3)

    def mass(self):
        """Mass (kg) of the active coils."""
        return P.STEEL_DENSITY * math.pi * self.wire_diameter**2 / 4 * math.pi * self.coil_diameter * self.active_coils


def coil_geometry(spring):
    """The coil of one spring (``stiffness`` k0 N/m, ``mass`` m0 kg): the rig's wire and coil
    diameters when given, else derived from k0 and m0 at SPRING_INDEX (module docstring);
    active coils from k0 unless given."""
    G = spring.shear_modulus or P.DEFAULT_SHEAR_MODULUS
    d, D = spring.wire_diameter, spring.coil_diameter
    if d is None and D is None:
        d = (32 * P.SPRING_INDEX**2 * spring.stiffness * spring.mass / (P.STEEL_DENSITY * math.pi**2 * G)) ** 0.25
        D = P.SPRING_INDEX * d
    elif d is None:
        d = D / P.SPRING_INDEX
    elif D is None:
        D = P.SPRING_INDEX * d
    n_active = spring.active_coils or G * d**4 / (8 * D**3 * spring.stiffness)
    return CoilGeometry(d, D, n_active, G)


def coil_bending_stiffness(spring):
    """Equivalent bending stiffness EI_eq (N m^2) of one helical spring at its free length."""
    g = coil_geometry(spring)
    E = P.DEFAULT_YOUNGS_MODULUS
    nu = E / (2 * g.shear_modulus) - 1
    I_w = math.pi * g.wire_diameter**4 / 64
    return 2 * E * I_w * spring.free_length / (math.pi * g.active_coils * g.coil_diameter * (2 + nu))


def coil_shear_stiffness(spring, length):
    """Equivalent shear stiffness GA_eq (N) of one spring at ``length`` (m): (E/G) k0 L (Haringx)."""
    G = spring.shear_modulus or P.DEFAULT_SHEAR_MODULUS
    return P.DEFAULT_YOUNGS_MODULUS / G * spring.stiffness * length

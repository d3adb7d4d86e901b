"""Helical-spring formulas: the closing spring from its datasheet, its stress and strength, and
its continuum model (ANCF).

Geometry (Wahl, Mechanical Springs, 1963; Shigley, Mechanical Engineering Design, ch. 10): wire
diameter d, mean coil diameter D, active coils n_a, spring index C = D/d;
k0 = G d^4 / (8 D^3 n_a) and the active coils' mass m0 = rho (pi d^2 / 4) pi D n_a. Given k0, m0
and C, d^4 = 32 C^2 k0 m0 / (rho pi^2 G). Shear stress under a force F with Wahl's correction:
tau = K_W 8 F D / (pi d^3), K_W = (4C - 1)/(4C - 4) + 0.615/C.

Datasheet (a spring maker's catalogue or drawing gives d, D, n_a, G and the free length): k0 and
the active coils' mass follow from the formulas above, the surge (first fixed-fixed axial)
frequency is f1 = (1/2) sqrt(k0 / m0) (Wahl ch. 25), and the wire's strength is Shigley's
S_ut = A / d^m (Table 10-4; d in mm, S_ut in MPa): A = 2005, m = 0.108 for oil-tempered
chromium-silicon wire (ASTM A401), A = 2211, m = 0.145 for music wire (A228). Shigley's allowable
static torsional stress in an extension spring's body is 0.45 S_ut (Table 10-7; 0.65 S_ut for
compression springs with set removed, Table 10-6).

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
    def index(self) -> float:
        return self.coil_diameter / self.wire_diameter

    def wahl_factor(self) -> float:
        c = self.index
        return (4 * c - 1) / (4 * c - 4) + 0.615 / c

    def shear_stress(self, force: float) -> float:
        """Wahl-corrected shear stress (Pa) of the wire under an axial force (N)."""
        return self.wahl_factor() * 8 * force * self.coil_diameter / (math.pi * self.wire_diameter**3)

    def mass(self) -> float:
        """Mass (kg) of the active coils."""
        return P.STEEL_DENSITY * math.pi * self.wire_diameter**2 / 4 * math.pi * self.coil_diameter * self.active_coils


#: Shigley's wire strength S_ut = A / d^m (Table 10-4): {wire: (A in MPa mm^m, m)}
WIRE_STRENGTH = {"chromium_silicon": (2005.0, 0.108), "music_wire": (2211.0, 0.145)}
#: Allowable static torsional stress of an extension spring's body, as a fraction of S_ut (Shigley Table 10-7)
EXTENSION_BODY_FRACTION = 0.45
#: The same for a compression spring with set removed (Shigley Table 10-6: hardened and tempered alloy steel)
COMPRESSION_SET_REMOVED_FRACTION = 0.65


def coil_stiffness(wire_diameter: float, coil_diameter: float, active_coils: float, shear_modulus: float) -> float:
    """k0 (N/m) = G d^4 / (8 D^3 n_a) of a helical spring (d, D in m; G in Pa)."""
    return shear_modulus * wire_diameter**4 / (8.0 * coil_diameter**3 * active_coils)


def coil_mass(wire_diameter: float, coil_diameter: float, active_coils: float, density: float) -> float:
    """Mass (kg) of the active coils: rho (pi d^2 / 4) pi D n_a (density in kg/m^3)."""
    return density * math.pi * wire_diameter**2 / 4.0 * math.pi * coil_diameter * active_coils


def surge_frequency(stiffness: float, mass: float) -> float:
    """First axial natural frequency (Hz) of a spring fixed at both ends: (1/2) sqrt(k0/m0)."""
    return 0.5 * math.sqrt(stiffness / mass)


def wire_strength(wire_diameter: float, wire: str = "chromium_silicon") -> float:
    """Ultimate tensile strength S_ut (Pa) of spring wire of diameter d (m): Shigley's A / d^m."""
    a, m = WIRE_STRENGTH[wire]
    return a / (1000.0 * wire_diameter) ** m * 1e6


def shear_stress_at_index(force: float, stiffness: float, mass: float, index: float, shear_modulus: float = P.DEFAULT_SHEAR_MODULUS,
                          density: float = P.STEEL_DENSITY) -> float:
    """Wahl-corrected shear stress (Pa) of the lightest coil with stiffness k0 (N/m), active mass
    m0 (kg) and spring index C that carries ``force`` (N): with d^4 = 32 C^2 k0 m0 / (rho pi^2 G),
    tau = K_W 8 F C / (pi d^2), nearly independent of C (it scales with F / sqrt(k0 m0))."""
    d = (32.0 * index**2 * stiffness * mass / (density * math.pi**2 * shear_modulus)) ** 0.25
    return CoilGeometry(d, index * d, 1.0, shear_modulus).shear_stress(force)


def coil_geometry(spring) -> CoilGeometry:
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


def coil_bending_stiffness(spring) -> float:
    """Equivalent bending stiffness EI_eq (N m^2) of one helical spring at its free length."""
    g = coil_geometry(spring)
    E = P.DEFAULT_YOUNGS_MODULUS
    nu = E / (2 * g.shear_modulus) - 1
    I_w = math.pi * g.wire_diameter**4 / 64
    return 2 * E * I_w * spring.free_length / (math.pi * g.active_coils * g.coil_diameter * (2 + nu))


def coil_shear_stiffness(spring, length: float) -> float:
    """Equivalent shear stiffness GA_eq (N) of one spring at ``length`` (m): (E/G) k0 L (Haringx)."""
    G = spring.shear_modulus or P.DEFAULT_SHEAR_MODULUS
    return P.DEFAULT_YOUNGS_MODULUS / G * spring.stiffness * length


def spring_check(spring, charged_force: float, wire: str = "chromium_silicon") -> dict[str, float | bool]:
    """What a designer checks of one closing spring charged to ``charged_force`` (N): k0 (N/m), the
    active mass m0 (kg), the surge frequency (Hz), the wire's shear stress (Pa) there (the coil of
    the rig's datasheet, or of :func:`coil_geometry`'s default index), the wire's strength S_ut
    and Shigley's allowable 0.45 S_ut for an extension spring's body (Pa), and their ratio; and
    0.65 S_ut, a compression spring's with set removed (the same coil used in compression)."""
    g = coil_geometry(spring)
    tau = g.shear_stress(charged_force)
    strength = wire_strength(g.wire_diameter, wire)
    allowable = EXTENSION_BODY_FRACTION * strength
    return {"stiffness_N_m": spring.stiffness, "mass_kg": spring.mass,
            "surge_frequency_hz": surge_frequency(spring.stiffness, spring.mass),
            "charged_force_N": charged_force, "wire_diameter_m": g.wire_diameter, "coil_diameter_m": g.coil_diameter,
            "shear_stress_Pa": tau, "allowable_Pa": allowable, "stress_ratio": tau / allowable,
            "allowable_compression_Pa": COMPRESSION_SET_REMOVED_FRACTION * strength,
            "coil_given": spring.wire_diameter is not None and spring.coil_diameter is not None}

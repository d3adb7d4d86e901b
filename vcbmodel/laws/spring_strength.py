"""A closing spring checked the way a spring maker would: body, hooks, initial tension, fatigue.

The closing spring is an extension (tension) spring (parameters.py, "spring strength"). A helical
extension spring of wire diameter d, mean coil diameter D (index C = D/d) pulled with F (Shigley,
Mechanical Engineering Design, sec. 10-11; EN 13906-2 uses the same stresses):

- body, torsion with Bergstrasser's factor K_B = (4C + 2) / (4C - 3): tau = K_B 8 F D / (pi d^3);
- hook at A (where the end loop bends up; mean radius r1, C1 = 2 r1 / d, C for a standard hook),
  bending with the curved-beam factor (K)_A = (4 C1^2 - C1 - 1) / (4 C1 (C1 - 1)):
  sigma_A = F ((K)_A 16 D / (pi d^3) + 4 / (pi d^2));
- hook at B (the bend from the body into the loop, r2, C2 = 2 r2 / d), torsion with
  (K)_B = (4 C2 - 1) / (4 C2 - 4): tau_B = (K)_B 8 F D / (pi d^3);
- initial tension: the preferred range of the uncorrected stress tau_i (parameters
  INITIAL_TENSION_STRESS, Shigley eq. 10-39), F_i = tau_i pi d^3 / (8 D);
- fatigue over N operations, each a cycle from F_min to F_max: Goodman's line through the
  R = 0 strength S_r of Shigley Table 10-8 (S_a = S_m = S_r / 2) and the ultimate (S_ut in bending,
  S_su = 0.67 S_ut in torsion): S_e = (S_r / 2) / (1 - S_r / (2 S_u)) and the factor of safety
  n_f = 1 / (s_a / S_e + s_m / S_u) (Shigley Example 10-7's method);
- the same coil read as a compression spring (a reading the paper's "인장" rules out, kept to show
  what it would take): body stress against 0.65 S_ut (set removed), and buckling: the critical
  deflection y_cr = L0 C1' (1 - sqrt(1 - C2' / lambda^2)), lambda = alpha L0 / D,
  C1' = E / (2 (E - G)), C2' = 2 pi^2 (E - G) / (2 G + E) (Shigley eq. 10-10, 10-11).

Units: SI (m, N, Pa). Material fractions and the rated operations are in parameters.py with their
sources; S_ut is :func:`vcbmodel.laws.coil.wire_strength`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .. import parameters as P
from .coil import coil_stiffness, coil_mass, wire_strength
from .mechanics import cam_pin


def bergstrasser_factor(index: float) -> float:
    """K_B = (4C + 2) / (4C - 3) (-): the body's curvature and direct-shear correction."""
    return (4.0 * index + 2.0) / (4.0 * index - 3.0)


def body_stress(force: float, wire: float, coil: float) -> float:
    """Shear stress (Pa) in the body of a spring pulled with ``force`` (N): K_B 8 F D / (pi d^3), d and D in m."""
    return bergstrasser_factor(coil / wire) * 8.0 * force * coil / (math.pi * wire**3)


def hook_bending_stress(force: float, wire: float, coil: float, bend_index: float | None = None) -> float:
    """Bending stress (Pa) at the hook's point A (Shigley eq. 10-34): F ((K)_A 16 D / (pi d^3) + 4 / (pi d^2)),
    (K)_A = (4 C1^2 - C1 - 1) / (4 C1 (C1 - 1)); ``bend_index`` C1 = 2 r1 / d, the spring index (a
    standard hook) when None."""
    c1 = coil / wire if bend_index is None else bend_index
    k_a = (4.0 * c1 * c1 - c1 - 1.0) / (4.0 * c1 * (c1 - 1.0))
    return force * (k_a * 16.0 * coil / (math.pi * wire**3) + 4.0 / (math.pi * wire**2))


def hook_torsion_stress(force: float, wire: float, coil: float, bend_index: float = P.HOOK_BEND_INDEX) -> float:
    """Torsional stress (Pa) at the hook's point B (Shigley eq. 10-35): (K)_B 8 F D / (pi d^3),
    (K)_B = (4 C2 - 1) / (4 C2 - 4), ``bend_index`` C2 = 2 r2 / d."""
    k_b = (4.0 * bend_index - 1.0) / (4.0 * bend_index - 4.0)
    return k_b * 8.0 * force * coil / (math.pi * wire**3)


def initial_tension_range(wire: float, coil: float) -> tuple[float, float]:
    """(lowest, highest) preferred initial tension (N) of an extension spring wound from wire ``wire``
    on a mean diameter ``coil`` (m): tau_i pi d^3 / (8 D) over Shigley's range of tau_i (parameters)."""
    a, b, c = P.INITIAL_TENSION_STRESS
    index = coil / wire
    centre, half = a / math.exp(b * index), c * (4.0 - (index - 3.0) / 6.5)
    per_pa = math.pi * wire**3 / (8.0 * coil)
    return (centre - half) * 1e6 * per_pa, (centre + half) * 1e6 * per_pa


def fatigue_fractions(operations: float) -> tuple[float, float, float]:
    """Shigley Table 10-8's R = 0 strengths (body torsion, hook torsion, hook bending) as fractions of
    S_ut at ``operations`` cycles: the table's row at or above it, its first row below 1e5 (conservative),
    interpolated in log N between rows."""
    rows = sorted(P.EXTENSION_FATIGUE.items())
    if operations <= rows[0][0]:
        return rows[0][1]
    for (n0, f0), (n1, f1) in zip(rows[:-1], rows[1:]):
        if operations <= n1:
            w = math.log(operations / n0) / math.log(n1 / n0)
            return tuple(a + w * (b - a) for a, b in zip(f0, f1))
    return rows[-1][1]


def goodman_factor(high: float, low: float, zero_based_strength: float, ultimate: float) -> float:
    """Fatigue factor of safety (-) of a stress cycling between ``low`` and ``high`` (Pa) on Goodman's line
    through the R = 0 strength S_r (``zero_based_strength``, Pa) and the ultimate S_u (Pa):
    S_e = (S_r/2) / (1 - S_r / (2 S_u)), n_f = 1 / (s_a / S_e + s_m / S_u)."""
    half = 0.5 * zero_based_strength
    endurance = half / (1.0 - half / ultimate)
    amplitude, mean = 0.5 * (high - low), 0.5 * (high + low)
    return 1.0 / (amplitude / endurance + mean / ultimate)


@dataclass(frozen=True)
class Check:
    """One line of a spring maker's check: the stress (Pa) against its allowable (Pa), or a fatigue factor
    of safety (-) against 1; ``source`` names where the allowable comes from."""

    name: str
    value: float
    allowable: float
    unit: str
    source: str
    #: True for a maker's preference rather than a strength limit: not passing it asks for something to
    #: be specified on the drawing (an initial tension below the preferred range), it does not fail the spring
    advisory: bool = False

    @property
    def ratio(self) -> float:
        """value / allowable for a stress or force (<= 1 passes); 1 / factor for a fatigue factor of
        safety (unit "-", <= 1 passes)."""
        return self.allowable / self.value if self.unit == "-" else self.value / self.allowable

    @property
    def passes(self) -> bool:
        return self.ratio <= 1.0

    @property
    def fails(self) -> bool:
        """Not passing a strength limit (an advisory check that does not pass asks for a specification)."""
        return not self.passes and not self.advisory


#: The checks of :func:`extension_checks` on the body alone: an extension spring whose ends are
#: screwed-in plugs or swivel inserts (no bent hook) has no hook stresses.
BODY_CHECKS = ("body torsion", "body fatigue")


def extension_checks(wire: float, coil: float, high: float, low: float, operations: float = P.RATED_OPERATIONS,
                     material: str = P.SPRING_WIRE, hooks: bool = True) -> list[Check]:
    """Every check of an extension spring (d ``wire``, D ``coil`` in m) that cycles between ``low`` and
    ``high`` pulls (N) ``operations`` times: static body, hook bending and hook torsion (Shigley Table
    10-7), their fatigue (Table 10-8 with Goodman) and whether the smallest pull keeps the coils apart
    (``low`` at least the lowest preferred initial tension, :func:`initial_tension_range`: advisory, a
    maker's preference; an initial tension below it can be specified). ``hooks`` False: ends with no bent
    hook (screwed-in plugs), the body's checks (:data:`BODY_CHECKS`) and the advisory one."""
    s_ut = wire_strength(wire, material)
    s_su = P.SHEAR_ULTIMATE_FRACTION * s_ut
    a = P.EXTENSION_ALLOWABLE
    body, bend, twist = (body_stress(high, wire, coil), hook_bending_stress(high, wire, coil),
                         hook_torsion_stress(high, wire, coil))
    body_low, bend_low, twist_low = (body_stress(low, wire, coil), hook_bending_stress(low, wire, coil),
                                     hook_torsion_stress(low, wire, coil))
    f_body, f_twist, f_bend = fatigue_fractions(operations)
    table = "Shigley Table 10-7"
    life = f"Shigley Table 10-8 at {operations:.0f} cycles, Goodman"
    initial = initial_tension_range(wire, coil)[0]
    checks = [Check("body torsion", body, a["body_torsion"] * s_ut, "Pa", f"{a['body_torsion']:.2f} S_ut, {table}"),
              Check("hook bending (A)", bend, a["hook_bending"] * s_ut, "Pa", f"{a['hook_bending']:.2f} S_ut, {table}"),
              Check(f"hook torsion (B, C2 = {P.HOOK_BEND_INDEX:g})", twist, a["hook_torsion"] * s_ut, "Pa",
                    f"{a['hook_torsion']:.2f} S_ut, {table}"),
              Check("body fatigue", goodman_factor(body, body_low, f_body * s_ut, s_su), 1.0, "-", life),
              Check("hook bending fatigue", goodman_factor(bend, bend_low, f_bend * s_ut, s_ut), 1.0, "-", life),
              Check("hook torsion fatigue", goodman_factor(twist, twist_low, f_twist * s_ut, s_su), 1.0, "-", life),
              Check("lowest preferred initial tension vs the smallest pull", initial, low, "N",
                    "Shigley eq. 10-39's preferred range, the easiest to hold in winding; below its initial tension "
                    "the coils close and the spring goes slack, so one below the range must be specified on the drawing",
                    advisory=True)]
    return checks if hooks else [c for c in checks if c.advisory or c.name in BODY_CHECKS]


def critical_deflection(free_length: float, coil: float, end: str = "fixed-fixed",
                        youngs: float = P.DEFAULT_YOUNGS_MODULUS, shear: float = P.DEFAULT_SHEAR_MODULUS) -> float:
    """Deflection (m) at which a compression spring of free length ``free_length`` and mean diameter
    ``coil`` (m) buckles (Shigley eq. 10-10); inf when it is absolutely stable (C2' / lambda^2 >= 1)."""
    lam = P.BUCKLING_END_CONSTANTS[end] * free_length / coil
    c1 = youngs / (2.0 * (youngs - shear))
    c2 = 2.0 * math.pi**2 * (youngs - shear) / (2.0 * shear + youngs)
    if c2 / lam**2 >= 1.0:
        return math.inf
    return free_length * c1 * (1.0 - math.sqrt(1.0 - c2 / lam**2))


def compression_reading(wire: float, coil: float, active_coils: float, stiffness: float, high: float,
                        material: str = P.SPRING_WIRE) -> dict[str, float]:
    """The same coil as a compression spring compressed to ``high`` (N): its body stress against
    0.65 S_ut (Pa), free length (m: solid (n_a + 2) d plus the largest deflection and its clash
    allowance), the largest deflection over the free length y/L0 (-) and the critical deflection
    (m) for each end condition (keys ``buckles_at_<end>``)."""
    deflection = high / stiffness
    free = (active_coils + 2.0) * wire + (1.0 + P.CLASH_ALLOWANCE) * deflection
    out = {"body_stress_Pa": body_stress(high, wire, coil),
           "allowable_Pa": P.COMPRESSION_ALLOWABLE * wire_strength(wire, material),
           "free_length_m": free, "deflection_m": deflection, "deflection_ratio": deflection / free}
    for end in P.BUCKLING_END_CONSTANTS:
        out[f"buckles_at_{end}_m"] = critical_deflection(free, coil, end)
    return out


def wire_for_index(index: float, stiffness: float, high: float, low: float, operations: float = P.RATED_OPERATIONS,
                   material: str = P.SPRING_WIRE, hooks: bool = True) -> dict[str, float]:
    """The thinnest wire (m) at spring index ``index`` whose extension spring of rate ``stiffness``
    (N/m) passes every stress and fatigue check of :func:`extension_checks` cycling between ``low`` and
    ``high`` (N) (``hooks`` False: the body's only, :data:`BODY_CHECKS`), by bisection on d (each
    check's ratio falls as d grows); with its coil diameter (m), active coils
    (k0 = G d^4 / (8 D^3 n_a)) and active mass (kg)."""
    def worst(d):
        checks = extension_checks(d, index * d, high, low, operations, material, hooks)
        return max(c.ratio for c in checks if not c.advisory)

    lo, hi = 1e-4, 0.1
    if worst(hi) > 1.0:
        raise ValueError(f"no wire up to {hi} m carries {high:g} N at index {index:g}")
    for _ in range(80):
        mid = math.sqrt(lo * hi)
        lo, hi = (lo, mid) if worst(mid) <= 1.0 else (mid, hi)
    d = hi
    coils = P.DEFAULT_SHEAR_MODULUS * d**4 / (8.0 * (index * d) ** 3 * stiffness)
    return {"index": index, "wire_diameter_m": d, "coil_diameter_m": index * d, "active_coils": coils,
            "mass_kg": coil_mass(d, index * d, coils, P.STEEL_DENSITY),
            "stiffness_N_m": coil_stiffness(d, index * d, coils, P.DEFAULT_SHEAR_MODULUS)}


def lightest_buildable(stiffness: float, high: float, low: float, indices=(4.0, 5.0, 6.0, 7.0, 8.0, 10.0, 12.0),
                       operations: float = P.RATED_OPERATIONS, material: str = P.SPRING_WIRE,
                       hooks: bool = True) -> dict[str, float]:
    """The lightest extension spring of rate ``stiffness`` (N/m) over the spring indices ``indices``
    (Shigley's preferred 4-12) that passes every check at ``high``/``low`` pulls (N) (``hooks`` as
    :func:`wire_for_index`'s): :func:`wire_for_index`'s numbers of the lightest."""
    return min((wire_for_index(c, stiffness, high, low, operations, material, hooks) for c in indices),
               key=lambda s: s["mass_kg"])


def closing_pulls(spring, cam) -> tuple[float, float]:
    """(charged, smallest) pull (N) of one closing spring (``stiffness`` N/m, ``free_length`` m,
    ``anchor``) on the cam's pin B: at the cam's initial angle, and at the springs' dead centre
    (B between the anchor O and the cam axis A: |OB| = |OA| - l_AB, the shortest over a turn), the
    range one closing cycles it through."""
    bx, by = cam_pin(cam.initial_angle, cam)
    ox, oy = spring.anchor
    charged = spring.stiffness * (math.hypot(bx - ox, by - oy) - spring.free_length)
    shortest = math.hypot(cam.pivot[0] - ox, cam.pivot[1] - oy) - cam.arm_length
    return charged, spring.stiffness * (shortest - spring.free_length)

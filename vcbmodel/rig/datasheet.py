"""A closing spring's datasheet fields (``closing_spring.wire_diameter``, ``coil_diameter``,
``shear_modulus``, ``density``) checked for the unit slips a datasheet invites: millimetres for
metres, GPa for Pa, g/cm^3 for kg/m^3, and an outer diameter or a typo that no spring maker could
wind (the spring index D/d). The rate k0 = G d^4 / (8 D^3 n_a) goes with d^4 / D^3, so such a slip
gives a spring millions of times off that still simulates: each is refused with one line."""
from __future__ import annotations

from .. import parameters as P
from .reader import Reader

#: field: (lowest, highest, unit, what a value outside most likely is)
LIMITS = {
    "wire_diameter": (0.0, P.SPRING_WIRE_LARGEST, "m", "in millimetres? lengths are in m"),
    "coil_diameter": (0.0, P.SPRING_COIL_LARGEST, "m", "in millimetres? lengths are in m"),
    "shear_modulus": (*P.SPRING_SHEAR_MODULUS_RANGE, "Pa", "in GPa? give Pa (steel 79.3e9)"),
    "density": (*P.SPRING_DENSITY_RANGE, "kg/m^3", "in g/cm^3? give kg/m^3 (steel 7850)"),
}


def check_datasheet(rd: Reader, coil: dict[str, float]) -> None:
    """Refuse a datasheet value outside what a breaker's closing spring can have (``LIMITS``), and a
    spring index D/d outside ``SPRING_INDEX_RANGE``, naming the field."""
    for key, (low, high, unit, hint) in LIMITS.items():
        if key in coil and not low < coil[key] <= high:
            rd.fail(f"closing_spring.{key}", f"{coil[key]:g} {unit} is outside {low:g}-{high:g} {unit}, the range of a "
                    f"closing spring's {key.replace('_', ' ')}: {hint}")
    if "wire_diameter" in coil and "coil_diameter" in coil:
        index = coil["coil_diameter"] / coil["wire_diameter"]
        low, high = P.SPRING_INDEX_RANGE
        if not low <= index <= high:
            rd.fail("closing_spring.coil_diameter", f"gives a spring index D/d of {index:.3g}, outside the {low:g}-{high:g} "
                    "that springs are wound with: coil_diameter is the MEAN coil diameter (outer less one wire), in m")

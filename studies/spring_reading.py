"""Which closing spring did the paper describe? Its readings checked against its own numbers and
against buildability: writes results/spring_reading.md and .json.

The paper gives k0 = 24230 N/m, m0 = 0.3364 kg and f0 = 85.83 Hz (eq. 8), says each spring is
heavy (about 1 kg) and that the closing springs' force falls from 6000 N to 1000 N (section 1;
eq. 11 carries a factor 2 for the pair). For each reading of m0 (the spring's whole active mass,
eq. 8's lumped-chain parameter, or a one-third effective mass) and of the force (each spring, or
the pair), this reports the spring's active mass, its first fixed-fixed frequency against the
paper's f0, the wire's shear stress in the lightest coil of that rate and mass at the charged pull,
against Shigley's allowable stresses for chromium-silicon wire of that size, and the energy the
pair releases from 6000 N to 1000 N.
"""
import math
from pathlib import Path

from _common import markdown_table, parse_args, write_json

from vcbmodel.laws.coil import (COMPRESSION_SET_REMOVED_FRACTION, EXTENSION_BODY_FRACTION, shear_stress_at_index,
                                surge_frequency, wire_strength)
from vcbmodel import parameters as P

K0, M0, F0_PAPER = 24230.0, 0.3364, 85.83
CHARGED, RELEASED = 6000.0, 1000.0  # N, the paper's closing springs' force at start and end
INDEX = 6.0  # spring index C = D/d of the coil sized here (closing springs: 5-8)
F0_MATCH = 0.01  # a reading "reproduces" the paper's f0 when its fundamental is within this fraction of it

READINGS = (
    ("m0 is the whole active mass; 6000 N each", M0, 1),
    ("m0 is the whole active mass; 6000 N for the pair", M0, 2),
    ("m0 is eq. 8's chain parameter (mass pi^2/4 m0); 6000 N each", math.pi**2 / 4 * M0, 1),
    ("m0 is eq. 8's chain parameter (mass pi^2/4 m0); 6000 N for the pair", math.pi**2 / 4 * M0, 2),
    ("m0 is a one-third effective mass (mass 3 m0); 6000 N for the pair", 3 * M0, 2),
)


def reading(label, mass, share):
    force = CHARGED / share  # N on one spring, charged
    d = (32.0 * INDEX**2 * K0 * mass / (P.STEEL_DENSITY * math.pi**2 * P.DEFAULT_SHEAR_MODULUS)) ** 0.25
    tau = shear_stress_at_index(force, K0, mass, INDEX)
    strength = wire_strength(d)
    energy = 2 * (force**2 - (RELEASED / share) ** 2) / (2 * K0)  # J, both springs
    return {"reading": label, "active_mass_kg": mass, "force_per_spring_N": force,
            "fixed_fixed_frequency_hz": surge_frequency(K0, mass), "wire_diameter_m": d,
            "shear_stress_Pa": tau, "allowable_extension_Pa": EXTENSION_BODY_FRACTION * strength,
            "allowable_compression_set_removed_Pa": COMPRESSION_SET_REMOVED_FRACTION * strength,
            "pair_energy_6000_to_1000_N_J": energy}


def conclusion(rows):
    """The page's reading of the table, every number from ``rows`` and each claim only where it holds."""
    chain = [r for r in rows if "chain parameter" in r["reading"]]
    near = {round(r["active_mass_kg"], 6) for r in rows
            if abs(r["fixed_fixed_frequency_hz"] / F0_PAPER - 1) < F0_MATCH}
    each = [r for r in rows if r["force_per_spring_N"] == CHARGED]
    pair = [r for r in chain if r["force_per_spring_N"] == CHARGED / 2]
    f_chain, m_chain = chain[0]["fixed_fixed_frequency_hz"], chain[0]["active_mass_kg"]
    text = ((f"Only m0 as eq. 8's chain parameter reproduces the paper's f0 (within {100 * F0_MATCH:g} %): its"
             if near == {round(m_chain, 6)} else
             f"The paper's f0 does not single out one reading (within {100 * F0_MATCH:g} %); with m0 as eq. 8's "
             "chain parameter, the spring's")
            + f" fixed-fixed continuum's fundamental is {f_chain:.1f} Hz, as the paper's eq. 8 chain "
            f"(w1 = 2 sqrt(k0/m0)), and its mass is {m_chain:.2f} kg (the text's \"about 1 kg\"). ")
    stress = [r["shear_stress_Pa"] / 1e9 for r in each]
    over = all(r["shear_stress_Pa"] > r["allowable_compression_set_removed_Pa"] for r in each)
    text += (f"Read with {CHARGED:g} N on each spring, the wire sees {min(stress):.2f}-{max(stress):.2f} GPa, "
             + ("above even a preset compression spring's allowable: no steel coil of this rate and mass carries "
                "the pull" if over else "not above every allowable") + "; ")
    r = pair[0]
    ratio = r["shear_stress_Pa"] / r["allowable_compression_set_removed_Pa"]
    text += (f"with {CHARGED:g} N for the pair the chain reading's coil runs at {ratio:.2f} of the allowable stress "
             f"of a preset compression spring and the pair releases {r['pair_energy_6000_to_1000_N_J']:.0f} J, not "
             f"{each[0]['pair_energy_6000_to_1000_N_J']:.0f} J.\n")
    return text


def main():
    args = parse_args(__doc__)
    rows = [reading(*r) for r in READINGS]
    write_json(f"{args.out}/spring_reading.json", {"k0_N_m": K0, "m0_kg": M0, "f0_paper_hz": F0_PAPER,
                                                    "spring_index": INDEX, "readings": rows})
    table = markdown_table(
        ["reading", "active mass (kg)", f"f1 fixed-fixed (Hz; paper f0 {F0_PAPER:g})", "pull per spring (N)",
         f"wire (mm, C = {INDEX:g})", "shear stress (GPa)",
         f"{EXTENSION_BODY_FRACTION:g} / {COMPRESSION_SET_REMOVED_FRACTION:g} S_ut (GPa)", "pair releases (J)"],
        [[r["reading"], f"{r['active_mass_kg']:.3f}", f"{r['fixed_fixed_frequency_hz']:.1f}",
          f"{r['force_per_spring_N']:.0f}", f"{1e3 * r['wire_diameter_m']:.2f}", f"{r['shear_stress_Pa'] / 1e9:.2f}",
          f"{r['allowable_extension_Pa'] / 1e9:.2f} / {r['allowable_compression_set_removed_Pa'] / 1e9:.2f}",
          f"{r['pair_energy_6000_to_1000_N_J']:.0f}"] for r in rows])
    text = ("# The paper's closing spring: which reading is a spring that exists\n\n"
            f"Generated by `studies/spring_reading.py`. k0 = {K0:g} N/m and m0 = {M0:g} kg are the paper's (eq. 8); "
            f"the stress is that of the lightest coil of this rate and mass at spring index {INDEX:g} (Wahl-corrected; it "
            "barely depends on the index: it scales as F / sqrt(k0 m)); S_ut of chromium-silicon wire (ASTM A401) "
            f"from Shigley Table 10-4; {EXTENSION_BODY_FRACTION:g} S_ut is the static allowable of an extension spring's "
            f"body (Table 10-7), {COMPRESSION_SET_REMOVED_FRACTION:g} S_ut that of a compression spring with set removed "
            "(Table 10-6).\n\n" + table + "\n" + conclusion(rows))
    Path(args.out, "spring_reading.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()

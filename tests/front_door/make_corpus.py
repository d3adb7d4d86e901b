"""Writes the front-door bad-input corpus (the files next to this script).

Run once from anywhere: ``python tests/front_door/make_corpus.py``. The outputs are committed,
binary and UTF-16 files included, so the tests never depend on this script; it is kept so the
corpus can be regenerated or extended. Everything is derived from the known-good files in
``tests/bad_rigs/`` (``good_cam.rig.json``, ``good_pendulum.rig.json``, ``good.csv``) and, for the
whole breaker, from ``results/synthetic/vcb_closing.rig.json``. Only the standard library is used,
and the output is deterministic (fixed seeds).
"""
import copy
import json
import math
import random
from pathlib import Path

HERE = Path(__file__).resolve().parent
TESTS = HERE.parent
ROOT = TESTS.parent
GOOD_CAM = json.loads((TESTS / "bad_rigs" / "good_cam.rig.json").read_text(encoding="utf-8"))
GOOD_PENDULUM = json.loads((TESTS / "bad_rigs" / "good_pendulum.rig.json").read_text(encoding="utf-8"))
GOOD_CSV = (TESTS / "bad_rigs" / "good.csv").read_bytes()
CLOSING = json.loads((ROOT / "results" / "synthetic" / "vcb_closing.rig.json").read_text(encoding="utf-8"))

BOM = b"\xef\xbb\xbf"


def dump(obj):
    return json.dumps(obj, indent=1) + "\n"


def write_text(name, text, encoding="utf-8"):
    (HERE / name).write_bytes(text.encode(encoding))


def write_bytes(name, data):
    (HERE / name).write_bytes(data)


def renamed(rig, section, old, new):
    """A copy of ``rig`` with key ``old`` renamed to ``new`` (in ``section``, or at the top
    level when ``section`` is None), keeping the key order."""
    rig = copy.deepcopy(rig)
    target = rig if section is None else rig[section]
    items = [(new if k == old else k, v) for k, v in target.items()]
    target.clear()
    target.update(items)
    return rig


def binary_bytes(seed, n=600):
    """Random bytes with NULs that are not valid UTF-8 and do not start with a byte-order mark."""
    rng = random.Random(seed)
    data = bytearray(rng.randrange(256) for _ in range(n))
    data[0:4] = b"\x89\x00\xc3\x28"  # not a BOM; NUL; an invalid UTF-8 sequence
    for i in range(7, n, 37):
        data[i] = 0
    data = bytes(data)
    try:
        data.decode("utf-8")
    except UnicodeDecodeError:
        return data
    raise AssertionError("the random bytes happen to be valid UTF-8: change the seed")


def rigs():
    cam_text = dump(GOOD_CAM)

    # --- encodings -------------------------------------------------------------------------
    write_text("utf16.rig.json", cam_text, "utf-16")  # with the UTF-16 byte-order mark
    write_bytes("binary.rig.json", binary_bytes(1))
    write_bytes("bom.rig.json", BOM + cam_text.encode("utf-8"))  # must be ACCEPTED

    # --- JSON that parses into something hostile ---------------------------------------------
    depth = 100_000
    nested = copy.deepcopy(GOOD_CAM)
    nested["cam"]["mass"] = "@NESTED@"
    write_text("deeply_nested.rig.json", dump(nested).replace('"@NESTED@"', "[" * depth + "]" * depth))

    overflow = copy.deepcopy(GOOD_CAM)
    overflow["cam"]["mass"] = "@BIG@"
    write_text("overflow.rig.json", dump(overflow).replace('"@BIG@"', "1e400"))  # json reads inf

    huge = copy.deepcopy(GOOD_CAM)
    huge["cam"]["mass"] = 1e300  # finite, absurd
    write_text("huge_mass.rig.json", dump(huge))

    # --- unknown keys (typos) ------------------------------------------------------------------
    write_text("unknown_top_key.rig.json", dump(renamed(GOOD_CAM, None, "friction", "frcition")))
    write_text("unknown_cam_key.rig.json", dump(renamed(GOOD_CAM, "cam", "mass", "mas")))
    write_text("unknown_spring_key.rig.json", dump(renamed(GOOD_CAM, "closing_spring", "stiffness", "stifness")))
    write_text("unknown_model_key.rig.json", dump(renamed(GOOD_CAM, "model", "effects", "effect")))
    pendulum = copy.deepcopy(GOOD_PENDULUM)
    pendulum["friction"] = {"mu_k": 0.12, "stick_velocity": 0.001}
    write_text("unknown_pendulum_key.rig.json", dump(renamed(pendulum, "pendulum", "inertia", "intertia")))

    # --- a model effect whose value the rig does not give (simulate refuses; fits fit it) -----
    no_mu_k = copy.deepcopy(GOOD_CAM)
    no_mu_k["friction"] = {"stick_velocity": 0.001}
    write_text("coulomb_without_mu_k.rig.json", dump(no_mu_k))

    no_viscous = copy.deepcopy(GOOD_CAM)
    no_viscous["model"]["effects"] = ["coulomb_friction", "viscous_friction"]
    write_text("viscous_without_value.rig.json", dump(no_viscous))

    no_ws = copy.deepcopy(GOOD_CAM)
    no_ws["model"]["effects"] = ["coulomb_friction", "stribeck"]
    del no_ws["friction"]["stribeck_velocity"]
    write_text("stribeck_without_velocity.rig.json", dump(no_ws))

    no_mu_s = copy.deepcopy(GOOD_CAM)
    no_mu_s["model"]["effects"] = ["coulomb_friction", "stribeck"]
    del no_mu_s["friction"]["mu_s"]
    write_text("stribeck_without_mu_s.rig.json", dump(no_mu_s))

    # control: viscous friction given as a damping ratio zeta (pendulum) is enough for simulate
    zeta = copy.deepcopy(GOOD_PENDULUM)
    zeta["friction"] = {"mu_k": 0.12, "stick_velocity": 0.001, "zeta": 0.01}
    zeta["model"]["effects"] = ["coulomb_friction", "viscous_friction"]
    write_text("pendulum_zeta.rig.json", dump(zeta))

    closing = copy.deepcopy(CLOSING)
    closing["model"] = {"effects": ["coulomb_friction", "stribeck", "contact_damping"], "spring_model": "massless"}
    del closing["breaker"]["contact"]["restitution"]
    write_text("closing_without_restitution.rig.json", dump(closing))

    closing = copy.deepcopy(CLOSING)
    closing["model"] = {"effects": ["coulomb_friction", "stribeck", "bellows_force"], "spring_model": "massless"}
    del closing["breaker"]["poles"]["bellows_force"]
    write_text("closing_without_bellows.rig.json", dump(closing))

    closing = copy.deepcopy(CLOSING)
    closing["breaker"] = renamed(closing["breaker"], "contact", "cam_roller_law", "cam_roller_lwa")
    write_text("unknown_contact_key.rig.json", dump(closing))


def with_comment_keys(obj, depth=0):
    """A copy with a ``_note`` comment key added to every JSON object in it."""
    if isinstance(obj, dict):
        out = {"_note": f"a comment at level {depth}"}
        out.update({k: with_comment_keys(v, depth + 1) for k, v in obj.items()})
        return out
    return obj


def comment_keys():
    """Keys starting with '_' are comments wherever they appear: must be ACCEPTED."""
    pendulum = copy.deepcopy(GOOD_PENDULUM)
    pendulum["friction"] = {"mu_k": 0.12, "stick_velocity": 0.001}
    write_text("comments_everywhere_pendulum.rig.json", dump(with_comment_keys(pendulum)))
    closing = copy.deepcopy(CLOSING)
    closing["model"] = {"effects": ["coulomb_friction", "stribeck"], "spring_model": "massless"}
    write_text("comments_everywhere_closing.rig.json", dump(with_comment_keys(closing)))


def csvs():
    text = GOOD_CSV.decode("utf-8")
    first, rest = text.split("\n", 1)
    assert first.startswith("#")

    # a comment written by a Windows tool in latin-1: byte 0xE9 (e acute); must be ACCEPTED
    latin1 = (first + "\n# capteur: cam\u00e9ra rapide, d\u00e9placement mesur\u00e9 au degr\u00e9 pr\u00e8s\n"
              + rest).encode("latin-1")
    assert b"\xe9" in latin1
    write_bytes("latin1_comment.csv", latin1)

    write_text("utf16.csv", text, "utf-16")
    write_bytes("binary.csv", binary_bytes(2))
    write_bytes("bom.csv", BOM + GOOD_CSV)  # BOM before a comment line: ACCEPTED
    write_bytes("bom_header.csv", BOM + rest.encode("utf-8"))  # BOM directly before the header: ACCEPTED

    # A pendulum record whose time axis is in milliseconds although the format says seconds:
    # 6 s at 1 kHz written as t = 0, 1, ..., 6000. Read as seconds it is a 100-minute test.
    lines = ["# pendulum test, potentiometer on the shaft", "t,pendulum_angle"]
    period_ms, a0, stop_ms = 930.0, 0.1745, 4200.0
    for k in range(6001):
        amplitude = a0 * max(0.0, 1.0 - k / stop_ms)
        lines.append(f"{k},{amplitude * math.cos(2 * math.pi * k / period_ms):.9f}")
    write_text("pendulum_ms.csv", "\n".join(lines) + "\n")
    rig = copy.deepcopy(GOOD_PENDULUM)
    rig["name"] = "pendulum record with its time axis in milliseconds"
    write_text("pendulum_ms.rig.json", dump(rig))  # the sibling rig: diagnose finds it by name


if __name__ == "__main__":
    rigs()
    comment_keys()
    csvs()
    print("\n".join(sorted(p.name for p in HERE.iterdir() if p.name != Path(__file__).name)))

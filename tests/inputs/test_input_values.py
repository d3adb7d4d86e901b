"""Values a new user's files really hold (issue 17, section 2): refused before any work with one line
naming the file and the field, or, where unambiguous, read as meant (docs/rig-format.md)."""
import json
import os
import time
from pathlib import Path

import numpy as np
import pytest

from vcbmodel.app.cli import main, results_only_on_stdout
from vcbmodel.errors import InputError
from vcbmodel.experiments.loading import load_pair, load_rig
from vcbmodel.records.measurement import load_measurement
from vcbmodel.rig.reader import read_json

ROOT = Path(__file__).resolve().parents[2]
SYNTHETIC = ROOT / "results" / "synthetic"
CAM_RIG = SYNTHETIC / "cam_drop_m0_0.336kg.rig.json"
PENDULUM_RIG = SYNTHETIC / "demo_pendulum.rig.json"


def refused(capsys, argv, *words):
    t0 = time.perf_counter()
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "Traceback" not in err[0], err
    for w in words:
        assert w in err[0], err[0]
    assert time.perf_counter() - t0 < 15  # before any work
    return err[0]


def record(tmp_path, rig, name, t, y, channel):
    """A record NAME.csv beside a copy of ``rig``."""
    (tmp_path / f"{name}.rig.json").write_bytes(Path(rig).read_bytes())
    lines = [f"t,{channel}"] + [f"{a:.9g},{b:.9g}" for a, b in zip(t, y)]
    path = tmp_path / f"{name}.csv"
    path.write_text("\n".join(lines) + "\n")
    return path


def swing(t):
    return 0.17 * np.exp(-0.3 * t) * np.cos(2 * np.pi * t / 1.1)


# --- plausible wrong answers ----------------------------------------------------------------------------

def test_a_duplicate_json_key_is_refused_naming_it(tmp_path, capsys):
    text = CAM_RIG.read_text().replace('"stiffness":', '"stiffness": 20000.0, "stiffness":', 1)
    f = tmp_path / "dup.rig.json"
    f.write_text(text)
    with pytest.raises(InputError, match=r"closing_spring\.stiffness: is given twice"):  # the dotted field
        read_json(f)
    refused(capsys, ["simulate", str(f)], "dup.rig.json", "closing_spring.stiffness", "twice")


def test_underscore_numerals_are_refused_not_read_as_digit_separators(tmp_path, capsys):
    f = record(tmp_path, PENDULUM_RIG, "u", np.linspace(0, 3, 301), swing(np.linspace(0, 3, 301)), "pendulum_angle")
    f.write_text(f.read_text().replace("0.01,", "0.0_1,", 1))
    refused(capsys, ["identify", str(f)], "u.csv", "line", "underscores")


def test_a_cam_angle_in_degrees_is_refused_with_a_units_hint(tmp_path, capsys):
    t = np.linspace(0, 0.035, 421)
    f = record(tmp_path, CAM_RIG, "deg", t, np.degrees(0.17 + 1e3 * t**2), "cam_angle")
    refused(capsys, ["diagnose", str(f), "--json"], "deg.csv", "cam_angle", "degrees")


def test_a_follower_in_millimetres_is_refused_with_a_units_hint(tmp_path, capsys):
    t = np.linspace(0, 0.05, 601)
    f = record(tmp_path, SYNTHETIC / "vcb_closing.rig.json", "mm", t, 11.0 * np.clip(t / 0.03, 0, 1),
               "follower_displacement")
    refused(capsys, ["diagnose", str(f)], "mm.csv", "millimetres")


# --- sample interval, duration, size --------------------------------------------------------------------

def test_a_device_is_not_read(capsys):
    refused(capsys, ["simulate", "/dev/zero"], "/dev/zero", "not a regular file")


def test_samples_a_picosecond_apart_are_refused(tmp_path, capsys):
    t = np.arange(420) * 1e-12
    f = record(tmp_path, CAM_RIG, "ps", t, 0.17 + t * 1e6, "cam_angle")
    refused(capsys, ["diagnose", str(f)], "ps.csv", "column 't'", "apart")


def test_a_42_microsecond_cam_drop_is_too_short(tmp_path, capsys):
    t = np.arange(0, 42e-6, 1 / 12000 / 10)
    f = record(tmp_path, CAM_RIG, "short", t, 0.17 + 1e3 * t**2, "cam_angle")
    refused(capsys, ["diagnose", str(f)], "short.csv", "needs at least")


def test_too_many_samples_are_refused_before_the_fit(tmp_path, monkeypatch, capsys):
    from vcbmodel.experiments import base
    monkeypatch.setattr(base, "MAX_SAMPLES", 1000)
    t = np.linspace(0, 0.035, 2001)
    f = record(tmp_path, CAM_RIG, "dense", t, 0.17 + 1e3 * t**2, "cam_angle")
    refused(capsys, ["diagnose", str(f)], "dense.csv", "decimate")


# --- what used to give tracebacks -----------------------------------------------------------------------

@pytest.mark.parametrize("command", ["diagnose", "identify"])
def test_a_constant_signal_is_refused(command, tmp_path, capsys):
    t = np.linspace(0, 3, 3001)
    f = record(tmp_path, PENDULUM_RIG, "flat", t, np.full_like(t, 0.1), "pendulum_angle")
    refused(capsys, [command, str(f), "--json"], "flat.csv", "never changes")


def test_a_three_sample_pendulum_record_is_refused_as_too_short(tmp_path, capsys):
    f = record(tmp_path, PENDULUM_RIG, "three", [0, 0.001, 0.002], [0.17, 0.17, 0.169], "pendulum_angle")
    refused(capsys, ["identify", str(f)], "three.csv", "at least")


def test_values_near_1e200_are_refused(tmp_path, capsys):
    t = np.linspace(0, 3, 301)
    f = record(tmp_path, PENDULUM_RIG, "big", t, swing(t) * 1e200, "pendulum_angle")
    line = refused(capsys, ["identify", str(f)], "big.csv", "implausible")
    assert "degrees" not in line  # no units hint for a value no unit slip explains


def test_native_messages_during_a_fit_cannot_reach_stdout(capfd):
    with results_only_on_stdout():
        os.write(1, b"** On entry to DLASCL parameter number 4 had an illegal value\n")
    print('{"json": true}')
    out, err = capfd.readouterr()
    assert out == '{"json": true}\n' and "DLASCL" in err


# --- misleading messages --------------------------------------------------------------------------------

def test_a_bad_contact_exponent_names_the_exponent(tmp_path, capsys):
    data = json.loads((SYNTHETIC / "vcb_closing.rig.json").read_text())
    data["breaker"]["contact"]["exponent"] = 15.0
    f = tmp_path / "x.rig.json"
    f.write_text(json.dumps(data))
    line = refused(capsys, ["simulate", str(f)], "breaker.contact.exponent", "between 1")
    assert "bellows" not in line


def test_identify_given_a_rig_file_says_so(capsys):
    line = refused(capsys, ["identify", str(PENDULUM_RIG)], "is a rig file", "NAME.csv")
    assert ".rig.rig.json" not in line
    with pytest.raises(InputError, match="is a rig file"):
        load_pair(PENDULUM_RIG)


# --- CSV variants: what is unambiguous is read as meant -------------------------------------------------

PLAIN = "t,cam_angle\n0.0,0.17\n0.001,0.171\n0.002,0.175\n0.003,0.18\n"
VARIANTS = {
    "semicolons and decimal commas": "t;cam_angle\n0,0;0,17\n0,001;0,171\n0,002;0,175\n0,003;0,18\n",
    "tabs": PLAIN.replace(",", "\t"),
    "units in the header": PLAIN.replace("t,cam_angle", "t [s],cam_angle [rad]"),
    "units in parentheses": PLAIN.replace("t,cam_angle", "t (s),cam_angle (rad)"),
    "quoted values": "\n".join(",".join(f'"{c}"' for c in line.split(",")) for line in PLAIN.strip().split("\n")) + "\n",
    "a trailing comma": "".join(line + ",\n" for line in PLAIN.strip().split("\n")),
    "capitals": PLAIN.replace("t,cam_angle", "T,Cam_Angle"),
    "windows line ends": PLAIN.replace("\n", "\r\n"),
}


@pytest.mark.parametrize("variant", VARIANTS)
def test_common_csv_variants_read_as_the_plain_file(variant, tmp_path):
    plain, other = tmp_path / "plain.csv", tmp_path / "other.csv"
    plain.write_text(PLAIN)
    other.write_bytes(VARIANTS[variant].encode())
    a, b = load_measurement(plain, "cam_angle"), load_measurement(other, "cam_angle", units={"cam_angle": "rad"})
    assert np.array_equal(a.t, b.t) and np.array_equal(a.channel("cam_angle"), b.channel("cam_angle"))


@pytest.mark.parametrize("text, words", [
    ("t [m],cam_angle\n0,0.17\n1,0.171\n2,0.175\n", ["'m'", "'s'"]),
    ("t,cam_angle [mm]\n0,10\n0.001,10.1\n0.002,10.2\n", ["'mm'", "'rad'"]),
    ("t,cam_angle [furlong]\n0,10\n0.001,10.1\n0.002,10.2\n", ["'furlong'", "not a unit"]),
    ("t,cam_angle\n0,0,17\n0,001,0,171\n0,002,0,175\n", ["decimal comma", "';'"]),
])
def test_ambiguous_or_wrong_csv_variants_name_the_cause(text, words, tmp_path):
    f = tmp_path / "v.csv"
    f.write_text(text)
    with pytest.raises(InputError) as e:
        load_measurement(f, "cam_angle", units={"cam_angle": "rad"})
    for w in words:
        assert w in str(e.value)


def test_a_clock_uncertainty_wider_than_the_fit_allows_is_refused(tmp_path, capsys):
    """uncertain.record.time_base is a prior on the record's clock; the fit bounds the clock to
    +-TIME_SCALE_SPAN, so a wider prior would be cut silently: refused, naming the field."""
    from vcbmodel import parameters as P

    data = json.loads(PENDULUM_RIG.read_text())
    data["uncertain"] = {"record.time_base": 0.5}
    f = tmp_path / "x.rig.json"
    f.write_text(json.dumps(data))
    refused(capsys, ["check", str(f)], "uncertain.record.time_base", f"at most {P.TIME_SCALE_SPAN / 2:g}")
    data["uncertain"] = {"record.time_base": 0.002}
    f.write_text(json.dumps(data))
    assert load_rig(f).uncertain == {"record.time_base": 0.002}

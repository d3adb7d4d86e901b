"""The front door: hostile and sloppy input at the command line (docs/cli.md, docs/rig-format.md).

Every bad input must give exit status 2, exactly one line on stderr naming the file (its
basename) and the field, no traceback, nothing on stdout and nothing written. Some inputs that
look odd are fine and must be accepted (a UTF-8 byte-order mark, a latin-1 comment, a space
after a comma in ``--effects``).

The corpus is in ``tests/front_door/`` (written once by ``tests/front_door/make_corpus.py`` from
the known-good files in ``tests/bad_rigs/``). The CLI is called in-process; the two inputs that
could hang a process (an absurd mass, a time axis in milliseconds) run in a subprocess with a
timeout instead.
"""
import copy
import importlib
import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

import vcbmodel
from vcbmodel import parameters as P

from vcbmodel.app.cli import main
from vcbmodel.experiments import experiment_of
from vcbmodel.records.measurement import load_measurement as _load_measurement


def load_measurement(path, experiment):
    return _load_measurement(path, experiment_of(experiment).measured_channel)

HERE = Path(__file__).resolve().parents[1]  # tests/
FD = HERE / "front_door"
BAD = HERE / "bad_rigs"
GOOD_CAM = BAD / "good_cam.rig.json"
GOOD_CSV = BAD / "good.csv"

# Words by which a refusal of an unreadable file (wrong encoding, not text at all) names what is wrong.
ENCODING_WORDS = ("encoding", "utf", "binary", "text", "byte", "decode")


# --- helpers ---------------------------------------------------------------------------------------

class WorkStarted(BaseException):
    """Raised by the tripwires: the command began solving before refusing its options."""


def run_cli(capsys, argv):
    """main(argv) -> (exit code, stdout, stderr). An exception escaping main would be a
    traceback for the user: it fails the test with a clear message instead of erroring."""
    problem = None
    try:
        code = main(argv)
    except SystemExit as e:  # argparse's own exits (usage errors, --help, --version)
        code = e.code if isinstance(e.code, int) else (0 if e.code is None else 2)
    except WorkStarted:
        problem = "started solving before checking its options"
    except Exception as e:  # noqa: BLE001 - this is the point of the test
        problem = f"main raised {type(e).__name__}: {str(e)[:300]} (the user would see a traceback)"
    out, err = capsys.readouterr()
    if problem:
        pytest.fail(f"vcbmodel {' '.join(map(str, argv))}: {problem}", pytrace=False)
    return code, out, err


def one_line(err):
    lines = err.strip().splitlines()
    assert len(lines) == 1, f"expected exactly one line on stderr, got {len(lines)}:\n{err}"
    assert "Traceback" not in err
    return lines[0]


def assert_refused(capsys, argv, filename, fields, out_dir, code=2):
    """Refused with ``code``, one line naming ``filename`` and one of ``fields``, nothing on
    stdout, nothing written into ``out_dir``. ``fields`` is a string or a tuple of alternatives
    (matched case-insensitively)."""
    got, out, err = run_cli(capsys, argv)
    assert got == code, f"exit status {got}, expected {code}; stderr: {err!r}"
    line = one_line(err)
    assert out == "", f"stdout must be empty on bad input, got {out[:200]!r}"
    assert filename in line, f"{filename!r} not named in: {line}"
    alternatives = (fields,) if isinstance(fields, str) else fields
    assert any(f.lower() in line.lower() for f in alternatives), f"none of {alternatives} named in: {line}"
    assert sorted(p.name for p in out_dir.iterdir()) == [], f"something was written: {list(out_dir.iterdir())}"
    return line


@pytest.fixture
def no_work(monkeypatch):
    """Tripwires on the solver and the analyses: a command that must refuse its options
    before any work fails the test if it gets as far as building or solving a model."""
    def tripwire(*args, **kwargs):
        raise WorkStarted()

    candidates = ["vcbmodel.experiments.simulation:simulate", "vcbmodel.analysis.diagnose:diagnose",
                  "vcbmodel.analysis.identify:identify", "exudyn:SystemContainer"]
    # names the command module imported at its top (they would escape the patches above)
    candidates += [f"{main.__module__}:{name}" for name in ("simulate", "diagnose", "identify")]
    for candidate in candidates:
        module_name, attr = candidate.split(":")
        monkeypatch.setattr(importlib.import_module(module_name), attr, tripwire)


def run_subprocess(argv, timeout=60):
    """Run ``python -m vcbmodel argv`` in its own session; kill that session (the process and
    any workers it forked) if it outlives ``timeout``. Returns (code, stdout, stderr, seconds)."""
    start = time.monotonic()
    p = subprocess.Popen([sys.executable, "-m", "vcbmodel", *map(str, argv)], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        p.communicate()
        pytest.fail(f"vcbmodel {' '.join(map(str, argv))} still running after {timeout} s (killed): "
                    "the input must be refused at once, not simulated")
    return p.returncode, out, err, time.monotonic() - start


def pendulum_rig_dict(friction):
    rig = copy.deepcopy(P.REFERENCE_PENDULUM)
    rig["friction"] = dict(friction)
    rig["model"] = {"effects": ["coulomb_friction"], "spring_model": "massless"}
    return rig


@pytest.fixture(scope="module")
def pendulum_record(tmp_path_factory):
    """A 2 s synthetic pendulum record made by ``vcbmodel simulate`` (mu_k 0.12, no noise)."""
    folder = tmp_path_factory.mktemp("pendulum")
    rig = folder / "truth.rig.json"
    rig.write_text(json.dumps(pendulum_rig_dict({"mu_k": 0.12, "stick_velocity": 1e-3})))
    csv = folder / "swing.csv"
    assert main(["simulate", str(rig), "--t-end", "2", "-o", str(csv)]) == 0
    return csv


# --- 1. rig files --------------------------------------------------------------------------------------

RIGS = [  # file in front_door/, what the one line must name (any of the alternatives)
    ("utf16", ENCODING_WORDS),
    ("binary", ENCODING_WORDS),
    ("deeply_nested", ("cam.mass", "line", "nest", "deep", "depth")),
    ("overflow", ("cam.mass", "line")),  # the field, or at least the line of the 1e400
    ("unknown_top_key", "frcition"),
    ("coulomb_without_mu_k", "friction.mu_k"),
    ("viscous_without_value", "friction.viscous"),
    ("stribeck_without_velocity", "friction.stribeck_velocity"),
    ("stribeck_without_mu_s", "friction.mu_s"),
    ("closing_without_restitution", "breaker.contact.restitution"),
    ("closing_without_bellows", "breaker.poles.bellows_force"),
]


@pytest.mark.parametrize("name,fields", RIGS, ids=[r[0] for r in RIGS])
def test_bad_rig_is_refused(name, fields, capsys, tmp_path):
    f = FD / f"{name}.rig.json"
    assert_refused(capsys, ["simulate", str(f), "-o", str(tmp_path / "out.csv")], f.name, fields, tmp_path)


UNKNOWN_SECTION_KEYS = [  # file, the unknown dotted name, the known name a hint should offer
    ("unknown_cam_key", "cam.mas", "mass"),
    ("unknown_spring_key", "closing_spring.stifness", "stiffness"),
    ("unknown_model_key", "model.effect", "effects"),
    ("unknown_pendulum_key", "pendulum.intertia", "inertia"),
    ("unknown_contact_key", "breaker.contact.cam_roller_lwa", "cam_roller_law"),
]


@pytest.mark.parametrize("name,dotted,known", UNKNOWN_SECTION_KEYS, ids=[u[0] for u in UNKNOWN_SECTION_KEYS])
def test_unknown_key_in_a_section_is_named(name, dotted, known, capsys, tmp_path):
    f = FD / f"{name}.rig.json"
    line = assert_refused(capsys, ["simulate", str(f), "-o", str(tmp_path / "out.csv")], f.name, dotted, tmp_path)
    # the typo itself, not a complaint about the missing right name ("cam.mass: missing" contains "cam.mas")
    assert re.search(re.escape(dotted) + r"(?![A-Za-z0-9_])", line), f"{dotted!r} not named as such in: {line}"
    rest = line.replace(dotted, "")
    assert known in rest, f"no hint naming {known!r} in: {line}"


def test_rig_with_utf8_bom_is_accepted(capsys, tmp_path):
    out = tmp_path / "out.csv"
    code, stdout, err = run_cli(capsys, ["simulate", str(FD / "bom.rig.json"), "-o", str(out)])
    assert code == 0, err
    assert load_measurement(out, "cam_drop").t.size > 100


@pytest.mark.parametrize("name", ["comments_everywhere_pendulum", "comments_everywhere_closing"])
def test_underscore_keys_are_comments_everywhere(name, capsys, tmp_path):
    """docs/rig-format.md: a key starting with '_' is a comment in every object of a rig."""
    out = tmp_path / "out.csv"
    code, stdout, err = run_cli(capsys, ["simulate", str(FD / f"{name}.rig.json"), "--t-end", "0.002", "-o", str(out)])
    assert code == 0, err
    assert out.exists()


def test_viscous_friction_given_as_zeta_is_enough(capsys, tmp_path):
    """Control for the 'value needed' check: a pendulum rig may give zeta instead of viscous."""
    out = tmp_path / "out.csv"
    code, stdout, err = run_cli(capsys, ["simulate", str(FD / "pendulum_zeta.rig.json"), "--t-end", "1",
                                         "-o", str(out)])
    assert code == 0, err
    assert load_measurement(out, "pendulum").t.size == 1001


def test_huge_mass_neither_hangs_nor_crashes(tmp_path):
    """cam.mass = 1e300 is finite: refuse it as implausible (2) or fail the solve cleanly (1)."""
    f = FD / "huge_mass.rig.json"
    code, out, err, seconds = run_subprocess(["simulate", f, "-o", tmp_path / "out.csv"], timeout=60)
    assert code in (1, 2), f"exit status {code}: a 1e300 kg cam must not pass as a result; stderr: {err!r}"
    line = one_line(err)
    assert out == ""
    assert list(tmp_path.iterdir()) == []
    if code == 2:
        assert f.name in line and "cam.mass" in line, line


# --- 2. measurement files -------------------------------------------------------------------------------

def test_latin1_comment_in_a_simulated_record_is_accepted(pendulum_record, tmp_path):
    lines = pendulum_record.read_bytes().split(b"\n")
    f = tmp_path / "latin1.csv"
    f.write_bytes(b"\n".join([lines[0], "# capteur: d\u00e9placement angulaire, \u00e9talonn\u00e9".encode("latin-1"),
                              *lines[1:]]))
    assert b"\xe9" in f.read_bytes()
    try:
        m = load_measurement(f, "pendulum")
    except Exception as e:  # noqa: BLE001
        pytest.fail(f"a latin-1 comment line is free text and must be accepted: {type(e).__name__}: {e}")
    original = load_measurement(pendulum_record, "pendulum")
    assert m.t.size == original.t.size and (m.channels["pendulum_angle"] == original.channels["pendulum_angle"]).all()


@pytest.mark.parametrize("name", ["latin1_comment", "bom", "bom_header"])
def test_odd_but_valid_csv_is_accepted(name):
    try:
        m = load_measurement(FD / f"{name}.csv", "cam_drop")
    except Exception as e:  # noqa: BLE001
        pytest.fail(f"{name}.csv must be accepted: {type(e).__name__}: {e}")
    assert m.t.size == 4 and list(m.channels) == ["cam_angle"]


@pytest.mark.parametrize("name", ["binary"])
def test_unreadable_csv_is_refused(name, capsys, tmp_path):
    f = FD / f"{name}.csv"
    assert_refused(capsys, ["diagnose", str(f), "--rig", str(GOOD_CAM), "--plot", str(tmp_path / "d.png")],
                   f.name, ENCODING_WORDS, tmp_path)


def test_time_in_milliseconds_is_refused_at_once(tmp_path):
    """t = 0, 1, ..., 6000 labelled seconds: a 6 s swing at 1 kHz written in ms. Read as seconds
    it asks for a 100-minute simulation; it must be refused at once with a hint."""
    f = FD / "pendulum_ms.csv"
    code, out, err, seconds = run_subprocess(["diagnose", f, "--json", "--plot", tmp_path / "d.png"], timeout=60)
    assert code == 2, f"exit status {code}; stderr: {err!r}"
    line = one_line(err)
    assert out == "" and list(tmp_path.iterdir()) == []
    assert f.name in line and "millisecond" in line.lower(), line
    assert seconds < 20, f"took {seconds:.1f} s: the check must come before any fit"


# --- 3. command options ---------------------------------------------------------------------------------

def test_effects_with_spaces_after_commas(capsys, tmp_path):
    out = tmp_path / "out.csv"
    code, stdout, err = run_cli(capsys, ["simulate", str(GOOD_CAM), "--effects", "coulomb_friction, stribeck",
                                         "--t-end", "0.005", "-o", str(out)])
    assert code == 0, err
    m = load_measurement(out, "cam_drop")
    assert m.t.size > 10
    assert "stribeck" in " ".join(m.comments)  # the header comment lists the effects simulated


def test_output_is_an_existing_directory(capsys, tmp_path, no_work):
    folder = tmp_path / "results"
    folder.mkdir()
    argv = ["simulate", str(GOOD_CAM), "-o", str(folder)]
    assert_refused(capsys, argv, "results", "-o", folder)
    assert [p.name for p in tmp_path.iterdir()] == ["results"]


@pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc")
def test_output_in_an_unwritable_place(capsys, tmp_path, no_work):
    assert_refused(capsys, ["simulate", str(GOOD_CAM), "-o", "/proc/vcbmodel.csv"], "vcbmodel.csv", "-o", tmp_path)
    assert not Path("/proc/vcbmodel.csv").exists()


def test_plot_with_an_unknown_image_format(capsys, tmp_path, no_work):
    argv = ["diagnose", str(GOOD_CSV), "--rig", str(GOOD_CAM), "--plot", str(tmp_path / "out.xyz")]
    assert_refused(capsys, argv, "out.xyz", "--plot", tmp_path)


def test_bare_command_prints_usage(capsys):
    code, out, err = run_cli(capsys, [])
    assert code in (0, 2)
    assert "usage" in (out + err).lower(), out + err
    assert "Traceback" not in out + err


def test_version(capsys):
    code, out, err = run_cli(capsys, ["--version"])
    assert code == 0, err
    assert vcbmodel.__version__ in out + err


# --- 4. identify with nothing left to fit ------------------------------------------------------------------

def test_identify_with_every_value_fixed_says_nothing_to_fit(pendulum_record, capsys, tmp_path):
    rig = tmp_path / "fixed.rig.json"
    rig.write_text(json.dumps(pendulum_rig_dict({"mu_k": 0.12, "mu_s": 0.12, "stick_velocity": 1e-3})))
    before = sorted(p.name for p in tmp_path.iterdir())
    code, out, err = run_cli(capsys, ["identify", str(pendulum_record), "--rig", str(rig), "--law", "stick-slip",
                                      "--json"])
    assert code == 2, f"exit status {code}: the stick-slip law's mu_k, mu_s and stick_velocity are all fixed"
    line = one_line(err)
    assert out == ""
    assert rig.name in line and "friction" in line, line
    assert "nothing to fit" in line.lower() or "no free" in line.lower() or "every" in line.lower(), line
    assert sorted(p.name for p in tmp_path.iterdir()) == before


# --- 5. identify --json carries its context --------------------------------------------------------------

def test_identify_json_carries_units_experiment_rig_and_version(pendulum_record, capsys, tmp_path):
    rig = tmp_path / "fit.rig.json"
    rig_dict = pendulum_rig_dict({"stick_velocity": 1e-3})  # mu_k removed: identify fits mu_k and mu_s
    rig.write_text(json.dumps(rig_dict))
    code, out, err = run_cli(capsys, ["identify", str(pendulum_record), "--rig", str(rig), "--law", "stick-slip",
                                      "--json"])
    assert code == 0, err
    j = json.loads(out)
    assert j["mu_k"] == pytest.approx(0.12, rel=0.02)
    for key in ("units", "experiment", "rig_name", "vcbmodel_version"):
        assert key in j, f"identify --json lacks {key!r}: {sorted(j)}"
    assert isinstance(j["units"], dict) and j["units"], j["units"]
    assert j["experiment"] == "pendulum"
    assert j["rig_name"] == rig_dict["name"]
    assert j["vcbmodel_version"] == vcbmodel.__version__

"""Parameter studies (``vcbmodel sweep``, docs/cli.md): the design (grids, seeded Latin
hypercube, no mixing), paths into the rig, bad input (exit 2, one line, nothing written), a
failed run's row, rows flushed as runs finish, --resume after an interrupt, the command line
end to end, the local process pool (a Dask cluster: test_sweep_cluster.py)."""
import copy
import csv
import json

import numpy as np
import pandas as pd
import pytest

from vcbmodel import parameters as P
from vcbmodel.analysis import sweep as S
from vcbmodel.app.cli import main
from vcbmodel.errors import InputError
from vcbmodel.experiments import experiment_of


def pendulum_data():
    return dict(copy.deepcopy(P.REFERENCE_PENDULUM), friction=dict(P.REFERENCE_PENDULUM_TRUTH))


@pytest.fixture
def rig(tmp_path):
    path = tmp_path / "p.rig.json"
    path.write_text(json.dumps(pendulum_data()))
    return str(path)


def read_rows(path):
    with open(path, newline="") as f:  # after the rig's fingerprint, a comment line
        return list(csv.reader(line for line in f if not line.startswith("#")))


# --- the design ---------------------------------------------------------------------------------

def test_grids_make_the_full_product_last_path_fastest():
    d = S.design(["a.x=0:1:3", "b.y=10:40:4"])
    assert list(d.columns) == ["a.x", "b.y"] and len(d) == 12
    assert list(d["a.x"][:4]) == [0.0] * 4 and list(d["b.y"][:4]) == [10.0, 20.0, 30.0, 40.0]
    assert sorted(set(d["a.x"])) == [0.0, 0.5, 1.0]
    assert len(S.design(["a=1:1:1"])) == 1


def test_latin_hypercube_is_seeded_repeatable_and_stratified():
    spec = ["a=uniform:0:1", "b=normal:5:2"]
    d1, d2 = S.design(spec, samples=20, seed=3), S.design(spec, samples=20, seed=3)
    pd.testing.assert_frame_equal(d1, d2)
    assert not np.allclose(d1["a"], S.design(spec, samples=20, seed=4)["a"])
    pd.testing.assert_frame_equal(S.design(spec, samples=20), S.design(spec, samples=20, seed=S.DEFAULT_SEED))
    # one draw in each of the 20 equal-probability strata of every axis
    from scipy.stats import norm
    for u in (d1["a"].to_numpy(), norm.cdf(d1["b"].to_numpy(), 5, 2)):
        assert sorted(np.floor(u * 20).astype(int)) == list(range(20))
    mc = S.design(spec, samples=20, seed=3, sampling="mc")
    assert len(mc) == 20 and not np.allclose(mc["a"], d1["a"])


@pytest.mark.parametrize("items, samples, message", [
    (["a=0:1:3", "b=normal:0:1"], None, "not both"),
    (["a=uniform:0:1"], None, "--samples"),
    (["a=0:1:3"], 5, "distributions only"),
    (["a=0:1"], None, "LO:HI:N"),
    (["a=0:1:2.5"], None, "whole number"),
    (["a=0:1:0"], None, "whole number"),
    (["a=0:1:1"], None, "N >= 2"),
    (["a=normal:1:0"], 3, "standard deviation"),
    (["a=uniform:2:1"], 3, "LO < HI"),
    (["a=weibull:1:2"], 3, "LO:HI:N"),
    (["a=0:x:2"], None, "not a number"),
    (["a=nan:1:2"], None, "finite"),
    (["a"], None, "PATH=SPEC"),
    (["=0:1:2"], None, "empty"),
    (["a=0:1:2", "a=0:1:3"], None, "twice"),
])
def test_bad_specs_are_refused(items, samples, message):
    with pytest.raises(InputError, match=message):
        S.design(items, samples=samples)


def test_paths_into_the_rig_json():
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    assert S.get_path(data, "breaker.poles.gap_offsets.1") == data["breaker"]["poles"]["gap_offsets"][1]
    edited = S.with_overrides(data, {"breaker.poles.gap_offsets.2": 1e-4, "cam.pivot.0": 0.5, "friction.viscous": 0.3})
    assert edited["breaker"]["poles"]["gap_offsets"][2] == 1e-4 and edited["cam"]["pivot"][0] == 0.5
    assert edited["friction"]["viscous"] == 0.3 and "viscous" not in data["friction"]  # a copy
    with pytest.raises(KeyError):
        S.with_overrides(data, {"cam.pivot.5": 1.0})


# --- bad input on the command line: exit 2, one line naming file and field, nothing written -----

@pytest.mark.parametrize("vary, extra, names", [
    (["friction.mu_kk=0:1:2"], [], "friction.mu_kk"),
    (["cam.mass=1:2:2"], [], "cam.mass"),
    (["model.effects=0:1:2"], [], "model.effects"),
    (["pendulum.mass.x=0:1:2"], [], "pendulum.mass.x"),
    (["friction.mu_k=0:1"], [], "friction.mu_k"),
    (["friction.mu_k=0:1:2", "friction.viscous=normal:0.6:0.1"], [], "friction.viscous"),
    (["friction.mu_k=normal:0.1:0.01"], [], "--samples"),
    (["friction.mu_k=0:1:2"], ["--workers", "0"], "--workers"),
])
def test_cli_bad_input_exits_2_with_one_line_and_writes_nothing(rig, tmp_path, capsys, vary, extra, names):
    out = tmp_path / "out.csv"
    argv = ["sweep", rig, *[a for v in vary for a in ("--vary", v)], *extra, "-o", str(out)]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("vcbmodel: bad input:") and names in err[0], err
    assert not out.exists()


def test_a_value_the_model_needs_but_the_rig_lacks_is_bad_input_before_the_sweep(tmp_path, capsys):
    data = pendulum_data()
    del data["friction"]["mu_s"]
    path = tmp_path / "p.rig.json"
    path.write_text(json.dumps(data))
    out = tmp_path / "out.csv"
    assert main(["sweep", str(path), "--vary", "friction.mu_k=0.1:0.2:2", "-o", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "friction.mu_s" in err and str(path) in err and len(err.splitlines()) == 1
    assert not out.exists()


# --- runs ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("spec", ["pendulum.mass=60:60000:3", "pendulum.mass=normal:60000:10"])
def test_a_varied_value_no_mechanism_has_is_bad_input_before_any_run(rig, tmp_path, capsys, spec):
    """60000 kg is grams typed as kg (docs/rig-format.md 3.11): refused naming --vary and the field, not a
    table of failed rows with status 0."""
    out = tmp_path / "out.csv"
    extra = ["--samples", "3"] if "normal" in spec else []
    assert main(["sweep", str(rig), "--vary", spec, *extra, "-o", str(out), "--workers", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("vcbmodel: bad input: --vary: pendulum.mass: ") and "impossible" in err[0]
    assert not out.exists()


def test_a_failed_run_gets_its_reason_and_the_sweep_goes_on(rig, tmp_path):
    out = tmp_path / "out.csv"
    df = S.sweep(rig, ["pendulum.mass=-60:60:3"], workers=1, output=str(out), verbose=False)
    assert list(df.status[:2]) == ["failed: pendulum.mass: must be positive, got -60",
                                   "failed: pendulum.mass: must be positive, got 0"]
    assert df.status[2] == "ok" and df.first_peak_rad[2] > 0 and np.isnan(df.first_peak_rad[0])
    rows = read_rows(out)
    assert rows[0] == ["run", "pendulum.mass", "first_peak_rad", "stop_time_s", "status"]
    assert rows[1][-1].startswith("failed: pendulum.mass") and rows[1][2] == "" and rows[3][-1] == "ok"


_FLUSH_LOG = {}


def evaluate_and_look_at_the_file(rig, t_end):
    """An evaluation that records how many rows the output file holds when each run starts."""
    _FLUSH_LOG.setdefault("rows_seen", []).append(len(read_rows(_FLUSH_LOG["path"])) - 1)
    return {"mass": rig.pendulum.mass}


def test_rows_are_written_and_flushed_as_runs_finish(rig, tmp_path):
    out = tmp_path / "out.csv"
    _FLUSH_LOG.clear()
    _FLUSH_LOG["path"] = out
    df = S.sweep(rig, ["pendulum.mass=50:59:4"], workers=1, output=str(out), evaluate=evaluate_and_look_at_the_file,
                 columns=["mass"], verbose=False)
    assert _FLUSH_LOG["rows_seen"] == [0, 1, 2, 3]  # run k starts with the k - 1 finished rows on disk
    assert list(df["mass"]) == [50.0, 53.0, 56.0, 59.0] == list(df["pendulum.mass"])


def test_resume_skips_finished_runs_after_an_interrupt(rig, tmp_path):
    vary = ["friction.mu_k=normal:0.13:0.02"]
    full_path = tmp_path / "full.csv"
    full = S.sweep(rig, vary, samples=5, seed=7, workers=1, output=str(full_path), verbose=False)
    assert full.attrs["runs_done"] == 5 and (full.status == "ok").all()
    lines = full_path.read_text().splitlines(keepends=True)
    # interrupted after runs 4 and 2 (finishing order), in the middle of writing a third row
    partial = tmp_path / "partial.csv"
    partial.write_text(lines[0] + lines[1] + lines[5] + lines[3] + lines[6][:9])  # the fingerprint, the header
    again = S.sweep(rig, vary, samples=5, seed=7, workers=1, output=str(partial), resume=True, verbose=False)
    assert again.attrs["runs_done"] == 3  # runs 1, 3 and 5
    pd.testing.assert_frame_equal(again, full, check_like=True)
    assert partial.read_text() == full_path.read_text()  # complete: rewritten in run order
    done = S.sweep(rig, vary, samples=5, seed=7, workers=1, output=str(partial), resume=True, verbose=False)
    assert done.attrs["runs_done"] == 0
    # another design (seed) cannot resume this file
    with pytest.raises(InputError, match="another sweep"):
        S.sweep(rig, vary, samples=5, seed=8, workers=1, output=str(partial), resume=True, verbose=False)
    with pytest.raises(InputError, match="columns of another sweep"):
        S.sweep(rig, ["friction.viscous=normal:0.6:0.1"], samples=5, workers=1, output=str(partial), resume=True,
                verbose=False)


def test_cli_end_to_end_on_a_tiny_pendulum_sweep(rig, tmp_path, capsys):
    out = tmp_path / "grid.csv"
    assert main(["sweep", rig, "--vary", "friction.mu_k=0.10:0.16:2", "--vary", "friction.viscous=0.3:0.6:2",
                 "--workers", "1", "-o", str(out)]) == 0
    captured = capsys.readouterr()
    assert captured.out == ""
    assert "4/4 done" in captured.err and "/min" in captured.err and "left" in captured.err
    # a swing has no closing: its runs are ok or failed, never "not closed"
    assert ": 4 ok, 0 failed in" in captured.err and "closed" not in captured.err
    rows = read_rows(out)
    assert rows[0] == ["run", "friction.mu_k", "friction.viscous", "first_peak_rad", "stop_time_s", "status"]
    assert [r[0] for r in rows[1:]] == ["1", "2", "3", "4"] and all(r[-1] == "ok" for r in rows[1:])
    peaks = {(float(r[1]), float(r[2])): float(r[3]) for r in rows[1:]}
    assert peaks[(0.10, 0.3)] > peaks[(0.16, 0.3)] and peaks[(0.10, 0.3)] > peaks[(0.10, 0.6)]  # more friction, smaller swing
    # to stdout, random draws
    assert main(["sweep", rig, "--vary", "friction.mu_k=uniform:0.1:0.16", "--samples", "2", "--seed", "1",
                 "--workers", "1"]) == 0
    table = capsys.readouterr().out.strip().splitlines()
    assert table[0] == "run,friction.mu_k,first_peak_rad,stop_time_s,status" and len(table) == 3


def test_cli_help_states_the_sampling_and_the_engine(capsys):
    with pytest.raises(SystemExit) as e:
        main(["sweep", "--help"])
    assert e.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "Latin hypercube" in text and "Dask" in text and "seed" in text


def test_local_process_pool_gives_the_serial_answer(rig):
    vary = ["friction.mu_k=0.08:0.16:4"]
    serial = S.sweep(rig, vary, workers=1, t_end=2.0, verbose=False)
    pool = S.sweep(rig, vary, workers=2, t_end=2.0, verbose=False)
    assert pool.attrs["workers"] == 2 and serial.attrs["workers"] == 1
    pd.testing.assert_frame_equal(pool, serial)


@pytest.mark.parametrize("data", [P.REFERENCE_CAM, P.REFERENCE_BREAKER], ids=["cam_drop", "vcb_closing"])
def test_every_experiment_gives_its_figures_of_merit(data):
    """The columns docs/cli.md lists, filled from the experiment's own figures_of_merit."""
    df = S.sweep(copy.deepcopy(data), ["cam.initial_velocity=0:0:1"], workers=1, verbose=False)
    assert list(df.columns) == ["run", "cam.initial_velocity", *experiment_of(data["experiment"]).figure_columns, "status"]
    assert df.status[0] == "ok" and df[list(experiment_of(data["experiment"]).figure_columns)].notna().all(axis=None)
    if data["experiment"] == "vcb_closing":  # every pole is judged: the slowest and fastest, not a mean at touch
        assert "touch_speed_m_s" not in df.columns
        assert df.zone_speed_min_m_s[0] < df.closing_speed_m_s[0] < df.zone_speed_max_m_s[0]


def test_a_closing_sweep_says_how_many_runs_did_not_close(caplog):
    """The closing line counts a closing's own status apart: a run that ends before any pole touches."""
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    with caplog.at_level("INFO", logger="vcbmodel"):
        S.sweep(data, ["cam.initial_velocity=0:0:1"], workers=1, t_end=0.01, verbose=True)
    assert ": 0 ok, 1 not closed, 0 failed in" in caplog.text


def test_the_pool_works_from_a_script_without_a_main_guard(tmp_path):
    import subprocess
    import sys

    script = tmp_path / "plain.py"
    script.write_text("from vcbmodel import parameters as P\nfrom vcbmodel.analysis.sweep import sweep\n"
                      "d = dict(P.REFERENCE_PENDULUM, friction=dict(P.REFERENCE_PENDULUM_TRUTH))\n"
                      "t = sweep(d, ['friction.mu_k=0.1:0.15:2'], workers=2, t_end=0.5, verbose=False)\n"
                      "print(list(t.status))\n")
    p = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and p.stdout.strip() == "['ok', 'ok']", p.stderr[-1500:]


def test_t_end_runs_a_closing_long_enough_to_latch_and_a_resume_keeps_it(tmp_path, capsys):
    """The template breaker's cam latches after the usual 55 ms: its kinetic margin is empty at the
    default duration and known with --t-end 0.08; resuming that table with another --t-end would mix two
    durations in one table: refused; a --t-end that is not a positive number: refused before any run."""
    rig = tmp_path / "t.rig.json"
    assert main(["init", "vcb_closing", "-o", str(rig)]) == 0
    vary = ["--vary", "friction.mu_k=0.13:0.16:2", "--workers", "1"]
    assert main(["sweep", str(rig), *vary, "-o", str(tmp_path / "usual.csv"), "-q"]) == 0
    assert main(["sweep", str(rig), *vary, "--t-end", "0.08", "-o", str(tmp_path / "long.csv"), "-q"]) == 0
    usual, long = (pd.read_csv(tmp_path / name, comment="#") for name in ("usual.csv", "long.csv"))
    assert usual["kinetic_margin_J"].isna().all()
    assert (long["kinetic_margin_J"] > 0).all() and long["kinetic_margin_J"].is_monotonic_decreasing  # more friction
    capsys.readouterr()
    assert main(["sweep", str(rig), *vary, "--t-end", "0.09", "-o", str(tmp_path / "long.csv"), "--resume"]) == 2
    assert "another --t-end" in capsys.readouterr().err
    assert main(["sweep", str(rig), *vary, "--t-end", "0", "-o", str(tmp_path / "zero.csv")]) == 2
    assert capsys.readouterr().err.strip().endswith("--t-end: t_end: must be a positive number of seconds")
    assert not (tmp_path / "zero.csv").exists()


def test_a_sweep_whose_every_run_failed_exits_1_with_one_line_and_keeps_its_table(rig, tmp_path, capsys):
    """Every run failed: status 1 and one line naming how many and the first reason (a script can tell);
    the table is still written, the record of each run's reason. One ok run keeps status 0, judged on the
    whole table: a --resume that only adds failed rows to a table with an ok row is a success, a --resume
    of an all-failed table fails again."""
    out = tmp_path / "failed.csv"
    assert main(["sweep", rig, "--vary", "pendulum.mass=-60:0:2", "--workers", "1", "-o", str(out), "-q"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"vcbmodel: simulation failed: every run of the sweep failed (2 of 2); the first, run 1: pendulum.mass: "
                   f"must be positive, got -60; the table {out} gives each run's reason"]
    rows = read_rows(out)
    assert [r[-1] for r in rows[1:]] == ["failed: pendulum.mass: must be positive, got -60",
                                         "failed: pendulum.mass: must be positive, got 0"]
    assert main(["sweep", rig, "--vary", "pendulum.mass=-60:0:2", "--workers", "1", "-o", str(out), "--resume", "-q"]) == 1
    assert "every run of the sweep failed (2 of 2)" in capsys.readouterr().err
    # runs 1 and 2 fail, run 3 (60 kg) is ok: a success, also when the ok row came first and --resume adds the failures
    mixed = tmp_path / "mixed.csv"
    assert main(["sweep", rig, "--vary", "pendulum.mass=-60:60:3", "--workers", "1", "-o", str(mixed), "-q"]) == 0
    lines = mixed.read_text().splitlines(keepends=True)
    mixed.write_text(lines[0] + lines[1] + lines[4])  # the fingerprint, the header, the ok run 3
    assert main(["sweep", rig, "--vary", "pendulum.mass=-60:60:3", "--workers", "1", "-o", str(mixed), "--resume", "-q"]) == 0
    assert capsys.readouterr().err == ""
    # to stdout, the same line names stdout
    assert main(["sweep", rig, "--vary", "pendulum.mass=-60:0:2", "--workers", "1", "-q"]) == 1
    captured = capsys.readouterr()
    assert len(captured.out.strip().splitlines()) == 3 and captured.err.strip().endswith("the table (stdout) gives each run's reason")


def test_a_t_end_spelt_out_at_its_default_resumes_like_none_and_another_is_refused(rig, tmp_path, capsys):
    """--t-end at the experiment's own duration runs the very runs no --t-end does: the same fingerprint
    (so tables written without it keep theirs, the rig's alone), either resumes the other's table; another
    --t-end is refused."""
    default = experiment_of("pendulum").default_duration
    usual, spelt = tmp_path / "usual.csv", tmp_path / "spelt.csv"
    vary = ["--vary", "friction.mu_k=0.13:0.13:1", "--workers", "1", "-q"]
    assert main(["sweep", rig, *vary, "-o", str(usual)]) == 0
    assert main(["sweep", rig, *vary, "--t-end", f"{default:g}", "-o", str(spelt)]) == 0
    first = usual.read_text().splitlines()[0]
    assert first == spelt.read_text().splitlines()[0] == S.table.fingerprint_line(
        S.table.rig_fingerprint(pendulum_data(), rig)).strip()
    assert main(["sweep", rig, *vary, "--t-end", f"{default:g}", "-o", str(usual), "--resume"]) == 0
    assert main(["sweep", rig, *vary, "-o", str(spelt), "--resume"]) == 0
    assert capsys.readouterr().err == ""
    assert main(["sweep", rig, *vary, "--t-end", f"{default / 2:g}", "-o", str(usual), "--resume"]) == 2
    assert "another --t-end" in capsys.readouterr().err


def test_a_sweep_states_its_duration_once_for_the_fingerprint_it_writes_and_resumes(rig, tmp_path, monkeypatch):
    """The duration the table's fingerprint hashes is decided once per sweep, resumed or not (it was
    worked out again for the file's first line); both lines agree, so a resume keeps the table."""
    calls = []
    stated = S._stated
    monkeypatch.setattr(S, "_stated", lambda *a: calls.append(a) or stated(*a))
    out = tmp_path / "once.csv"
    vary = ["--vary", "pendulum.mass=-60:0:2", "--workers", "1", "-o", str(out), "-q"]  # runs that fail at once
    assert main(["sweep", rig, *vary]) == 1 and len(calls) == 1
    first = out.read_text().splitlines()[0]
    assert main(["sweep", rig, *vary, "--resume"]) == 1 and len(calls) == 2
    assert out.read_text().splitlines()[0] == first and len(read_rows(out)) == 3

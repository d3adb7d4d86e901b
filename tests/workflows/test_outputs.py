"""What a command writes (docs/cli.md, "Output files"): never over an input, an existing result only
with --force, a lock on a sweep's table, SIGTERM stops the workers and leaves a resumable table, a full
disk and a bad cluster address give one line; fields the model does not read are refused; a breaker
that never closes is counted apart."""
import copy
import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from vcbmodel import parameters as P
from vcbmodel.analysis import sweep as S
from vcbmodel.analysis.sweep import executors
from vcbmodel.analysis.sweep.table import table_lock
from vcbmodel.app.cli import main
from vcbmodel.errors import InputError
from vcbmodel.experiments import experiment_of

HERE = Path(__file__).resolve().parents[1]  # tests/
GOOD_CAM = HERE / "bad_rigs" / "good_cam.rig.json"
GOOD_PENDULUM = HERE / "bad_rigs" / "good_pendulum.rig.json"


def one_error_line(capsys):
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "Traceback" not in err[0], err
    return err[0]


@pytest.fixture
def pendulum_rig(tmp_path):
    path = tmp_path / "p.rig.json"
    path.write_text(json.dumps(dict(copy.deepcopy(P.REFERENCE_PENDULUM), friction=dict(P.REFERENCE_PENDULUM_TRUTH))))
    return path


# --- never over an input, an existing result only with --force ----------------------------------------

def test_simulate_refuses_to_write_over_its_own_rig(tmp_path, capsys):
    rig = tmp_path / "x.rig.json"
    rig.write_bytes(GOOD_CAM.read_bytes())
    before = rig.read_bytes()
    assert main(["simulate", str(rig), "-o", str(rig), "--force"]) == 2
    assert "is an input of this command" in one_error_line(capsys)
    assert rig.read_bytes() == before


def test_simulate_refuses_the_same_file_for_the_csv_and_the_plot(tmp_path, capsys):
    """-o fig.png --plot fig.png wrote the CSV, then the figure over it, with status 0."""
    out = tmp_path / "fig.png"
    assert main(["simulate", str(GOOD_CAM), "--t-end", "0.002", "-o", str(out), "--plot", str(out)]) == 2
    assert "--plot: is also the -o file" in one_error_line(capsys) and not out.exists()


@pytest.mark.parametrize("name, words", [("closing.png", "--plot FILE.png"), ("result.json", "--json prints the JSON")])
def test_a_csv_output_named_as_a_figure_or_json_is_refused(tmp_path, capsys, name, words):
    """``simulate -o closing.png`` meant --plot, ``-o result.json`` meant --json: a CSV under such a name is a slip."""
    out = tmp_path / name
    assert main(["simulate", str(GOOD_CAM), "--t-end", "0.005", "-o", str(out)]) == 2
    line = one_error_line(capsys)
    assert line.startswith(f"vcbmodel: bad input: {out}: -o: writes the CSV table") and words in line
    assert main(["sweep", str(GOOD_CAM), "--vary", "friction.mu_k=0.1:0.2:2", "-o", str(out), "--workers", "1"]) == 2
    assert "writes the CSV table" in one_error_line(capsys)
    assert not out.exists() and not list(tmp_path.iterdir())


def test_an_existing_result_is_replaced_only_with_force(tmp_path, capsys):
    out = tmp_path / "sim.csv"
    out.write_text("mine\n")
    assert main(["simulate", str(GOOD_CAM), "--t-end", "0.002", "-o", str(out)]) == 2
    assert "--force" in one_error_line(capsys) and out.read_text() == "mine\n"
    assert main(["simulate", str(GOOD_CAM), "--t-end", "0.002", "-o", str(out), "--force"]) == 0
    assert out.read_text().startswith("# vcbmodel")


def test_diagnose_refuses_an_existing_plot_before_the_fit(tmp_path, capsys):
    plot = tmp_path / "d.png"
    plot.write_bytes(b"mine")
    t0 = time.perf_counter()
    demo = HERE.parent / "results" / "synthetic" / "demo_pendulum.csv"
    assert main(["diagnose", str(demo), "--plot", str(plot)]) == 2
    assert "--force" in one_error_line(capsys) and plot.read_bytes() == b"mine"
    assert time.perf_counter() - t0 < 20  # refused before any fit (a fit of this record takes longer)


def test_a_sweep_refuses_an_existing_table_without_force_or_resume(pendulum_rig, tmp_path, capsys):
    out = tmp_path / "t.csv"
    out.write_text("run,x,status\n1,2,ok\n")
    assert main(["sweep", str(pendulum_rig), "--vary", "friction.mu_k=0.1:0.2:2", "-o", str(out)]) == 2
    line = one_error_line(capsys)
    assert "--force" in line and "--resume" in line and out.read_text() == "run,x,status\n1,2,ok\n"


def test_a_second_writer_of_a_sweep_table_is_refused_at_once(pendulum_rig, tmp_path, capsys):
    out = tmp_path / "t.csv"
    with table_lock(str(out)):  # another sweep is writing it
        t0 = time.perf_counter()
        code = main(["sweep", str(pendulum_rig), "--vary", "friction.mu_k=0.1:0.2:2", "--workers", "1", "-o", str(out)])
        assert code == 2 and time.perf_counter() - t0 < 10
    assert "another vcbmodel sweep is writing this table" in one_error_line(capsys)
    assert not out.exists()
    # the lock goes with its holder: a sweep now runs
    assert main(["sweep", str(pendulum_rig), "--vary", "friction.mu_k=0.1:0.2:2", "--workers", "1", "-o", str(out)]) == 0
    assert not (tmp_path / ".t.csv.lock").exists()


# --- a full disk ---------------------------------------------------------------------------------------

@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="needs /dev/full")
@pytest.mark.parametrize("redirect", [False, True])
def test_a_full_disk_gives_one_line_and_no_traceback(redirect):
    cmd = [sys.executable, "-m", "vcbmodel", "simulate", str(GOOD_CAM), "--t-end", "0.002", "--quiet"]
    with open("/dev/full", "w") as full:
        p = subprocess.run(cmd if redirect else cmd + ["-o", "/dev/full"], stdout=full if redirect else None,
                           stderr=subprocess.PIPE, text=True, timeout=120)
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 1 and len(lines) == 1 and "Traceback" not in p.stderr
    assert "No space left on device" in lines[0] and ("stdout" if redirect else "/dev/full") in lines[0]


# --- SIGTERM -------------------------------------------------------------------------------------------

def _children(pid):
    out = subprocess.run(["ps", "-o", "pid=", "--ppid", str(pid)], capture_output=True, text=True).stdout
    return [int(x) for x in out.split()]


def test_sigterm_stops_the_workers_and_leaves_a_resumable_table(pendulum_rig, tmp_path):
    out = tmp_path / "t.csv"
    # on Exudyn: each run takes a tenth of a second, so the signal lands while the sweep runs (the
    # compiled path would finish all 40 before the first rows are seen)
    args = ["sweep", str(pendulum_rig), "--vary", "friction.mu_k=0.05:0.2:40", "--workers", "2", "-o", str(out),
            "--backend", "exudyn"]
    p = subprocess.Popen([sys.executable, "-m", "vcbmodel", *args], stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 120
    while time.time() < deadline and not (out.exists() and out.read_text().count("\n") >= 3):
        time.sleep(0.2)
    workers = _children(p.pid)
    assert workers, "the sweep should be running on worker processes"
    p.send_signal(signal.SIGTERM)
    p.wait(timeout=60)
    err = p.stderr.read()
    assert p.returncode == 128 + signal.SIGTERM and "Traceback" not in err and "--resume" in err
    time.sleep(0.5)
    alive = [w for w in workers if Path(f"/proc/{w}").exists() and "zombie" not in Path(f"/proc/{w}/status").read_text()]
    assert alive == []  # no orphans
    rows_before = out.read_text().count("\n") - 1
    assert 0 < rows_before < 40
    assert main([*args, "--resume"]) == 0
    lines = [line for line in out.read_text().splitlines() if not line.startswith("#")]  # the rig's fingerprint first
    assert len(lines) == 41 and [int(r.split(",")[0]) for r in lines[1:]] == list(range(1, 41))


# --- fields the model does not read; a breaker that never closes ---------------------------------------

@pytest.mark.parametrize("rig, path, effect", [
    (GOOD_PENDULUM, "friction.mu_s", "stribeck"),
    (GOOD_CAM, "closing_spring.mass", "spring_mass"),
])
def test_sweeping_a_field_the_model_does_not_read_is_refused(rig, path, effect, tmp_path, capsys):
    data = json.loads(Path(rig).read_text())
    data["model"]["effects"] = [e for e in data["model"]["effects"] if e != effect]
    if effect == "spring_mass":
        data["model"]["spring_model"] = "massless"
    if path == "friction.mu_s":
        data["friction"].update(mu_k=0.1, mu_s=0.15)
    f = tmp_path / "r.rig.json"
    f.write_text(json.dumps(data))
    assert main(["sweep", str(f), "--vary", f"{path}=0.3:0.6:2", "-o", str(tmp_path / "t.csv")]) == 2
    line = one_error_line(capsys)
    assert path in line and effect in line and "not used" in line
    assert not (tmp_path / "t.csv").exists()


def test_sweeping_a_limit_is_refused(tmp_path, capsys):
    """A sweep judges no limits (its table holds the figures): ``--vary breaker.limits.closing_time.max=60:80:3``
    ran three identical rows, as if a sweep's table said which pass."""
    rig = Path(__file__).resolve().parents[2] / "results" / "synthetic" / "vcb_closing.rig.json"
    out = tmp_path / "t.csv"
    assert main(["sweep", str(rig), "--vary", "breaker.limits.closing_time.max=60:80:3", "-o", str(out)]) == 2
    line = one_error_line(capsys)
    assert "breaker.limits.closing_time.max" in line and "judges no limits" in line and not out.exists()


def test_sweeping_a_coils_release_is_refused(tmp_path, capsys):
    """A sweep's closings start at the latch release and its table has no time from the coil: ``--vary
    breaker.closing_release.voltage=100:240:3`` ran three identical rows."""
    rig = Path(__file__).resolve().parents[2] / "results" / "synthetic" / "vcb_cycle.rig.json"
    out = tmp_path / "t.csv"
    for path in ("breaker.closing_release.voltage=100:240:3", "breaker.opening_release.resistance=20:40:3"):
        assert main(["sweep", str(rig), "--vary", path, "-o", str(out)]) == 2
        line = one_error_line(capsys)
        assert path.split("=")[0] in line and "time from the coil" in line and not out.exists()


def test_a_closing_without_a_closing_time_is_not_closed_not_ok():
    record = experiment_of("vcb_closing")
    ok = dict.fromkeys(record.figure_columns, 1.0)
    assert record.run_status(ok) == "ok"
    assert record.run_status({**ok, "closing_time_s": None}) == "not_closed"
    assert record.run_status({**ok, "closing_time_s": float("nan")}) == "not_closed"
    assert experiment_of("cam_drop").run_status({}) == "ok"  # a cam drop has nothing that can fail to happen


def test_every_experiment_states_its_sweep_columns_with_units():
    for name in ("pendulum", "cam_drop", "vcb_closing"):
        record = experiment_of(name)
        assert record.figure_columns and all(u for _, u in record.figure_units)


# --- a cluster address that is not one ----------------------------------------------------------------

@pytest.fixture
def silent_port():
    """A port that accepts connections and says nothing (like a web server waiting for a request)."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(4)
    conns = []
    stop = threading.Event()

    def accept():
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                conns.append(server.accept()[0])
            except OSError:
                pass

    threading.Thread(target=accept, daemon=True).start()
    yield server.getsockname()[1]
    stop.set()
    server.close()


def _closed_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


@pytest.mark.parametrize("address, words", [
    ("foo", "not a scheduler address"),
    ("http://127.0.0.1:8786", "not a scheduler address"),
    ("tcp://no-such-host.invalid:8786", "unknown host"),
    ("CLOSED", "cannot connect"),
    ("SILENT", "is not a Dask scheduler"),
])
def test_a_bad_scheduler_fails_in_seconds_with_one_line(address, words, pendulum_rig, tmp_path, capsys, silent_port):
    address = {"CLOSED": f"tcp://127.0.0.1:{_closed_port()}", "SILENT": f"tcp://127.0.0.1:{silent_port}"}.get(
        address, address)
    out = tmp_path / "t.csv"
    t0 = time.perf_counter()
    code = main(["sweep", str(pendulum_rig), "--vary", "friction.mu_k=0.1:0.2:2", "--scheduler", address, "-o", str(out)])
    assert code == 2 and time.perf_counter() - t0 < 10
    assert words in one_error_line(capsys)
    assert not out.exists()  # no header-only table left behind


def test_a_scheduler_without_workers_is_refused_and_leaves_no_table(pendulum_rig, tmp_path, capsys, monkeypatch):
    distributed = pytest.importorskip("distributed")
    monkeypatch.setattr(executors, "WORKER_WAIT", 1.0)
    with distributed.LocalCluster(n_workers=0, processes=False, dashboard_address=None, host="127.0.0.1",
                                  protocol="tcp") as cluster:
        out = tmp_path / "t.csv"
        code = main(["sweep", str(pendulum_rig), "--vary", "friction.mu_k=0.1:0.2:2", "--scheduler",
                     cluster.scheduler_address, "-o", str(out)])
    assert code == 2 and "no workers" in one_error_line(capsys)
    assert not out.exists()


def test_sweep_api_refuses_to_replace_a_table_without_force(pendulum_rig, tmp_path):
    out = tmp_path / "t.csv"
    S.sweep(str(pendulum_rig), ["friction.mu_k=0.1:0.2:2"], workers=1, output=str(out), verbose=False)
    with pytest.raises(InputError, match="--force"):
        S.sweep(str(pendulum_rig), ["friction.mu_k=0.1:0.2:2"], workers=1, output=str(out), verbose=False)
    again = S.sweep(str(pendulum_rig), ["friction.mu_k=0.1:0.2:2"], workers=1, output=str(out), force=True,
                    verbose=False)
    assert len(again) == 2

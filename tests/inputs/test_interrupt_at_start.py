"""Ctrl-C while the command is still loading its modules ends it in one line, as later (no traceback
from inside an import)."""
import builtins
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from vcbmodel.app import entry


def test_an_interrupt_while_the_command_loads_is_one_line(monkeypatch, capsys):
    real = builtins.__import__

    def interrupted(name, globals=None, locals=None, fromlist=(), level=0):
        if level == 1 and name == "cli":
            raise KeyboardInterrupt
        return real(name, globals, locals, fromlist, level)

    monkeypatch.setattr(builtins, "__import__", interrupted)
    assert entry.main(["--version"]) == entry.INTERRUPTED_STATUS
    assert capsys.readouterr().err == entry.INTERRUPTED + "\n"


def test_the_installed_command_interrupted_at_once_prints_no_traceback():
    command = Path(sys.executable).parent / "vcbmodel"
    p = subprocess.Popen([str(command), "--version"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         env=dict(os.environ, PYTHONPATH=str(Path(__file__).resolve().parents[2])))
    time.sleep(0.4)  # within the second or more its imports take
    p.send_signal(signal.SIGINT)
    out, err = p.communicate(timeout=60)
    assert "Traceback" not in err
    assert err.strip() in ("", entry.INTERRUPTED) or out.startswith("vcbmodel")  # done before the signal came
    assert p.returncode != 0 or out.startswith("vcbmodel")

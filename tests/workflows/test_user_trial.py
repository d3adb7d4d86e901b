"""What a new user's trial found: the command line's figures are the sweep's, a datasheet field that
changes nothing is not swept, a refused backend is one line, outputs are readable by others."""
import json
import os
import stat

import pandas as pd
import pytest

from vcbmodel import parameters as P
from vcbmodel.app.cli import main

from conftest import write_rig


@pytest.fixture
def breaker(tmp_path):
    return write_rig(tmp_path, P.REFERENCE_BREAKER, "breaker")


def test_simulate_summary_gives_the_sweeps_figures(breaker, tmp_path, capsys):
    assert main(["simulate", str(breaker), "-o", str(tmp_path / "c.csv"), "-q"]) == 0
    printed = capsys.readouterr().out
    def shown(words):  # the value printed on the whole breaker's line, in ms
        line = next(ln for ln in printed.splitlines() if ln.strip().startswith(words))
        return float(line.split(" ms ", 1)[1].split()[0])
    assert main(["sweep", str(breaker), "--vary", "friction.mu_k=0.13:0.13:1", "-o", str(tmp_path / "s.csv"), "-q",
                 "--workers", "1"]) == 0
    row = pd.read_csv(tmp_path / "s.csv", comment="#").iloc[0]
    # printed to 4 significant figures, in ms
    assert shown("closing time (last pole)") == pytest.approx(1e3 * row["closing_time_s"], abs=0.006)
    assert shown("pole spread") == pytest.approx(1e3 * row["pole_spread_s"], abs=6e-4)


def test_a_datasheet_field_that_changes_nothing_is_not_swept(breaker, tmp_path, capsys):
    # a rig that gives the spring's stiffness and mass only (the reference breaker also gives its wire and
    # coil diameters, for check's stress: with those, active_coils would complete a datasheet)
    data = json.loads(breaker.read_text())
    for key in ("wire_diameter", "coil_diameter"):
        data["closing_spring"].pop(key, None)
    plain = write_rig(tmp_path, data, "plain")
    assert main(["sweep", str(plain), "--vary", "closing_spring.active_coils=13:17:3",
                 "-o", str(tmp_path / "s.csv")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "closing_spring.active_coils" in err[0] and "not used" in err[0]
    assert not (tmp_path / "s.csv").exists()
    # with the spring given by its datasheet, the same field is a design variable
    data = json.loads(breaker.read_text())
    spring = {k: v for k, v in data["closing_spring"].items() if k not in ("stiffness", "mass")}
    spring.update(wire_diameter=0.0078, coil_diameter=0.047, active_coils=15, shear_modulus=79.3e9)
    data["closing_spring"] = spring
    sheet = write_rig(tmp_path, data, "sheet")
    assert main(["sweep", str(sheet), "--vary", "closing_spring.active_coils=13:17:3", "-o", str(tmp_path / "t.csv"),
                 "-q"]) == 0
    assert pd.read_csv(tmp_path / "t.csv", comment="#")["closing_time_s"].nunique() == 3


def test_compiled_ancf_is_refused_in_one_line_before_any_work(breaker, tmp_path, capsys):
    assert main(["simulate", str(breaker), "--backend", "compiled", "--spring-model", "ancf",
                 "-o", str(tmp_path / "x.csv")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--spring-model" in err[0] and "backend: backend" not in err[0]
    assert not (tmp_path / "x.csv").exists()


def test_outputs_are_readable_by_others(breaker, tmp_path):
    old = os.umask(0o022)
    try:
        # 5 ms: no pole touches yet: no closed contact force to judge, as no closing time (status 0)
        assert main(["simulate", str(breaker), "-o", str(tmp_path / "c.csv"), "-q", "--t-end", "0.005"]) == 0
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "c.csv").stat().st_mode) == 0o644

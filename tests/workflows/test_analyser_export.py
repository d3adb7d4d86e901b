"""A breaker analyser's export reads as written: time in ms, travel in mm, one channel per pole, units
in the header (``t [ms]``, ``pole_1_travel [mm]``) or in a units row under it; and diagnose gives a
closing record exported so the same verdict as the record in SI units."""
import json
import shutil

import numpy as np
import pytest

from vcbmodel import parameters as P
from vcbmodel.app.cli import main
from vcbmodel.experiments.loading import load_pair, load_record, load_rig

from conftest import ROOT, write_rig

CLOSING = ROOT / "results" / "synthetic" / "vcb_closing"


def si_rows(path):
    """(comments, header, rows) of a record written in SI units."""
    lines = path.read_text().splitlines()
    comments = [line for line in lines if line.startswith("#")]
    body = [line for line in lines if not line.startswith("#")]
    return comments, body[0].split(","), np.array([[float(c) for c in line.split(",")] for line in body[1:]])


def analyser_export(src, dst, units_row=False, separator=","):
    """``src`` (SI) as an analyser writes it: t in ms, travels in mm, contacts as they are; the units
    in the header (``t [ms]``) or in a row under it; ``;`` with decimal commas if asked."""
    comments, header, rows = si_rows(src)
    unit = {"t": "ms", "follower_displacement": "mm"}
    for name in header:
        unit.setdefault(name, "mm" if name.endswith("_travel") else "-" if name.endswith("_contact") else None)
    keep = [j for j, name in enumerate(header) if unit[name] is not None]
    scale = np.array([1e3 if unit[header[j]] in ("ms", "mm") else 1.0 for j in keep])
    values = rows[:, keep] * scale
    names = ["T" if header[j] == "t" else header[j] for j in keep]
    if units_row:
        head = [separator.join(names), separator.join(unit[header[j]] for j in keep)]
    else:
        head = [separator.join(f"{n} [{unit[header[j]]}]" for n, j in zip(names, keep))]
    text = [separator.join(repr(float(v)) for v in row) for row in values]
    if separator == ";":
        text = [line.replace(".", ",") for line in text]
    dst.write_text("\n".join(comments + head + text) + "\n")
    return [header[j] for j in keep]


@pytest.mark.parametrize("units_row, separator", [(False, ","), (True, ";")])
def test_a_per_pole_export_in_ms_and_mm_reads_as_the_si_record(tmp_path, units_row, separator):
    rig_path = write_rig(tmp_path, P.REFERENCE_BREAKER, "closing")
    csv = tmp_path / "closing.csv"
    assert main(["simulate", str(rig_path), "--backend", "fast", "--t-end", "0.045", "-o", str(csv), "-q"]) == 0
    rig = load_rig(rig_path)
    si = load_record(csv, rig)
    export = tmp_path / "analyser.csv"
    kept = analyser_export(csv, export, units_row, separator)
    assert {"pole_1_travel", "pole_3_contact"} <= set(kept) and "pole_1_velocity" not in kept
    read = load_record(export, rig)
    assert np.allclose(read.t, si.t, rtol=0, atol=1e-12)
    for name in kept[1:]:
        assert np.allclose(read.channel(name), si.channel(name), rtol=1e-12, atol=1e-15), name
    assert set(read.channel("pole_2_contact")) == {0.0, 1.0}


def test_diagnose_gives_an_analyser_export_the_verdict_of_the_si_record(tmp_path, capsys):
    export = tmp_path / "closing_ms.csv"
    analyser_export(CLOSING.with_suffix(".csv"), export)
    shutil.copy(CLOSING.with_suffix(".rig.json"), tmp_path / "closing_ms.rig.json")
    assert "T [ms],follower_displacement [mm]" in export.read_text()
    reports = []
    for record in (CLOSING.with_suffix(".csv"), export):
        assert main(["diagnose", str(record), "--json", "--processes", "1", "-q"]) == 0
        reports.append(json.loads(capsys.readouterr().out))
    si, ms = reports
    assert ms["explained"] == si["explained"] and ms["missing_effects"] == si["missing_effects"]
    for name, value in si["fitted"].items():
        assert ms["fitted"][name] == pytest.approx(value, rel=1e-4, abs=1e-9), name
    # the record is the same in SI: its release is found at the same time
    _, plain = load_pair(CLOSING.with_suffix(".csv"))
    _, converted = load_pair(export)
    assert np.allclose(converted.channel("follower_displacement"), plain.channel("follower_displacement"), atol=1e-15)

"""Records as instruments export them (a second new user's trial): an oscilloscope's CSV with its
preamble ('Record Length', 'Sample Interval', ... above the header), two records pasted side by
side, a summary line below the data, an analyser's record of the poles alone. Each is read as meant
or refused with one line naming the file, the line or column, and the cause."""
import numpy as np
import pytest

from vcbmodel.app.cli import main
from vcbmodel.errors import InputError
from vcbmodel.experiments.loading import load_pair
from vcbmodel.records.measurement import load_measurement

from conftest import ROOT

PENDULUM = ROOT / "results" / "synthetic" / "pendulum_10deg"
#: A Tektronix MSO's CSV preamble (key, value lines above the header), as the scope saves it.
TEK_PREAMBLE = ["Model,MSO44", "Firmware Version,1.30.5", "", "Waveform Type,ANALOG", "Point Format,Y",
                "Horizontal Units,s", "Sample Interval,0.001", "Record Length,6001", "Gating,0.0%,100.0%",
                "Vertical Units,V", "Vertical Scale,0.05", ",", ",", "Label,"]


def pendulum_rows():
    lines = PENDULUM.with_suffix(".csv").read_text().splitlines()
    return [line for line in lines if not line.startswith("#")][1:]


def write(tmp_path, name, lines, ends="\r\n"):
    (tmp_path / f"{name}.csv").write_text(ends.join(lines) + ends)
    (tmp_path / f"{name}.rig.json").write_text(PENDULUM.with_suffix(".rig.json").read_text())
    return tmp_path / f"{name}.csv"


def refusal(path, capsys):
    assert main(["identify", str(path), "--law", "hybrid"]) == 2
    out, err = capsys.readouterr()
    err = err.strip()
    assert out == "" and "\n" not in err and "Traceback" not in err
    return err


def test_an_oscilloscopes_preamble_above_the_header_is_read_as_comments(tmp_path):
    _, plain = load_pair(PENDULUM.with_suffix(".csv"))
    path = write(tmp_path, "tek", TEK_PREAMBLE + ["TIME,pendulum_angle"] + pendulum_rows())
    _, scope = load_pair(path)
    assert np.array_equal(scope.t, plain.t)
    assert np.array_equal(scope.channel("pendulum_angle"), plain.channel("pendulum_angle"))
    assert "Record Length: 6001" in scope.comments and "Sample Interval: 0.001" in scope.comments


def test_a_preamble_whose_header_does_not_name_the_time_is_refused_naming_its_first_line(tmp_path, capsys):
    path = write(tmp_path, "keysight", ["x-axis,1", "second,Volt"] + pendulum_rows())
    err = refusal(path, capsys)
    assert "keysight.csv: line 1: the first column must be the time" in err and "'x-axis'" in err


def test_a_scopes_units_row_in_words_reads_the_time_in_seconds(tmp_path, capsys):
    _, plain = load_pair(PENDULUM.with_suffix(".csv"))
    _, scope = load_pair(write(tmp_path, "keysight", ["t,pendulum_angle", "second,rad"] + pendulum_rows()))
    assert np.array_equal(scope.t, plain.t)
    err = refusal(write(tmp_path, "volts", ["t,pendulum_angle", "second,Volt"] + pendulum_rows()), capsys)
    assert "volts.csv: line 2, column 'pendulum_angle': the units row says 'Volt'" in err


def test_an_older_scope_layout_with_the_data_in_later_columns_is_refused_saying_so(tmp_path, capsys):
    """A Tektronix TDS CSV: settings in columns 1-3 of the first lines, the data in columns 4-5."""
    rows = pendulum_rows()
    settings = ["Record Length,6001,", "Sample Interval,0.001,", "Trigger Point,0,"]
    lines = [f"{settings[k] if k < 3 else ',,'},{row}" for k, row in enumerate(rows)]
    err = refusal(write(tmp_path, "tds", lines), capsys)
    assert "tds.csv: line 4: the first column is empty and the values start in column 4" in err


def test_a_units_row_above_the_header_is_refused_not_read_as_a_preamble(tmp_path, capsys):
    err = refusal(write(tmp_path, "above", ["s,rad", "t,pendulum_angle"] + pendulum_rows()), capsys)
    assert "above.csv: line 1: reads as a units row (s, rad) with no header above it" in err
    err = refusal(write(tmp_path, "typo", ["tim,pendulum_angle", "ms,rad"] + pendulum_rows()), capsys)
    assert "typo.csv: line 2: reads as a units row (ms, rad)" in err and "line 1, does not start with the time" in err
    assert "got 'tim'" in err


def test_a_sample_interval_the_data_does_not_have_is_refused(tmp_path, capsys):
    preamble = [line.replace("0.001", "0.0001") for line in TEK_PREAMBLE]
    err = refusal(write(tmp_path, "tek", preamble + ["TIME,pendulum_angle"] + pendulum_rows()), capsys)
    assert "tek.csv: line 7: the preamble's sample interval 0.0001 s" in err and "0.001 s" in err


@pytest.mark.parametrize("header, pad, column", [("t,pendulum_angle,t,pendulum_angle", ",", "column 3"),
                                                 ("t,pendulum_angle,,t,pendulum_angle", ",,", "column 3")])
def test_two_records_side_by_side_are_refused_as_such(tmp_path, capsys, header, pad, column):
    rows = [f"{row}{pad}{row}" for row in pendulum_rows()]
    err = refusal(write(tmp_path, "side", [header] + rows), capsys)
    assert f"side.csv: line 1, {column}" in err and "two records side by side" in err


@pytest.mark.parametrize("tail", [["Mean,0.0123", "Max,0.1745"], ["6001 samples"]])
def test_a_summary_line_below_the_data_is_refused_saying_so(tmp_path, capsys, tail):
    lines = ["t,pendulum_angle"] + pendulum_rows() + tail
    err = refusal(write(tmp_path, "summ", lines), capsys)
    assert f"summ.csv: line {len(lines) - len(tail) + 1}:" in err and "below the data" in err


def test_rows_broken_from_the_first_or_the_middle_on_are_not_called_a_summary(tmp_path, capsys):
    """Decimal commas in a comma-separated file: every row fails; that is no summary below the data."""
    rows = [row.replace(".", ",") for row in pendulum_rows()]
    err = refusal(write(tmp_path, "commas", ["t,pendulum_angle"] + rows), capsys)
    assert "commas.csv: line 2: has 4 values" in err and "below the data" not in err
    rows = pendulum_rows()
    err = refusal(write(tmp_path, "half", ["t,pendulum_angle"] + rows[:100] + [r.replace(".", ",") for r in rows[100:]]),
                  capsys)
    assert "half.csv: line 102: has 4 values" in err and "below the data" not in err


def test_a_text_row_inside_the_data_is_not_called_a_summary(tmp_path, capsys):
    rows = pendulum_rows()
    lines = ["t,pendulum_angle"] + rows[:100] + ["Mean,0.0123"] + rows[100:]
    err = refusal(write(tmp_path, "mid", lines), capsys)
    assert "mid.csv: line 102: value 'Mean' is not a number" in err and "below the data" not in err


def test_a_sample_interval_in_a_tds_scopes_capital_seconds_is_checked(tmp_path, capsys):
    """An older Tektronix writes 'Horizontal Units,S': the check was skipped, so a time column in the
    wrong unit read on unrefused."""
    preamble = [line.replace("0.001", "0.0001").replace("Horizontal Units,s", "Horizontal Units,S")
                for line in TEK_PREAMBLE]
    err = refusal(write(tmp_path, "tds", preamble + ["TIME,pendulum_angle"] + pendulum_rows()), capsys)
    assert "tds.csv: line 7: the preamble's sample interval 0.0001 s" in err


def test_an_index_column_before_the_time_is_refused_naming_it_not_an_older_scope(tmp_path, capsys):
    """pandas' to_csv writes its row index first under an empty header cell: the refusal called it an
    older Tektronix layout."""
    rows = [f"{k},{row}" for k, row in enumerate(pendulum_rows())]
    err = refusal(write(tmp_path, "frame", [",t,pendulum_angle"] + rows), capsys)
    assert "frame.csv: line 1: the first column has no name and the time is column 2: an index column" in err
    assert "Tektronix" not in err


@pytest.mark.parametrize("tail, said", [("0.004,nan", "value is not finite"), ("0.00", "has 1 values")])
def test_a_broken_last_sample_is_not_called_a_summary(tmp_path, capsys, tail, said):
    """A NaN sample (a sensor's dropout) or a line cut short as the last row was called 'a summary line
    below the data, not a sample'."""
    rows = pendulum_rows()
    lines = ["t,pendulum_angle"] + rows + [tail]
    err = refusal(write(tmp_path, "last", lines), capsys)
    assert f"last.csv: line {len(lines)}" in err and said in err and "summary" not in err


def test_a_units_row_above_the_header_with_an_empty_cell_is_refused(tmp_path):
    """'ms,,deg' (an empty cell for the contact channel, as a units row may have) above the header was
    kept as a preamble comment and the time read in seconds: a record 1000 times too long."""
    path = tmp_path / "above.csv"
    path.write_text("ms,,deg\nt,pole_1_contact,pendulum_angle\n0,0,10\n1,0,11\n2,1,12\n3,1,13\n")
    with pytest.raises(InputError, match=r"above.csv: line 1: reads as a units row \(ms, , deg\) with no header above it"):
        load_measurement(path)


@pytest.mark.parametrize("n", [100, 101, 2000])
def test_a_sample_interval_is_checked_on_a_time_column_written_to_fewer_digits(tmp_path, n):
    """2.5 us samples with the time in whole microseconds (steps of 2 and 3 us): the median step, 2 us
    for an even count of samples, refused a record that has the stated interval."""
    path = tmp_path / "fast.csv"
    t = np.arange(n) * 2.5e-6
    path.write_text("\n".join(["Sample Interval,2.5e-06", "TIME,ch1"] + [f"{x:.6f},{k}" for k, x in enumerate(t)]) + "\n")
    assert load_measurement(path).t.size == n
    path.write_text(path.read_text().replace("2.5e-06", "2e-06"))
    with pytest.raises(InputError, match="sample interval 2e-06 s is not the data's time step"):
        load_measurement(path)


@pytest.mark.parametrize("pad", [",", ",,", ",,,,"])
def test_a_header_padded_with_empty_cells_reads_as_the_plain_record(tmp_path, capsys, pad):
    """Excel pads every row to the sheet's widest (``t,pendulum_angle,,``): the empty columns are no
    second record; the values are the unpadded file's. A value under an unnamed column stays refused."""
    rows = pendulum_rows()
    plain = load_measurement(write(tmp_path, "plain", ["t,pendulum_angle"] + rows))
    padded = load_measurement(write(tmp_path, "padded", ["t,pendulum_angle" + pad] + [r + pad for r in rows]))
    assert np.array_equal(padded.t, plain.t) and list(padded.channels) == ["pendulum_angle"]
    assert np.array_equal(padded.channels["pendulum_angle"], plain.channels["pendulum_angle"])
    units = load_measurement(write(tmp_path, "units", ["t,pendulum_angle" + pad, "s,rad" + pad] + [r + pad for r in rows]))
    assert np.array_equal(units.channels["pendulum_angle"], plain.channels["pendulum_angle"])
    stray = ["t,pendulum_angle" + pad] + [r + pad for r in rows]
    stray[5] = rows[4] + ",7" + pad[1:]  # a value in a column the header leaves unnamed
    err = refusal(write(tmp_path, "stray", stray), capsys)
    assert "stray.csv: line 6: has " in err and "the header has 2" in err
    assert "a value under a column the header does not name" in err and "decimal comma" not in err


def test_a_padded_semicolon_export_with_decimal_commas_reads(tmp_path):
    rows = [r.replace(",", ";").replace(".", ",") + ";;" for r in pendulum_rows()]
    padded = load_measurement(write(tmp_path, "excel", ["t;pendulum_angle;;"] + rows))
    plain = load_measurement(write(tmp_path, "plain", ["t,pendulum_angle"] + pendulum_rows()))
    assert np.array_equal(padded.channels["pendulum_angle"], plain.channels["pendulum_angle"])

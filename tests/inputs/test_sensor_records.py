"""Records as sensors and loggers leave them: an encoder that wraps at a full turn (read unwrapped, the
same record as the shaft turned), a channel clipped at the sensor's range or a dropout held or zeroed
(refused: fitted as motion it would be a wrong diagnosis), a quantised sensor (neither: its turning points
and rests hold a value too, and are read as they are), and a UTF-16 export (read as its text)."""
import logging
import math

import numpy as np
import pytest

from vcbmodel.app.cli import main
from vcbmodel.errors import InputError
from vcbmodel.experiments.loading import load_pair
from vcbmodel.records.integrity import check_held_values, unwrap_turns

from conftest import ROOT

SYNTHETIC = ROOT / "results" / "synthetic"
PENDULUM, CAM = SYNTHETIC / "pendulum_10deg", SYNTHETIC / "demo_cam"


def write(tmp_path, name, source, t, y, header=None, encoding="utf-8", sep=","):
    """``t``, ``y`` under ``header`` (the source's channel) as ``name.csv``, beside a copy of the source's rig."""
    _, clean = load_pair(source.with_suffix(".csv"))
    channel = next(iter(clean.channels))
    lines = [header or f"t{sep}{channel}"] + [f"{a:.7f}{sep}{b:.9g}" for a, b in zip(t, y)]
    (tmp_path / f"{name}.csv").write_text("\r\n".join(lines) + "\r\n", encoding=encoding)
    (tmp_path / f"{name}.rig.json").write_text(source.with_suffix(".rig.json").read_text())
    return tmp_path / f"{name}.csv"


def clean(source):
    _, m = load_pair(source.with_suffix(".csv"))
    return m.t, next(iter(m.channels.values()))


def refused(capsys, path, tmp_path):
    """``diagnose`` refuses ``path``: status 2, one line naming the file, nothing on stdout or written."""
    plot = tmp_path / "out" / "d.png"
    plot.parent.mkdir()
    assert main(["diagnose", str(path), "--json", "--plot", str(plot)]) == 2
    out, err = capsys.readouterr()
    err = err.strip()
    assert out == "" and "\n" not in err and "Traceback" not in err and path.name in err, err
    assert list(plot.parent.iterdir()) == []
    return err


@pytest.mark.parametrize("source,wrap", [(CAM, "pm_pi"), (PENDULUM, "deg_360"), (PENDULUM, "zero_to_2pi")])
def test_an_encoder_that_wraps_at_a_full_turn_is_read_as_the_shaft_turned(tmp_path, caplog, source, wrap):
    t, y = clean(source)
    channel = "cam_angle" if source == CAM else "pendulum_angle"
    if wrap == "pm_pi":  # an absolute encoder counting -180..180 deg: the cam passes 180 deg
        path = write(tmp_path, wrap, source, t, (y + math.pi) % (2 * math.pi) - math.pi)
    elif wrap == "deg_360":
        path = write(tmp_path, wrap, source, t, np.degrees(y) % 360, header=f"t,{channel} [deg]")
    else:  # 0..360 deg: the pendulum swings through its zero, many times, noise flicking across it
        path = write(tmp_path, wrap, source, t, y % (2 * math.pi))
    assert np.ptp(load_pair(path)[1].channel(channel)) > 0
    with caplog.at_level(logging.WARNING, logger="vcbmodel"):
        _, read = load_pair(path)
    assert np.allclose(read.channel(channel), y, atol=1e-7, rtol=0)
    assert "wraps at a full turn" in caplog.text


def test_a_wrapped_cam_record_gets_the_clean_records_diagnosis(tmp_path, capsys):
    import json
    t, y = clean(CAM)
    path = write(tmp_path, "wrapped", CAM, t, (y + math.pi) % (2 * math.pi) - math.pi)
    verdicts = []
    for record in (CAM.with_suffix(".csv"), path):
        assert main(["diagnose", str(record), "--json"]) == 0
        d = json.loads(capsys.readouterr().out)
        verdicts.append((d["explained"], d["final_effects"], round(d["rms_after"], 6)))
    assert verdicts[0] == verdicts[1] and verdicts[0][0] is True


@pytest.mark.parametrize("source,what", [(CAM, "top"), (CAM, "bottom"), (PENDULUM, "top"), (PENDULUM, "bottom")])
def test_a_channel_clipped_at_its_range_is_refused_not_fitted(tmp_path, capsys, source, what):
    """Before this check the cam record clipped at 85 % of its travel was diagnosed as missing viscous
    friction: a plausible, wrong answer."""
    t, y = clean(source)
    lo, hi = y.min(), y.max()
    clipped = np.minimum(y, lo + 0.85 * (hi - lo)) if what == "top" else np.maximum(y, lo + 0.15 * (hi - lo))
    err = refused(capsys, write(tmp_path, f"clip_{what}", source, t, clipped), tmp_path)
    assert "column" in err and "clipped" in err and ("largest" if what == "top" else "smallest") in err


@pytest.mark.parametrize("fill", ["held", "zeros"])
@pytest.mark.parametrize("source", [CAM, PENDULUM])
def test_a_dropout_filled_by_the_logger_is_refused_naming_when(tmp_path, capsys, source, fill):
    t, y = clean(source)
    i = t.size // 3
    y = y.copy()
    y[i:i + 20] = y[i] if fill == "held" else 0.0
    if source == PENDULUM and fill == "held":
        y[i:i + 40] = y[i]  # a pendulum at 1 kHz moves little in 20 ms: a short hold is harmless and let be
    err = refused(capsys, write(tmp_path, f"dropout_{fill}", source, t, y), tmp_path)
    assert "exactly over" in err and f"t = {t[i]:.6g}" in err and ("zeros" if fill == "zeros" else "last value") in err


@pytest.mark.parametrize("smooth", [False, True])
@pytest.mark.parametrize("levels", [4096, 256, 64, 16])
@pytest.mark.parametrize("noise", [0.0, 0.3])
@pytest.mark.parametrize("name", ["pendulum_10deg", "pendulum_15deg", "held_out_10deg", "demo_cam", "cam_drop_m0_1kg",
                                  "vcb_closing"])
def test_a_quantised_sensors_turning_points_and_rests_are_not_called_held(name, noise, levels, smooth):
    """A sensor with few levels (an encoder, a digitiser with few bits) holds a value at each turning
    point and rest; with or without noise before the rounding (``smooth``: the record's own noise first
    taken out by a 15-sample moving average, a quiet sensor), none of it is refused."""
    from scipy.ndimage import uniform_filter1d
    _, m = load_pair((SYNTHETIC / name).with_suffix(".csv"))
    channel, y = next(iter(m.channels.items()))
    y = uniform_filter1d(y, 15) if smooth else y
    q = float(np.ptp(y)) / levels
    rng = np.random.default_rng(levels)
    rounded = np.round((y + noise * q * rng.standard_normal(y.size)) / q) * q
    check_held_values(m.t, rounded, name, channel)


def test_unwrapping_leaves_a_record_without_whole_turn_steps_alone():
    y = np.linspace(0.0, 3.0, 200) + 1e-3 * np.random.default_rng(1).standard_normal(200)
    same, wraps = unwrap_turns(y)
    assert wraps == 0 and np.array_equal(same, y)
    jump = y.copy()
    jump[100:] += 2 * math.pi  # a whole turn between samples whose neighbours are also far apart: not a wrap
    jump[99] += 1.0
    assert unwrap_turns(jump)[1] == 0


def test_a_utf16_export_reads_as_the_same_record(tmp_path):
    """Excel's "Unicode text": UTF-16 with its byte-order mark, tab-separated, Windows line ends."""
    t, y = clean(PENDULUM)
    path = write(tmp_path, "unicode_text", PENDULUM, t, y, header="t\tpendulum_angle", encoding="utf-16", sep="\t")
    assert path.read_bytes()[:2] in (b"\xff\xfe", b"\xfe\xff")
    _, read = load_pair(path)
    assert np.array_equal(read.t, t) and np.array_equal(read.channel("pendulum_angle"), y)
    broken = tmp_path / "broken.csv"
    broken.write_bytes(b"\xff\xfet\x00,\x00\x00\xd8")  # a lone surrogate: not UTF-16
    with pytest.raises(InputError, match="UTF-16"):
        load_pair(broken, PENDULUM.with_suffix(".rig.json"))


@pytest.mark.parametrize("source", [CAM, PENDULUM])
def test_an_angle_record_with_its_sign_turned_is_refused_not_fitted_as_a_mirror_image(tmp_path, capsys, source):
    """Before this check identify fitted the turned pendulum record (mu_k 0.287 for 0.130, a warning only)
    and diagnose called the turned cam record not explained (rms 2.2 rad)."""
    t, y = clean(source)
    err = refused(capsys, write(tmp_path, "turned", source, t, -y), tmp_path)
    assert "sign turned" in err and "initial_angle" in err


def test_a_time_column_of_sample_numbers_is_refused_saying_so(tmp_path, capsys):
    t, y = clean(CAM)
    err = refused(capsys, write(tmp_path, "numbers", CAM, np.arange(t.size), y), tmp_path)
    assert "column 't'" in err and "sample numbers" in err


@pytest.mark.parametrize("form", ["iso", "iso_t", "time_of_day", "semicolon"])
def test_a_time_column_of_clock_times_reads_as_seconds_from_the_first(tmp_path, form):
    """A logger's clock (an ISO date and time, or the time of day) in the time column: seconds from the
    first sample's clock time, to the microsecond."""
    import datetime as dt
    t, y = clean(PENDULUM)
    start = dt.datetime(2026, 11, 27, 23, 50, 0)
    stamps = [start + dt.timedelta(seconds=float(a)) for a in t]
    cell = {"iso": lambda s: s.isoformat(sep=" ", timespec="microseconds"),
            "iso_t": lambda s: s.isoformat(timespec="milliseconds"),
            "time_of_day": lambda s: s.time().isoformat(timespec="milliseconds"),
            "semicolon": lambda s: s.isoformat(sep=" ", timespec="milliseconds").replace(".", ",")}[form]
    sep, value = (";", lambda v: f"{v:.9g}".replace(".", ",")) if form == "semicolon" else (",", lambda v: f"{v:.9g}")
    lines = [f"Time{sep}pendulum_angle"] + [f"{cell(s)}{sep}{value(v)}" for s, v in zip(stamps, y)]
    (tmp_path / "clock.csv").write_text("\n".join(lines) + "\n")
    (tmp_path / "clock.rig.json").write_text(PENDULUM.with_suffix(".rig.json").read_text())
    _, read = load_pair(tmp_path / "clock.csv")
    assert np.allclose(read.t, t - t[0], atol=1e-9, rtol=0) and np.array_equal(read.channel("pendulum_angle"), y)
    said = "23:50:00" if form == "time_of_day" else "2026-11-27 23:50:00"
    assert any(c.endswith(f"clock time, {said}") for c in read.comments), read.comments


def test_a_time_column_mixing_clock_times_and_numbers_is_refused_naming_the_line(tmp_path):
    (tmp_path / "mixed.csv").write_text("t,pendulum_angle\n10:00:00.000,0.1\n10:00:00.001,0.1\n0.002,0.1\n")
    with pytest.raises(InputError, match="line 4, column 't'.*below clock times"):
        load_pair(tmp_path / "mixed.csv", PENDULUM.with_suffix(".rig.json"))


def test_a_thousands_separator_is_refused_saying_so(tmp_path):
    (tmp_path / "grouped.csv").write_text("t [ms];pendulum_angle\n" + "".join(
        f"{'1.' if i >= 1000 else ''}{i % 1000 if i >= 1000 else i:0{3 if i >= 1000 else 1}d},0;0,1{i % 7}\n"
        for i in range(995, 1060)))
    with pytest.raises(InputError, match="line 7: value '1.000.0' is not a number .a thousands separator"):
        load_pair(tmp_path / "grouped.csv", PENDULUM.with_suffix(".rig.json"))


def test_a_closing_travel_with_its_sign_turned_is_refused_not_diagnosed(tmp_path, capsys):
    """Before this check diagnose named viscous friction missing from the turned record (explained: false)."""
    closing = SYNTHETIC / "vcb_closing"
    t, y = clean(closing)
    err = refused(capsys, write(tmp_path, "turned", closing, t, -y), tmp_path)
    assert "column 'follower_displacement'" in err and "sign" in err
    offset = write(tmp_path, "offset", closing, t, y - 2e-4)  # a transducer's zero 0.2 mm off: read
    assert load_pair(offset)[1].t.size == t.size


def test_matlab_comment_lines_are_comments_anywhere(tmp_path):
    t, y = clean(PENDULUM)
    lines = ["% logged by a MATLAB script, 1 kHz", "t,pendulum_angle"] + [f"{a:.7f},{b:.9g}" for a, b in zip(t, y)]
    lines.insert(500, "% trigger re-armed")
    (tmp_path / "matlab.csv").write_text("\n".join(lines) + "\n")
    _, read = load_pair(tmp_path / "matlab.csv", PENDULUM.with_suffix(".rig.json"))
    assert np.array_equal(read.t, t) and read.comments == ("logged by a MATLAB script, 1 kHz", "trigger re-armed")


@pytest.mark.parametrize("levels", [0, 4096, 256])
@pytest.mark.parametrize("source", [CAM, PENDULUM])
def test_a_pre_trigger_held_exactly_at_rest_is_read(source, levels):
    """A rest before the release that a quiet or quantised sensor reads as one value (at the record's
    largest or smallest value) is the shaft at rest, not a clipped sensor: the motion leaves it from rest."""
    t, y = clean(source)
    step = float(t[1] - t[0])
    t = np.concatenate([t[0] - step * np.arange(200, 0, -1), t])
    y = np.concatenate([np.full(200, y[0]), y])
    if levels:
        q = float(np.ptp(y)) / levels
        y = np.round(y / q) * q
    check_held_values(t, y, source.name, "angle")


def test_a_time_column_of_spreadsheet_date_serials_is_refused_saying_so(tmp_path, capsys):
    t, y = clean(CAM)
    lines = ["t,cam_angle"] + [f"{46353.4 + a / 86400:.12f},{b:.9g}" for a, b in zip(t, y)]
    (tmp_path / "serial.csv").write_text("\n".join(lines) + "\n")
    (tmp_path / "serial.rig.json").write_text(CAM.with_suffix(".rig.json").read_text())
    err = refused(capsys, tmp_path / "serial.csv", tmp_path)
    assert "column 't'" in err and "date-time serial" in err


def test_columns_separated_by_spaces_read_as_the_same_record(tmp_path):
    """Octave's ``save -ascii`` or a fixed-width export: columns separated by runs of spaces, a unit in
    brackets after its name (``Time [ms]``, ``pendulum_angle (deg)``)."""
    t, y = clean(PENDULUM)
    lines = ["# octave", "Time [ms]   pendulum_angle (deg)"] + [f"{1e3 * a:10.3f} {math.degrees(b):14.9f}" for a, b in zip(t, y)]
    (tmp_path / "spaces.csv").write_text("\n".join(lines) + "\n")
    _, read = load_pair(tmp_path / "spaces.csv", PENDULUM.with_suffix(".rig.json"))
    assert np.allclose(read.t, t, atol=1e-12, rtol=0) and np.allclose(read.channel("pendulum_angle"), y, atol=1e-10, rtol=0)


def test_a_second_header_below_the_data_is_refused_as_two_records_joined(tmp_path):
    t, y = clean(PENDULUM)
    rows = [f"{a:.7f},{b:.9g}" for a, b in zip(t, y)]
    (tmp_path / "joined.csv").write_text("\n".join(["t,pendulum_angle"] + rows[:3000] + ["t,pendulum_angle"] + rows[3000:]) + "\n")
    with pytest.raises(InputError, match="line 3002: .*a second header below the data"):
        load_pair(tmp_path / "joined.csv", PENDULUM.with_suffix(".rig.json"))


def test_a_loggers_end_marker_ends_the_record_and_nothing_may_follow_it(tmp_path):
    t, y = clean(PENDULUM)
    rows = ["t,pendulum_angle"] + [f"{a:.7f},{b:.9g}" for a, b in zip(t, y)]
    (tmp_path / "end.csv").write_text("\n".join(rows + ["END", "", "# saved 23:50"]) + "\n")
    _, read = load_pair(tmp_path / "end.csv", PENDULUM.with_suffix(".rig.json"))
    assert np.array_equal(read.t, t)
    (tmp_path / "more.csv").write_text("\n".join(rows + ["END", "7.0,0.1"]) + "\n")
    with pytest.raises(InputError, match=f"line {len(rows) + 1}: has 1 values"):
        load_pair(tmp_path / "more.csv", PENDULUM.with_suffix(".rig.json"))


@pytest.mark.parametrize("source", [CAM, PENDULUM, SYNTHETIC / "vcb_closing"])
def test_values_in_si_under_a_stated_smaller_unit_are_refused(tmp_path, capsys, source):
    """rad under ``[deg]``, m under ``[mm]``: converted once too often, the record is a tiny motion the
    fits would read as missing effects (before: the closing record diagnosed as missing viscous friction)."""
    t, y = clean(source)
    channel, unit = {CAM: ("cam_angle", "deg"), PENDULUM: ("pendulum_angle", "deg")}.get(source, ("follower_displacement", "mm"))
    err = refused(capsys, write(tmp_path, "small", source, t, y, header=f"t,{channel} [{unit}]"), tmp_path)
    assert f"column '{channel}'" in err and ("converted from degrees once too often" in err or "spans only" in err)


def test_a_time_that_starts_again_is_refused_as_segments(tmp_path):
    t, y = clean(PENDULUM)
    k = t.size // 3
    path = write(tmp_path, "segments", PENDULUM, np.concatenate([t[:k], t[k:] - t[k]]), y)
    with pytest.raises(InputError, match=f"line {k + 2}, column 't'.*the time starts again"):
        load_pair(path)


def test_a_spreadsheet_workbook_is_refused_as_such(tmp_path):
    import zipfile
    with zipfile.ZipFile(tmp_path / "book.csv", "w") as z:
        z.writestr("xl/workbook.xml", "<workbook/>")
    with pytest.raises(InputError, match="book.csv: file: is a spreadsheet workbook"):
        load_pair(tmp_path / "book.csv", PENDULUM.with_suffix(".rig.json"))

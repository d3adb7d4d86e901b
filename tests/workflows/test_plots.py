"""The figures a breaker engineer reads: simulate --plot of a closing (the analyser's view), vcbmodel plot
of a sweep's table, identify --plot. Checked on matplotlib's objects: the panels, the units in every
axis label, the same colour for a pole in every panel, the zone, touches and limits drawn where the
figures of merit put them."""
import copy

import matplotlib
import numpy as np
import pandas as pd
import pytest
from matplotlib.colors import to_rgba

from vcbmodel import parameters as P
from vcbmodel.analysis.identify import identify
from vcbmodel.app.cli import main
from vcbmodel.app.closing_plot import closing_figure, pole_colour
from vcbmodel.app.table_plot import fit_figure, sweep_figure
from vcbmodel.experiments.loading import load_pair, load_rig
from vcbmodel.experiments.simulation import simulate
from vcbmodel.experiments.summaries import closing_report, result_figures

from conftest import ROOT, write_rig


@pytest.fixture(scope="module")
def closing(tmp_path_factory):
    rig = load_rig(write_rig(tmp_path_factory.mktemp("plots"), P.REFERENCE_BREAKER, "ref"))
    result = simulate(rig, backend="fast")
    fig = closing_figure(result, rig, "reference", closing_report(result, rig))
    yield rig, result, result_figures(result, rig), fig
    matplotlib.pyplot.close(fig)


def pole_lines(ax):
    return {line.get_label(): line for line in ax.get_lines() if line.get_label().startswith("pole ")}


def test_the_closing_figure_has_the_analysers_panels_with_units(closing):
    _, _, _, fig = closing
    travel, speed, timing, closeup, energy = fig.axes
    assert travel.get_ylabel() == "travel (mm)" and speed.get_ylabel() == "speed (m/s)"
    assert energy.get_ylabel() == "energy (J)"
    for ax in (timing, closeup, energy):
        assert ax.get_xlabel() == "t (ms from the latch release)"
    assert [t.get_text() for t in timing.get_yticklabels()] == ["pole 3", "pole 2", "pole 1"]
    assert "SIMULATED" in fig._suptitle.get_text() and "all pass" in fig._suptitle.get_text()
    labels = [line.get_label() for line in energy.get_lines()]
    assert "released by the closing springs" in labels and any(label.startswith("kinetic") for label in labels)


def test_a_pole_has_one_colour_in_every_panel(closing):
    _, _, _, fig = closing
    travel, speed, timing, closeup, _ = fig.axes
    for i in (1, 2, 3):
        want = to_rgba(pole_colour(i))
        assert to_rgba(pole_lines(travel)[f"pole {i}"].get_color()) == want
        assert to_rgba(pole_lines(speed)[f"pole {i}"].get_color()) == want
        for ax in (timing, closeup):  # bars: pole 1 on the top row
            bars = [c for c in ax.collections if abs(c.get_paths()[0].vertices[:, 1].mean() - (3 - i)) < 0.5]
            assert len(bars) == 1 and tuple(bars[0].get_facecolor()[0]) == pytest.approx(want)
    assert len({to_rgba(pole_colour(i)) for i in (1, 2, 3)}) == 3


def test_touches_zone_bounces_and_limits_are_where_the_figures_put_them(closing):
    rig, result, fom, fig = closing
    travel, speed, _, closeup, _ = fig.axes
    touches = sorted(line.get_xdata()[0] for line in travel.get_lines() if line.get_marker() == "o" and len(line.get_xdata()))
    assert touches == pytest.approx(sorted(1e3 * t for t in fom["per_pole"]["touch_s"]))
    zone = [p for p in travel.patches if p.get_label().startswith("speed zone")]
    gap_mm = 1e3 * rig.breaker.poles.contact_gap
    assert len(zone) == 1 and np.ptp(zone[0].get_path().vertices[:, 1]) == pytest.approx(1.0)  # axes fraction
    y0, y1 = zone[0].get_extents().y0, zone[0].get_extents().y1
    assert y1 > y0 and gap_mm - 4.0 == pytest.approx(travel.transData.inverted().transform((0, y0))[1], abs=1e-6)
    limits = sorted(line.get_ydata()[0] for line in speed.get_lines() if line.get_linestyle() == ":" and len(line.get_ydata()))
    assert limits == pytest.approx([1.0, 1.5])
    lo, hi = closeup.get_xlim()
    first = 1e3 * min(fom["per_pole"]["touch_s"])
    last = max(1e3 * (t + d) for t, d in zip(fom["per_pole"]["touch_s"], fom["per_pole"]["bounce_duration_s"]))
    assert lo < first < last < hi and hi - lo < 5.0  # a close-up of a few ms
    for i, n in enumerate(fom["per_pole"]["bounces"], start=1):
        assert f"pole {i} {n} (" in closeup.get_title(loc="left")


def test_simulate_plot_draws_a_closing(tmp_path, capsys):
    rig = write_rig(tmp_path, P.REFERENCE_BREAKER, "ref")
    png = tmp_path / "c.png"
    assert main(["simulate", str(rig), "--backend", "fast", "-o", str(tmp_path / "c.csv"), "--plot", str(png), "-q"]) == 0
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 50_000


def sweep_table():
    rows = []
    for k, (mu, offset) in enumerate([(m, o) for o in (-3e-4, 3e-4) for m in (0.10, 0.13, 0.16)], start=1):
        rows.append({"run": k, "friction.mu_k": mu, "breaker.poles.gap_offsets.1": offset,
                     "closing_time_s": 0.038 + 0.07 * (mu - 0.1) + offset, "bounce_count": 2,
                     "peak_cam_roller_force_N": 25e3 + 1e5 * mu, "status": "ok"})
    rows.append(dict(rows[0], run=7, status="not_closed"))
    return pd.DataFrame(rows)


def test_a_sweep_is_drawn_per_group_in_engineering_units():
    fig = sweep_figure(sweep_table(), "friction.mu_k", ["closing_time_s", "peak_cam_roller_force_N"], "t")
    top, bottom = fig.axes
    assert top.get_ylabel() == "closing time (ms)" and bottom.get_ylabel() == "peak cam roller force (kN)"
    assert bottom.get_xlabel() == "friction.mu_k"
    lines = top.get_lines()
    assert [line.get_label() for line in lines] == ["breaker.poles.gap_offsets.1 = -0.3 mm",
                                                    "breaker.poles.gap_offsets.1 = 0.3 mm"]
    assert list(lines[0].get_ydata()) == pytest.approx([38.0 - 0.3, 40.1 - 0.3, 42.2 - 0.3])  # ms
    assert to_rgba(lines[0].get_color()) != to_rgba(lines[1].get_color())
    assert fig._suptitle.get_text().endswith("; left out: 1 run not closed (no pole touched in its run)")
    matplotlib.pyplot.close(fig)


def test_the_title_counts_the_runs_left_out_by_status():
    """A ``not_closed`` run finished (its breaker did not close in the run): the title said '1 run(s) that
    did not finish left out' of it, as of a crashed run. Each status is counted as what it is."""
    table = sweep_table()
    table = pd.concat([table, pd.DataFrame([dict(table.iloc[1], run=8, status="failed: the run created energy"),
                                            dict(table.iloc[2], run=9, status="failed: solver")])])
    fig = sweep_figure(table, "friction.mu_k", ["closing_time_s"], "t")
    text = fig._suptitle.get_text()
    assert text.endswith("; left out: 1 run not closed (no pole touched in its run), 2 runs failed"), text
    assert "did not finish" not in text
    matplotlib.pyplot.close(fig)
    every = sweep_figure(sweep_table().iloc[:6], "friction.mu_k", ["closing_time_s"], "t")
    assert "left out" not in every._suptitle.get_text()
    matplotlib.pyplot.close(every)


def test_a_figure_without_values_says_so_in_its_panel():
    """A pendulum sweep where every run still swings at the end (stop_time_s empty) and one where one
    run of three has no value: the panels say how many ok runs have none."""
    table = pd.DataFrame({"run": [1, 2, 3], "friction.mu_k": [0.0, 0.02, 0.04], "first_peak_rad": [1.49, 1.48, 1.47],
                          "stop_time_s": [np.nan, np.nan, np.nan], "status": ["ok"] * 3})
    fig = sweep_figure(table, "friction.mu_k", ["stop_time_s", "first_peak_rad"], "t")
    empty, full = fig.axes
    assert [t.get_text() for t in empty.texts] == ["no ok run has a value of stop_time_s (its cells are empty)"]
    assert not full.texts and full.get_title(loc="left") == ""
    table.loc[1:, "stop_time_s"] = [2.5, 2.1]
    fig2 = sweep_figure(table, "friction.mu_k", ["stop_time_s"], "t")
    assert fig2.axes[0].get_title(loc="left") == "1 of 3 ok runs have no value of stop_time_s (empty cells)"
    matplotlib.pyplot.close(fig)
    matplotlib.pyplot.close(fig2)


def test_the_plot_command_writes_and_refuses_in_one_line(tmp_path, capsys):
    table = tmp_path / "s.csv"
    sweep_table().to_csv(table, index=False)
    assert main(["plot", str(table), "--x", "friction.mu_k", "--y", "closing_time_s", "-q"]) == 0
    assert (tmp_path / "s.png").stat().st_size > 10_000  # beside the table by default
    assert main(["plot", str(table), "--x", "friction.mu_k", "--y", "closing_time_s", "-q"]) == 2
    assert "--force" in capsys.readouterr().err
    for args, words in ((["--x", "friction.mu_k", "--y", "closing_tme_s"], "--y: no column 'closing_tme_s'"),
                        (["--x", "friction.mu_k", "--y", "status"], "is not numeric")):
        assert main(["plot", str(table), *args, "-o", str(tmp_path / "x.png")]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and words in err and not (tmp_path / "x.png").exists()


def test_identify_plot_shows_measured_fitted_and_the_residual(tmp_path):
    pair = load_pair(ROOT / "results" / "synthetic" / "pendulum_10deg.csv")
    result = identify([pair], verbose=False)
    fig = fit_figure(result)
    top, bottom = fig.axes
    assert top.get_ylabel() == "shaft angle (deg)" and bottom.get_ylabel() == "model - measured (mrad)"
    assert bottom.get_xlabel() == "t (s)"
    measured = next(line for line in top.get_lines() if line.get_label() == "measured")
    assert np.max(measured.get_ydata()) == pytest.approx(10.0, abs=0.2)  # the 10 deg release, in degrees
    residual = bottom.get_lines()[0]
    assert np.sqrt(np.mean(residual.get_ydata() ** 2)) == pytest.approx(1e3 * result.fit.rms, rel=0.05)
    matplotlib.pyplot.close(fig)


def test_random_draws_are_points_coloured_by_the_other_field():
    rng = np.random.default_rng(1)
    table = pd.DataFrame({"run": range(1, 13), "friction.mu_k": rng.uniform(0.1, 0.16, 12),
                          "closing_spring.stiffness": rng.normal(24230, 500, 12),
                          "closing_speed_m_s": rng.uniform(1.2, 1.3, 12), "status": "ok"})
    fig = sweep_figure(table, "friction.mu_k", ["closing_speed_m_s"], "t")
    ax, bar = fig.axes
    assert ax.get_ylabel() == "closing speed (m/s)" and bar.get_ylabel() == "closing_spring.stiffness (N/m)"
    assert len(ax.collections) == 1 and len(ax.collections[0].get_offsets()) == 12
    matplotlib.pyplot.close(fig)


def test_identify_plot_refuses_an_existing_file_or_an_input_before_fitting(tmp_path, capsys):
    record = ROOT / "results" / "synthetic" / "pendulum_10deg.csv"
    old = tmp_path / "fit.png"
    old.write_bytes(b"mine")
    for target, words in ((old, "--force"), (record, "is an input")):
        assert main(["identify", str(record), "--plot", str(target), "-q"]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and words in err
    assert old.read_bytes() == b"mine"


def test_a_failing_closing_names_its_failures_in_the_title(closing, tmp_path):
    """The figure's title names each failing figure and pole; the values and limits are the report's."""
    rig, result, _, _ = closing
    data = copy.deepcopy(P.REFERENCE_BREAKER)
    data["breaker"]["limits"] = {"closing_speed": {"min": 1.0, "max": 1.3, "unit": "m/s"},
                                 "bounce_duration": {"max": 1.0, "unit": "ms"}}
    tight = load_rig(write_rig(tmp_path, data, "tight"))
    fig = closing_figure(result, tight, "tight", closing_report(result, tight))
    text = " ".join(fig._suptitle.get_text().split())
    assert "FAIL: closing speed, 4-0 mm before touch on pole 3; bounce duration on pole 1, 2, 3" in text
    assert "m/s" not in text and "limit" not in text.split("FAIL")[1]
    matplotlib.pyplot.close(fig)


def test_a_long_title_is_broken_to_fit_the_figure(closing):
    rig, result, _, _ = closing
    name = "my breaker with a long name: 12 kV, 40 kA, three poles on a 60 mm main shaft, spring set B, " * 2
    report = closing_report(result, rig)
    fig = closing_figure(result, rig, name, report)
    fig.canvas.draw()
    title = fig._suptitle
    renderer = fig.canvas.get_renderer()
    box = title.get_window_extent(renderer)
    assert title.get_text().count("\n") >= 2 and box.width <= fig.bbox.width
    # above the first panel and its own title, not over them
    assert box.y0 >= fig.axes[0].title.get_window_extent(renderer).y1
    # the words are all there, in order
    assert " ".join(title.get_text().split()).startswith(" ".join(name.split()))
    matplotlib.pyplot.close(fig)


def test_the_diagnosis_figure_is_in_engineering_units():
    """diagnose --plot of a closing record: travel in mm, its residual in um, time in ms (a 55 ms
    record), the noise band at +-2 sigma and the windows where the diagnosis put them."""
    from types import SimpleNamespace

    from vcbmodel.app.plots import diagnosis_figure

    t = np.linspace(0.0, 0.055, 661)
    travel = 0.015 * np.clip((t - 0.02) / 0.03, 0.0, 1.0)
    residual = 2e-8 * np.sin(2e3 * t)
    fit = SimpleNamespace(simulations=[SimpleNamespace(measured=travel + residual)], effects=("coulomb_friction",),
                          spring_model=SimpleNamespace(label="lumped-2 (exact)"), times=[t], residuals=[residual],
                          rms=float(np.sqrt(np.mean(residual**2))))
    d = SimpleNamespace(unit="m", measurement=SimpleNamespace(t=t, channel=lambda name: travel), baseline=fit, final=fit,
                        missing_effects=[], nuisance={"values": {"release_time": 1e-4}}, explained=True, noise=1e-8,
                        window=(0.03, 0.04), verdict={}, rig=SimpleNamespace(experiment="vcb_closing"))
    fig = diagnosis_figure(d)
    top, bottom = fig.axes
    assert top.get_ylabel() == "follower displacement (mm)" and bottom.get_ylabel() == "model - measurement (um)"
    assert bottom.get_xlabel() == "t (ms, record time)"
    measured = top.get_lines()[0]
    assert np.max(measured.get_ydata()) == pytest.approx(15.0) and np.max(measured.get_xdata()) == pytest.approx(55.0)
    assert np.max(np.abs(bottom.get_lines()[0].get_ydata())) == pytest.approx(0.02, rel=1e-3)
    assert sorted(abs(line.get_ydata()[0]) for line in bottom.get_lines()[1:3]) == pytest.approx([0.02, 0.02])
    span = bottom.patches[0]
    assert (span.get_x(), span.get_x() + span.get_width()) == pytest.approx((30.0, 40.0))
    matplotlib.pyplot.close(fig)


def test_the_energy_legend_covers_no_curve(closing):
    """On a 100 ms run (the cam resting on its latch) the energies fill the panel's upper left."""
    rig = closing[0]
    result = simulate(rig, backend="fast", t_end=0.1)
    fig = closing_figure(result, rig, "long", closing_report(result, rig))
    energy = fig.axes[4]
    fig.canvas.draw()
    box = energy.get_legend().get_window_extent(fig.canvas.get_renderer())
    for line in energy.get_lines():
        xy = energy.transData.transform(np.column_stack([line.get_xdata(), line.get_ydata()]))
        inside = (xy[:, 0] > box.x0) & (xy[:, 0] < box.x1) & (xy[:, 1] > box.y0) & (xy[:, 1] < box.y1)
        assert not inside.any(), line.get_label()
    matplotlib.pyplot.close(fig)

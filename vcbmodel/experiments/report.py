"""``simulate``'s report of one run, as a test set prints it: each figure in the unit an engineer reads
(ms, mm, m/s, kN, deg; :mod:`vcbmodel.rig.units`) to 3-4 significant figures, a closing's figures per
pole in columns, each against the rig's limits (``breaker.limits``) with pass or FAIL, and notes.

A :class:`Report` holds SI values; :func:`report_text` and :func:`report_json` show them. A figure the
evaluation adds (a per-pole entry of ``figures_of_merit()["per_pole"]``, or a whole-breaker figure
whose name ends in its unit) gets a row of its own, named from its key, without a change here.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

from ..rig.limits import LIMITED_FIGURES, Limit
from ..rig.units import display, format_value, shown, to_si, unit_of_name

NO_LIMIT = "no limit given"


@dataclass
class Row:
    """One figure: ``values`` in SI (one per pole, or one for the whole run), ``unit`` its SI unit,
    ``key`` its name with the unit (``closing_time_s``: a limit ``closing_time`` applies), ``show``
    the unit to print it in (None: :data:`vcbmodel.rig.units.DISPLAY`'s)."""

    key: str
    what: str
    values: list
    unit: str | None
    show: str | None = None
    #: why the figure does not apply to this breaker (``one pole`` for a single pole's spread): shown
    #: in place of its value, never judged against a limit; "" for a figure that applies
    absent: str = ""

    @property
    def figure(self) -> str:
        """The key without its unit suffix (what ``breaker.limits`` names)."""
        unit = unit_of_name(self.key)
        suffix = {"m/s": "_m_s", "rad/s": "_rad_s", "N m": "_N_m"}.get(unit, f"_{unit}") if unit else ""
        return self.key[: len(self.key) - len(suffix)] if suffix and self.key.endswith(suffix) else self.key

    def cells(self) -> tuple[str, list[str], list]:
        """(shown unit, each value as printed, each value in the shown unit)."""
        if self.absent:
            return "", [f"does not apply: {self.absent}"], [None]
        if self.show is not None and to_si(self.show) is not None:
            factor = to_si(self.show)[1]
            out = [None if _missing(v) else float(v) / factor for v in self.values]
            return self.show, [format_value(v) for v in out], out
        triples = [shown(v, self.unit) for v in self.values]
        return display(self.unit).unit, [text for _, _, text in triples], [v for v, _, _ in triples]


def label(key: str) -> str:
    """A row's label from a figure's key: its name without the unit, in words (``kinetic_margin_J``
    -> ``kinetic margin``)."""
    return Row(key, "", [], None).figure.replace("_", " ")


def _missing(v) -> bool:
    return v is None or isinstance(v, bool) or (isinstance(v, float) and not math.isfinite(v))


@dataclass
class Check:
    """A row against its limit: ``holds`` per value (True, False, None: no value), ``result`` in words."""

    limit: Limit
    holds: list

    @property
    def result(self) -> str:
        failed = [i for i, h in enumerate(self.holds, start=1) if h is False]
        if failed:
            return "FAIL" + (f" pole {', '.join(map(str, failed))}" if len(self.holds) > 1 else "")
        return "no value" if any(h is None for h in self.holds) else "pass"


@dataclass
class Report:
    """``pole_rows`` (a value per pole; ``poles`` of them), ``rows`` (whole-run figures), ``notes``
    and ``limits`` (None: the experiment has none; (): the rig gives none)."""

    title: str
    rows: list
    pole_rows: list = field(default_factory=list)
    poles: int = 0
    notes: list = field(default_factory=list)
    limits: tuple | None = None
    #: what the limits cannot say about a closing, said in the verdict: ``(text, brief text, fails)`` for
    #: a cam that stops short of its latch (the closing fails: True) or a run that ends before it
    #: reaches it (False); None
    latching: tuple | None = None

    def judged_per_pole(self, row: Row) -> bool:
        """Whether ``row`` is a whole-run row of a figure the per-pole rows carry (the mechanism's wipe
        beside each pole's): a limit on that figure judges each pole, not the whole run
        (:data:`vcbmodel.rig.limits.LIMITED_FIGURES`)."""
        return bool(row.key) and not any(row is r for r in self.pole_rows) and \
            row.figure in {r.figure for r in self.pole_rows}

    def check(self, row: Row) -> Check | None:
        """The row against the rig's limit on its figure (None: no limit on it, or one that judges
        the poles' rows instead: :meth:`judged_per_pole`)."""
        if self.judged_per_pole(row) or row.absent:
            return None
        for limit in self.limits or ():
            if limit.figure == row.figure:
                return Check(limit, [limit.holds(None if _missing(v) else float(v)) for v in row.values])
        return None

    def checks(self) -> list[tuple[Row, Check]]:
        return [(row, c) for row in self.pole_rows + self.rows if (c := self.check(row)) is not None]

    def limit_cell(self, row: Row) -> tuple[str, str]:
        """(limit, result) as printed: the limit's text and pass/FAIL; ``no limit given`` for a figure
        a limit could bound that the rig leaves without one; blank for the others."""
        c = self.check(row)
        if c is not None:
            return c.limit.text(), c.result
        return ((NO_LIMIT, "") if self.limits is not None and row.figure in LIMITED_FIGURES
                and not self.judged_per_pole(row) and not row.absent else ("", ""))

    def failures(self) -> list[str]:
        """What fails the run's acceptance, briefly (each failing figure and its poles; ``CLOSING FAILS
        (latch not reached)`` for a cam short of its latch); a limit with no value, or latching not
        judged, fails nothing."""
        failed = [self._failure(row, c, True) for row, c in self.checks() if c.result.startswith("FAIL")]
        return failed + ([self.latching[1]] if self.latching and self.latching[2] else [])

    def fails(self) -> bool:
        """Whether anything fails the run's acceptance (:meth:`failures`)."""
        return bool(self.failures())

    def verdict(self, brief: bool = False) -> str:
        """One line: how many limits hold, which fail (``brief``: each failing figure and its poles,
        without the values and limits, for a figure's title)."""
        if self.limits is None:
            return ""
        latching = "" if self.latching is None else "; " + self.latching[1 if brief else 0]
        if not self.limits:
            return "limits: none given (breaker.limits): no figure is judged" + latching
        checks = self.checks()
        failed = [self._failure(row, c, brief) for row, c in checks if c.result.startswith("FAIL")]
        unseen = [row.what for row, c in checks if c.result == "no value"]
        # a limit is judged where the run gives its figure a value (a FAIL on one pole judges it too)
        judged = len({c.limit.figure for _, c in checks if c.result != "no value"})
        head = f"limits (breaker.limits): {judged} of {len(self.limits)} judged"
        if failed:
            return f"{head}: FAIL: {'; '.join(failed)}{latching}"
        if not checks:  # none of the rig's limits bounds a figure of this run (an opening's, in a closing)
            return head + latching
        parts = (["all pass"] if judged else []) + ([f"no value in this run for {', '.join(unseen)}"] if unseen else [])
        return f"{head}: {'; '.join(parts)}{latching}"


    def _failure(self, row: Row, check: Check, brief: bool = False) -> str:
        """``closing speed ... on pole 3 (1.307 m/s; limit 1-1.5 m/s)`` (``brief``: without the brackets)."""
        unit, texts, _ = row.cells()
        bad = [i for i, h in enumerate(check.holds) if h is False]
        where = f" on pole {', '.join(str(i + 1) for i in bad)}" if len(check.holds) > 1 else ""
        if brief:
            return f"{row.what}{where}"
        values = ", ".join(texts[i] for i in bad)
        return f"{row.what}{where} ({values} {unit}; limit {check.limit.text()})".replace(" ;", ";")


def lines_report(title: str, lines: Sequence[tuple]) -> Report:
    """A report from summary lines ``(what, SI value, SI unit[, unit to show])``; a line whose value
    is text (``("note", text, None)``) is a note."""
    rows = [Row("", line[0], [line[1]], line[2], line[3] if len(line) > 3 else None)
            for line in lines if not isinstance(line[1], str)]
    return Report(title, rows, notes=[line[1] for line in lines if isinstance(line[1], str)])


def report_text(report: Report) -> str:
    """The report as text: a title, the per-pole table (figure, unit, a column per pole, limit,
    result), the whole-run figures, the notes and the verdict on the limits."""
    width = max((len(r.what) for r in report.pole_rows + report.rows), default=0) + 2
    columns = max(report.poles, 1)
    out = [report.title] if report.title else []

    def line(what, unit, cells, limit="", result=""):
        # a cell wider than its column still keeps a space from the one before
        body = f"  {what:<{width}}{unit:<5}" + "".join(f"{c:>9}" if len(c) < 9 else f" {c}"
                                                        for c in cells + [""] * (columns - len(cells)))
        return (body + (f"   {limit:<15}{result}" if limit or result else "")).rstrip()

    judged = report.limits is not None
    if report.pole_rows:
        out.append(line("per pole", "unit", [f"pole {i}" for i in range(1, report.poles + 1)],
                        "limit" if judged else "", "result" if judged else ""))
        out += [line(r.what, r.cells()[0], r.cells()[1], *report.limit_cell(r)) for r in report.pole_rows]
        out.append(line("whole breaker", "", []))
    out += [line(r.what, r.cells()[0], r.cells()[1], *report.limit_cell(r)) for r in report.rows]
    out += [f"  note: {n}" for n in report.notes]
    if report.verdict():
        out.append(report.verdict())
        out += [f"  {c.limit.figure.replace('_', ' ')} {c.limit.text()}: {c.limit.source}"
                for c in {c.limit.figure: c for _, c in report.checks()}.values() if c.limit.source]
    return "\n".join(out)


def _row_json(report: Report, row: Row, pole: int | None = None) -> dict:
    unit, _, values = row.cells()
    value = values[pole] if pole is not None else values[0]
    out = {"what": row.what, "value": value, "unit": unit}
    if row.key:
        out["figure"] = row.key
    if row.absent:
        out["does_not_apply"] = row.absent
    c = report.check(row)
    if c is not None:
        holds = c.holds[pole if pole is not None else 0]
        out.update({"limit": c.limit.text(), "pass": holds})
    elif report.limits is not None and row.figure in LIMITED_FIGURES and not report.judged_per_pole(row) and not row.absent:
        out["limit"] = None
    return out


def report_json(report: Report) -> dict:
    """The report as JSON: ``poles`` (per pole: {figure: {what, value, unit, limit, pass}}), ``summary``
    (the whole-run figures as [{what, value, unit, ...}]), ``notes``, ``limits`` (each with its values
    in SI, the unit it is stated in, source, result), ``verdict`` and ``fails`` (:meth:`Report.fails`); values
    in the units shown."""
    out = {"summary": [_row_json(report, r) for r in report.rows], "notes": list(report.notes)}
    if report.pole_rows:
        out["poles"] = [{"pole": i + 1, **{r.figure or r.what: _row_json(report, r, i) for r in report.pole_rows}}
                        for i in range(report.poles)]
    if report.limits is not None:
        results = {c.limit.figure: c.result for _, c in report.checks() if not c.result.startswith("FAIL")}
        results.update({c.limit.figure: c.result for _, c in report.checks() if c.result.startswith("FAIL")})
        out["limits"] = [{"figure": lim.figure, "min_si": lim.low, "max_si": lim.high, "unit": lim.unit,
                          "text": lim.text(), "source": lim.source, "result": results.get(lim.figure, "not in the report")}
                         for lim in report.limits]
        out["verdict"] = report.verdict()
        out["fails"] = report.fails()
    return out

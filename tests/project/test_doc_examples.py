"""The docs' examples print what the installed code prints (docs/cli.md, docs/your-breaker.md).

An example is checked when an HTML comment ``<!-- doctest -->`` stands on the line before its fenced
block. In such a block a line starting with ``$ `` is a command (a line ending in ``\\`` continues it) and
the lines after it, up to the next command, are what it prints (stdout, then stderr). Each shown line
must appear in the real output, whitespace runs folded to one space, so every number is checked to the
digits the page shows; a line that is just ``...`` elides any number of lines, and ``...`` inside a line
any text. Lines shown without a ``...`` between them must come out one after the other.

The commands run from a temporary folder holding a copy of ``results/synthetic/``, in which the rigs the
studies write straight from ``vcbmodel/parameters.py`` are written again from it, so an example follows
the code, not a ``results/`` left from an earlier run. Every checked example runs in a few seconds.
"""
import copy
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from vcbmodel import parameters as P
from vcbmodel.experiments.loading import rig_from_data

ROOT = Path(__file__).resolve().parents[2]
PAGES = ("docs/cli.md", "docs/your-breaker.md")
MARK = "<!-- doctest -->"


def _rigs_from_parameters() -> dict:
    """The rigs of results/synthetic/ that the studies write from parameters.py, as they write them."""
    heavy = copy.deepcopy(P.REFERENCE_CAM)  # studies/spring_models.py, rig_variant
    heavy["closing_spring"]["mass"] = P.HEAVY_SPRING_MASS
    heavy["name"] = "cam_drop_m0_1kg"
    return {"vcb_closing.rig.json": P.REFERENCE_BREAKER,  # studies/vcb_closing.py
            "vcb_cycle.rig.json": P.REFERENCE_CYCLE_BREAKER,  # studies/vcb_cycle.py
            "cam_drop_m0_1kg.rig.json": heavy}


def examples() -> list:
    """(page, line, block text) of every block marked as a checked example."""
    found = []
    for page in PAGES:
        lines = (ROOT / page).read_text(encoding="utf-8").splitlines()
        for i, line in enumerate(lines):
            if line.strip() != MARK:
                continue
            assert lines[i + 1].startswith("```"), f"{page}:{i + 1}: {MARK} must stand right before a fenced block"
            end = next(j for j in range(i + 2, len(lines)) if lines[j].startswith("```"))
            found.append((page, i + 2, lines[i + 2:end]))
    return found


def commands_and_outputs(block: list) -> list:
    """[(command, [shown output lines])] of one block."""
    pairs, command = [], None
    for line in block:
        if command is not None and command.endswith("\\"):
            command = command[:-1] + " " + line.strip()
            pairs[-1] = (command, pairs[-1][1])
        elif line.startswith("$ "):
            command = line[2:].strip()
            pairs.append((command, []))
        else:
            assert pairs, f"output before any command: {line!r}"
            pairs[-1][1].append(line)
    return pairs


def _folded(line: str) -> str:
    return " ".join(line.split())


def _pattern(shown: str) -> re.Pattern:
    parts = [re.escape(p) for p in _folded(shown).split("...")]
    return re.compile("^" + ".*?".join(parts) + "$")


def missing_lines(shown: list, real: list) -> list:
    """The shown lines that do not come out where the page puts them (empty: the example holds)."""
    runs, run = [], []
    for line in shown:
        if line.strip() == "...":
            runs.append(run)
            run = []
        elif line.strip():
            run.append(_pattern(line))
    runs.append(run)
    real = [_folded(r) for r in real]
    start, missing = 0, []
    for run in (r for r in runs if r):
        at = next((i for i in range(start, len(real) - len(run) + 1)
                   if all(p.match(real[i + k]) for k, p in enumerate(run))), None)
        if at is None:
            missing.append(next((p.pattern for k, p in enumerate(run)
                                 if not any(p.match(r) for r in real[start:])), run[0].pattern))
        else:
            start = at + len(run)
    return missing


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    work = tmp_path_factory.mktemp("doc_inputs")
    shutil.copytree(ROOT / "results" / "synthetic", work / "results" / "synthetic")
    for name, data in _rigs_from_parameters().items():
        (work / "results" / "synthetic" / name).write_text(json.dumps(data, indent=2) + "\n")
    shutil.copytree(ROOT / "docs" / "examples", work / "docs" / "examples")
    return work


@pytest.fixture
def workdir(inputs, tmp_path):
    """A folder of the example's own (what one example writes is not another's input), with the inputs."""
    for folder in ("results", "docs"):
        (tmp_path / folder).symlink_to(inputs / folder, target_is_directory=True)
    return tmp_path


def test_the_pages_mark_their_output_examples():
    marked = examples()
    assert len(marked) >= 5, [(p, n) for p, n, _ in marked]
    assert all(commands_and_outputs(block) for _, _, block in marked)


@pytest.mark.parametrize("page, line, block", examples(), ids=lambda v: v if isinstance(v, (str, int)) else "")
def test_an_example_prints_what_its_page_shows(workdir, page, line, block):
    env = dict(os.environ, PATH=str(Path(sys.executable).parent) + os.pathsep + os.environ["PATH"],
               MPLBACKEND="Agg", PYTHONPATH=str(ROOT))
    for command, shown in commands_and_outputs(block):
        run = subprocess.run(["bash", "-c", command], cwd=workdir, env=env, capture_output=True, text=True,
                             timeout=300)
        assert run.returncode == 0, f"{page}:{line}: {command}\n{run.stderr[-2000:]}"
        real = run.stdout.splitlines() + run.stderr.splitlines()
        missing = missing_lines(shown, real)
        assert not missing, f"{page}:{line}: {command}: not in its output: {missing}\n" + "\n".join(real[:60])


def test_the_matcher_checks_every_digit_and_keeps_the_order():
    real = ["a  1.280   1.275", "b 2", "c 3", "note: the run ends at 55 ms with the cam still turning"]
    assert missing_lines(["a 1.280 1.275", "...", "c 3"], real) == []
    assert missing_lines(["note: the run ends at ... still turning"], real) == []
    assert missing_lines(["a 1.28 1.275"], real) != []  # a digit fewer is another number
    assert missing_lines(["a 1.280 1.275", "c 3"], real) != []  # consecutive unless elided
    assert missing_lines(["c 3", "...", "a 1.280 1.275"], real) != []  # in order


def test_rig_format_s_example_rigs_load_and_its_breaker_is_the_reference():
    """Every complete rig printed in docs/rig-format.md loads as printed; section 8.3's is REFERENCE_BREAKER."""
    page = (ROOT / "docs" / "rig-format.md").read_text(encoding="utf-8")
    rigs = [json.loads(b) for b in re.findall(r"```json\n(.*?)```", page, re.S) if '"experiment"' in b]
    assert len(rigs) >= 4
    for data in rigs:
        rig_from_data(data, "docs/rig-format.md")
    assert P.REFERENCE_BREAKER in rigs


def _slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces as hyphens."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def test_the_docs_index_lists_every_page_and_every_link_resolves():
    index = (ROOT / "docs" / "README.md").read_text(encoding="utf-8")
    pages = {p.name for p in (ROOT / "docs").glob("*.md")} - {"README.md"}
    listed = set(re.findall(r"\]\(([^)#]+)\)", index))
    assert pages | {"../results/README.md", "../CHANGELOG.md", "../tests/README.md"} <= listed
    for page in (ROOT / "docs").glob("*.md"):
        text = page.read_text(encoding="utf-8")
        for target, anchor in re.findall(r"\]\(([^)#\s]*)(?:#([^)\s]+))?\)", text):
            if target.startswith(("http://", "https://")):
                continue
            linked = (page.parent / target).resolve() if target else page
            assert linked.exists(), f"{page.name}: {target}"
            if anchor and linked.suffix == ".md":
                headings = re.findall(r"^#+ (.+)$", linked.read_text(encoding="utf-8"), re.M)
                assert anchor in {_slug(h) for h in headings}, f"{page.name}: {target}#{anchor}"


def test_findings_lists_every_study():
    """docs/findings.md's table of studies names every script of studies/ (run_all.py runs them)."""
    table = (ROOT / "docs" / "findings.md").read_text(encoding="utf-8").split("## The studies", 1)[1].split("\n## ", 1)[0]
    scripts = {p.name for p in (ROOT / "studies").glob("*.py")} - {"_common.py", "run_all.py"}
    assert {s for s in scripts if f"`studies/{s}`" not in table} == set()


# docs/your-breaker.md's walk-through (a cam from points, a spring from its datasheet) runs as written and
# prints the lines the page shows (the block marked ``<!-- doctest: walk-through -->``, matched as above).
WALKTHROUGH_PAGE = (ROOT / "docs" / "your-breaker.md").read_text(encoding="utf-8")


def test_walkthrough_runs_as_written(tmp_path):
    block = re.findall(r"```bash\n(.*?)```", WALKTHROUGH_PAGE, re.S)[0]
    env = dict(os.environ, PATH=str(Path(sys.executable).parent) + os.pathsep + os.environ["PATH"],
               TMPDIR=str(tmp_path), MPLBACKEND="Agg")
    run = subprocess.run(["bash", "-c", "set -euo pipefail\n" + block + 'echo "OUT=$out"\n'], cwd=ROOT, env=env,
                         capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr[-2000:]
    out = Path(run.stdout.strip().splitlines()[-1].split("=", 1)[1])
    # check reported the datasheet spring and the cam from points
    assert "from the datasheet" in run.stdout and "spline through the rig's points" in run.stdout
    assert "largest pressure angle" in run.stdout
    # the closing ran and closed every pole
    csv_text = (out / "closing.csv").read_text()
    assert "follower_displacement" in csv_text and "pole_3_contact" in csv_text
    touch_row = run.stdout.split("closing time (touch)", 1)[1].splitlines()[0].split()
    assert touch_row[0] == "ms" and all(float(v) > 0 for v in touch_row[1:4])  # a closing time on each pole
    shown = WALKTHROUGH_PAGE.split("<!-- doctest: walk-through -->\n```\n", 1)[1].split("```", 1)[0].splitlines()
    assert missing_lines(shown, run.stdout.splitlines()) == []

"""The spring model is decided in at most three places: a module that parses text into a
:class:`~vcbmodel.rig.spring_model.SpringModel`, builds one, or makes a model choice decides it, and
every other module reads the value it is handed (an import contract, checked with ``ast``; no
import is executed)."""
import ast
from pathlib import Path

import vcbmodel

PACKAGE = Path(vcbmodel.__file__).resolve().parent

#: Where the spring model may be decided, and why there.
DECIDERS = {
    "rig/spring_model.py": "the value, its parser, the rig file's model section (and the mass models the diagnosis tries)",
    "model/choice.py": "a run's overrides of the rig's model: the one rule",
    "analysis/identify.py": "the friction identification's pendulum: a massless spring, a constant",
}


def decisions(tree: ast.AST) -> list[str]:
    """What in a module decides a spring model or a model choice: ``SpringModel(...)``,
    ``SpringModel.parse``, ``ModelChoice(...)``, ``.with_convention(...)`` (``line: text``)."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in ("SpringModel", "ModelChoice"):
            found.append(f"{node.lineno}: {node.func.id}(...)")
        elif isinstance(node, ast.Attribute) and node.attr in ("parse", "with_convention") and \
                isinstance(node.value, ast.Name) and node.value.id == "SpringModel":
            found.append(f"{node.lineno}: SpringModel.{node.attr}")
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "with_convention":
            found.append(f"{node.lineno}: .with_convention(...)")
    return sorted(found, key=lambda line: int(line.split(":")[0]))


def deciding_modules(package: Path = PACKAGE) -> dict[str, list[str]]:
    """{module path under the package: its decisions} for every module that decides."""
    out = {}
    for path in sorted(package.rglob("*.py")):
        found = decisions(ast.parse(path.read_text(encoding="utf-8")))
        if found:
            out[path.relative_to(package).as_posix()] = found
    return out


def test_the_spring_model_is_decided_in_at_most_three_places():
    assert len(DECIDERS) <= 3
    outside = {module: found for module, found in deciding_modules().items() if module not in DECIDERS}
    assert outside == {}, f"a fourth place decides the spring model: {outside}"


def test_the_check_sees_a_fourth_place():
    code = ("from vcbmodel.rig.spring_model import SpringModel\n"
            "def f(text, rig):\n"
            "    return SpringModel.parse(text or rig.model.spring_model)\n"
            "DEFAULT = SpringModel('lumped', 3)\n")
    assert decisions(ast.parse(code)) == ["3: SpringModel.parse", "4: SpringModel(...)"]
    assert decisions(ast.parse("x = spring.with_convention('paper')\n")) == ["1: .with_convention(...)"]
    assert "model/choice.py" in deciding_modules()  # the one rule is where the check looks

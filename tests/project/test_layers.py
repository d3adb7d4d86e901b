"""The package's layer table, as ``vcbmodel/__init__.py`` states it, holds in the code: no module
imports from a layer after its own, and the folders' imports form no cycle; inside ``analysis/``
the same for its folders and modules, in the order ``vcbmodel/analysis/__init__.py`` states (an
import contract, checked with ``ast``; no import is executed)."""
import ast
import re
from pathlib import Path

import vcbmodel
import vcbmodel.analysis

PACKAGE = Path(vcbmodel.__file__).resolve().parent
BASE = {"errors", "parameters"}
#: the package's entry points: they may import anything
ENTRY = {"__init__", "__main__"}


def stated_layers(doc=vcbmodel.__doc__):
    """[[folder, ...], ...] in order, from the docstring's ``a`` -> ``b``, ``c`` -> ... chain."""
    chain = doc.split("Layers", 1)[1].split("sit below", 1)[0]
    layers = [re.findall(r"``(\w+)``", part) for part in chain.split("->")]
    return [[name for name in names if name not in BASE] for names in layers]


def imports_of(path, package_parts):
    """vcbmodel folders (or base modules) a module imports, resolved from relative imports."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package_parts[: len(package_parts) - node.level + 1]
                target = base + (node.module.split(".") if node.module else [])
                if not node.module:
                    target = target + [alias.name for alias in node.names][:1]
            elif node.module and node.module.split(".")[0] == "vcbmodel":
                target = node.module.split(".")
            else:
                continue
            out.add(target[1] if len(target) > 1 else target[0])
        elif isinstance(node, ast.Import):
            for alias in node.names:
                parts = alias.name.split(".")
                if parts[0] == "vcbmodel" and len(parts) > 1:
                    out.add(parts[1])
    return out


def package_imports(package=PACKAGE):
    """{folder: {folder or base module it imports}} over every module of the package."""
    graph = {}
    for path in package.rglob("*.py"):
        rel = path.relative_to(package.parent).with_suffix("").parts  # ("vcbmodel", "laws", "friction")
        folder = rel[1]
        if folder in ENTRY:
            continue
        parts = list(rel[:-1])
        graph.setdefault(folder, set()).update(imports_of(path, parts) - {folder})
    return graph


def violations(graph, layers):
    level = {name: i + 1 for i, names in enumerate(layers) for name in names}
    level.update({name: 0 for name in BASE})
    bad = []
    for folder, targets in graph.items():
        for target in targets:
            if folder in level and target in level and level[target] > level[folder]:
                bad.append(f"{folder} (layer {level[folder]}) imports {target} (layer {level[target]})")
    return sorted(bad)


def cycles(graph):
    seen, stack, found = set(), [], []

    def visit(node):
        if node in stack:
            found.append(stack[stack.index(node):] + [node])
            return
        if node in seen:
            return
        seen.add(node)
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            visit(nxt)
        stack.pop()

    for node in sorted(graph):
        visit(node)
    return found


def test_the_docstring_states_every_folder_in_a_layer():
    layers = stated_layers()
    assert layers[0] == ["laws"] and layers[-1] == ["app"]
    folders = {p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    assert folders == {name for names in layers for name in names}


def test_no_module_imports_from_a_later_layer_and_no_folder_cycle():
    graph = package_imports()
    assert violations(graph, stated_layers()) == []
    assert cycles(graph) == []


def test_the_check_catches_an_upward_import_and_a_cycle():
    layers = stated_layers()
    graph = {name: set(targets) for name, targets in package_imports().items()}
    graph["laws"].add("analysis")
    assert violations(graph, layers) == ["laws (layer 1) imports analysis (layer 6)"]
    assert cycles({"a": {"b"}, "b": {"a"}}) and not cycles({"a": {"b"}, "b": set()})
    rel = imports_of(PACKAGE / "analysis" / "sweep" / "runs.py", ["vcbmodel", "analysis", "sweep"])
    assert {"errors", "experiments", "model", "rig"} <= rel  # three-dot imports resolve to the top folders


ANALYSIS = PACKAGE / "analysis"


def stated_analysis_layers(doc=vcbmodel.analysis.__doc__):
    """[[folder or module, ...], ...] in order, from the docstring's ``Inside`` chain."""
    chain = doc.split("Inside", 1)[1]
    return [re.findall(r"``(\w+)``", part) for part in chain.split("->")]


def analysis_imports(package=ANALYSIS):
    """{analysis folder or module: {analysis folder or module it imports}}."""
    graph = {}
    for path in package.rglob("*.py"):
        rel = path.relative_to(package).parts
        unit = rel[0] if len(rel) > 1 else path.stem
        if unit == "__init__":
            continue
        targets = imports_of_analysis(path, ["vcbmodel", "analysis", *rel[:-1]])
        graph.setdefault(unit, set()).update(targets - {unit})
    return graph


def imports_of_analysis(path, package_parts):
    """The analysis folders or modules a module imports (relative or absolute imports)."""
    out = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if not isinstance(node, ast.ImportFrom):
            continue
        if node.level:
            target = package_parts[: len(package_parts) - node.level + 1] + (node.module.split(".") if node.module else [])
            if not node.module:
                target = target + [alias.name for alias in node.names][:1]
        elif node.module and node.module.startswith("vcbmodel."):
            target = node.module.split(".")
        else:
            continue
        if len(target) > 2 and target[1] == "analysis":
            out.add(target[2])
    return out


def test_analysis_keeps_its_inner_order():
    layers = stated_analysis_layers()
    assert layers[0][0] == "progress" and "diagnose" in layers[-1]
    graph = analysis_imports()
    stated = {name for names in layers for name in names}
    assert set(graph) - stated == set(), "an analysis module or folder without a place in analysis/__init__.py's order"
    assert violations(graph, layers) == []
    assert cycles(graph) == []


def test_the_inner_check_catches_an_import_against_the_order():
    layers = stated_analysis_layers()
    graph = {name: set(targets) for name, targets in analysis_imports().items()}
    assert "fit" in graph["diagnosis"] and "discovery" in graph["diagnosis"]  # read from today's imports
    graph["fit"].add("diagnosis")
    assert violations(graph, layers) == ["fit (layer 2) imports diagnosis (layer 4)"]

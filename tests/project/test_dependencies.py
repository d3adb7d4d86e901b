"""Every third-party import of vcbmodel/, studies/ and tests/ is declared in setup.cfg.

A package installed by hand on a developer's machine once hid an undeclared import (sympy) while both
README commands failed on a fresh machine. This test reads the imports with ``ast`` and maps each to the
distribution that provides it in the running environment.
"""
import ast
import configparser
import re
import sys
from importlib import metadata
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FOLDERS = ("vcbmodel", "studies", "tests", ".ci")


def _norm(name):
    return re.sub(r"[-_.]+", "-", name).lower()


def declared_distributions(setup_cfg=ROOT / "setup.cfg"):
    """Distribution names in install_requires and every extra (normalised)."""
    cfg = configparser.ConfigParser()
    cfg.read(setup_cfg)
    chunks = [cfg.get("options", "install_requires", fallback="")]
    if cfg.has_section("options.extras_require"):
        chunks += [value for _, value in cfg.items("options.extras_require")]
    names = set()
    for line in "\n".join(chunks).splitlines():
        match = re.match(r"[A-Za-z0-9_.\-]+", line.split("#")[0].strip())
        if match:
            names.add(_norm(match.group(0)))
    return names


def top_level_imports(folders=FOLDERS):
    """{top-level module: first 'path:line' importing it} for absolute imports under folders."""
    found = {}
    for folder in folders:
        for path in sorted((ROOT / folder).rglob("*.py")):
            tree = ast.parse(path.read_text(encoding="utf-8"))
            for node in ast.walk(tree):
                if isinstance(node, ast.Import):
                    modules = [alias.name for alias in node.names]
                elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                    modules = [node.module]
                else:
                    continue
                for module in modules:
                    found.setdefault(module.split(".")[0], f"{path.relative_to(ROOT)}:{node.lineno}")
    return found


def _own_modules():
    own = {"vcbmodel", "conftest"}
    for folder in ("studies", "tests"):
        own |= {p.stem for p in (ROOT / folder).rglob("*.py")}
    return own


def undeclared_imports(declared=None):
    distributions_of = metadata.packages_distributions()
    declared = declared_distributions() if declared is None else declared
    own = _own_modules()
    missing = []
    for module, where in sorted(top_level_imports().items()):
        if module in sys.stdlib_module_names or module in own:
            continue
        dists = distributions_of.get(module)
        if not dists:
            missing.append(f"{module} (not installed at all) imported at {where}")
        elif not any(_norm(d) in declared for d in dists):
            missing.append(f"{module} (distribution {'/'.join(sorted(set(dists)))}) imported at {where}")
    return missing


def test_every_third_party_import_is_declared():
    assert undeclared_imports() == []


def test_the_check_finds_an_undeclared_import(tmp_path):
    """The check itself: a declared list without sympy must flag the reference solve's import."""
    cfg = tmp_path / "setup.cfg"
    text = (ROOT / "setup.cfg").read_text()
    cfg.write_text(re.sub(r"\n\s*sympy[^\n]*", "", text))
    assert "sympy" not in declared_distributions(cfg)
    assert any(m.startswith("sympy") for m in undeclared_imports(declared_distributions(cfg)))

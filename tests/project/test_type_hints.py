"""Type hints on the public API stay (issue 21): every public function and method in the
scoped folders has a return annotation or at least one annotated parameter. Checked with
``ast``, nothing is imported; ``analysis/diagnose.py`` is left out (reworked elsewhere)."""
import ast
from pathlib import Path

import vcbmodel

PACKAGE = Path(vcbmodel.__file__).resolve().parent
#: folders of the package whose public functions must carry hints
FOLDERS = ("laws", "rig", "records", "model", "experiments", "builders", "compiled", "analysis", "app", "reference")
#: modules left out, relative to the package (the diagnosis is being reworked elsewhere: its module,
#: or its folder should it become one)
EXCLUDED = ("analysis/diagnose.py", "analysis/diagnose/")


def is_hinted(node):
    """A return annotation, or at least one annotated parameter (``self``/``cls`` count as none)."""
    if node.returns is not None:
        return True
    a = node.args
    params = a.posonlyargs + a.args + a.kwonlyargs + [p for p in (a.vararg, a.kwarg) if p is not None]
    return any(p.annotation is not None for p in params)


def public_functions(tree):
    """(qualified name, node) of the module's public functions and its public classes' public
    methods (names not starting with ``_``; nested functions are private)."""
    functions = (ast.FunctionDef, ast.AsyncFunctionDef)
    for node in tree.body:
        if isinstance(node, functions) and not node.name.startswith("_"):
            yield node.name, node
        elif isinstance(node, ast.ClassDef) and not node.name.startswith("_"):
            for sub in node.body:
                if isinstance(sub, functions) and not sub.name.startswith("_"):
                    yield f"{node.name}.{sub.name}", sub


def unhinted(source, label="<source>"):
    """``label:line name`` of each public function of ``source`` without any hint."""
    tree = ast.parse(source)
    return [f"{label}:{node.lineno} {name}" for name, node in public_functions(tree) if not is_hinted(node)]


def scoped_modules(package=PACKAGE):
    for folder in FOLDERS:
        for path in sorted((package / folder).rglob("*.py")):
            if not path.relative_to(package).as_posix().startswith(EXCLUDED):
                yield path


def test_every_public_function_has_hints():
    missing = []
    count = 0
    for path in scoped_modules():
        source = path.read_text(encoding="utf-8")
        count += sum(1 for _ in public_functions(ast.parse(source)))
        missing += unhinted(source, path.relative_to(PACKAGE).as_posix())
    assert count > 500, f"only {count} public functions found: is the package where the test looks?"
    assert not missing, "public functions without type hints:\n" + "\n".join(missing)


def test_checker_catches_an_unhinted_function():
    source = '''
def hinted(x: float) -> float:
    return x


def returns_only(x) -> float:
    return x


def bare(x, y=1.0):
    return x + y


def _private(x):
    return x


class Thing:
    def method(self, x):
        return x

    def typed(self) -> int:
        return 1

    def _helper(self, x):
        return x


class _Hidden:
    def method(self, x):
        return x
'''
    assert unhinted(source) == ["<source>:10 bare", "<source>:19 Thing.method"]


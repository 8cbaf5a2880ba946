"""The layers go one way: inputs -> coefficients -> equations -> solver -> results -> views.

The model packages (transport, thermal, geometry, properties, correlations) never import the
layers built on them: cases, estimation, cli, report, app, studies, and the orchestrator
``rotarydryer.simulation``. Every import statement is
checked (``import rotarydryer.X``, ``from rotarydryer.X import ...``, ``from ..X import ...``,
``from .. import X``), at module level and inside functions (found with ``ast``, nothing is
imported here).
"""

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = "rotarydryer"
MODEL_PACKAGES = ("transport", "thermal", "geometry", "properties", "correlations")
UPPER_LAYERS = frozenset({"cases", "estimation", "cli", "report", "app", "studies", "simulation"})

def _module_name(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _imported_modules(path: Path, root: Path = SRC):
    """(absolute module name, line) of every import statement of ``path`` (``root``: the
    directory holding the top-level package). ``from X import a, b`` gives X; ``from .. import a``
    gives the package's a (a subpackage or a name, both are imports of that layer)."""
    name = _module_name(path, root)
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, node.lineno
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = name.split(".")
                if path.name != "__init__.py":
                    base = base[:-1]  # the package holding the module
                base = base[: len(base) - (node.level - 1)]
                if node.module:
                    yield ".".join(base + [node.module]), node.lineno
                else:
                    for alias in node.names:
                        yield ".".join(base + [alias.name]), node.lineno
            elif node.module:
                yield node.module, node.lineno


def _layer(module: str):
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[0] == PACKAGE else None


def _violations():
    """{(file relative to src/rotarydryer, imported module): first line}."""
    found = {}
    for pkg in MODEL_PACKAGES:
        for path in sorted((SRC / PACKAGE / pkg).rglob("*.py")):
            rel = path.relative_to(SRC / PACKAGE).as_posix()
            for module, line in _imported_modules(path):
                if _layer(module) in UPPER_LAYERS:
                    found.setdefault((rel, module), line)
    return found


def test_model_packages_exist():
    for pkg in MODEL_PACKAGES:
        assert (SRC / PACKAGE / pkg / "__init__.py").is_file(), pkg


@pytest.mark.parametrize("file, source, expected", [
    ("transport/mod.py", "from ..cases import load_case", "rotarydryer.cases"),
    ("transport/mod.py", "from .. import report", "rotarydryer.report"),
    ("transport/sub/__init__.py", "from ...studies import x", "rotarydryer.studies"),
    ("thermal/mod.py", "import rotarydryer.estimation.fit as f", "rotarydryer.estimation.fit"),
    ("thermal/mod.py", "from rotarydryer.app.x import y", "rotarydryer.app.x"),
    ("geometry/mod.py", "def f():\n    if True:\n        from ..cli.simulate import main", "rotarydryer.cli.simulate"),
])
def test_the_checker_sees_relative_absolute_and_local_imports(tmp_path, file, source, expected):
    mod = tmp_path / PACKAGE / file
    mod.parent.mkdir(parents=True)
    mod.write_text(source)
    assert [m for m, _ in _imported_modules(mod, tmp_path)] == [expected]
    assert _layer(expected) in UPPER_LAYERS


def test_same_layer_imports_are_not_flagged(tmp_path):
    mod = tmp_path / PACKAGE / "transport" / "mod.py"
    mod.parent.mkdir(parents=True)
    mod.write_text("from .network import Network\nfrom .. import _validation\nfrom ..geometry import FlightedDrum\n"
                   "import numpy as np\nfrom rotarydryer.properties import water")
    assert not [m for m, _ in _imported_modules(mod, tmp_path) if _layer(m) in UPPER_LAYERS]


def test_models_do_not_import_upper_layers():
    """No exceptions: move the code instead (a model needs inputs passed in; plots go to report,
    analyses that load cases or fit go to studies, case readers to rotarydryer.cases.build)."""
    found = _violations()
    assert not found, "model modules import upper layers (" + "/".join(sorted(UPPER_LAYERS)) + "):\n" + "\n".join(
        f"  src/{PACKAGE}/{rel}:{line} imports {mod}" for (rel, mod), line in sorted(found.items()))

"""The front ends share logic through ``rotarydryer.services``, never through each other.

- ``rotarydryer.app`` (web app) never imports ``rotarydryer.cli``;
- ``rotarydryer.services`` imports neither front end (``rotarydryer.cli``, ``rotarydryer.app``)
  nor their toolkits (typer, click, streamlit).

Every import is checked without importing anything: ``import X``, ``from X import a``, relative
``from ..X import a`` and ``from .. import X``, at module level or inside functions, and
``importlib.import_module("X")`` / ``__import__("X")`` with a literal name (found with ``ast``).
"""

import ast
from importlib.util import resolve_name
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = "rotarydryer"
#: package (under src/rotarydryer) -> modules it must not import (or anything below them)
FORBIDDEN = {
    "app": ("rotarydryer.cli",),
    "services": ("rotarydryer.cli", "rotarydryer.app", "typer", "click", "streamlit"),
}


def imports(path: Path, root: Path = SRC):
    """(absolute module, line) of every import in ``path`` (``root``: the directory holding the
    top-level package). ``from X import a`` gives X and X.a (``a`` may be a submodule)."""
    package = ".".join(path.parent.relative_to(root).parts)   # a module's package, or an __init__'s own
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), filename=str(path))):
        if isinstance(node, ast.Import):
            yield from ((alias.name, node.lineno) for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = resolve_name("." * node.level + (node.module or ""), package) if node.level else node.module
            if node.module:
                yield base, node.lineno
            yield from ((f"{base}.{alias.name}", node.lineno) for alias in node.names if alias.name != "*")
        elif (isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant)
              and isinstance(node.args[0].value, str)
              and getattr(node.func, "attr", getattr(node.func, "id", None)) in ("import_module", "__import__")):
            yield node.args[0].value, node.lineno


def _is_under(module: str, banned: str) -> bool:
    return module == banned or module.startswith(banned + ".")


def violations(root: Path = SRC) -> dict:
    """{(file relative to root/rotarydryer, forbidden module): first line}; one entry per import
    statement (``from ..cli.lab import a, b`` is reported as rotarydryer.cli.lab only)."""
    found = {}
    for pkg, banned in FORBIDDEN.items():
        for path in sorted((root / PACKAGE / pkg).rglob("*.py")):
            rel, lines = path.relative_to(root / PACKAGE).as_posix(), set()
            for module, line in imports(path, root):
                if line not in lines and any(_is_under(module, b) for b in banned):
                    lines.add(line)
                    found.setdefault((rel, module), line)
    return found


def _tree(tmp_path: Path, file: str, source: str) -> Path:
    mod = tmp_path / PACKAGE / file
    mod.parent.mkdir(parents=True, exist_ok=True)
    mod.write_text(source)
    return tmp_path


@pytest.mark.parametrize("file, source, expected", [
    ("app/mod.py", "from ..cli.lab import x", "rotarydryer.cli.lab"),
    ("app/mod.py", "from .. import cli", "rotarydryer.cli"),
    ("app/mod.py", "def f():\n    if True:\n        from rotarydryer.cli import app", "rotarydryer.cli"),
    ("app/sub/__init__.py", "from ...cli import design", "rotarydryer.cli"),
    ("app/mod.py", "import importlib\nimportlib.import_module('rotarydryer.cli.lab')", "rotarydryer.cli.lab"),
    ("services/mod.py", "import typer", "typer"),
    ("services/mod.py", "def f():\n    from click.exceptions import Exit", "click.exceptions"),
    ("services/mod.py", "import streamlit as st", "streamlit"),
    ("services/mod.py", "from ..app.logic import png", "rotarydryer.app.logic"),
    ("services/mod.py", "import rotarydryer.cli._common", "rotarydryer.cli._common"),
])
def test_the_checker_flags_a_bad_import(tmp_path, file, source, expected):
    found = violations(_tree(tmp_path, file, source))
    assert (file, expected) in found, found


def test_the_checker_passes_allowed_imports(tmp_path):
    _tree(tmp_path, "app/mod.py", "import streamlit as st\nfrom ..services.lab import rig_analysis\n"
                                  "from .logic import png\nfrom .. import control as C\nimport typing")
    _tree(tmp_path, "services/mod.py", "import math\nfrom ._options import check_option\nfrom .. import design\n"
                                       "from ..lab import flight_rig\nimport typing\nimport clickhouse")
    assert violations(tmp_path) == {}


def test_the_checked_packages_exist():
    for pkg in FORBIDDEN:
        assert (SRC / PACKAGE / pkg / "__init__.py").is_file(), pkg
    assert {"control.py", "design.py", "lab.py"} <= {p.name for p in (SRC / PACKAGE / "services").glob("*.py")}


def test_app_and_services_do_not_import_the_cli_or_front_end_toolkits():
    """Logic both front ends need goes to ``rotarydryer.services`` (option checks raising
    ``ValueError``, runners with a ``progress`` callback); the CLI translates, never the app."""
    found = violations()
    assert not found, "forbidden imports:\n" + "\n".join(
        f"  src/{PACKAGE}/{rel}:{line} imports {mod}" for (rel, mod), line in sorted(found.items()))

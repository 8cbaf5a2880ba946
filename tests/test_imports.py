"""Imports at the top of each module by default (issue 27 item 6).

A package-internal import inside a function is allowed only in the modules listed here, each with
its reason: a measured start-up cost (the time ``import <module>`` gains when its function-local
imports move to the top, fresh interpreter, 2026-12-02, best of 3), an import cycle between two
modules of one package, or a front end (the CLI, the web app and their shared services import what
a command runs, so that ``rotarydryer --help`` starts in about 0.15 s). Third-party modules
(matplotlib, SALib, scikit-image, ...) may be imported where they are used; an optional one that is
not a dependency (Dask) only in the modules of ``OPTIONAL_IMPORTS``, inside functions.
"""

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "rotarydryer"

#: layers whose modules import what a command runs (start-up of the CLI and the app)
FRONT_ENDS = ("cli", "app", "services")

#: module -> why it keeps package-internal imports inside functions
LAZY = {
    "rotarydryer._workers": "start-up: +130-190 ms (the executor, for the CLI's option checks; 2026-12-07)",
    "rotarydryer.cases": "start-up: the thesis formats' schemas (rotarydryer.cases.readers, 10 ms) only when a file "
                         "of one is read, tracer data sets (rotarydryer.rtd, +0.4-0.9 s) and the material library "
                         "(numba kernels, +0.3 s) only when a case names them",
    "rotarydryer.control": "start-up: +984 ms (the coupled model and its studies)",
    "rotarydryer.dem.calibrate": "start-up: +161 ms",
    "rotarydryer.design": "start-up: +1569 ms",
    "rotarydryer.estimation.cases": "start-up: +582 ms",
    "rotarydryer.fmu": "start-up: +1522 ms",
    "rotarydryer.geometry.drum": "cycle: geometry.unloading and geometry.design_load import the drum",
    "rotarydryer.geometry.unloading": "cycle: geometry.drum imports the unloading model",
    "rotarydryer.lab.design_load_fit": "start-up: +73 ms",
    "rotarydryer.lab.flight_rig": "start-up: +70 ms",
    "rotarydryer.lab.images": "start-up: +832 ms",
    "rotarydryer.lab.steps": "start-up: +946 ms",
    "rotarydryer.properties.humid_air": "cycle: properties.combustion uses humid air",
    "rotarydryer.report.figures": "start-up: +1079 ms",
    "rotarydryer.report.html": "start-up: +1474 ms",
    "rotarydryer.report.manager": "start-up: +1563 ms",
    "rotarydryer.results": "start-up: +1613 ms (the case loader and the thermal model for a Results file)",
    "rotarydryer.rtd.models": "cycle: rtd.pulses uses the RTD models",
    "rotarydryer.simulation": "start-up: +144 ms; and the three upward imports (Simulation.fit, .calibrate, .target: "
                              "tests/test_layering.py)",
    "rotarydryer.studies.invicta_rtd_spread": "start-up: +952 ms",
    "rotarydryer.studies.mmg_cross_test": "start-up: +1008 ms",
    "rotarydryer.studies.sensitivity": "start-up: +1505 ms",
    "rotarydryer.studies.song_pilot": "start-up: +864 ms",
    "rotarydryer.transport.ajayi_predictive": "start-up: +73 ms",
    "rotarydryer.transport.forward_step": "start-up: +94 ms (the trajectory integrator)",
    "rotarydryer.transport.models": "start-up: +178 ms (the material laws' numba kernels)",
    "rotarydryer.transport.network": "start-up: rotarydryer.rtd (+0.4 s) for the moments of a simulated curve",
    "rotarydryer.transport.plots": "start-up: +560 ms (matplotlib)",
    "rotarydryer.transport.sections": "start-up: +59 ms",
}

#: optional third-party packages (not dependencies): the only modules that import them, each with its
#: reason; always inside a function, so that the package imports without them
OPTIONAL_IMPORTS = {
    "dask": {"rotarydryer.executor": "only where a Dask cluster is asked for (--scheduler, --cluster local:N); "
                                     "dask[distributed] is not a dependency"},
}


def _module(path: Path) -> str:
    parts = list(path.relative_to(SRC.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _local_internal_imports(path: Path) -> list[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    top = {id(m) for n in tree.body if isinstance(n, (ast.If, ast.Try, ast.Import, ast.ImportFrom))
           for m in ast.walk(n)}
    out = []
    for n in ast.walk(tree):
        if id(n) in top:
            continue
        if isinstance(n, ast.ImportFrom) and (n.level > 0 or (n.module or "").startswith("rotarydryer")):
            out.append(f"line {n.lineno}: {ast.unparse(n)}")
        elif isinstance(n, ast.Import) and any(a.name.startswith("rotarydryer") for a in n.names):
            out.append(f"line {n.lineno}: {ast.unparse(n)}")
    return out


def _library_modules():
    for p in sorted(SRC.rglob("*.py")):
        if p.relative_to(SRC).parts[0] not in FRONT_ENDS:
            yield _module(p), p


def test_package_imports_are_at_the_top_unless_listed():
    unlisted = {m: found for m, p in _library_modules() if m not in LAZY and (found := _local_internal_imports(p))}
    assert not unlisted, ("function-local package imports outside tests/test_imports.py LAZY (move them to the top "
                          f"of the module, or list the module with its measured reason): {unlisted}")


def test_every_listed_module_still_needs_its_entry():
    modules = dict(_library_modules())
    stale = [m for m in LAZY if m not in modules or not _local_internal_imports(modules[m])]
    assert not stale, f"LAZY entries with no function-local package import left: {stale}"


@pytest.mark.parametrize("source, expected", [
    ("def f():\n    from .x import y\n", ["line 2: from .x import y"]),
    ("from .x import y\n\ndef f():\n    return y\n", []),
    ("def f():\n    import numpy as np\n", []),                  # third party: where it is used
    ("if True:\n    from .x import y\n", []),                    # module-level block
])
def test_the_check_sees_function_local_imports(tmp_path, source, expected):
    p = tmp_path / "m.py"
    p.write_text(source)
    assert _local_internal_imports(p) == expected


def _imports_of(path: Path, package: str) -> list[tuple[int, bool]]:
    """(line, at module level) of every import of ``package`` (or a submodule) in ``path``."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    top = {id(m) for n in tree.body if isinstance(n, (ast.Import, ast.ImportFrom)) for m in ast.walk(n)}
    out = []
    for n in ast.walk(tree):
        names = [a.name for a in n.names] if isinstance(n, ast.Import) else \
            [n.module or ""] if isinstance(n, ast.ImportFrom) and not n.level else []
        if any(x == package or x.startswith(package + ".") for x in names):
            out.append((n.lineno, id(n) in top))
    return out


@pytest.mark.parametrize("package", sorted(OPTIONAL_IMPORTS))
def test_optional_packages_only_where_listed_and_inside_functions(package):
    allowed = OPTIONAL_IMPORTS[package]
    found = {m: hits for m, p in _library_modules() if (hits := _imports_of(p, package))}
    for p in sorted(SRC.rglob("*.py")):
        if p.relative_to(SRC).parts[0] in FRONT_ENDS and (hits := _imports_of(p, package)):
            found[_module(p)] = hits
    assert set(found) <= set(allowed), f"{package} imported outside {sorted(allowed)}: {sorted(set(found) - set(allowed))}"
    assert not [m for m, hits in found.items() if any(top for _, top in hits)], f"{package} imported at module level"
    assert set(allowed) <= set(found), f"stale OPTIONAL_IMPORTS entries for {package}: {sorted(set(allowed) - set(found))}"

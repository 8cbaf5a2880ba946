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


# ---- the whole house: one layer order over every import, and no cycles ---------------------------
#: Layers, lowest first. A module belongs to the longest entry that prefixes its name below
#: ``rotarydryer.``; it may import its own unit, any unit of its own layer, and lower layers.
LAYERS = (
    ("infrastructure", ("_validation", "_limits", "_io", "_jit", "_aot", "_threads", "_startup", "_display", "_plotting",
                        "_sparse_fd", "_grids",
                        "executor", "_workers", "_dask_worker",
                        "_extras", "_docblocks", "published", "data", "__version__")),
    ("correlations", ("correlations",)),
    ("properties", ("properties",)),
    ("geometry", ("geometry",)),
    ("statistics", ("estimation",)),     # least squares and intervals (fit, uncertainty); not its cases module
    ("tracer analysis", ("rtd",)),
    ("transport", ("transport",)),
    ("heat and mass", ("thermal",)),
    ("case readers and builders", ("cases",)),
    ("results container", ("results",)),
    ("assembler", ("simulation", "Simulation")),
    ("analyses", ("estimation.cases", "estimation.calibrate", "validate", "control", "design", "studies", "lab", "dem",
                  "fmu")),
    ("services and views", ("services", "report")),
    ("web app", ("app",)),
    ("command line", ("cli", "__main__")),
)
#: the package's own ``__init__`` is the facade over everything (lazy attributes only)
FACADES = frozenset({PACKAGE})
#: the only imports against the order, each with its reason: (importing module, imported unit)
ALLOWED_UPWARD = {
    ("rotarydryer.results", "simulation"): "deprecated alias results.run_case (warns; the assembler is simulation)",
    ("rotarydryer.simulation", "estimation.cases"): "Simulation.fit, a facade over estimation.cases.fit_case_to_tracer",
    ("rotarydryer.simulation", "estimation.calibrate"): "Simulation.calibrate, a facade over estimation.calibrate.calibrate",
    ("rotarydryer.simulation", "studies"): "Simulation.target, a facade over studies.target.target (its only import of studies)",
}
_UNITS = {u: i for i, (_, units) in enumerate(LAYERS) for u in units}


def _unit(module: str):
    """The layer unit of an absolute module name (None outside the package or for the facade)."""
    parts = module.split(".")
    if parts[0] != PACKAGE or len(parts) == 1:
        return None
    rest = parts[1:]
    for n in range(len(rest), 0, -1):
        u = ".".join(rest[:n])
        if u in _UNITS:
            return u
    return rest[0]


def _import_edges(root: Path = SRC):
    """[(importing module, its unit, imported unit, file, line)] of every internal import."""
    out = []
    for path in sorted((root / PACKAGE).rglob("*.py")):
        name = _module_name(path, root)
        if name in FACADES:
            continue
        src = _unit(name)
        for module, line in _imported_modules(path, root):
            dst = _unit(module)
            if dst is not None and dst != src:
                out.append((name, src, dst, path.relative_to(root).as_posix(), line))
    return out


def _order_violations(edges):
    bad = []
    for name, src, dst, rel, line in edges:
        if src not in _UNITS or dst not in _UNITS:
            bad.append(f"{rel}:{line}: unit {src if src not in _UNITS else dst!r} is in no layer of LAYERS")
        elif _UNITS[dst] > _UNITS[src] and (name, dst) not in ALLOWED_UPWARD:
            bad.append(f"{rel}:{line}: {LAYERS[_UNITS[src]][0]} ({src}) imports the higher layer "
                       f"{LAYERS[_UNITS[dst]][0]} ({dst})")
    return bad


def _cycles(edges):
    """Cycles of the unit graph (Tarjan's strongly connected components of two or more units),
    the listed upward imports left out."""
    graph: dict = {}
    for name, src, dst, _, _ in edges:
        if (name, dst) not in ALLOWED_UPWARD:
            graph.setdefault(src, set()).add(dst)
    index, low, stack, on, comps = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                comps.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return comps


def test_every_import_follows_the_layer_order():
    bad = _order_violations(_import_edges())
    assert not bad, "imports against the layer order (tests/test_layering.py LAYERS):\n  " + "\n  ".join(bad)


def test_no_import_cycles_between_units():
    comps = _cycles(_import_edges())
    assert not comps, f"import cycles between units: {comps}"


def _tree(tmp_path, files):
    for rel, text in files.items():
        p = tmp_path / PACKAGE / rel
        p.parent.mkdir(parents=True, exist_ok=True)
        p.write_text(text)
    return tmp_path


@pytest.mark.parametrize("files, expect", [
    # a model importing the assembler (function-local): upward
    ({"transport/__init__.py": "", "transport/m.py": "def f():\n    from ..simulation import Simulation\n",
      "simulation.py": ""}, "order"),
    # properties importing heat and mass: upward (the import removed in issue 27)
    ({"properties/__init__.py": "", "properties/materials.py": "from ..thermal.drying import DryingKinetics\n",
      "thermal/__init__.py": "", "thermal/drying.py": ""}, "order"),
    # two units of one layer importing each other: a cycle, not an order violation
    ({"studies/__init__.py": "from ..design import x\n", "design.py": "from .studies import y\n"}, "cycle"),
    # an unknown top-level unit must be placed in LAYERS
    ({"newthing.py": "from .transport import x\n", "transport/__init__.py": ""}, "order"),
    # downward and same-unit imports are fine
    ({"thermal/__init__.py": "", "thermal/m.py": "from ..transport.network import Network\nfrom .n import y\n",
      "transport/__init__.py": "", "transport/network.py": "", "thermal/n.py": ""}, None),
])
def test_the_house_checker_fails_on_upward_and_cyclic_imports(tmp_path, files, expect):
    edges = _import_edges(_tree(tmp_path, files))
    order, cycles = _order_violations(edges), _cycles(edges)
    assert bool(order) == (expect == "order"), order
    assert bool(cycles) == (expect == "cycle"), cycles

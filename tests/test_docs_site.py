"""The documentation site builds with warnings as errors (``mkdocs build --strict``).

Needs the ``docs`` extra (mkdocs, mkdocstrings[python]); skipped with the reason otherwise.
Build it yourself: ``python -m pip install -e ".[docs]" && mkdocs build --strict``.
"""

from __future__ import annotations

import importlib.util
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
_MISSING = [m for m in ("mkdocs", "mkdocstrings", "mkdocstrings_handlers.python")
            if importlib.util.find_spec(m.split(".")[0]) is None
            or (m == "mkdocstrings_handlers.python" and importlib.util.find_spec("mkdocstrings_handlers") is None)]


@pytest.mark.skipif(bool(_MISSING), reason=f"docs extra not installed (missing {', '.join(_MISSING)}): "
                    "python -m pip install -e '.[docs]'")
def test_docs_site_builds_strict(tmp_path):
    site = tmp_path / "site"
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)],
                          cwd=ROOT, capture_output=True, text=True, timeout=600)
    log = proc.stdout + proc.stderr
    assert proc.returncode == 0, f"mkdocs build --strict failed:\n{log[-5000:]}"
    assert "WARNING" not in log, log[-5000:]
    for page in ("index.html", "tutorial.html", "references.html", "reference/simulation.html",
                 "guide/own_material.html", "explanation/thermal_modes.html"):
        assert (site / page).is_file(), page
    api = (site / "reference" / "simulation.html").read_text(encoding="utf-8")
    assert "Simulation" in api and "steady_state" in api     # generated from the docstrings

"""The documentation site builds with warnings as errors (``mkdocs build --strict``), and its
HTML shows no raw Sphinx/RST markup and no unrendered maths.

Needs the ``docs`` extra (mkdocs, mkdocstrings[python], pymdown-extensions, latex2mathml);
skipped with the reason otherwise. The site is built once per test session (``built_site``).
Build it yourself: ``python -m pip install -e ".[docs]" && mkdocs build --strict``.
"""

from __future__ import annotations

import html
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
_MISSING = [m for m in ("mkdocs", "mkdocstrings", "mkdocstrings_handlers.python", "pymdownx", "latex2mathml")
            if importlib.util.find_spec(m.split(".")[0]) is None
            or (m == "mkdocstrings_handlers.python" and importlib.util.find_spec("mkdocstrings_handlers") is None)]


_NEEDS_DOCS = pytest.mark.skipif(bool(_MISSING), reason=f"docs extra not installed (missing {', '.join(_MISSING)}): "
                                 "python -m pip install -e '.[docs]'")


@pytest.fixture(scope="module")
def built_site(tmp_path_factory):
    """(site directory, build log) of one ``mkdocs build --strict``, shared by the tests below."""
    site = tmp_path_factory.mktemp("docs") / "site"
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(site)],
                          cwd=ROOT, capture_output=True, text=True, timeout=600)
    return site, proc.returncode, proc.stdout + proc.stderr


@_NEEDS_DOCS
def test_docs_site_builds_strict(built_site):
    site, returncode, log = built_site
    assert returncode == 0, f"mkdocs build --strict failed:\n{log[-5000:]}"
    assert "WARNING" not in log, log[-5000:]
    for page in ("index.html", "tutorial.html", "references.html", "reference/simulation.html",
                 "guide/own_material.html", "explanation/thermal_modes.html", "gallery.html"):
        assert (site / page).is_file(), page
    api = (site / "reference" / "simulation.html").read_text(encoding="utf-8")
    assert "Simulation" in api and "steady_state" in api     # generated from the docstrings


# Sphinx roles and RST directives that Markdown shows as raw text (issue "docs that render")
_RAW_ROLE = re.compile(r":(?:py:)?(?:math|class|func|meth|attr|data|mod|ref|exc|obj):`?")
_RAW_DIRECTIVE = re.compile(r"\.\. (?:math|code-block|code|note|warning|table|csv-table)::")
# maths left as source: arithmatex markup not turned into MathML, $$ blocks, $...$ spans
_RAW_MATH = re.compile(r'class="arithmatex"|\$\$|(?<![\w$])\$(?=[^\s$\d])[^$<>\n]*[^\s$\\]\$(?![\w$])'
                       r"|\\\(|\\\[.*?\\\]")
# pages whose sources carry maths: each must show MathML
_MATH_PAGES = ("reference/correlations.html", "reference/rtd.html", "reference/thermal.html", "reference/geometry.html",
               "reference/properties.html", "reference/estimation.html")


def _text_outside_code(page_html: str) -> str:
    """The page without its code (pre, code), scripts and MathML: the prose a reader sees."""
    body = re.sub(r"<(pre|code|script|style|math)\b[^>]*>.*?</\1>", " ", page_html, flags=re.S)
    return html.unescape(re.sub(r"<[^>]+>", " ", body))


@_NEEDS_DOCS
def test_docs_site_has_no_raw_roles_or_maths(built_site):
    site, returncode, log = built_site
    assert returncode == 0, f"mkdocs build --strict failed:\n{log[-5000:]}"
    pages = sorted(p for p in site.rglob("*.html") if p.relative_to(site).parts[0] not in ("search", "assets"))
    assert len(pages) > 30
    problems = []
    for page in pages:
        raw = page.read_text(encoding="utf-8")
        text = _text_outside_code(raw)
        for kind, pattern in (("role", _RAW_ROLE), ("directive", _RAW_DIRECTIVE), ("maths", _RAW_MATH)):
            for m in pattern.finditer(text):
                problems.append(f"{page.relative_to(site)}: raw {kind} {text[max(0, m.start() - 40):m.end() + 40]!r}")
        if 'class="arithmatex"' in raw:
            problems.append(f"{page.relative_to(site)}: arithmatex markup not converted to MathML")
    assert not problems, "\n".join(problems[:50])
    for name in _MATH_PAGES:
        raw = (site / name).read_text(encoding="utf-8")
        assert "<math" in raw, f"{name}: no MathML (<math>) although its docstrings carry maths"
    n_math = sum((site / name).read_text(encoding="utf-8").count("<math") for name in _MATH_PAGES)
    assert n_math > 100, n_math        # about 180 formulas in the API reference

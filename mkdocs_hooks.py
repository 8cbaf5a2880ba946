"""MkDocs hooks for the documentation site (mkdocs.yml ``hooks:``).

* Pages in ``docs/`` that the nav does not list (topic pages added later) are appended to the
  Explanation section, so a new page is never left out of the site.
* Links from a docs page to a repository file outside ``docs/`` (``../../examples/size_a_dryer.py``)
  become the file's path in code style: the site has no copy of the sources. A link to a file
  that does not exist is left alone, so ``mkdocs build --strict`` still reports it.
* Maths (``$...$`` inline, ``$$ ... $$`` blocks, in the pages and in the docstrings), which
  ``pymdownx.arithmatex`` in generic mode leaves as ``<span class="arithmatex">\\(...\\)</span>``
  and ``<div class="arithmatex">\\[...\\]</div>``, becomes MathML (``<math>``) at build time with
  ``latex2mathml``: browsers render MathML natively, so the site needs no JavaScript and no CDN.
  A formula latex2mathml cannot convert fails the build with the page and the formula.
"""

from __future__ import annotations

import html
import posixpath
import re
from pathlib import Path

_LINK = re.compile(r"(?<!!)\[([^\]]+)\]\(([^)\s]+)\)")


def _listed(nav) -> set[str]:
    out: set[str] = set()
    if isinstance(nav, str):
        out.add(nav)
    elif isinstance(nav, dict):
        for v in nav.values():
            out |= _listed(v)
    elif isinstance(nav, list):
        for v in nav:
            out |= _listed(v)
    return out


def on_config(config, **kwargs):
    nav = config.get("nav")
    if not nav:
        return config
    docs = Path(config["docs_dir"])
    listed = _listed(nav)
    extra = sorted(p.relative_to(docs).as_posix() for p in docs.glob("*.md"))
    extra = [p for p in extra if p not in listed]
    if extra:
        for section in nav:
            if isinstance(section, dict) and "Explanation" in section:
                section["Explanation"].extend(extra)
                break
        else:
            nav.append({"More topics": extra})
    return config


def on_page_markdown(markdown, page, config, files, **kwargs):
    docs = Path(config["docs_dir"]).resolve()
    repo = docs.parent
    src_dir = posixpath.dirname(page.file.src_uri)

    def fix(m):
        text, target = m.group(1), m.group(2)
        if "://" in target or target.startswith(("#", "mailto:")):
            return m.group(0)
        path = target.split("#", 1)[0]
        if not path:
            return m.group(0)
        rel = posixpath.normpath(posixpath.join(src_dir, path))
        if not rel.startswith("../"):
            return m.group(0)                       # inside docs/: mkdocs validates it
        full = (docs / rel).resolve()
        if not full.exists():
            return m.group(0)                       # broken: let the strict build report it
        shown = full.relative_to(repo).as_posix()
        return text if text.strip("`") == shown else f"{text} (`{shown}`)"

    # leave fenced code blocks untouched
    parts = re.split(r"(^```.*?^```)", markdown, flags=re.S | re.M)
    return "".join(p if p.startswith("```") else _LINK.sub(fix, p) for p in parts)


_MATH = re.compile(r'<(span|div) class="arithmatex">(.*?)</\1>', re.S)
_DELIMS = {"span": (r"\(", r"\)"), "div": (r"\[", r"\]")}


def math_to_mathml(page_html: str, where: str = "page") -> str:
    """Replace the arithmatex (generic mode) spans and divs of ``page_html`` by MathML."""
    from latex2mathml.converter import convert

    def repl(m):
        tag, tex = m.group(1), html.unescape(m.group(2)).strip()
        opening, closing = _DELIMS[tag]
        if tex.startswith(opening) and tex.endswith(closing):
            tex = tex[len(opening):-len(closing)].strip()
        try:
            mathml = convert(tex, display="block" if tag == "div" else "inline")
        except Exception as exc:  # latex2mathml raises its own exception classes
            raise ValueError(f"{where}: cannot convert the formula {tex!r} to MathML: {exc}") from exc
        return f'<div class="math">{mathml}</div>' if tag == "div" else mathml

    return _MATH.sub(repl, page_html)


def on_page_content(html_text, page, config, files, **kwargs):
    return math_to_mathml(html_text, page.file.src_uri)


# --- griffe extension (mkdocs.yml: mkdocstrings handlers.python.options.extensions) ------------
try:
    from griffe import Extension
except ImportError:  # the hooks are also imported without the docs extra (never in a build)
    Extension = object


def fence_doctests(text: str) -> str:
    """Put runs of ``>>>`` lines (with their expected output) outside numpydoc sections in
    ``pycon`` code fences, so that a module docstring's doctest renders as code, not Markdown
    (``['a', 'b']`` would otherwise read as a link)."""
    lines, out, i = text.split("\n"), [], 0
    section = False
    while i < len(lines):
        line = lines[i]
        if i + 1 < len(lines) and lines[i + 1].strip() and set(lines[i + 1].strip()) == {"-"} and line.strip():
            section = line.strip() != "Examples"
        if not line.strip():
            pass
        elif line.startswith(">>>") and not section:
            block = []
            while i < len(lines) and lines[i].strip() and not lines[i].startswith("```"):
                block.append(lines[i])
                i += 1
            out += ["```pycon", *block, "```"]
            continue
        elif not line.startswith(" ") and not section:
            pass
        out.append(line)
        i += 1
    return "\n".join(out)


class DoctestFences(Extension):
    """Fence doctests in docstrings before mkdocstrings renders them."""

    def on_instance(self, *, obj, **kwargs):
        doc = getattr(obj, "docstring", None)
        if doc is not None and ">>>" in doc.value:
            doc.value = fence_doctests(doc.value)

"""The project's bibliography (``rotarydryer/data/references.toml``) for the report.

>>> from rotarydryer.report.references import cited_keys, format_reference, load_references
>>> refs = load_references()
>>> refs["lee2008"]["cite"]
'Lee (2008)'
>>> cited_keys("as in Ajayi (2011) Eq. 4.19 and Lee (2008) Table 4.1")
['ajayi2011', 'lee2008']
>>> format_reference("song2003", markup=False)
'Song, Y. (2003). Solids transportation, heat and mass transfer in rotary dryers. M.A.Sc. thesis, University of Ottawa, Ottawa, Canada.'

One file holds the bibliographic details; ``docs/references.md`` lists the same sources with
the equations the code implements (a test checks that the two agree).
"""

from __future__ import annotations

import functools
import html
import re
import tomllib
from importlib import resources

__all__ = ["load_references", "format_reference", "cited_keys", "strip_line_numbers"]


@functools.lru_cache(maxsize=1)
def _load() -> dict:
    text = (resources.files("rotarydryer") / "data" / "references.toml").read_text(encoding="utf-8")
    return tomllib.loads(text)


def load_references() -> dict[str, dict]:
    """``{key: entry}`` of every source (a copy; fields in the file's header comment)."""
    return {k: dict(v) for k, v in _load().items()}


def _authors(names: list[str]) -> str:
    return names[0] if len(names) == 1 else ", ".join(names[:-1]) + " and " + names[-1]


def format_reference(key: str, *, markup: bool = True) -> str:
    """Full reference of ``key``: authors (year). Title. Source details.  With ``markup`` the
    result is HTML (escaped, book/journal/thesis titles in ``<i>``) and a URL becomes a plain
    text note (the report has no links out)."""
    e = _load()[key]
    esc = html.escape if markup else (lambda s: s)

    def it(s):
        return f"<i>{esc(s)}</i>" if markup else s

    kind = e["type"]
    title = e["title"]
    head = f"{esc(_authors(e['authors']))} ({e['year']}). "
    if kind == "article":
        body = (f"{esc(title)}. {it(e['journal'])} {esc(e['volume'])}, "
                f"{esc(e['pages'].replace('-', chr(8211)) if markup else e['pages'])}.")
    elif kind in ("phdthesis", "mastersthesis"):
        body = f"{it(title)}. {esc(e['degree'])}, {esc(e['institution'])}, {esc(e['place'])}."
    elif kind == "report":
        body = f"{it(title)}. {esc(e['institution'])}, {esc(e['note'])}."
    else:  # book, handbook
        body = ", ".join(p for p in (it(title), esc(e.get("edition", "")), esc(e.get("publisher", ""))) if p) + "."
        if e.get("note"):
            body = body[:-1] + f", {esc(e['note'])}."
    if kind == "article" and e.get("note"):
        body += f" {esc(e['note'])}."
    if e.get("url"):
        body += f" {esc(e['url'])}"
    return head + body


def _pattern(label: str) -> re.Pattern:
    # "Lee (2008)" also matches "Lee 2008" and "Lee et al. (2008)"; "&" may be "and"
    name, year = re.fullmatch(r"(.+?) \((\d{4})\)", label).groups()
    name = re.escape(name).replace(r"\ et\ al\.", r"(?:\ et\ al\.)?").replace(r"\ \&\ ", r"\s+(?:&|and)\s+")
    return re.compile(rf"\b{name}(?:\s+et\s+al\.)?\s+\(?{year}\)?")


def cited_keys(text: str) -> list[str]:
    """Keys of the sources cited (author-year, e.g. "Lee (2008)", "Baker 1988") in ``text``
    (plain text; unescape HTML first), in order of first citation."""
    found = []
    for key, e in _load().items():
        m = _pattern(e["cite"]).search(text)
        if m:
            found.append((m.start(), key))
    return [k for _, k in sorted(found)]


_LINE_REFS = re.compile(r"\s*\((?:l|L)\.?\s?\d+(?:\s*-\s*\d+)?(?:\s*,\s*\d+(?:\s*-\s*\d+)?)*\)"   # (l.4130-4144)
                        r"|\s+(?:l\.|L)\d+(?:\s*-\s*\d+)?\b")                                     # l.12456, L1270


def strip_line_numbers(text: str) -> str:
    """``text`` without line numbers of the plain-text copies of the sources ("(l.4130-4144)",
    "l.12456", "L1270"): the report cites equations, tables and sections only."""
    return re.sub(r"\s+([,;:)])", r"\1", _LINE_REFS.sub("", text)).strip()

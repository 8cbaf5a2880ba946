"""Generated blocks in the docs: an example script computes a table and checks (or rewrites) the
block between two HTML-comment markers of a docs page, so the published tables never drift from
what the code computes. Used by ``examples/mmg_cross_test.py`` and ``examples/song_prediction.py``."""

from __future__ import annotations

import re
from pathlib import Path

from ._io import write_text_atomic

__all__ = ["same_block", "sync_doc_block"]


def _tokens(text):
    return [t for t in re.split(r"[\s|/()%*,:;]+", text) if t]


def same_block(a: str, b: str, rel: float = 0.02, abs_tol: float = 0.02) -> bool:
    """The two blocks hold the same words and, where both are numbers, the same values to
    ``rel`` (relative) + ``abs_tol`` (absolute)."""
    ta, tb = _tokens(a), _tokens(b)
    if len(ta) != len(tb):
        return False
    for x, y in zip(ta, tb):
        if x == y:
            continue
        try:
            fx, fy = float(x), float(y)
        except ValueError:
            return False
        if abs(fx - fy) > abs_tol + rel * abs(fy):
            return False
    return True


def sync_doc_block(doc, begin: str, end: str, block: str, *, update: bool, script: str) -> str:
    """Compare ``block`` with the generated block of ``doc`` (between ``begin`` and ``end``), or
    rewrite it when ``update``. Returns "updated", "up to date" or "missing" (no doc); raises
    ``SystemExit`` with a message naming ``script --update-docs`` when they differ."""
    doc = Path(doc)
    if not doc.exists():
        return "missing"
    text = doc.read_text(encoding="utf-8")
    if begin not in text or end not in text:
        raise SystemExit(f"{doc}: the markers {begin} / {end} are missing")
    head, rest = text.split(begin, 1)
    old, tail = rest.split(end, 1)
    if update:
        write_text_atomic(doc, head + begin + "\n" + block + end + tail)
        return "updated"
    if not same_block(old, block):
        raise SystemExit(f"{doc}: the generated tables differ from this run; run python {script} --update-docs "
                         "and review the change")
    return "up to date"

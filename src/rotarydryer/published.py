"""Published data sets shipped with the package (``rotarydryer/data/*.csv``).

Each file's first line (``# ...``) gives its source: document, table and line
numbers, units and column meanings. Columns marked DERIVED were computed from the
source, not printed in it.
"""

from __future__ import annotations

import csv
from importlib import resources

__all__ = ["list_published", "read_published_csv", "published_source"]


def _text(name: str) -> str:
    path = resources.files("rotarydryer.data").joinpath(name)
    if not path.is_file():
        raise ValueError(f"no published data set named {name!r}; see list_published()")
    return path.read_text("utf-8")


def list_published() -> list[str]:
    """Names of the shipped CSV files."""
    return sorted(p.name for p in resources.files("rotarydryer.data").iterdir() if p.name.endswith(".csv"))


def published_source(name: str) -> str:
    """The source line (without the leading '#') of a shipped CSV file."""
    first = _text(name).splitlines()[0]
    return first.lstrip("#").strip()


def read_published_csv(name: str) -> list[dict[str, str]]:
    """Rows of a shipped CSV file as dictionaries of strings (comment lines skipped)."""
    lines = [ln for ln in _text(name).splitlines() if ln.strip() and not ln.startswith("#")]
    return list(csv.DictReader(lines))

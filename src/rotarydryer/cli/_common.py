"""Argument helpers shared by the command modules (kept import-light)."""

from __future__ import annotations

from pathlib import Path
from typing import List, Optional


def parse_sets(sets: Optional[List[str]]) -> dict:
    """``["operating.rpm=4", ...]`` -> ``{"operating.rpm": "4"}``; the case model converts the
    values to their types and checks them."""
    out = {}
    for item in sets or []:
        if "=" not in item:
            raise ValueError(f"--set {item!r}: expected KEY=VALUE, e.g. transport.n_cells=35")
        k, v = item.split("=", 1)
        out[k.strip()] = v.strip()
    return out


def load_tracer(data: str):
    """A tracer curve from a CSV file path or the name of a shipped data set."""
    from ..rtd import load_tracer_csv, load_tracer_dataset, tracer_datasets

    if Path(data).is_file():
        return load_tracer_csv(data)
    if data in tracer_datasets():
        return load_tracer_dataset(data)
    raise ValueError(
        f"DATA {data!r} is neither an existing file nor a shipped data set "
        f"({', '.join(tracer_datasets())})"
    )

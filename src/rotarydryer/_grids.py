"""Sweep grids: the cartesian product of ``KEY=V1,V2`` options and the ceiling on runs (no model
imports, so the command line loads it at start-up)."""

from __future__ import annotations

import itertools
import math

__all__ = ["MAX_POINTS", "check_points", "grid_product", "parse_grid"]

#: most runs one sweep may ask for (a grid or list above it is refused before anything runs)
MAX_POINTS = 10000


def check_points(n: int, what: str):
    """Refuse a sweep of more than `MAX_POINTS` runs (``what`` names the option)."""
    if n > MAX_POINTS:
        raise ValueError(f"{what} has {n} runs; the limit is {MAX_POINTS} per sweep (split it, or run "
                         "a global sensitivity study with fewer points)")


def grid_product(keys, values, what: str) -> list[dict]:
    """The cartesian product of ``values`` (one list per key) as override dicts, in order; refused
    (``what`` names the option) above `MAX_POINTS` runs."""
    check_points(math.prod(len(v) for v in values), what)
    return [dict(zip(keys, combo)) for combo in itertools.product(*values)]


def parse_grid(items) -> list[dict]:
    """``["operating.rpm=2,3", "drum.slope=2,4"]`` -> the cartesian product as override dicts
    (at most `MAX_POINTS`)."""
    keys, values = [], []
    for item in items or []:
        if "=" not in item:
            raise ValueError(f"--grid {item!r}: expected KEY=V1,V2,..., e.g. operating.rpm=2,3,4")
        k, v = item.split("=", 1)
        parts = [x.strip() for x in v.split(",")]
        vals = [x for x in parts if x]
        if not vals:
            raise ValueError(f"--grid {item!r}: no values")
        if len(vals) < len(parts):
            raise ValueError(f"--grid {item!r}: an empty value between commas (V1,V2,...)")
        if k.strip() in keys:
            raise ValueError(f"--grid {k.strip()} is given twice: one --grid per key, with all its values "
                             "(KEY=V1,V2,...)")
        keys.append(k.strip())
        values.append(vals)
        check_points(math.prod(len(v) for v in values), "--grid")
    return grid_product(keys, values, "--grid") if keys else []

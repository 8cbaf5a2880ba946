"""Argument helpers shared by the command modules (kept import-light)."""

from __future__ import annotations

import math
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

    p = Path(data)
    if data in tracer_datasets() and not p.exists():
        return load_tracer_dataset(data)
    if p.exists() or p.is_symlink() or p.suffix or any(sep in data for sep in ("/", "\\")):
        return load_tracer_csv(p)  # names the file: missing, a directory, not UTF-8, too large...
    raise ValueError(
        f"DATA {data!r} is neither an existing file nor a shipped data set "
        f"({', '.join(tracer_datasets())})"
    )


def check_option(option: str, value, low: float = -math.inf, high: float = math.inf, *, unit: str = "",
                 low_inclusive: bool = False, high_inclusive: bool = False) -> float:
    """``value`` of the command-line option ``option`` (e.g. ``--rpm``) as a float, or a
    ``ValueError`` naming the option, the value as a plain number, the allowed range and unit:
    ``--rpm = -2 rev/min is outside the allowed range (0, 100] rev/min``."""
    u = f" {unit}" if unit else ""
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{option} = {value!r} is not a number{(' (' + unit + ')') if unit else ''}") from None
    ok = math.isfinite(v) and (v >= low if low_inclusive else v > low) and (v <= high if high_inclusive else v < high)
    if not ok:
        lb = "[" if low_inclusive else "("
        hb = "]" if high_inclusive else ")"
        shown = _plain(v)
        if not math.isfinite(v) and low == -math.inf and high == math.inf:
            raise ValueError(f"{option} = {shown} is not a finite number{(' (' + unit + ')') if unit else ''}")
        why = "is not a finite number" if not math.isfinite(v) else "is outside the allowed range"
        raise ValueError(f"{option} = {shown}{u} {why}; allowed: {lb}{_plain(low)}, {_plain(high)}{hb}{u}")
    return v


def _plain(x: float) -> str:
    if math.isinf(x):
        return "inf" if x > 0 else "-inf"
    if math.isnan(x):
        return "nan"
    return str(int(x)) if x == int(x) and abs(x) < 1e15 else f"{x:.6g}"


def check_out_dir(option: str, out) -> None:
    """Refuse, before any work is done, an output directory option that cannot be one: an
    existing file, or a path under a file (``a_file.txt/sub``). Nothing is created here."""
    if out is None:
        return
    p = Path(out)
    if p.exists() and not p.is_dir():
        raise ValueError(f"{option} {str(p)!r} is an existing file, not a directory; give a directory for the outputs")
    q = p
    while not q.exists():
        if q.parent == q:
            return
        q = q.parent
    if not q.is_dir():
        raise ValueError(f"{option} {str(p)!r}: cannot create the directory, {str(q)!r} is a file")


def check_out_file(option: str, out, suffixes=None) -> None:
    """Refuse an output file option that is a directory, lies under a file or has an unknown
    suffix (``suffixes``: allowed lower-case suffixes without the dot; none = any)."""
    if out is None:
        return
    p = Path(out)
    if p.is_dir():
        raise ValueError(f"{option} {str(p)!r} is a directory; give a file name (e.g. {str(p / 'annotated.png')!r})")
    if suffixes is not None and p.suffix and p.suffix.lower().lstrip(".") not in suffixes:
        raise ValueError(f"{option} {str(p)!r}: unknown file type {p.suffix!r}; use one of "
                         f"{', '.join('.' + s for s in suffixes)}")
    q = p.parent
    while not q.exists():
        if q.parent == q:
            return
        q = q.parent
    if not q.is_dir():
        raise ValueError(f"{option} {str(p)!r}: cannot create the file, {str(q)!r} is a file")

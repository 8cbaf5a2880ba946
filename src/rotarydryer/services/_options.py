"""Option checking of the front ends: a value with its option name, range and unit, or a
one-line ``ValueError`` naming them (import-light: `math` only)."""

from __future__ import annotations

import math

from .._workers import check_cluster, check_scheduler, check_workers, executor_from_options, usable_cpus

__all__ = ["check_option", "check_scheduler", "check_workers", "check_cluster", "executor_from_options", "usable_cpus"]


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

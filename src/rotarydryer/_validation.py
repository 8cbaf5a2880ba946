"""Input validation shared by the whole package.

Every public function checks its inputs with these helpers so that bad input
raises a ``ValueError`` that names the argument, the offending value and the
allowed range, instead of returning NaN or failing deep inside NumPy/SciPy.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["check_range", "check_positive", "check_finite", "check_choice"]


def _describe(value: Any) -> str:
    arr = np.asarray(value)
    if arr.ndim == 0:
        return repr(arr.item())
    return f"array with min {np.nanmin(arr)!r} and max {np.nanmax(arr)!r}"


def check_finite(name: str, value: Any) -> np.ndarray:
    """Return ``value`` as a float array; raise if any element is NaN or infinite."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a real number, got {value!r}") from exc
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} must be finite, got {_describe(value)}")
    return arr


def check_range(
    name: str,
    value: Any,
    low: float = -math.inf,
    high: float = math.inf,
    *,
    low_inclusive: bool = False,
    high_inclusive: bool = False,
    unit: str = "",
) -> np.ndarray:
    """Check that every element of ``value`` lies in the interval (low, high).

    Bounds are open unless ``low_inclusive``/``high_inclusive`` are set.
    Returns the value as a float array (0-d for scalars).
    """
    arr = check_finite(name, value)
    lo_ok = arr >= low if low_inclusive else arr > low
    hi_ok = arr <= high if high_inclusive else arr < high
    if not (np.all(lo_ok) and np.all(hi_ok)):
        lb = "[" if low_inclusive else "("
        hb = "]" if high_inclusive else ")"
        u = f" {unit}" if unit else ""
        raise ValueError(
            f"{name} = {_describe(value)}{u} is outside the allowed range "
            f"{lb}{low:g}, {high:g}{hb}{u}"
        )
    return arr


def check_positive(name: str, value: Any, unit: str = "") -> np.ndarray:
    """Check that every element of ``value`` is finite and > 0."""
    return check_range(name, value, 0.0, math.inf, unit=unit)


def check_choice(name: str, value: str, choices) -> str:
    """Check that ``value`` is one of ``choices`` (strings)."""
    choices = tuple(choices)
    if value not in choices:
        raise ValueError(f"{name} = {value!r} is not one of {', '.join(map(repr, choices))}")
    return value

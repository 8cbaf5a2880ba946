"""Helpers shared by the correlation modules (range warnings, unit constants)."""

from __future__ import annotations

import warnings

import numpy as np

from . import CorrelationRangeWarning

STANDARD_GRAVITY = 9.80665  # m/s^2
SECONDS_PER_HOUR = 3600.0


def warn_outside(
    name: str,
    value,
    low: float,
    high: float,
    *,
    unit: str = "",
    source: str = "",
    stacklevel: int = 3,
) -> None:
    """Warn with `CorrelationRangeWarning` if any element of ``value`` is outside [low, high].

    The message names the argument, the offending value(s), the fitted range and the source.
    """
    arr = np.asarray(value, dtype=float)
    if arr.size == 0:
        return
    if np.any(arr < low) or np.any(arr > high):
        u = f" {unit}" if unit else ""
        if arr.ndim == 0:
            desc = f"{arr.item():g}"
        else:
            desc = f"array with min {np.min(arr):g} and max {np.max(arr):g}"
        src = f" of {source}" if source else ""
        warnings.warn(
            f"{name} = {desc}{u} is outside the fitted range{src} "
            f"[{low:g}, {high:g}]{u}; the result is an extrapolation",
            CorrelationRangeWarning,
            stacklevel=stacklevel,
        )


def as_result(x):
    """Return a Python float for 0-d results, otherwise the array."""
    arr = np.asarray(x, dtype=float)
    return float(arr) if arr.ndim == 0 else arr

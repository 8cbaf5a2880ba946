"""Input validation shared by the whole package.

Every public function checks its inputs with these helpers so that bad input
raises a ``ValueError`` that names the argument (the case-file key or the CLI
option the user set), the offending value as a plain number and the allowed
range with its unit, instead of returning NaN or failing deep inside NumPy/SciPy:

>>> check_range("drum.length", float("nan"), 0.0, unit="m")
Traceback (most recent call last):
...
ValueError: drum.length = nan m is not a number (allowed range (0, inf) m)
>>> check_range("solids.repose_angle", [616.1, 643.0], 0.0, 90.0, unit="deg")
Traceback (most recent call last):
...
ValueError: solids.repose_angle = 616.1 to 643 deg (2 values) is outside the allowed range (0, 90) deg

Numbers in messages never carry NumPy reprs (``np.float64(...)``, ``array(...)``):
`fmt_number` writes them as a user would type them.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

__all__ = ["check_range", "check_positive", "check_finite", "check_choice", "finite_number", "fmt_number", "describe"]


def fmt_number(x: Any) -> str:
    """A number as a user would type it: ``1000``, ``0.01``, ``-1``, ``5e-324``, ``616.104``,
    ``nan``, ``inf`` (never ``np.float64(...)``); at most 6 significant digits unless the short
    form of the float is exact."""
    try:
        v = float(x)
    except (TypeError, ValueError):
        return repr(x)
    if math.isnan(v):
        return "nan"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    if v == int(v) and abs(v) < 1e15:
        return str(int(v))
    r = repr(v)
    if len(r) <= 10:
        return r
    return f"{v:.6g}"


def describe(value: Any, unit: str = "") -> str:
    """``value`` (with ``unit``) for a message: a plain number, or for an array
    ``min to max unit (n values)`` (a non-finite entry named with its position)."""
    u = f" {unit}" if unit else ""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        return repr(value)
    if arr.ndim == 0 or arr.size == 1:
        return fmt_number(arr.ravel()[0]) + u
    if arr.size == 0:
        return "[] (no values)"
    flat = arr.ravel()
    bad = ~np.isfinite(flat)
    if bad.any():
        i = int(np.argmax(bad))
        return f"{fmt_number(flat[i])}{u} (element {i} of {flat.size} values)"
    lo, hi = float(flat.min()), float(flat.max())
    if lo == hi:
        return f"{fmt_number(lo)}{u} ({flat.size} values)"
    return f"{fmt_number(lo)} to {fmt_number(hi)}{u} ({flat.size} values)"


# kept for callers of the old private name
_describe = describe


def _interval(low, high, low_inclusive, high_inclusive, unit) -> str:
    lb = "[" if low_inclusive else "("
    hb = "]" if high_inclusive else ")"
    u = f" {unit}" if unit else ""
    return f"{lb}{fmt_number(low)}, {fmt_number(high)}{hb}{u}"


def _as_float_array(name: str, value: Any) -> np.ndarray:
    # a boolean is never a number here: True would be read as 1 (a 1 m flight section from ``true`` in a TOML file)
    if isinstance(value, (str, bytes, bool, np.bool_)) or getattr(getattr(value, "dtype", None), "kind", "") == "b":
        raise ValueError(f"{name} must be a real number, got {value!r}")
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise ValueError(f"{name} must be a real number, got {value!r}") from None


def check_finite(name: str, value: Any, unit: str = "") -> np.ndarray:
    """Return ``value`` as a float array; raise if any element is NaN or infinite."""
    arr = _as_float_array(name, value)
    if not np.all(np.isfinite(arr)):
        what = "not a number" if np.any(np.isnan(arr)) else "not finite"
        raise ValueError(f"{name} = {describe(arr, unit)} is {what}: it must be a finite number")
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
    """Check that every element of ``value`` is finite and lies in the interval (low, high).

    Bounds are open unless ``low_inclusive``/``high_inclusive`` are set. Returns the value as
    a float array (0-d for scalars). Messages name ``name``, the value (plain numbers; min and
    max for arrays), the allowed range and ``unit``.
    """
    if type(value) is float or type(value) is int:      # the common case: one plain number, no array reductions
        v = float(value)
        if math.isfinite(v) and (v >= low if low_inclusive else v > low) and (v <= high if high_inclusive else v < high):
            return np.asarray(v)
    arr = _as_float_array(name, value)
    lo_ok = arr >= low if low_inclusive else arr > low
    hi_ok = arr <= high if high_inclusive else arr < high
    if (np.isfinite(arr) & lo_ok & hi_ok).all():       # one reduction when every value is valid
        return arr
    if not np.all(np.isfinite(arr)):
        what = "not a number" if np.any(np.isnan(arr)) else "not finite"
        raise ValueError(f"{name} = {describe(arr, unit)} is {what} (allowed range "
                         f"{_interval(low, high, low_inclusive, high_inclusive, unit)})")
    if not (np.all(lo_ok) and np.all(hi_ok)):
        raise ValueError(
            f"{name} = {describe(arr, unit)} is outside the allowed range "
            f"{_interval(low, high, low_inclusive, high_inclusive, unit)}"
        )
    return arr


def check_positive(name: str, value: Any, unit: str = "") -> np.ndarray:
    """Check that every element of ``value`` is finite and > 0."""
    return check_range(name, value, 0.0, math.inf, unit=unit)


def finite_number(value: Any, what: str, hint: str = "") -> float:
    """``value`` (a number or its text) as a finite float; else a ``ValueError`` ``"{what} {value!r} is not a
    (finite) number{hint}"`` (``what`` names where it was given, e.g. ``"--recycle:"``; ``hint``: the form
    expected). The one parser of a number typed in a list or a file (what-if values, targets, schedules).

    >>> finite_number("0.2", "--recycle:")
    0.2
    >>> finite_number("inf", "--recycle:")
    Traceback (most recent call last):
    ...
    ValueError: --recycle: 'inf' is not a finite number
    """
    if isinstance(value, (bool, np.bool_)):       # true in a TOML file: not 1.0
        raise ValueError(f"{what} {value!r} is not a number{hint}")
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{what} {value!r} is not a number{hint}") from None
    if not math.isfinite(v):
        raise ValueError(f"{what} {value!r} is not a finite number{hint}")
    return v


def check_choice(name: str, value: str, choices) -> str:
    """Check that ``value`` is one of ``choices`` (strings)."""
    choices = tuple(choices)
    if value not in choices:
        raise ValueError(f"{name} = {value!r} is not one of {', '.join(map(repr, choices))}")
    return value

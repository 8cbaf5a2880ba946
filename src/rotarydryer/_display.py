"""Short text and HTML views of results objects (notebooks, the REPL).

Every results object has a one-line ``__repr__`` naming what it is and its key numbers, and a
``_repr_html_`` table for Jupyter; ``to_dataframe()`` gives the named outputs as a pandas table
(pandas comes with xarray).
"""

from __future__ import annotations

import html
import math

__all__ = ["fmt", "fmt_error", "fmt_angle", "fmt_moisture", "short_repr", "html_table", "outputs_dataframe"]


def _finite(v) -> tuple[float | None, str]:
    """``(float(v), "")`` for a finite number, else ``(None, the text shown)``: ``str(v)`` for what
    is not a number, ``'inf'`` / ``'nan'`` for those."""
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None, str(v)
    return (x, "") if math.isfinite(x) else (None, str(x))


def fmt(v, digits: int = 4) -> str:
    """A number as people write it (``digits`` significant digits, 4 by default; thousands
    separated from 1 000 to 1e6, exponent outside 1e-3 to 1e6), else str. The one number
    format of the text surfaces (CLI tables, the report, reprs)."""
    if isinstance(v, bool) or v is None:
        return str(v)
    x, text = _finite(v)
    if x is None:
        return text
    if x != 0 and (abs(x) >= 1e6 or abs(x) < 1e-3):
        return f"{x:.{digits}g}"
    if abs(x) >= 1000:
        return f"{x:,.0f}"
    return f"{x:.{digits}g}"


def fmt_error(v, floor: float = 1e-9) -> str:
    """A relative balance error: ``< 1e-9`` below ``floor`` (round-off, the balance closes),
    else two significant digits (``6.9e-06``, ``0.012``)."""
    x, text = _finite(v)
    if x is None:
        return text
    if abs(x) < floor:
        return f"< {floor:.0e}".replace("e-0", "e-")
    return f"{x:.2g}"


def fmt_angle(v) -> str:
    """An angle in degrees to 0.1 deg (``44.2``)."""
    x, text = _finite(v)
    return text if x is None else f"{x:.1f}"


def fmt_moisture(v, digits: int = 4) -> str:
    """A moisture content given in kg/kg as a percentage (the display unit of moisture on the
    text surfaces, % wet basis for a wet-basis value): ``digits`` significant digits, ``< 0.001``
    below 1e-5 kg/kg."""
    x, text = _finite(v)
    if x is None:
        return text
    x *= 100.0
    if abs(x) < 1e-3:
        return "< 0.001" if x > 0 else "0"
    return f"{x:.{digits}g}"


def short_repr(kind: str, title: str, pairs) -> str:
    """``<kind title: name value, ...>`` (at most ~200 characters)."""
    body = ", ".join(f"{k} {fmt(v)}" for k, v in pairs)
    text = f"<{kind}{' ' + title if title else ''}: {body}>"
    return text if len(text) <= 240 else text[:236] + "...>"


def _split_unit(name: str):
    for suffix, unit in (("_kg_kg", "kg/kg"), ("_kg_s", "kg/s"), ("_degC", "degC"), ("_kg", "kg"),
                         ("_s", "s"), ("_W", "W"), ("_m", "m")):
        if name.endswith(suffix):
            return name[: -len(suffix)].replace("_", " "), unit
    return name.replace("_", " "), ""


def html_table(outputs: dict, caption: str = "", limit: int = 40) -> str:
    """An HTML table (quantity, value, unit) of named outputs; non-numbers are skipped."""
    rows = []
    for k, v in outputs.items():
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            name, unit = _split_unit(k)
            rows.append(f"<tr><td>{html.escape(name)}</td><td style='text-align:right'>{html.escape(fmt(v))}</td>"
                        f"<td>{html.escape(unit)}</td></tr>")
        if len(rows) >= limit:
            break
    cap = f"<caption>{html.escape(caption)}</caption>" if caption else ""
    return f"<table>{cap}<tr><th>quantity</th><th>value</th><th>unit</th></tr>{''.join(rows)}</table>"


def outputs_dataframe(outputs: dict):
    """pandas DataFrame (index: output name; columns value, unit) of the numeric outputs."""
    import pandas as pd

    rows = {k: (float(v), _split_unit(k)[1]) for k, v in outputs.items()
            if isinstance(v, (int, float)) and not isinstance(v, bool)}
    return pd.DataFrame.from_dict(rows, orient="index", columns=["value", "unit"])

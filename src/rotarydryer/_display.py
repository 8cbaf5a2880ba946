"""The number and unit conventions of the text surfaces, and short views of results objects.

**Display units, chosen once.** Outputs are SI with a unit suffix in their names everywhere a
program reads them (JSON, CSV, netCDF: ``product_moisture_kg_kg``, ``shell_heat_loss_W``). The
text a person reads (the CLI's tables, the report, the app) shows each *quantity* in one display
unit (`DEFAULT_UNITS`: moisture in %, fuel in kg/h, heat duties in kW, times in min...), which a
user may change once for every surface:

* ``ROTARYDRYER_UNITS="moisture=kg/kg,power=MW"`` in the environment, or
* a ``[display]`` table in ``$ROTARYDRYER_CONFIG`` (default ``~/.config/rotarydryer/config.toml``)::

      [display]
      mass_flow = "t/h"
      temperature = "degF"

* or ``rotarydryer --units moisture=kg/kg COMMAND ...`` for one command.

The environment wins over the file, the option over both. `UNITS` lists what each quantity may
be shown in; an unknown quantity or unit is refused with the allowed ones
([`display_units`][rotarydryer._display.display_units]).

**Views.** Every results object has a one-line ``__repr__`` naming what it is and its key numbers,
and a ``_repr_html_`` table for Jupyter; ``to_dataframe()`` gives the named outputs as a pandas
table (pandas comes with xarray).
"""

from __future__ import annotations

import html
import math
import os
import tomllib
from pathlib import Path

__all__ = ["fmt", "fmt_error", "fmt_angle", "fmt_moisture", "short_repr", "html_table", "outputs_dataframe",
           "UNITS", "DEFAULT_UNITS", "display_units", "set_display_units", "parse_units", "unit_of", "to_display",
           "show", "quantity_of", "show_output", "UNIT_QUANTITIES"]

#: display units of each quantity: unit -> (scale, offset) from the SI value (shown = SI x scale + offset);
#: moisture and humidity are kg/kg (wet or dry basis as the quantity says), temperatures degC, energies J
UNITS: dict[str, dict[str, tuple[float, float]]] = {
    "moisture": {"%": (100.0, 0.0), "kg/kg": (1.0, 0.0)},
    "humidity": {"kg/kg": (1.0, 0.0), "g/kg": (1000.0, 0.0)},
    "temperature": {"degC": (1.0, 0.0), "K": (1.0, 273.15), "degF": (1.8, 32.0)},
    "temperature_difference": {"K": (1.0, 0.0), "degF": (1.8, 0.0)},
    "mass_flow": {"kg/s": (1.0, 0.0), "kg/h": (3600.0, 0.0), "t/h": (3.6, 0.0)},
    "fuel_flow": {"kg/h": (3600.0, 0.0), "kg/s": (1.0, 0.0), "t/h": (3.6, 0.0)},
    "power": {"kW": (1e-3, 0.0), "MW": (1e-6, 0.0), "W": (1.0, 0.0)},
    "mass": {"kg": (1.0, 0.0), "t": (1e-3, 0.0)},
    "time": {"min": (1.0 / 60.0, 0.0), "s": (1.0, 0.0), "h": (1.0 / 3600.0, 0.0)},
    "length": {"m": (1.0, 0.0), "mm": (1000.0, 0.0)},
    "particle_size": {"um": (1e6, 0.0), "mm": (1e3, 0.0), "m": (1.0, 0.0)},
    "specific_energy": {"kJ/kg": (1e-3, 0.0), "MJ/kg": (1e-6, 0.0)},
}

#: the display unit of each quantity unless the user chose another (module docstring)
DEFAULT_UNITS: dict[str, str] = {
    "moisture": "%", "humidity": "kg/kg", "temperature": "degC", "temperature_difference": "K",
    "mass_flow": "kg/s", "fuel_flow": "kg/h", "power": "kW", "mass": "kg", "time": "min", "length": "m",
    "specific_energy": "kJ/kg", "particle_size": "um",
}

#: the choice of this process (``--units``), over the environment and the file; None: not set
_CHOSEN: dict = {"units": None}


def _finite(v) -> tuple[float | None, str]:
    """``(float(v), "")`` for a finite number, else ``(None, the text shown)``: ``'n/a'`` for None (an
    undefined output), ``str(v)`` for what else is not a number, ``'inf'`` / ``'nan'`` for those."""
    if v is None:
        return None, "n/a"
    try:
        x = float(v)
    except (TypeError, ValueError):
        return None, str(v)
    return (x, "") if math.isfinite(x) else (None, str(x))


def fmt(v, digits: int = 4) -> str:
    """A number as people write it (``digits`` significant digits, 4 by default; thousands
    separated from 1 000 to 1e6, exponent outside 1e-3 to 1e6), else str. The one number
    format of the text surfaces (CLI tables, the report, reprs); None (an undefined value) is ``n/a``."""
    if isinstance(v, bool):
        return str(v)
    if v is None:
        return "n/a"
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


#: the unit suffixes of output names and their units (the text forms of every summary; `split_unit`)
UNIT_SUFFIXES = {
    "_kJ_kg_water": "kJ/kg water",
    "_Pa": "Pa",
    "_K": "K",
    "_kg_m3": "kg/m3",
    "_degC": "degC",
    "_W": "W",
    "_kg_kg": "kg/kg",
    "_kg_s": "kg/s",
    "_m2": "m2",
    "_deg": "deg",
    "_min": "min",
    "_kg": "kg",
    "_s": "s",
    "_m": "m",
}


def split_unit(name: str) -> tuple[str, str]:
    """``"repose_angle_deg"`` -> ``("repose_angle", "deg")``; no known suffix -> ``(name, "-")``."""
    for suf in sorted(UNIT_SUFFIXES, key=len, reverse=True):
        if name.endswith(suf) and len(name) > len(suf):
            return name[: -len(suf)], UNIT_SUFFIXES[suf]
    return name, "-"


def _split_unit(name: str):
    """(name with spaces, unit or "") of an output name, for tables (`split_unit`)."""
    base, unit = split_unit(name)
    return base.replace("_", " "), "" if unit == "-" else unit


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


# ---------------------------------------------------------------------------- display units
def parse_units(spec, source: str = "--units") -> dict[str, str]:
    """``{quantity: unit}`` of ``"moisture=kg/kg,power=MW"`` (or a mapping), checked against `UNITS`:
    an unknown quantity or unit raises ``ValueError`` naming ``source``, the value and the allowed ones."""
    if isinstance(spec, dict):
        pairs = [(str(k), str(v)) for k, v in spec.items()]
    else:
        pairs = []
        for item in str(spec).split(","):
            if not item.strip():
                continue
            if "=" not in item:
                raise ValueError(f"{source}: {item.strip()!r} is not QUANTITY=UNIT (e.g. moisture=kg/kg); "
                                 f"quantities: {', '.join(UNITS)}")
            k, v = item.split("=", 1)
            pairs.append((k.strip(), v.strip()))
    out = {}
    for k, v in pairs:
        if k not in UNITS:
            raise ValueError(f"{source}: unknown quantity {k!r}; allowed: {', '.join(UNITS)}")
        if v not in UNITS[k]:
            raise ValueError(f"{source}: {k} = {v!r} is not a display unit of {k}; allowed: {', '.join(UNITS[k])}")
        out[k] = v
    return out


def _config_path() -> Path:
    p = os.environ.get("ROTARYDRYER_CONFIG")
    if p:
        return Path(p)
    base = os.environ.get("XDG_CONFIG_HOME") or os.path.join(os.path.expanduser("~"), ".config")
    return Path(base) / "rotarydryer" / "config.toml"


def _file_units() -> dict[str, str]:
    path = _config_path()
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        return {}
    except OSError as exc:
        raise ValueError(f"{path}: {exc.strerror or exc}") from exc
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML ({exc})") from exc
    table = data.get("display", {})
    if not isinstance(table, dict):
        raise ValueError(f"{path}: [display] must be a table of QUANTITY = \"UNIT\"")
    return parse_units(table, f"{path} [display]")


def display_units() -> dict[str, str]:
    """The display unit of every quantity: `DEFAULT_UNITS`, then the config file's ``[display]``,
    then ``ROTARYDRYER_UNITS``, then this process's `set_display_units` (module docstring).
    A bad entry raises ``ValueError`` naming where it came from."""
    units = dict(DEFAULT_UNITS)
    units.update(_file_units())
    env = os.environ.get("ROTARYDRYER_UNITS")
    if env:
        units.update(parse_units(env, "ROTARYDRYER_UNITS"))
    if _CHOSEN["units"]:
        units.update(_CHOSEN["units"])
    return units


def set_display_units(spec) -> None:
    """Choose display units for this process (``rotarydryer --units``), over the environment and the
    config file; ``None`` forgets the choice. A bad choice raises ``ValueError`` and changes nothing."""
    _CHOSEN["units"] = None if spec is None else parse_units(spec)


def unit_of(quantity: str) -> str:
    """The display unit of ``quantity`` (a key of `UNITS`)."""
    return display_units()[quantity]


def to_display(value, quantity: str, unit: str | None = None) -> float:
    """An SI value (kg/kg, degC, kg/s, W, kg, s, m, J/kg) of ``quantity`` in its display unit (or ``unit``)."""
    scale, offset = UNITS[quantity][unit or unit_of(quantity)]
    return float(value) * scale + offset


def show(value, quantity: str, digits: int = 4, *, unit: str | None = None, with_unit: bool = True) -> str:
    """An SI value of ``quantity`` as text in its display unit, engineering rounding (`fmt`):
    ``"12.6 %"``, ``"1,234 kg/h"``; non-numbers as `fmt` shows them."""
    u = unit or unit_of(quantity)
    x, text = _finite(value)
    if x is None:
        return text
    if quantity == "moisture" and u == "%":
        number = fmt_moisture(x, digits)
    elif quantity in ("temperature", "temperature_difference"):
        number = f"{to_display(x, quantity, u):.1f}"
    else:
        number = fmt(to_display(x, quantity, u), digits)
    return f"{number} {u}" if with_unit else number


#: a written unit -> (its display quantity, factor to the quantity's SI unit of `UNITS`): the units case keys,
#: validation items and screening constraints are given in (one table for every surface that converts them)
UNIT_QUANTITIES: dict[str, tuple[str, float]] = {
    "s": ("time", 1.0), "min": ("time", 60.0), "h": ("time", 3600.0), "kg": ("mass", 1.0), "t": ("mass", 1e3),
    "kg/s": ("mass_flow", 1.0), "kg/h": ("mass_flow", 1.0 / 3600.0), "t/h": ("mass_flow", 1.0 / 3.6),
    "degC": ("temperature", 1.0), "K": ("temperature_difference", 1.0), "W": ("power", 1.0), "kW": ("power", 1e3),
    "m": ("length", 1.0)}


#: output-name suffixes (longest first): (suffix, quantity, factor to the SI unit of `UNITS`)
_SUFFIXES = (("_kJ_kg_water", "specific_energy", 1e3), ("_kg_kg", None, 1.0), ("_kg_s", "mass_flow", 1.0),
             ("_kg_h", "mass_flow", 1.0 / 3600.0), ("_degC", "temperature", 1.0), ("_kW", "power", 1e3),
             ("_W", "power", 1.0), ("_kg", "mass", 1.0), ("_K", "temperature_difference", 1.0),
             ("_s", "time", 1.0), ("_m", "length", 1.0))


def quantity_of(name: str) -> tuple[str, float] | None:
    """``(quantity, factor to SI)`` of an output name by its unit suffix (``fuel_rate_kg_s`` ->
    ``("fuel_flow", 1.0)``), or None for a dimensionless or unknown one."""
    for suffix, quantity, factor in _SUFFIXES:
        if name.endswith(suffix):
            if suffix == "_kg_kg":
                quantity = "humidity" if "humidity" in name else "moisture"
            elif quantity == "mass_flow" and "fuel" in name:
                quantity = "fuel_flow"
            elif quantity == "length" and ("d50" in name or "diameter" in name):
                quantity = "particle_size"
            return (quantity, factor) if quantity is not None else None
    return None


def show_output(name: str, value, digits: int = 4) -> str:
    """An output ``value`` named with its unit suffix, shown in its quantity's display unit
    (`quantity_of`); a dimensionless one by `fmt`."""
    q = quantity_of(name)
    if q is None:
        return fmt(value, digits)
    x, text = _finite(value)
    return text if x is None else show(x * q[1], q[0], digits)


def show_delta(value, quantity: str, digits: int = 3, *, with_unit: bool = True) -> str:
    """A difference of an SI ``quantity`` in its display unit: moisture in percentage points (``pp``)
    where moisture is shown in %, 0 below 0.001 pp as `fmt_moisture`; a temperature difference in K
    or degF; other quantities as `show` without their offset (none has one)."""
    x, text = _finite(value)
    if x is None:
        return text
    if quantity == "temperature":       # degF where either the temperatures or the differences are shown in it
        quantity = "temperature_difference"
        unit = "degF" if "degF" in (unit_of("temperature"), unit_of("temperature_difference")) else "K"
    else:
        unit = unit_of(quantity)
    scale = UNITS[quantity][unit][0]
    label = "pp" if (quantity, unit) == ("moisture", "%") else unit
    # a moisture change below the resolution of a moisture shown in % (`fmt_moisture`: 0.001 %) is
    # none at all there ("-1.25e-07 pp" was solver noise read as a change)
    if label == "pp" and abs(x * scale) < 1e-3:
        x = 0.0
    number = fmt(x * scale, digits)
    return f"{number} {label}" if with_unit else number


def output_cells(name: str, value, digits: int = 4) -> tuple[str, str]:
    """``(number, unit)`` of `show_output` for a table's value and unit columns."""
    text = show_output(name, value, digits)
    q = quantity_of(name)
    if q is None or _finite(value)[0] is None:
        return text, ""
    number, _, unit = text.rpartition(" ")      # the unit is one word; a number may be "< 0.001"
    return number, unit

"""Keys of the thesis case formats (``kind = "lee2008"``, ``"ajayi2011"``) given as overrides of a ``kind = "dryer"``
case (``--set solids.moisture_inlet=0.2``): `LEGACY_KEYS` maps each to its replacement, converting the value where
the unit or form changed, with a ``FutureWarning``. Kept apart from the formats' schemas
(`rotarydryer.cases.readers`), which load only when a file of a thesis format is read: every case load with
overrides needs this table, and the schemas' pydantic classes cost a one-off command about 10 ms."""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from typing import Any

__all__ = ["LEGACY_KEYS", "translate_legacy_overrides"]


def _wet(w: float) -> float:
    """Wet-basis moisture (kg/kg wet) of a dry-basis one (kg/kg dry)."""
    return w / (1.0 + w)


def _float(value):
    """``value`` as a float, or None when it is not a number (the new key's validation then names it)."""
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


def _dry_to_wet(value):
    """A dry-basis moisture (kg/kg dry) on the wet basis, w / (1 + w)."""
    w = _float(value)
    return value if w is None or not (math.isfinite(w) and w > -1.0) else _wet(w)


def _bulk_law(value):
    """A constant bulk density as the material's law kg/m^3 = a + b x."""
    v = _float(value)
    return value if v is None else {"a": v, "b": 0.0}


def _constant_law(value):
    """A constant repose angle as the material's law deg = a x + b."""
    v = _float(value)
    return value if v is None else {"b": v, "a": 0.0}


#: old key -> (new key, conversion of the value or None, what the conversion does)
LEGACY_KEYS: dict[str, tuple[str, Callable | None, str]] = {
    "operating.gas_flow": ("gas.direction", None, ""),
    "solids.moisture_inlet": ("operating.feed_moisture", _dry_to_wet,
                              " (kg/kg wet = w / (1 + w) of the dry-basis value)"),
    "solids.moisture_outlet": ("transport.product_moisture", _dry_to_wet,
                               " (kg/kg wet = w / (1 + w) of the dry-basis value)"),
    "solids.bulk_density": ("material.bulk_density", _bulk_law, " (a constant law: {a = value, b = 0})"),
    "solids.repose_angle": ("material.repose_angle", _constant_law, " (a constant law: {a = 0, b = value})"),
    "gas.feed_temperature": ("operating.feed_temperature", None, ""),
    # the ajayi2011 format's [thermal] block and transport names
    "thermal.gas_flow": ("gas.flow", None, ""),
    "thermal.gas_inlet_temperature": ("gas.inlet_temperature", None, ""),
    "thermal.gas_inlet_humidity": ("gas.inlet_humidity", None, ""),
    "thermal.leak_air_flow": ("gas.leak_air_flow", None, ""),
    "thermal.solids_inlet_temperature": ("operating.feed_temperature", None, ""),
    "thermal.ambient_temperature": ("shell.ambient_temperature", None, ""),
    "thermal.scale_thickness": ("shell.scale_thickness", None, ""),
    "thermal.insulation_thickness": ("shell.insulation_thickness", None, ""),
    "thermal.loss_factor": ("shell.loss_factor", None, ""),
    "thermal.shell_inner_radius": ("shell.inner_radius", None, ""),
    "thermal.shell_thickness": ("shell.thickness", None, ""),
    "thermal.fouling": ("transport.fouling", None, ""),
    "thermal.burner.combustion_air_share": ("gas.burner.combustion_air_share", None, ""),
    "thermal.burner.heat_loss_fraction": ("gas.burner.heat_loss_fraction", None, ""),
    "thermal.burner.fuel_water_fraction": ("gas.burner.fuel_water_fraction", None, ""),
    "thermal.burner.fuel_sulphur_fraction": ("gas.burner.fuel_sulphur_fraction", None, ""),
    "thermal.burner.fuel_carbon_hydrogen_ratio": ("gas.burner.fuel_carbon_hydrogen_ratio", None, ""),
    "thermal.burner.fuel_lower_heating_value": ("gas.burner.fuel_lower_heating_value", None, ""),
    "transport.kiln_velocity": ("transport.solids_velocity", None, ""),
    "transport.design_load_factor": ("geometry.design_load_factor", None, ""),
    "solids.moisture_scale": ("transport.moisture_scale", None, ""),
}


def translate_legacy_overrides(overrides: dict | None, valid: set[str] | list[str]) -> dict:
    """``overrides`` with the keys of the old formats that a ``kind = "dryer"`` case does not have
    replaced by their `LEGACY_KEYS` replacements (a ``FutureWarning`` names each)."""
    if not overrides:
        return dict(overrides or {})
    valid = set(valid)
    out: dict[str, Any] = {}
    for key, value in overrides.items():
        if key in LEGACY_KEYS and key not in valid:
            new, convert, how = LEGACY_KEYS[key]
            if new in overrides or any(k.startswith(new + ".") for k in overrides):
                raise ValueError(f"override keys {key!r} and {new!r} set the same quantity: give {new!r} only "
                                 f"({key!r} is its deprecated name)")
            warnings.warn(f"override key {key!r} is deprecated: use {new!r}{how}", FutureWarning, stacklevel=3)
            if isinstance(value, str) and value.strip().lower() in ("none", "null", ""):
                out[new] = value
                continue
            value = convert(value) if convert is not None else value
            if isinstance(value, dict):      # a material law: merged into the material's table
                for k, v in value.items():
                    out[f"{new}.{k}"] = v
                continue
            out[new] = value
        else:
            out[key] = value
    return out

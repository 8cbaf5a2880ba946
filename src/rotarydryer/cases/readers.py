"""Readers of the plant case formats: each translates its file into the one dryer specification.

Below the readers every layer sees one schema, :class:`rotarydryer.cases.DryerSpec`
(``kind = "dryer"``). The older formats of the thesis plants stay readable so that old case
files load:

* ``kind = "lee2008"`` (Lee (2008), one flighted drum: ``[solids]`` bulk density and dry-basis
  moisture, ``[[parameter_sets]]`` of Table 7.2) -> :func:`lee2008_to_spec`;
* ``kind = "ajayi2011"`` (Ajayi (2011), the MMG dryer: ``[[tests]]`` with Table 5.2 fits, the gas
  and shell in ``[thermal]``) -> :func:`ajayi2011_to_spec`.

A reader first validates the file in its own format (messages name the keys of that file),
then returns the ``kind = "dryer"`` document that :class:`~rotarydryer.cases.DryerSpec`
validates. Nothing else in the package knows these formats.

Keys of the old formats that a rewritten shipped case no longer has still work as overrides
(``--set``): :data:`LEGACY_KEYS` maps each to its replacement, with a ``DeprecationWarning``
naming it.
"""

from __future__ import annotations

import math
import warnings
from typing import Any, Callable

from .._validation import check_range

__all__ = ["lee2008_to_spec", "ajayi2011_to_spec", "LEGACY_KEYS", "translate_legacy_overrides", "check_lee2008"]

#: bulk densities a granular solid can have, kg/m^3: above air (1.2) and below osmium (22 590)
BULK_DENSITY_RANGE = (1.0, 23000.0)


def _wet(w: float) -> float:
    """Wet-basis moisture (kg/kg wet) of a dry-basis one (kg/kg dry)."""
    return w / (1.0 + w)


def _same_law(mat, key: str, a: float, b: float) -> bool:
    law = getattr(mat, f"{key}_law")
    return float(law[0]) == float(a) and float(law[1]) == float(b)


def check_lee2008(case) -> None:
    """Checks of a ``kind = "lee2008"`` file in its own keys: ``solids.bulk_density`` in
    :data:`BULK_DENSITY_RANGE`, ``solids.repose_angle`` in (0, 90) deg, and the dry-basis moistures
    ``solids.moisture_inlet`` / ``moisture_outlet`` inside the material's range."""
    from .build import material_of

    lo, hi = BULK_DENSITY_RANGE
    check_range("solids.bulk_density", case.solids.bulk_density, lo, hi, low_inclusive=True, high_inclusive=True,
                unit="kg/m^3")
    if case.solids.repose_angle is not None:
        check_range("solids.repose_angle", case.solids.repose_angle, 0.0, 90.0, unit="deg")
    if case.material is not None:
        mat = material_of(case)
        for key in ("moisture_inlet", "moisture_outlet"):
            mat.check_moisture(f"solids.{key}", getattr(case.solids, key), basis="dry")


def lee2008_to_spec(case) -> dict:
    """The ``kind = "dryer"`` document of a validated ``kind = "lee2008"`` case.

    Lee's drum is one flighted section ``"dryer"`` of ``drum.length``; ``solids.moisture_inlet`` /
    ``moisture_outlet`` (kg/kg dry) become ``operating.feed_moisture`` / ``transport.product_moisture``
    (kg/kg wet) with Lee's Eq. 7.3 profile (``transport.moisture_profile = "lee2008_eq7.3"``);
    ``solids.bulk_density`` and ``solids.repose_angle`` become the material's laws (constants) where
    they differ from the library material (``raw_sugar_lee2008`` when the file names none: Lee's
    Eq. 7.2 is that sugar's); ``operating.gas_flow`` is ``gas.direction``; ``gas.feed_temperature``
    is ``operating.feed_temperature``. Heat and mass transfer is on when the file enables it and
    gives [gas] and [material], as before."""
    from .build import material_of

    check_lee2008(case)
    d, fl, op, so, tr, ge = case.drum, case.flight, case.operating, case.solids, case.transport, case.geometry
    material = case.material.model_dump() if case.material is not None else {"name": "raw_sugar_lee2008"}
    lib = material_of(case) if case.material is not None else None
    if lib is None:
        from rotarydryer.properties.materials import load_material

        lib = load_material("raw_sugar_lee2008")
    if not _same_law(lib, "bulk_density", so.bulk_density, 0.0):
        material["bulk_density"] = {"a": float(so.bulk_density), "b": 0.0, "source": "solids.bulk_density"}
    if so.repose_angle is not None:
        material["repose_angle"] = {"a": 0.0, "b": float(so.repose_angle), "source": "solids.repose_angle"}
    gas: dict[str, Any] = {"direction": op.gas_flow}
    feed_temperature = 20.0
    if case.gas is not None:
        given = case.gas.model_dump(exclude_none=True)
        feed_temperature = given.pop("feed_temperature", feed_temperature)
        if "direction" in case.gas.model_fields_set and case.gas.direction != op.gas_flow:
            raise ValueError(f"gas.direction = {case.gas.direction!r} disagrees with operating.gas_flow = "
                             f"{op.gas_flow!r}: one gas direction (give one of them, or both the same)")
        given["direction"] = op.gas_flow
        gas = given
    transport = tr.model_dump(exclude_none=True)
    transport["product_moisture"] = _wet(so.moisture_outlet)
    transport["moisture_profile"] = "lee2008_eq7.3"
    thermal = case.thermal.model_dump()
    thermal["enabled"] = bool(case.thermal.enabled and case.gas is not None and case.material is not None)
    spec = {
        "kind": "dryer",
        "meta": case.meta.model_dump(),
        "drum": {"radius": d.radius, "slope": d.slope, "length": d.length, "n_flights": d.n_flights},
        "flight": fl.model_dump(),
        "operating": {"feed_rate": op.feed_rate, "rpm": op.rpm, "feed_moisture": _wet(so.moisture_inlet),
                      "feed_temperature": feed_temperature},
        "material": material,
        "transport": transport,
        "geometry": ge.model_dump(exclude_none=True),
        "sections": [{"name": "dryer", "kind": "flighted", "length": d.length}],
        "gas": gas,
        "shell": case.shell.model_dump(),
        "thermal": thermal,
        "tracer": case.tracer.model_dump(),
        "parameter_sets": [p.model_dump() for p in case.parameter_sets],
    }
    return spec


#: fouling of a test marked "Scaled" in the ajayi2011 format: flight loading capacity -80 % (Ajayi (2011) l.1715)
SCALED_FOULING = 0.8


def _pi_gas_inlet_temperature(test: int):
    """The measured gas inlet temperature (degC) of an MMG test (Ajayi (2011) Tables 3.5-3.11, PI data), or None."""
    from rotarydryer.published import read_published_csv

    for r in read_published_csv("ajayi_pi_operating_conditions.csv"):
        if int(r["test"]) == int(test):
            return float(r["gas_inlet_T_C"])
    return None


def ajayi2011_to_spec(case) -> dict:
    """The ``kind = "dryer"`` document of a validated ``kind = "ajayi2011"`` case (Ajayi (2011), MMG).

    ``[[tests]]`` rows keep their operating points (``moisture_inlet`` / ``moisture_outlet`` ->
    ``feed_moisture`` / ``product_moisture``, ``kiln_velocity`` -> ``solids_velocity``, ``scaled`` ->
    ``fouling = 0.8``) and gain the measured gas inlet temperature of the PI data; ``[thermal]`` keys
    go to [gas], [shell] and [operating] (one key per quantity); the thesis mode's own gas flow
    (Ajayi's code, l.3225) and area scale 1 become ``thermal.mode_values.ajayi2011``; the heat-and-mass
    model's unflighted volumes default to one per 0.3 m (at least 4), as the format did."""
    from rotarydryer.thermal.dryer import AJAYI_GAS_FLOW

    op, tr, th = case.operating, case.transport, case.thermal
    fixed = th.model_fields_set
    # one fouling: the transport's, else the thermal block's, else the tests' (Scaled: 0.8)
    fouling = tr.fouling
    if th.fouling is not None:
        if fouling is not None and fouling != th.fouling:
            raise ValueError(f"thermal.fouling = {th.fouling!r} disagrees with transport.fouling = {tr.fouling!r}: one "
                             "fouling of the flights (give one of them, or both the same)")
        fouling = th.fouling
    tests = []
    for t in case.tests:
        row = {"test": t.test, "feed_rate": t.feed_rate, "rpm": t.rpm, "feed_moisture": t.moisture_inlet,
               "product_moisture": t.moisture_outlet, "solids_velocity": t.kiln_velocity, "dispersion": t.dispersion,
               "fouling": SCALED_FOULING if t.scaled else 0.0, "gas_flow": t.gas_flow,
               "gas_inlet_temperature": _pi_gas_inlet_temperature(t.test), "mrt_model_min": t.mrt_model_min,
               "holdup_model_kg": t.holdup_model_kg, "mrt_measured_min": t.mrt_measured_min, "source": t.source}
        tests.append({k: v for k, v in row.items() if v is not None})
    sections = []
    for s in case.sections:
        sec = s.model_dump(exclude_none=True)
        if s.kind == "flighted" and "regression" in sec and case.geometry.method != "ajayi2011_regressions":
            pass    # kept: the coefficients stay with the section for geometry.method = "ajayi2011_regressions"
        sections.append(sec)
    unflighted = {s.name: th.unflighted_cells.get(s.name, max(4, int(math.ceil(s.length / 0.3))))
                  for s in case.sections if s.kind == "unflighted"}
    gas = {"direction": op.gas_flow, "inlet_humidity": th.gas_inlet_humidity, "leak_air_flow": th.leak_air_flow}
    if "gas_flow" in fixed or not any(t.gas_flow is not None for t in case.tests):
        gas["flow"] = th.gas_flow
    if th.gas_inlet_temperature is not None:
        gas["inlet_temperature"] = th.gas_inlet_temperature
    if th.burner is not None:
        gas["burner"] = th.burner.model_dump(exclude_none=True)
    transport = {"model": "ajayi2011", "loading": "state", "unflighted_inlet": tr.unflighted_inlet,
                 "parameter_source": tr.parameter_source, "velocity_law": tr.velocity_law,
                 "moisture_profile": "ajayi2011_eq3.1", "moisture_scale": case.solids.moisture_scale}
    u = tr.solids_velocity or tr.kiln_velocity
    for key, value in (("solids_velocity", u), ("dispersion", tr.dispersion), ("unflighted_cells", tr.unflighted_cells),
                       ("fouling", fouling), ("velocity_coefficient", tr.velocity_coefficient),
                       ("dispersion_coefficient", tr.dispersion_coefficient)):
        if value is not None:
            transport[key] = value
    geometry = case.geometry.model_dump(exclude_none=True)
    geometry.update(design_load_method="ajayi2011", design_load_factor=tr.design_load_factor)
    return {
        "kind": "dryer",
        "meta": case.meta.model_dump(),
        "drum": case.drum.model_dump(exclude_none=True),
        "operating": {k: v for k, v in {"test": op.test, "feed_rate": op.feed_rate, "rpm": op.rpm,
                                        "feed_temperature": th.solids_inlet_temperature}.items() if v is not None},
        "material": case.material.model_dump(),
        "transport": transport,
        "geometry": geometry,
        "sections": sections,
        "tests": tests,
        "gas": gas,
        "shell": {"ambient_temperature": th.ambient_temperature, "ambient_humidity": 0.0193 / (1.0 - 0.0193),
                  "scale_thickness": th.scale_thickness, "insulation_thickness": th.insulation_thickness,
                  "loss_factor": th.loss_factor, "inner_radius": th.shell_inner_radius,
                  "thickness": th.shell_thickness},
        "thermal": {"enabled": th.enabled, "mode": th.mode, "area_scale": th.area_scale,
                    "moisture_coupling": th.moisture_coupling, "design_load_smoothing": th.design_load_smoothing,
                    "unflighted_cells": unflighted,
                    "mode_values": {"ajayi2011": {"gas.flow": AJAYI_GAS_FLOW, "thermal.area_scale": 1.0}}},
        "tracer": case.tracer.model_dump(),
    }


#: readers by the ``kind`` of the file: (schema of the file, translation into the dryer document)
def readers() -> dict[str, tuple[type, Callable]]:
    from . import AjayiCase, LeeCase

    return {"lee2008": (LeeCase, lee2008_to_spec), "ajayi2011": (AjayiCase, ajayi2011_to_spec)}


# ---- keys of the old formats as overrides of the rewritten shipped cases ------------------------
def _dry_to_wet(key: str) -> Callable[[Any], Any]:
    def convert(value):
        try:
            w = float(value)
        except (TypeError, ValueError):
            return value            # the new key's validation names the value
        if not (math.isfinite(w) and w > -1.0):
            return value
        return _wet(w)
    convert.__doc__ = f"{key} (kg/kg dry) on the wet basis"
    return convert


def _constant_law(value):
    try:
        v = float(value)
    except (TypeError, ValueError):
        return value
    return {"b": v, "a": 0.0}


def _bulk_law(value):
    try:
        v = float(value)
    except (TypeError, ValueError):
        return value
    return {"a": v, "b": 0.0}


#: old key -> (new key, conversion of the value or None, what the conversion does)
LEGACY_KEYS: dict[str, tuple[str, Callable | None, str]] = {
    "operating.gas_flow": ("gas.direction", None, ""),
    "solids.moisture_inlet": ("operating.feed_moisture", _dry_to_wet("solids.moisture_inlet"),
                              " (kg/kg wet = w / (1 + w) of the dry-basis value)"),
    "solids.moisture_outlet": ("transport.product_moisture", _dry_to_wet("solids.moisture_outlet"),
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
    replaced by their :data:`LEGACY_KEYS` replacements (a ``DeprecationWarning`` names each)."""
    if not overrides:
        return dict(overrides or {})
    valid = set(valid)
    out: dict[str, Any] = {}
    for key, value in overrides.items():
        if key in LEGACY_KEYS and key not in valid:
            new, convert, how = LEGACY_KEYS[key]
            warnings.warn(f"override key {key!r} is deprecated: use {new!r}{how}", DeprecationWarning, stacklevel=3)
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


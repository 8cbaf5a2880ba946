"""Materials library: citable solids data (``rotarydryer/data/materials/*.toml``) and a small API.

A [`Material`][rotarydryer.properties.materials.Material] carries the moisture laws of its source (repose angle and bulk density,
linear in moisture on the source's own basis), the range where they hold, thermal data and
the drying kinetics. Moisture given to the methods is always **wet basis** (kg water/kg wet
solid); [`Material.to_basis`][rotarydryer.properties.materials.Material.to_basis] converts it to the basis of the laws. The property methods
are unchecked vectorised kernels; validate once with [`Material.check_moisture`][rotarydryer.properties.materials.Material.check_moisture].

Library (every number is cited in its TOML file; "choice" marks values the sources do not give)
----------------------------------------------------------------------------------------------
``zinc_concentrate_ajayi2011``
:   Wet basis; Ajayi (2011) Eq. 3.2 ``phi = 419.6 x - 7.801`` and Eq. 3.4 as coded
    ``rho_b = 2043.81 - 3095.24 x``; x = 0.08-0.19 (the thermal model's transport range);
    cp 505 J/(kg K), rho_p 2800 kg/m^3 (App. F code); d_p 0.012 m by default, per section
    A-E 0.02, 0.015, 0.012, 0.008, 0.007 m (l.2255, ``particle_diameter_by_section``);
    kinetics ``"ajayi2011"`` (unhindered rate).

``raw_sugar_lee2008``
:   Dry basis (Lee's w); Lee (2008) Eq. 7.2 ``phi = 1222.2 w + 34.5``, rho_b 940 kg/m^3
    (code); w = 0-0.04 (choice, covers Lee's profile 0.002-0.02); d_p 850 um (l.9280);
    cp 1250 J/(kg K) and rho_p 1588 kg/m^3 (sucrose; choices); constant + falling rate
    with X_cr = 0.01, X_e = 0.0005 kg/kg dry (choices).

``ottawa_sand_song2003``
:   Wet basis; d_p 444 um and bulk density 1650 kg/m^3 (Song (2003) L1283); repose angle
    33 deg constant (choice, dry river sand of Lee (2008) Table 5.2); rho_p 2650 kg/m^3,
    cp 830 J/(kg K), x = 0-0.2, X_cr = 0.005, X_e = 0 (choices).

>>> m = load_material("raw_sugar_lee2008")
>>> round(float(m.repose_angle(0.02 / 1.02)), 3)     # w = 0.02 kg/kg dry, Lee Eq. 7.2
58.944
"""

from __future__ import annotations

import copy
import math
import os
import tomllib
from dataclasses import dataclass
from functools import cache
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from .._limits import LIMITS, check_key, describe_limit
from .drying import DryingKinetics

__all__ = ["Material", "load_material", "list_materials", "library_table"]

_LIBRARY = resources.files("rotarydryer.data") / "materials"
_TABLES = ("repose_angle", "bulk_density", "kinetics", "particle_diameter_by_section", "transport")
_FIELDS = ("name", "title", "citations", "moisture_basis", "moisture_range", "repose_angle", "bulk_density",
           "heat_capacity", "water_heat_capacity", "particle_density", "particle_diameter",
           "particle_diameter_by_section", "kinetics", "transport", "max_temperature", "max_temperature_source")
_OPTIONAL = ("water_heat_capacity", "particle_diameter_by_section", "transport", "max_temperature",
             "max_temperature_source")
#: coefficients of the predictive transport law a material may carry (its class's calibration;
#: the case's transport.<key> wins): key -> the range of that case key (rotarydryer._limits.LIMITS),
#: one declaration for the material's default and the case's value
TRANSPORT_COEFFICIENTS = {k: LIMITS[f"transport.{k}"] for k in ("step_factor", "curtain_coefficient",
                                                                 "velocity_coefficient", "dispersion_coefficient")}
#: the operating range of the data those coefficients were calibrated on: key -> (quantity, unit)
CALIBRATED_RANGES = {"calibrated_rpm": ("drum speed", "rev/min"), "calibrated_froude": ("Froude number omega^2 R/g", "-"),
                     "calibrated_fill": ("solids fill of the drum volume", "-"),
                     "calibrated_moisture": ("feed moisture", "kg/kg wet")}
_KINETICS = {"method", "critical_moisture", "equilibrium_moisture", "exponent", "curve", "basis",
             "saturation_method", "source", "model", "parameters", "activation_energy", "reference_temperature_K",
             "initial_moisture"}
_TOL = 1e-12  # kg/kg: a range end recomputed from the other basis still counts as inside


@dataclass(frozen=True)
class Material:
    """A solid material: moisture laws, the range where they hold, thermal data and kinetics.

    ``repose_angle_law`` (a, b): deg = a x + b; ``bulk_density_law`` (a, b): kg/m^3 = a + b x;
    x in ``moisture_basis`` ("wet" or "dry", kg/kg) inside ``moisture_range``. Heat capacities
    J/(kg K) (dry solids, liquid water); ``particle_density`` kg/m^3; ``particle_diameter`` m
    (``particle_diameter_by_section``: informational per-section values, (section, m) pairs).
    """

    name: str
    title: str
    citations: tuple[str, ...]
    moisture_basis: str
    moisture_range: tuple[float, float]
    repose_angle_law: tuple[float, float]
    bulk_density_law: tuple[float, float]
    heat_capacity: float
    particle_density: float
    particle_diameter: float
    kinetics: DryingKinetics
    water_heat_capacity: float = 4182.0
    repose_angle_source: str = ""
    bulk_density_source: str = ""
    particle_diameter_by_section: tuple[tuple[str, float], ...] = ()
    #: coefficients of the predictive transport law calibrated for this material class, (key, value)
    #: pairs of :data:`TRANSPORT_COEFFICIENTS`; the case's ``transport.<key>`` wins
    transport_coefficients: tuple[tuple[str, float], ...] = ()
    transport_source: str = ""
    #: (key of :data:`CALIBRATED_RANGES`, (low, high)) pairs: where the coefficients were calibrated
    transport_ranges: tuple[tuple[str, tuple[float, float]], ...] = ()
    #: degC: the solids' temperature above which the material's data no longer hold (it melts, decomposes or
    #: reacts); None: not given. A steady state whose solids exceed it warns (`SolidsTemperatureWarning`)
    max_temperature: float | None = None
    max_temperature_source: str = ""

    def transport_coefficient(self, key: str):
        """The material class's value of predictive-transport coefficient ``key``, or None."""
        return dict(self.transport_coefficients).get(key)

    def to_basis(self, x_wet):
        """Wet-basis moisture (kg/kg) on the basis of the laws (X = x/(1 - x) for "dry"); unchecked."""
        x = np.asarray(x_wet, dtype=float)
        return x if self.moisture_basis == "wet" else x / (1.0 - x)

    def repose_angle(self, x_wet):
        """Dynamic angle of repose, deg, at wet-basis moisture; unchecked kernel (no warnings)."""
        a, b = self.repose_angle_law
        return a * self.to_basis(x_wet) + b

    def bulk_density(self, x_wet):
        """Bulk density, kg/m^3, at wet-basis moisture; unchecked kernel."""
        a, b = self.bulk_density_law
        return a + b * self.to_basis(x_wet)

    def wet_range(self) -> tuple[float, float]:
        """``moisture_range`` on the wet basis, kg/kg wet."""
        lo, hi = self.moisture_range
        return (lo, hi) if self.moisture_basis == "wet" else (lo / (1.0 + lo), hi / (1.0 + hi))

    def check_moisture(self, key: str, x_wet, basis: str = "wet") -> None:
        """Raise ``ValueError`` (one line naming ``key``, the worst value and the range) if any
        moisture lies outside the material's range; ``basis`` ("wet" or "dry") is the basis of the
        values given and of the message."""
        if basis not in ("wet", "dry"):
            raise ValueError(f"basis = {basis!r} is not one of 'wet', 'dry'")
        lo, hi = self.wet_range()
        if basis == "dry":
            lo, hi = lo / (1.0 - lo), hi / (1.0 - hi)
        x = np.ravel(np.asarray(x_wet, dtype=float))
        off = np.where(np.isnan(x), np.inf, np.maximum(lo - x, x - hi))
        if not np.any(off > _TOL):
            return
        value = float(x[int(np.argmax(off))])
        srcs = dict.fromkeys(s for s in (self.repose_angle_source, self.bulk_density_source) if s)
        cite = "; ".join(srcs) or (self.citations[0] if self.citations else "source")
        raise ValueError(f"{key} = {value:g} kg/kg {basis} is outside the moisture range of material '{self.name}' "
                         f"([{lo:g}, {hi:g}] kg/kg {basis}; the repose-angle and bulk-density laws ({cite}) hold "
                         "there only)")


def list_materials() -> list[str]:
    """Names of the library materials (the TOML files in ``rotarydryer/data/materials``)."""
    return list(_library_names())


@cache
def _library_names() -> tuple[str, ...]:
    """`list_materials`, read from the package's data once per process (every material load asks it: a study's run
    listed the directory three times, 0.2 ms)."""
    return tuple(sorted(p.name[:-5] for p in _LIBRARY.iterdir() if p.name.endswith(".toml")))


@cache
def _library_table(name: str) -> dict:
    return tomllib.loads((_LIBRARY / f"{name}.toml").read_text(encoding="utf-8"))


def library_table(name: str) -> dict:
    """The TOML table of library material ``name`` as a dict, a fresh copy to edit freely: a
    starting point for a material of one's own, which [`load_material`][rotarydryer.properties.materials.load_material] takes as a dict.

    Raises ``ValueError`` for a name that is not in the library (see
    [`list_materials`][rotarydryer.properties.materials.list_materials]).

    >>> table = library_table("ottawa_sand_song2003")
    >>> table["name"], load_material(table).name
    ('ottawa_sand_song2003', 'ottawa_sand_song2003')
    """
    names = list_materials()
    if name not in names:
        raise ValueError(f"material = {name!r} is not in the materials library ({', '.join(names)})")
    return copy.deepcopy(_library_table(name))


@cache
def _library_material(name: str) -> Material:
    return _build(_library_table(name))


def load_material(spec) -> Material:
    """Material from a library name, a path to a ``.toml`` file, or a dict (a case-file inline
    table: ``{"name": <library name>, <field>: <override>, ...}`` or a full definition; nested
    tables of an override are merged key by key).

    Raises ``ValueError`` for an unknown name and for a bad or missing field (naming
    ``material.<field>``, the value and the allowed range).
    """
    names = _library_names()
    if isinstance(spec, dict):
        name = spec.get("name")
        if isinstance(name, str) and name in names:
            if set(spec) == {"name"}:
                return _library_material(name)
            merged = _merge(_library_table(name), spec)
            if "max_temperature" in spec and "max_temperature_source" not in spec:
                merged["max_temperature_source"] = "the case's value"      # not the library's source of its own
            return _build(merged)
        return _build(spec)
    if isinstance(spec, str) and spec in names:
        return _library_material(spec)
    if isinstance(spec, (str, os.PathLike)) and os.fspath(spec).endswith(".toml") and os.path.isfile(spec):
        try:
            table = tomllib.loads(Path(spec).read_text(encoding="utf-8-sig"))   # BOM dropped
        except tomllib.TOMLDecodeError as exc:
            raise ValueError(f"material = {os.fspath(spec)!r} is not valid TOML: {exc}") from None
        if set(table) == {"material"} and isinstance(table["material"], dict):
            return load_material(table["material"])     # a case file's [material] block (rotarydryer lab drying)
        return _build(table)
    raise ValueError(f"material = {spec!r} is not in the materials library ({', '.join(names)}) nor a .toml file")


def _merge(base: dict, override: dict) -> dict:
    out = dict(base)
    for key, val in override.items():
        if (key == "kinetics" and isinstance(val, dict) and isinstance(base.get(key), dict)
                and val.get("method", base[key].get("method")) != base[key].get("method")):
            out[key] = {"source": "case-file override", **val}     # another method: its own fields only
        elif key in _TABLES and isinstance(val, dict) and isinstance(base.get(key), dict):
            out[key] = {**base[key], **val}
            if key != "particle_diameter_by_section" and "source" not in val:
                out[key]["source"] = "case-file override"
        else:
            out[key] = val
    return out


def _fail(key: str, value: Any, allowed: str):
    raise ValueError(f"material.{key} = {value!r} is outside the allowed range {allowed}")


def _number(key: str, value: Any, lo: float, hi: float, unit: str, lo_closed: bool = False) -> float:
    """A real number in (lo, hi) ([lo, hi) if ``lo_closed``), else ``ValueError`` naming key, value, range."""
    if (isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value)
            or not ((value >= lo if lo_closed else value > lo) and value < hi)):
        _fail(key, value, f"{'[' if lo_closed else '('}{lo:g}, {hi:g}) {unit}".rstrip())
    return float(value)


def _coefficient(key: str, value: Any) -> float:
    """``material.transport.<key>`` in the range of the case key ``transport.<key>``."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        _fail(f"transport.{key}", value, describe_limit(f"transport.{key}"))
    return float(check_key(f"transport.{key}", value, f"material.transport.{key}"))


def _law(key: str, table: Any) -> tuple[tuple[float, float], str]:
    if isinstance(table, (list, tuple)) and len(table) == 2:
        table = {"a": table[0], "b": table[1]}
    if not isinstance(table, dict):
        raise ValueError(f"material.{key} = {table!r} must be a table {{a = ..., b = ...}}")
    extra = set(table) - {"a", "b", "source"}
    if extra:
        raise ValueError(f"material.{key}.{sorted(extra)[0]} is not a field (allowed: a, b, source)")
    a, b = (_number(f"{key}.{c}", table.get(c), -math.inf, math.inf, "") for c in "ab")
    return (a, b), str(table.get("source", ""))


def _build(d: dict) -> Material:
    unknown = set(d) - set(_FIELDS)
    if unknown:
        raise ValueError(f"material.{sorted(unknown)[0]} is not a material field (allowed: {', '.join(_FIELDS)})")
    missing = [f for f in _FIELDS if f not in d and f not in _OPTIONAL]
    if missing:
        raise ValueError(f"material.{missing[0]} is missing (a {d.get('name', 'new')!r} definition needs: "
                         f"{', '.join(f for f in _FIELDS if f not in _OPTIONAL)})")
    for key, val in (("name", [d["name"]]), ("title", [d["title"]]), ("citations", d["citations"])):
        if not isinstance(val, (list, tuple)) or not val or not all(isinstance(c, str) and c.strip() for c in val):
            raise ValueError(f"material.{key} = {d[key]!r} must be a non-empty "
                             + ("list of strings" if key == "citations" else "string"))
    cites, basis = tuple(d["citations"]), d["moisture_basis"]
    if basis not in ("wet", "dry"):
        raise ValueError(f"material.moisture_basis = {basis!r} is not one of 'wet', 'dry'")
    top = 1.0 if basis == "wet" else 10.0
    rng = d["moisture_range"]
    if not isinstance(rng, (list, tuple)) or len(rng) != 2:
        raise ValueError(f"material.moisture_range = {rng!r} must be [low, high] kg/kg {basis}")
    lo = _number("moisture_range[0]", rng[0], 0.0, top, f"kg/kg {basis}", lo_closed=True)
    hi = _number("moisture_range[1]", rng[1], lo, top, f"kg/kg {basis}")
    repose, repose_src = _law("repose_angle", d["repose_angle"])
    density, density_src = _law("bulk_density", d["bulk_density"])
    for x in (lo, hi):  # linear laws: checking the range ends checks the whole range
        phi, rho = repose[0] * x + repose[1], density[0] + density[1] * x
        if not 0.0 < phi < 90.0:
            raise ValueError(f"material.repose_angle gives {phi:g} deg at {x:g} kg/kg {basis}, outside the "
                             f"allowed range (0, 90) deg over moisture_range [{lo:g}, {hi:g}]")
        if not 0.0 < rho < 25000.0:
            raise ValueError(f"material.bulk_density gives {rho:g} kg/m3 at {x:g} kg/kg {basis}, outside the "
                             f"allowed range (0, 25000) kg/m3 over moisture_range [{lo:g}, {hi:g}]")
    sections = d.get("particle_diameter_by_section", {})
    if not isinstance(sections, dict):
        raise ValueError(f"material.particle_diameter_by_section = {sections!r} must be a table section = m")
    sections = tuple((str(k), _number(f"particle_diameter_by_section.{k}", v, 0.0, 0.2, "m"))
                     for k, v in sections.items())
    tr = d.get("transport", {})
    if not isinstance(tr, dict):
        raise ValueError(f"material.transport = {tr!r} must be a table (step_factor, curtain_coefficient, ...)")
    extra = set(tr) - set(TRANSPORT_COEFFICIENTS) - set(CALIBRATED_RANGES) - {"source"}
    if extra:
        raise ValueError(f"material.transport.{sorted(extra)[0]} is not a field (allowed: "
                         f"{', '.join(TRANSPORT_COEFFICIENTS)}, {', '.join(CALIBRATED_RANGES)}, source)")
    coeffs = tuple((k, _coefficient(k, tr[k])) for k in TRANSPORT_COEFFICIENTS if k in tr)
    ranges = []
    for k in CALIBRATED_RANGES:
        if k in tr:
            v = tr[k]
            if not isinstance(v, (list, tuple)) or len(v) != 2:
                raise ValueError(f"material.transport.{k} = {v!r} must be [low, high]")
            lo_r = _number(f"transport.{k}[0]", v[0], 0.0, math.inf, "", lo_closed=True)
            hi_r = _number(f"transport.{k}[1]", v[1], 0.0, math.inf, "", lo_closed=True)
            if hi_r < lo_r:
                _fail(f"transport.{k}", list(v), "[low, high] with low <= high")
            ranges.append((k, (lo_r, hi_r)))
    particle_density = _number("particle_density", d["particle_density"], 0.0, 25000.0, "kg/m3")
    particle_diameter = _number("particle_diameter", d["particle_diameter"], 0.0, 0.2, "m")
    kinetics = _kinetics(d["kinetics"], particle_density, particle_diameter)
    t_max = d.get("max_temperature")
    if t_max is not None:
        t_max = _number("max_temperature", t_max, 0.0, 3000.0, "degC")
    t_src = d.get("max_temperature_source", "")
    if not isinstance(t_src, str):
        raise ValueError(f"material.max_temperature_source = {t_src!r} must be a string")
    return Material(
        name=d["name"], title=d["title"], citations=cites, moisture_basis=basis, moisture_range=(lo, hi),
        repose_angle_law=repose, bulk_density_law=density,
        heat_capacity=_number("heat_capacity", d["heat_capacity"], 0.0, 1e4, "J/(kg K)"),
        particle_density=particle_density,
        particle_diameter=particle_diameter,
        kinetics=kinetics,
        water_heat_capacity=_number("water_heat_capacity", d.get("water_heat_capacity", 4182.0), 0.0, 1e4,
                                    "J/(kg K)"),
        repose_angle_source=repose_src, bulk_density_source=density_src, particle_diameter_by_section=sections,
        transport_coefficients=coeffs, transport_source=str(tr.get("source", "")), transport_ranges=tuple(ranges),
        max_temperature=t_max, max_temperature_source=t_src)


def _kinetics(kin: Any, particle_density: float, particle_diameter: float) -> DryingKinetics:
    """``material.kinetics`` checked into a `DryingKinetics`; a thin-layer law takes its
    ``solids_per_area`` (rho_p d_p / 3, kg/m2) from the material's particle density and diameter."""
    if not isinstance(kin, dict):
        raise ValueError(f"material.kinetics = {kin!r} must be a table (method, critical_moisture, ...)")
    if set(kin) - _KINETICS:
        raise ValueError(f"material.kinetics.{sorted(set(kin) - _KINETICS)[0]} is not a field "
                         f"(allowed: {', '.join(sorted(_KINETICS))})")
    kin = dict(kin)
    thin = kin.get("method") == "thin_layer"
    if thin:
        ignored = sorted({"critical_moisture", "exponent", "curve"} & set(kin))
        if ignored:
            raise ValueError(f"material.kinetics.{ignored[0]} is not a field of a thin-layer law (method = "
                             "'thin_layer' takes model, parameters, activation_energy, reference_temperature_K, "
                             "initial_moisture, equilibrium_moisture)")
        if not isinstance(kin.get("parameters"), dict):
            _fail("kinetics.parameters", kin.get("parameters"), "{a table of the law's parameters, e.g. "
                  "{k = 2e-3, n = 0.9}}")
        kin["parameters"] = tuple(kin["parameters"].items())
        kin["solids_per_area"] = particle_density * particle_diameter / 3.0
    for key, lo_k, hi_k, unit, closed in (
            ("critical_moisture", 0.0, 10, "kg/kg dry", False), ("equilibrium_moisture", 0.0, 10, "kg/kg dry", True),
            ("exponent", 0.0, 20, "", False), ("initial_moisture", 0.0, 10, "kg/kg dry", False),
            ("activation_energy", 0.0, 1e6, "J/mol", True), ("reference_temperature_K", 200.0, 1000.0, "K", False)):
        if key in kin:
            kin[key] = _number(f"kinetics.{key}", kin[key], lo_k, hi_k, unit, lo_closed=closed)
    if "critical_moisture" in kin and kin["critical_moisture"] <= kin.get("equilibrium_moisture", 0.0):
        _fail("kinetics.critical_moisture", kin["critical_moisture"],
              f"(equilibrium_moisture = {kin.get('equilibrium_moisture', 0.0):g}, 10) kg/kg dry")
    if "initial_moisture" in kin and kin["initial_moisture"] <= kin.get("equilibrium_moisture", 0.0):
        _fail("kinetics.initial_moisture", kin["initial_moisture"],
              f"(equilibrium_moisture = {kin.get('equilibrium_moisture', 0.0):g}, 10) kg/kg dry")
    try:
        if "curve" in kin:
            kin["curve"] = tuple(tuple(float(v) for v in c) for c in kin["curve"])
        return DryingKinetics(**kin)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"material.kinetics.{exc}") from None

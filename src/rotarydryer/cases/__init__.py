"""Packaged case files (TOML, with citations) and a minimal validated loader.

>>> from rotarydryer.cases import load_case, build_model
>>> case = load_case("lee2008_invicta", {"geometry.method": "lee2008_regressions"})
>>> model = build_model(case)              # a rotarydryer.transport.TransportModel
>>> round(model.steady_state().total_holdup)  # kg
16398

Overrides are flat ``"section.key": value`` pairs (the CLI's ``--set``); values may
be strings and are converted by pydantic.  An unknown key raises ``ValueError``
naming it and listing the valid keys; an invalid value raises ``ValueError`` naming
the key, the value and the constraint.
"""

from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path
from typing import Any, Literal, Optional

from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

__all__ = ["list_cases", "load_case", "build_model", "measured_rtd", "measured_rtd_moments", "valid_override_keys", "DryerCase",
           "LeeCase", "AjayiCase"]


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", validate_assignment=False)


class Meta(_Strict):
    title: str = ""
    citations: list[str] = []


class Drum(_Strict):
    radius: float = Field(gt=0, description="m")
    length: float = Field(gt=0, description="m")
    slope: float = Field(ge=0, lt=45, description="deg")
    n_flights: int = Field(ge=2, description="-")


class Flight(_Strict):
    s1: float = Field(gt=0, description="m, flight base")
    s2: float = Field(ge=0, description="m, flight tip")
    alpha1: float = Field(gt=0, lt=180, description="deg")
    alpha2: float = Field(gt=0, lt=180, description="deg")


class LeeOperating(_Strict):
    feed_rate: float = Field(gt=0, description="kg/s")
    rpm: float = Field(gt=0, le=60, description="rev/min")
    gas_flow: Literal["counter-current", "co-current"] = "counter-current"


class LeeSolids(_Strict):
    bulk_density: float = Field(gt=0, description="kg/m3")
    moisture_inlet: float = Field(gt=0, lt=1, description="kg/kg")
    moisture_outlet: float = Field(gt=0, lt=1, description="kg/kg")
    repose_angle: Optional[float] = Field(default=None, gt=0, lt=90, description="deg, constant")


class LeeTransport(_Strict):
    model: Literal["lee2008", "sheehan2005_model2"] = "lee2008"
    n_cells: int = Field(ge=1, le=100000)
    kiln_time: Optional[float] = Field(default=None, gt=0, description="s")
    backmix: Optional[float] = Field(default=None, ge=0, le=1, description="C_B, -")
    drag_reduction: Optional[float] = Field(default=None, ge=0, description="C_F^G, -")
    loading: Literal["fixed", "state"] = "fixed"
    backmix_to: Literal["passive", "active"] = "passive"


class LeeGeometry(_Strict):
    method: Literal["exact", "lee2008_regressions"] = "exact"
    passive_time_branch: Optional[Literal["eq3.4", "lee2008_ch7"]] = None


class Tracer(_Strict):
    fraction: float = Field(gt=0, description="kg tracer per kg feed during the pulse")
    duration: float = Field(ge=0, description="s")
    t_end: float = Field(gt=0, description="s")
    dt: float = Field(gt=0, description="s")
    measured: Optional[str] = None
    measured_offset: float = 0.0
    dataset: Optional[str] = Field(default=None, description="rotarydryer.rtd dataset; {test} is replaced")
    baseline: str = Field(default="none", description="baseline method for the measured moments")


# ---- blocks shared by every case kind: material, gas, shell, thermal ---------------------
class Burner(_Strict):
    """Direct-fired burner making the drying gas (rotarydryer.thermal.burner, Ajayi (2011) App. A)."""
    combustion_air_share: float = Field(gt=0, lt=1, description="fraction of the air (combustion + dilution) fed through the burner")
    heat_loss_fraction: float = Field(default=0.0, ge=0, le=0.5, description="fraction of the fuel's heat lost by the chamber")
    fuel_water_fraction: float = Field(default=0.0035, ge=0, le=0.5, description="kg/kg fuel (default Ajayi (2011) Table A2 fuel oil)")
    fuel_sulphur_fraction: float = Field(default=0.0095, ge=0, le=0.1, description="kg/kg fuel")
    fuel_carbon_hydrogen_ratio: float = Field(default=7.6, gt=0, le=100, description="C:H mass ratio of the fuel")
    fuel_lower_heating_value: Optional[float] = Field(default=None, ge=1e6, le=1e8, description="J/kg; default from the composition (Channiwala & Parikh 2002)")


class Gas(_Strict):
    """Drying gas (humid air or combustion gas)."""
    direction: Literal["co-current", "counter-current"] = "co-current"
    flow: float = Field(gt=0, le=1000, description="kg/s wet gas into the dryer")
    inlet_temperature: float = Field(gt=0, le=600, description="degC")
    inlet_humidity: float = Field(default=0.01, ge=0, lt=0.2, description="kg/kg wet gas")
    leak_air_flow: float = Field(default=0.0, ge=0, le=1000, description="kg/s ambient air leaking in at the gas inlet")
    feed_temperature: Optional[float] = Field(default=None, ge=0, lt=99, description="degC of the wet feed (plant cases without [operating] feed_temperature)")
    burner: Optional[Burner] = Field(default=None, description="burner making the gas; gives the fuel rate (none: the gas is heated elsewhere)")


class Shell(_Strict):
    """Drum shell and surroundings."""
    ambient_temperature: float = Field(default=25.0, gt=-40, lt=60, description="degC")
    ambient_humidity: float = Field(default=0.01, ge=0, le=0.3, description="kg/kg dry air")
    scale_thickness: float = Field(default=0.0, ge=0, le=0.5, description="m, scale layer inside the shell")
    insulation_thickness: float = Field(default=0.0, ge=0, le=2.0, description="m, external lagging")
    loss_factor: float = Field(default=15.0, ge=0, le=1000, description="theta_loss (thermal.mode = ajayi2011 only)")


class ThermalModel(_Strict):
    """Heat and mass transfer model choices (rotarydryer.thermal.dryer)."""
    enabled: bool = Field(default=True, description="solve heat and mass transfer (false: solids transport only)")
    mode: Literal["physical", "ajayi2011"] = "physical"
    area_scale: float = Field(default=1.0, ge=0, le=100, description="multiplier on the sections' area factors")
    moisture_coupling: bool = Field(default=True, description="repose angle and bulk density from the computed moisture")
    design_load_smoothing: float = Field(default=0.0, ge=0, le=0.1, description="relative width of the smoothed design-load switch (0 = exact)")


class Material(_Strict):
    """A material of the library (rotarydryer.properties.materials) by name, with optional
    field overrides, or a complete inline definition."""
    model_config = ConfigDict(extra="allow")
    name: str = Field(description="library name or a label for an inline material")


class LeeParameterSet(_Strict):
    n_cells: int
    kiln_time: float
    backmix: float
    drag_reduction: float
    source: str = ""


class LeeCase(_Strict):
    kind: Literal["lee2008"]
    meta: Meta = Meta()
    drum: Drum
    flight: Flight
    operating: LeeOperating
    solids: LeeSolids
    transport: LeeTransport
    geometry: LeeGeometry = LeeGeometry()
    tracer: Tracer
    parameter_sets: list[LeeParameterSet] = []
    material: Optional[Material] = None
    gas: Optional[Gas] = None
    shell: Shell = Shell()
    thermal: ThermalModel = ThermalModel(enabled=False)


# ---- Ajayi (2011) MMG Karumba --------------------------------------------------------
class AjayiDrum(_Strict):
    radius: float = Field(gt=0, description="m")
    slope: float = Field(ge=0, lt=45, description="deg")


class AjayiOperating(_Strict):
    test: int = Field(ge=1, le=6)
    feed_rate: Optional[float] = Field(default=None, gt=0, description="kg/s wet; default from the test")
    rpm: Optional[float] = Field(default=None, gt=0, le=60, description="rev/min; default from the test")
    gas_flow: Literal["co-current", "counter-current"] = "co-current"


class AjayiSolids(_Strict):
    moisture_scale: float = Field(default=1.0, gt=0, description="factor on the Eq. 3.1 moisture profile")


class AjayiTransport(_Strict):
    model: Literal["ajayi2011"] = "ajayi2011"
    solids_velocity: Optional[float] = Field(default=None, gt=0, description="u_s, m/s, Ajayi's solids (kilning) velocity; default Table 5.2")
    kiln_velocity: Optional[float] = Field(default=None, gt=0, description="alias of solids_velocity (m/s); solids_velocity wins when both are set")
    dispersion: Optional[float] = Field(default=None, ge=0, description="axial dispersion, m2/s; default Table 5.2")
    unflighted_inlet: Literal["ajayi", "danckwerts"] = "ajayi"
    unflighted_cells: Optional[int] = Field(default=None, ge=2, le=100000, description="FV cells per unflighted section; default auto")
    design_load_factor: float = Field(default=1.24, gt=0, description="m_des = factor * m_Baker (Ajayi code)")
    fouling: Optional[float] = Field(default=None, ge=0, le=0.95, description="fraction of flight loading capacity lost to scale (Ajayi Eq. 5.21); default 0.8 for tests marked scaled (l.1715), else 0")


class AjayiGeometry(_Strict):
    method: Literal["exact", "ajayi2011_regressions"] = "ajayi2011_regressions"
    passive_time_branch: Optional[Literal["eq3.4", "lee2008_ch7"]] = None


class AjayiSection(_Strict):
    name: str
    kind: Literal["flighted", "unflighted"]
    length: float = Field(gt=0)
    n_cells: Optional[int] = None
    n_flights: Optional[int] = None
    s1: Optional[float] = None
    s2: Optional[float] = None
    alpha1: Optional[float] = None
    alpha2: Optional[float] = None
    regression: Optional[dict[str, list[float]]] = None
    area_factor: float = Field(default=1.0, ge=0, description="theta_AL / theta_a, exposed-area factor")
    particle_diameter: Optional[float] = Field(default=None, gt=0, description="m; default the material's")
    shell_temperature: Optional[float] = Field(default=None, gt=-40, lt=600, description="degC, fixed shell temperature (thermal.mode = ajayi2011)")


class AjayiTest(_Strict):
    test: int
    feed_rate: float = Field(gt=0, description="kg/s wet")
    rpm: float
    moisture_inlet: float
    moisture_outlet: float
    kiln_velocity: float
    dispersion: float
    mrt_model_min: Optional[float] = None
    holdup_model_kg: Optional[float] = None
    mrt_measured_min: Optional[float] = None
    scaled: bool = False
    gas_flow: Optional[float] = Field(default=None, gt=0, le=1000,
                                      description="kg/s wet gas in this test, where known (fan openings, a "
                                                  "balance); replaces thermal.gas_flow in the physical mode")
    source: str = ""


class AjayiThermal(_Strict):
    """Heat and mass transfer parameters (rotarydryer.thermal.dryer.ThermalSettings); SI, degC."""
    mode: Literal["physical", "ajayi2011"] = "physical"
    gas_flow: float = Field(default=16.25, gt=0, le=1000, description="kg/s wet gas into the dryer (physical mode)")
    area_scale: float = Field(default=2.6, ge=0, le=100, description="multiplier on Ajayi's area factors (physical mode)")
    gas_inlet_temperature: Optional[float] = Field(default=None, gt=0, le=600, description="degC; default the test's PI value")
    gas_inlet_humidity: float = Field(default=0.0193, ge=0, lt=0.2, description="kg/kg wet gas (Ajayi l.3227)")
    solids_inlet_temperature: float = Field(default=28.0, ge=0, lt=99, description="degC (Ajayi l.3241)")
    ambient_temperature: float = Field(default=26.0, gt=-40, lt=60, description="degC (Ajayi l.3231)")
    fouling: Optional[float] = Field(default=None, ge=0, le=0.95, description="fraction of flight loading capacity lost to scale; default 0.8 for 'Scaled' tests")
    scale_thickness: float = Field(default=0.0, ge=0, le=0.5, description="m, shell scale layer")
    insulation_thickness: float = Field(default=0.0, ge=0, le=2.0, description="m, external lagging")
    loss_factor: float = Field(default=15.0, ge=0, le=1000, description="theta_loss (ajayi2011 mode only)")
    leak_air_flow: float = Field(default=0.0, ge=0, le=1000, description="kg/s ambient air leaking in at the gas inlet end")
    unflighted_cells: dict[str, int] = Field(default={}, description="finite volumes per unflighted section of the thermal model; default one per 0.3 m (at least 4)")
    design_load_smoothing: float = Field(default=0.0, ge=0, le=0.1, description="relative width of the smoothed design-load switch (0 = exact)")
    moisture_coupling: bool = True
    enabled: bool = True
    burner: Optional[Burner] = Field(default=None, description="the combustion chamber (Ajayi (2011) App. A); gives the fuel rate")


class AjayiCase(_Strict):
    kind: Literal["ajayi2011"]
    meta: Meta = Meta()
    drum: AjayiDrum
    operating: AjayiOperating
    solids: AjayiSolids = AjayiSolids()
    transport: AjayiTransport = AjayiTransport()
    geometry: AjayiGeometry = AjayiGeometry()
    tracer: Tracer
    sections: list[AjayiSection]
    tests: list[AjayiTest]
    thermal: AjayiThermal = AjayiThermal()
    material: Material = Material(name="zinc_concentrate_ajayi2011")

    @model_validator(mode="after")
    def _flighted_sections_complete(self):
        """A flighted section needs its cell count and what the chosen geometry method uses:
        Ajayi's regression coefficients (7 area, 11 fall-time) or the flight dimensions."""
        problems = []
        for i, sec in enumerate(self.sections):
            if sec.kind != "flighted":
                continue
            where = f"sections[{i}] ({sec.name})"
            if sec.n_cells is None or sec.n_cells < 1:
                problems.append(f"{where}.n_cells = {sec.n_cells!r}: a flighted section needs n_cells >= 1")
            if self.geometry.method == "ajayi2011_regressions":
                reg = sec.regression or {}
                for key, n in (("area", 7), ("fall_time", 11)):
                    got = reg.get(key)
                    if got is None or len(got) != n:
                        problems.append(f"{where}.regression.{key} = {got!r}: geometry.method = "
                                        f"'ajayi2011_regressions' needs {n} coefficients")
            else:
                for key in ("n_flights", "s1", "s2", "alpha1", "alpha2"):
                    if getattr(sec, key) is None:
                        problems.append(f"{where}.{key} is missing: geometry.method = 'exact' needs the flight dimensions")
        if problems:
            raise ValueError("; ".join(problems))
        return self


# ---- the general schema: any flighted dryer ----------------------------------------------
class DryerDrum(_Strict):
    radius: float = Field(gt=0, le=20, description="m")
    slope: float = Field(ge=0, lt=45, description="deg")
    n_flights: Optional[int] = Field(default=None, ge=2, description="flights per flighted section (default)")


class DryerOperating(_Strict):
    feed_rate: float = Field(gt=0, le=1000, description="kg/s wet solids")
    rpm: float = Field(gt=0, le=60, description="rev/min")
    feed_moisture: float = Field(ge=0, lt=1, description="kg/kg wet")
    feed_temperature: float = Field(default=20.0, ge=0, lt=99, description="degC")


class DryerTransport(_Strict):
    """Defaults for the sections (a section's own value wins)."""
    model: Literal["lee2008", "sheehan2005_model1", "sheehan2005_model2", "ajayi2011"] = "lee2008"
    n_cells: Optional[int] = Field(default=None, ge=1, le=100000, description="cells per flighted section (default)")
    passive_rate: Optional[float] = Field(default=None, ge=0, description="k_PP, 1/s (sheehan2005_model1)")
    exchange_rate: Optional[float] = Field(default=None, gt=0, description="k_PA, 1/s (sheehan2005_model1)")
    return_rate: Optional[float] = Field(default=None, gt=0, description="k_AP, 1/s (sheehan2005_model1)")
    kiln_rate: Optional[float] = Field(default=None, ge=0, description="k_K, 1/s (sheehan2005_model1)")
    kiln_time: float = Field(default=10.0, gt=0, description="s, kilning time of the excess over the design load (lee2008)")
    backmix: float = Field(default=0.0, ge=0, le=1, description="C_B, -")
    drag_reduction: float = Field(default=1.0, ge=0, description="C_F^G, -")
    loading: Literal["fixed", "state"] = "state"
    solids_velocity: float = Field(default=0.01, gt=0, description="u_s, m/s: rolling-bed velocity (unflighted) and kilning velocity (ajayi2011)")
    dispersion: float = Field(default=1e-3, ge=0, description="m2/s, axial dispersion of unflighted sections")
    unflighted_cells: Optional[int] = Field(default=None, ge=2, le=100000, description="finite volumes per unflighted section; default auto")
    fouling: float = Field(default=0.0, ge=0, le=0.95, description="fraction of flight capacity lost to scale")
    product_moisture: Optional[float] = Field(default=None, ge=0, lt=1, description="kg/kg wet, assumed outlet moisture of the transport-only profile (default: the feed moisture)")


class DryerGeometry(_Strict):
    method: Literal["exact"] = "exact"
    passive_time_branch: Optional[Literal["eq3.4", "lee2008_ch7"]] = None
    design_load_method: Literal["lee2008", "ajayi2011"] = "lee2008"


class DryerSection(_Strict):
    name: str = Field(min_length=1)
    kind: Literal["flighted", "unflighted"]
    length: float = Field(gt=0, le=200, description="m")
    n_cells: Optional[int] = Field(default=None, ge=1, le=100000)
    model: Optional[Literal["lee2008", "sheehan2005_model1", "sheehan2005_model2", "ajayi2011"]] = None
    n_flights: Optional[int] = Field(default=None, ge=2)
    s1: Optional[float] = Field(default=None, gt=0, description="m, flight base")
    s2: Optional[float] = Field(default=None, ge=0, description="m, flight tip")
    alpha1: Optional[float] = Field(default=None, gt=0, lt=180, description="deg")
    alpha2: Optional[float] = Field(default=None, gt=0, lt=180, description="deg")
    area_factor: float = Field(default=1.0, ge=0, description="exposed-area factor of the heat/mass transfer")
    particle_diameter: Optional[float] = Field(default=None, gt=0, description="m; default the material's")
    shell_temperature: Optional[float] = Field(default=None, gt=-40, lt=600, description="degC (thermal.mode = ajayi2011)")


class DryerTracer(_Strict):
    fraction: float = Field(default=1e-4, gt=0, description="kg tracer per kg feed during the pulse")
    duration: float = Field(default=60.0, ge=0, description="s")
    t_end: float = Field(default=7200.0, gt=0, description="s")
    dt: float = Field(default=10.0, gt=0, description="s")


class DryerCase(_Strict):
    """One schema for any flighted rotary dryer (``kind = "dryer"``)."""
    kind: Literal["dryer"]
    meta: Meta = Meta()
    drum: DryerDrum
    flight: Optional[Flight] = None
    operating: DryerOperating
    material: Material
    transport: DryerTransport = DryerTransport()
    geometry: DryerGeometry = DryerGeometry()
    sections: list[DryerSection]
    gas: Optional[Gas] = None
    shell: Shell = Shell()
    thermal: ThermalModel = ThermalModel()
    tracer: DryerTracer = DryerTracer()

    @model_validator(mode="after")
    def _complete(self):
        problems = []
        if not self.sections:
            problems.append("sections = []: a dryer needs at least one [[sections]] entry")
        names = [sec.name for sec in self.sections]
        if len(set(names)) != len(names):
            problems.append(f"sections: names {names} are not unique")
        for i, sec in enumerate(self.sections):
            where = f"sections[{i}] ({sec.name})"
            if sec.kind != "flighted":
                continue
            if sec.n_cells is None and self.transport.n_cells is None:
                problems.append(f"{where}.n_cells is missing (and no transport.n_cells default)")
            if (sec.n_flights or self.drum.n_flights) is None:
                problems.append(f"{where}.n_flights is missing (and no drum.n_flights default)")
            for key in ("s1", "s2", "alpha1", "alpha2"):
                if getattr(sec, key) is None and (self.flight is None or getattr(self.flight, key, None) is None):
                    problems.append(f"{where}.{key} is missing (and no [flight] default)")
        if self.thermal.enabled and self.gas is None:
            problems.append("gas is missing: [gas] (flow, inlet_temperature) is needed when thermal.enabled = true")
        if problems:
            raise ValueError("; ".join(problems))
        return self


#: case model of each ``kind``
CASE_MODELS = {"dryer": DryerCase, "lee2008": LeeCase, "ajayi2011": AjayiCase}
_KINDS = CASE_MODELS
_NOT_OVERRIDABLE = {"kind", "meta", "parameter_sets", "sections", "tests"}


def list_cases() -> list[str]:
    """Names of the packaged cases."""
    return sorted(p.name[:-5] for p in resources.files(__package__).iterdir() if p.name.endswith(".toml"))


def valid_override_keys(case_cls) -> list[str]:
    """Flat ``section.key`` names that may be overridden for a case class."""
    import typing

    def block(annotation):
        if typing.get_origin(annotation) is not None:      # Optional[Block]
            annotation = next((a for a in typing.get_args(annotation)
                               if isinstance(a, type) and issubclass(a, BaseModel)), None)
        return annotation if isinstance(annotation, type) and issubclass(annotation, BaseModel) else None

    def fields(cls, prefix):
        out = []
        for k, finfo in cls.model_fields.items():
            out.append(f"{prefix}.{k}")
            sub = block(finfo.annotation)
            if sub is not None:                            # a nested block: gas.burner.combustion_air_share
                out += fields(sub, f"{prefix}.{k}")
        return out

    keys = []
    for sec, finfo in case_cls.model_fields.items():
        sub = block(finfo.annotation)
        if sec not in _NOT_OVERRIDABLE and sub is not None:
            keys += fields(sub, sec)
    return sorted(keys)


def _source(name: str) -> tuple[str, str]:
    """(TOML text, display name) of a packaged case or a .toml path."""
    p = Path(name)
    if p.suffix == ".toml" and p.exists():
        return p.read_text(), str(p)
    res = resources.files(__package__) / f"{name}.toml"
    if not res.is_file():
        raise ValueError(f"case = {name!r} is not a packaged case ({', '.join(list_cases())}) nor a .toml file")
    return res.read_text(), f"{name}.toml"


def _read(name: str) -> dict:
    return _parse(*_source(name))


def _parse(text: str, shown: str) -> dict:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{shown}: not valid TOML: {exc}") from None


def _toml_line(text: str, loc: tuple) -> int | None:
    """Line (1-based) of the key at ``loc`` in a TOML text; the table header when the key is
    absent; None when not found. Handles [table], [table.sub] and [[array]] headers."""
    want = [str(x) for x in loc]
    current: list[str] = []
    counts: dict[str, int] = {}
    best = None
    for no, line in enumerate(text.splitlines(), start=1):
        stripped = line.split("#", 1)[0].strip()
        if not stripped:
            continue
        if stripped.startswith("[["):
            name = stripped.strip("[] ")
            counts[name] = counts.get(name, -1) + 1
            current = name.split(".") + [str(counts[name])]
        elif stripped.startswith("["):
            current = stripped.strip("[] ").split(".")
        elif "=" in stripped:
            key = stripped.split("=", 1)[0].strip().strip('"')
            if current + [key] == want[: len(current) + 1] and len(current) + 1 == len(want):
                return no
            continue
        else:
            continue
        if want[: len(current)] == current:
            best = no
    return best


def _format_validation_error(exc: ValidationError, raw: dict, text: str = "", shown: str = "",
                             overrides: dict | None = None) -> str:
    """One line per problem: ``file:line: field = value: message (allowed ...)``."""
    lines = []
    for e in exc.errors():
        loc = tuple(e["loc"])
        dotted = ".".join(str(x) for x in loc)
        where = shown
        if overrides and dotted in overrides:
            where = f"--set {dotted}"
        elif text:
            no = _toml_line(text, loc)
            where = f"{shown}:{no}" if no else shown
        kind = e.get("type", "")
        if kind == "missing":
            msg = f"{dotted} is missing (a required field or section)"
        elif kind == "extra_forbidden":
            msg = f"{dotted} is not a known field here"
        else:
            msg = f"{dotted} = {e.get('input')!r}: {e['msg']}"
        lines.append(f"{where}: {msg}")
    return "\n".join(lines)


def load_case(name: str, overrides: dict[str, Any] | None = None):
    """Load a packaged case (or a TOML path), apply overrides, validate.

    Parameters
    ----------
    name : str
        ``"lee2008_invicta"``, ``"ajayi2011_mmg"`` or a path to a ``.toml`` file.
    overrides : dict, optional
        ``{"transport.n_cells": 33, "geometry.method": "lee2008_regressions"}``.

    Returns
    -------
    LeeCase or AjayiCase (pydantic models, SI units).
    """
    text, shown = _source(name)
    raw = _parse(text, shown)
    kind = raw.get("kind")
    if kind not in _KINDS:
        raise ValueError(f"kind = {kind!r} is not one of {', '.join(map(repr, _KINDS))}")
    cls = _KINDS[kind]
    if isinstance(raw.get("material"), str):
        raw["material"] = {"name": raw["material"]}
    valid = valid_override_keys(cls)
    for key, value in (overrides or {}).items():
        if key not in valid and not key.startswith("material."):
            raise ValueError(f"unknown override key {key!r} for case {name!r}; valid keys: {', '.join(valid)}")
        *path, fld = key.split(".")
        if isinstance(value, str) and value.strip().lower() in ("none", "null", ""):
            value = None
        node = raw
        for part in path:
            nxt = node.get(part)
            if not isinstance(nxt, dict):
                nxt = node[part] = {}
            node = nxt
        node[fld] = value
    try:
        return cls.model_validate(raw)
    except ValidationError as exc:
        n = len(exc.errors())
        details = _format_validation_error(exc, raw, text, shown, overrides)
        raise ValueError(f"invalid case {name!r} ({n} problem{'s' if n > 1 else ''}):\n{details}") from None


def measured_rtd(case):
    """Measured tracer curve of a case as (time s since injection start, signal), or None.

    Uses the shipped dataset of :mod:`rotarydryer.rtd` (``tracer.dataset``; ``{test}`` is
    replaced by ``operating.test``) when available, else the CSV named by
    ``tracer.measured``.  The signal is E(t) in 1/s for a normalised curve (Lee), else
    the raw concentration (Ajayi: ppm, no baseline subtraction); normalise by its
    integral (see :func:`measured_rtd_moments`)."""
    import numpy as np

    tr = case.tracer
    if tr.dataset is not None:
        from rotarydryer.rtd import load_tracer_dataset

        d = load_tracer_dataset(tr.dataset.format(test=getattr(case.operating, "test", "")))
        t = np.asarray(d.time_s, float) - d.time_origin_s
        y = np.asarray(d.signal, float) * (d.rate_factor or 1.0)
        keep = t >= 0
        return t[keep], y[keep]
    if tr.measured is None:
        return None
    import csv

    text = (resources.files("rotarydryer") / "data" / tr.measured).read_text()
    rows = [r for r in csv.reader(line for line in text.splitlines() if not line.startswith("#"))]
    head, body = rows[0], rows[1:]
    body = [r for r in body if r[0].strip() and r[1].strip()]
    t = np.array([float(r[0]) for r in body])
    if head[0].endswith("_min"):
        t = t * 60.0
    t = t - tr.measured_offset
    y = np.array([float(r[1]) for r in body])
    if head[1].endswith("per_h"):
        y = y / 3600.0
    keep = t >= 0
    order = np.argsort(t[keep])
    return t[keep][order], y[keep][order]


def measured_rtd_moments(case):
    """Mean and SD (s) of the case's measured RTD, with the case's baseline method
    (``tracer.baseline``), by :func:`rotarydryer.rtd.rtd_moments`. Returns a dict or None."""
    data = measured_rtd(case)
    if data is None:
        return None
    from rotarydryer.rtd import rtd_moments

    t, y = data
    m = rtd_moments(t, y, baseline=case.tracer.baseline)
    return {"mean_s": m.mean_s, "std_s": m.std_s, "baseline": m.baseline, "baseline_method": m.baseline_method,
            "tail_truncated": m.tail_truncated}


from .build import build_model, lee_parameters  # noqa: E402  (the builders read the classes above)

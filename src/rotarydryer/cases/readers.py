"""Readers of the plant case formats: each translates its file into the one dryer specification.

Below the readers every layer sees one schema, `rotarydryer.cases.DryerSpec`
(``kind = "dryer"``). The older formats of the thesis plants stay readable so that old case
files load:

* ``kind = "lee2008"`` (Lee (2008), one flighted drum: ``[solids]`` bulk density and dry-basis
  moisture, ``[[parameter_sets]]`` of Table 7.2) -> `lee2008_to_spec`;
* ``kind = "ajayi2011"`` (Ajayi (2011), the MMG dryer: ``[[tests]]`` with Table 5.2 fits, the gas
  and shell in ``[thermal]``) -> `ajayi2011_to_spec`.

A reader first validates the file in its own format (messages name the keys of that file),
then returns the ``kind = "dryer"`` document that `DryerSpec`
validates. Nothing else in the package knows these formats.

Keys of the old formats that a rewritten shipped case no longer has still work as overrides
(``--set``): `LEGACY_KEYS` maps each to its replacement, with a ``FutureWarning`` (shown to users by default, the CLI prints it as a ``warning:`` line)
naming it.
"""

import math
from collections.abc import Callable
from typing import Annotated, Any, Literal, Optional

from pydantic import Field, model_validator

from rotarydryer.properties.materials import load_material
from rotarydryer.published import read_published_csv
from rotarydryer.thermal.settings import AJAYI_GAS_FLOW

from .._limits import field_bounds
from .._validation import check_range
from . import (
    _MODEL1_RATES,
    MAX_ENTRIES,
    MAX_FLIGHTS,
    Burner,
    Drum,
    Flight,
    Gas,
    Material,
    Meta,
    ParameterSet,
    Shell,
    ThermalModel,
    Tracer,
    _cells_problem,
    _core_problem,
    _dataset_problem,
    _length_problem,
    _Strict,
    _TransportVariants,
    regression_problems,
)
from .build import BULK_DENSITY_RANGE, material_of
from .legacy_keys import LEGACY_KEYS, _wet, translate_legacy_overrides

__all__ = ["lee2008_to_spec", "ajayi2011_to_spec", "LEGACY_KEYS", "translate_legacy_overrides", "check_lee2008",
           "LeeCase", "AjayiCase", "SCHEMAS", "READERS"]



# ---- the plant formats' schemas ----------------------------------------------------------------
# Their numeric bounds are those of the keys they become (rotarydryer._limits.LIMITS), so a value the old
# format accepts is never refused for its range after the translation into the one specification.
def _positive(key: str) -> dict:
    """`field_bounds` of ``key`` with its lower end open at 0 (the old formats' gas flows: the
    heat-and-mass model needs a gas flow; the one specification allows 0 for transport-only runs)."""
    b = field_bounds(key)
    b.pop("ge", None)
    b.setdefault("gt", 0.0)
    return b


class LeeOperating(_Strict):
    feed_rate: float = Field(**field_bounds("operating.feed_rate"), description="kg/s")
    rpm: float = Field(**field_bounds("operating.rpm"), description="rev/min")
    gas_flow: Literal["counter-current", "co-current"] = "counter-current"


class LeeSolids(_Strict):
    bulk_density: float = Field(gt=0, description="kg/m3")
    moisture_inlet: float = Field(gt=0, lt=1, description="kg/kg")
    moisture_outlet: float = Field(gt=0, lt=1, description="kg/kg")
    repose_angle: Optional[float] = Field(default=None, gt=0, lt=90, description="deg, constant")


class LeeTransport(_TransportVariants):
    model: Literal["lee2008", "sheehan2005_model1", "sheehan2005_model2"] = "lee2008"

    @model_validator(mode="after")
    def _variants(self):
        problems = [p for p in (_core_problem(self),) if p]
        if self.model == "sheehan2005_model1":
            missing = [f"transport.{k}" for k in _MODEL1_RATES if getattr(self, k) is None]
            if missing:
                problems.append(f"transport.model = 'sheehan2005_model1' needs {', '.join(missing)} (1/s; "
                                "Sheehan et al. (2005) Model 1, notes lee_models.md Section 4.2)")
            elif self.passive_rate == 0 and self.kiln_rate == 0:
                problems.append("transport.passive_rate = 0 and transport.kiln_rate = 0: no solids leave the "
                                "cells (give one of them > 0)")
        else:
            given = [f"transport.{k}" for k in _MODEL1_RATES if getattr(self, k) is not None]
            if given:
                problems.append(f"{', '.join(given)} set but transport.model = {self.model!r}: the rates are "
                                "those of transport.model = 'sheehan2005_model1'")
        if problems:
            raise ValueError("; ".join(problems))
        return self
    n_cells: int = Field(**field_bounds("transport.n_cells"))
    kiln_time: Optional[float] = Field(default=None, **field_bounds("transport.kiln_time"), description="s")
    backmix: Optional[float] = Field(default=None, **field_bounds("transport.backmix"), description="C_B, -")
    drag_reduction: Optional[float] = Field(default=None, **field_bounds("transport.drag_reduction"), description="C_F^G, -")
    loading: Literal["fixed", "state"] = "fixed"
    backmix_to: Literal["passive", "active"] = "passive"


class LeeGeometry(_Strict):
    method: Literal["exact", "lee2008_regressions"] = "exact"
    passive_time_branch: Optional[Literal["eq3.4", "lee2008_ch7"]] = None
    tabulated: bool = Field(default=True, description="exact geometry from a per-drum table (within 1e-7 of the "
                            "direct evaluation, at the cost of the regressions: docs/geometry.md); false = direct")


LeeParameterSet = ParameterSet


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
    parameter_sets: list[LeeParameterSet] = Field(default=[], max_length=MAX_ENTRIES)
    material: Optional[Material] = None
    gas: Optional[Gas] = None
    shell: Shell = Shell()
    thermal: ThermalModel = ThermalModel(enabled=False)

    @model_validator(mode="after")
    def _shipped_dataset(self):
        problem = _dataset_problem(self)
        if problem:
            raise ValueError(problem)
        return self


# ---- Ajayi (2011) MMG Karumba --------------------------------------------------------
class AjayiDrum(_Strict):
    radius: float = Field(**field_bounds("drum.radius"), description="m")
    slope: float = Field(**field_bounds("drum.slope"), description="deg")
    length: Optional[float] = Field(default=None, **field_bounds("drum.length"), description="m, whole drum; optional: the sum of the sections' lengths, which it must equal")


class AjayiOperating(_Strict):
    test: int = Field(ge=1, le=6)
    feed_rate: Optional[float] = Field(default=None, **field_bounds("operating.feed_rate"), description="kg/s wet; default from the test")
    rpm: Optional[float] = Field(default=None, **field_bounds("operating.rpm"), description="rev/min; default from the test")
    gas_flow: Literal["co-current", "counter-current"] = "co-current"


class AjayiSolids(_Strict):
    moisture_scale: float = Field(default=1.0, **field_bounds("transport.moisture_scale"), description="factor on the Eq. 3.1 moisture profile")


class AjayiTransport(_Strict):
    model: Literal["ajayi2011"] = "ajayi2011"
    solids_velocity: Optional[float] = Field(default=None, **field_bounds("transport.solids_velocity"), description="u_s, m/s, Ajayi's solids (kilning) velocity; default Table 5.2")
    kiln_velocity: Optional[float] = Field(default=None, **field_bounds("transport.solids_velocity"), description="alias of solids_velocity (m/s); solids_velocity wins when both are set")
    dispersion: Optional[float] = Field(default=None, **field_bounds("transport.dispersion"), description="axial dispersion, m2/s; default Table 5.2")
    unflighted_inlet: Literal["ajayi", "danckwerts"] = "ajayi"
    unflighted_cells: Optional[int] = Field(default=None, **field_bounds("transport.unflighted_cells"), description="FV cells per unflighted section; default auto")
    design_load_factor: float = Field(default=1.24, **field_bounds("geometry.design_load_factor"), description="m_des = factor * m_Baker (Ajayi code)")
    fouling: Optional[float] = Field(default=None, **field_bounds("transport.fouling"), description="fraction of flight loading capacity lost to scale (Ajayi Eq. 5.21); default 0.8 for tests marked scaled (l.1715), else 0")
    parameter_source: Literal["per_test", "predictive"] = Field(default="per_test", description="per_test: u_s and D of the test (Ajayi Table 5.2); predictive: from the operating point (rotarydryer.transport.ajayi_predictive, docs/mmg_cross_test.md)")
    velocity_law: Literal["friedman_marshall", "kramers"] = Field(default="friedman_marshall", description="predictive kiln velocity: Sullivan/Friedman-Marshall (Song 2003 Eq. 1-2) or Kramers-Croockewit bed (comparison)")
    velocity_coefficient: Optional[float] = Field(default=None, **field_bounds("transport.velocity_coefficient"), description="c_u (-), predictive: u_s = c_u x the velocity law; the case file holds the calibration")
    dispersion_coefficient: Optional[float] = Field(default=None, **field_bounds("transport.dispersion_coefficient"), description="c_D (-), predictive: D = c_D u_s d_p; the case file holds the calibration")


class AjayiGeometry(_Strict):
    method: Literal["exact", "ajayi2011_regressions"] = "exact"
    passive_time_branch: Optional[Literal["eq3.4", "lee2008_ch7"]] = None
    tabulated: bool = Field(default=True, description="exact geometry from a per-drum table (within 1e-7 of the "
                            "direct evaluation, at the cost of the regressions: docs/geometry.md); false = direct")


class AjayiSection(_Strict):
    name: str
    kind: Literal["flighted", "unflighted"]
    length: float = Field(gt=0, le=200, description="m")
    n_cells: Optional[int] = Field(default=None, le=100000)
    n_flights: Optional[int] = Field(default=None, ge=2, le=MAX_FLIGHTS)
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
    feed_rate: float = Field(**field_bounds("operating.feed_rate"), description="kg/s wet")
    rpm: float
    moisture_inlet: float
    moisture_outlet: float
    kiln_velocity: Optional[float] = Field(default=None, **field_bounds("transport.solids_velocity"), description="u_s, m/s, Ajayi Table 5.2 (none for test 1, not modelled by Ajayi)")
    dispersion: Optional[float] = Field(default=None, **field_bounds("transport.dispersion"), description="m2/s, Ajayi Table 5.2 (none for test 1)")
    mrt_model_min: Optional[float] = None
    holdup_model_kg: Optional[float] = None
    mrt_measured_min: Optional[float] = None
    scaled: bool = False
    gas_flow: Optional[float] = Field(default=None, **_positive("gas.flow"),
                                      description="kg/s wet gas in this test, where known (fan openings, a "
                                                  "balance); replaces thermal.gas_flow in the physical mode")
    source: str = ""


class AjayiThermal(_Strict):
    """Heat and mass transfer parameters (rotarydryer.thermal.dryer.ThermalSettings); SI, degC."""
    mode: Literal["physical", "ajayi2011"] = "physical"
    gas_flow: float = Field(default=16.25, **_positive("gas.flow"), description="kg/s wet gas into the dryer (physical mode)")
    area_scale: float = Field(default=2.6, **field_bounds("thermal.area_scale"), description="multiplier on Ajayi's area factors (physical mode)")
    gas_inlet_temperature: Optional[float] = Field(default=None, **field_bounds("gas.inlet_temperature"), description="degC; default the test's PI value")
    gas_inlet_humidity: float = Field(default=0.0193, **field_bounds("gas.inlet_humidity"), description="kg/kg wet gas (Ajayi l.3227)")
    solids_inlet_temperature: float = Field(default=28.0, **field_bounds("operating.feed_temperature"), description="degC (Ajayi l.3241)")
    ambient_temperature: float = Field(default=26.0, **field_bounds("shell.ambient_temperature"), description="degC (Ajayi l.3231)")
    fouling: Optional[float] = Field(default=None, **field_bounds("transport.fouling"), description="fraction of flight loading capacity lost to scale; default 0.8 for 'Scaled' tests")
    scale_thickness: float = Field(default=0.0, **field_bounds("shell.scale_thickness"), description="m, shell scale layer")
    insulation_thickness: float = Field(default=0.0, **field_bounds("shell.insulation_thickness"), description="m, external lagging")
    loss_factor: float = Field(default=15.0, **field_bounds("shell.loss_factor"), description="theta_loss (ajayi2011 mode only)")
    shell_inner_radius: float = Field(default=1.90, **field_bounds("shell.inner_radius"), description="m, steel shell inner radius (Ajayi's code R_in = 1.90, l.3870)")
    shell_thickness: float = Field(default=0.05, **field_bounds("shell.thickness"), description="m, steel shell wall (Ajayi's code R_out - R_in = 1.95 - 1.90, l.4381)")
    leak_air_flow: float = Field(default=0.0, **field_bounds("gas.leak_air_flow"), description="kg/s ambient air leaking in at the gas inlet end")
    unflighted_cells: dict[str, Annotated[int, Field(ge=1, le=100000)]] = Field(default={}, max_length=MAX_ENTRIES, description="finite volumes per unflighted section of the thermal model; default one per 0.3 m (at least 4)")
    design_load_smoothing: float = Field(default=0.0, **field_bounds("thermal.design_load_smoothing"), description="relative width of the smoothed design-load switch (0 = exact)")
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
    sections: list[AjayiSection] = Field(max_length=MAX_ENTRIES)
    tests: list[AjayiTest] = Field(max_length=MAX_ENTRIES)
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
                problems += regression_problems(where, sec)
            else:
                for key in ("n_flights", "s1", "s2", "alpha1", "alpha2"):
                    if getattr(sec, key) is None:
                        problems.append(f"{where}.{key} is missing: geometry.method = 'exact' needs the flight dimensions")
        problems += filter(None, [_length_problem(self), _cells_problem(self), _dataset_problem(self)])
        if problems:
            raise ValueError("; ".join(problems))
        return self




def _same_law(mat, key: str, a: float, b: float) -> bool:
    law = getattr(mat, f"{key}_law")
    return float(law[0]) == float(a) and float(law[1]) == float(b)


def check_lee2008(case) -> None:
    """Checks of a ``kind = "lee2008"`` file in its own keys: ``solids.bulk_density`` in
    `BULK_DENSITY_RANGE`, ``solids.repose_angle`` in (0, 90) deg, and the dry-basis moistures
    ``solids.moisture_inlet`` / ``moisture_outlet`` inside the material's range."""
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
    check_lee2008(case)
    d, fl, op, so, tr, ge = case.drum, case.flight, case.operating, case.solids, case.transport, case.geometry
    material = case.material.model_dump() if case.material is not None else {"name": "raw_sugar_lee2008"}
    lib = material_of(case) if case.material is not None else None
    if lib is None:

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

    op, tr, th = case.operating, case.transport, case.thermal
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
    sections = [s.model_dump(exclude_none=True) for s in case.sections]
    unflighted = {s.name: th.unflighted_cells.get(s.name, max(4, int(math.ceil(s.length / 0.3))))
                  for s in case.sections if s.kind == "unflighted"}
    gas = {"direction": op.gas_flow, "inlet_humidity": th.gas_inlet_humidity, "leak_air_flow": th.leak_air_flow}
    gas["flow"] = th.gas_flow      # a test row's own gas_flow wins (cases.build.thermal_settings)
    if th.gas_inlet_temperature is not None:
        gas["inlet_temperature"] = th.gas_inlet_temperature
    if th.burner is not None:
        gas["burner"] = th.burner.model_dump(exclude_none=True)
    transport = {"model": "ajayi2011", "loading": "state", "unflighted_inlet": tr.unflighted_inlet,
                 "parameter_source": tr.parameter_source, "velocity_law": tr.velocity_law,
                 "moisture_profile": "ajayi2011_eq3.1", "moisture_scale": case.solids.moisture_scale}
    if tr.parameter_source == "predictive":     # this format's predictive mode: the kilning-velocity law
        transport["predictive_flights"] = "kiln_velocity"
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


#: schema of each plant format (``kind``) and the reader translating it into the one specification
SCHEMAS: dict[str, type] = {"lee2008": LeeCase, "ajayi2011": AjayiCase}
READERS: dict[str, Callable] = {"lee2008": lee2008_to_spec, "ajayi2011": ajayi2011_to_spec}

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

import copy
import math
import re
import tomllib
import typing
import warnings
from functools import cache, lru_cache
from importlib import resources
from pathlib import Path
from typing import Annotated, Any, Literal, Optional, get_args

from pydantic import BaseModel, ConfigDict, Field, ValidationError, field_validator, model_validator

from .._limits import LIMITS, MAX_FLIGHTS, describe_limit, field_bounds
from .._validation import _interval
from ..geometry.flights import MAX_SEGMENTS
from .calibration import (
    CalibrationRecord,
    CalibrationWarning,
    applied_calibrations,
    apply_calibrations,
    record_problems,
)

__all__ = ["list_cases", "load_case", "load_case_text", "discrete_kind", "build_model", "has_tracer_curve", "measured_rtd", "measured_rtd_moments",
           "measured_exit_age", "exit_age_r_squared",
           "valid_override_keys", "override_key_type", "measured_files", "resolve_dataset", "DryerCase", "DryerSpec", "CASE_KINDS", "CASE_MODELS",
           "MAX_CELLS", "MAX_TIME_STEPS", "MAX_CASE_BYTES", "case_calibrations", "override_value", "UnusedKeyWarning"]

# ---- ceilings of the model size (docs/app_threat_model.md) -------------------------------
#: cells + finite volumes of one case, all sections together (transport model)
MAX_CELLS = 100_000
#: tracer time steps t_end / dt of one RTD simulation
MAX_TIME_STEPS = 200_000
#: bytes of a case file (TOML)
MAX_CASE_BYTES = 1_000_000
#: entries of a list of a case file (sections, tests, parameter_sets)
MAX_ENTRIES = 1000
#: cells of the auto-discretised unflighted section (rotarydryer.transport.sections.unflighted_cells_auto)
_AUTO_UNFLIGHTED_CELLS = 2000


def _takes_bool(annotation) -> bool:
    """Whether a field of type ``annotation`` may hold a boolean anywhere (bool itself, or inside it)."""
    if annotation is bool:
        return True
    return any(_takes_bool(a) for a in get_args(annotation))


def _takes_str(annotation) -> bool:
    """Whether a field of type ``annotation`` may hold a text anywhere: ``str``, a choice of texts (``Literal``), an
    enumeration, a path, ``Any``, or any of these inside it. A field of numbers only (``float``, ``int``,
    ``Optional[float]``, ``list[float]``, a block) may not."""
    if annotation is Any or annotation is str:
        return True
    if typing.get_origin(annotation) is Literal:
        return any(isinstance(a, str) for a in get_args(annotation))
    if isinstance(annotation, type) and not get_args(annotation):
        return not issubclass(annotation, (bool, int, float, BaseModel, type(None)))
    return any(_takes_str(a) for a in get_args(annotation))


def _holds_str(value) -> bool:
    """Whether ``value`` is a text that reads as a number (pydantic's lax mode takes it; any other text it refuses
    with its own message) or a list (of lists...) holding one."""
    if isinstance(value, str):
        try:
            float(value)
        except ValueError:
            return False
        return True
    return isinstance(value, (list, tuple)) and any(_holds_str(v) for v in value)


def _holds_bool(value) -> bool:
    """Whether ``value`` is a boolean or a list (of lists...) holding one; numbers, the common case of a
    case's tables, cost one type test each."""
    if isinstance(value, bool):
        return True
    if isinstance(value, (list, tuple)):
        for v in value:
            t = type(v)
            if t is float or t is int or t is str:
                continue
            if t is bool or _holds_bool(v):
                return True
    return False


#: the units a schema field's description may start with ("m, flight base"), as `_field_range` quotes them
_FIELD_UNITS = frozenset({"m", "mm", "deg", "s", "min", "h", "kg", "kg/s", "m/s", "m2/s", "m^2/s", "K", "degC", "W",
                          "W/K", "kW", "Pa", "kg/m3", "kg/m^3", "1/s", "rev/min", "kg/kg", "J/(kg K)", "W/(m K)",
                          "W/(m2 K)", "m2", "m^2", "m3", "m^3"})


def _model_in(annotation):
    """The case block class of a field's annotation (``Block``, ``Optional[Block]``, ``list[Block]``), or None."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    return next((m for m in map(_model_in, get_args(annotation)) if m is not None), None)


@cache
def _field_kinds(cls) -> dict:
    """``{field: (block class or None, whether it may hold a boolean)}`` of the schema class ``cls``, worked out
    once per class: walking the annotations took 6 ms of every case load (a study loads one per run)."""
    return {key: (_model_in(f.annotation), _takes_bool(f.annotation), _takes_str(f.annotation))
            for key, f in getattr(cls, "model_fields", {}).items()}


#: `_misread_values` of the blocks walked so far, by identity: (schema class, id(block), check) -> (block, findings):
#: a case file's parsed blocks are shared by every load of its text (`_parse_text`: overrides copy only what they
#: change), so a study's runs walk only the blocks their overrides copied (the two walks were a third of a case
#: load). The block is kept with its entry, so its id is not reused while the entry lives; cleared when full.
_MISREAD_MEMO: dict = {}
_MISREAD_MEMO_SIZE = 1024


def _misread_values(cls, raw, misread, check: str = ""):
    """The dotted keys (as tuples of keys and list indices, relative to ``raw``, with their values) of ``raw`` (a
    case document, or a block of it, for the schema class ``cls``) whose value ``misread(kind, value)`` flags
    (``kind``: the field's `_field_kinds` entry), walking the blocks and the lists of blocks. Unknown keys are left
    to the schema's own check. ``check`` names ``misread`` for `_MISREAD_MEMO` (no memo without a name)."""
    if not isinstance(raw, dict):
        return ()
    memo_key = (cls, id(raw), check)
    hit = _MISREAD_MEMO.get(memo_key) if check else None
    if hit is not None and hit[0] is raw:
        return hit[1]
    out: list = []
    kinds = _field_kinds(cls)
    for key, value in raw.items():
        kind = kinds.get(key)
        if kind is None:
            continue
        block = kind[0]
        if block is not None and isinstance(value, dict):
            out += [((key, *where), v) for where, v in _misread_values(block, value, misread, check)]
        elif block is not None and isinstance(value, list) and all(isinstance(v, dict) for v in value):
            for i, row in enumerate(value):
                out += [((key, i, *where), v) for where, v in _misread_values(block, row, misread, check)]
        elif misread(kind, value):
            out.append(((key,), value))
    found = tuple(out)
    if check:
        if len(_MISREAD_MEMO) >= _MISREAD_MEMO_SIZE:
            _MISREAD_MEMO.clear()
        _MISREAD_MEMO[memo_key] = (raw, found)
    return found


def _text_numbers(cls, raw):
    """The dotted keys (with their values) of ``raw`` (a case file's document) that hold a text where the schema
    expects numbers only: pydantic's lax mode reads ``radius = "1.0"`` as 1.0, so a quoted number in a case file
    passed silently. Only the file's own values: an override of the command line or of a form is text by nature
    and is read as a number."""
    return _misread_values(cls, raw, lambda kind, value: kind[0] is None and not kind[2] and _holds_str(value), "text")


def _boolean_numbers(cls, raw):
    """The dotted keys (with their values) of ``raw`` (a case document) that hold a boolean where the schema
    expects a number: pydantic's lax mode reads true as 1.0 (a 1 m flight section, a feed of 1 kg/s)."""
    return _misread_values(cls, raw, lambda kind, value: _holds_bool(value) and not kind[1], "boolean")


class _Strict(BaseModel):
    # allow_inf_nan=False: TOML's nan/inf are refused everywhere ("Input should be a finite number")
    model_config = ConfigDict(extra="forbid", validate_assignment=False, allow_inf_nan=False, defer_build=True)


# ---- shipped data sets a case may name (never a path) ------------------------------------
_TIME_HEADERS = ("time_s,", "time_min,")


@lru_cache(maxsize=1)
def measured_files() -> tuple[str, ...]:
    """File names allowed in ``tracer.measured``: the CSVs shipped in ``rotarydryer/data`` whose
    header starts with a time column (``time_s`` or ``time_min``), i.e. the measured tracer
    curves.  A case names one of these by its bare file name; no path is ever accepted."""
    root = resources.files("rotarydryer.data")
    out = []
    for p in root.iterdir():
        if not (p.name.endswith(".csv") and p.is_file()):
            continue
        head = next((ln for ln in p.read_text("utf-8").splitlines() if ln.strip() and not ln.startswith("#")), "")
        if head.startswith(_TIME_HEADERS):
            out.append(p.name)
    return tuple(sorted(out))


def _dataset_names() -> list[str]:
    from rotarydryer.data import tracer_dataset_names  # not via rotarydryer.rtd: 0.4-0.9 s of imports

    return tracer_dataset_names()


_DATASET_CHARS = frozenset("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-")


def _check_measured(value):
    if value is None:
        return value
    allowed = measured_files()
    if value in allowed:
        return value
    pathlike = any(c in value for c in "/\\:\x00") or ".." in value or value.startswith("~")
    why = "paths are refused; give" if pathlike else "give"
    raise ValueError(f"is not a shipped data set ({why} the bare file name of a tracer CSV shipped in "
                     f"rotarydryer/data); allowed: {', '.join(allowed)}")


def _check_dataset(value):
    if value is None:
        return value
    rest = value.replace("{test}", "")
    if not rest or not set(rest) <= _DATASET_CHARS:
        raise ValueError(f"is not a shipped data set name (letters, digits, '_' and '-'; the only placeholder "
                         f"is {{test}}, replaced by operating.test); allowed: {', '.join(_dataset_names())}")
    return value


def resolve_dataset(template: str, test="") -> str:
    """``tracer.dataset`` with ``{test}`` replaced by ``test`` (plain text replacement, never
    ``str.format``)."""
    return template.replace("{test}", str(test))


def _dataset_problem(case) -> str | None:
    tr = case.tracer
    if getattr(tr, "dataset", None) is None:
        return None
    test = getattr(case.operating, "test", "")
    name = resolve_dataset(tr.dataset, test)
    names = _dataset_names()
    if name in names:
        return None
    shown = f"{tr.dataset!r}" + (f" (with operating.test = {test}: {name!r})" if "{test}" in tr.dataset else "")
    return f"tracer.dataset = {shown} is not a shipped data set; allowed: {', '.join(names)}"


class Meta(_Strict):
    title: str = ""
    citations: list[str] = []


class Drum(_Strict):
    radius: float = Field(**field_bounds("drum.radius"), description="m")
    length: float = Field(**field_bounds("drum.length"), description="m")
    slope: float = Field(**field_bounds("drum.slope"), description="deg")
    n_flights: int = Field(ge=2, le=MAX_FLIGHTS, description="-")


class Flight(_Strict):
    s1: float = Field(gt=0, description="m, flight base")
    s2: float = Field(ge=0, description="m, flight tip")
    alpha1: float = Field(gt=0, lt=180, description="deg")
    alpha2: float = Field(gt=0, lt=180, description="deg")


#: a section of a polygonal flight: [length m, angle deg] (first: base to wall; then interior angles at the bends)
FlightSection = tuple[Annotated[float, Field(gt=0, le=100)], Annotated[float, Field(gt=0, lt=360)]]
#: a vertex of a polygonal flight in its own frame: [x m (forward along the wall), y m (inward)]
FlightVertex = tuple[Annotated[float, Field(ge=-100, le=100)], Annotated[float, Field(ge=-100, le=100)]]
#: the two-section keys of a flight
TWO_SECTION_KEYS = ("s1", "s2", "alpha1", "alpha2")
#: the polygonal-flight keys (one of them describes the whole flight)
POLYGON_KEYS = ("segments", "vertices")


def _flight_problem(where: str, block) -> str | None:
    """A flight block gives the two-section keys or one polygonal description, not both."""
    poly = [k for k in POLYGON_KEYS if getattr(block, k, None) is not None]
    two = [k for k in TWO_SECTION_KEYS if getattr(block, k, None) is not None]
    if len(poly) > 1:
        return f"{where}: segments and vertices are both given; give the flight one way"
    if poly and two:
        return (f"{where}: {poly[0]} and {', '.join(two)} are both given; a polygonal flight ({poly[0]}) "
                "replaces s1, s2, alpha1 and alpha2")
    return None


class DryerFlight(_Strict):
    """The flights of a dryer: a two-section flight (``s1``, ``s2``, ``alpha1``, ``alpha2``; Lee (2008)
    Fig. 4.2) or a polygonal flight of any shape (``segments`` or ``vertices``,
    `rotarydryer.geometry.PolygonFlight`)."""
    s1: Optional[float] = Field(default=None, gt=0, description="m, flight base")
    s2: Optional[float] = Field(default=None, ge=0, description="m, flight tip")
    alpha1: Optional[float] = Field(default=None, gt=0, lt=180, description="deg")
    alpha2: Optional[float] = Field(default=None, gt=0, lt=180, description="deg")
    segments: Optional[list[FlightSection]] = Field(default=None, min_length=1, max_length=MAX_SEGMENTS, description=(
        "a flight of any shape: [[length m, angle deg], ...] from the root (first angle: base to wall, 90 = radial; "
        "then the interior angle at each bend, 180 = straight on, < 180 bent forward); replaces s1, s2, alpha1, alpha2"))
    vertices: Optional[list[FlightVertex]] = Field(default=None, min_length=2, max_length=MAX_SEGMENTS + 1, description=(
        "a flight of any shape: [[x m, y m], ...] from the root [0, 0] in the flight's frame (x forward along the "
        "wall, y inward); replaces s1, s2, alpha1, alpha2"))

    @model_validator(mode="after")
    def _one_way(self):
        problem = _flight_problem("flight", self)
        if problem:
            raise ValueError(problem)
        return self


#: stagnant-core variants of ``transport.core`` (rotarydryer.transport.core_variants, docs/rtd_spread.md)
CORE_CHOICES = ("none", "first_order", "diffusive")


def _core_problem(tr) -> str | None:
    """``transport.core`` needs both ``core_fraction`` and ``core_time``; they need a core."""
    given = [k for k in ("core_fraction", "core_time") if getattr(tr, k) is not None]
    if tr.core != "none":
        missing = [f"transport.{k}" for k in ("core_fraction", "core_time") if getattr(tr, k) is None]
        if missing:
            return (f"transport.core = {tr.core!r} needs {' and '.join(missing)} (core_fraction: core mass / "
                    f"mobile passive mass, -, in {describe_limit('transport.core_fraction')}; core_time: s, in "
                    f"{describe_limit('transport.core_time')})")
    elif given:
        return (f"{' and '.join('transport.' + k for k in given)} set but transport.core = 'none': choose "
                f"transport.core = 'first_order' or 'diffusive' (or remove them)")
    return None


_MODEL1_RATES = ("passive_rate", "exchange_rate", "return_rate", "kiln_rate")


class _TransportVariants(_Strict):
    """Transport options shared by the Lee and the general case: Sheehan et al. (2005) Model 1
    rates, the near-stagnant core and the forward-step source."""
    passive_rate: Optional[float] = Field(default=None, **field_bounds("transport.passive_rate"), description="k_PP, 1/s (sheehan2005_model1)")
    exchange_rate: Optional[float] = Field(default=None, **field_bounds("transport.exchange_rate"), description="k_PA, 1/s (sheehan2005_model1)")
    return_rate: Optional[float] = Field(default=None, **field_bounds("transport.return_rate"), description="k_AP, 1/s (sheehan2005_model1)")
    kiln_rate: Optional[float] = Field(default=None, **field_bounds("transport.kiln_rate"), description="k_K, 1/s (sheehan2005_model1)")
    core: Literal["none", "first_order", "diffusive"] = Field(
        default="none", description="near-stagnant core of the passive phase of every cell "
        "(rotarydryer.transport.core_variants.add_stagnant_core; docs/rtd_spread.md)")
    core_fraction: Optional[float] = Field(default=None, **field_bounds("transport.core_fraction"), description="beta, core mass / mobile "
                                           "passive mass (-), with transport.core only")
    core_time: Optional[float] = Field(default=None, **field_bounds("transport.core_time"), description="s: t_c, mean stay in the core "
                                       "(first_order), or t_D = d^2/D_core, diffusion time across it (diffusive)")
    forward_step: Literal["fitted", "trajectory"] = Field(default="fitted", description="C_F from the fitted drag_reduction (Lee Eq. 3.7-3.8) or from particle trajectories through [gas] (docs/transport.md)")
    curtain_velocity_ratio: Optional[float] = Field(default=None, **field_bounds("transport.curtain_velocity_ratio"), description="U_c/U_g in the curtains (trajectory step); default Sherritt, Lee Eq. 2.14")
    curtain_coefficient: Optional[float] = Field(default=None, **field_bounds("transport.curtain_coefficient"), description="K of Sherritt's c_v = min(1, K h^-0.76 q^-0.86) (trajectory step; default the material's [transport] value, else Lee Eq. 2.14's 1.546; docs/predictive_transport.md)")
    step_factor: Optional[float] = Field(default=None, **field_bounds("transport.step_factor"), description="c_0 (-), advance of a cascade without gas over the drag-free fall h_m sin(theta) (trajectory step; default the material's [transport] value, else 1 = a straight fall)")
    kiln_law: Literal["fixed", "cascade"] = Field(default="fixed", description="kilning of the excess over the design load (lee2008): 'fixed', at 1/transport.kiln_time (Lee Eq. 3.9), or 'cascade', at the axial speed of the flight-borne solids without gas, c_0 h_m sin(theta)/(t_p + t_a) (docs/predictive_transport.md; transport.kiln_time unused)")


class _TracerSource(_Strict):
    """Where a case's measured tracer curve comes from (shared by the tracer blocks of every schema)."""
    measured: Optional[str] = Field(default=None, max_length=200,
                                    description="bare file name of a shipped tracer CSV (measured_files())")
    measured_offset: float = Field(default=0.0, description="s, injection start in the measured file")
    dataset: Optional[str] = Field(default=None, max_length=200,
                                   description="rotarydryer.rtd dataset; {test} is replaced (plain text)")
    baseline: Literal["none", "leading", "trailing", "linear"] = Field(
        default="none", description="baseline method for the measured moments (rotarydryer.rtd.BASELINE_METHODS)")

    @field_validator("measured")
    @classmethod
    def _measured_shipped(cls, v):
        return _check_measured(v)

    @field_validator("dataset")
    @classmethod
    def _dataset_shipped(cls, v):
        return _check_dataset(v)

    @model_validator(mode="after")
    def _time_grid(self):
        check_time_grid(self.t_end, self.dt, getattr(self, "duration", None))
        return self


class Tracer(_TracerSource):
    """The tracer pulse of the plant formats (every value given)."""
    fraction: float = Field(gt=0, description="kg tracer per kg feed during the pulse")
    duration: float = Field(ge=0, description="s")
    t_end: float = Field(gt=0, description="s")
    dt: float = Field(gt=0, description="s")


def check_time_grid(t_end: float, dt: float, duration: float | None = None, t_end_key: str = "tracer.t_end",
                    dt_key: str = "tracer.dt") -> None:
    """A tracer's time grid: ``t_end`` / ``dt`` (s) within (1, MAX_TIME_STEPS] (the RTD simulation stores every step),
    the pulse of ``duration`` s (None: an impulse) inside the record; ``t_end_key``, ``dt_key``: the names the
    messages give them (a grid given to `Simulation.rtd`: its arguments). Raises ValueError."""
    steps = t_end / dt
    if t_end <= dt:
        raise ValueError(f"{t_end_key} = {t_end!r} s must be larger than {dt_key} = {dt!r} s")
    if steps > MAX_TIME_STEPS:
        raise ValueError(f"{t_end_key} = {t_end!r} s and {dt_key} = {dt!r} s give {steps:.6g} time steps; "
                         f"the limit is {MAX_TIME_STEPS} (raise {dt_key} or lower {t_end_key})")
    # the pulse ends inside the record: one longer than it was simulated as fed to the end, and its "RTD" moments
    # were those of a truncated step (a mean of 1e28 min for a 1e30 s pulse; found by fuzzing)
    if duration is not None and not duration < t_end:
        raise ValueError(f"tracer.duration = {duration!r} s must be shorter than {t_end_key} = {t_end!r} s (the "
                         f"pulse must end inside the simulated record; allowed: [0, {t_end!r}) s)")


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
    flow: Optional[float] = Field(default=None, **field_bounds("gas.flow"), description="kg/s wet gas into the dryer (0: no gas, e.g. Song's no-air runs; heat and mass transfer needs > 0, so use thermal.enabled = false); needed by the heat-and-mass model and the trajectory forward step")
    inlet_temperature: Optional[float] = Field(default=None, **field_bounds("gas.inlet_temperature"), description="degC; needed as gas.flow")
    inlet_humidity: float = Field(default=0.01, **field_bounds("gas.inlet_humidity"), description="kg/kg wet gas")
    leak_air_flow: float = Field(default=0.0, **field_bounds("gas.leak_air_flow"), description="kg/s ambient air leaking in at the gas inlet")
    feed_temperature: Optional[float] = Field(default=None, **field_bounds("gas.feed_temperature"), description="degC of the wet feed (plant cases without [operating] feed_temperature)")
    burner: Optional[Burner] = Field(default=None, description="burner making the gas; gives the fuel rate (none: the gas is heated elsewhere)")
    recycle_fraction: float = Field(default=0.0, **field_bounds("gas.recycle_fraction"), description="fraction of the exhaust (dry gas) returned to the burner and mixed with the fresh air; the drum's dry gas flow and gas.inlet_temperature stay, the burner heats the mix (docs/guide/energy_audit.md)")


class Shell(_Strict):
    """Drum shell and surroundings."""
    ambient_temperature: float = Field(default=25.0, **field_bounds("shell.ambient_temperature"), description="degC")
    ambient_humidity: float = Field(default=0.01, **field_bounds("shell.ambient_humidity"), description="kg/kg dry air; above the saturation humidity at ambient_temperature and the site's pressure the model takes saturated air (a warning)")
    scale_thickness: float = Field(default=0.0, **field_bounds("shell.scale_thickness"), description="m, scale layer inside the shell")
    insulation_thickness: float = Field(default=0.0, **field_bounds("shell.insulation_thickness"), description="m, external lagging")
    loss_factor: float = Field(default=15.0, **field_bounds("shell.loss_factor"), description="theta_loss (thermal.mode = ajayi2011 only)")
    inner_radius: Optional[float] = Field(default=None, **field_bounds("shell.inner_radius"), description="m, inner radius of the steel shell; default the drum radius")
    thickness: Optional[float] = Field(default=None, **field_bounds("shell.thickness"), description="m, steel shell wall; default 2.63 % of the inner radius (Ajayi's 0.05 m at 1.90 m)")
    max_temperature: Optional[float] = Field(default=None, **field_bounds("shell.max_temperature"), description="degC, highest allowed steel wall temperature (e.g. 593, the mild-steel limit Ajayi (2011) Ch. 7 quotes from API 521): a warning and shell_temperature_limit_exceeded when the model's wall is hotter; default none")


class Site(_Strict):
    """The site's atmosphere: its pressure, from the altitude (the ambient temperature and humidity are
    [shell] ambient_temperature and ambient_humidity)."""
    altitude: float = Field(default=0.0, **field_bounds("site.altitude"), description="m above sea level: the pressure of the gas, the combustion and the outside air is the ISO 2533 standard atmosphere's there (0 m: 101325 Pa; 2000 m: 79.5 kPa)")


class ThermalModel(_Strict):
    """Heat and mass transfer model choices (rotarydryer.thermal.dryer)."""
    enabled: bool = Field(default=True, description="solve heat and mass transfer (false: solids transport only)")
    mode: Literal["physical", "ajayi2011"] = "physical"
    area_scale: float = Field(default=1.0, **field_bounds("thermal.area_scale"), description="multiplier on the sections' area factors")
    moisture_coupling: bool = Field(default=True, description="repose angle and bulk density from the computed moisture")
    design_load_smoothing: float = Field(default=0.0, **field_bounds("thermal.design_load_smoothing"), description="relative width of the smoothed design-load switch (0 = exact)")
    kiln_bed_area: bool = Field(default=True, description="physical mode: the solids of a flighted cell above its design load (a kiln bed: overloaded or fouled flights) exchange with the gas through the bed's active layer (Ajayi (2011) Eq. 6.56-6.61); false: curtains and unflighted beds only, as the thesis")
    discharge_cooling_ntu: float = Field(default=0.0, **field_bounds("thermal.discharge_cooling_ntu"), description="transfer units of the product's cooling by ambient air between the drum outlet and the product temperature sensor (rotarydryer.thermal.streams.discharge_cooling; 0: the sensor at the drum outlet)")
    unflighted_cells: dict[str, Annotated[int, Field(ge=1, le=100000)]] = Field(default={}, max_length=MAX_ENTRIES, description="finite volumes per unflighted section of the heat-and-mass model (default the transport model's)")
    mode_values: dict[str, dict[str, float]] = Field(default={}, max_length=10, description="per thermal.mode, values of gas.flow and thermal.area_scale that mode takes instead of the case's (the source's own settings of its mode, e.g. Ajayi's code gas flow)")

    @field_validator("mode_values")
    @classmethod
    def _mode_values(cls, v):
        for mode, vals in v.items():
            if mode not in ("physical", "ajayi2011"):
                raise ValueError(f"names mode {mode!r}; allowed: 'physical', 'ajayi2011'")
            bad = sorted(set(vals) - {"gas.flow", "thermal.area_scale"})
            if bad:
                raise ValueError(f"[{mode}] sets {', '.join(bad)}; allowed keys: 'gas.flow', 'thermal.area_scale'")
        return v


class Material(_Strict):
    """A material of the library (rotarydryer.properties.materials) by name, with optional
    field overrides, or a complete inline definition. A case names a library material, never
    a file: ``material = "path/to/x.toml"`` is refused (the library function
    ``load_material`` still reads a path given by a program)."""
    model_config = ConfigDict(extra="allow")
    name: str = Field(min_length=1, max_length=200, description="library name or a label for an inline material")

    @model_validator(mode="after")
    def _library_name(self):
        if not self.model_extra:    # a bare name: must be a library material
            from rotarydryer.properties.materials import list_materials

            names = list_materials()
            if self.name not in names:
                raise ValueError(f"material.name = {self.name!r} is not a material of the library; allowed: "
                                 f"{', '.join(names)} (or an inline definition with its fields)")
        return self


class ParameterSet(_Strict):
    """Fitted transport coefficients of one cell count (Lee (2008) Table 7.2)."""
    n_cells: int = Field(**field_bounds("transport.n_cells"))
    kiln_time: float = Field(**field_bounds("transport.kiln_time"), description="s")
    backmix: float = Field(**field_bounds("transport.backmix"), description="C_B, -")
    drag_reduction: float = Field(**field_bounds("transport.drag_reduction"), description="C_F^G, -")
    source: str = ""
# ---- the general schema: any flighted dryer ----------------------------------------------
class DryerDrum(_Strict):
    radius: float = Field(**field_bounds("drum.radius"), description="m")
    slope: float = Field(**field_bounds("drum.slope"), description="deg")
    length: Optional[float] = Field(default=None, **field_bounds("drum.length"), description="m, whole drum; optional: the sum of the sections' lengths, which it must equal")
    n_flights: Optional[int] = Field(default=None, ge=2, le=MAX_FLIGHTS, description="flights per flighted section (default)")


class DryerOperating(_Strict):
    test: Optional[int] = Field(default=None, ge=0, le=1_000_000, description="the [[tests]] row whose operating "
                                "point this run takes: its values are the defaults of the keys it gives")
    feed_rate: Optional[float] = Field(default=None, **field_bounds("operating.feed_rate"), description="kg/s wet solids (default the test's)")
    rpm: Optional[float] = Field(default=None, **field_bounds("operating.rpm"), description="rev/min (default the test's)")
    feed_moisture: Optional[float] = Field(default=None, **field_bounds("operating.feed_moisture"), description="kg/kg wet (default the test's)")
    feed_temperature: float = Field(default=20.0, **field_bounds("operating.feed_temperature"), description="degC")


class OperatingTest(_Strict):
    """One measured operating point of the plant (a row of [[tests]], selected by operating.test):
    its values are the defaults of the case keys named in each field's description."""
    test: int = Field(ge=0, le=1_000_000)
    feed_rate: float = Field(**field_bounds("operating.feed_rate"), description="kg/s wet (operating.feed_rate)")
    rpm: float = Field(**field_bounds("operating.rpm"), description="rev/min (operating.rpm)")
    feed_moisture: float = Field(**field_bounds("operating.feed_moisture"), description="kg/kg wet (operating.feed_moisture)")
    product_moisture: Optional[float] = Field(default=None, **field_bounds("transport.product_moisture"), description="kg/kg wet, measured (transport.product_moisture)")
    solids_velocity: Optional[float] = Field(default=None, **field_bounds("transport.solids_velocity"), description="u_s, m/s, fitted to this test (transport.solids_velocity)")
    dispersion: Optional[float] = Field(default=None, **field_bounds("transport.dispersion"), description="m2/s, fitted to this test (transport.dispersion)")
    fouling: float = Field(default=0.0, **field_bounds("transport.fouling"), description="fraction of flight capacity lost to scale in this test (transport.fouling)")
    gas_flow: Optional[float] = Field(default=None, **field_bounds("gas.flow"), description="kg/s wet gas in this test, where known (gas.flow; 0: no gas, transport only)")
    slope: Optional[float] = Field(default=None, **field_bounds("drum.slope"), description="deg, drum inclination in this test (drum.slope; a --set drum.slope wins)")
    gas_inlet_temperature: Optional[float] = Field(default=None, **field_bounds("gas.inlet_temperature"), description="degC, measured (replaces gas.inlet_temperature in this test; a --set gas.inlet_temperature wins)")
    mrt_model_min: Optional[float] = Field(default=None, gt=0, lt=1e6, description="min, the source's model result (for comparison)")
    holdup_model_kg: Optional[float] = Field(default=None, gt=0, description="kg, the source's model result (for comparison)")
    mrt_measured_min: Optional[float] = Field(default=None, gt=0, lt=1e6, description="min, measured mean residence time")
    holdup_measured_kg: Optional[float] = Field(default=None, gt=0, description="kg, measured total holdup (e.g. mean residence time x feed)")
    moisture_profile: Optional[str] = Field(default=None, max_length=200, description="shipped CSV of solids moisture samples along the drum at this test (columns position_m, moisture_kg_per_kg_wet; a bare file name in rotarydryer/data)")
    gas_outlet_temperature: Optional[float] = Field(default=None, gt=-40, lt=1000, description="degC, measured exhaust gas temperature")
    product_temperature: Optional[float] = Field(default=None, gt=-40, lt=600, description="degC, measured product temperature (at the plant's sensor: thermal.discharge_cooling_ntu)")
    product_d50: Optional[float] = Field(default=None, gt=0, le=0.2, description="m, measured mass-median size of the product (a sieve analysis; needs [particle_size])")
    dust_rate: Optional[float] = Field(default=None, ge=0, le=1000, description="kg/s wet (with its water, as dust_rate_kg_s), measured dust carried to the exhaust (a baghouse catch; needs [particle_size])")
    source: str = ""

    @field_validator("moisture_profile")
    @classmethod
    def _profile_file(cls, v):
        if v is None:
            return v
        if any(c in v for c in "/\\:\x00") or ".." in v or not v.endswith(".csv") \
                or not (resources.files("rotarydryer.data") / v).is_file():
            raise ValueError("is not the bare name of a CSV shipped in rotarydryer/data (e.g. "
                             "'ajayi_moisture_profile_table3_3.csv'); paths are refused")
        return v


class DryerTransport(_TransportVariants):
    """Defaults for the sections (a section's own value wins)."""

    @model_validator(mode="after")
    def _core_complete(self):
        problem = _core_problem(self)
        if problem:
            raise ValueError(problem)
        return self

    model: Literal["lee2008", "sheehan2005_model1", "sheehan2005_model2", "ajayi2011"] = "lee2008"
    n_cells: Optional[int] = Field(default=None, **field_bounds("transport.n_cells"), description="cells per flighted section (default)")
    kiln_time: Optional[float] = Field(default=None, **field_bounds("transport.kiln_time"), description="s, kilning time of the excess over the design load (lee2008); default the [[parameter_sets]] row of n_cells, else 10 s")
    backmix: Optional[float] = Field(default=None, **field_bounds("transport.backmix"), description="C_B, -; default the [[parameter_sets]] row of n_cells, else 0")
    drag_reduction: Optional[float] = Field(default=None, **field_bounds("transport.drag_reduction"), description="C_F^G, -; default the [[parameter_sets]] row of n_cells, else 1")
    backmix_to: Literal["passive", "active"] = Field(default="passive", description="where backmixed solids go: the previous passive phase (Lee 2008) or active phase (sheehan2005_model2 always)")
    loading: Literal["fixed", "state"] = "state"
    moisture_profile: Literal["exponential", "lee2008_eq7.3", "ajayi2011_eq3.1"] = Field(
        default="exponential", description="assumed moisture of the transport-only network from operating.feed_moisture to "
        "transport.product_moisture: exponential in the wet basis at the cells' centres, or Lee (2008) Eq. 7.3 (exponential "
        "in the dry basis at i/(N-1), i = 0..N-1, as Lee's gPROMS code), or Ajayi (2011) Eq. 3.1 times transport.moisture_scale "
        "(the MMG dryer's measured profile; with transport.parameter_source = 'predictive' mapped onto the feed and product "
        "moisture)")
    solids_velocity: Optional[float] = Field(default=None, **field_bounds("transport.solids_velocity"), description="u_s, m/s: rolling-bed velocity (unflighted) and kilning velocity (ajayi2011); default the test's, else 0.01")
    dispersion: Optional[float] = Field(default=None, **field_bounds("transport.dispersion"), description="m2/s, axial dispersion of unflighted sections; default the test's, else 1e-3")
    unflighted_cells: Optional[int] = Field(default=None, **field_bounds("transport.unflighted_cells"), description="finite volumes per unflighted section; default auto")
    fouling: Optional[float] = Field(default=None, **field_bounds("transport.fouling"), description="fraction of flight capacity lost to scale (default the test's, else 0)")
    product_moisture: Optional[float] = Field(default=None, **field_bounds("transport.product_moisture"), description="kg/kg wet, assumed outlet moisture of the transport-only profile (default: the test's, else the feed moisture)")
    moisture_scale: float = Field(default=1.0, **field_bounds("transport.moisture_scale"), description="factor on the ajayi2011_eq3.1 moisture profile")
    unflighted_inlet: Literal["danckwerts", "ajayi"] = Field(default="danckwerts", description="inlet condition of a first unflighted section: Danckwerts flux, or Dirichlet m(0) = F/u (Ajayi (2011) Eq. 5.11-5.13 as coded)")
    parameter_source: Literal["per_test", "predictive"] = Field(default="per_test", description="per_test: the fitted coefficients (lee2008: transport.kiln_time, backmix, drag_reduction or [[parameter_sets]]; ajayi2011: transport.solids_velocity, transport.dispersion, else the selected test's fit); predictive: from geometry, material and operating point (lee2008: the trajectory forward step with transport.step_factor and transport.curtain_coefficient and kiln_law = 'cascade'; ajayi2011: rotarydryer.transport.ajayi_predictive; docs/predictive_transport.md)")
    predictive_flights: Literal["cascade", "kiln_velocity"] = Field(default="cascade", description="ajayi2011 flighted sections under parameter_source = 'predictive': the cascade law of every flighted model (trajectory step, transport.step_factor, excess kilned at the cascade speed; docs/predictive_transport.md), or Ajayi's kilning of the whole passive mass at the velocity law's u_s (docs/mmg_cross_test.md)")
    velocity_law: Literal["friedman_marshall", "kramers"] = Field(default="friedman_marshall", description="predictive kiln velocity: Sullivan/Friedman-Marshall (Song 2003 Eq. 1-2) or Kramers-Croockewit bed (comparison)")
    velocity_coefficient: Optional[float] = Field(default=None, **field_bounds("transport.velocity_coefficient"), description="c_u (-), predictive: u_s = c_u x the velocity law (unflighted beds, ajayi2011 kilning); default the material's [transport] value")
    dispersion_coefficient: Optional[float] = Field(default=None, **field_bounds("transport.dispersion_coefficient"), description="c_D (-), predictive: D = c_D u_s d_p (unflighted beds); default the material's [transport] value")


class DryerGeometry(_Strict):
    method: Literal["exact", "lee2008_regressions", "ajayi2011_regressions"] = Field(
        default="exact", description="exact flight geometry, or Lee (2008) Eq. 4.24-4.28 regressions (fitted to the "
        "Invicta flights; reproduce Lee's Ch. 7), or Ajayi (2011) Appendix F per-section regressions (sections[].regression)")
    design_load_factor: float = Field(default=1.24, **field_bounds("geometry.design_load_factor"), description="m_des = factor x m_Baker of the ajayi2011_regressions (Ajayi (2011) Section 4.5)")
    passive_time_branch: Optional[Literal["eq3.4", "lee2008_ch7"]] = None
    tabulated: bool = Field(default=True, description="exact geometry from a per-drum table (within 1e-7 of the "
                            "direct evaluation, at the cost of the regressions: docs/geometry.md); false = direct")
    design_load_method: Literal["lee2008", "ajayi2011"] = "lee2008"
    finite_particle: bool = Field(default=False, description="finite-particle correction of the flight holdup "
                                  "(surface layer of 1.51 particle diameters, calibrated on DEM: docs/dem.md) with the "
                                  "section's or the material's particle diameter")


class DryerSection(_Strict):
    name: str = Field(min_length=1)
    kind: Literal["flighted", "unflighted"]
    length: float = Field(gt=0, le=200, description="m")
    n_cells: Optional[int] = Field(default=None, **field_bounds("transport.n_cells"))
    model: Optional[Literal["lee2008", "sheehan2005_model1", "sheehan2005_model2", "ajayi2011"]] = None
    n_flights: Optional[int] = Field(default=None, ge=2, le=MAX_FLIGHTS)
    s1: Optional[float] = Field(default=None, gt=0, description="m, flight base")
    s2: Optional[float] = Field(default=None, ge=0, description="m, flight tip")
    alpha1: Optional[float] = Field(default=None, gt=0, lt=180, description="deg")
    alpha2: Optional[float] = Field(default=None, gt=0, lt=180, description="deg")
    segments: Optional[list[FlightSection]] = Field(default=None, min_length=1, max_length=MAX_SEGMENTS, description=(
        "this section's flights of any shape, as flight.segments (replaces the [flight] and s1..alpha2)"))
    vertices: Optional[list[FlightVertex]] = Field(default=None, min_length=2, max_length=MAX_SEGMENTS + 1, description=(
        "this section's flights of any shape, as flight.vertices"))
    area_factor: float = Field(default=1.0, ge=0, description="exposed-area factor of the heat/mass transfer")
    particle_diameter: Optional[float] = Field(default=None, gt=0, description="m; default the material's")
    shell_temperature: Optional[float] = Field(default=None, gt=-40, lt=600, description="degC (thermal.mode = ajayi2011)")
    regression: Optional[dict[str, list[float]]] = Field(default=None, description="Ajayi (2011) Appendix F coefficients: area (7) and fall_time (11), geometry.method = ajayi2011_regressions")


class DryerTracer(_TracerSource):
    fraction: float = Field(default=1e-4, gt=0, description="kg tracer per kg feed during the pulse")
    duration: float = Field(default=60.0, ge=0, description="s")
    t_end: float = Field(default=7200.0, gt=0, description="s")
    dt: float = Field(default=10.0, gt=0, description="s")


#: shipped sieve analyses of ``[particle_size] dataset``: name -> column of lee_particle_size_distribution.csv
PSD_DATASETS = {"lee2008_filter_sand": "filter_sand_wt_pct_passing", "lee2008_zeolite": "zeolite_wt_pct_passing",
                "lee2008_fine_river_sand": "fine_river_sand_wt_pct_passing"}


class ParticleSize(_Strict):
    """The feed's particle size distribution, cut into size classes (rotarydryer.properties.psd): a
    shipped sieve analysis (``dataset``), a sieve table (``sieve_m``, ``passing_pct``) or a named
    distribution; without this block the model has one class of the material's diameter."""
    classes: int = Field(default=5, **field_bounds("particle_size.classes"), description="equal-mass size classes")
    dataset: Optional[str] = Field(default=None, description="shipped sieve analysis: " + ", ".join(PSD_DATASETS)
                                   + " (Lee (2008) Table 5.3)")
    sieve_m: Optional[list[float]] = Field(default=None, max_length=100, description="sieve openings, m, ascending")
    passing_pct: Optional[list[float]] = Field(default=None, max_length=100, description="cumulative mass % passing "
                                               "each sieve (non-decreasing, 100 at the coarsest)")
    distribution: Optional[Literal["rosin_rammler", "lognormal"]] = Field(default=None, description="a named "
                                                                          "distribution in place of sieve data")
    d63: Optional[float] = Field(default=None, **field_bounds("particle_size.d63"), description="m, Rosin-Rammler size")
    spread: Optional[float] = Field(default=None, **field_bounds("particle_size.spread"), description="Rosin-Rammler n")
    d50: Optional[float] = Field(default=None, **field_bounds("particle_size.d50"), description="m, log-normal median")
    sigma_g: Optional[float] = Field(default=None, **field_bounds("particle_size.sigma_g"),
                                     description="log-normal geometric standard deviation")
    entrainment: bool = Field(default=True, description="the gas carries fines out of the curtains (dust) where it "
                                                        "is faster than their terminal velocity")

    @model_validator(mode="after")
    def _one_source(self):
        given = [k for k, v in (("dataset", self.dataset), ("sieve_m", self.sieve_m),
                                ("distribution", self.distribution)) if v is not None]
        if len(given) != 1:
            raise ValueError(f"give one of particle_size.dataset, particle_size.sieve_m (with passing_pct) or "
                             f"particle_size.distribution (got {', '.join(given) or 'none'})")
        if self.dataset is not None and self.dataset not in PSD_DATASETS:
            raise ValueError(f"particle_size.dataset = {self.dataset!r} is not one of {', '.join(PSD_DATASETS)}")
        if (self.sieve_m is None) != (self.passing_pct is None):
            raise ValueError("particle_size.sieve_m and particle_size.passing_pct go together")
        need = {"rosin_rammler": ("d63", "spread"), "lognormal": ("d50", "sigma_g")}.get(self.distribution or "", ())
        missing = [f"particle_size.{k}" for k in need if getattr(self, k) is None]
        if missing:
            raise ValueError(f"particle_size.distribution = {self.distribution!r} needs {', '.join(missing)}")
        return self


def _exhaust_problems(case) -> list[str]:
    """A [[tests]] row whose measured exhaust is hotter than both the gas entering the drum, measured in the same
    row, and the feed: nothing in a dryer heats the gas above both (a calibration drove that row's gas flow to
    1000 kg/s and ended with exit 0; found by review). A row without its own inlet temperature is not checked against
    the case's ``gas.inlet_temperature``: that may be a run's choice (``--set gas.inlet_temperature``), not a
    measurement."""
    out = []
    feed_t = case.operating.feed_temperature
    for r in case.tests:
        t_in = r.gas_inlet_temperature
        if r.gas_outlet_temperature is None or t_in is None:
            continue
        top = max(t_in, feed_t if feed_t is not None else -math.inf)
        if r.gas_outlet_temperature > top:
            out.append(f"tests.{r.test}.gas_outlet_temperature = {r.gas_outlet_temperature:g} degC is above the gas "
                       f"inlet temperature ({t_in:g} degC) and the feed's: no dryer heats its exhaust above both; check "
                       "the row's measurements")
    return out


class DryerCase(_Strict):
    """One schema for any flighted rotary dryer (``kind = "dryer"``)."""
    kind: Literal["dryer"]
    meta: Meta = Meta()
    drum: DryerDrum
    flight: Optional[DryerFlight] = None
    operating: DryerOperating
    material: Material
    transport: DryerTransport = DryerTransport()
    geometry: DryerGeometry = DryerGeometry()
    sections: list[DryerSection] = Field(max_length=MAX_ENTRIES)
    gas: Optional[Gas] = None
    shell: Shell = Shell()
    site: Site = Site()
    thermal: ThermalModel = ThermalModel()
    particle_size: Optional[ParticleSize] = None
    tracer: DryerTracer = DryerTracer()
    parameter_sets: list[ParameterSet] = Field(default=[], max_length=MAX_ENTRIES, description="fitted transport "
                                               "coefficients per transport.n_cells (e.g. Lee (2008) Table 7.2)")
    tests: list[OperatingTest] = Field(default=[], max_length=MAX_ENTRIES, description="measured operating points "
                                       "of the plant (operating.test selects one)")
    calibrations: list[CalibrationRecord] = Field(default=[], max_length=MAX_ENTRIES, description="fitted values "
                                                  "with the data and model configuration they hold for "
                                                  "(rotarydryer.cases.calibration)")

    @model_validator(mode="after")
    def _complete(self):
        problems = _operating_problems(self)
        if self.operating.test is not None and not any(t.test == self.operating.test for t in self.tests):
            raise ValueError(problems[0])      # what depends on the test (data set, gas) follows from it
        problem = _dataset_problem(self)
        if problem:
            problems.append(problem)
        keys = valid_override_keys(DryerCase)
        for i, rec in enumerate(self.calibrations):
            problems += record_problems(rec, keys, self.tests, f"calibrations[{i}] ({rec.name})", self.meta.title)
        rates = [f"transport.{k}" for k in _MODEL1_RATES if getattr(self.transport, k) is not None]
        models = {sec.model or self.transport.model for sec in self.sections if sec.kind == "flighted"}
        if rates and "sheehan2005_model1" not in models:
            problems.append(f"{', '.join(rates)} set but transport.model = {self.transport.model!r}: the rates are "
                            "those of transport.model = 'sheehan2005_model1'")
        if self.gas is not None and self.gas.feed_temperature is not None:
            problems.append(f"gas.feed_temperature = {self.gas.feed_temperature!r} is a key of the lee2008 format: give "
                            "operating.feed_temperature (degC) instead")
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
            if self.geometry.method == "ajayi2011_regressions":
                problems += regression_problems(where, sec)
                continue
            problem = _flight_problem(where, sec)
            if problem:
                problems.append(problem)
                continue
            if any(getattr(sec, k) is not None for k in POLYGON_KEYS):
                continue                                  # the section's own polygonal flight
            own = any(getattr(sec, k) is not None for k in TWO_SECTION_KEYS)
            if not own and self.flight is not None and any(getattr(self.flight, k) is not None for k in POLYGON_KEYS):
                continue                                  # the [flight] polygonal flight
            for key in TWO_SECTION_KEYS:
                if getattr(sec, key) is None and (self.flight is None or getattr(self.flight, key, None) is None):
                    problems.append(f"{where}.{key} is missing (and no [flight] default"
                                    f"{': [flight] gives a polygonal flight, a section that sets s1..alpha2 gives all four' if own and self.flight is not None and any(getattr(self.flight, k) is not None for k in POLYGON_KEYS) else ''})")
        if self.thermal.enabled:
            row = next((t for t in self.tests if t.test == self.operating.test), None)
            missing = (["gas"] if self.gas is None else
                       [f"gas.{k}" for k in ("flow", "inlet_temperature") if getattr(self.gas, k) is None
                        and getattr(row, f"gas_{k}", None) is None])      # or the selected test's
            if missing:
                problems.append(f"{' and '.join(missing)} {'is' if len(missing) == 1 else 'are'} missing: [gas] flow "
                                "and inlet_temperature are needed when thermal.enabled = true")
        problems += filter(None, [_length_problem(self), _cells_problem(self)])
        problems += _exhaust_problems(self)
        if problems:
            raise ValueError("; ".join(problems))
        return self


def regression_problems(where: str, sec) -> list[str]:
    """Ajayi (2011) Appendix F coefficients of a flighted section for geometry.method =
    'ajayi2011_regressions': 7 area and 11 fall-time coefficients."""
    reg = sec.regression or {}
    out = []
    for key, n in (("area", 7), ("fall_time", 11)):
        got = reg.get(key)
        if got is None or len(got) != n:
            out.append(f"{where}.regression.{key} = {got!r}: geometry.method = 'ajayi2011_regressions' needs {n} "
                       "coefficients")
    return out


def _operating_problems(case) -> list[str]:
    """The operating point is complete: ``operating.test`` names a [[tests]] row, and every one of
    feed_rate, rpm, feed_moisture is given or comes from that row."""
    op, out = case.operating, []
    row = None
    if op.test is not None:
        row = next((t for t in case.tests if t.test == op.test), None)
        if row is None:
            have = ", ".join(str(t.test) for t in case.tests) or "none"
            out.append(f"operating.test = {op.test} is not in the case's [[tests]] (tests: {have})")
            return out
    nums = [t.test for t in case.tests]
    if len(set(nums)) != len(nums):
        out.append(f"tests: test numbers {nums} are not unique")
    missing = [f"operating.{k}" for k in ("feed_rate", "rpm", "feed_moisture") if getattr(op, k) is None and row is None]
    if missing:
        out.append(f"{', '.join(missing)} {'is' if len(missing) == 1 else 'are'} missing (give {'it' if len(missing) == 1 else 'them'}, "
                   "or operating.test with a [[tests]] row)")
    return out


#: relative tolerance of drum.length against the sum of the section lengths
_LENGTH_RTOL = 1e-9


def _length_problem(case) -> str | None:
    """``drum.length``, when a sectioned case gives it, must equal the sum of its sections' lengths:
    one quantity, one value (the message names both keys)."""
    L = getattr(case.drum, "length", None)
    if L is None or not case.sections:
        return None
    total = sum(s.length for s in case.sections)
    if abs(total - L) <= _LENGTH_RTOL * max(L, total):
        return None
    parts = " + ".join(f"sections[{k}].length = {s.length:g}" for k, s in enumerate(case.sections))
    return (f"drum.length = {L:g} m disagrees with the sections' lengths ({parts} = {total:g} m): give drum.length "
            "equal to their sum, or leave it out (the sections set the length)")


def _cells_problem(case) -> str | None:
    """The total number of cells and finite volumes of a sectioned case (an auto-discretised
    unflighted section counts with its maximum) against `MAX_CELLS`."""
    total = thermal = 0
    tr = case.transport
    th_cells = case.thermal.unflighted_cells      # the heat-and-mass model's volumes (default: the transport's)
    for sec in case.sections:
        if sec.kind == "flighted":
            n = (sec.n_cells if sec.n_cells is not None else getattr(tr, "n_cells", None)) or 0
        else:
            n = sec.n_cells or tr.unflighted_cells or _AUTO_UNFLIGHTED_CELLS
        total += n
        thermal += th_cells.get(sec.name, n) if sec.kind == "unflighted" else n
    if max(total, thermal) > MAX_CELLS:
        return (f"sections: {max(total, thermal)} cells in all (n_cells of the flighted sections plus the finite "
                f"volumes of the unflighted ones, {_AUTO_UNFLIGHTED_CELLS} when automatic"
                f"{', thermal.unflighted_cells' if thermal > total else ''}); the limit is {MAX_CELLS}")
    return None


_NOT_OVERRIDABLE = {"kind", "meta", "parameter_sets", "sections", "tests", "calibrations"}


def list_cases() -> list[str]:
    """Names of the packaged cases."""
    return list(_packaged_cases())


@cache
def _packaged_cases() -> tuple[str, ...]:
    """`list_cases`, read from the package's data once per process (every case load asks it)."""
    return tuple(sorted(p.name[:-5] for p in resources.files(__package__).iterdir() if p.name.endswith(".toml")))


def valid_override_keys(case_cls) -> list[str]:
    """Flat ``section.key`` names that may be overridden for a case class."""
    return list(_override_keys(case_cls))


def override_key_type(case_cls, key: str):
    """The value type of override key ``key`` of a case class (``int``, ``float``, ``str``, ``bool``, a
    ``Literal`` or other annotation; ``Optional`` unwrapped), or None for a key it does not have."""

    node, out = case_cls, None
    for part in key.split("."):
        finfo = getattr(node, "model_fields", {}).get(part) if isinstance(node, type) else None
        if finfo is None:
            return None
        ann = finfo.annotation
        if typing.get_origin(ann) is typing.Union:
            ann = next((a for a in typing.get_args(ann) if a is not type(None)), ann)
        node = out = ann
    return out


def discrete_kind(case_cls, key: str) -> str | None:
    """What override key ``key`` of a case class takes where that is not a continuous number ("whole numbers",
    or "no continuous number" for text and choices), else None (a float key, or one the class does not have):
    a search over the key (target, fit, Sobol study) cannot sample it."""
    kind = override_key_type(case_cls, key)
    if kind is None or kind is float:
        return None
    return "whole numbers" if kind is int else "no continuous number"


@cache
def _override_keys(case_cls) -> tuple[str, ...]:
    """`valid_override_keys`, computed once per class (every case load needs them)."""

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
    return tuple(sorted(keys))


def _decode(content: bytes, shown: str) -> str:
    """UTF-8 text of a case file of at most `MAX_CASE_BYTES` bytes, else ``ValueError``."""
    if len(content) > MAX_CASE_BYTES:
        raise ValueError(f"{shown}: the case file is larger than the limit of {MAX_CASE_BYTES} bytes")
    try:
        return content.decode("utf-8-sig")     # a leading byte-order mark (Windows editors) is dropped
    except UnicodeDecodeError as exc:
        raise ValueError(f"{shown}: not UTF-8 text (byte 0x{content[exc.start]:02x} at offset {exc.start})") from None


def _source(name: str) -> tuple[str, str]:
    """(TOML text, display name) of a packaged case or a .toml path (a regular file of at most
    `MAX_CASE_BYTES` bytes)."""
    p = Path(name)
    if p.suffix == ".toml" and p.exists():
        if not p.is_file():
            raise ValueError(f"case = {name!r} is not a regular file")
        with open(p, "rb") as fh:
            content = fh.read(MAX_CASE_BYTES + 1)
        return _decode(content, str(p)), str(p)
    if name in list_cases():
        return (resources.files(__package__) / f"{name}.toml").read_text("utf-8"), f"{name}.toml"
    raise ValueError(f"case = {name!r} is not a packaged case ({', '.join(list_cases())}) nor a .toml file")


def _read(name: str) -> dict:
    return _parse(*_source(name))


def _parse(text: str, shown: str) -> dict:
    """The TOML document as a dict (a fresh copy: the caller applies its overrides to it)."""
    return copy.deepcopy(_parse_text(text, shown))


@lru_cache(maxsize=32)
def _parse_text(text: str, shown: str) -> dict:
    """``tomllib.loads`` remembered per text: the runs of a study or a sweep load one case many times."""
    try:
        return tomllib.loads(text.removeprefix("\ufeff"))     # a byte-order mark is not TOML: dropped
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{shown}: not valid TOML: {exc}") from None
    except RecursionError:   # deeply nested arrays/tables
        raise ValueError(f"{shown}: not valid TOML: nested too deeply") from None


def _shown_value(value, limit: int = 120) -> str:
    """``repr`` of an input value for a message, cut to ``limit`` characters."""
    r = repr(value)
    return r if len(r) <= limit else r[:limit] + " ..."


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


#: pydantic error types of a violated ge/gt/le/lt bound
_BOUND_ERRORS = frozenset({"greater_than", "greater_than_equal", "less_than", "less_than_equal", "finite_number"})
#: a value of another type where a number is wanted: its message gets the key's range too ("drum.n_flights = '2.5':
#: Input should be a valid integer" named none; found by an acceptance check)
_NUMBER_TYPE_ERRORS = frozenset({"int_parsing", "int_type", "int_from_float", "float_parsing", "float_type"})
#: the ranges of a polygonal flight's numbers (FlightSection, FlightVertex), by (list key, position in the pair)
_POLYLINE_RANGES = {("segments", 0): "(0, 100] m", ("segments", 1): "(0, 360) deg", ("vertices", 0): "[-100, 100] m",
                    ("vertices", 1): "[-100, 100] m"}
#: list entries whose fields are the values of case keys: ``parameter_sets[i].backmix`` is ``transport.backmix``
_ENTRY_KEYS = {"parameter_sets": "transport", "sections": "transport"}


def _limit_key(loc: tuple) -> str | None:
    """The `rotarydryer._limits.LIMITS` key of an error location, if it has one."""
    dotted = ".".join(str(x) for x in loc)
    if dotted in LIMITS:
        return dotted
    if len(loc) == 3 and loc[0] in _ENTRY_KEYS and isinstance(loc[1], int):
        key = f"{_ENTRY_KEYS[loc[0]]}.{loc[2]}"
        return key if key in LIMITS else None
    return None


def _model_in(annotation):
    """The case-schema model class inside a field's annotation (``Optional[Flight]``, ``list[Section]``), or None."""
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    for arg in get_args(annotation):
        found = _model_in(arg)
        if found is not None:
            return found
    return None


def _field_range(cls, loc: tuple) -> str | None:
    """The allowed range of the schema field at ``loc`` from its own bounds (``gt``/``ge``/``lt``/``le``), with
    the unit its description starts with (``"m, flight base"``): for a bounded field without a `LIMITS` entry
    (``flight.s1 = -1`` said "Input should be greater than 0", not the interval and its unit)."""
    info = None
    for part in loc:
        if isinstance(part, int):       # an entry of a list: its model's fields follow
            continue
        fields = getattr(cls, "model_fields", None)
        if not fields or part not in fields:
            return None
        info = fields[part]
        cls = _model_in(info.annotation)
    if info is None:
        return None
    low, high, low_in, high_in = -math.inf, math.inf, False, False
    for m in info.metadata:
        if getattr(m, "gt", None) is not None:
            low, low_in = float(m.gt), False
        if getattr(m, "ge", None) is not None:
            low, low_in = float(m.ge), True
        if getattr(m, "lt", None) is not None:
            high, high_in = float(m.lt), False
        if getattr(m, "le", None) is not None:
            high, high_in = float(m.le), True
    if low == -math.inf and high == math.inf:
        return None
    head = re.split(r"[,;]", info.description or "")[0].strip()
    unit = head if head in _FIELD_UNITS else ""         # a symbol (u_s, C_B) is not a unit
    return _interval(low, high, low_in, high_in, unit)


def _problem_where(loc: tuple, text: str, shown: str, overrides: dict | None) -> str:
    """Where a problem at case key ``loc`` was given: the ``--set`` options at, below or above it (a list's item:
    ``--set flight.segments=[...]`` for ``flight.segments.1.0``), else the file's line (``shown:line``), else the
    file."""
    named = ".".join(str(x) for x in loc)
    below = [k for k in overrides or {} if k == named or (named and (k.startswith(named + ".")
                                                                     or named.startswith(k + ".")))]
    if below:
        return "--set " + ", --set ".join(below)
    no = _toml_line(text, loc) if text and loc else None
    return f"{shown}:{no}" if no else shown


def _shown_loc(loc: tuple, raw: dict) -> tuple:
    """The location as a person names it: a ``[[tests]]`` row by its test number, as the calibration keys
    (``tests.2.product_moisture`` is test 2's; the list index named test 2 ``tests.1``), else as pydantic gives it."""
    if len(loc) >= 2 and loc[0] == "tests" and isinstance(loc[1], int):
        rows = raw.get("tests") if isinstance(raw, dict) else None
        row = rows[loc[1]] if isinstance(rows, list) and loc[1] < len(rows) else None
        test = row.get("test") if isinstance(row, dict) else None
        if isinstance(test, int) and not isinstance(test, bool) and \
                sum(isinstance(r, dict) and r.get("test") == test for r in rows) == 1:
            return ("tests", test, *loc[2:])
    return loc


def _format_validation_error(exc: ValidationError, raw: dict, text: str = "", shown: str = "",
                             overrides: dict | None = None, cls=None) -> str:
    """One line per problem: ``file:line: field = value: message (allowed ...)``."""
    lines = []
    for e in exc.errors():
        loc = tuple(e["loc"])
        dotted = ".".join(str(x) for x in _shown_loc(loc, raw))
        kind = e.get("type", "")
        text_msg = e["msg"].removeprefix("Value error, ")
        if not loc:   # a check of the whole case: locate the key its message starts with
            m = re.match(r"([A-Za-z_]\w*(?:\.[A-Za-z_]\w*)+) = ", text_msg)
            loc = tuple(m.group(1).split(".")) if m else loc
        where = _problem_where(loc, text, shown, overrides)
        if kind == "missing":
            msg = f"{dotted} is missing (a required field or section)"
        elif kind == "extra_forbidden":
            msg = f"{dotted} is not a known field here"
        elif kind == "value_error" and (not loc or isinstance(e.get("input"), dict)):
            msg = text_msg  # a check of a whole block or case: its message names the keys
        elif kind == "value_error":
            msg = f"{dotted} = {_shown_value(e.get('input'))} {text_msg}"
        else:
            msg = f"{dotted} = {_shown_value(e.get('input'))}: {e['msg']}"
            ranged = kind in _BOUND_ERRORS or kind in _NUMBER_TYPE_ERRORS     # the range where a number was wanted
            limit = _limit_key(loc) if ranged else None
            polyline = (_POLYLINE_RANGES.get((loc[-3], loc[-1])) if ranged and len(loc) >= 3
                        and isinstance(loc[-2], int) else None)
            field = (_field_range(cls, loc) if cls is not None and limit is None and polyline is None
                     and ranged else None)
            if limit is not None:        # the whole interval, as the runtime checks quote it (docs/errors.md)
                msg += f" (allowed range {describe_limit(limit)})"
            elif polyline is not None:   # a polygonal flight's section length or angle, a vertex coordinate
                msg += f" (allowed range {polyline})"
            elif field is not None:      # the schema field's own bounds
                msg += f" (allowed range {field})"
        lines.append(f"{where}: {msg}")
    return "\n".join(lines)


def load_case_text(text: str | bytes, name: str = "uploaded case", overrides: dict[str, Any] | None = None):
    """Validate a case given as TOML text (or UTF-8 bytes), e.g. a case file uploaded to the
    web app: nothing is written to or read from disk except the shipped data the case names.
    ``name`` is the display name in messages. Same checks and result as `load_case`."""
    if isinstance(text, (bytes, bytearray)):
        text = _decode(bytes(text), name)
    elif len(text.encode("utf-8", "surrogatepass")) > MAX_CASE_BYTES:
        raise ValueError(f"{name}: the case file is larger than the limit of {MAX_CASE_BYTES} bytes")
    return _validate(text, name, name, overrides)


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
    DryerCase (pydantic model, SI units): the one specification; files of the plant formats
    (``kind = "lee2008"``, ``"ajayi2011"``) are translated by `rotarydryer.cases.readers`.
    """
    text, shown = _source(name)
    return _validate(text, shown, name, overrides)


def _validate(text: str, shown: str, name: str, overrides: dict[str, Any] | None):
    raw = dict(_parse_text(text, shown))     # copied where the overrides write (below), not whole
    kind = raw.get("kind")
    if not isinstance(kind, str) or kind not in CASE_KINDS:
        raise ValueError(f"{shown}: kind = {_shown_value(kind)} is not one of {', '.join(map(repr, CASE_KINDS))}")
    cls, reader = (DryerCase, None) if kind == "dryer" else _plant_format(kind)
    if isinstance(raw.get("material"), str):
        raw["material"] = {"name": raw["material"]}
    valid = valid_override_keys(cls)
    if reader is None:      # the one specification: keys of the old formats map to their replacements
        overrides = translate_legacy_overrides(overrides, valid)
    case = _validated(cls, raw, valid, text, shown, name, overrides)
    if reader is None:
        for msg in unused_keys(case, overrides or ()):     # a value that would change nothing, said once at load
            warnings.warn(f"{shown}: {msg}", UnusedKeyWarning, stacklevel=3)
        return case
    try:       # a plant format: its reader translates it into the one specification
        spec = reader(case)
    except ValueError as exc:
        raise ValueError(_invalid(name, f"{shown}: {exc}", 1)) from None
    try:
        return DryerCase.model_validate(spec)
    except ValidationError as exc:
        n = len(exc.errors())
        details = _format_validation_error(exc, spec, "", shown, overrides, DryerCase)
        raise ValueError(_invalid(name, details, n)) from None


def _test_slope(raw, overrides):
    """The selected [[tests]] row's ``slope`` is the run's ``drum.slope`` (a ``--set drum.slope`` wins)."""
    op, tests = raw.get("operating"), raw.get("tests")
    if not isinstance(op, dict) or not isinstance(tests, list) or op.get("test") is None:
        return
    if overrides and "drum.slope" in overrides:
        return
    want = str(op.get("test")).strip()
    row = next((r for r in tests if isinstance(r, dict) and str(r.get("test")) == want), None)
    if row is not None and row.get("slope") is not None and isinstance(raw.get("drum"), dict):
        raw["drum"] = {**raw["drum"], "slope": row["slope"]}


def _invalid(name, details: str, n: int) -> str:
    """The message of an invalid case with ``n`` problems (``details``: a line each, and perhaps a note): one line
    for one problem, else their count and a line per problem."""
    if n == 1:
        return f"invalid case {name!r}: " + " ".join(details.splitlines())
    return f"invalid case {name!r} ({n} problems):\n{details}"


def _none_override(value) -> bool:
    """An override value that removes its key: None, or the text none / null / empty (any case, spaces around)."""
    return value is None or (isinstance(value, str) and value.strip().lower() in ("none", "null", ""))


def _validated(cls, raw, valid, text, shown, name, overrides):
    file_raw = dict(raw)      # the file's values: the overrides below copy what they change
    for key, value in (overrides or {}).items():
        if key not in valid and not key.startswith("material."):
            raise ValueError(f"unknown override key {key!r} for case {name!r}; valid keys: {', '.join(valid)}, "
                             "material.<field> (any field of the material)")
        *path, fld = key.split(".")
        if isinstance(value, bool) and key in LIMITS:     # a number's key: True would read as 1.0
            raise ValueError(f"--set {key}: {key} = {value!r} is not a number (allowed range "
                             f"{describe_limit(key)})")
        if _none_override(value):
            value = None
        elif isinstance(value, str) and key.startswith("material.") and key != "material.name":
            value = override_value(value)      # material fields are free-form: read "0.0006" as TOML would
        elif isinstance(value, str) and value.strip().startswith("[") and value.strip().endswith("]"):
            value = override_value(value)      # a list from the command line ("[1e-4, 2e-4]"), read as TOML
        node = raw
        for part in path:       # copy on write: the parsed document is shared by every load of the text
            nxt = node.get(part)
            nxt = node[part] = dict(nxt) if isinstance(nxt, dict) else {}
            node = nxt
        # a block or list given as a value (``{"gas.burner": {...}}`` from Python) is copied: the document holds no
        # object of the caller's, which could change between loads (`_MISREAD_MEMO` remembers blocks by identity)
        node[fld] = copy.deepcopy(value) if isinstance(value, (dict, list)) else value
        prefix = ".".join(path)
        whole = fld in POLYGON_KEYS or (fld in TWO_SECTION_KEYS and all(
            f"{prefix}.{k}" in overrides and not _none_override(overrides[f"{prefix}.{k}"]) for k in TWO_SECTION_KEYS))
        if value is not None and whole:
            # a whole flight given one way (a polygon key, or all four of s1..alpha2) replaces the file's other way
            # (``--set flight.segments=[...]`` on a case with s1..alpha2 was refused as "both given", and only four
            # more --set ...=none made it run; found by an acceptance check); what the overrides give themselves
            # stays, and is refused if it conflicts; one two-section key alone is a change of the file's flight
            others = [k for k in (POLYGON_KEYS if fld in TWO_SECTION_KEYS else (*TWO_SECTION_KEYS, *POLYGON_KEYS))
                      if k != fld]
            for other in others:
                if other in node and f"{prefix}.{other}" not in overrides:
                    del node[other]
    pending: list[str] = []          # the calibrations' warnings, issued once the case validates
    if raw.get("calibrations") and cls is DryerCase:
        _calibrate(raw, overrides, shown, file_raw, pending)
    _test_slope(raw, overrides)
    for key, fld in (("gas.flow", "gas_flow"), ("gas.inlet_temperature", "gas_inlet_temperature")):
        if overrides and key in overrides and isinstance(raw.get("tests"), list):
            # a --set gas.flow (gas.inlet_temperature) is this run's: it wins over the selected test's (a
            # row's value otherwise replaces the case's)
            raw["tests"] = [{**r, fld: None} if isinstance(r, dict) else r for r in raw["tests"]]
    origin = raw.pop("__calibrated__", {})
    booleans = _boolean_numbers(cls, raw)
    if booleans:
        lines = [f"{_problem_where(loc, text, shown, overrides)}: {'.'.join(str(x) for x in loc)} = "
                 f"{_shown_value(value)} holds a boolean (true/false) where a number is expected"
                 for loc, value in booleans]
        raise ValueError(_invalid(name, "\n".join(lines), len(lines)))
    texts = [(loc, value) for loc, value in _text_numbers(cls, file_raw)
             if not any(k == ".".join(map(str, loc)) or k.startswith(".".join(map(str, loc)) + ".")
                        for k in overrides or {})]
    if texts:
        lines = [f"{_problem_where(loc, text, shown, None)}: {'.'.join(str(x) for x in loc)} = "
                 f"{_shown_value(value)} is a text (a quoted TOML string) where a number is expected: write the "
                 "number without quotes" for loc, value in texts]
        raise ValueError(_invalid(name, "\n".join(lines), len(lines)))
    try:
        case = cls.model_validate(raw)
    except ValidationError as exc:
        n = len(exc.errors())
        details = _format_validation_error(exc, raw, text, shown, overrides, cls)
        locs = {".".join(str(p) for p in e["loc"]) for e in exc.errors()}
        from_records = sorted({f"{k} from calibration {origin[k]!r}" for k in origin
                               if k in locs or any(loc.startswith(k + ".") for loc in locs)})
        if from_records:
            details += "\n(" + "; ".join(from_records) + ")"
        raise ValueError(_invalid(name, details, n)) from None
    for message in pending:
        warnings.warn(message, CalibrationWarning, stacklevel=2)
    return case


@lru_cache(maxsize=4096)
def _schema_default(cls, key: str):
    """The default of case key ``key`` (``geometry.method``) in schema ``cls``; None where a block is optional.
    Remembered (the schema does not change; a default built by pydantic's factories costs a deep copy
    of its block, and every case load compares its calibrations' configurations with them)."""
    first, *rest = key.split(".")
    finfo = cls.model_fields.get(first)
    value = None if finfo is None else finfo.get_default(call_default_factory=True)
    for part in rest:
        value = getattr(value, part, None)
    return value


def case_calibrations(case) -> list[CalibrationRecord]:
    """The ``[[calibrations]]`` records that apply to a validated case (one of each group of records
    setting overlapping keys; `rotarydryer.cases.calibration`)."""
    return applied_calibrations(case, lambda key: _schema_default(DryerCase, key))


def _calibrate(raw: dict, overrides, shown: str, file_raw: dict | None = None, pending: list | None = None) -> None:
    """Apply the case's [[calibrations]] to ``raw`` (`rotarydryer.cases.calibration.apply_calibrations`);
    a malformed record is refused naming its entry and key."""
    recs = raw.get("calibrations")
    if not isinstance(recs, list):
        raise ValueError(f"{shown}: calibrations must be an array of tables ([[calibrations]])")
    rows = raw.get("tests") if isinstance(raw.get("tests"), list) else []
    title = (raw.get("meta") or {}).get("title", "") if isinstance(raw.get("meta"), dict) else ""
    key = (id(recs), id(rows), title, shown)
    hit = _RECORDS_MEMO.get(key)
    if hit is not None and hit[0] is recs and hit[1] is rows:
        records = hit[2]
    else:
        records = _checked_records(recs, rows, title, shown)
        if len(_RECORDS_MEMO) >= 8:
            _RECORDS_MEMO.pop(next(iter(_RECORDS_MEMO)))
        _RECORDS_MEMO[key] = (recs, rows, records)
    apply_calibrations(raw, overrides, lambda key: _schema_default(DryerCase, key), shown, file_raw,
                       records=records, pending=pending)


#: the checked records of the last few parsed documents: (records list, tests rows, checked records)
#: by their identities (the parsed document is shared by every load of one text and never written:
#: the overrides copy what they change), so a study's runs check a case's records once
_RECORDS_MEMO: dict = {}


def _checked_records(recs: list, rows: list, title: str, shown: str) -> list[CalibrationRecord]:
    """The validated ``[[calibrations]]`` records, each checked against the case (`record_problems`);
    a malformed or misplaced record is refused naming its entry and key."""
    keys = valid_override_keys(DryerCase)
    out = []
    for i, rec in enumerate(recs):
        try:
            r = CalibrationRecord.model_validate(rec)
        except ValidationError as exc:
            err = exc.errors()[0]
            loc = ".".join(str(p) for p in err["loc"])
            raise ValueError(f"{shown}: calibrations[{i}].{loc}: {err['msg']} ({len(exc.errors())} problem"
                             f"{'s' if len(exc.errors()) > 1 else ''})") from None
        problems = record_problems(r, keys, [t for t in rows if isinstance(t, dict)],
                                   f"calibrations[{i}] ({r.name})", title)
        if problems:             # before any value is written: the record, not the case, is at fault
            raise ValueError(f"{shown}: " + "; ".join(problems))
        out.append(r)
    return out


def override_value(text: str):
    """A --set value as its TOML literal (number, boolean, array, quoted string), else the text
    (``"4"`` -> 4, ``"1e3"`` -> 1000.0, ``"lee2008"`` -> ``"lee2008"``)."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except (tomllib.TOMLDecodeError, ValueError):
        return text


def has_tracer_curve(case) -> bool:
    """Does the case have a measured tracer curve (``tracer.dataset`` or ``tracer.measured``)? Its tests' measured
    mean residence times (``mrt_measured_min``) are then the curve's mean from the injection start, which a model
    gives as its tracer curve's mean (with the pulse); without a curve they are a residence time holdup / feed
    (Song's step method), the model's ``mean_residence_time``. `rotarydryer validate` and `rotarydryer calibrate
    -r mrt` compare the same quantity."""
    tr = getattr(case, "tracer", None)
    return getattr(tr, "dataset", None) is not None or getattr(tr, "measured", None) is not None


def measured_rtd(case):
    """Measured tracer curve of a case as (time s since injection start, signal), or None.

    Uses the shipped dataset of [`rotarydryer.rtd`][rotarydryer.rtd] (``tracer.dataset``; ``{test}`` is
    replaced by ``operating.test``) when available, else the CSV named by
    ``tracer.measured``.  The signal is E(t) in 1/s for a normalised curve (Lee), else
    the raw concentration (Ajayi: ppm, no baseline subtraction); normalise by its
    integral (see `measured_rtd_moments`)."""
    import numpy as np

    tr = case.tracer
    if getattr(tr, "dataset", None) is not None:
        from rotarydryer.rtd import load_tracer_dataset

        # plain text replacement: a case's string is never a format string
        d = load_tracer_dataset(resolve_dataset(tr.dataset, getattr(case.operating, "test", "")))
        t = np.asarray(d.time_s, float) - d.time_origin_s
        y = np.asarray(d.signal, float) * (d.rate_factor or 1.0)
        keep = t >= 0
        return t[keep], y[keep]
    if getattr(tr, "measured", None) is None:
        return None
    import csv

    _check_measured(tr.measured)  # a bare name of a shipped CSV (also when the case was built in code)
    text = resources.files("rotarydryer.data").joinpath(tr.measured).read_text("utf-8")
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
    (``tracer.baseline``), by [`rotarydryer.rtd.rtd_moments`][rotarydryer.rtd.rtd_moments]. Returns a dict or None."""
    data = measured_rtd(case)
    if data is None:
        return None
    from rotarydryer.rtd import rtd_moments

    t, y = data
    m = rtd_moments(t, y, baseline=case.tracer.baseline)
    return {"mean_s": m.mean_s, "std_s": m.std_s, "baseline": m.baseline, "baseline_method": m.baseline_method,
            "tail_truncated": m.tail_truncated}


def measured_exit_age(case):
    """The case's measured tracer curve as E(t): (time s since injection start, E 1/s) with the
    case's baseline removed (`measured_rtd_moments`), clipped at 0 and normalised by its
    area over the measured window; None without a measured curve. The curve every model-data
    comparison of E(t) uses (R^2 of the report, the calibration, the validation suite)."""
    data = measured_rtd(case)
    if data is None:
        return None
    import numpy as np

    from rotarydryer.rtd import rtd_moments

    t, y = data
    m = rtd_moments(t, y, baseline=case.tracer.baseline)
    return np.asarray(t, float), np.clip(np.asarray(y, float) - m.baseline, 0.0, None) / m.area


def exit_age_r_squared(e_measured, e_model) -> float:
    """1 - SSR/SST of a model E(t) against the measured E(t) at the same times (unweighted)."""
    import numpy as np

    y, f = np.asarray(e_measured, float), np.asarray(e_model, float)
    return 1.0 - float(np.sum((y - f) ** 2)) / float(np.sum((y - y.mean()) ** 2))


#: the one internal specification (``kind = "dryer"``)
DryerSpec = DryerCase

from .build import UnusedKeyWarning, build_model, lee_parameters, unused_keys  # noqa: E402, F401  (the builders read the classes above)
from .legacy_keys import translate_legacy_overrides  # noqa: E402

#: the ``kind`` of a case file: the one specification and the thesis formats read into it
#: (`rotarydryer.cases.readers`, loaded when a file of one is read)
CASE_KINDS = ("dryer", "lee2008", "ajayi2011")
#: names of `rotarydryer.cases.readers` this package still offers (``from rotarydryer.cases import LeeCase``)
_READER_NAMES = frozenset({"lee2008_to_spec", "ajayi2011_to_spec", "LEGACY_KEYS", "check_lee2008", "LeeCase",
                           "AjayiCase", "SCHEMAS", "READERS"})


def _plant_format(kind: str):
    """``(schema, reader)`` of a thesis format's ``kind``; its module loads here, on the first file of one."""
    from .readers import READERS, SCHEMAS

    return SCHEMAS[kind], READERS[kind]


def __getattr__(name: str):
    """`CASE_MODELS` (case model of each ``kind``) and the readers' names, on first use (PEP 562)."""
    if name == "CASE_MODELS":
        from .readers import SCHEMAS

        value = {"dryer": DryerCase, **SCHEMAS}
    elif name in _READER_NAMES:
        from . import readers

        value = getattr(readers, name)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value         # one object from now on (a plain attribute: this hook is not called again)
    return value

"""Validation suite: every case against every measured or published number it has.

Each number is compared with the model against a tolerance written *before* the run in a data
file, ``rotarydryer/data/validation.toml``, with its kind, its reason and its source:

* items **derived from case data** (any case, a user's too): for each ``[[tests]]`` row, run with
  ``operating.test`` set to it, the tracer mean against ``mrt_measured_min``, R^2 of E(t) against
  the test's measured tracer curve, the total holdup against ``holdup_measured_kg`` and, where the
  case has heat and mass transfer, the product moisture, gas outlet and product temperatures
  against the row's measurements, with the energy balance error of the coupled state; a case
  without ``[[tests]]`` its measured tracer curve (mean and R^2). Their tolerances are the
  ``[defaults]`` of the data file;
* **published numbers** of the shipped cases (``[[items]]``): thesis tables and figures,
  reproductions of the theses' own models in their configuration, each with its overrides.

An item whose ``known_miss`` is set is listed with its figure and reason but does not fail the
run (it shows "pass" when it meets its tolerance). Overrides given to `run_validation`
apply on top of every item's own (how a test perturbs a calibration).

>>> spec = load_tolerances()                                # the shipped tolerances, checked
>>> spec.defaults["r_squared"].tolerance, spec.defaults["r_squared"].kind
(0.95, 'minimum')
>>> report = run_validation(["song2003_ottawa"])            # doctest: +SKIP
>>> report.passed, report.summary()["n_items"]              # doctest: +SKIP

Pure library code: nothing is printed; ``progress`` (a callable taking one line) reports what runs.
The command line is ``rotarydryer validate``; the docs page ``docs/validation.md`` is written by
``examples/validation_page.py``.
"""

from __future__ import annotations

import functools
import json
import math
import time
import tomllib
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any, Literal, Optional, Union

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from . import _jit
from ._display import UNIT_QUANTITIES, show, show_delta
from .cases import has_tracer_curve, list_cases, load_case, measured_rtd_moments
from .cases.build import build_model, rows_shadowed, thermal_enabled
from .published import read_published_csv
from .results import rtd_comparison
from .simulation import Simulation

__all__ = ["run_validation", "load_tolerances", "ValidationItem", "ValidationReport", "ValidationSpec",
           "TOLERANCE_KINDS", "STATUSES", "DERIVED_QUANTITIES", "METRICS", "TOLERANCES_FILE"]

#: how a tolerance is applied: |model - measured| <= t, |model / measured - 1| <= t, model >= t, model <= t
TOLERANCE_KINDS = ("absolute", "relative", "minimum", "maximum")
#: status of an item ("known miss": outside its tolerance, listed with its reason, not a failure)
STATUSES = ("pass", "fail", "known miss")
#: the shipped tolerances file (package data)
TOLERANCES_FILE = "validation.toml"

#: quantities of the items derived from case data -> unit of the values
DERIVED_QUANTITIES = {
    "tracer_mean": "min",             # model tracer mean against the test row's mrt_measured_min
    "mean_residence_time": "min",     # holdup / flow against mrt_measured_min (a row without a tracer curve)
    "curve_mean": "min",              # model tracer mean against the mean of the measured curve
    "r_squared": "-",                 # E(t) against the measured curve
    "holdup": "kg",                   # total holdup against holdup_measured_kg
    "product_moisture": "kg/kg",      # wet basis
    "gas_outlet_temperature": "degC",
    "product_temperature": "degC",
    "product_d50": "m",               # mass-median diameter of the product (a case with [particle_size])
    "dust_rate": "kg/s",              # solids and water carried to the exhaust (a case with [particle_size])
    "energy_balance_error": "-",      # relative error of the coupled steady state
}

_DERIVED_TEXT = {
    "tracer_mean": "tracer mean residence time",
    "mean_residence_time": "mean residence time (holdup / flow)",
    "curve_mean": "tracer mean residence time against the measured curve's mean",
    "r_squared": "R^2 of the tracer E(t) against the measured curve",
    "holdup": "total holdup",
    "product_moisture": "product moisture (wet basis)",
    "gas_outlet_temperature": "gas outlet temperature",
    "product_temperature": "product temperature",
    "product_d50": "product d50 (mass median diameter)",
    "dust_rate": "dust rate to the exhaust",
    "energy_balance_error": "energy balance error of the coupled steady state",
}

_THERMAL_FIELDS = {"product_moisture": "product_moisture", "gas_outlet_temperature": "gas_outlet_temperature",
                   "product_temperature": "product_temperature", "product_d50": "product_d50", "dust_rate": "dust_rate"}


# ---------------------------------------------------------------------------------- data file
class _Entry(BaseModel):
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)


_Value = Union[bool, int, float, str, dict[str, Union[bool, int, float, str]]]


class Tolerance(_Entry):
    """A tolerance with its kind, the reason for its size and where the number comes from."""
    tolerance: float = Field(ge=0)
    kind: Literal["absolute", "relative", "minimum", "maximum"]
    reason: str = Field(min_length=1, max_length=4000)
    source: str = Field(min_length=1, max_length=2000)


class DefaultTolerance(Tolerance):
    """``[defaults.<quantity>]``: the tolerance of every derived item of that quantity."""
    description: str = Field(min_length=1, max_length=400)
    unit: str = Field(max_length=40)


class DerivedEntry(_Entry):
    """``[[derived]]``: a note on one derived item (by its id), e.g. a known miss with its figure."""
    id: str = Field(min_length=1, max_length=200)
    known_miss: str = Field(min_length=1, max_length=4000)


class TestSetting(_Entry):
    """``[[test_settings]]``: how one [[tests]] row of a shipped case runs (extra overrides,
    thermal items or not), with the reason."""
    case: str = Field(min_length=1)
    test: int
    overrides: dict[str, _Value] = {}
    thermal: bool = True
    reason: str = Field(min_length=1, max_length=4000)
    source: str = Field(min_length=1, max_length=2000)


class PublishedItem(Tolerance):
    """``[[items]]``: one published number of a shipped case."""
    id: str = Field(min_length=1, max_length=200)
    case: str = Field(min_length=1)
    description: str = Field(min_length=1, max_length=400)
    quantity: str = Field(min_length=1, description="a key of METRICS: what the model computes")
    unit: str = Field(max_length=40)
    measured: Optional[float] = None
    overrides: dict[str, _Value] = {}
    data: Optional[str] = Field(default=None, description="shipped CSV the metric reads (profiles)")
    params: dict[str, Union[int, float, str]] = {}
    known_miss: Optional[str] = Field(default=None, min_length=1, max_length=4000)

    @model_validator(mode="after")
    def _consistent(self):
        metric = METRICS.get(self.quantity)
        if metric is None:
            raise ValueError(f"quantity = {self.quantity!r} is not a metric; allowed: {', '.join(METRICS)}")
        if self.unit != metric[1]:
            raise ValueError(f"unit = {self.unit!r}: quantity {self.quantity!r} is computed in {metric[1]!r}")
        if self.kind in ("absolute", "relative") and self.measured is None:
            raise ValueError(f"kind = {self.kind!r} needs measured (the published number)")
        if self.kind in ("minimum", "maximum") and self.measured is not None:
            raise ValueError(f"kind = {self.kind!r} is a bound on the model value: give no measured")
        if self.kind == "relative" and self.measured == 0:
            raise ValueError("kind = 'relative' with measured = 0")
        return self


class ValidationSpec(_Entry):
    """The tolerances file: ``[defaults]``, ``[[test_settings]]``, ``[[derived]]``, ``[[items]]``."""
    format: Literal[1] = 1
    title: str = ""
    defaults: dict[str, DefaultTolerance]
    test_settings: list[TestSetting] = []
    derived: list[DerivedEntry] = []
    items: list[PublishedItem] = []

    @model_validator(mode="after")
    def _complete(self):
        missing = sorted(set(DERIVED_QUANTITIES) - set(self.defaults))
        unknown = sorted(set(self.defaults) - set(DERIVED_QUANTITIES))
        if missing or unknown:
            raise ValueError(f"defaults: missing {missing}, unknown {unknown}; the quantities are "
                             f"{', '.join(DERIVED_QUANTITIES)}")
        for key, d in self.defaults.items():
            if d.unit != DERIVED_QUANTITIES[key]:
                raise ValueError(f"defaults.{key}.unit = {d.unit!r}: the values are in {DERIVED_QUANTITIES[key]!r}")
            if d.kind in ("relative", "absolute") and key == "r_squared":
                raise ValueError("defaults.r_squared: kind must be 'minimum'")
        ids = [i.id for i in self.items] + [d.id for d in self.derived]
        dup = sorted({i for i in ids if ids.count(i) > 1})
        if dup:
            raise ValueError(f"ids given twice: {', '.join(dup)}")
        return self


def load_tolerances(path=None) -> ValidationSpec:
    """The tolerances file (default the shipped ``rotarydryer/data/validation.toml``), checked:
    ``ValueError`` naming the file and the entry when it is malformed. A file of the user's (``path``) is laid over
    the shipped one: each of its ``[defaults.<quantity>]`` tables replaces the fields it gives of that quantity's
    (``tolerance``, ``kind``, ``reason`` ...; the others stay the shipped ones), its ``[[derived]]`` and ``[[items]]``
    are added, and a complete file (every quantity, as the shipped one) is that file alone. A user's own dryer is
    judged by tolerances of its own measurements, not by those written for MMG (found by review)."""
    shipped = resources.files("rotarydryer.data").joinpath(TOLERANCES_FILE).read_text("utf-8")
    if path is None:
        text, shown = shipped, TOLERANCES_FILE
    else:
        p = Path(path)
        if not p.is_file():
            raise ValueError(f"tolerances file {str(p)!r} is not a file")
        text, shown = p.read_text("utf-8-sig"), str(p)      # a byte-order mark is dropped
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{shown}: not valid TOML: {exc}") from None
    given = raw.get("defaults") or {}
    if not isinstance(given, dict):
        raise ValueError(f"{shown}: defaults must be a table of [defaults.<quantity>] tables")
    if path is not None and not set(DERIVED_QUANTITIES) <= set(given):
        base = tomllib.loads(shipped)
        for key, entry in given.items():
            if key not in base["defaults"] or not isinstance(entry, dict):
                raise ValueError(f"{shown}: defaults.{key}: not a quantity of the validation "
                                 f"({', '.join(DERIVED_QUANTITIES)})")
            base["defaults"][key] = {**base["defaults"][key], **entry}
        for part in ("derived", "items", "test_settings"):
            if not isinstance(raw.get(part, []), list):
                raise ValueError(f"{shown}: {part} must be an array of [[{part}]] tables")
            base[part] = list(base.get(part, [])) + list(raw.get(part, []))
        unknown = sorted(set(raw) - {"defaults", "derived", "items", "test_settings", "format", "title"})
        if unknown:
            raise ValueError(f"{shown}: {', '.join(unknown)}: not a part of a tolerances file (defaults, derived, "
                             "items, test_settings)")
        raw = base
    try:
        return ValidationSpec.model_validate(raw)
    except ValidationError as exc:
        err = exc.errors()[0]
        loc = ".".join(str(x) for x in err["loc"])
        n = len(exc.errors())
        raise ValueError(f"{shown}: {loc}: {err['msg'].removeprefix('Value error, ')}"
                         + (f" (and {n - 1} more problems)" if n > 1 else "")) from None


# ---------------------------------------------------------------------------------- results
@dataclass
class ValidationItem:
    """One compared number. ``measured`` and ``model`` are in ``unit`` (None where the item is a
    bound on the model value, or the model could not be computed); ``error`` is model - measured
    (``kind = "absolute"``, in ``unit``), model / measured - 1 (``"relative"``, a fraction), or
    None (bounds); ``tolerance`` applies as its ``kind`` says. ``message``: why the model value
    could not be computed (the item then fails unless it is a known miss); ``notes``: warnings
    of the runs the item used (e.g. a calibration used outside its configuration)."""
    id: str
    case: str
    description: str
    quantity: str
    unit: str
    measured: Optional[float]
    model: Optional[float]
    error: Optional[float]
    tolerance: float
    kind: str
    status: str
    reason: str
    source: str
    known_miss: str = ""
    overrides: dict = field(default_factory=dict)
    message: str = ""
    notes: list[str] = field(default_factory=list)

    @property
    def within_tolerance(self) -> bool:
        return self.status == "pass"

    def to_dict(self) -> dict:
        return dict(id=self.id, case=self.case, description=self.description, quantity=self.quantity, unit=self.unit,
                    measured=_finite(self.measured), model=_finite(self.model), error=_finite(self.error),
                    tolerance=self.tolerance, kind=self.kind, status=self.status, reason=self.reason,
                    source=self.source, known_miss=self.known_miss, overrides=dict(self.overrides),
                    message=self.message, notes=list(self.notes))


@dataclass
class ValidationReport:
    """The compared items of a validation run, in order: per case the derived items (per test),
    then its published items."""
    items: list[ValidationItem]
    cases: list[str]
    overrides: dict = field(default_factory=dict)
    case_notes: dict = field(default_factory=dict)
    tolerances_file: str = TOLERANCES_FILE
    runtime_s: float = 0.0

    @property
    def passed(self) -> bool:
        """True when no item other than a known miss is outside its tolerance."""
        return not any(i.status == "fail" for i in self.items)

    def summary(self) -> dict:
        """Counts: ``n_items``, ``n_pass``, ``n_fail``, ``n_known_miss`` and ``passed``, overall and
        per case (``cases``)."""
        def count(items):
            return dict(n_items=len(items), n_pass=sum(i.status == "pass" for i in items),
                        n_fail=sum(i.status == "fail" for i in items),
                        n_known_miss=sum(i.status == "known miss" for i in items),
                        passed=not any(i.status == "fail" for i in items))
        out = count(self.items)
        out["cases"] = {c: count([i for i in self.items if i.case == c]) for c in self.cases}
        return out

    def to_dict(self) -> dict:
        return dict(passed=self.passed, summary=self.summary(), cases=list(self.cases), overrides=dict(self.overrides),
                    case_notes=dict(self.case_notes), tolerances_file=self.tolerances_file,
                    runtime_s=self.runtime_s, items=[i.to_dict() for i in self.items])

    def _summary_line(self) -> str:
        s = self.summary()
        verdict = "passed" if self.passed else "FAILED: items outside their tolerance"
        return (f"{s['n_items']} items: {s['n_pass']} pass, {s['n_fail']} fail, {s['n_known_miss']} known miss; "
                f"{verdict}")

    def text(self) -> str:
        """An aligned table (item, measured, model, error, tolerance, status), then the known
        misses with their reasons, the messages of items that could not be computed, notes per
        case and the summary."""
        head = ("item", "measured", "model", "error", "tolerance", "status")
        rows = [(i.id, *display_cells(i), i.status) for i in self.items]      # in the display units (--units)
        widths = [max(len(r[k]) for r in [head, *rows]) for k in range(len(head))]
        right = (False, True, True, True, True, False)

        def line(r):
            return "  ".join(c.rjust(w) if ri else c.ljust(w) for c, w, ri in zip(r, widths, right)).rstrip()

        out = [f"validation of {', '.join(self.cases)}" + (f" with {_shown_overrides(self.overrides)}"
                                                          if self.overrides else "")]
        if rows:
            out += [line(head), line(tuple("-" * w for w in widths))] + [line(r) for r in rows]
        misses = [i for i in self.items if i.known_miss and i.status != "pass"]
        if misses:
            out += ["", "known misses (listed, not counted as failures):"]
            out += [f"  {i.id}: {i.known_miss}" for i in misses]
        errs = [i for i in self.items if i.message]
        if errs:
            out += ["", "not computed:"]
            out += [f"  {i.id}: {i.message}" for i in errs]
        warned: dict[str, int] = {}
        for i in self.items:
            for n in i.notes:
                warned[n] = warned.get(n, 0) + 1
        if warned:
            out += ["", "warnings of the runs (number of items):"]
            out += [f"  ({k}) {n}" for n, k in warned.items()]
        if self.case_notes:
            out += [""] + [f"{c}: {n}" for c, n in self.case_notes.items()]
        out += ["", self._summary_line()]
        return "\n".join(out)

    def markdown(self) -> str:
        """The table for the docs page (item, description, measured, model, error, tolerance,
        status, reason as a numbered note), the known misses and the numbered reasons, each with
        the sources of the items it covers. No run time or machine-dependent text: a page regenerated on the same model is
        the same."""
        reasons: dict[str, int] = {}
        sources: dict[str, list[str]] = {}
        for i in self.items:
            reasons.setdefault(i.reason, len(reasons) + 1)
            if i.source not in sources.setdefault(i.reason, []):
                sources[i.reason].append(i.source)
        if not self.items:
            L = ["No items: the cases have no measured or published numbers."]
        else:
            L = ["| item | description | measured | model | error | tolerance | status | why |",
                 "|---|---|---|---|---|---|---|---|"]
        for i in self.items:
            cells = [f"`{i.id}`", i.description, _value(i.measured, i.unit), _value(i.model, i.unit), _error(i),
                     _tolerance(i), f"**{i.status}**" if i.status == "fail" else i.status,
                     f"[{reasons[i.reason]}]"]
            L.append("| " + " | ".join(c.replace("|", "/") for c in cells) + " |")
        L += ["", f"**Summary:** {self._summary_line()}.", ""]
        for c, n in self.case_notes.items():
            L += [f"*{c}:* {n}", ""]
        misses = [i for i in self.items if i.known_miss]
        if misses:
            L += ["**Known misses** (listed with their figure, not counted as failures; \"pass\" when met):", ""]
            L += [f"* `{i.id}`: {i.known_miss}" for i in misses]
            L.append("")
        if reasons:
            L += ["**Why these tolerances** (from the tolerances file, written before the runs):", ""]
            L += [f"{n}. {reason} *Source{'s' if len(sources[reason]) > 1 else ''}:* {'; '.join(sources[reason])}"
                  for reason, n in reasons.items()]
        return "\n".join(L) + "\n"


# ---------------------------------------------------------------------------------- formatting
def _finite(v):
    return None if v is None or not math.isfinite(v) else float(v)


def _number(v: float) -> str:
    if v != 0 and abs(v) < 1e-3:
        return f"{v:.2e}"
    if abs(v) >= 1000:
        return f"{v:.0f}"
    return f"{v:.4g}"


def _value(v, unit: str) -> str:
    if v is None or not math.isfinite(v):
        return "-"
    return _number(v) + (f" {unit}" if unit not in ("", "-") else "")


def _error(i: ValidationItem) -> str:
    if i.error is None or not math.isfinite(i.error):
        return "-"
    if i.kind == "relative":
        return f"{100 * i.error:+.2f} %"
    return ("+" if i.error >= 0 else "") + _value(i.error, i.unit)


def _tolerance(i: ValidationItem) -> str:
    unit = "" if i.unit in ("", "-") else f" {i.unit}"
    return {"relative": f"±{100 * i.tolerance:g} %", "absolute": f"±{i.tolerance:g}{unit}",
            "minimum": f">= {i.tolerance:g}{unit}", "maximum": f"<= {i.tolerance:g}{unit}"}[i.kind]


#: an item's unit -> (its display quantity, factor to the quantity's SI unit): the shared table, and kg/kg (a moisture,
#: or a humidity by its quantity's name)
_DISPLAY_UNITS = {**UNIT_QUANTITIES, "kg/kg": ("moisture", 1.0)}


def display_cells(i: ValidationItem) -> tuple[str, str, str, str]:
    """(measured, model, error, tolerance) of an item as text in the display units (``--units``,
    `rotarydryer._display`), each with its unit; an item in a unit without a display quantity (a ratio, %) as
    `text` gives it. The docs page (`ValidationReport.markdown`) keeps the items' own units."""
    q = _DISPLAY_UNITS.get(i.unit)
    if q is None:
        return _value(i.measured, i.unit), _value(i.model, i.unit), _error(i), _tolerance(i)
    quantity, f = q
    if quantity == "moisture" and "humidity" in i.quantity:
        quantity = "humidity"

    def value(v):
        return "-" if v is None or not math.isfinite(v) else show(v * f, quantity)

    def delta(v, sign=True):
        text = show_delta(v * f, quantity) if quantity != "temperature_difference" else show(v * f, quantity)
        return ("+" if sign and v >= 0 else "") + text

    if i.error is None or not math.isfinite(i.error):
        err = "-"
    else:
        err = f"{100 * i.error:+.2f} %" if i.kind == "relative" else delta(i.error)
    tol = {"relative": f"±{100 * i.tolerance:g} %", "absolute": "±" + delta(i.tolerance, sign=False),
           "minimum": ">= " + value(i.tolerance), "maximum": "<= " + value(i.tolerance)}[i.kind]
    return value(i.measured), value(i.model), err, tol


def _shown_overrides(ov: dict) -> str:
    return ", ".join(f"--set {k}={v}" for k, v in ov.items())


def _judge(measured, model, tolerance: float, kind: str) -> tuple[Optional[float], bool]:
    """(error, within tolerance) of ``model`` against ``measured``."""
    if model is None or not math.isfinite(model):
        return None, False
    if kind == "absolute":
        err = model - measured
        return err, abs(err) <= tolerance
    if kind == "relative":
        err = model / measured - 1.0
        return err, abs(err) <= tolerance
    if kind == "minimum":
        return None, model >= tolerance
    return None, model <= tolerance


# ---------------------------------------------------------------------------------- runs
class _NotComputed(Exception):
    """The model value of an item could not be computed (the message says why)."""


def _one_line(exc: BaseException) -> str:
    text = " ".join(part.strip() for part in str(exc).strip().splitlines() if part.strip())
    return text or type(exc).__name__


class _Run:
    """One case with one set of overrides: the Simulation and what is computed from it, each once;
    a failure (ValueError, e.g. no steady state) is kept and raised to every item that needs it,
    warnings are kept as notes."""

    def __init__(self, case: str, overrides: dict):
        self.case, self.overrides = case, dict(overrides)
        self._memo: dict[str, tuple[Any, Optional[str]]] = {}
        self.notes: list[str] = []

    def get(self, key: str, compute: Callable[[], Any]):
        if key not in self._memo:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always")
                try:
                    self._memo[key] = (compute(), None)
                except _NotComputed as exc:
                    self._memo[key] = (None, str(exc))
                except (ValueError, ArithmeticError) as exc:      # the project's errors (DryerError included)
                    self._memo[key] = (None, _one_line(exc))
                except RuntimeError as exc:        # e.g. a singular factorisation: the item fails, the report goes on
                    self._memo[key] = (None, f"internal error ({type(exc).__name__}: {_one_line(exc)})")
            for w in caught:
                note = " ".join(str(w.message).split())
                if note not in self.notes:
                    self.notes.append(note)
        value, problem = self._memo[key]
        if problem is not None:
            raise _NotComputed(problem)
        return value

    def simulation(self) -> Simulation:
        return self.get("simulation", lambda: Simulation(self.case, self.overrides))

    def results(self):
        """Results of the solids transport alone with the tracer pulse simulated and the measured curve."""
        return self.get("results", lambda: self.simulation().results(thermal=False))

    def rtd(self) -> dict:
        def compute():
            c = rtd_comparison(self.results())
            if c is None:
                raise _NotComputed("no measured tracer curve for this run")
            return c
        return self.get("rtd", compute)

    def transport(self):
        return self.get("transport", lambda: self.simulation().transport_steady_state())

    def tracer_moments(self) -> dict:
        """Analytic moments (s) of the outlet tracer curve of the transport steady state, from the injection start."""
        return self.get("moments", lambda: self.transport().tracer_system().moments(self.simulation().tracer_input))

    def steady(self):
        """The coupled heat-and-mass steady state."""
        def compute():
            st = self.simulation().steady_state()
            if st.thermal is None:
                raise _NotComputed("the run has no heat and mass transfer (thermal.enabled = false or no [gas])")
            return st
        return self.get("steady", compute)

    def summary(self) -> dict:
        return self.get("summary", lambda: self.steady().summary())


class _Context:
    """What one validation run shares: the overrides of the caller, the runs by (case, overrides)
    and the runs an item used (for its notes)."""

    def __init__(self, spec: ValidationSpec, sets: dict, progress):
        self.spec, self.sets, self.progress = spec, dict(sets), progress
        self._runs: dict[str, _Run] = {}
        self.used: list[_Run] = []

    def run(self, case: str, overrides: dict) -> _Run:
        ov = {**overrides, **self.sets}
        key = json.dumps([case, ov], sort_keys=True, default=str)
        r = self._runs.get(key)
        if r is None:
            r = self._runs[key] = _Run(case, ov)
        self.used.append(r)
        return r

    def tests(self, case: str) -> list:
        """The [[tests]] rows of ``case`` that have a measured mean residence time."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            c = load_case(case)
        return [t for t in getattr(c, "tests", []) if t.mrt_measured_min is not None]


# ---------------------------------------------------------------------------------- metrics
def _need(value, what: str) -> float:
    if value is None:
        raise _NotComputed(f"the run gives no {what}")
    return float(value)


def _m_tracer_mean(ctx, item, ov):
    return ctx.run(item.case, ov).tracer_moments()["mean"] / 60.0


def _m_tracer_std(ctx, item, ov):
    return ctx.run(item.case, ov).tracer_moments()["std"] / 60.0


def _m_measured_curve(stat):
    def metric(ctx, item, ov):
        r = ctx.run(item.case, ov)
        mm = r.get("measured_moments", lambda: measured_rtd_moments(r.simulation().case))
        if mm is None:
            raise _NotComputed("the case has no measured tracer curve")
        return float(mm[stat]) / 60.0
    return metric


def _m_holdup(attr):
    def metric(ctx, item, ov):
        return float(getattr(ctx.run(item.case, ov).transport(), attr))
    return metric


def _m_design_load(ctx, item, ov):
    r = ctx.run(item.case, ov)
    r.transport()
    return float(np.nansum(r.simulation().transport_model().design_load))


def _m_first_cell_flow(phase):
    def metric(ctx, item, ov):
        return float(ctx.run(item.case, ov).transport().flow(phase)[0])
    return metric


def _m_moisture_profile_rms(ctx, item, ov):
    """RMS (kg/kg wet) of the coupled state's solids moisture (flights and beds, interpolated
    along the drum; clamped beyond its ends) against the samples of ``item.data`` (columns
    position_m, moisture_kg_per_kg_wet) inside the dryer (position > 0: the sample at 0 is the feed)."""
    if not item.data:
        raise _NotComputed("the item names no data file (data = ...)")
    th = ctx.run(item.case, ov).steady().thermal
    rows = read_published_csv(item.data)
    z = np.array([float(r["position_m"]) for r in rows])
    x = np.array([float(r["moisture_kg_per_kg_wet"]) for r in rows])
    keep = z > 0
    model = th.solids_moisture_at(z[keep])
    return float(np.sqrt(np.mean((model - x[keep]) ** 2)))


def _m_fuel_rate(ctx, item, ov):
    s = ctx.run(item.case, ov).summary()
    if s.get("fuel_rate_kg_s") is None:
        raise _NotComputed(s.get("fuel_rate_error") or "the case has no burner ([gas.burner])")
    return 3600.0 * float(s["fuel_rate_kg_s"])


def _test_of_line(ctx, item) -> int:
    """The [[tests]] row whose source names Song's Appendix A line ``params.src_line``."""
    if "src_line" not in item.params:
        raise _NotComputed("the item names no Appendix A run (params.src_line)")
    tag = f"L{int(item.params['src_line'])}"
    hit = [t.test for t in ctx.tests(item.case) if t.source.split()[-1:] == [tag]]
    if not hit:
        raise _NotComputed(f"no [[tests]] row of {item.case} at source line {item.params['src_line']}")
    return int(hit[0])


def _m_song_mape(ctx, item, ov):
    """Mean absolute relative error (%) of the transport mean residence time over the case's [[tests]]
    rows with a measured one (Song's Appendix A runs), each run as ``--set operating.test=N``."""
    rows = ctx.tests(item.case)
    if not rows:
        raise _NotComputed("the case has no [[tests]] row with mrt_measured_min")
    tau = np.array([ctx.run(item.case, {"operating.test": t.test, **ov}).transport().mean_residence_time
                    for t in rows])
    meas = 60.0 * np.array([t.mrt_measured_min for t in rows])
    return float(100.0 * np.mean(np.abs(tau / meas - 1.0)))


def _m_song_holdup(ctx, item, ov):
    return float(ctx.run(item.case, {"operating.test": _test_of_line(ctx, item), **ov}).transport().total_holdup)


#: quantity of a published item -> (model value from (context, item, overrides), unit)
METRICS: dict[str, tuple[Callable[..., float], str]] = {
    "tracer_mean": (_m_tracer_mean, "min"),
    "tracer_std": (_m_tracer_std, "min"),
    "measured_curve_mean": (_m_measured_curve("mean_s"), "min"),
    "measured_curve_std": (_m_measured_curve("std_s"), "min"),
    "total_holdup": (_m_holdup("total_holdup"), "kg"),
    "active_holdup": (_m_holdup("active_holdup"), "kg"),
    "passive_holdup": (_m_holdup("passive_holdup"), "kg"),
    "design_load": (_m_design_load, "kg"),
    "first_cell_kiln_flow": (_m_first_cell_flow("kiln"), "kg/s"),
    "first_cell_forward_flow": (_m_first_cell_flow("forward"), "kg/s"),
    "first_cell_backmix_flow": (_m_first_cell_flow("backmix"), "kg/s"),
    "solids_moisture_profile_rms": (_m_moisture_profile_rms, "kg/kg"),
    "fuel_rate": (_m_fuel_rate, "kg/h"),
    "song_appendix_a_mrt_mape": (_m_song_mape, "%"),
    "song_run_total_holdup": (_m_song_holdup, "kg"),
}


# ---------------------------------------------------------------------------------- items
def _item(ctx: _Context, *, id, case, description, quantity, unit, measured, tol: Tolerance, overrides,
          compute: Callable[[], float], known_miss: str = "", run: Optional[_Run] = None) -> ValidationItem:
    """Compute one item. ``measured`` is a number, None (a bound) or a callable (the measured side
    read from the run, e.g. the moments of the case's measured curve); ``run``: the run the
    computation uses (else the runs it asks the context for)."""
    ctx.used = [] if run is None else [run]
    message = ""
    model: Optional[float] = None
    try:
        if callable(measured):
            measured = float(measured())
        model = float(compute())
    except _NotComputed as exc:
        message = str(exc)
    if callable(measured):
        measured = None
    notes: list[str] = []
    for r in ctx.used:
        notes += [n for n in r.notes if n not in notes]
    err, ok = (None, False) if (measured is None and tol.kind in ("absolute", "relative")) else \
        _judge(measured, model, tol.tolerance, tol.kind)
    status = "pass" if ok else ("known miss" if known_miss else "fail")
    return ValidationItem(id=id, case=case, description=description, quantity=quantity, unit=unit,
                          measured=None if measured is None else float(measured), model=model, error=err,
                          tolerance=tol.tolerance, kind=tol.kind, status=status, reason=tol.reason,
                          source=tol.source, known_miss=known_miss or "", overrides={**overrides, **ctx.sets},
                          message=message, notes=notes)


def _label(case: str) -> str:
    """Case name in item ids: a packaged case's name, a file's stem."""
    return Path(case).stem if case.endswith(".toml") else case


def _comparable(case) -> dict:
    """A loaded case's content as validation sees it: without its [meta] and its records' case labels (what
    `rotarydryer new --from` changes in a copy)."""
    d = case.model_dump()
    d.pop("meta", None)
    for rec in d.get("calibrations") or []:
        rec.pop("case", None)
    return d


def shipped_twin(case) -> str | None:
    """The shipped case a loaded ``case`` (loaded without overrides) is a copy of (`rotarydryer new --from NAME`,
    unedited but for its title): the same dryer, data and calibrations, whose known misses and test settings are the
    copy's too; else None."""
    mine = _comparable(case)
    for name in list_cases():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            other = load_case(name)
        if _comparable(other) == mine:
            return name
    return None


def _derived_items(ctx: _Context, case: str, loaded, shipped: bool, twin: str | None = None) -> list[ValidationItem]:
    """The derived items of ``case``; a shipped case's known misses and test settings apply to it (``shipped``) or,
    for a copy of one (``twin``: its name), to the copy under the copy's own ids."""
    spec = ctx.spec
    own = case if shipped else twin
    prefix = f"{own}/" if own else None
    misses = ({_label(case) + "/" + d.id[len(prefix):]: d.known_miss for d in spec.derived if d.id.startswith(prefix)}
              if prefix else {})
    settings = {s.test: s for s in spec.test_settings if s.case == own} if own else {}
    has_curve = has_tracer_curve(loaded)
    thermal = thermal_enabled(loaded)
    out = []
    name = _label(case)

    def add(prefix, key, measured, compute, ov, run, extra=""):
        d = spec.defaults[key]
        iid = f"{name}/{prefix}/{key}"
        out.append(_item(ctx, id=iid, case=case, description=f"{d.description}{extra}", quantity=key,
                         unit=d.unit, measured=measured, tol=d, overrides=ov, compute=compute,
                         known_miss=misses.get(iid, ""), run=run))

    for row in sorted(loaded.tests, key=lambda r: r.test):
        setting = settings.get(row.test)
        ov = {"operating.test": row.test, **(setting.overrides if setting else {})}
        run = ctx.run(case, ov)
        prefix, where = f"test{row.test}", f", test {row.test}"
        if ctx.progress is not None:
            ctx.progress(f"validate {case}: test {row.test}")
        if row.mrt_measured_min is not None and has_curve:
            add(prefix, "tracer_mean", row.mrt_measured_min, lambda r=run: r.rtd()["model_mean_s"] / 60.0, ov, run, where)
        elif row.mrt_measured_min is not None:      # no tracer curve: a residence time H/F (Song's step method)
            add(prefix, "mean_residence_time", row.mrt_measured_min,
                lambda r=run: r.transport().mean_residence_time / 60.0, ov, run, where)
        elif has_curve:
            add(prefix, "curve_mean", lambda r=run: r.rtd()["measured_mean_s"] / 60.0,
                lambda r=run: r.rtd()["model_mean_s"] / 60.0, ov, run, where)
        if has_curve:
            add(prefix, "r_squared", None, lambda r=run: r.rtd()["r_squared"], ov, run, where)
        if row.holdup_measured_kg is not None:
            add(prefix, "holdup", row.holdup_measured_kg, lambda r=run: r.results().scalars["total_holdup_kg"], ov,
                run, where + " (transport steady state of the tracer run)")
        measured = {k: getattr(row, f) for k, f in _THERMAL_FIELDS.items() if getattr(row, f) is not None}
        if thermal and (setting is None or setting.thermal) and measured:
            if "product_moisture" in measured:
                add(prefix, "product_moisture", measured["product_moisture"],
                    lambda r=run: _need(r.summary().get("product_moisture_kg_kg"), "product moisture"), ov, run, where)
            if "gas_outlet_temperature" in measured:
                add(prefix, "gas_outlet_temperature", measured["gas_outlet_temperature"],
                    lambda r=run: _need(r.summary().get("gas_outlet_temperature_degC"), "gas outlet temperature"),
                    ov, run, where)
            if "product_temperature" in measured:
                def product_t(r=run):
                    s = r.summary()
                    return _need(s.get("product_temperature_at_sensor_degC", s.get("product_temperature_degC")),
                                 "product temperature")
                sensor = loaded.thermal.discharge_cooling_ntu > 0
                add(prefix, "product_temperature", measured["product_temperature"], product_t, ov, run,
                    where + (" (at the sensor)" if sensor else " (at the drum outlet)"))
            for key, out_key in (("product_d50", "product_d50_m"), ("dust_rate", "dust_rate_kg_s")):
                if key in measured:
                    add(prefix, key, measured[key],
                        lambda r=run, k=out_key, t=_DERIVED_TEXT[key]: _need(r.summary().get(k), t), ov, run, where)
            add(prefix, "energy_balance_error", None,
                lambda r=run: _need(r.summary().get("energy_balance_error"), "energy balance error"), ov, run, where)
    if not loaded.tests and has_curve:
        run = ctx.run(case, {})
        if ctx.progress is not None:
            ctx.progress(f"validate {case}: measured tracer curve")
        add("tracer", "curve_mean", lambda r=run: r.rtd()["measured_mean_s"] / 60.0,
            lambda r=run: r.rtd()["model_mean_s"] / 60.0, {}, run)
        add("tracer", "r_squared", None, lambda r=run: r.rtd()["r_squared"], {}, run)
    return out


def _published_items(ctx: _Context, case: str) -> list[ValidationItem]:
    out = []
    entries = [e for e in ctx.spec.items if e.case == case]
    if entries and ctx.progress is not None:
        ctx.progress(f"validate {case}: {len(entries)} published numbers")
    for e in entries:
        fn = METRICS[e.quantity][0]
        ov = {**e.overrides, **ctx.sets}
        out.append(_item(ctx, id=e.id, case=case, description=e.description, quantity=e.quantity, unit=e.unit,
                         measured=e.measured, tol=e, overrides=e.overrides,
                         compute=functools.partial(fn, ctx, e, ov), known_miss=e.known_miss or ""))
    return out


def run_validation(cases=None, overrides=None, progress=None, *, tolerances=None) -> ValidationReport:
    """Compare cases with their measured and published numbers.

    Parameters
    ----------
    cases : list of str, optional
        Packaged case names or ``.toml`` files; default every packaged case
        (`rotarydryer.cases.list_cases`). Published items (``[[items]]``) belong to
        packaged cases; a file gets the items derived from its own data.
    overrides : dict, optional
        ``{"thermal.area_scale": 5}`` (the CLI's ``--set``): applied on top of every item's own
        overrides of every selected case. Checked first: an unknown key or a bad value raises
        ``ValueError`` naming it before anything runs.
    progress : callable, optional
        Called with one line of text per case and test run.
    tolerances : path, optional
        Another tolerances file (default the shipped ``rotarydryer/data/validation.toml``).

    Returns
    -------
    ValidationReport
    """
    _jit.long_runs()        # every case and test: many steady states, the compiled kernels pay
    t0 = time.perf_counter()
    spec = load_tolerances(tolerances)
    shipped = list_cases()
    names = list(shipped if cases is None else [cases] if isinstance(cases, str) else cases)
    if not names:
        raise ValueError("cases: give at least one case (or none for every packaged case)")
    sets = dict(overrides or {})
    if "operating.test" in sets:
        # each item runs its own test (its overrides set operating.test): one test for all of them compared every
        # row's measurements with that test's run, under the other rows' names (found by review)
        raise ValueError(f"--set operating.test = {sets['operating.test']}: validate runs every [[tests]] row at its "
                         "own test number; to validate one test, give a case with only that row")
    loaded = {}
    for name in names:            # bad input first: unknown case, unknown key, bad value
        if not isinstance(name, str) or not name:
            raise ValueError(f"case = {name!r} is not a case name or a .toml file")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            loaded[name] = load_case(name, sets)
            if sets:    # a dryer the overrides make impossible (a flight wider than the drum) is bad input, not
                # 48 failed items (found by fuzzing); the shipped cases build as they are
                build_model(loaded[name])
    ctx = _Context(spec, sets, progress)
    items: list[ValidationItem] = []
    notes = {}
    for name in dict.fromkeys(names):
        is_shipped = name in shipped
        twin = None
        if not is_shipped:          # the file as written (a --set applies to the copy and the shipped case alike)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                try:
                    twin = shipped_twin(load_case(name) if sets else loaded[name])
                except ValueError:      # a file that is valid only with the --set: no copy of a shipped case
                    twin = None
        found = _derived_items(ctx, name, loaded[name], is_shipped, twin)
        if is_shipped:
            found += _published_items(ctx, name)
        if not found:
            # nothing to compare: the case must still run (a "passed" with 0 items on a dryer that has no steady
            # state would read as a clean bill of health)
            try:
                ctx.run(name, {}).simulation().steady_state()
            except ValueError as exc:
                raise ValueError(f"{name}: no steady state ({' '.join(str(exc).split())})") from None
            notes[name] = ("no measured or published data (no [[tests]] rows, no measured tracer curve, no published "
                           "items): 0 items; its steady state solves")
        shadow = rows_shadowed(loaded[name], sets)
        if shadow and found:           # in the report's notes (text and JSON), once
            notes[name] = shadow
        if twin is not None:
            notes[name] = " ".join(filter(None, [notes.get(name), f"a copy of the shipped case {twin}: its known "
                                                 "misses and test settings apply"]))
        items += found
    return ValidationReport(items=items, cases=list(dict.fromkeys(names)), overrides=sets, case_notes=notes,
                            tolerances_file=str(tolerances) if tolerances is not None else TOLERANCES_FILE,
                            runtime_s=time.perf_counter() - t0)

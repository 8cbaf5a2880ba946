"""Multi-response calibration of case keys to plant data, written as a calibration record.

One call fits chosen case keys to several measured responses of one or many operating tests at
once: tracer curves E(t), mean residence times, holdups, exhaust gas and product temperatures and
product moisture (the ``[[tests]]`` rows of the case hold the measured numbers, the case's
``[tracer]`` names the curves). A key is shared by every test (``thermal.area_scale``) or belongs to
one test (``tests.4.solids_velocity``: that test's fitted or unmeasured input, e.g. a gas flow
that was not metered); ``tests.*.gas_flow`` stands for the key of every selected test.

Weights: each response's residuals are divided by its measurement standard deviation
(`DEFAULT_SIGMA`, or the caller's): the weighted least-squares estimate with Wald 95 %
intervals (and profile-likelihood intervals on request) from `rotarydryer.estimation.fit`,
which also reports non-identifiable parameters. The result converts to a
`rotarydryer.cases.calibration.CalibrationRecord` (`CaseCalibration.record`) that holds
the values, intervals, correlation, the data and weights, the model configuration of the fit, the
software version and the date.

Each test's heat-and-mass model is built once: an evaluation that changes only parameter values
(gas flow, area scale, ... `rotarydryer.cases.build.PARAMETER_KEYS`) reuses it, warm-started
from that test's previous state.
"""

from __future__ import annotations

import datetime as _dt
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from .. import __version__
from .._threads import single_threaded
from ..cases import (
    case_calibrations,
    discrete_kind,
    exit_age_r_squared,
    has_tracer_curve,
    load_case,
    measured_exit_age,
    measured_rtd_moments,
    resolve_dataset,
    valid_override_keys,
)
from ..cases.build import any_trajectory, cascade_law, law_coefficient, rows_shadowed, test_row, thermal_settings
from ..cases.calibration import NONE_VALUE, TEST_FIELDS, TEST_KEY_PREFIX, CalibrationRecord, section_values
from ..executor import Executor
from ..published import read_published_csv
from ..simulation import Simulation
from .cases import DEFAULT_BOUNDS
from .fit import Dataset, FitResult, Parameter, fit, profile_likelihood

__all__ = ["RESPONSES", "DEFAULT_SIGMA", "CONFIGURATION_KEYS", "KEY_BOUNDS", "Measurement", "CaseCalibration", "measurements",
           "calibrate", "record_toml"]

#: responses a calibration can fit: name -> (what, unit, [[tests]] field of the measured value)
RESPONSES: dict[str, tuple[str, str, str | None]] = {
    "tracer": ("E(t) of the measured tracer curve", "1/s", None),
    "mrt": ("mean residence time", "s", "mrt_measured_min"),
    "holdup": ("total solids holdup", "kg", "holdup_measured_kg"),
    "gas_outlet_temperature": ("exhaust gas temperature", "degC", "gas_outlet_temperature"),
    "product_moisture": ("product moisture", "kg/kg wet", "product_moisture"),
    "product_temperature": ("product temperature at the plant's sensor", "degC", "product_temperature"),
    "moisture_profile": ("solids moisture along the drum", "kg/kg wet", "moisture_profile"),
    "product_d50": ("mass-median size of the product", "m", "product_d50"),
    "dust_rate": ("dust carried to the exhaust (wet)", "kg/s", "dust_rate"),
}
_TRANSPORT = ("tracer", "mrt", "holdup")
_THERMAL = ("gas_outlet_temperature", "product_moisture", "product_temperature", "moisture_profile", "product_d50",
            "dust_rate")

#: measurement standard deviations (the weights 1/sigma^2), chosen for plant data of this kind:
#: ``("absolute", s)`` in the response's unit or ``("relative", f)`` of the measured value; the
#: tracer's is relative to the curve's peak.
DEFAULT_SIGMA: dict[str, tuple[str, float]] = {
    # sampled outlet concentrations scatter by several % of the peak (Ajayi (2011) App. B: ppm
    # readings of 30-60 s grab samples; Lee (2008) Fig. 7.6)
    "tracer": ("relative", 0.05),
    # first moment of a sampled curve with an uncertain tail and background
    "mrt": ("relative", 0.02),
    # holdup = MRT x feed rate, feed rate SD 5-10 % of its mean (Ajayi Table 3.14, PI SDs)
    "holdup": ("relative", 0.10),
    # a thermocouple in a dusty exhaust duct, and the 1-2 h test mean of a controlled process
    "gas_outlet_temperature": ("absolute", 5.0),
    # oven-dried grab samples (Ajayi (2011) l.806), +/- 0.5 % moisture
    "product_moisture": ("absolute", 0.005),
    "product_temperature": ("absolute", 2.0),
    # oven-dried samples along the stopped drum (Ajayi (2011) l.802-806), as the product's
    "moisture_profile": ("absolute", 0.005),
    # a sieve analysis of the product: +/- 5 % of its d50
    "product_d50": ("relative", 0.05),
    # a baghouse catch weighed over a test: +/- 10 %
    "dust_rate": ("relative", 0.10),
}

#: case keys whose values make the model configuration a calibration holds for
CONFIGURATION_KEYS = ("geometry.method", "geometry.design_load_method", "transport.model", "transport.n_cells",
                      "transport.loading", "transport.forward_step", "transport.parameter_source", "transport.predictive_flights", "thermal.mode",
                      "thermal.kiln_bed_area")
_THERMAL_CONFIG = ("thermal.mode", "thermal.kiln_bed_area")

#: coefficients of the predictive transport law (a start value from the material class when the case has none)
_LAW_KEYS = ("transport.step_factor", "transport.curtain_coefficient", "transport.velocity_coefficient",
             "transport.dispersion_coefficient")
#: case key of each [[tests]] field a calibration may set (the run's override for that test)
_TEST_FIELD_KEYS = {"solids_velocity": "transport.solids_velocity", "dispersion": "transport.dispersion",
                    "gas_flow": "gas.flow", "fouling": "transport.fouling"}
_FIELD_BOUNDS = {"gas_flow": (0.01, 1000.0, True), "fouling": (0.0, 0.95, False)}
#: (lower, upper, log) of keys a calibration often fits, beyond :data:`rotarydryer.estimation.cases.DEFAULT_BOUNDS`
KEY_BOUNDS = {**DEFAULT_BOUNDS,
              "transport.moisture_scale": (0.62, 1.22, False),   # the range the material's laws allow (MMG)
              "transport.fouling": (0.0, 0.95, False),
              "transport.velocity_coefficient": (0.01, 10.0, True),
              "transport.dispersion_coefficient": (1e-3, 1e4, True),
              "transport.step_factor": (0.05, 20.0, True),         # c_0 of the cascade law (Song: 2.45)
              "transport.curtain_coefficient": (1e-4, 1e4, True),  # Sherritt's K (Lee Eq. 2.14: 1.546)
              "thermal.area_scale": (1e-3, 100.0, True),
              "thermal.discharge_cooling_ntu": (0.0, 50.0, False),
              "gas.flow": (0.01, 1000.0, True),
              "gas.leak_air_flow": (0.0, 1000.0, False)}


@dataclass(frozen=True)
class Measurement:
    """One measured response of one test: values ``y`` with standard deviations ``sigma`` at ``x``
    (times s of a tracer curve; empty for a scalar)."""

    test: int | None
    response: str
    y: np.ndarray
    sigma: np.ndarray
    x: np.ndarray = field(default_factory=lambda: np.zeros(0))
    source: str = ""

    @property
    def name(self) -> str:
        return f"{'case' if self.test is None else f'test{self.test}'}.{self.response}"


def _get(obj, key: str):
    for part in key.split("."):
        obj = getattr(obj, part, None)
    return obj


def _sigma(response: str, value: np.ndarray, sigmas: Mapping[str, float] | None) -> np.ndarray:
    if sigmas and response in sigmas:
        s = float(sigmas[response])
        if not (math.isfinite(s) and s > 0):
            raise ValueError(f"sigma of {response!r} = {sigmas[response]!r} must be a finite number > 0 "
                             f"({RESPONSES[response][1]})")
        return np.full(value.shape, s)
    kind, s = DEFAULT_SIGMA[response]
    if response == "tracer":
        return np.full(value.shape, s * float(np.max(value)))
    return np.full(value.shape, s * float(np.max(np.abs(value))) if kind == "relative" else s)


def _test_case(case_name: str, base: dict, test: int | None):
    ov = dict(base)
    if test is not None:
        ov["operating.test"] = int(test)
    return load_case(case_name, ov)


def measurements(case_name: str, tests: Sequence[int] | None = None, responses: Sequence[str] | None = None, *,
                 base_overrides: dict | None = None, sigmas: Mapping[str, float] | None = None,
                 strict: bool = False) -> list[Measurement]:
    """The measured responses of a case's tests (its ``[[tests]]`` rows and tracer curves).

    ``tests`` default every row of the case (a case without rows: its one operating point);
    ``responses`` default every response in `RESPONSES` the data have (with ``strict`` a
    requested response a test lacks is an error, naming the test and the row field)."""
    base = dict(base_overrides or {})
    case = load_case(case_name, base)
    rows = {t.test: t for t in case.tests}
    if tests is None:
        tests = sorted(rows) if rows else [None]
    for t in tests:
        if t is not None and t not in rows:
            raise ValueError(f"--tests: test {t} is not a [[tests]] row of case {case_name!r} (rows: "
                             f"{', '.join(map(str, sorted(rows))) or 'none'})")
    wanted = list(RESPONSES) if responses is None else list(responses)
    for r in wanted:
        if r not in RESPONSES:
            raise ValueError(f"--response {r!r} is not one of {', '.join(RESPONSES)}")
    thermal = Simulation(case).thermal_enabled
    out: list[Measurement] = []
    missing: dict[str, list] = {}
    for t in tests:
        c = _test_case(case_name, base, t) if t is not None else case
        row = rows.get(t)
        for r in wanted:
            if r in _THERMAL and not thermal:
                if strict:
                    raise ValueError(f"--response {r}: case {case_name!r} has no heat and mass transfer "
                                     "(thermal.enabled = false or no [gas])")
                continue
            if r == "moisture_profile" and (row is None or row.moisture_profile is None):
                missing.setdefault(r, []).append(t)
                continue
            if r == "tracer":
                meas = measured_exit_age(c)
                if meas is None:
                    missing.setdefault(r, []).append(t)
                    continue
                tt, e = meas
                src = resolve_dataset(c.tracer.dataset, t if t is not None else "") if c.tracer.dataset else c.tracer.measured
                out.append(Measurement(t, r, e, _sigma(r, e, sigmas), tt, source=str(src)))
                continue
            fld = RESPONSES[r][2]
            v = None if row is None else getattr(row, fld, None)
            if r == "moisture_profile" and v is not None:
                rows_ = read_published_csv(v)
                z = np.array([float(q["position_m"]) for q in rows_])
                x = np.array([float(q["moisture_kg_per_kg_wet"]) for q in rows_])
                keep = z > 0                       # the sample at 0 m is the feed
                out.append(Measurement(t, r, x[keep], _sigma(r, x[keep], sigmas), z[keep], source=v))
                continue
            if v is None and r == "mrt" and row is None:
                mom = measured_rtd_moments(c)      # a case without test rows: its measured curve's mean
                if mom is not None:
                    y = np.array([float(mom["mean_s"])])
                    out.append(Measurement(t, r, y, _sigma(r, y, sigmas), source="mean of the measured tracer curve"))
                    continue
            if v is None:
                missing.setdefault(r, []).append(t)
                continue
            v = float(v) * (60.0 if r == "mrt" else 1.0)
            y = np.array([v])
            out.append(Measurement(t, r, y, _sigma(r, y, sigmas), source=f"[[tests]] test {t}: {fld}"))
    have = {m.response for m in out}
    for r in wanted if strict else ():
        if r not in have and r in missing:     # asked for, and none of the tests has it
            where = ("tracer curve ([tracer] dataset or measured)" if r == "tracer"
                     else f"[[tests]] {RESPONSES[r][2]}")
            who = (f"case {case_name!r} (no [[tests]] rows)" if missing[r] == [None] else
                   f"{'test ' if len(missing[r]) == 1 else 'tests '}{', '.join(str(x) for x in missing[r])} of case "
                   f"{case_name!r}")
            raise ValueError(f"--response {r}: {who} {'has' if len(missing[r]) == 1 else 'have'} no measured {where}")
    if not out:
        where = "its operating point (no [[tests]] rows)" if list(tests) == [None] else \
            f"tests {', '.join(map(str, tests))}"
        raise ValueError(f"case {case_name!r} has no measured data for the responses {', '.join(wanted)} of {where} "
                         "(the measured values are [[tests]] fields: docs/calibration.md)")
    return out


def _expand(keys: Sequence[str], tests: Sequence[int | None]) -> list[str]:
    """``tests.*.field`` -> one key per selected test."""
    out = []
    for k in keys:
        if k.startswith(TEST_KEY_PREFIX + "*."):
            fld = k.split(".", 2)[2]
            out += [f"{TEST_KEY_PREFIX}{t}.{fld}" for t in tests if t is not None]
            if all(t is None for t in tests):
                raise ValueError(f"parameter {k!r}: the case has no [[tests]] rows")
        else:
            out.append(k)
    return list(dict.fromkeys(out))


def _is_gas_key(key: str) -> bool:
    """A gas key (``gas.*``, a test's ``gas_flow``): heat and mass, and the trajectory step's curtain drag."""
    return key.startswith("gas.") or key.endswith(".gas_flow")


def _is_heat_key(key: str) -> bool:
    """A key of the heat-and-mass model (thermal, gas, shell, drying kinetics)."""
    return key.startswith(("thermal.", "shell.", "material.kinetics")) or _is_gas_key(key)


def _parameter(case_name: str, base: dict, key: str, tests) -> Parameter:
    if key.startswith(TEST_KEY_PREFIX):
        parts = key.split(".")
        if len(parts) != 3 or not parts[1].isdigit():
            raise ValueError(f"parameter {key!r} must be tests.<test>.<field> or tests.*.<field>")
        t, fld = int(parts[1]), parts[2]
        if fld not in TEST_FIELDS:
            raise ValueError(f"parameter {key!r}: a calibration fits {', '.join(TEST_FIELDS)} of a [[tests]] row")
        if t not in tests:
            raise ValueError(f"parameter {key!r}: test {t} is not among the calibrated tests "
                             f"({', '.join(map(str, tests))})")
        case = _test_case(case_name, base, t)
        if fld == "gas_flow":
            value = thermal_settings(case).gas_flow
        else:
            value = _get(case, _TEST_FIELD_KEYS[fld])
            if value is None:
                value = getattr(test_row(case), fld, None)
            if value is None:      # a test without its own value yet: start from the other tests' mean
                known = [getattr(r, fld) for r in case.tests if getattr(r, fld, None) is not None]
                value = float(np.exp(np.mean(np.log(known)))) if known and min(known) > 0 else None
        lo, hi, lg = _FIELD_BOUNDS.get(fld, KEY_BOUNDS.get(_TEST_FIELD_KEYS[fld], (0.0, math.inf, True)))
    else:
        case = load_case(case_name, base)
        valid = valid_override_keys(type(case))
        if key not in valid:
            raise ValueError(f"unknown parameter key {key!r} for case {case_name!r}: a case key "
                             f"(rotarydryer schema) or tests.<test>.<field>")
        takes = discrete_kind(type(case), key)
        if takes is not None:   # operating.test was tried at 3.99999 (found by fuzzing)
            raise ValueError(f"parameter {key}: the key takes {takes}; a calibration needs "
                             f"a continuous parameter (compare the values you want with `rotarydryer sweep --grid "
                             f"{key}=...`)")
        value = _get(case, key)
        if value is None and key in ("transport.solids_velocity", "transport.dispersion", "transport.fouling"):
            row = test_row(case)
            value = getattr(row, key.split(".")[1], None) if row is not None else None
        if value is None and key == "gas.flow":
            value = thermal_settings(case).gas_flow
        if value is None and key in _LAW_KEYS:      # the material class's value, else the neutral one
            value = law_coefficient(case, key.split(".", 1)[1])
        lo, hi, lg = KEY_BOUNDS.get(key, (0.0, math.inf, True))
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"parameter {key!r} has no numeric value in case {case_name!r} (value {value!r}); "
                         "it cannot be calibrated")
    value = float(value)
    if lg and value == 0.0 and lo >= 0.0:
        # a search on the log scale cannot leave 0, and on the linear one it stalled there (area_scale 2e-10 with a
        # false "lack of fit"; found by review)
        raise ValueError(f"parameter {key} starts at 0, where its search (on the log scale, within [{lo:g}, {hi:g}]) "
                         f"cannot move: give it a positive start (--set {key}=...) or leave the case's value")
    if lg and not value > 0:
        lg, lo = False, min(lo, value)
    return Parameter(key, value, lo, hi, lg)


def _run_overrides(base: dict, values: Mapping[str, float], test: int | None) -> dict:
    ov = dict(base)
    if test is not None:
        ov["operating.test"] = int(test)
    for k, v in values.items():
        if k.startswith(TEST_KEY_PREFIX):
            _, t, fld = k.split(".")
            if test is not None and int(t) == int(test):
                ov[_TEST_FIELD_KEYS[fld]] = float(v)
        else:
            ov[k] = float(v)
    return ov


class _Model:
    """values -> {measurement name: prediction}; one warm heat-and-mass model per test."""

    def __init__(self, case_name: str, base: dict, data: list[Measurement], on_solve: Callable | None = None):
        self.case_name, self.base, self.data = case_name, base, data
        self.on_solve = on_solve          # called with the count after each model run (progress)
        self.tests = list(dict.fromkeys(m.test for m in data))
        self.warm: dict = {}
        self.n_solves = 0
        self._last: dict = {}       # test -> (its overrides, its predictions): a test whose inputs did not change

    def fresh(self) -> _Model:
        """The same model without its warm states and counts: what one start of a multi-start fit
        runs on (`rotarydryer.estimation.fit.fit`), so that it gives the same result in any process."""
        return _Model(self.case_name, self.base, self.data, on_solve=self.on_solve)

    def __getstate__(self):
        state = dict(self.__dict__)
        state.update(on_solve=None, warm={}, _last={})    # a worker process: no progress callback, no warm state
        return state

    def predict_test(self, values, test, wanted):
        ov = _run_overrides(self.base, values, test)
        key = tuple(sorted((k, repr(v)) for k, v in ov.items()))
        last = self._last.get(test)
        if last is not None and last[0] == key:        # e.g. another test's parameter perturbed
            return last[1]
        out = self._predict(ov, values, wanted)
        self._last[test] = (key, out)
        return out

    def _predict(self, ov, values, wanted):
        test = ov.get("operating.test")
        out = {}
        need_transport = [m for m in wanted if m.response in _TRANSPORT]
        need_thermal = [m for m in wanted if m.response in _THERMAL]
        if need_transport:
            sim = Simulation(self.case_name, ov)
            ss = sim.transport_steady_state()
            self._solved()
            r = None
            curve = has_tracer_curve(sim.case)
            for m in need_transport:
                if (m.response == "tracer" or (m.response == "mrt" and curve)) and r is None:
                    tmax = max([float(x.x[-1]) for x in need_transport if x.response == "tracer"] or [0.0])
                    t_end = max(math.ceil((tmax + 60.0) / 10.0) * 10.0, float(sim.case.tracer.t_end))
                    r = ss.rtd(sim.transport_model().tracer_input, t_end=t_end, dt=10.0)
                if m.response == "tracer":
                    e = np.interp(m.x, r.response.time, r.response.exit_age, left=0.0, right=0.0)
                    if not float(np.max(e)) > 1e-3 * float(np.max(r.response.exit_age)):   # nothing in the window
                        raise ValueError(f"{m.name}: no tracer reaches the outlet within the measured window "
                                         f"({m.x[-1]:.0f} s) with {dict(values)}")
                    out[m.name] = e
                elif m.response == "mrt" and curve:     # a tracer curve's mean, from the injection start
                    out[m.name] = np.array([float(r.tracer_mean)])
                elif m.response == "mrt":               # no curve: holdup / feed (has_tracer_curve), as validate
                    out[m.name] = np.array([float(ss.mean_residence_time)])
                else:
                    out[m.name] = np.array([float(ss.total_holdup)])
        if need_thermal:
            sim = Simulation(self.case_name, ov)
            res = sim.steady_state(warm=self.warm.get(test))
            self.warm[test] = res.warm_data()
            self._solved()
            s = res.summary()
            for m in need_thermal:
                if m.response == "moisture_profile":
                    out[m.name] = np.asarray(res.thermal.solids_moisture_at(m.x), float)
                    continue
                key = {"gas_outlet_temperature": "gas_outlet_temperature_degC",
                       "product_moisture": "product_moisture_kg_kg",
                       "product_temperature": "product_temperature_at_sensor_degC",
                       "product_d50": "product_d50_m", "dust_rate": "dust_rate_kg_s"}[m.response]
                v = s.get(key, s["product_temperature_degC"] if m.response == "product_temperature" else None)
                out[m.name] = np.array([float(v)])
        return out

    def _solved(self):
        self.n_solves += 1
        if self.on_solve is not None:
            self.on_solve(self.n_solves)

    def __call__(self, values):
        out = {}
        for t in self.tests:
            out.update(self.predict_test(values, t, [m for m in self.data if m.test == t]))
        return out


@dataclass
class CaseCalibration:
    """Result of `calibrate`: the fit, its data and what it was run on."""

    case: str
    case_title: str
    keys: list[str]
    tests: list
    base_overrides: dict
    data: list[Measurement]
    fit: FitResult
    configuration: dict
    profiles: dict = field(default_factory=dict)
    seconds: float = 0.0
    n_solves: int = 0

    def comparison(self) -> list[dict]:
        """Per measurement: measured and calibrated model (means for a curve), weighted RMS residual,
        and R^2 for a tracer curve."""
        rows = []
        for m in self.data:
            f = np.asarray(self.fit.predictions[m.name], float)
            row = dict(name=m.name, test=m.test, response=m.response, unit=RESPONSES[m.response][1],
                       n_points=int(m.y.size), weighted_rms=float(np.sqrt(np.mean(((f - m.y) / m.sigma) ** 2))))
            if m.response == "tracer":
                row.update(r_squared=exit_age_r_squared(m.y, f))
            else:
                row.update(measured=float(m.y[0]), model=float(f[0]), error=float(f[0] - m.y[0]))
            rows.append(row)
        return rows

    def held_values(self) -> tuple[dict, list[str]]:
        """``({key: value}, [record names])`` of the keys this calibration holds but did not fit: the
        other keys of the records it supersedes (those applied to the run that set a fitted key), at
        the run's values. A record applies whole (`rotarydryer.cases.calibration`), so the new one
        carries them: appending it changes only the fitted keys."""
        case = load_case(self.case, self.base_overrides)
        held: dict = {}
        names = []
        for rec in case_calibrations(case):
            if not set(rec.values) & set(self.keys):
                continue
            names.append(rec.name)
            for k in rec.values:
                if k in self.keys or k in held:
                    continue
                if k.startswith(TEST_KEY_PREFIX):
                    _, t, fld = k.split(".")
                    row = next((r for r in case.tests if r.test == int(t)), None)
                    v = getattr(row, fld, None)
                else:
                    v = _get(case, k)
                if v is not None:
                    held[k] = v if isinstance(v, (bool, str)) else float(v)
        # the model coefficients the run fixed with --set: the fit holds for them (a calibrated case without them ran
        # another model: drag_reduction 1.0 for a fit at 0.8, found by a workflow check)
        for k in held_overrides(self.base_overrides, self.keys):
            if k not in held:
                v = _get(case, k)
                if v is not None:
                    held[k] = v if isinstance(v, (bool, str)) else float(v)
                    if "--set" not in names:
                        names.append("--set")
        return held, names

    def record(self, name: str | None = None, description: str = "") -> CalibrationRecord:
        """The calibration record (values, intervals, correlation, data, configuration, version, date);
        with the held values of the records it supersedes (`held_values`)."""
        p = self.fit.parameters
        values = {k: float(p[k].value) for k in self.keys}
        held, superseded = self.held_values()
        prof = {k: v for k, v in self.profiles.items() if v is not None}
        intervals = {}
        for k in self.keys:
            if k in prof and math.isfinite(prof[k].ci_low) and math.isfinite(prof[k].ci_high):
                intervals[k] = [float(prof[k].ci_low), float(prof[k].ci_high)]
            elif math.isfinite(p[k].ci_low) and math.isfinite(p[k].ci_high):
                intervals[k] = [float(p[k].ci_low), float(p[k].ci_high)]
        corr = np.asarray(self.fit.correlation, float)
        correlation = None
        if corr.shape == (len(self.fit.names),) * 2 and np.all(np.isfinite(corr)) and len(self.keys) > 1:
            idx = [self.fit.names.index(k) for k in self.keys]
            correlation = {"keys": list(self.keys), "matrix": [[round(float(corr[i, j]), 6) for j in idx] for i in idx]}
        data = [dict(name=m.name, response=m.response, sigma=float(m.sigma.flat[0]), unit=RESPONSES[m.response][1],
                     n_points=int(m.y.size), source=m.source) for m in self.data]
        tests = ", ".join(str(t) for t in self.tests if t is not None)
        if not description:
            description = (f"{', '.join(self.keys[:6])}{' ...' if len(self.keys) > 6 else ''} fitted to "
                           f"{len(self.data)} data sets{f' of tests {tests}' if tests else ''}")
            if held:
                description += (f"; held at the run's values: {', '.join(list(held)[:6])}"
                                f"{' ...' if len(held) > 6 else ''} (of {'; '.join(superseded)})")
        return CalibrationRecord.model_validate(dict(
            name=name or f"rotarydryer calibrate {self.case_title or self.case}"[:200],
            description=description[:2000], case=self.case_title, configuration=self.configuration,
            values={**values, **held}, held=list(held), intervals=intervals,
            interval_method="profile" if prof else "wald", correlation=correlation, data=data,
            method=f"weighted least squares ({self.fit.method}), {len(self.fit.starts)} start(s)",
            objective=float(self.fit.objective), n_evaluations=int(self.fit.n_evaluations),
            software_version=__version__, date=_dt.datetime.now(_dt.UTC).date().isoformat(),
            source="rotarydryer calibrate"))

    def to_dict(self) -> dict:
        d = self.fit.to_dict()
        d.update(case=self.case, keys=list(self.keys), tests=list(self.tests), base_overrides=dict(self.base_overrides),
                 comparison=self.comparison(), configuration=dict(self.configuration), seconds=self.seconds,
                 n_solves=self.n_solves,
                 profiles={k: (None if v is None else {"ci_low": v.ci_low, "ci_high": v.ci_high})
                           for k, v in self.profiles.items()})
        return d


def _configuration(case, thermal: bool) -> dict:
    out = {}
    # the predictive law of lee2008-type sections fixes their forward step and loading (cases.build)
    cascade = all(cascade_law(case, s.model or case.transport.model) for s in case.sections if s.kind == "flighted")
    forced = (("transport.forward_step", "transport.loading") if cascade else ()) + (
        () if any((s.model or case.transport.model) == "ajayi2011" for s in case.sections)
        and case.transport.parameter_source == "predictive" else ("transport.predictive_flights",))
    # a case-wide default every flighted section replaces is not part of the configuration: written unset
    for k in CONFIGURATION_KEYS:
        if (k in _THERMAL_CONFIG and not thermal) or k in forced:
            continue
        v = None if section_values(case, k) is not None else _get(case, k)
        out[k] = NONE_VALUE if v is None else v       # TOML has no null
    return out


@single_threaded()
def calibrate(case_name: str, parameters: Sequence[str], *, tests: Sequence[int] | None = None,
              responses: Sequence[str] | None = None, base_overrides: dict | None = None,
              sigmas: Mapping[str, float] | None = None, n_starts: int = 1, seed: int = 0,
              profile: Sequence[str] | bool = False, progress: Callable | None = None,
              executor: Executor | None = None) -> CaseCalibration:
    """Fit case keys ``parameters`` to the measured responses of ``tests`` at once (module docstring).

    ``parameters``: case keys (shared) and ``tests.<test>.<field>`` / ``tests.*.<field>`` (per test).
    ``responses``: names of `RESPONSES` (default: every one the data have that the parameters
    can move: transport keys move the transport responses; thermal keys the thermal ones).
    ``sigmas``: {response: standard deviation} replacing `DEFAULT_SIGMA`. ``profile``: True
    or the keys to profile (likelihood intervals; each point re-fits the others).
    ``progress(stage, k, n)`` after each start / profile (``stage`` "start", "profile") and after each
    model run (``"model run", k, 0``: k runs so far, no total known; the runs of starts on worker
    processes are counted when their start ends). ``executor`` (`rotarydryer.executor.Executor`)
    runs the starts, each from the case's cold state: every backend gives the same calibration."""
    t0 = time.perf_counter()
    base = dict(base_overrides or {})
    if not parameters:
        raise ValueError("--param: give at least one case key to calibrate")
    if int(n_starts) != n_starts or not 1 <= n_starts <= 100:
        raise ValueError(f"--starts = {n_starts!r} must be an integer in [1, 100]")
    case = load_case(case_name, base)
    all_tests = sorted(t.test for t in case.tests)
    sel = list(all_tests or [None]) if tests is None else list(tests)
    keys = _expand(list(parameters), sel)
    params = [_parameter(case_name, base, k, sel) for k in keys]
    thermal_keys = any(_is_heat_key(k) for k in keys)
    if responses is None:
        wanted = list(_TRANSPORT) if not thermal_keys else list(_TRANSPORT + _THERMAL)
        if thermal_keys and not any(k.startswith(("transport.", "geometry.")) or k.endswith(
                (".solids_velocity", ".dispersion", ".fouling")) for k in keys):
            wanted = list(_THERMAL)
        data = measurements(case_name, sel, wanted, base_overrides=base, sigmas=sigmas)
    else:
        # gas.* and a test's gas_flow move the transport only through the trajectory step's curtain drag
        gas_moves_transport = any_trajectory(case)
        heat_keys = [k for k in keys if _is_heat_key(k) and not (gas_moves_transport and _is_gas_key(k))]
        if heat_keys and all(r in _TRANSPORT for r in responses):
            # the fit failed "in any direction around the solution (last refusal: none)" (found by fuzzing)
            raise ValueError(f"parameter {heat_keys[0]}: a heat-and-mass key does not move the solids transport "
                             f"responses ({', '.join(responses)}); fit it to a thermal response "
                             f"({', '.join(_THERMAL[:3])}, ...) or leave it out")
        data = measurements(case_name, sel, responses, base_overrides=base, sigmas=sigmas, strict=True)
    n = sum(m.y.size for m in data)
    if n <= len(params):
        raise ValueError(f"{n} measured values for {len(params)} parameters: give more data (--tests, --response) "
                         "or fewer parameters")
    model = _Model(case_name, base, data, on_solve=None if progress is None else lambda k: progress("model run", k, 0))
    datasets = [Dataset(m.name, m.y, m.sigma) for m in data]

    def on_start(k, total, best):
        if progress is not None:
            progress("start", k, total)

    res = fit(model, params, datasets, method="wls", n_starts=n_starts, seed=seed, progress=on_start,
              executor=executor)
    shadow = rows_shadowed(case, base) if any(t is not None for t in sel) else None
    if shadow:          # every test ran at the [operating] values: first among the fit's warnings
        res.warnings.insert(0, shadow)
    profiles = {}
    names = keys if profile is True else list(profile or [])
    for i, k in enumerate(names):
        if k not in keys:
            raise ValueError(f"--profile {k!r} is not a calibrated parameter ({', '.join(keys)})")
        try:
            profiles[k] = profile_likelihood(model, params, datasets, res, k, n_points=9)
        except Exception:  # noqa: BLE001 - a profile that fails leaves the Wald interval
            profiles[k] = None
        if progress is not None:
            progress("profile", i + 1, len(names))
    title = case.meta.title or case_name
    thermal = Simulation(case).thermal_enabled and any(m.response in _THERMAL for m in data)
    return CaseCalibration(case_name, title, keys, sel, base, data, res, _configuration(case, thermal),
                           profiles, time.perf_counter() - t0, model.n_solves)


def held_overrides(base: Mapping, fitted: Sequence[str]) -> list[str]:
    """The keys of a run's ``--set`` a calibration record carries as held values: the model's coefficients
    (``transport.*``, ``thermal.*``, ``geometry.*``, and keys a calibration may fit), not its configuration
    (`CONFIGURATION_KEYS`, recorded as such), operating conditions, the gas, the material or the site (the plant's
    inputs, which each run and test gives)."""
    out = []
    for k in base:
        if k in fitted or k in CONFIGURATION_KEYS or k.startswith(TEST_KEY_PREFIX):
            continue
        if k.startswith(("transport.", "thermal.", "geometry.")) or (k in KEY_BOUNDS and not k.startswith(
                ("operating.", "gas.", "material.", "site.", "drum."))):
            out.append(k)
    return out


# ----------------------------------------------------------------------------- TOML of a record
def _toml_scalar(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        if isinstance(v, float) and not math.isfinite(v):
            raise ValueError(f"a calibration record holds a non-finite number {v!r}")
        return repr(v)
    s = str(v).replace("\\", "\\\\").replace('"', '\\"').replace("\n", " ")
    return f'"{s}"'


def _toml_value(v) -> str:
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return _toml_scalar(v)


def record_toml(record: CalibrationRecord) -> str:
    """The record as a ``[[calibrations]]`` TOML table (append it to a case file to use it)."""
    d = record.model_dump(exclude_none=True)
    lines = ["[[calibrations]]"]
    nested = {}
    for k, v in d.items():
        if isinstance(v, dict):
            nested[k] = v
        elif k == "data":
            continue
        else:
            lines.append(f"{k} = {_toml_value(v)}")
    for k, v in nested.items():
        lines.append(f"[calibrations.{k}]")
        lines += [f"{_toml_scalar(kk)} = {_toml_value(vv)}" for kk, vv in v.items()]
    for item in d.get("data", []):
        lines.append("[[calibrations.data]]")
        lines += [f"{kk} = {_toml_value(vv)}" for kk, vv in item.items()]
    return "\n".join(lines) + "\n"

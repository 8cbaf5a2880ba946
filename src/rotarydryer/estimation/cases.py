"""Fit case parameters, named by their override keys, to measured tracer curves.

Example:

    from rotarydryer.estimation.cases import fit_case_to_tracer
    from rotarydryer.rtd import load_tracer_dataset
    res = fit_case_to_tracer("lee2008_invicta", load_tracer_dataset("lee2008_invicta"),
                             ["transport.kiln_time", "transport.backmix", "transport.drag_reduction"],
                             base_overrides={"transport.n_cells": 35,
                                             "geometry.method": "lee2008_regressions"})
    res.fit.parameters["transport.backmix"].ci_low

The model of a parameter vector is: the case with the overrides as a
[`rotarydryer.Simulation`][rotarydryer.simulation.Simulation], its transport steady state, simulate the tracer response to the case's
tracer input, and interpolate E(t) (1/s) at the measured times (measured from the
start of injection). A signal in 1/h is converted to 1/s; a raw concentration
(``scale="fit"``) is matched by the best scale factor for each parameter vector
(variable projection: the scale is eliminated in closed form).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from .._threads import single_threaded
from .._validation import check_choice
from .fit import Dataset, FitResult, Parameter, fit

__all__ = ["DEFAULT_BOUNDS", "BASELINE", "BASELINE_CHOICES", "CaseFit", "case_parameter", "tracer_model",
           "fit_case_to_tracer", "evaluate_objective", "baseline_parameter", "profile_case_fit"]

#: name of the fitted constant tracer background (signal unit; not a case key)
BASELINE = "baseline"
#: ``baseline`` choices of :func:`fit_case_to_tracer` (and ``rotarydryer fit --baseline``)
BASELINE_CHOICES = ("none", "fit")

#: Default (lower, upper, log) of well-known keys; any other numeric key gets (0, inf, log)
#: when positive, else unbounded.
DEFAULT_BOUNDS = {
    "transport.kiln_time": (0.5, 200.0, True),  # s, Lee (2008) t_kiln
    "transport.backmix": (0.0, 0.95, False),  # -, Lee (2008) C_B
    "transport.drag_reduction": (0.0, 3.0, False),  # -, Lee (2008) C_F^G
    "transport.solids_velocity": (1e-4, 0.5, True),  # m/s, Ajayi (2011) Table 5.2
    "transport.dispersion": (1e-7, 1e-1, True),  # m^2/s, Ajayi (2011) Table 5.2
    "transport.core_fraction": (1e-4, 10.0, True),  # -, beta of transport.core (docs/rtd_spread.md)
    "transport.core_time": (1.0, 1e6, True),  # s, t_c or t_D of transport.core
    "transport.passive_rate": (1e-6, 10.0, True),  # 1/s, Sheehan et al. (2005) Model 1
    "transport.exchange_rate": (1e-6, 100.0, True),
    "transport.return_rate": (1e-6, 100.0, True),
    "transport.kiln_rate": (1e-6, 100.0, True),
}


def _current_value(case, key: str) -> float:
    sec, fld = key.split(".", 1)
    value = case
    for part in key.split("."):
        value = getattr(value, part, None)
    if value is None and sec == "transport":
        # the default the model takes: the selected test's row (Table 5.2 in the MMG case) or the
        # [[parameter_sets]] row of n_cells (Lee's Table 7.2)
        from ..cases.build import law_coefficient, solids_transport, test_row, transport_coefficients

        row = test_row(case)
        value = getattr(row, fld, None) if row is not None else None
        try:
            if value is None and fld in ("kiln_time", "backmix", "drag_reduction"):
                value = transport_coefficients(case).get(fld)
            elif value is None and fld in ("step_factor", "curtain_coefficient", "velocity_coefficient",
                                           "dispersion_coefficient"):
                value = law_coefficient(case, fld)      # the material class's, else the neutral value
            elif value is None and fld in ("solids_velocity", "dispersion"):
                u, D, _ = solids_transport(case)
                vals = list((u if fld == "solids_velocity" else D).values())
                value = vals[0] if vals and all(v == vals[0] for v in vals) else None
        except Exception:  # noqa: BLE001 - only a default start is being looked up
            value = None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"parameter {key!r} is not numeric in this case (value {value!r}); it cannot be fitted")
    return float(value)


def case_parameter(case_name: str, key: str, base_overrides: dict | None = None, *, initial=None,
                   lower=None, upper=None, log=None) -> Parameter:
    """A [`Parameter`][rotarydryer.estimation.cases.Parameter] for override key ``key``: start from the case's value unless given.

    Raises ``ValueError`` for a key the case does not have (naming the valid keys) or a
    non-numeric one.
    """
    from ..cases import discrete_kind, load_case, valid_override_keys

    case = load_case(case_name, dict(base_overrides or {}))
    valid = valid_override_keys(type(case))
    if key not in valid:
        raise ValueError(f"unknown parameter key {key!r} for case {case_name!r}; valid keys: {', '.join(valid)}")
    if discrete_kind(type(case), key) == "whole numbers":      # (text keys: "not numeric", below)
        # a whole-number key (transport.n_cells) was tried at 19.999999999999996 cells (found by fuzzing)
        raise ValueError(f"parameter {key}: the key takes whole numbers; a fit needs a continuous parameter (compare "
                         f"the values you want with `rotarydryer sweep --grid {key}=...`)")
    value = _current_value(case, key) if initial is None else float(initial)
    lo, hi, lg = DEFAULT_BOUNDS.get(key, (0.0 if value > 0 else -math.inf, math.inf, value > 0))
    lo = lo if lower is None else float(lower)
    hi = hi if upper is None else float(upper)
    lg = lg if log is None else bool(log)
    if lg and lo <= 0.0:
        lo = 0.0
    return Parameter(key, value, lo, hi, lg)


def _relative_times(data, scale: str = "known"):
    """Times since the injection start (s) and the signal, as E(t) in 1/s when the file's
    ``signal_unit`` is a normalised RTD; a raw concentration needs ``scale="fit"``."""
    t = np.asarray(data.time_s, dtype=float) - data.time_origin_s
    y = np.asarray(data.signal, dtype=float)
    keep = t >= 0.0
    rate = data.rate_factor
    if rate is not None:
        y = y * rate
    elif scale == "known":
        given = ("the file gives no signal unit" if data.signal_unit is None
                 else f"signal_unit = {data.signal_unit!r} is not a normalised RTD (1/s, 1/min, 1/h)")
        raise ValueError(
            f"{given}: a curve in 1/s needs a '# signal_unit: 1/s' line (or 1/min, 1/h) above its header; fit a raw "
            "concentration with --scale fit (scale='fit')"
        )
    return t[keep], y[keep]


def tracer_model(case_name: str, times: np.ndarray, *, base_overrides: dict | None = None, scale: str = "known",
                 observed: np.ndarray | None = None, dt: float | None = None, with_holdup: bool = False):
    """Model callable ``values -> E(t)`` at ``times`` (s since injection) for [`fit`][rotarydryer.estimation.cases.fit];
    with ``with_holdup`` a dict ``{"tracer": E, "holdup": [total holdup, kg]}``. A value
    `BASELINE` in ``values`` (a fitted constant background, signal unit) is added to the
    curve (with ``scale="fit"`` the scale is matched to the observed signal minus it)."""
    check_choice("scale", scale, ("known", "fit"))
    if scale == "fit" and observed is None:
        raise ValueError("scale = 'fit' needs the observed signal (observed=...) to match the scale to")
    times = np.asarray(times, dtype=float)
    t_end = float(times.max()) * 1.02 + 1.0
    # 10 s steps: E(t) at the data times within 1e-3 of the peak for Lee's 39.6 s pulse,
    # far below the measurement noise, at half the cost of 5 s steps
    step = dt if dt is not None else min(10.0, max(t_end / 200.0, 1.0))
    return _TracerModel(case_name, times, dict(base_overrides or {}), scale, observed, t_end, step, with_holdup)


class _TracerModel:
    """The callable of `tracer_model` (a class, so that it pickles for worker processes)."""

    def __init__(self, case_name, times, base, scale, observed, t_end, step, with_holdup):
        self.case_name, self.times, self.base, self.scale = case_name, times, base, scale
        self.observed, self.t_end, self.step, self.with_holdup = observed, t_end, step, with_holdup

    def __call__(self, values: dict):
        from ..simulation import Simulation

        values = dict(values)
        b = float(values.pop(BASELINE, 0.0))
        ss = Simulation(self.case_name, {**self.base, **values}).transport_steady_state()
        resp = ss.rtd(t_end=self.t_end, dt=self.step).response
        e = np.interp(self.times, resp.time, resp.exit_age)
        if self.scale == "fit":
            den = float(e @ e)
            c = float((self.observed - b) @ e) / den if den > 0 else 0.0
            e = c * e
        e = e + b
        if self.with_holdup:
            return {"tracer": e, "holdup": np.array([ss.total_holdup])}
        return e


@dataclass
class CaseFit:
    """A case fit: the estimation result plus what was fitted."""

    case: str
    keys: list
    base_overrides: dict
    times: np.ndarray
    observed: np.ndarray
    fit: FitResult
    reference_objective: float | None = None
    #: what :func:`profile_case_fit` re-fits: the model callable, its parameters and data sets
    model: object = field(default=None, repr=False)
    parameters: list = field(default_factory=list, repr=False)
    datasets: list = field(default_factory=list, repr=False)

    def to_dict(self) -> dict:
        d = self.fit.to_dict()
        d.update(case=self.case, keys=list(self.keys), base_overrides=self.base_overrides,
                 reference_objective=self.reference_objective)
        return d


def evaluate_objective(case_name: str, data, values: dict, *, base_overrides=None, scale="known") -> float:
    """Weighted sum of squares (unit weights) of the case with ``values`` against ``data``."""
    t, y = _relative_times(data, scale)
    model = tracer_model(case_name, t, base_overrides=base_overrides, scale=scale, observed=y)
    return float(np.sum((y - model(values)) ** 2))


@single_threaded()
def fit_case_to_tracer(case_name: str, data, keys: Sequence[str] | Sequence[Parameter], *,
                       base_overrides: dict | None = None, method: str = "wls", n_starts: int = 2,
                       seed: int = 0, scale: str = "known", progress=None,
                       reference: dict | None = None, holdup: tuple[float, float] | None = None,
                       tracer_sigma: float | None = None, baseline: str = "none", executor=None) -> CaseFit:
    """Fit override keys of a case to a measured tracer curve ([`rotarydryer.rtd.TracerData`][rotarydryer.rtd.TracerData]).

    ``keys`` are override keys (start values and bounds from the case and
    `DEFAULT_BOUNDS`) or ready [`Parameter`][rotarydryer.estimation.cases.Parameter] objects. ``scale="fit"`` for a raw
    concentration of unknown scale or recovery. ``reference`` (values for the same keys,
    e.g. published estimates) is evaluated with the same model and weights and reported
    as ``reference_objective``.

    ``holdup=(value_kg, sigma_kg)`` adds a measured total holdup as a second data set; the
    tracer then needs its own standard deviation ``tracer_sigma`` (units of E, 1/s, or of
    the raw signal with ``scale="fit"``) so that the two are weighted against each other
    (``method="ml"`` estimates both variances instead).

    ``baseline="fit"`` adds a constant background of the signal (`BASELINE`, signal unit:
    1/s for E(t), ppm for Ajayi's raw lithium) as one more fitted parameter
    ([`baseline_parameter`][rotarydryer.estimation.cases.baseline_parameter]): y = A E(t) + b.

    ``executor`` ([`rotarydryer.executor.Executor`][rotarydryer.executor.Executor]) runs the starts (default serially; every backend
    gives the same fit).
    """
    check_choice("scale", scale, ("known", "fit"))
    check_choice("baseline", baseline, BASELINE_CHOICES)
    params = [k if isinstance(k, Parameter) else case_parameter(case_name, k, base_overrides) for k in keys]
    t, y = _relative_times(data, scale)
    if baseline == "fit":
        if BASELINE in [p.name for p in params]:
            raise ValueError(f"parameter {BASELINE!r} is given twice (it is added by baseline = 'fit')")
        params.append(baseline_parameter(y))
    if t.size <= len(params):
        raise ValueError(f"too few data points after the injection start: {t.size} for {len(params)} parameters")
    data_sets = [Dataset("tracer", y, None if tracer_sigma is None else np.full(y.shape, float(tracer_sigma)))]
    if holdup is not None:
        value, sigma = (float(v) for v in holdup)
        if not (value > 0 and sigma > 0):
            raise ValueError(f"holdup = {holdup!r} must be (value_kg > 0, sigma_kg > 0)")
        if method == "wls" and tracer_sigma is None:
            raise ValueError("fitting a tracer curve and a holdup together by wls needs tracer_sigma "
                             "(or method='ml', which estimates each data set's variance)")
        data_sets.append(Dataset("holdup", np.array([value]), np.array([sigma])))
    model = tracer_model(case_name, t, base_overrides=base_overrides, scale=scale, observed=y,
                         with_holdup=holdup is not None)
    res = fit(model, params, data_sets, method=method, n_starts=n_starts, seed=seed, progress=progress,
              executor=executor)
    ref = None
    if reference is not None:
        pred = model(dict(reference))
        pred = pred["tracer"] if isinstance(pred, dict) else pred
        ref = float(np.sum((y - pred) ** 2))
    return CaseFit(case_name, [p.name for p in params], dict(base_overrides or {}), t, y, res, ref,
                   model=model, parameters=params, datasets=data_sets)


def baseline_parameter(observed) -> Parameter:
    """The fitted constant background `BASELINE` (signal unit) for an observed tracer
    signal: start at the median of the lowest quarter of the samples (the background before the
    tracer arrives and after it has left), bounds +/- the largest |signal|."""
    y = np.asarray(observed, dtype=float)
    top = float(np.max(np.abs(y))) if y.size else 0.0
    if not top > 0:
        raise ValueError("baseline = 'fit' needs a signal with a non-zero value")
    low = np.sort(y)[: max(1, y.size // 4)]
    return Parameter(BASELINE, float(np.clip(np.median(low), -top, top)), -top, top, False)


def profile_case_fit(case_fit: CaseFit, names: Sequence[str] | None = None, *, n_points: int = 11,
                     span: float = 4.0, progress=None) -> dict:
    """Profile likelihood ([`rotarydryer.estimation.profile_likelihood`][rotarydryer.estimation.profile_likelihood]) of the parameters
    ``names`` (default all) of a [`CaseFit`][rotarydryer.estimation.cases.CaseFit]: {name: ProfileResult}. Each profile point
    re-fits the other parameters with the parameter held fixed, on a grid of ``n_points``
    values within +/- ``span`` Wald standard errors; the 95 % interval is where the objective
    rises by less than chi2(0.95, 1) = 3.84 (in units of the residual variance for wls).
    ``progress(name, k, n)`` after each parameter."""
    from .fit import profile_likelihood

    if case_fit.model is None:
        raise ValueError("this CaseFit carries no model (fit it with fit_case_to_tracer)")
    n = int(n_points)
    if n != n_points or not 3 <= n <= 101:
        raise ValueError(f"n_points = {n_points!r} must be an integer in [3, 101]")
    all_names = [p.name for p in case_fit.parameters]
    names = list(all_names if names is None else names)
    for k in names:
        check_choice("profile parameter", k, all_names)
    out = {}
    for i, k in enumerate(names):
        out[k] = profile_likelihood(case_fit.model, case_fit.parameters, case_fit.datasets, case_fit.fit, k,
                                    n_points=n, span=span)
        if progress is not None:
            progress(k, i + 1, len(names))
    return out

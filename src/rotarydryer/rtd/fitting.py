r"""Least-squares fitting of the reference RTD models to a tracer curve.

Model of the measured outlet signal (Levenspiel 1999 ch. 11 convolution):

$$
y(t) = A\,(E_\vartheta * u)(t - t_0 - \delta) + b
$$

with E the tanks-in-series (Lee (2008) Eq. 2.11), axial-dispersion or cell RTD
(interactive mixers with dead zones, Song (2003) Eq. 2.10-2.16) of
[`rotarydryer.rtd.models`][rotarydryer.rtd.models], u the normalised tracer input
([`pulse_input`][rotarydryer.rtd.pulse_input], Dirac by default), A an optional
unknown scale (the area of a raw concentration curve, signal unit × s; fixed
to 1 when the signal already is E in 1/s), δ an optional dead time (s) and b an
optional constant background (``fit_baseline``, signal unit; e.g. the lithium
background of Ajayi's raw ppm, about 0.56 ppm, notes ajayi_transport.md). The
number of cells N of the cell models is an integer (Song (2003) l.743); it is scanned
(each N a least-squares fit of the other parameters) unless given.

Estimation: ``scipy.optimize.least_squares`` (trust-region reflective, bounds)
on (optionally weighted) residuals r_i = (y_i - ŷ_i)/σ_i, with τ, N, Pe, k, α, β and A
optimised on a log scale (δ and b linear) (positivity, conditioning). Starting values come from
the curve's moments (method of moments, with the input's mean and variance
subtracted, since moments add under convolution); ``n_starts`` > 1 adds
starts scattered around it and keeps the best (all objectives reported).

Uncertainty: the Jacobian J of the residuals with respect to the natural
parameters is recomputed at the optimum by central differences; the
covariance is $s^2 (J^T J)^{-1}$ with $s^2 = \sum r_i^2/(n-p)$
(the residual variance is estimated from the fit, i.e. σ_i are relative
weights, as ``curve_fit(absolute_sigma=False)``); 95 % intervals are
est ± t(0.975, n-p)·SE; the correlation matrix is cov_ij/√(cov_ii cov_jj).
A near-singular JᵀJ (condition number > 1e12), a pair of parameters with
|correlation| > 0.999, a parameter at its bound and non-convergence are reported
in ``RTDFit.warnings`` (and issued as ``RuntimeWarning``).
These linearised intervals assume independent errors of constant (weighted)
variance; tracer data with a systematic misfit (e.g. Lee's Invicta tail) give
intervals that are too narrow, which ``r_squared`` and the residuals reveal.
"""

from __future__ import annotations

import math
import warnings as _warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy import optimize

from .._validation import check_choice, check_finite, check_range
from ..estimation.uncertainty import cut_interval, linearised_uncertainty
from ._datafile import fmt
from .analysis import rtd_moments
from .models import (
    AnalyticMoments,
    AxialDispersion,
    CholetteCloutier,
    TanksInSeries,
    axial_dispersion_moments,
)
from .pulses import TracerPulse, convolve_rtd, convolved_moments, pulse_input

__all__ = ["RTDFit", "fit_rtd_model", "fit_tracer_data", "RTD_MODELS", "CELL_MODELS", "RTD_FIT_MODELS"]

#: the classical reference models (fitted together by :func:`rotarydryer.results.fit_measured_rtd`)
RTD_MODELS = ("tanks_in_series", "dispersion_closed", "dispersion_open")
#: Song (2003) Eq. 2.10-2.16 cell models (integer N scanned): interactive mixers, and with dead zones
CELL_MODELS = ("interactive_mixers", "cholette_cloutier")
#: every model :func:`fit_rtd_model` (and ``rotarydryer rtd-fit --model``) accepts
RTD_FIT_MODELS = RTD_MODELS + CELL_MODELS
_VESSEL = {
    "tanks_in_series": ("mean_residence_time_s", "n_tanks"),
    "dispersion_closed": ("space_time_s", "peclet"),
    "dispersion_open": ("space_time_s", "peclet"),
    "interactive_mixers": ("conductance_per_s",),
    "cholette_cloutier": ("conductance_per_s", "active_fraction", "exchange_ratio"),
}
_SHAPE_BOUNDS = {"n_tanks": (1.0, 1e6), "peclet": (1e-2, 1e7), "active_fraction": (1e-4, 1.0),
                 "exchange_ratio": (1e-6, 1e6)}
#: largest N of the integer scan of the cell models
MAX_SCAN_CELLS = 5000
#: start of the dead-zone parameters of ``cholette_cloutier`` (alpha, beta)
_CC_START = (0.8, 0.5)
#: more starts (alpha, beta) of ``cholette_cloutier``: nearly the interactive mixers (which it
#: contains), a small fast and a large slow dead zone
_CC_GRID = ((0.97, 1.0), (0.9, 0.05), (0.7, 0.01))


def _make_model(kind, values, n_cells=None):
    if kind == "tanks_in_series":
        return TanksInSeries(values["mean_residence_time_s"], values["n_tanks"])
    if kind in ("dispersion_closed", "dispersion_open"):
        return AxialDispersion(values["space_time_s"], values["peclet"],
                               "closed" if kind == "dispersion_closed" else "open")
    if kind == "interactive_mixers":
        return CholetteCloutier(int(n_cells), values["conductance_per_s"])
    return CholetteCloutier(int(n_cells), values["conductance_per_s"], values["active_fraction"],
                            values["exchange_ratio"])


@dataclass(frozen=True, eq=False)
class RTDFit:
    """Result of [`fit_rtd_model`][rotarydryer.rtd.fitting.fit_rtd_model].

    Attributes
    ----------
    model : model name (one of ``RTD_FIT_MODELS``).
    parameter_names : names of the fitted parameters, in order
        (``mean_residence_time_s``/``space_time_s`` (s), ``n_tanks``/``peclet`` (-), or
        ``conductance_per_s`` (1/s) [, ``active_fraction``, ``exchange_ratio`` (-)] of the
        cell models, then ``scale`` (signal unit × s), ``delay_s`` (s) and ``baseline``
        (signal unit) if fitted).
    values, std_errors, ci_low, ci_high : dicts name -> float (same units).
    covariance, correlation : (p, p) arrays in the order of parameter_names.
    objective : weighted sum of squared residuals at the optimum.
    r_squared : 1 - SSR/SST (unweighted) (-).
    n_points, n_evaluations : data points; model evaluations (all starts,
        including the Jacobian for the covariance).
    start_objectives : objective reached from each start.
    rtd_moments : analytic moments of the fitted vessel RTD E(t) (no input, no delay).
    outlet_moments : moments of the predicted outlet curve (RTD + delay + input).
    fixed : fixed values used (scale = 1 and/or delay_s = 0 when not fitted; ``n_cells``
        of the cell models, an integer chosen by the scan or given, held fixed in the
        covariance).
    n_cells_scan : cell models: objective of each N tried by the integer scan.
    warnings : identifiability / convergence warnings (strings).
    """

    model: str
    parameter_names: tuple
    values: dict
    std_errors: dict
    ci_low: dict
    ci_high: dict
    covariance: np.ndarray = field(repr=False)
    correlation: np.ndarray = field(repr=False)
    objective: float = 0.0
    r_squared: float = 0.0
    n_points: int = 0
    n_evaluations: int = 0
    start_objectives: tuple = ()
    rtd_moments: AnalyticMoments | None = None
    outlet_moments: AnalyticMoments | None = None
    fixed: dict = field(default_factory=dict)
    time_origin_s: float = 0.0
    pulse: TracerPulse | None = field(default=None, repr=False)
    residuals: np.ndarray | None = field(default=None, repr=False)
    warnings: tuple = ()
    n_cells_scan: dict = field(default_factory=dict)

    def vessel_model(self):
        """The fitted reference model object (TanksInSeries, AxialDispersion or CholetteCloutier)."""
        return _make_model(self.model, self.values, self.fixed.get("n_cells"))

    def predict(self, time_s):
        """Predicted outlet signal at ``time_s`` (s, same clock as the data), with the fitted
        baseline when there is one."""
        p = {**self.fixed, **self.values}
        t = check_finite("time_s", time_s) - self.time_origin_s - p["delay_s"]
        m = self.vessel_model()
        out = m.outlet(t, self.pulse) if hasattr(m, "outlet") else convolve_rtd(m.e, t, self.pulse)
        return p["scale"] * out + p.get("baseline", 0.0)

    def to_dict(self) -> dict[str, Any]:
        """JSON-friendly summary: parameters with value/std_error/ci_low/ci_high, statistics, moments."""
        out = {
            "model": self.model,
            "parameters": {
                k: {
                    "value": self.values[k],
                    "std_error": self.std_errors[k],
                    "ci_low": self.ci_low[k],
                    "ci_high": self.ci_high[k],
                }
                for k in self.parameter_names
            },
            "fixed": dict(self.fixed),
            "correlation": np.asarray(self.correlation).tolist(),
            "objective": self.objective,
            "r_squared": self.r_squared,
            "n_points": self.n_points,
            "n_evaluations": self.n_evaluations,
            "start_objectives": list(self.start_objectives),
            "rtd_moments": self.rtd_moments.to_dict() if self.rtd_moments else None,
            "outlet_moments": self.outlet_moments.to_dict() if self.outlet_moments else None,
            "warnings": list(self.warnings),
        }
        if self.n_cells_scan:
            out["n_cells_scan"] = {str(n): v for n, v in sorted(self.n_cells_scan.items())}
        return out


def _pe_from_relative_variance(kind, rel_var):
    """Invert the analytic variance/mean² relation of the ADM for Pe (method of moments)."""
    boundary = "closed" if kind == "dispersion_closed" else "open"

    def g(pe):
        m = axial_dispersion_moments(1.0, pe, boundary)
        return m.variance_s2 / m.mean_s**2 - rel_var

    lo, hi = _SHAPE_BOUNDS["peclet"]
    if g(lo) < 0:
        return lo
    if g(hi) > 0:
        return hi
    return optimize.brentq(g, lo, hi, xtol=1e-10, rtol=1e-10)


def _mixers_cells(rel_var):
    """N (real, >= 1) of interactive mixers with var/mean^2 = ``rel_var``: the root of
    2(2N+1)/(3N(N+1)) = rel_var (moments of Song (2003) Eq. 2.10 with alpha = 1)."""
    rv = max(float(rel_var), 1e-12)
    b = 3.0 * rv - 4.0
    return max((-b + math.sqrt(b * b + 24.0 * rv)) / (6.0 * rv), 1.0)


def _background_start(y):
    """Start of a fitted constant background: the median of the lowest quarter of the samples."""
    q = np.sort(y)[: max(1, y.size // 4)]
    return float(np.median(q))


def _moment_start(kind, t, y, t0, pulse, fit_delay):
    m = rtd_moments(t, np.maximum(y, 0.0), time_origin_s=t0)
    mean = m.mean_s - pulse.mean_s
    var = max(m.variance_s2 - pulse.variance_s2, 1e-6 * m.variance_s2)
    delay = 0.0
    if fit_delay:
        ts = t - t0
        above = np.nonzero(y > 0.05 * np.max(y))[0]
        t_br = max(float(ts[above[0]]) - pulse.duration_s, 0.0)
        delay = 0.5 * min(t_br, max(mean - math.sqrt(var), 0.0))
        mean -= delay
    mean = max(mean, 1e-9 * max(abs(m.mean_s), 1.0))
    extra = {}
    if kind == "tanks_in_series":
        start = {"mean_residence_time_s": mean, "n_tanks": float(np.clip(mean**2 / var, *_SHAPE_BOUNDS["n_tanks"]))}
    elif kind in CELL_MODELS:
        alpha, beta = (1.0, 1.0) if kind == "interactive_mixers" else _CC_START
        c = (1.0 - alpha) / alpha
        factor = 1.0 + 2.0 * c * c / (beta * (1.0 + c) ** 2)
        extra["n_cells"] = int(min(round(_mixers_cells(var / mean**2 / factor)), MAX_SCAN_CELLS))
        extra["mean"] = mean
        start = {"active_fraction": alpha, "exchange_ratio": beta}
    else:
        pe = _pe_from_relative_variance(kind, var / mean**2)
        start = {"space_time_s": mean if kind == "dispersion_closed" else mean / (1 + 2 / pe), "peclet": pe}
    return start, m.area, delay, extra


def _conductance_for_mean(n, mean, alpha):
    """k (1/s) of N interactive mixers with active fraction alpha and this mean (s)."""
    return n * (n + 1.0) / (2.0 * mean * alpha)


def fit_rtd_model(
    time_s,
    signal,
    model: str = "tanks_in_series",
    *,
    pulse: TracerPulse | None = None,
    time_origin_s: float = 0.0,
    fit_scale: bool = False,
    fit_delay: bool = False,
    fit_baseline: bool = False,
    n_cells: int | None = None,
    sigma=None,
    initial: dict | None = None,
    n_starts: int = 1,
    seed: int = 0,
    max_nfev: int = 2000,
) -> RTDFit:
    """Fit a reference RTD model to a tracer curve.

    Parameters
    ----------
    time_s : 1-D array, sample times (s), strictly increasing.
    signal : 1-D array. With ``fit_scale=False`` it must be E(t) in 1/s;
        otherwise any unit (the fitted ``scale`` is its area, unit × s).
    model : one of ``RTD_FIT_MODELS``: ``"tanks_in_series"``, ``"dispersion_closed"``,
        ``"dispersion_open"``, ``"interactive_mixers"`` (Song (2003) Section 2.7 model 1:
        N, k) or ``"cholette_cloutier"`` (Song Eq. 2.10-2.16: N, k, alpha, beta).
    pulse : tracer input ([`pulse_input`][rotarydryer.rtd.fitting.pulse_input]), default Dirac.
    time_origin_s : start of the injection on the ``time_s`` clock (s).
    fit_scale : fit an unknown scale A (raw concentration / incomplete recovery).
    fit_delay : fit a dead time δ (s) >= 0 (plug-flow delay before the vessel).
    fit_baseline : fit a constant background b (signal unit) added to the model curve,
        y = A (E * u)(t - t0 - δ) + b (e.g. the lithium background of Ajayi's raw ppm).
    n_cells : cell models only: the number of cells N (integer); default None scans the
        integers (Song (2003) l.743: N takes integer values) from the moment estimate to the
        best least-squares objective (expanding bracket, then integer section search).
    sigma : optional scalar or array of measurement standard deviations
        (relative weights; residual variance still estimated from the fit).
    initial : optional starting values by parameter name (overrides the
        method-of-moments start).
    n_starts : number of starts (>= 1); extra starts are log-uniform within a
        factor 3 of the first (``seed`` for the generator).
    max_nfev : evaluation budget per start.

    Returns
    -------
    RTDFit
    """
    check_choice("model", model, RTD_FIT_MODELS)
    t = check_finite("time_s", time_s)
    y = check_finite("signal", signal)
    if t.ndim != 1 or t.shape != y.shape:
        raise ValueError(f"time_s and signal must be 1-D of equal length, got {t.shape} and {y.shape}")
    if np.any(np.diff(t) <= 0):
        raise ValueError("time_s must be strictly increasing (sort the data and remove duplicate times)")
    pulse = pulse_input("dirac") if pulse is None else pulse
    if not isinstance(pulse, TracerPulse):
        raise ValueError(f"pulse must be a TracerPulse from pulse_input(), got {type(pulse).__name__}")
    t0 = float(check_finite("time_origin_s", time_origin_s))
    if t.size and t0 >= t[-1]:
        raise ValueError(
            f"time_origin_s = {fmt(t0)} s is at or after the last sample ({fmt(t[-1])} s); the tracer "
            "injection must start before the data end"
        )
    if t.size and not np.any(y[t > t0] > 0):
        raise ValueError(f"time_origin_s = {fmt(t0)} s is after all the positive signal: nothing to fit")
    n_starts = int(check_range("n_starts", n_starts, 1, 1000, low_inclusive=True, high_inclusive=True))
    cells = model in CELL_MODELS
    if n_cells is not None:
        if not cells:
            raise ValueError(f"n_cells = {n_cells!r} applies only to the cell models ({', '.join(CELL_MODELS)}), "
                             f"not to model = {model!r}")
        nc = float(check_range("n_cells", n_cells, 1, MAX_SCAN_CELLS, low_inclusive=True, high_inclusive=True))
        if nc != int(nc):
            raise ValueError(f"n_cells = {n_cells!r} must be an integer in [1, {MAX_SCAN_CELLS}]")
        n_cells = int(nc)
    w = np.ones_like(y) if sigma is None else np.broadcast_to(check_range("sigma", sigma, 0.0, math.inf), y.shape)
    vessel = list(_VESSEL[model])
    names = vessel + (["scale"] if fit_scale else []) + (["delay_s"] if fit_delay else [])
    names += ["baseline"] if fit_baseline else []
    linear = {"delay_s", "baseline"}
    p = len(names)
    if y.size <= p:
        raise ValueError(f"{y.size} data points cannot determine {p} parameters {names}")
    if not np.max(y) > 0:
        raise ValueError("signal has no positive value; nothing to fit")
    if not np.ptp(y) > 0:
        raise ValueError(f"signal is {fmt(float(y[0]))} at every sample: no tracer pulse to fit")

    b0 = _background_start(y) if fit_baseline else 0.0
    y_net = y - b0
    if not np.max(y_net) > 0:
        y_net = y
    vstart, area0, delay0, extra = _moment_start(model, t, y_net, t0, pulse, fit_delay)
    start = {**vstart, "scale": area0, "delay_s": delay0, "baseline": b0}
    area_ref = abs(float(np.trapezoid(np.maximum(y_net, 0.0), t))) or 1.0
    if initial:
        allowed = [n for n in names if not (cells and n == "conductance_per_s")] if n_cells is None else names
        for k, v in initial.items():
            if k not in allowed:
                raise ValueError(f"initial has unknown or unfitted parameter {k!r}; fitted parameters: {allowed}")
            start[k] = float(check_finite(f"initial[{k!r}]", v))
    span = float(t[-1] - t0)
    delay_hi = max(span, 1.0)
    nfev = [0]

    def bounds(n):
        """Natural bounds of every fitted parameter for N = n cells (cell models)."""
        out = {}
        for k in names:
            if k in ("mean_residence_time_s", "space_time_s"):
                out[k] = (1e-9 * max(span, 1.0), 1e3 * max(span, 1.0))
            elif k == "conductance_per_s":
                s1 = n * (n + 1.0) / 2.0
                out[k] = (s1 / (1e3 * max(span, 1.0)), s1 / (1e-9 * max(span, 1.0)))
            elif k in _SHAPE_BOUNDS:
                out[k] = _SHAPE_BOUNDS[k]
            elif k == "scale":   # the tracer mostly inside the record (recovery >= 10 %)
                out[k] = (0.1 * area_ref, 10.0 * area_ref)
            elif k == "delay_s":
                out[k] = (0.0, delay_hi)
            else:
                out[k] = (-math.inf, math.inf)
        return out

    def to_natural(x, n=None):
        d = {k: (float(x[j]) if k in linear else math.exp(x[j])) for j, k in enumerate(names)}
        if cells:   # optimised in log(mean of the vessel) = log(N(N+1)/(2 k alpha)): k follows
            d["conductance_per_s"] = _conductance_for_mean(n, d.pop("conductance_per_s"),
                                                           d.get("active_fraction", 1.0))
        return d

    def to_x(d, n=None):
        if cells:
            d = dict(d, conductance_per_s=_conductance_for_mean(n, d["conductance_per_s"],
                                                                 d.get("active_fraction", 1.0)))
        return np.array([d[k] if k in linear else math.log(d[k]) for k in names])

    def x_bounds(n):
        bn = bounds(n)
        if cells:
            bn["conductance_per_s"] = (1e-9 * max(span, 1.0), 1e3 * max(span, 1.0))   # the vessel mean, s
        lb = [bn[k][0] if k in linear else (math.log(bn[k][0]) if bn[k][0] > 0 else -math.inf) for k in names]
        ub = [bn[k][1] if k in linear else (math.log(bn[k][1]) if math.isfinite(bn[k][1]) else math.inf)
              for k in names]
        return np.array(lb, float), np.array(ub, float)

    def predict(d, n):
        nfev[0] += 1
        m = _make_model(model, d, n)
        ts = t - t0 - d.get("delay_s", 0.0)
        out = m.outlet(ts, pulse) if hasattr(m, "outlet") else convolve_rtd(m.e, ts, pulse)
        return d.get("scale", 1.0) * out + d.get("baseline", 0.0)

    def fit_at(n, x_starts, tol=1e-12):
        """Least squares with N = n cells from the starts ``x_starts`` (optimiser space) and
        ``n_starts - 1`` scattered around the first: (result, objectives, start x's)."""
        lb, ub = x_bounds(n)
        x0 = np.clip(x_starts[0], lb + 1e-12, ub - 1e-12)
        rng = np.random.default_rng(seed)
        starts = [x0]
        nv = len(vessel)
        for _ in range(n_starts - 1):
            xs = x0.copy()
            xs[:nv] += rng.uniform(-math.log(3), math.log(3), nv)
            if fit_delay:
                j = names.index("delay_s")
                xs[j] = rng.uniform(0, 2 * max(x0[j], 1e-3 * span))
            starts.append(np.clip(xs, lb + 1e-12, ub - 1e-12))
        starts += [np.clip(xs, lb + 1e-12, ub - 1e-12) for xs in x_starts[1:]]

        def resid_x(x):
            return (predict(to_natural(x, n), n) - y) / w

        best, objs = None, []
        for xs in starts:
            res = optimize.least_squares(
                resid_x, xs, bounds=(lb, ub), method="trf", x_scale="jac", max_nfev=max_nfev,
                ftol=tol, xtol=tol, gtol=tol,
            )
            objs.append(float(2 * res.cost))
            if best is None or res.cost < best.cost:
                best = res
        return best, objs, starts

    def first_x(n):
        """Start (optimiser space) from the moment start and ``initial``, checked against the bounds."""
        sv = dict(start)
        if cells:
            sv["conductance_per_s"] = _conductance_for_mean(n, extra["mean"], sv.get("active_fraction", 1.0))
            if initial and "conductance_per_s" in initial:
                sv["conductance_per_s"] = float(initial["conductance_per_s"])
        for k in names:
            if k not in linear and not sv[k] > 0:
                raise ValueError(f"starting value {k} = {fmt(sv[k])} must be > 0")
        if initial:
            bn = bounds(n)
            for k in names:
                if k in initial and not bn[k][0] <= sv[k] <= bn[k][1]:
                    raise ValueError(f"initial {k} = {fmt(initial[k])} is outside the fitting bounds "
                                     f"[{bn[k][0]:g}, {bn[k][1]:g}]")
        return to_x(sv, n)

    def dead_zone_grid(n, x):
        """More starts of ``cholette_cloutier``: the grid _CC_GRID of (alpha, beta) at the mean of ``x``
        (the model has several local optima: a fast, small or a slow, large dead zone)."""
        if model != "cholette_cloutier" or (initial and {"active_fraction", "exchange_ratio"} & set(initial)):
            return []
        ja, jb = names.index("active_fraction"), names.index("exchange_ratio")
        out = []
        for a_, b_ in _CC_GRID:
            xs = np.array(x, float)
            xs[ja], xs[jb] = math.log(a_), math.log(b_)
            out.append(xs)
        return out

    if cells and n_cells is None:
        # N and the other starts from a tanks-in-series fit (same options): the cell models' relative
        # variance 2(2N+1)/(3N(N+1)) matched to the fitted 1/n_tanks
        with _warnings.catch_warnings():
            _warnings.simplefilter("ignore", RuntimeWarning)
            tis = fit_rtd_model(t, y, "tanks_in_series", pulse=pulse, time_origin_s=t0, fit_scale=fit_scale,
                                fit_delay=fit_delay, fit_baseline=fit_baseline, sigma=sigma, max_nfev=max_nfev)
        nfev[0] += tis.n_evaluations
        if not initial:
            rv = 1.0 / tis.values["n_tanks"]
            if model == "cholette_cloutier":
                c = (1.0 - _CC_START[0]) / _CC_START[0]
                rv /= 1.0 + 2.0 * c * c / (_CC_START[1] * (1.0 + c) ** 2)
            extra["n_cells"] = int(min(round(_mixers_cells(rv)), MAX_SCAN_CELLS))
            extra["mean"] = tis.values["mean_residence_time_s"]
            start.update({k: v for k, v in tis.values.items() if k in ("scale", "delay_s", "baseline")})
    scan = {}
    if not cells:
        best, objs, starts = fit_at(None, [first_x(None)])
        n_best = None
    else:
        fits: dict = {}

        def warm(n):
            """The best fit so far (its mean kept; alpha below 0.99 so that beta matters), or the
            first start and the dead-zone grid."""
            if not fits:
                x = first_x(n)
                return [x] + dead_zone_grid(n, x)
            x = np.array(min(fits.values(), key=lambda f: f[0].cost)[0].x, float)
            if model == "cholette_cloutier":
                ja = names.index("active_fraction")
                x[ja] = min(x[ja], math.log(0.99))
            return [x]

        def objective(n):
            # the scan's fits stop at a relative tolerance of 1e-8; the chosen N is refined below
            n = int(min(max(n, 1), MAX_SCAN_CELLS))
            if n not in fits:
                fits[n] = fit_at(n, warm(n), tol=1e-8)
                scan[n] = float(2 * fits[n][0].cost)
            return scan[n]

        n_best = n_cells if n_cells is not None else _integer_minimum(objective, extra["n_cells"], MAX_SCAN_CELLS)
        objective(n_best)
        best, objs, starts = fit_at(n_best, [np.array(fits[n_best][0].x, float)])
        scan[n_best] = float(2 * best.cost)
    warn = []
    if not best.success:
        warn.append(f"least_squares did not converge: {best.message}")
    est = to_natural(best.x, n_best)
    if np.allclose(best.x, starts[int(np.argmin(objs))]) and best.nfev <= 1:
        warn.append("the optimiser did not move from the starting point")

    def resid_nat(d):
        return (predict(d, n_best) - y) / w

    # Jacobian in natural parameters (central differences) at the optimum; one-sided at a bound
    bn = bounds(n_best)
    r0 = resid_nat(est)
    J = np.empty((y.size, p))
    for j, k in enumerate(names):
        lower, upper = bn[k]
        if k == "scale":
            lower = -math.inf
        h = 1e-6 * max(abs(est[k]), 1e-3 * (span if k == "delay_s" else 1.0))
        dp, dm = dict(est), dict(est)
        dp[k], dm[k] = est[k] + h, est[k] - h
        if est[k] - h < lower:
            J[:, j] = (resid_nat(dp) - r0) / h
        elif est[k] + h > upper:
            J[:, j] = (r0 - resid_nat(dm)) / h
        else:
            J[:, j] = (resid_nat(dp) - resid_nat(dm)) / (2 * h)
    ssr = float(r0 @ r0)
    # s^2 = SSR/(n - p); inverse unless cond(J^T J) >= 1e12, then the pseudo-inverse
    unc = linearised_uncertainty(J, r0, estimates=[est[k] for k in names], inverse="inv",
                                 singular_rtol=1e-6, correlation_threshold=0.999)
    cov, se, corr = unc.covariance, unc.std_errors, unc.correlation
    if unc.singular:
        warn.append(
            f"J^T J is near-singular (condition number {unc.condition_number:.3g}): the parameters are not all "
            "identifiable from these data; standard errors are unreliable"
        )
    for i, j, r in unc.correlated_pairs:
        warn.append(
            f"{names[i]} and {names[j]} are strongly correlated (r = {r:.3f}): the data "
            "barely separate them; consider fixing one"
        )
    for k in names:
        if k == "n_tanks" and abs(est[k] - bn[k][0]) < 1e-6 * bn[k][0]:
            warn.append(f"{k} is at its lower bound {bn[k][0]:g}; the interval is not meaningful")
        if k == "delay_s" and est[k] < 1e-9 * max(span, 1.0):
            warn.append("delay_s is at its lower bound 0; the interval is not meaningful")
        if k == "active_fraction" and est[k] > 1.0 - 1e-6:
            warn.append("active_fraction is at its upper bound 1 (no dead zone): exchange_ratio is not identifiable")
        if k == "exchange_ratio" and not bn[k][0] * (1 + 1e-6) < est[k] < bn[k][1] * (1 - 1e-6):
            warn.append(f"exchange_ratio = {est[k]:.3g} is at a bound; the interval is not meaningful")
    if cells and n_cells is None and n_best in (1, MAX_SCAN_CELLS):
        warn.append(f"the integer scan ended at N = {n_best}, a limit of the scan [1, {MAX_SCAN_CELLS}]")
    yhat = predict(est, n_best)
    sst = float(np.sum((y - y.mean()) ** 2))
    r2 = 1.0 - float(np.sum((y - yhat) ** 2)) / sst if sst > 0 else float("nan")
    vessel_model = _make_model(model, est, n_best)
    vm = vessel_model.moments()
    delay = est.get("delay_s", 0.0)
    om = convolved_moments(vm, pulse)
    om = AnalyticMoments(mean_s=om.mean_s + delay, variance_s2=om.variance_s2, skewness=om.skewness)
    fixed = {}
    if not fit_scale:
        fixed["scale"] = 1.0
    if not fit_delay:
        fixed["delay_s"] = 0.0
    if cells:
        assert n_best is not None      # set by the scan over the cell counts
        fixed["n_cells"] = int(n_best)
    ci_low, ci_high = unc.ci_low, unc.ci_high
    assert ci_low is not None and ci_high is not None     # linearised_uncertainty gives both
    ci_low, ci_high = np.array(ci_low, float), np.array(ci_high, float)
    for j, k in enumerate(names):
        # intervals within the physical range (a negative mean residence time or tank count is none): the shape
        # parameters' own (a tank count >= 1, a fraction <= 1); the times, the scale and the delay >= 0 (their
        # search bounds are not physical limits)
        lo_k, hi_k = bn[k] if k in _SHAPE_BOUNDS else ((0.0, math.inf) if bn[k][0] >= 0 else (-math.inf, math.inf))
        ci_low[j], ci_high[j], cut = cut_interval(k, ci_low[j], ci_high[j], lo_k, hi_k)
        if cut:
            warn.append(cut)
    for msg in warn:
        _warnings.warn(msg, RuntimeWarning, stacklevel=2)
    return RTDFit(
        model=model,
        parameter_names=tuple(names),
        values={k: float(est[k]) for k in names},
        std_errors={k: float(se[j]) for j, k in enumerate(names)},
        ci_low={k: float(ci_low[j]) for j, k in enumerate(names)},
        ci_high={k: float(ci_high[j]) for j, k in enumerate(names)},
        covariance=cov,
        correlation=corr,
        objective=ssr,
        r_squared=float(r2),
        n_points=int(y.size),
        n_evaluations=int(nfev[0]),
        start_objectives=tuple(objs),
        rtd_moments=vm,
        outlet_moments=om,
        fixed=fixed,
        time_origin_s=t0,
        pulse=pulse,
        residuals=r0,
        warnings=tuple(warn),
        n_cells_scan=dict(scan),
    )


def _integer_minimum(f, n0: int, n_max: int) -> int:
    """Integer n in [1, n_max] minimising ``f`` (assumed unimodal near its minimum), from ``n0``:
    a bracket grown by factors 1.6 in the descending direction, then parabolic steps in log n
    (the curve's relative variance goes as 1/N) with golden-section steps as the fallback."""
    n0 = int(min(max(n0, 1), n_max))
    if n_max == 1:
        return 1
    a = n0
    b = a + 1 if a < n_max else a - 1
    if f(b) > f(a):
        a, b = b, a
        c = b - 1 if b > 1 else None
        if c is None or f(c) >= f(b):
            return b
        a, b = b, c
    d = 1 if b > a else -1
    while True:
        c = int(min(max(round(b * 1.6 ** d), 1), n_max))
        if c == b:          # at a limit of the scan, still descending: is the limit the minimum?
            inner = b - d
            if inner == a or f(inner) >= f(b):
                return b
            a, b, c = a, inner, b
            break
        if f(c) >= f(b):
            break
        a, b = b, c
    lo, mid, hi = min(a, c), b, max(a, c)
    while hi - lo > 2:
        v = np.log([lo, mid, hi])
        fv = np.array([f(lo), f(mid), f(hi)])
        den = (v[1] - v[0]) * (fv[1] - fv[2]) - (v[1] - v[2]) * (fv[1] - fv[0])
        cand = None
        if den != 0.0:
            num = (v[1] - v[0]) ** 2 * (fv[1] - fv[2]) - (v[1] - v[2]) ** 2 * (fv[1] - fv[0])
            vs = v[1] - 0.5 * num / den
            if np.isfinite(vs):
                cand = int(round(math.exp(min(vs, 50.0))))
        if cand is None or not lo < cand < hi or cand == mid:
            cand = int(round(mid + 0.382 * (hi - mid))) if hi - mid >= mid - lo else int(round(mid - 0.382 * (mid - lo)))
            if cand in (lo, mid, hi):
                cand = mid + 1 if hi - mid > 1 else mid - 1
        if f(cand) < f(mid):
            lo, hi = (mid, hi) if cand > mid else (lo, mid)
            mid = cand
        elif cand > mid:
            hi = cand
        else:
            lo = cand
    return min(range(lo, hi + 1), key=f)


def fit_tracer_data(data, model: str = "tanks_in_series", **kwargs) -> RTDFit:
    """Fit a [`TracerData`][rotarydryer.rtd.TracerData] curve.

    Uses the file's ``time_origin_s`` and tracer input (``pulse_kind``,
    ``pulse_duration_s``) unless given. A signal in a normalised unit (1/s,
    1/min, 1/h) is converted to E in 1/s and fitted with a fixed scale of 1
    unless ``fit_scale=True``; any other unit needs ``fit_scale=True``
    (default then) so that the area is estimated.
    """
    kwargs.setdefault("time_origin_s", data.time_origin_s)
    kwargs.setdefault("pulse", data.pulse())
    y = np.asarray(data.signal, float)
    unit = data.signal_unit
    rate = data.rate_factor
    if rate is not None:
        y = y * rate
        kwargs.setdefault("fit_scale", False)
    else:
        kwargs.setdefault("fit_scale", True)
        if not kwargs["fit_scale"]:
            raise ValueError(
                f"the signal's unit ({unit or 'not given'}) is not a normalised RTD's (1/s, 1/min, 1/h), so its scale "
                "must be fitted: fit_scale=True (on the command line --scale, the default, not --no-scale)"
            )
    if "sigma" in kwargs and kwargs["sigma"] is not None and rate is not None:
        kwargs["sigma"] = np.asarray(kwargs["sigma"], float) * rate
    return fit_rtd_model(data.time_s, y, model, **kwargs)

r"""Least-squares fitting of the classical RTD models to a tracer curve.

Model of the measured outlet signal (Levenspiel 1999 ch. 11 convolution):

.. math:: y(t) = A\,(E_\vartheta * u)(t - t_0 - \delta)

with E the tanks-in-series (Lee (2008) Eq. 2.11) or axial-dispersion RTD of
:mod:`rotarydryer.rtd.models`, u the normalised tracer input
(:func:`~rotarydryer.rtd.pulse_input`, Dirac by default), A an optional
unknown scale (the area of a raw concentration curve, signal unit × s; fixed
to 1 when the signal already is E in 1/s) and δ an optional dead time (s).

Estimation: ``scipy.optimize.least_squares`` (trust-region reflective, bounds)
on (optionally weighted) residuals r_i = (y_i - ŷ_i)/σ_i, with τ, N or Pe and A
optimised on a log scale (positivity, conditioning). Starting values come from
the curve's moments (method of moments, with the input's mean and variance
subtracted, since moments add under convolution); ``n_starts`` > 1 adds
starts scattered around it and keeps the best (all objectives reported).

Uncertainty: the Jacobian J of the residuals with respect to the natural
parameters is recomputed at the optimum by central differences; the
covariance is :math:`s^2 (J^T J)^{-1}` with :math:`s^2 = \sum r_i^2/(n-p)`
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
from ..estimation.uncertainty import linearised_uncertainty
from ._datafile import fmt
from .analysis import rtd_moments
from .models import (
    AnalyticMoments,
    AxialDispersion,
    TanksInSeries,
    axial_dispersion_moments,
)
from .pulses import TracerPulse, convolve_rtd, convolved_moments, pulse_input

__all__ = ["RTDFit", "fit_rtd_model", "fit_tracer_data", "RTD_MODELS"]

RTD_MODELS = ("tanks_in_series", "dispersion_closed", "dispersion_open")
_SHAPE_NAME = {"tanks_in_series": "n_tanks", "dispersion_closed": "peclet", "dispersion_open": "peclet"}
_TAU_NAME = {
    "tanks_in_series": "mean_residence_time_s",
    "dispersion_closed": "space_time_s",
    "dispersion_open": "space_time_s",
}
_SHAPE_BOUNDS = {"n_tanks": (1.0, 1e6), "peclet": (1e-2, 1e7)}


def _make_model(kind, tau, shape):
    if kind == "tanks_in_series":
        return TanksInSeries(tau, shape)
    return AxialDispersion(tau, shape, "closed" if kind == "dispersion_closed" else "open")


@dataclass(frozen=True, eq=False)
class RTDFit:
    """Result of :func:`fit_rtd_model`.

    Attributes
    ----------
    model : model name (one of ``RTD_MODELS``).
    parameter_names : names of the fitted parameters, in order
        (``mean_residence_time_s``/``space_time_s`` (s), ``n_tanks``/``peclet`` (-),
        then ``scale`` (signal unit × s) and ``delay_s`` (s) if fitted).
    values, std_errors, ci_low, ci_high : dicts name -> float (same units).
    covariance, correlation : (p, p) arrays in the order of parameter_names.
    objective : weighted sum of squared residuals at the optimum.
    r_squared : 1 - SSR/SST (unweighted) (-).
    n_points, n_evaluations : data points; model evaluations (all starts,
        including the Jacobian for the covariance).
    start_objectives : objective reached from each start.
    rtd_moments : analytic moments of the fitted vessel RTD E(t) (no input, no delay).
    outlet_moments : moments of the predicted outlet curve (RTD + delay + input).
    fixed : fixed values used (scale = 1 and/or delay_s = 0 when not fitted).
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
    residuals: np.ndarray = field(default=None, repr=False)
    warnings: tuple = ()

    def vessel_model(self):
        """The fitted reference model object (TanksInSeries or AxialDispersion)."""
        return _make_model(self.model, self.values[self.parameter_names[0]], self.values[self.parameter_names[1]])

    def predict(self, time_s):
        """Predicted outlet signal at ``time_s`` (s, same clock as the data)."""
        p = {**self.fixed, **self.values}
        t = check_finite("time_s", time_s) - self.time_origin_s - p["delay_s"]
        return p["scale"] * convolve_rtd(self.vessel_model().e, t, self.pulse)

    def to_dict(self) -> dict[str, Any]:
        """JSON-friendly summary: parameters with value/std_error/ci_low/ci_high, statistics, moments."""
        return {
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
    if kind == "tanks_in_series":
        shape = float(np.clip(mean**2 / var, *_SHAPE_BOUNDS["n_tanks"]))
        tau = mean
    else:
        shape = _pe_from_relative_variance(kind, var / mean**2)
        tau = mean if kind == "dispersion_closed" else mean / (1 + 2 / shape)
    return tau, shape, m.area, delay


def fit_rtd_model(
    time_s,
    signal,
    model: str = "tanks_in_series",
    *,
    pulse: TracerPulse | None = None,
    time_origin_s: float = 0.0,
    fit_scale: bool = False,
    fit_delay: bool = False,
    sigma=None,
    initial: dict | None = None,
    n_starts: int = 1,
    seed: int = 0,
    max_nfev: int = 2000,
) -> RTDFit:
    """Fit a tanks-in-series or axial-dispersion RTD to a tracer curve.

    Parameters
    ----------
    time_s : 1-D array, sample times (s), strictly increasing.
    signal : 1-D array. With ``fit_scale=False`` it must be E(t) in 1/s;
        otherwise any unit (the fitted ``scale`` is its area, unit × s).
    model : ``"tanks_in_series"``, ``"dispersion_closed"`` or ``"dispersion_open"``.
    pulse : tracer input (:func:`pulse_input`), default Dirac.
    time_origin_s : start of the injection on the ``time_s`` clock (s).
    fit_scale : fit an unknown scale A (raw concentration / incomplete recovery).
    fit_delay : fit a dead time δ (s) >= 0 (plug-flow delay before the vessel).
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
    check_choice("model", model, RTD_MODELS)
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
    w = np.ones_like(y) if sigma is None else np.broadcast_to(check_range("sigma", sigma, 0.0, math.inf), y.shape)
    names = [_TAU_NAME[model], _SHAPE_NAME[model]]
    names += (["scale"] if fit_scale else []) + (["delay_s"] if fit_delay else [])
    p = len(names)
    if y.size <= p:
        raise ValueError(f"{y.size} data points cannot determine {p} parameters {names}")
    if not np.max(y) > 0:
        raise ValueError("signal has no positive value; nothing to fit")

    tau0, shape0, area0, delay0 = _moment_start(model, t, y, t0, pulse, fit_delay)
    start = {names[0]: tau0, names[1]: shape0, "scale": area0, "delay_s": delay0}
    if initial:
        for k, v in initial.items():
            if k not in names:
                raise ValueError(f"initial has unknown or unfitted parameter {k!r}; fitted parameters: {names}")
            start[k] = float(check_finite(f"initial[{k!r}]", v))
    lo_s, hi_s = _SHAPE_BOUNDS[names[1]]
    span = float(t[-1] - t0)
    delay_hi = max(span, 1.0)
    # Transformed vector: log tau, log shape, [log scale], [delay]
    lb = [math.log(1e-9 * max(span, 1.0)), math.log(lo_s)]
    ub = [math.log(1e3 * max(span, 1.0)), math.log(hi_s)]
    if fit_scale:
        lb.append(-math.inf)
        ub.append(math.inf)
    if fit_delay:
        lb.append(0.0)
        ub.append(delay_hi)

    def to_natural(x):
        d = {names[0]: math.exp(x[0]), names[1]: math.exp(x[1])}
        k = 2
        if fit_scale:
            d["scale"] = math.exp(x[k])
            k += 1
        if fit_delay:
            d["delay_s"] = float(x[k])
        return d

    def to_x(d):
        x = [math.log(d[names[0]]), math.log(d[names[1]])]
        if fit_scale:
            x.append(math.log(d["scale"]))
        if fit_delay:
            x.append(d["delay_s"])
        return np.array(x)

    nfev = [0]

    def predict(d):
        nfev[0] += 1
        scale = d.get("scale", 1.0)
        delay = d.get("delay_s", 0.0)
        m = _make_model(model, d[names[0]], d[names[1]])
        return scale * convolve_rtd(m.e, t - t0 - delay, pulse)

    def resid_nat(d):
        return (predict(d) - y) / w

    def resid_x(x):
        return resid_nat(to_natural(x))

    for k in names:
        if k != "delay_s" and not start[k] > 0:
            raise ValueError(f"starting value {k} = {fmt(start[k])} must be > 0")
    if initial:
        xi = to_x(start)
        for j, k in enumerate(names):
            if k in initial and not (lb[j] <= xi[j] <= ub[j]):
                lo_n = math.exp(lb[j]) if k != "delay_s" else lb[j]
                hi_n = math.exp(ub[j]) if k != "delay_s" else ub[j]
                raise ValueError(f"initial {k} = {fmt(initial[k])} is outside the fitting bounds [{lo_n:g}, {hi_n:g}]")
    x0 = np.clip(to_x(start), np.array(lb) + 1e-12, np.array(ub) - 1e-12)
    rng = np.random.default_rng(seed)
    starts = [x0]
    for _ in range(n_starts - 1):
        xs = x0.copy()
        xs[:2] += rng.uniform(-math.log(3), math.log(3), 2)
        if fit_delay:
            xs[-1] = rng.uniform(0, 2 * max(x0[-1], 1e-3 * span))
        starts.append(np.clip(xs, np.array(lb) + 1e-12, np.array(ub) - 1e-12))
    best, objs, msgs = None, [], []
    for xs in starts:
        res = optimize.least_squares(
            resid_x, xs, bounds=(lb, ub), method="trf", x_scale="jac", max_nfev=max_nfev,
            ftol=1e-12, xtol=1e-12, gtol=1e-12,
        )
        objs.append(float(2 * res.cost))
        msgs.append(res.message)
        if best is None or res.cost < best.cost:
            best = res
    warn = []
    if not best.success:
        warn.append(f"least_squares did not converge: {best.message}")
    est = to_natural(best.x)
    if np.allclose(best.x, starts[int(np.argmin(objs))]) and best.nfev <= 1:
        warn.append("the optimiser did not move from the starting point")

    # Jacobian in natural parameters (central differences) at the optimum
    r0 = resid_nat(est)
    J = np.empty((y.size, p))
    for j, k in enumerate(names):
        h = 1e-6 * max(abs(est[k]), 1e-3 * (span if k == "delay_s" else 1.0))
        lower = 0.0 if k == "delay_s" else (lo_s if k == names[1] else -math.inf)
        dp = dict(est)
        dp[k] = est[k] + h
        if est[k] - h < lower:  # one-sided difference at a lower bound
            J[:, j] = (resid_nat(dp) - r0) / h
        else:
            dm = dict(est)
            dm[k] = est[k] - h
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
        if k in ("n_tanks",) and abs(est[k] - lo_s) < 1e-6 * lo_s:
            warn.append(f"{k} is at its lower bound {lo_s}; the interval is not meaningful")
        if k == "delay_s" and est[k] < 1e-9 * max(span, 1.0):
            warn.append("delay_s is at its lower bound 0; the interval is not meaningful")
    yhat = predict(est)
    sst = float(np.sum((y - y.mean()) ** 2))
    r2 = 1.0 - float(np.sum((y - yhat) ** 2)) / sst if sst > 0 else float("nan")
    vessel = _make_model(model, est[names[0]], est[names[1]])
    vm = vessel.moments()
    delay = est.get("delay_s", 0.0)
    om = convolved_moments(vm, pulse)
    om = AnalyticMoments(mean_s=om.mean_s + delay, variance_s2=om.variance_s2, skewness=om.skewness)
    fixed = {}
    if not fit_scale:
        fixed["scale"] = 1.0
    if not fit_delay:
        fixed["delay_s"] = 0.0
    for msg in warn:
        _warnings.warn(msg, RuntimeWarning, stacklevel=2)
    return RTDFit(
        model=model,
        parameter_names=tuple(names),
        values={k: float(est[k]) for k in names},
        std_errors={k: float(se[j]) for j, k in enumerate(names)},
        ci_low={k: float(unc.ci_low[j]) for j, k in enumerate(names)},
        ci_high={k: float(unc.ci_high[j]) for j, k in enumerate(names)},
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
    )


def fit_tracer_data(data, model: str = "tanks_in_series", **kwargs) -> RTDFit:
    """Fit a :class:`~rotarydryer.rtd.TracerData` curve.

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
                f"signal_unit {unit!r} is not a normalised RTD (1/s, 1/min, 1/h); fit with fit_scale=True"
            )
    if "sigma" in kwargs and kwargs["sigma"] is not None and rate is not None:
        kwargs["sigma"] = np.asarray(kwargs["sigma"], float) * rate
    return fit_rtd_model(data.time_s, y, model, **kwargs)

"""Parameter estimation: weighted least squares and maximum likelihood with uncertainty.

The model is any callable ``model(values) -> predictions`` where ``values`` maps
parameter names to floats and ``predictions`` maps data-set names to arrays shaped
like the data (a bare array is accepted when there is one data set). The
estimation layer knows nothing about dryers: [`rotarydryer.estimation.cases`][rotarydryer.estimation.cases]
(when present) wraps case overrides into such a model.

Estimators
----------
``method="wls"``
:   Weighted least squares: minimise ``sum ((y - f)/sigma)^2`` with the given
    standard deviations ``sigma`` (1 when not given, the residual variance then
    estimated from the fit as ``SSE/(n - p)``).

``method="ml"``
:   Maximum likelihood with Gaussian errors whose variance is unknown and
    estimated per data set (as gPROMS does): ``variance="constant"``
    (``sigma_k``) or ``variance="power"`` (``sigma_k |f_i|^gamma``, heteroscedastic,
    ``gamma`` given per data set). Solved by iteratively re-weighted least squares
    (the generalised-least-squares estimator; the log-determinant term of the power
    model is not differentiated through, which keeps it a least-squares problem).

Uncertainty: covariance ``s^2 (J^T J)^{-1}`` from the Jacobian of the weighted
residuals at the optimum (Gauss-Newton Fisher information), 95 % intervals from the
t distribution (in log space, hence asymmetric, for log-transformed parameters),
correlation matrix; [`profile_likelihood`][rotarydryer.estimation.fit.profile_likelihood] and [`bootstrap`][rotarydryer.estimation.fit.bootstrap] for the
non-linear cases. Non-identifiability is reported, with the reason, from the
singular values of the scaled Jacobian and from parameter correlations.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy import optimize, stats

from .._validation import check_choice
from ..executor import Executor, RunFailure
from .uncertainty import cut_interval, linearised_uncertainty

__all__ = [
    "Parameter",
    "Dataset",
    "FitError",
    "IdentifiabilityWarning",
    "ParameterEstimate",
    "StartResult",
    "FitResult",
    "fit",
    "profile_likelihood",
    "bootstrap",
]


class FitError(RuntimeError):
    """The estimation could not produce a result (all starts failed, bad set-up)."""


class IdentifiabilityWarning(UserWarning):
    """The data cannot identify one or more parameters."""


#: a known-sigma fit whose worst residual exceeds this many of its data's standard deviations warns (lack of fit)
LACK_OF_FIT_SIGMAS = 10.0

@dataclass(frozen=True)
class Parameter:
    """A parameter to estimate.

    ``log=True`` estimates ``log(value)`` (requires ``lower >= 0`` and ``initial > 0``),
    which suits positive parameters spanning decades (time constants, dispersion).
    """

    name: str
    initial: float
    lower: float = -math.inf
    upper: float = math.inf
    log: bool = False

    def __post_init__(self):
        for attr in ("initial", "lower", "upper"):
            v = getattr(self, attr)
            if not isinstance(v, (int, float)) or isinstance(v, bool) or math.isnan(v):
                raise ValueError(f"parameter {self.name!r}: {attr} = {v!r} must be a number")
        if not math.isfinite(self.initial):
            raise ValueError(f"parameter {self.name!r}: initial = {self.initial!r} must be finite")
        if not self.lower < self.upper:
            raise ValueError(f"parameter {self.name!r}: lower = {self.lower!r} must be < upper = {self.upper!r}")
        if not self.lower <= self.initial <= self.upper:
            raise ValueError(
                f"parameter {self.name!r}: the start {self.initial!r} lies outside its bounds "
                f"[{self.lower!r}, {self.upper!r}]"
            )
        if self.log and not (self.initial > 0 and self.lower >= 0):
            raise ValueError(
                f"parameter {self.name!r}: log=True needs initial > 0 and lower >= 0 "
                f"(got initial {self.initial!r}, lower {self.lower!r})"
            )

    # transformed (optimiser) space
    def to_z(self, v):
        return np.log(v) if self.log else np.asarray(v, dtype=float)

    def from_z(self, z):
        return np.exp(z) if self.log else np.asarray(z, dtype=float)

    @property
    def z_bounds(self) -> tuple[float, float]:
        if self.log:
            lo = math.log(self.lower) if self.lower > 0 else -math.inf
            hi = math.log(self.upper) if math.isfinite(self.upper) else math.inf
            return lo, hi
        return self.lower, self.upper


@dataclass(frozen=True)
class Dataset:
    """Observations ``y`` (any shape) with optional known standard deviations ``sigma``.

    ``variance`` (for ``method="ml"``): ``"constant"`` or ``"power"`` with exponent
    ``power`` (sigma proportional to |prediction|^power; 1 = constant relative error).
    """

    name: str
    y: np.ndarray
    sigma: np.ndarray | None = None
    variance: str = "constant"
    power: float = 1.0

    def __post_init__(self):
        y = np.asarray(self.y, dtype=float)
        if y.size == 0:
            raise ValueError(f"data set {self.name!r} is empty")
        if not np.all(np.isfinite(y)):
            raise ValueError(f"data set {self.name!r} contains NaN or infinite values")
        object.__setattr__(self, "y", y)
        if self.sigma is not None:
            s = np.broadcast_to(np.asarray(self.sigma, dtype=float), y.shape)
            if not np.all(np.isfinite(s) & (s > 0)):
                bad = s[~(np.isfinite(s) & (s > 0))].flat[0]
                raise ValueError(f"data set {self.name!r}: sigma = {bad!r} is not allowed; it must be finite and > 0")
            object.__setattr__(self, "sigma", s)
        if self.variance not in ("constant", "power"):
            raise ValueError(f"data set {self.name!r}: variance = {self.variance!r} is not 'constant' or 'power'")


@dataclass(frozen=True)
class ParameterEstimate:
    """Estimate with standard error and 95 % confidence interval."""

    value: float
    std_error: float
    ci_low: float
    ci_high: float
    at_bound: bool = False

    def to_dict(self) -> dict:
        return {"value": self.value, "std_error": self.std_error, "ci_low": self.ci_low,
                "ci_high": self.ci_high, "at_bound": self.at_bound}


@dataclass(frozen=True)
class StartResult:
    """One start of the multi-start search."""

    start: dict
    objective: float
    success: bool
    n_evaluations: int
    message: str


@dataclass
class FitResult:
    """Result of [`fit`][rotarydryer.estimation.fit.fit]. ``objective`` is the weighted sum of squares (wls) or the
    negative log-likelihood (ml) at the optimum. ``sigma``: each data set's standard deviation, in its units, as the
    fit used it (wls with the data's known sigma: that sigma, their root mean square where they differ) or
    estimated it (wls without: the residuals' standard deviation; ml: its sigma_k, relative with
    ``variance="power"``)."""

    parameters: dict[str, ParameterEstimate]
    covariance: np.ndarray
    correlation: np.ndarray
    names: list[str]
    objective: float
    r_squared: float
    n_evaluations: int
    n_data: int
    dof: int
    sigma: dict[str, float]
    predictions: dict[str, np.ndarray]
    residuals: dict[str, np.ndarray]
    starts: list[StartResult]
    method: str
    warnings: list[str] = field(default_factory=list)
    seconds: float = 0.0
    r_squared_by_dataset: dict = field(default_factory=dict)

    @property
    def values(self) -> dict[str, float]:
        return {k: p.value for k, p in self.parameters.items()}

    def to_dict(self) -> dict:
        return {
            "parameters": {k: p.to_dict() for k, p in self.parameters.items()},
            "objective": self.objective,
            "r_squared": self.r_squared,
            "r_squared_by_dataset": self.r_squared_by_dataset,
            "n_evaluations": self.n_evaluations,
            "n_data": self.n_data,
            "dof": self.dof,
            "sigma": self.sigma,
            "correlation": self.correlation.tolist(),
            "names": self.names,
            "method": self.method,
            "starts": [dict(start=s.start, objective=s.objective, success=s.success,
                            n_evaluations=s.n_evaluations) for s in self.starts],
            "warnings": list(self.warnings),
            "seconds": self.seconds,
        }


# ----------------------------------------------------------------------------- internals
class _Problem:
    def __init__(self, model, parameters, data, method, fixed=None):
        self.model = model
        self.params = list(parameters)
        self.data = list(data)
        self.method = method
        self.fixed = dict(fixed or {})
        self.n_eval = 0
        self.weights = {d.name: 1.0 for d in self.data}  # 1/sigma_k for ml
        self.infeasible = 0
        self.last_infeasible = ""
        self._last_key, self._last_pred = None, None
        n = sum(d.y.size for d in self.data)
        big = 1e3 * (1.0 + sum(float(np.sum((d.y / (d.sigma if d.sigma is not None else 1.0)) ** 2))
                               for d in self.data))
        self.penalty = np.full(n, math.sqrt(big / n))

    def values(self, z) -> dict:
        v = {p.name: float(p.from_z(zi)) for p, zi in zip(self.params, z)}
        v.update(self.fixed)
        return v

    def predict(self, values: dict) -> dict:
        # one-entry cache: the solver, the re-weighting loop, the objective and the final
        # Jacobian often ask for the point just evaluated (a failed evaluation is not cached)
        key = tuple(values.items())
        if key == self._last_key:
            return self._last_pred
        pred = self._evaluate(values)
        self._last_key, self._last_pred = key, pred
        return pred

    def _evaluate(self, values: dict) -> dict:
        self.n_eval += 1
        out = self.model(values)
        if not isinstance(out, Mapping):
            if len(self.data) != 1:
                raise FitError("the model returned one array but there are several data sets")
            out = {self.data[0].name: out}
        pred = {}
        for d in self.data:
            if d.name not in out:
                raise FitError(f"the model returned no prediction for data set {d.name!r}")
            f = np.asarray(out[d.name], dtype=float)
            if f.shape != d.y.shape:
                raise FitError(f"prediction for {d.name!r} has shape {f.shape}, data {d.y.shape}")
            if not np.all(np.isfinite(f)):
                raise FloatingPointError(f"the model returned non-finite values for {d.name!r} at {values}")
            pred[d.name] = f
        return pred

    def scale(self, d: Dataset, f: np.ndarray, power_ref=None) -> np.ndarray | float:
        s = d.sigma if (d.sigma is not None and self.method == "wls") else 1.0
        if self.method == "ml" and d.variance == "power":
            ref = np.abs(f if power_ref is None else power_ref)
            floor = 1e-6 * max(np.max(ref), 1e-300)
            s = np.maximum(ref, floor) ** d.power
        return s

    def residuals(self, z, power_ref=None) -> np.ndarray:
        try:
            pred = self.predict(self.values(z))
        except (ValueError, FloatingPointError) as exc:
            # an infeasible parameter vector (the model refuses it, e.g. a coefficient
            # leaving its physical range): a large constant residual makes the trust-region
            # method reject the step and shrink, instead of aborting the fit
            self.infeasible += 1
            self.last_infeasible = str(exc)
            return self.penalty
        return self._weighted(pred, power_ref)

    def _weighted(self, pred, power_ref=None) -> np.ndarray:
        parts = []
        for d in self.data:
            f = pred[d.name]
            ref = None if power_ref is None else power_ref[d.name]
            r = (d.y - f) / self.scale(d, f, ref) * self.weights[d.name]
            parts.append(r.ravel())
        return np.concatenate(parts)


def _starts(problem: _Problem, n_starts: int, rng) -> list[np.ndarray]:
    z0 = np.array([float(p.to_z(p.initial)) for p in problem.params])
    starts = [z0]
    if n_starts <= 1:
        return starts
    sampler = stats.qmc.LatinHypercube(d=len(z0), seed=rng)
    u = sampler.random(n_starts - 1)
    for row in u:
        z = np.empty_like(z0)
        for i, (p, ui) in enumerate(zip(problem.params, row)):
            lo, hi = p.z_bounds
            if math.isfinite(lo) and math.isfinite(hi):
                z[i] = lo + ui * (hi - lo)
            elif p.log:
                z[i] = z0[i] + (ui - 0.5) * 2.0 * math.log(10.0)  # within a decade
            else:
                half = max(abs(p.initial), 1e-3)
                z[i] = np.clip(p.initial + (ui - 0.5) * 2.0 * half, lo, hi)
        starts.append(z)
    return starts


def _feasible_starts(problem: _Problem, n_starts: int, rng, tries: int = 30) -> list[np.ndarray]:
    """The given start plus sampled ones; a sampled start where the model refuses the
    parameters (infeasible) is replaced by a new sample (up to ``tries`` times)."""
    out = _starts(problem, n_starts, rng)
    for i in range(1, len(out)):
        for _ in range(tries):
            before = problem.infeasible
            problem.residuals(out[i])
            if problem.infeasible == before:
                break
            out[i] = _starts(problem, 2, rng)[1]
    return out


def _feasible_jacobian(problem: _Problem, z, power_ref=None):
    """Forward-difference Jacobian of the weighted residuals at ``z`` that steps into the
    feasible side of any constraint the model enforces. Returns (J, names of parameters
    with no feasible step in one direction)."""
    r0 = problem.residuals(z, power_ref)
    J = np.zeros((r0.size, z.size))
    boundary = []
    lo = np.array([q.z_bounds[0] for q in problem.params])
    hi = np.array([q.z_bounds[1] for q in problem.params])
    for i in range(z.size):
        h = 1e-6 * max(1.0, abs(z[i]))
        col = None
        for sgn in (1.0, -1.0):
            zz = z.copy()
            zz[i] = z[i] + sgn * h
            if not lo[i] <= zz[i] <= hi[i]:
                continue
            before = problem.infeasible
            r = problem.residuals(zz, power_ref)
            if problem.infeasible == before:
                col = (r - r0) / (sgn * h)
                break
            boundary.append(problem.params[i].name)
        if col is None:
            raise FitError(
                f"the model cannot be evaluated on either side of {problem.params[i].name} = "
                f"{float(problem.params[i].from_z(z[i])):.6g} (last refusal: {problem.last_infeasible}); "
                "no estimate is returned"
            )
        J[:, i] = col
    return J, sorted(set(boundary))


def _solve(problem: _Problem, z0, max_nfev, jac):
    lo = np.array([p.z_bounds[0] for p in problem.params])
    hi = np.array([p.z_bounds[1] for p in problem.params])
    z0 = np.clip(z0, np.nextafter(lo, hi), np.nextafter(hi, lo))
    kw = dict(bounds=(lo, hi), x_scale="jac", max_nfev=max_nfev, method="trf")
    if jac is not None:
        kw["jac"] = jac
    if problem.method == "wls":
        return optimize.least_squares(problem.residuals, z0, **kw)
    # ml: iteratively re-weighted least squares with per-data-set variances
    res = None
    z = z0
    for _ in range(6):
        ref = problem.predict(problem.values(z))
        res = optimize.least_squares(lambda zz: problem.residuals(zz, ref), z, **kw)
        z = res.x
        pred = problem.predict(problem.values(z))
        changed = False
        for d in problem.data:
            r = (d.y - pred[d.name]) / problem.scale(d, pred[d.name], ref[d.name])
            s2 = max(float(np.mean(r**2)), 1e-300)
            w = 1.0 / math.sqrt(s2)
            if abs(w - problem.weights[d.name]) > 1e-6 * w:
                changed = True
            problem.weights[d.name] = w
        if not changed:
            break
    final_ref = problem.predict(problem.values(z))
    res = optimize.least_squares(lambda zz: problem.residuals(zz, final_ref), z, **kw)
    res.power_ref = final_ref
    return res


def _objective(problem: _Problem, res) -> float:
    if problem.method == "wls":
        return float(np.sum(res.fun**2))
    pred = problem.predict(problem.values(res.x))
    nll = 0.0
    for d in problem.data:
        f = pred[d.name]
        scale = problem.scale(d, f)
        r = (d.y - f) / scale
        n = r.size
        s2 = max(float(np.mean(r**2)), 1e-300)
        nll += 0.5 * n * (math.log(2 * math.pi * s2) + 1.0) + float(np.sum(np.log(np.broadcast_to(scale, r.shape))))
    return nll


def fit(
    model: Callable[[dict], object],
    parameters: Sequence[Parameter],
    data: Sequence[Dataset] | Dataset,
    *,
    method: str = "wls",
    n_starts: int = 4,
    seed: int = 0,
    jac=None,
    max_nfev: int | None = None,
    fixed: Mapping[str, float] | None = None,
    progress: Callable[[int, int, float], None] | None = None,
    executor: Executor | None = None,
) -> FitResult:
    """Estimate ``parameters`` of ``model`` from ``data``; see the module docstring.

    Parameters
    ----------
    model : callable
        ``model(values: dict) -> dict[data set name, array]`` (or an array for one data set).
    parameters : sequence of Parameter
    data : Dataset or sequence of Dataset
    method : {"wls", "ml"}
    n_starts : int
        Number of starts: the given initial values plus Latin-hypercube samples within the
        bounds (in the transformed space). All are reported in ``FitResult.starts``.
    seed : int
        Seed of the start sampler (results are reproducible).
    jac : callable, optional
        Jacobian of the weighted residuals in the transformed space; default 2-point
        finite differences.
    fixed : mapping, optional
        Extra model inputs held fixed.
    progress : callable, optional
        ``progress(starts_done, n_starts, best_objective_so_far)`` after each start.
    executor : rotarydryer.executor.Executor, optional
        Runs the starts (default serially): each on its own problem and, where the model has a
        ``fresh()`` method, its own copy of the model's state, so every backend gives the same
        result; the model (and ``jac``) must pickle for worker processes.

    Raises
    ------
    FitError
        When no start converges (the initial guess is never returned as a result).
    ValueError
        Bad set-up: no parameters, duplicate names, too few data points.
    """
    t0 = time.perf_counter()
    check_choice("method", method, ("wls", "ml"))
    params = list(parameters)
    if not params:
        raise ValueError("no parameters to estimate")
    names = [p.name for p in params]
    if len(set(names)) != len(names):
        twice = next(n for n in names if names.count(n) > 1)
        raise ValueError(f"duplicate parameter: {twice} is given twice (-p on the command line): give each parameter once")
    data = [data] if isinstance(data, Dataset) else list(data)
    if not data:
        raise ValueError("no data sets")
    n = sum(d.y.size for d in data)
    if n <= len(params):
        raise ValueError(f"too few data points: {n} observations for {len(params)} parameters (need more than {len(params)})")
    if isinstance(n_starts, bool) or int(n_starts) != n_starts or n_starts < 1:
        raise ValueError(f"n_starts = {n_starts!r} must be an integer >= 1")
    rng = np.random.default_rng(seed)
    problem = _Problem(model, params, data, method, fixed)
    try:
        problem.predict(problem.values(np.array([float(p.to_z(p.initial)) for p in params])))
    except (FitError, ValueError, FloatingPointError) as exc:
        raise FitError(f"the model cannot be evaluated at the initial values: {exc}") from exc
    best, best_obj, best_weights = None, math.inf, None
    penalty_cost = float(np.sum(problem.penalty**2))
    starts: list[StartResult] = []
    zs = _feasible_starts(problem, int(n_starts), rng)
    spec = (model, params, data, method, fixed, max_nfev, jac, penalty_cost)
    outcomes: list = [None] * len(zs)
    done = [0]

    def tick(n):
        done[0] += n
        if progress is not None:
            objs = [o["start"].objective for o in outcomes if isinstance(o, dict) and o["start"].success]
            progress(done[0], int(n_starts), min(objs, default=math.inf))

    ex = executor or Executor()
    ex.map(_run_start, list(zs), args=(spec,), chunks=1, progress=tick, results=outcomes)
    for z0, out in zip(zs, outcomes):
        if isinstance(out, RunFailure):      # the start's worker failed (not the model: that is caught inside)
            start_vals = {p.name: float(p.from_z(zi)) for p, zi in zip(params, z0)}
            out = dict(start=StartResult(start_vals, math.inf, False, 0, f"model failed: {out.error}"), res=None,
                       weights=None, n_eval=0, infeasible=0, last_infeasible="", n_solves=0)
        starts.append(out["start"])
        problem.n_eval += out["n_eval"]
        problem.infeasible += out["infeasible"]
        problem.last_infeasible = out["last_infeasible"] or problem.last_infeasible
        solves = getattr(model, "n_solves", None)
        if out["n_solves"] and isinstance(solves, int):     # a model that counts its solves (calibrate) sees the starts'
            setattr(model, "n_solves", solves + out["n_solves"])  # noqa: B010
        if out["start"].success and out["start"].objective < best_obj:
            best, best_obj, best_weights = out["res"], out["start"].objective, out["weights"]
    if best is None:
        msgs = [s.message for s in starts]
        if len(set(msgs)) == 1:
            raise FitError(f"no start converged ({'the only start' if len(msgs) == 1 else f'all {len(msgs)} starts'}): "
                           f"{msgs[0]}")
        raise FitError("no start converged: " + "; ".join(f"start {i + 1}: {m}" for i, m in enumerate(msgs)))
    problem.weights = best_weights
    return _summarise(problem, best, best_obj, starts, time.perf_counter() - t0)


def _run_start(z0, spec) -> dict:
    """One start of the multi-start search on its own problem (and, through ``model.fresh()``
    where the model has it, its own model state), so that it gives the same result whichever
    process runs it and whatever ran before. Top-level, so that it pickles for worker processes."""
    model, params, data, method, fixed, max_nfev, jac, penalty_cost = spec
    fresh = getattr(model, "fresh", None)
    own = fresh() if callable(fresh) else model
    problem = _Problem(own, params, data, method, fixed)
    start_vals = {p.name: float(p.from_z(zi)) for p, zi in zip(params, z0)}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            res = _solve(problem, np.asarray(z0, dtype=float), max_nfev, jac)
        obj = _objective(problem, res)
        ok = bool(res.success) and math.isfinite(obj) and float(np.sum(res.fun**2)) < 0.5 * penalty_cost
        msg = res.message
        if not ok and problem.infeasible and float(np.sum(res.fun**2)) >= 0.5 * penalty_cost:
            # the search ended where the model refuses the parameters (the constant residual of a refusal has no
            # gradient, so the solver reports convergence): say what the model refused
            msg = f"the model refused the parameters it ended at ({problem.last_infeasible})"
    except (FloatingPointError, ValueError, FitError) as exc:
        res, obj, ok, msg = None, math.inf, False, f"model failed: {exc}"
    return dict(start=StartResult(start_vals, obj, ok, problem.n_eval, str(msg)), res=res if ok else None,
                weights=dict(problem.weights), n_eval=problem.n_eval, infeasible=problem.infeasible,
                last_infeasible=problem.last_infeasible,
                n_solves=getattr(own, "n_solves", 0) if own is not model else 0)


#: a parameter whose whole range moves the weighted prediction by less than this fraction of the weighted data has
#: no effect on the fit (`_summarise`): an infinite standard error and a note. Above the finite differences' own
#: noise (a kiln time the curve does not depend on: 4e-8, its whole range times a derivative of rounding errors)
NO_EFFECT = 1e-6


def _summarise(problem: _Problem, res, obj, starts, seconds) -> FitResult:
    params = problem.params
    names = [p.name for p in params]
    z = res.x
    values = problem.values(z)
    pred = problem.predict(values)
    J, on_constraint = _feasible_jacobian(problem, z, getattr(res, "power_ref", None))
    if not J.any():
        if not problem.last_infeasible:
            # nothing refused: the predictions do not move at all (a key the case's configuration does not use; it
            # read "cannot be evaluated in any direction (last refusal: none)", naming no key; found by review)
            raise FitError(
                f"the fitted data do not depend on {', '.join(names)}: moving {'it' if len(names) == 1 else 'them'} "
                "changes no prediction (a key this case's configuration does not use, e.g. one of another geometry "
                "method or transport law, or of another response); no estimate is returned"
            )
        raise FitError(
            "the model cannot be evaluated in any direction around the solution "
            f"(last refusal: {problem.last_infeasible}); no estimate is returned"
        )
    n = J.shape[0]
    dof = n - len(params)
    known_sigma = problem.method == "wls" and all(d.sigma is not None for d in problem.data)
    # Fisher information in z space (s^2 = 1 when sigma is known or estimated per data set by
    # ml); the pseudo-inverse guards singular cases
    unc = linearised_uncertainty(J, res.fun, dof, sigma_known=known_sigma or problem.method == "ml",
                                 estimates=z, inverse="pinv", rcond=1e-12, singular_rtol=1e-7,
                                 correlation_threshold=0.99)
    s2 = unc.residual_variance
    notes: list[str] = []
    if on_constraint:
        notes.append(
            "the optimum lies on a constraint of the model (a step in "
            + ", ".join(on_constraint)
            + " makes it infeasible): intervals are from one-sided sensitivities and the true "
            "interval is cut by the constraint"
        )
    cov_z, sd_z, corr = unc.covariance, unc.std_errors, unc.correlation
    ci_low, ci_high = unc.ci_low, unc.ci_high
    # parameters without an interval (an infinite standard error, the interval cut to their range below), not the
    # zero-width one the pseudo-inverse gives them
    blind = np.zeros(len(params), dtype=bool)
    # identifiability: relative (scaled) sensitivities
    if unc.singular:
        worst = unc.null_direction
        culprits = [names[i] for i in np.argsort(-np.abs(worst))[:2] if abs(worst[i]) > 0.3]
        # along the direction the data do not see (a kiln time without effect on the curve was 0.508868
        # [0.508868, 0.508868]; found by fuzzing)
        blind |= np.abs(worst) > 0.3
        notes.append(
            f"near-singular Fisher information (condition number {unc.jacobian_condition:.2e}): "
            "the data cannot separate " + (" and ".join(culprits) if culprits else "the parameters")
        )
    # a parameter the fitted curve does not depend on at all: moving it across its whole range moves the weighted
    # prediction by less than NO_EFFECT of the weighted data (one parameter has no relative singularity to flag;
    # on noise-free data its standard error was 0/0, a kiln time without effect got +-2e-6 s)
    ref = getattr(res, "power_ref", None)
    signal = float(np.linalg.norm(np.concatenate([
        (np.asarray(d.y, float) / problem.scale(d, pred[d.name], None if ref is None else ref[d.name])
         * problem.weights[d.name]).ravel() for d in problem.data])))
    span = np.array([q.z_bounds[1] - q.z_bounds[0] for q in params], float)
    effect = np.linalg.norm(J, axis=0) * np.where(np.isfinite(span), span, 1.0)
    no_effect = (effect <= NO_EFFECT * max(signal, 1e-300)) & ~blind & np.isfinite(sd_z)
    for i in np.flatnonzero(no_effect):
        notes.append(f"the data do not depend on {names[i]} here: across its whole range it moves the fitted "
                     f"curve by less than {NO_EFFECT:g} of the data (not identifiable; its value is where the "
                     "search stopped)")
    blind |= no_effect
    assert ci_low is not None and ci_high is not None     # estimates were given
    sd_z = np.where(blind, np.inf, sd_z)
    ci_low, ci_high = np.where(blind, -np.inf, ci_low), np.where(blind, np.inf, ci_high)
    for i, j, r in unc.correlated_pairs:
        notes.append(f"{names[i]} and {names[j]} are correlated {r:+.3f}: one may not be identifiable")
    est = {}
    lo_b = np.array([q.z_bounds[0] for q in params])
    hi_b = np.array([q.z_bounds[1] for q in params])
    for i, q in enumerate(params):
        v = float(q.from_z(z[i]))
        at_bound = bool(np.isclose(z[i], lo_b[i], rtol=1e-6, atol=1e-9) or np.isclose(z[i], hi_b[i], rtol=1e-6, atol=1e-9))
        if at_bound:
            notes.append(f"{q.name} = {v:.6g} is at a bound: its interval is not reliable, and the best fit may lie "
                         "inside the bounds (a search from more starts, `rotarydryer calibrate --starts 5`, finds it "
                         "where the objective has more than one minimum)")
        if q.log:
            se = v * sd_z[i]
            lo, hi = float(np.exp(ci_low[i])), float(np.exp(ci_high[i]))
        else:
            se = float(sd_z[i])
            lo, hi = float(ci_low[i]), float(ci_high[i])
        lo_cut, hi_cut, cut = cut_interval(q.name, lo, hi, q.lower, q.upper)
        if not np.isfinite(se) or se > 1e6 * max(abs(v), 1e-12):
            notes.append(f"{q.name}: standard error {se:.3g} is huge relative to the estimate; flat objective")
        elif cut:
            if not at_bound:            # at a bound, the note above says the interval is not reliable
                notes.append(cut)
        elif q.log and 2.0 * 1.959964 * float(sd_z[i]) > math.log(1e4):
            # a log parameter's interval spanning more than four decades: the data hardly see it
            notes.append(f"{q.name}: its 95 % interval [{lo:.3g}, {hi:.3g}] spans more than four decades: the data "
                         "hardly depend on it (not identifiable here)")
        lo, hi = lo_cut, hi_cut
        est[q.name] = ParameterEstimate(v, float(se), float(lo), float(hi), at_bound)
    # covariance in natural space
    jac_t = np.array([float(q.from_z(z[i])) if q.log else 1.0 for i, q in enumerate(params)])
    cov = cov_z * np.outer(jac_t, jac_t)
    # R^2 per data set (pooling data of different units would be meaningless); the headline
    # value is that of the first data set
    r2_by = {}
    for d in problem.data:
        sst = float(np.sum((d.y - d.y.mean()) ** 2))
        r2_by[d.name] = 1.0 - float(np.sum((d.y - pred[d.name]) ** 2)) / sst if sst > 0 else float("nan")
    r2 = r2_by[problem.data[0].name]
    sig = {}
    for d in problem.data:
        r = (d.y - pred[d.name]) / problem.scale(d, pred[d.name])
        if problem.method == "ml":
            sig[d.name] = float(np.sqrt(np.mean(r**2)))
        elif known_sigma:       # the data's own (the fit's weights), not the factor 1 of a known sigma
            sig[d.name] = float(np.sqrt(np.mean(np.asarray(d.sigma, dtype=float) ** 2)))
        else:
            sig[d.name] = float(np.sqrt(s2))
    if known_sigma:     # data the model misses by many of their own standard deviations at the optimum
        worst = None
        for d in problem.data:
            r = np.abs(d.y - pred[d.name]) / np.maximum(np.asarray(d.sigma, dtype=float) * np.ones_like(d.y), 1e-300)
            i = int(np.argmax(r)) if r.size else 0
            if r.size and np.isfinite(r[i]) and (worst is None or r[i] > worst[0]):
                worst = (float(r[i]), d.name, float(np.ravel(d.y)[i]), float(np.ravel(pred[d.name])[i]))
        if worst is not None and worst[0] > LACK_OF_FIT_SIGMAS:
            notes.append(f"lack of fit: {worst[1]} is missed by {worst[0]:.3g} of its standard deviations at the "
                         f"optimum (measured {worst[2]:.6g}, model {worst[3]:.6g}): no value of the fitted keys "
                         "reproduces these data, so their values and intervals describe no fit; check the data (units, "
                         "a typing error) and what the fitted keys can move")
    if problem.infeasible:
        notes_info = (f"{problem.infeasible} model evaluations were infeasible and rejected "
                      f"(last: {problem.last_infeasible})")
    else:
        notes_info = None
    for msg in notes:
        warnings.warn(msg, IdentifiabilityWarning, stacklevel=3)
    if notes_info:
        notes.append(notes_info)
    return FitResult(
        parameters=est, covariance=cov, correlation=corr, names=names, objective=float(obj),
        r_squared=r2, n_evaluations=problem.n_eval, n_data=n, dof=dof, sigma=sig,
        predictions=pred, residuals={d.name: d.y - pred[d.name] for d in problem.data},
        starts=starts, method=problem.method, warnings=notes, seconds=seconds, r_squared_by_dataset=r2_by,
    )


@dataclass(frozen=True)
class ProfileResult:
    """Profile of the objective along one parameter (others re-optimised).

    ``delta`` is the increase of ``2 x`` negative log-likelihood (ml) or of the weighted
    SSE divided by the residual variance (wls); the 95 % interval is where
    ``delta < chi2(0.95, 1) = 3.84``. ``flat`` flags a profile that never reaches it. A grid
    point where the other parameters could not be re-fitted has ``delta = inf``.
    """

    name: str
    values: np.ndarray
    delta: np.ndarray
    ci_low: float
    ci_high: float
    flat: bool
    #: the profile stays below the threshold on that side (the interval ends at the grid, open)
    open_low: bool = False
    open_high: bool = False


def profile_likelihood(model, parameters, data, result: FitResult, name: str, *, n_points: int = 15,
                       span: float = 4.0, method: str | None = None, extend: int = 4) -> ProfileResult:
    """Profile likelihood of parameter ``name`` around the estimate in ``result``.

    The grid spans ``+/- span`` standard errors (in the transformed space for log
    parameters). Each point re-fits the other parameters from the optimum. A side where the
    profile stays below the 95 % threshold is extended, up to ``extend`` times, by
    ``n_points // 2`` points reaching 1.5 times further each time (within the parameter's
    bounds): the profile may be much flatter than the Wald (linearised) curvature says.
    """
    params = list(parameters)
    idx = {p.name: i for i, p in enumerate(params)}
    if name not in idx:
        raise ValueError(f"no parameter named {name!r}; parameters are {list(idx)}")
    method = method or result.method
    target = params[idx[name]]
    est = result.parameters[name]
    zc = float(target.to_z(est.value))
    sd_z = est.std_error / est.value if target.log else est.std_error
    sd_z = sd_z if (np.isfinite(sd_z) and sd_z > 0) else 0.1 * max(abs(zc), 1.0)
    lo_b, hi_b = target.z_bounds
    others = [
        Parameter(p.name, float(np.clip(result.values[p.name], p.lower, p.upper)), p.lower, p.upper, p.log)
        for p in params if p.name != name
    ]
    data = [data] if isinstance(data, Dataset) else list(data)
    s2 = 1.0
    if method == "wls" and not all(d.sigma is not None for d in data):
        s2 = result.objective / max(result.dof, 1)
    base = result.objective
    crit = float(stats.chi2.ppf(0.95, 1))
    points: dict[float, float] = {}

    def delta(zg):
        zg = float(zg)
        if zg in points:
            return points[zg]
        v = float(target.from_z(zg))
        if others:
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    r = fit(model, others, data, method=method, n_starts=1, fixed={name: v})
                obj = r.objective
            except FitError:
                # the model cannot be fitted with the parameter held here (e.g. infeasible): the point
                # counts as outside the interval, which then ends at the last point that could be fitted
                obj = math.inf
        else:
            prob = _Problem(model, [], data, method, {name: v})
            res = type("R", (), {})()
            res.x = np.array([])
            res.fun = prob.residuals(np.array([]))
            obj = _objective(prob, res)
        points[zg] = max(2.0 * (obj - base) if method == "ml" else (obj - base) / s2, 0.0)
        return points[zg]

    for zg in np.clip(zc + np.linspace(-span, span, n_points) * sd_z, lo_b, hi_b):
        delta(zg)
    for sign, _bound in ((-1.0, lo_b), (1.0, hi_b)):
        reach = span
        for _ in range(int(extend)):
            side = [d for z, d in points.items() if sign * (z - zc) > 0]
            end = zc + sign * reach * sd_z
            if (side and max(side) >= crit) or not (lo_b < end < hi_b):
                break
            new = reach * 1.5
            for f in np.linspace(reach, new, max(n_points // 2, 2) + 1)[1:]:
                delta(float(np.clip(zc + sign * f * sd_z, lo_b, hi_b)))
            reach = new
    grid_z = np.array(sorted(points))
    deltas = np.array([points[z] for z in grid_z])
    vals = np.array([float(target.from_z(z)) for z in grid_z])
    flat = bool(deltas.max() < crit)
    lo, hi = _crossings(grid_z, deltas, crit, zc)
    open_low = not bool(np.any(deltas[grid_z < zc] >= crit))
    open_high = not bool(np.any(deltas[grid_z > zc] >= crit))
    lo, hi = float(target.from_z(lo)), float(target.from_z(hi))
    if flat:
        warnings.warn(f"profile of {name} is flat over the grid ({vals.min():.4g} to {vals.max():.4g}): not "
                      "identifiable from these data", IdentifiabilityWarning, stacklevel=2)
    return ProfileResult(name, vals, deltas, lo, hi, flat, open_low, open_high)


def _crossings(z, delta, crit, zc):
    """Where the profile crosses ``crit`` on each side of the optimum (linear interpolation);
    the grid end when it does not cross."""
    left, right = z <= zc, z >= zc
    zl, dl = z[left][::-1], delta[left][::-1]  # from the optimum outwards
    zr, dr = z[right], delta[right]

    def cross(zs, ds):
        above = np.nonzero(ds >= crit)[0]
        if above.size == 0 or above[0] == 0:
            return zs[-1] if above.size == 0 else zs[0]
        k = above[0]
        return zs[k - 1] + (crit - ds[k - 1]) * (zs[k] - zs[k - 1]) / (ds[k] - ds[k - 1])

    return cross(zl, dl), cross(zr, dr)


@dataclass(frozen=True)
class BootstrapResult:
    samples: dict[str, np.ndarray]
    ci_low: dict[str, float]
    ci_high: dict[str, float]
    n_failed: int


def bootstrap(model, parameters, data, result: FitResult, *, n_boot: int = 100, seed: int = 0) -> BootstrapResult:
    """Residual bootstrap: refit to ``prediction + resampled residuals``; percentile 95 % intervals."""
    rng = np.random.default_rng(seed)
    data = [data] if isinstance(data, Dataset) else list(data)
    params = [Parameter(p.name, float(np.clip(result.values[p.name], p.lower, p.upper)), p.lower, p.upper, p.log)
              for p in parameters]
    samples: dict[str, list[float]] = {p.name: [] for p in params}
    failed = 0
    for _ in range(int(n_boot)):
        boot = []
        for d in data:
            r = result.residuals[d.name].ravel()
            y = result.predictions[d.name] + rng.choice(r, size=r.size, replace=True).reshape(d.y.shape)
            boot.append(Dataset(d.name, y, d.sigma, d.variance, d.power))
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                rb = fit(model, params, boot, method=result.method, n_starts=1)
        except FitError:
            failed += 1
            continue
        for k, v in rb.values.items():
            samples[k].append(v)
    arr = {k: np.array(v) for k, v in samples.items()}
    lo = {k: float(np.percentile(v, 2.5)) if v.size else float("nan") for k, v in arr.items()}
    hi = {k: float(np.percentile(v, 97.5)) if v.size else float("nan") for k, v in arr.items()}
    return BootstrapResult(arr, lo, hi, failed)

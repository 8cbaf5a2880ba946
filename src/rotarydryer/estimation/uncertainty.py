r"""Linearised (Gauss-Newton) parameter uncertainty of a least-squares fit.

For residuals $r(\theta)$ (n values) with Jacobian $J = \partial r/\partial\theta$
(n x p) at the least-squares estimate $\hat\theta$, the asymptotic covariance is

$$
\operatorname{Cov}\hat\theta \approx s^2 (J^T J)^{-1},
\qquad s^2 = \frac{\sum_i r_i^2}{n - p}
$$

(Bates & Watts (1988) *Nonlinear Regression Analysis and Its Applications*, section 2.3;
Seber & Wild (1989) *Nonlinear Regression*, section 2.1 and Eq. 5.1): ``s^2`` is the
residual variance estimated from the fit, or 1 when the residuals were divided by known
standard deviations (``sigma_known=True``, the inverse Fisher information). Standard errors
are $\sqrt{\operatorname{diag}\,\mathrm{Cov}}$, the ``confidence`` intervals
$\hat\theta_j \pm t_{1-\alpha/2,\,n-p}\,\mathrm{SE}_j$ (exact for a linear model
with Gaussian errors), and the correlation matrix
$\mathrm{Cov}_{jk}/(\mathrm{SE}_j\,\mathrm{SE}_k)$.

Everything is in the units of the Jacobian's columns: a fit in transformed parameters (for
example log-parameters) gets its covariance in that space and transforms afterwards.

A rank-deficient or near-singular $J^T J$ (a parameter combination the data do not
determine) is flagged from the singular values of $J$, whose squares are the
eigenvalues of $J^T J$ (Seber & Wild (1989) section 3.4); the covariance is then a
Moore-Penrose pseudo-inverse, whose standard errors are **not** meaningful along
`LinearisedUncertainty.null_direction`. The caller words the warnings.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import stats

__all__ = ["LinearisedUncertainty", "linearised_uncertainty", "cut_interval", "INVERSE_METHODS"]

INVERSE_METHODS = ("pinv", "inv")


@dataclass(frozen=True, eq=False)
class LinearisedUncertainty:
    """Result of [`linearised_uncertainty`][rotarydryer.estimation.uncertainty.linearised_uncertainty] (p = number of parameters).

    Attributes
    ----------
    covariance : (p, p) array
        ``s^2 (J^T J)^{-1} * variance_inflation``, in squared parameter units.
    std_errors : (p,) array
        Square roots of the covariance diagonal (negative round-off clipped to 0).
    correlation : (p, p) array
        ``cov_jk / (se_j se_k)``; entries undefined by a zero standard error are 0, the
        diagonal is 1.
    ci_low, ci_high : (p,) arrays or None
        ``estimates -/+ t_quantile * std_errors``; None when no estimates were given.
    residual_variance : float
        ``s^2`` used (before ``variance_inflation``): 1 when sigma is known.
    dof : int
        Degrees of freedom ``n - p`` (or as given).
    t_quantile : float
        Student-t quantile ``t(0.5 + confidence/2, max(dof, 1))``.
    singular_values : (min(n, p),) array
        Singular values of J, descending.
    null_direction : (p,) array
        Right singular vector of the smallest singular value: the parameter combination
        the data determine worst.
    condition_number : float
        2-norm condition number of ``J^T J`` (``numpy.linalg.cond``; inf when singular).
    singular : bool
        The smallest singular value of J is <= ``singular_rtol`` x the largest.
    rank : int
        Number of singular values of J above ``singular_rtol`` x the largest.
    correlated_pairs : tuple of (j, k, r)
        Parameter index pairs (j < k, row-major order) with ``|r| > correlation_threshold``.
    """

    covariance: np.ndarray
    std_errors: np.ndarray
    correlation: np.ndarray
    ci_low: np.ndarray | None
    ci_high: np.ndarray | None
    residual_variance: float
    dof: int
    t_quantile: float
    singular_values: np.ndarray
    null_direction: np.ndarray
    condition_number: float
    singular: bool
    rank: int
    correlated_pairs: tuple = ()

    @property
    def jacobian_condition(self) -> float:
        """Condition number of J itself, ``s_max / s_min`` (s_min floored at 1e-300)."""
        sv = self.singular_values
        return float(sv.max() / max(sv.min(), 1e-300)) if sv.size else 1.0

    def delta_se(self, gradient) -> float:
        """Delta-method standard error of a derived quantity g(theta) with gradient
        ``dg/dtheta`` (p,): ``sqrt(grad^T Cov grad)`` (negative round-off clipped to 0)."""
        g = np.asarray(gradient, dtype=float)
        return float(np.sqrt(max(g @ self.covariance @ g, 0.0)))


def linearised_uncertainty(
    jac,
    residuals=None,
    dof: int | None = None,
    *,
    sigma_known: bool = False,
    residual_variance: float | None = None,
    estimates=None,
    confidence: float = 0.95,
    variance_inflation: float = 1.0,
    inverse: str = "pinv",
    rcond: float = 1e-15,
    singular_rtol: float = 1e-7,
    correlation_threshold: float = 0.99,
) -> LinearisedUncertainty:
    """Covariance, standard errors, t intervals and correlations from the Jacobian (see module notes).

    Parameters
    ----------
    jac : (n, p) array_like
        Jacobian of the (weighted) residuals with respect to the parameters at the estimate.
    residuals : (n,) array_like, optional
        (Weighted) residuals at the estimate; ``s^2 = r.r / max(dof, 1)``. Not needed when
        ``sigma_known`` or ``residual_variance`` is given.
    dof : int, optional
        Residual degrees of freedom, default ``n - p``.
    sigma_known : bool
        The residuals were divided by known standard deviations: ``s^2 = 1``.
    residual_variance : float, optional
        ``s^2`` computed by the caller (e.g. a profiled residual sum of squares / dof).
    estimates : (p,) array_like, optional
        Parameter values (same space as the Jacobian columns) for the intervals.
    confidence : float
        Two-sided confidence level of the intervals (0.95 = 95 %).
    variance_inflation : float
        Factor applied to the covariance (e.g. ``(1 + r1)/(1 - r1)`` for AR(1) residuals).
    inverse : {"pinv", "inv"}
        ``"pinv"``: always the pseudo-inverse ``pinv(J^T J, rcond)``. ``"inv"``: the inverse,
        falling back to the pseudo-inverse when J is flagged singular or the inverse fails.
    rcond : float
        Relative cut-off of the pseudo-inverse's singular values (of ``J^T J``).
    singular_rtol : float
        J is singular when its smallest singular value is <= ``singular_rtol`` x its
        largest (``singular_rtol = 1e-6`` is ``cond(J^T J) >= 1e12``; 0 flags exact
        rank deficiency only).
    correlation_threshold : float
        ``|r|`` above which a pair is listed in ``correlated_pairs``.

    Returns
    -------
    LinearisedUncertainty
    """
    if inverse not in INVERSE_METHODS:
        raise ValueError(f"inverse = {inverse!r} is not one of {INVERSE_METHODS}")
    if sigma_known and residual_variance is not None:
        raise ValueError("give either sigma_known=True or residual_variance, not both")
    J = np.asarray(jac, dtype=float)
    if J.ndim != 2:
        raise ValueError(f"the Jacobian must be a 2-D (n, p) array, got shape {J.shape}")
    n, p = J.shape
    dof = n - p if dof is None else int(dof)
    if sigma_known:
        s2 = 1.0
    elif residual_variance is not None:
        s2 = float(residual_variance)
    elif residuals is not None:
        r = np.asarray(residuals, dtype=float).ravel()
        s2 = float(r @ r) / max(dof, 1)
    else:
        raise ValueError("residuals are needed to estimate the residual variance (or give sigma_known=True)")

    jtj = J.T @ J
    _, sv, vt = np.linalg.svd(J, full_matrices=False)
    smax = float(sv.max()) if sv.size else 0.0
    tol = singular_rtol * smax
    singular = bool(sv.size and sv.min() <= tol)
    rank = int(np.count_nonzero(sv > tol))
    cond = float(np.linalg.cond(jtj)) if p else 1.0

    if inverse == "inv" and not singular:
        try:
            inv = np.linalg.inv(jtj)
        except np.linalg.LinAlgError:
            inv = np.linalg.pinv(jtj, rcond=rcond)
    else:
        inv = np.linalg.pinv(jtj, rcond=rcond)
    cov = s2 * inv * float(variance_inflation)

    se = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(se, se)
    corr = np.where(np.isfinite(corr), corr, 0.0)
    np.fill_diagonal(corr, 1.0)
    iu, ju = np.triu_indices(p, 1)
    hit = np.abs(corr[iu, ju]) > correlation_threshold
    pairs = tuple((int(i), int(j), float(corr[i, j])) for i, j in zip(iu[hit], ju[hit]))

    # Student's t where s^2 is estimated from the residuals (dof of them); the normal's quantile where the
    # standard deviations are known (s^2 = 1: nothing is estimated, and the profile likelihood's interval of
    # the same fit is then the normal's, chi2(1))
    q = 0.5 + confidence / 2.0
    tq = float(stats.norm.ppf(q)) if sigma_known else float(stats.t.ppf(q, max(dof, 1)))
    if estimates is None:
        lo = hi = None
    else:
        est = np.asarray(estimates, dtype=float)
        lo, hi = est - tq * se, est + tq * se
    return LinearisedUncertainty(
        covariance=cov, std_errors=se, correlation=corr, ci_low=lo, ci_high=hi, residual_variance=s2,
        dof=dof, t_quantile=tq, singular_values=sv, null_direction=vt[-1] if p else np.empty(0),
        condition_number=cond, singular=singular, rank=rank, correlated_pairs=pairs,
    )


def cut_interval(name: str, low: float, high: float, lower: float, upper: float) -> tuple[float, float, str | None]:
    """A linearised interval ``[low, high]`` of parameter ``name`` cut to its allowed range ``[lower, upper]``
    (the interval is symmetric in the fitted coordinate; the parameter cannot leave its range, so neither does
    its interval), and the note that says so, or None where it was inside."""
    if low >= lower and high <= upper:
        return low, high, None
    note = (f"{name}: its 95 % interval [{low:.4g}, {high:.4g}] leaves the allowed range [{lower:.6g}, {upper:.6g}] "
            "and is cut to it: the data constrain it weakly")
    return max(low, lower), min(high, upper), note

"""Linearised (Gauss-Newton) parameter uncertainty: exact linear-regression results, singular
Jacobians and invariances."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import stats

from rotarydryer.estimation.uncertainty import linearised_uncertainty


def _line_data(seed=0, n=25, sigma=0.3):
    rng = np.random.default_rng(seed)
    x = np.linspace(0.0, 10.0, n)
    X = np.column_stack([np.ones(n), x, x**2])
    beta = np.linalg.lstsq(X, 1.0 + 0.5 * x - 0.02 * x**2 + rng.normal(0.0, sigma, n), rcond=None)
    return X, rng, beta


def test_linear_regression_known_sigma_matches_analytic_covariance():
    """y = X b + e, e ~ N(0, sigma^2): Cov b = sigma^2 (X^T X)^-1 exactly. With residuals divided
    by the known sigma the Jacobian is X/sigma and s^2 = 1."""
    sigma = 0.3
    X, _, _ = _line_data(sigma=sigma)
    u = linearised_uncertainty(X / sigma, sigma_known=True)
    exact = sigma**2 * np.linalg.inv(X.T @ X)
    np.testing.assert_allclose(u.covariance, exact, rtol=1e-10)
    np.testing.assert_allclose(u.std_errors, np.sqrt(np.diag(exact)), rtol=1e-10)
    d = np.sqrt(np.diag(exact))
    np.testing.assert_allclose(u.correlation, exact / np.outer(d, d), rtol=1e-10, atol=1e-14)
    assert u.residual_variance == 1.0 and u.dof == X.shape[0] - 3
    assert not u.singular and u.rank == 3 and u.ci_low is None


def test_linear_regression_estimated_sigma_matches_ols_and_t_intervals():
    """Unknown sigma: s^2 = SSR/(n - p), intervals b +/- t(0.975, n - p) SE (the textbook OLS result)."""
    X, rng, _ = _line_data()
    y = X @ np.array([1.0, 0.5, -0.02]) + rng.normal(0.0, 0.3, X.shape[0])
    b, *_ = np.linalg.lstsq(X, y, rcond=None)
    r = y - X @ b
    n, p = X.shape
    s2 = r @ r / (n - p)
    u = linearised_uncertainty(-X, r, estimates=b, confidence=0.9)  # d(y - Xb)/db = -X
    np.testing.assert_allclose(u.covariance, s2 * np.linalg.inv(X.T @ X), rtol=1e-10)
    assert u.residual_variance == pytest.approx(s2, rel=1e-12)
    tq = stats.t.ppf(0.95, n - p)
    assert u.t_quantile == pytest.approx(tq, rel=1e-12)
    np.testing.assert_allclose(u.ci_low, b - tq * u.std_errors, rtol=1e-12)
    np.testing.assert_allclose(u.ci_high, b + tq * u.std_errors, rtol=1e-12)
    # the derived quantity b0 + b1 has delta-method variance g^T Cov g
    g = np.array([1.0, 1.0, 0.0])
    assert u.delta_se(g) == pytest.approx(np.sqrt(g @ u.covariance @ g), rel=1e-12)


def test_variance_inflation_and_inverse_methods_agree_when_regular():
    X, rng, _ = _line_data(seed=4)
    r = rng.normal(0.0, 1.0, X.shape[0])
    a = linearised_uncertainty(X, r, inverse="pinv")
    b = linearised_uncertainty(X, r, inverse="inv", variance_inflation=2.5)
    np.testing.assert_allclose(b.covariance, 2.5 * a.covariance, rtol=1e-9)
    np.testing.assert_allclose(b.std_errors, np.sqrt(2.5) * a.std_errors, rtol=1e-9)
    np.testing.assert_allclose(b.correlation, a.correlation, rtol=1e-9, atol=1e-12)


def test_singular_jacobian_flagged_with_null_direction_and_correlation():
    """Two identical columns (only their sum is determined): flagged singular, rank 2, the null
    direction is (0, 1, -1)/sqrt(2), the pair reported as correlated, and the pseudo-inverse
    covariance stays finite whatever inverse is asked for."""
    x = np.linspace(0.0, 1.0, 12)
    J = np.column_stack([np.ones_like(x), x, x])
    r = np.sin(7.0 * x)
    for inverse in ("pinv", "inv"):
        u = linearised_uncertainty(J, r, inverse=inverse)
        assert u.singular and u.rank == 2
        assert u.condition_number > 1e12 and u.jacobian_condition > 1e7
        nd = u.null_direction * np.sign(u.null_direction[1])
        np.testing.assert_allclose(nd, [0.0, 2**-0.5, -(2**-0.5)], atol=1e-8)
        assert np.all(np.isfinite(u.covariance)) and np.all(np.isfinite(u.std_errors))
        assert [(i, j) for i, j, _ in u.correlated_pairs] == [(1, 2)]
        assert u.correlated_pairs[0][2] == pytest.approx(1.0, abs=1e-9)
        np.testing.assert_allclose(u.covariance, np.linalg.pinv(J.T @ J) * (r @ r) / 9, rtol=1e-6, atol=1e-12)


def test_zero_column_gives_zero_correlation_not_nan():
    J = np.column_stack([np.linspace(1.0, 2.0, 6), np.zeros(6)])
    u = linearised_uncertainty(J, np.ones(6))
    assert u.singular and u.rank == 1
    assert u.std_errors[1] == 0.0
    np.testing.assert_array_equal(u.correlation, np.eye(2))


def test_thresholds_and_bad_input():
    x = np.linspace(0.0, 1.0, 10)
    J = np.column_stack([np.ones_like(x), x])
    u = linearised_uncertainty(J, np.ones(10), correlation_threshold=0.5)
    assert [(i, j) for i, j, _ in u.correlated_pairs] == [(0, 1)]  # r(intercept, slope) ~ -0.85
    assert linearised_uncertainty(J, np.ones(10), correlation_threshold=0.9).correlated_pairs == ()
    assert not linearised_uncertainty(J, np.ones(10), singular_rtol=0.0).singular
    assert linearised_uncertainty(J, np.ones(10), singular_rtol=0.5).singular
    with pytest.raises(ValueError, match="residuals"):
        linearised_uncertainty(J)
    with pytest.raises(ValueError, match="not both"):
        linearised_uncertainty(J, sigma_known=True, residual_variance=2.0)
    with pytest.raises(ValueError, match="inverse"):
        linearised_uncertainty(J, np.ones(10), inverse="lu")
    with pytest.raises(ValueError, match="2-D"):
        linearised_uncertainty(np.ones(10), np.ones(10))


@settings(max_examples=40, deadline=None)
@given(
    seed=st.integers(0, 2**32 - 1),
    scales=st.lists(st.floats(1e-3, 1e3), min_size=3, max_size=3),
)
def test_scaling_jacobian_columns_scales_std_errors_inversely(seed, scales):
    """Reparametrising theta_j = c_j phi_j multiplies column j of J by c_j: SE(phi_j) = SE(theta_j)/c_j,
    the correlations and the singularity verdict do not change."""
    rng = np.random.default_rng(seed)
    J = rng.normal(size=(15, 3))
    r = rng.normal(size=15)
    c = np.array(scales)
    a = linearised_uncertainty(J, r)
    b = linearised_uncertainty(J * c, r)
    np.testing.assert_allclose(b.std_errors, a.std_errors / c, rtol=1e-6)
    np.testing.assert_allclose(b.correlation, a.correlation, rtol=1e-6, atol=1e-9)
    assert b.residual_variance == a.residual_variance


def test_known_standard_deviations_give_the_normal_quantile():
    """With the residuals divided by known standard deviations nothing is estimated (s^2 = 1): the Wald interval is
    the normal's, as the profile likelihood's of the same fit (chi2(1)); it used Student's t at the residual degrees
    of freedom, 2.2x wider at 2 of them and 6.5x at 1 (found by a review of `rotarydryer calibrate --profile`).
    With the variance estimated from the residuals it stays Student's t."""
    J = np.array([[1.0, 0.0], [0.0, 2.0], [1.0, 1.0]])       # 3 residuals, 2 parameters: 1 dof
    known = linearised_uncertainty(J, sigma_known=True, estimates=[1.0, 2.0])
    assert known.t_quantile == pytest.approx(stats.norm.ppf(0.975), rel=1e-12)
    np.testing.assert_allclose(known.ci_high - known.ci_low, 2 * 1.959963984540054 * known.std_errors, rtol=1e-12)
    est = linearised_uncertainty(J, residuals=[0.1, -0.2, 0.1], estimates=[1.0, 2.0])
    assert est.t_quantile == pytest.approx(stats.t.ppf(0.975, 1), rel=1e-12)

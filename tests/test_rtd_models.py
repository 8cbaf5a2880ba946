"""Reference RTD models: E integrates to 1, numeric moments = analytic moments, limits."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import trapezoid

from rotarydryer.rtd import (
    AxialDispersion,
    TanksInSeries,
    axial_dispersion_e,
    axial_dispersion_moments,
    tanks_in_series_e,
    tanks_in_series_f,
    tanks_in_series_moments,
)
from rotarydryer.rtd.models import _adm_closed_image, _adm_closed_talbot


def numeric_moments(t, e):
    a = trapezoid(e, t)
    m = trapezoid(t * e, t) / a
    v = trapezoid((t - m) ** 2 * e, t) / a
    mu3 = trapezoid((t - m) ** 3 * e, t) / a
    return a, m, v, mu3 / v**1.5


def grid_for(mean, std, n=200001, lo=0.0):
    return np.linspace(lo, mean + 60 * std, n)


@pytest.mark.parametrize("tau,n", [(600.0, 1.0), (600.0, 1.7), (100.0, 5.0), (3.0, 30.0), (1000.0, 400.0)])
def test_tanks_in_series_numeric_moments_match_analytic(tau, n):
    am = tanks_in_series_moments(tau, n)
    t = grid_for(am.mean_s, am.std_s)
    a, m, v, sk = numeric_moments(t, tanks_in_series_e(t, tau, n))
    assert a == pytest.approx(1.0, abs=2e-6)
    assert m == pytest.approx(am.mean_s, rel=1e-6)
    assert v == pytest.approx(am.variance_s2, rel=1e-5)
    assert sk == pytest.approx(am.skewness, rel=1e-3)


def test_tanks_in_series_integer_n_equals_classical_formula():
    # Lee (2008) Eq. 2.11 reduces to the classical N-CSTR formula for integer N
    t = np.linspace(0.0, 3000.0, 301)
    tau, n = 500.0, 4
    classical = n**n * t ** (n - 1) * np.exp(-n * t / tau) / (math.factorial(n - 1) * tau**n)
    np.testing.assert_allclose(tanks_in_series_e(t, tau, n), classical, rtol=1e-12, atol=1e-300)


def test_tanks_in_series_f_is_integral_of_e():
    t = np.linspace(0.0, 5000.0, 50001)
    e = tanks_in_series_e(t, 700.0, 3.3)
    from scipy.integrate import cumulative_trapezoid

    np.testing.assert_allclose(cumulative_trapezoid(e, t, initial=0), tanks_in_series_f(t, 700.0, 3.3), atol=1e-7)


def test_tanks_in_series_large_n_approaches_plug_flow():
    # N -> large: F(t) -> step at tau (plug flow), variance tau^2/N -> 0
    tau = 600.0
    for n, width in [(1e2, 0.3), (1e4, 0.03), (1e6, 0.003)]:
        f = tanks_in_series_f(np.array([tau * (1 - width), tau * (1 + width)]), tau, n)
        assert f[0] < 0.01 and f[1] > 0.99
    assert tanks_in_series_moments(tau, 1e6).std_s / tau < 1.01e-3


def test_tanks_in_series_zero_and_negative_times():
    assert tanks_in_series_e(0.0, 10.0, 1.0) == pytest.approx(0.1)
    assert tanks_in_series_e(0.0, 10.0, 2.0) == 0.0
    assert tanks_in_series_e(-5.0, 10.0, 3.0) == 0.0


@pytest.mark.parametrize("boundary", ["closed", "open"])
@pytest.mark.parametrize("pe", [0.3, 1.0, 5.0, 20.0, 99.0, 100.0, 400.0, 5000.0, 1e6])
def test_dispersion_numeric_moments_match_analytic(pe, boundary):
    tau = 800.0
    am = axial_dispersion_moments(tau, pe, boundary)
    t = np.linspace(0.0, am.mean_s + 60 * am.std_s + (40 * tau if pe < 5 else 0), 200001)
    a, m, v, sk = numeric_moments(t, axial_dispersion_e(t, tau, pe, boundary))
    assert a == pytest.approx(1.0, abs=1e-8)
    assert m == pytest.approx(am.mean_s, rel=1e-8)
    assert v == pytest.approx(am.variance_s2, rel=1e-6)
    if am.skewness is not None:
        assert sk == pytest.approx(am.skewness, rel=1e-4)


def test_dispersion_analytic_moment_formulas():
    # Levenspiel (1999) ch. 13: closed-closed and open-open moments
    tau, pe = 120.0, 7.0
    c = axial_dispersion_moments(tau, pe, "closed")
    o = axial_dispersion_moments(tau, pe, "open")
    assert c.mean_s == pytest.approx(tau)
    assert c.variance_s2 == pytest.approx(tau**2 * (2 / pe - 2 / pe**2 * (1 - math.exp(-pe))))
    assert o.mean_s == pytest.approx(tau * (1 + 2 / pe))
    assert o.variance_s2 == pytest.approx(tau**2 * (2 / pe + 8 / pe**2))


@pytest.mark.parametrize("pe", [0.1, 1.0, 2.0, 10.0, 200.0])
def test_closed_dispersion_cumulants_from_transfer_function(pe):
    # independent of the inversion: Taylor coefficients of ln G(s) by a Cauchy integral
    # (FFT on a circle inside the radius of convergence Pe/4); kappa_k = (-1)^k k! c_k
    a = pe / 2
    rho = min(pe / 8, 0.5)
    s = rho * np.exp(2j * np.pi * np.arange(64) / 64)
    q = np.sqrt(1 + 4 * s / pe)
    ln_g = np.log(4 * q) + a * (1 - q) - np.log((1 + q) ** 2 - (1 - q) ** 2 * np.exp(-2 * q * a))
    c = np.fft.fft(ln_g) / 64
    kappa = [-c[1].real / rho, 2 * c[2].real / rho**2, -6 * c[3].real / rho**3]
    m = axial_dispersion_moments(1.0, pe, "closed")
    assert kappa[0] == pytest.approx(m.mean_s, rel=1e-9)
    assert kappa[1] == pytest.approx(m.variance_s2, rel=1e-9)
    assert kappa[2] == pytest.approx(m.skewness * m.variance_s2**1.5, rel=1e-8)


def test_closed_dispersion_branches_agree_at_switch():
    # Talbot inversion (Pe < 100) and closed-form first image term (Pe >= 100)
    th = np.linspace(0.01, 3.0, 3001)
    for pe in [100.0, 300.0]:
        a = _adm_closed_talbot(th, np.full_like(th, pe), nodes=40)
        b = _adm_closed_image(th, np.full_like(th, pe))
        assert np.max(np.abs(a - b)) < 1e-9 * np.max(b)


def test_closed_dispersion_small_pe_matches_eigenfunction_series():
    # Independent check: residue (eigenfunction) series of the Wehner-Wilhelm
    # transfer function, poles at 2 atan(mu) + mu Pe/2 = k pi; accurate for theta >~ 0.3.
    from scipy.optimize import brentq

    pe, a = 2.0, 1.0
    th = np.linspace(0.3, 6.0, 58)
    total = np.zeros_like(th)
    for k in range(1, 400):
        def g(m, k=k):
            return 2 * math.atan(m) + m * a - k * math.pi

        mu = brentq(g, (k - 1) * math.pi / (a + 2) * 0.5, k * math.pi / a)
        q = 1j * mu
        dD = (2 * (1 + q) + a * (1 + q) ** 2) * np.exp(q * a) + (2 * (1 - q) + a * (1 - q) ** 2) * np.exp(-q * a)
        res = (4 * a * q**2 * math.exp(a) / dD).real
        total += res * np.exp(-a * (1 + mu**2) / 2 * th)
    np.testing.assert_allclose(axial_dispersion_e(th, 1.0, pe, "closed"), total, rtol=1e-7, atol=1e-10)


def test_dispersion_large_pe_approaches_tanks_in_series_with_n_pe_over_2():
    # classical limit: ADM with large Pe ~ TiS with N = Pe/2 (Levenspiel 1999 ch. 14)
    tau = 600.0
    t = np.linspace(1.0, 1200.0, 2400)
    for pe, tol in [(200.0, 0.06), (2000.0, 0.02)]:
        adm = axial_dispersion_e(t, tau, pe, "closed")
        tis = tanks_in_series_e(t, tau, pe / 2)
        assert np.max(np.abs(adm - tis)) < tol * np.max(tis)
        assert math.sqrt(axial_dispersion_moments(tau, pe).variance_s2) == pytest.approx(
            tanks_in_series_moments(tau, pe / 2).std_s, rel=2 / pe
        )


def test_open_and_closed_agree_at_large_pe():
    # the open-open mean is shifted by 2 tau/Pe, i.e. by sqrt(2/Pe) standard deviations
    for pe in (1e3, 1e5):
        t = np.linspace(400.0, 800.0, 4001)
        c = axial_dispersion_e(t, 600.0, pe, "closed")
        o = axial_dispersion_e(t, 600.0, pe, "open")
        assert np.max(np.abs(c - o)) < math.sqrt(2 / pe) * c.max()


def test_broadcasting_over_parameters():
    t = np.linspace(0, 3000, 7)[:, None]
    e = tanks_in_series_e(t, np.array([300.0, 600.0]), 3.0)
    assert e.shape == (7, 2)
    e2 = axial_dispersion_e(t, 600.0, np.array([[1.0, 50.0, 500.0]]))
    assert e2.shape == (7, 3)
    np.testing.assert_allclose(e2[:, 1], axial_dispersion_e(t[:, 0], 600.0, 50.0))
    m = tanks_in_series_moments(np.array([1.0, 2.0]), 4.0)
    np.testing.assert_allclose(m.variance_s2, [0.25, 1.0])


@settings(max_examples=40, deadline=None)
@given(
    tau=st.floats(1.0, 1e4),
    pe=st.floats(0.5, 1e4),
    boundary=st.sampled_from(["closed", "open"]),
)
def test_dispersion_e_nonnegative_and_finite(tau, pe, boundary):
    t = np.linspace(0.0, 5 * tau, 501)
    e = axial_dispersion_e(t, tau, pe, boundary)
    assert np.all(np.isfinite(e)) and np.all(e >= 0)


@settings(max_examples=40, deadline=None)
@given(pe1=st.floats(0.2, 5e3), factor=st.floats(1.05, 10.0))
def test_variance_decreases_with_peclet(pe1, factor):
    for b in ("closed", "open"):
        v_hi = axial_dispersion_moments(1.0, pe1 * factor, b).variance_s2
        assert v_hi < axial_dispersion_moments(1.0, pe1, b).variance_s2


@settings(max_examples=40, deadline=None)
@given(n1=st.floats(1.0, 1e5), factor=st.floats(1.01, 10.0))
def test_tis_variance_and_skewness_decrease_with_n(n1, factor):
    a, b = tanks_in_series_moments(1.0, n1), tanks_in_series_moments(1.0, n1 * factor)
    assert b.variance_s2 < a.variance_s2 and b.skewness < a.skewness


@pytest.mark.parametrize(
    "call,match",
    [
        (lambda: tanks_in_series_e(1.0, -1.0, 2.0), "mean_residence_time_s"),
        (lambda: tanks_in_series_e(1.0, 1.0, 0.5), "n_tanks"),
        (lambda: tanks_in_series_e(float("nan"), 1.0, 2.0), "time_s"),
        (lambda: axial_dispersion_e(1.0, 1.0, 0.0), "peclet"),
        (lambda: axial_dispersion_e(1.0, 1.0, 10.0, "semi"), "boundary"),
        (lambda: AxialDispersion(0.0, 10.0), "space_time_s"),
        (lambda: TanksInSeries(10.0, 1e9), "n_tanks"),
    ],
)
def test_bad_input_raises_naming_argument(call, match):
    with pytest.raises(ValueError, match=match):
        call()

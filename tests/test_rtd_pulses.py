"""Tracer inputs and convolution: moments add, analytic special cases."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import trapezoid
from scipy.stats import truncnorm

from rotarydryer.rtd import (
    AxialDispersion,
    TanksInSeries,
    convolve_rtd,
    convolve_sampled_rtd,
    convolved_moments,
    pulse_input,
    rtd_moments,
    tanks_in_series_f,
)


def test_lee_pulse_moments():
    # Lee (2008) App. I Experiment entity: 39.6 s rectangular pulse
    p = pulse_input("rectangular", 39.6)
    assert p.mean_s == pytest.approx(19.8) and p.variance_s2 == pytest.approx(39.6**2 / 12)


def test_gaussian_pulse_moments_match_truncated_normal():
    d = 120.0
    p = pulse_input("gaussian", d)
    ref = truncnorm(-3, 3, loc=d / 2, scale=d / 6)
    assert p.mean_s == pytest.approx(ref.mean())
    assert p.variance_s2 == pytest.approx(ref.var(), rel=1e-12)
    t = np.linspace(0, d, 20001)
    assert trapezoid(p.density(t), t) == pytest.approx(1.0, abs=1e-8)


@pytest.mark.parametrize("kind", ["dirac", "rectangular", "gaussian", "array"])
@pytest.mark.parametrize("model", [TanksInSeries(600.0, 3.0), AxialDispersion(500.0, 12.0, "closed")])
def test_convolution_moments_add(kind, model):
    if kind == "array":
        tt = np.linspace(0, 90, 10)
        pulse = pulse_input(tt, values=np.exp(-tt / 30.0))
    else:
        pulse = pulse_input(kind, 90.0)
    t = np.linspace(0, 12000, 6001)
    y = convolve_rtd(model.e, t, pulse)
    m = rtd_moments(t, y)
    ref = convolved_moments(model.moments(), pulse)
    assert m.area == pytest.approx(1.0, abs=1e-6)
    assert m.mean_s == pytest.approx(ref.mean_s, rel=1e-6)
    assert m.variance_s2 == pytest.approx(ref.variance_s2, rel=1e-5)
    if ref.skewness is not None:
        assert m.skewness == pytest.approx(ref.skewness, rel=1e-3)


def test_rectangular_convolution_equals_cdf_difference():
    # (E * rect_d)(t) = (F(t) - F(t - d)) / d exactly
    d, tau, n = 60.0, 700.0, 2.5
    t = np.linspace(0, 4000, 401)
    y = convolve_rtd(TanksInSeries(tau, n).e, t, pulse_input("rectangular", d))
    exact = (tanks_in_series_f(t, tau, n) - tanks_in_series_f(t - d, tau, n)) / d
    late = t >= 3 * d  # E smooth over the pulse window: quadrature at round-off level
    np.testing.assert_allclose(y[late], exact[late], rtol=1e-8, atol=1e-14)
    # within one pulse duration of t = 0 the rule ends at the t^1.5 start of E
    np.testing.assert_allclose(y, exact, rtol=0, atol=1e-7 * exact.max())


def test_dirac_is_identity_and_sampled_matches_analytic():
    m = TanksInSeries(600.0, 4.0)
    t = np.linspace(0, 6000, 6001)
    np.testing.assert_allclose(convolve_rtd(m.e, t, pulse_input("dirac")), m.e(t))
    p = pulse_input("rectangular", 40.0)
    np.testing.assert_allclose(convolve_sampled_rtd(t, m.e(t), p), convolve_rtd(m.e, t, p), atol=1e-8)


@settings(max_examples=25, deadline=None)
@given(d=st.floats(1.0, 600.0), n=st.floats(2.0, 50.0))
def test_convolution_conserves_tracer(d, n):
    m = TanksInSeries(600.0, n)
    t = np.linspace(0, 600 + d + 40 * 600 / np.sqrt(n) + 3000, 20001)
    y = convolve_rtd(m.e, t, pulse_input("rectangular", d))
    assert trapezoid(y, t) == pytest.approx(1.0, abs=2e-4)
    assert np.all(y >= 0)


@pytest.mark.parametrize(
    "args,kwargs,match",
    [
        (("square", 10.0), {}, "kind"),
        (("rectangular",), {}, "duration_s"),
        (("rectangular", -1.0), {}, "duration_s"),
        (([0.0, 1.0, 0.5],), dict(values=[1, 1, 1]), "increasing"),
        (([0.0, 1.0, 2.0],), dict(values=[1, -1, 1]), ">= 0"),
        (([0.0, 1.0, 2.0],), {}, "values"),
    ],
)
def test_bad_pulse_input(args, kwargs, match):
    with pytest.raises(ValueError, match=match):
        pulse_input(*args, **kwargs)

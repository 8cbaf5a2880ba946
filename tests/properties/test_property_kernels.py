"""Issue 16: the compiled humid-air, water and gas-radiation kernels (numba) give the numbers of their
NumPy references (:mod:`rotarydryer.properties._kernels`) over the whole property range, in every
shape the solvers pass, and fall back to NumPy with a warning when numba fails."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from rotarydryer import _jit
from rotarydryer.properties import _kernels, water
from rotarydryer.properties import humid_air as ha
from rotarydryer.thermal import radiation as rad

pytestmark = pytest.mark.skipif(not _jit.available(), reason="compiled kernels off (no numba or ROTARYDRYER_JIT=0)")

T = st.floats(0.0, 600.0)
Y = st.floats(0.0, 0.3)


def _reference_heat(t, y):
    return (ha._dry_air_heat_capacity(t) + y * ha._species_heat_capacity("H2O", t), ha._dry_air_enthalpy(t),
            ha._vapour_enthalpy(t))


@settings(max_examples=80, deadline=None)
@given(t=arrays(float, st.integers(1, 40), elements=T), y=Y)
def test_transport_and_heat_equal_their_numpy_references(t, y):
    mu, k = ha._transport(t, y)
    mu0, k0 = ha._transport_numpy(t, y)
    np.testing.assert_allclose(mu, mu0, rtol=2e-15, atol=0)
    np.testing.assert_allclose(k, k0, rtol=2e-15, atol=0)
    cs, air, vap = ha._heat_terms(t, y)
    cs0, air0, vap0 = _reference_heat(t, y)
    np.testing.assert_allclose(cs, cs0, rtol=1e-15, atol=0)
    np.testing.assert_allclose(air, air0, rtol=1e-14, atol=1e-9)      # J/kg; zero at 0 degC
    np.testing.assert_allclose(vap, vap0, rtol=1e-15, atol=0)
    np.testing.assert_allclose(ha._enthalpy(t, y), air0 + y * vap0, rtol=1e-14, atol=1e-9)
    np.testing.assert_allclose(ha._heat_capacity(t, y), cs0 / (1 + y), rtol=1e-15, atol=0)


@settings(max_examples=60, deadline=None)
@given(t=arrays(float, st.integers(1, 40), elements=st.floats(-100.0, 373.9)))
def test_saturation_pressure_equals_wagner_pruss_and_the_ice_line(t):
    np.testing.assert_allclose(water._saturation_pressure(t), water._saturation_pressure_numpy_k(t + 273.15),
                               rtol=2e-14, atol=0)


@settings(max_examples=60, deadline=None)
@given(t=arrays(float, st.integers(1, 40), elements=T), p=st.floats(5e4, 2e5))
def test_diffusivity_equals_marrero_mason_with_its_blend(t, p):
    np.testing.assert_allclose(ha._water_vapour_diffusivity(t, p), ha._water_vapour_diffusivity_numpy(t, p),
                               rtol=2e-15, atol=0)


def test_the_blend_window_and_the_triple_point_edges():
    t = np.array([176.0, 176.35, 176.5, 176.85, 177.2, 177.35, 177.5]) - 0.0
    np.testing.assert_allclose(ha._water_vapour_diffusivity(t, 101325.0),
                               ha._water_vapour_diffusivity_numpy(t, 101325.0), rtol=2e-15)
    tt = np.array([0.0, 0.01, 0.0100001, -0.01, 373.946])
    np.testing.assert_allclose(water._saturation_pressure(tt), water._saturation_pressure_numpy_k(tt + 273.15),
                               rtol=2e-14)


def test_shapes_the_solvers_pass():
    """Scalars give NumPy scalars, a batch (k, n) keeps its shape, a per-stage humidity broadcasts
    against a batch of temperatures, empty arrays stay empty."""
    mu, k = ha._transport(20.0, 0.0)
    assert isinstance(mu, np.floating) and isinstance(k, np.floating)
    assert float(mu) * 1e6 == pytest.approx(18.191, abs=1e-3)           # the doctest value
    t = np.linspace(20.0, 580.0, 12).reshape(3, 4)
    y = np.array([0.0, 0.05, 0.1, 0.3])
    for got, want in zip(ha._transport(t, y), ha._transport_numpy(t, y)):
        assert got.shape == (3, 4)
        np.testing.assert_allclose(got, want, rtol=2e-15)
    assert ha._humid_heat(t, y).shape == (3, 4)
    assert ha._water_vapour_diffusivity(t, np.array([1e5, 1.1e5, 9e4, 101325.0])).shape == (3, 4)
    assert water._saturation_pressure(t[:, :2] / 6).shape == (3, 2)
    assert rad._emissivity(t + 273.15, 1e4 * y, 1.1e3, 3.6).shape == (3, 4)
    for a in ha._transport(np.empty(0), 0.1) + ha._heat_terms(np.empty(0), 0.1):
        assert a.shape == (0,)
    assert ha._enthalpy_parts(25.0)[0] == pytest.approx(ha._dry_air_enthalpy(25.0), rel=1e-15)


def test_not_finite_inputs_give_not_finite_values_as_numpy_does():
    mu, k = ha._transport(np.array([np.nan, 20.0]), 0.01)
    assert np.isnan(mu[0]) and np.isnan(k[0]) and np.isfinite(mu[1])
    assert np.isnan(ha._humid_heat(np.array([np.nan]), 0.0)[0])


def test_a_failing_kernel_falls_back_to_numpy_with_a_warning(monkeypatch):
    t, y = np.array([25.0, 300.0]), np.array([0.01, 0.2])
    want = ha._transport_numpy(t, y)

    def broken(*args):
        raise RuntimeError("no LLVM here")
    monkeypatch.setattr(_jit, "_DISABLED", _jit._DISABLED)          # restored after the test
    monkeypatch.setitem(_kernels._compiled, "transport", broken)
    with pytest.warns(RuntimeWarning, match="compiled kernels disabled .RuntimeError: no LLVM here.; using NumPy"):
        got = ha._transport(t, y)
    assert not _jit.enabled()
    np.testing.assert_array_equal(got, want)
    # every kernel is off now: the NumPy forms, bit for bit
    np.testing.assert_array_equal(ha._humid_heat(t, y), _reference_heat(t, y)[0])
    np.testing.assert_array_equal(water._saturation_pressure(t / 4), water._saturation_pressure_numpy_k(t / 4 + 273.15))


def test_packed_coefficients_follow_the_reference_tables():
    """The kernels read the coefficients of the reference functions (packed at import), not copies."""
    from rotarydryer.properties import combustion as cb

    c = ha._KERNEL_COEFFICIENTS
    assert tuple(c[:9]) == cb._LEMMON_JACOBSEN["air"]
    assert tuple(c[_kernels._NASA:_kernels._NASA + 7]) == cb._NASA["N2"]
    assert tuple(c[_kernels._NASA + 21:_kernels._NASA + 28]) == cb._NASA["H2O"]
    assert c[_kernels._R] == cb.GAS_CONSTANT and c[_kernels._LAT] == ha._LATENT_REF

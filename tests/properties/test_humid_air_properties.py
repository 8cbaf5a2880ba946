"""Humid-air, water and combustion-gas properties: published values, limits, monotonicity, bad input.

Needs no reference library (the CoolProp/psychrolib comparisons are in test_humid_air.py).
"""

import doctest

import numpy as np
import pytest
from hypothesis import assume, example, given, settings
from hypothesis import strategies as st

from rotarydryer.properties import combustion, water
from rotarydryer.properties import humid_air as ha


@pytest.mark.parametrize("module", [ha, water, combustion], ids=lambda m: m.__name__)
def test_doctests(module):
    result = doctest.testmod(module, optionflags=doctest.NORMALIZE_WHITESPACE, verbose=False)
    assert result.failed == 0 and result.attempted > 0


def test_ice_branch_and_continuity_at_triple_point():
    assert float(water.saturation_pressure(0.01)) == pytest.approx(611.657, rel=1e-5)
    assert float(water.saturation_pressure(0.0099999)) == pytest.approx(611.657, rel=1e-4)
    # IAPWS R14-08 check value: 611.657 Pa at 273.16 K, 0.0131 Pa at 200 K is outside; at 253.15 K ~103.2 Pa
    assert float(water.saturation_pressure(-20.0)) == pytest.approx(103.26, rel=2e-3)


def test_ajayi_compatibility_values():
    """Ajayi (2011) App. F correlations reproduce the notes' sanity values at 500 degC (ajayi_energy.md 1.11)."""
    assert float(ha.density(500.0, 0.0, method="ajayi2011")) == pytest.approx(0.445, abs=0.001)
    assert float(ha.thermal_conductivity(500.0, 0.0, method="ajayi2011")) == pytest.approx(0.0558, abs=0.0001)
    assert float(ha.viscosity(500.0, 0.0, method="ajayi2011")) == pytest.approx(3.51e-5, abs=0.01e-5)
    assert float(water.vapour_heat_capacity(500.0, method="ajayi2011_as_coded")) == pytest.approx(2.12, abs=0.01)
    # and the physical model is close to Ajayi's fits for dry air (3 % density, 5 % viscosity)
    assert float(ha.density(500.0, 0.0)) == pytest.approx(0.445, rel=0.03)
    assert float(ha.viscosity(500.0, 0.0)) == pytest.approx(3.51e-5, rel=0.05)


def test_diffusivity_matches_ajayi_constant_and_is_continuous():
    # Ajayi's D_AB = 2.65e-5 m2/s (L4008) is the Marrero-Mason value at ~33 degC
    assert float(ha.water_vapour_diffusivity(33.0)) == pytest.approx(2.65e-5, rel=0.01)
    below = float(ha.water_vapour_diffusivity(450.0 - 273.15 - 1e-9))
    above = float(ha.water_vapour_diffusivity(450.0 - 273.15 + 1e-9))
    assert above == pytest.approx(below, rel=0.005)
    # Fuller-Schettler-Giddings (Poling Eq. 11-4.4) at 25 degC: 2.55e-5 m2/s; the two agree within 5 %
    assert float(ha.water_vapour_diffusivity(25.0)) == pytest.approx(2.55e-5, rel=0.05)


def test_humidity_conversions_roundtrip():
    y = np.linspace(0, 0.3, 31)
    assert np.allclose(ha.humidity_from_mass_fraction(ha.mass_fraction_from_humidity(y)), y)
    pv = ha.vapour_partial_pressure(y)
    assert np.allclose(ha.humidity_from_vapour_pressure(pv), y)
    assert float(ha.humidity_from_relative_humidity(30.0, 1.0)) == pytest.approx(float(ha.saturation_humidity(30.0)))


@pytest.mark.parametrize("bad", [
    lambda: ha.enthalpy(-41.0, 0.01),
    lambda: ha.enthalpy(601.0, 0.01),
    lambda: ha.enthalpy(100.0, 1.01),       # above humid_air.Y_MAX
    lambda: ha.enthalpy(float("nan"), 0.01),
    lambda: ha.density(100.0, 0.01, pressure=-1.0),
    lambda: ha.saturation_humidity(100.5),
    lambda: water.saturation_pressure(380.0),
    lambda: water.latent_heat(20.0, method="nope"),
    lambda: ha.dew_point(0.0),
])
def test_bad_input_raises_value_error(bad):
    with pytest.raises(ValueError):
        bad()


def test_vectorised_broadcasting():
    t = np.linspace(0, 600, 7)[:, None]
    y = np.linspace(0, 0.3, 4)[None, :]
    for f in (ha.heat_capacity, ha.enthalpy, ha.density, ha.viscosity, ha.thermal_conductivity):
        out = f(t, y)
        assert out.shape == (7, 4)
        assert np.all(np.isfinite(out))


# ---------------------------------------------------------------- property tests (hypothesis)

temps = st.floats(0.0, 600.0)
hums = st.floats(0.0, 0.3)


@settings(max_examples=60, deadline=None)
@given(t=st.floats(0.0, 599.0), dt=st.floats(0.01, 1.0), y=hums)
def test_enthalpy_increases_with_temperature_and_cp_is_its_derivative(t, dt, y):
    h1, h2 = float(ha.enthalpy(t, y)), float(ha.enthalpy(t + dt, y))
    assert h2 > h1
    # dh/dT per kg dry air = humid heat (ideal gas): mean-value check
    cs = float(ha.humid_heat(t + dt / 2, y))
    assert (h2 - h1) / dt == pytest.approx(cs, rel=1e-4)


@settings(max_examples=60, deadline=None)
@given(t=temps, y=st.floats(0.0, 0.29), dy=st.floats(1e-4, 0.01))
def test_monotone_in_humidity(t, y, dy):
    y2 = min(y + dy, 0.3)
    assert float(ha.enthalpy(t, y2)) > float(ha.enthalpy(t, y))
    assert float(ha.density(t, y2)) < float(ha.density(t, y))  # water vapour is lighter than air
    assert float(ha.heat_capacity(t, y2)) > float(ha.heat_capacity(t, y))


@settings(max_examples=40, deadline=None)
@given(t=st.floats(5.0, 600.0), y=st.floats(0.001, 0.3))
def test_wet_bulb_between_dew_point_and_dry_bulb(t, y):
    if float(ha.relative_humidity(t, y)) >= 1.0:
        return
    try:
        wb = float(ha.wet_bulb_temperature(t, y))
    except ValueError as exc:  # cold dry air: wet bulb below the 0 degC model range
        assert "below 0 degC" in str(exc)
        return
    assert wb <= t + 1e-9
    assert wb >= float(ha.dew_point(y)) - 1e-6


@settings(max_examples=40, deadline=None)
@given(t=st.floats(0.0, 370.0), dt=st.floats(0.1, 3.0))
def test_saturation_pressure_increasing_and_latent_heat_decreasing(t, dt):
    t2 = min(t + dt, 370.0)
    if t2 <= t:
        return
    assert float(water.saturation_pressure(t2)) > float(water.saturation_pressure(t))
    assert float(water.latent_heat(t2)) < float(water.latent_heat(t))


@settings(max_examples=40, deadline=None)
@given(t=temps)
def test_dry_limit_equals_dry_air(t):
    assert float(ha.heat_capacity(t, 0.0)) == pytest.approx(float(ha.dry_air_heat_capacity(t)))
    assert float(ha.viscosity(t, 0.0)) == pytest.approx(float(combustion.lemmon_jacobsen_viscosity("air", t + 273.15)))


def test_combustion_gas_against_published_values():
    """Ideal-gas c_p of dry air at 300 K: 1005 J/(kg K) (Incropera Table A.4: 1.007 kJ/(kg K)); flue-gas mixture rules."""
    assert float(combustion.heat_capacity(26.85, combustion.DRY_AIR_COMPOSITION)) == pytest.approx(1007.0, rel=0.005)
    x = {"N2": 0.75, "O2": 0.187, "Ar": 0.009, "CO2": 0.011, "H2O": 0.039, "SO2": 0.004}
    assert float(combustion.mixture_molar_mass(x)) == pytest.approx(sum(
        v * combustion.MOLAR_MASS[k] for k, v in x.items()))
    w = combustion.mass_fractions(x)
    assert np.allclose(combustion.mole_fractions_from_mass(w), [x[s] for s in combustion.SPECIES])
    with pytest.raises(ValueError, match="sum to 1"):
        combustion.heat_capacity(100.0, {"N2": 0.5})


def test_diffusivity_branches_blend_smoothly_at_450_k():
    """Marrero & Mason's two power laws meet at 450 K with slopes a quarter apart: blended over
    449.5-450.5 K (continuous with a continuous slope), each unchanged outside that window."""
    t = np.linspace(448.0, 452.0, 4001) - 273.15
    d = ha.water_vapour_diffusivity(t)
    tk = t + 273.15
    low, high = 1.87e-10 * tk**2.072, 2.75e-9 * tk**1.632
    out = np.abs(tk - 450.0) > 0.5
    # unchanged outside the window (to rounding: numba's pow may differ from NumPy's in the last bit)
    np.testing.assert_allclose(d[out], np.where(tk < 450.0, low, high)[out], rtol=1e-15, atol=0)
    inside = ~out
    assert np.all((d[inside] - np.minimum(low, high)[inside]) >= -1e-20)
    assert np.all((np.maximum(low, high)[inside] - d[inside]) >= -1e-20)
    slope = np.diff(np.log(d)) / np.diff(np.log(tk))           # d ln D / d ln T
    assert np.max(np.abs(np.diff(slope))) < 2e-3                # no jump (it was 0.44 at 450 K)
    assert np.max(np.abs(np.diff(np.log(d)))) < 1e-5            # no step in value (it was 1.8e-4)
    assert slope[0] == pytest.approx(2.072, abs=1e-3) and slope[-1] == pytest.approx(1.632, abs=1e-3)


@settings(max_examples=200, deadline=None)
@given(st.floats(-30.0, 600.0), st.floats(0.0, 0.2), st.floats(-20.0, 80.0), st.floats(60e3, 110e3))
@example(16.0, 0.0, 0.0, 60000.0)         # an ice bulb at -0.84 degC against 0 degC, where the bulb's enthalpy jumps
@example(13.0, 0.0, 3.272932348434437e-284, 73451.0)      # ... and against a threshold just above 0 degC
@example(17.0, 0.0, 0.0, 60000.0)         # a root on each side of 0 degC (ice -0.x, liquid +0.49): the liquid bulb
@example(17.0, 0.0, 0.3, 60000.0)         # ... against a threshold between the two
def test_wet_bulb_below_agrees_with_the_wet_bulb(t, y, threshold, p):
    """`wet_bulb_below` (one evaluation of the balance) says what the solved wet bulb says."""
    assume(float(ha.relative_humidity(t, y, p)) < 1.0)
    try:
        wb = float(ha.wet_bulb_temperature(t, y, p))
    except ValueError:          # below the model's range: nothing to compare
        return
    assume(abs(wb - threshold) > 1e-6)
    assert bool(ha.wet_bulb_below(t, y, threshold, p)) == (wb < threshold)

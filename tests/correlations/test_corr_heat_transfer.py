"""Heat-transfer correlations: Song (2003) Tables 3.1-3.3, Ajayi (2011) Eq. 6.41."""

import csv
import math
import warnings
from importlib import resources

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.correlations import (
    CorrelationRangeWarning,
    chilton_colburn_mass_transfer_coefficient,
    heat_transfer_coefficient,
    log_mean_temperature_difference,
    nusselt_number,
    nusselt_number_methods,
    ua_from_drying_data,
    volumetric_heat_transfer_coefficient,
    volumetric_heat_transfer_coefficient_methods,
)
from rotarydryer.correlations.heat_transfer import (
    douglas_1993_ua,
    friedman_marshall_1949_ua,
    miller_1942_ua,
    sharples_1964_ua,
)

# Renaud pilot dryer (Song 2003 L1108): 0.159 m3/s STP air, 0.31 m diameter, 3 m long
RENAUD_G = 0.159 * 1.293 / (math.pi / 4 * 0.31**2)
RENAUD_D = 0.31
RENAUD_V = math.pi / 4 * 0.31**2 * 3.0


def _table_3_3():
    text = resources.files("rotarydryer").joinpath("data", "song_table3_3_heat_mass_coeffs.csv").read_text()
    rows = list(csv.DictReader(line for line in text.splitlines() if not line.startswith("#")))
    return [{k: float(v) for k, v in r.items()} for r in rows]


@pytest.mark.parametrize(
    "method, kwargs, expected",
    [  # hand values from the printed Table 3.1 formulas at the Renaud conditions (notes/song.md §5.4)
        ("mccormick_1962", {}, 1496.0),
        ("myklestad_1963", {}, 943.0),
        ("alvarez_shene_1994", {"material": "sand"}, 2041.0),
        ("miller_1942", {"n_flights": 6}, 2276.0),
        ("friedman_marshall_1949", {}, 37.9),
    ],
)
def test_table_3_1_at_renaud_conditions(method, kwargs, expected):
    ua = volumetric_heat_transfer_coefficient(method, gas_mass_flux=RENAUD_G, diameter=RENAUD_D, **kwargs)
    assert ua == pytest.approx(expected, rel=0.002)


def test_measured_ua_lies_between_correlations():
    """Song's measured Ua ~ 200 W/(m3 K) lies between F&M (counter-current) and McCormick (notes §5.4)."""
    measured = [r["Ua_W_m3C"] for r in _table_3_3()]
    assert friedman_marshall_1949_ua(RENAUD_G, RENAUD_D) < min(measured)
    assert volumetric_heat_transfer_coefficient("mccormick_1962", gas_mass_flux=RENAUD_G,
                                                diameter=RENAUD_D) > 4 * max(measured)


def test_song_eq_3_9_reproduces_table_3_3():
    """Eq. 3.9 with the printed temperatures and moistures reproduces Table 3.3 Ua within 7 %."""
    for r in _table_3_3():
        dry_feed = 67.5 / 3600 / (1 + r["X_in"])  # 67.5 kg/h wet feed (L1108)
        ua = ua_from_drying_data(dry_feed, r["X_in"], r["X_out"], RENAUD_V,
                                 r["Tg_in_C"], r["Tg_out_C"], r["Ts_in_C"], r["Ts_out_C"])
        assert ua == pytest.approx(r["Ua_W_m3C"], rel=0.07)


def test_chilton_colburn_reproduces_table_3_3():
    """Eq. 3.8 with the gas density reproduces the Table 3.3 Chilton-Colburn K_m a within 6 %."""
    for r in _table_3_3():
        t = 273.15 + 0.5 * (r["Tg_in_C"] + r["Tg_out_C"])
        rho = 101325 * 0.02897 / (8.314 * t)
        kma = chilton_colburn_mass_transfer_coefficient(r["Ua_W_m3C"], rho, 1006.0, 0.60, 0.71, t)
        assert kma * 1e3 == pytest.approx(r["Kma_CC_kg_m3_s_kPa"], rel=0.06)


def test_chilton_colburn_independent_of_temperature_for_ideal_gas():
    vals = []
    for t in (300.0, 400.0, 500.0):
        rho = 101325 * 0.02897 / (8.314 * t)
        vals.append(chilton_colburn_mass_transfer_coefficient(200.0, rho, 1006.0, 0.6, 0.71, t))
    assert np.ptp(vals) < 1e-12


def test_miller_twelve_flight_reading():
    ditto = miller_1942_ua(1.0, 1.0, n_flights=12)
    none = miller_1942_ua(1.0, 1.0, n_flights=12, twelve_flight_factor="none")
    assert ditto == pytest.approx(62 * 11) and none == pytest.approx(62)
    assert ditto > miller_1942_ua(1.0, 1.0, n_flights=6)
    with pytest.raises(ValueError, match="n_flights"):
        miller_1942_ua(1.0, 1.0, n_flights=8)


def test_ua_constants_required():
    with pytest.raises(ValueError, match="constant"):
        friedman_marshall_1949_ua(1.0, 1.0, gas_flow="co-current")
    assert friedman_marshall_1949_ua(1.0, 2.0, gas_flow="co-current", constant=50.0) == pytest.approx(25.0)
    assert sharples_1964_ua(4.0, 3.0, 10.0) == pytest.approx(60.0)
    assert douglas_1993_ua(1.0, 1.0, 100.0, 1.0, 5.0, 1.0) == pytest.approx(5.0)
    methods = volumetric_heat_transfer_coefficient_methods(gas_mass_flux=1.0, diameter=1.0)
    assert "sharples_1964" not in methods and "mccormick_1962" in methods
    assert "sharples_1964" in volumetric_heat_transfer_coefficient_methods(gas_mass_flux=1.0, rpm=3, constant=1)


def test_ajayi_2011_heat_transfer_coefficient():
    """Ajayi Eq. 6.41 at 500 C: Re ~ 1490, d_p = 0.02 m, k_g = 0.0561 W/(m K) -> h_c ~ 74 W/(m2 K)."""
    nu = nusselt_number(1490.0, method="ajayi_2011")
    assert heat_transfer_coefficient(nu, 0.0561, 0.02) == pytest.approx(74.0, rel=0.01)
    assert nu == nusselt_number(1490.0, method="mcadams_1951")


def test_ranz_marshall_limits_and_warning():
    assert nusselt_number(0.0, 0.7, method="ranz_marshall_1952") == pytest.approx(2.0)
    with pytest.warns(CorrelationRangeWarning, match=r"0\.0014"):
        nusselt_number(100.0, 0.7, method="ranz_marshall_1952", particle_diameter=444e-6)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        nusselt_number(100.0, 0.7, method="ranz_marshall_1952", particle_diameter=2e-3)


def test_nusselt_dispatcher_errors():
    with pytest.raises(ValueError, match="prandtl"):
        nusselt_number(100.0, method="ranz_marshall_1952")
    with pytest.raises(ValueError, match="reynolds"):
        nusselt_number(-1.0, 0.7)
    with pytest.raises(ValueError, match="method"):
        nusselt_number(10.0, 0.7, method="bogus")
    assert "tscheng_watkinson_1979_solids" in nusselt_number_methods(reynolds=1.0, rotational_reynolds=10.0,
                                                                     fill_fraction=0.1)


@settings(max_examples=50, deadline=None)
@given(re=st.floats(0.1, 1e4), factor=st.floats(1.01, 10.0), pr=st.floats(0.5, 5.0))
def test_nusselt_increases_with_reynolds(re, factor, pr):
    extra = dict(rotational_reynolds=500.0, fill_fraction=0.1)
    for m in ("ranz_marshall_1952", "ajayi_2011", "van_krevelen_hoftijzer", "kunii_levenspiel_1977",
              "chang_1994", "alvarez_shene_1994", "tscheng_watkinson_1979_solids", "tscheng_watkinson_1979_wall"):
        assert nusselt_number(re * factor, pr, method=m, **extra) > nusselt_number(re, pr, method=m, **extra)


@settings(max_examples=50, deadline=None)
@given(a=st.floats(0.1, 500.0), b=st.floats(0.1, 500.0))
def test_lmtd_bounded_and_symmetric(a, b):
    lm = log_mean_temperature_difference(a, b)
    assert min(a, b) * (1 - 1e-9) <= lm <= max(a, b) * (1 + 1e-9)
    assert lm == pytest.approx(log_mean_temperature_difference(b, a), rel=1e-9)
    assert lm <= 0.5 * (a + b) * (1 + 1e-9)

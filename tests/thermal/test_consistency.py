"""Energetic consistency of plant tests (rotarydryer.thermal.consistency)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.cases import load_case
from rotarydryer.simulation import build_thermal_dryer
from rotarydryer.thermal.consistency import (
    balance_gas_outlet_temperature,
    implied_gas_flow,
    max_gas_outlet_temperature,
    measured_balances,
    pi_test_conditions,
)

Y_IN = 0.0193 / (1 - 0.0193)          # Ajayi l.3227


@pytest.fixture(scope="module")
def model():
    return {t: build_thermal_dryer(load_case("ajayi2011_mmg", {"operating.test": t, "geometry.method": "ajayi2011_regressions"})).steady_state() for t in (4, 6)}


@given(g=st.floats(12.0, 60.0), t_in=st.floats(300.0, 600.0), x_out=st.floats(0.10, 0.15),
       loss=st.floats(0.0, 1e6))
@settings(max_examples=30, deadline=None)
def test_gas_flow_and_outlet_temperature_are_inverse(g, t_in, x_out, loss):
    kw = dict(gas_in_c=t_in, gas_humidity_in=Y_IN, feed_rate=40.0, moisture_in=0.163, moisture_out=x_out,
              solids_in_c=28.0, solids_out_c=55.0, heat_loss=loss)
    try:
        t_out = balance_gas_outlet_temperature(g, **kw)
    except ValueError:
        return                                          # this gas cannot do the job: nothing to invert
    if t_out > t_in:
        return
    assert implied_gas_flow(gas_out_c=t_out, **kw) == pytest.approx(g, rel=1e-8)


def test_model_steady_state_obeys_its_overall_balance(model):
    """The coupled model's Test 4 outlets, put through the outlet balance, give back its gas flow."""
    ss = model[4]
    c = pi_test_conditions(4)
    g = implied_gas_flow(ss.dryer.settings.gas_inlet_temperature, Y_IN, ss.gas_outlet_temperature_degC,
                         ss.dryer.feed_rate, ss.dryer.feed_moisture, ss.product_moisture, 28.0,
                         ss.product_temperature_degC, heat_loss=ss.shell_heat_loss_w)
    assert g == pytest.approx(ss.dryer.settings.gas_flow, rel=0.01)
    assert c["gas_out_c"] == 131.0


def test_test6_needs_more_gas_than_test4(model):
    """Measured balances (PI data) with the model's shell loss and product temperature: Test 6 needs
    ~22 % more gas than Test 4; the tests' gas flows differ (Ajayi used one value for all)."""
    tests = (4, 6)
    b = measured_balances(tests, heat_loss=[model[t].shell_heat_loss_w for t in tests],
                          product_c=[model[t].product_temperature_degC for t in tests])
    g4, g6 = b[0].gas_flow_at_product_c, b[1].gas_flow_at_product_c
    assert g4 == pytest.approx(model[4].dryer.settings.gas_flow, rel=0.02)   # the tuned value
    assert 1.15 < g6 / g4 < 1.30


def test_test6_gas_outlet_bound_at_test4_gas_flow(model):
    """Any energy-conserving model with Test 4's gas flow and the model's shell loss: with the product
    inside the moisture tolerance (<= 0.122 + 0.007) and no colder than the exhaust dew point, Test 6's
    gas outlet is at most ~130 degC, i.e. the 20 K acceptance band (>= 130) is reachable only at its corner."""
    c = pi_test_conditions(6)
    ss = model[6]
    bound = max_gas_outlet_temperature(ss.dryer.settings.gas_flow, c["gas_in_c"], Y_IN, ss.dryer.feed_rate,
                                       ss.dryer.feed_moisture, c["moisture_out"] + 0.007, 28.0,
                                       heat_loss=ss.shell_heat_loss_w)
    assert 125.0 < bound["gas_out_c"] < 133.0
    # the coupled model sits below the bound: it is wetter-bulbed than the dew point
    assert ss.gas_outlet_temperature_degC < bound["gas_out_c"]
    assert ss.product_temperature_degC > bound["product_c"]


def test_measured_product_temperature_below_exhaust_dew_point():
    """All six tests: the measured product temperature (45-50 degC) lies below the dew point of the exhaust
    implied by the measured balance (no shell loss: the most gas-rich, driest reading)."""
    for b in measured_balances(heat_loss=0.0):
        assert b.product_c < b.exhaust_dew_point_c - 5.0, b
        assert 12.0 < b.gas_flow < 26.0


def test_bad_input_is_named():
    kw = dict(gas_in_c=500.0, gas_humidity_in=Y_IN, gas_out_c=131.0, feed_rate=40.0, moisture_in=0.163,
              solids_in_c=28.0, solids_out_c=46.0)
    with pytest.raises(ValueError, match="moisture_out"):
        implied_gas_flow(moisture_out=0.2, **kw)
    with pytest.raises(ValueError, match="gas_out_c"):
        implied_gas_flow(**{**kw, "gas_out_c": 520.0}, moisture_out=0.12)
    with pytest.raises(ValueError, match="heat_loss"):
        implied_gas_flow(moisture_out=0.12, heat_loss=1e9, **kw)
    with pytest.raises(ValueError, match="test"):
        pi_test_conditions(9)
    with pytest.raises(ValueError, match="gas_humidity_in"):
        max_gas_outlet_temperature(16.0, 500.0, -0.01, 40.0, 0.163, 0.13, 28.0)
    with pytest.raises(ValueError, match="cannot carry"):
        balance_gas_outlet_temperature(1.0, 500.0, Y_IN, 40.0, 0.163, 0.12, 28.0, 46.0)
    assert np.isfinite(implied_gas_flow(moisture_out=0.124, **kw))


def test_test6_with_its_balance_implied_gas_flow(model):
    """Given the gas flow its own measured balance implies (a consistency check, not a validation: the
    flow uses the measured outlets), the Test-4-tuned model predicts Test 6 within Ajayi's accuracy."""
    ss6 = model[6]
    g6 = measured_balances((6,), heat_loss=ss6.shell_heat_loss_w,
                           product_c=ss6.product_temperature_degC)[0].gas_flow_at_product_c
    ss = build_thermal_dryer(load_case("ajayi2011_mmg", {"operating.test": 6, "thermal.gas_flow": g6, "geometry.method": "ajayi2011_regressions"})).steady_state()
    c = pi_test_conditions(6)
    assert abs(ss.product_moisture - c["moisture_out"]) <= 0.007
    assert abs(ss.gas_outlet_temperature_degC - c["gas_out_c"]) <= 20.0
    assert ss.gas_outlet_temperature_degC > ss6.gas_outlet_temperature_degC + 5.0


def test_a_tests_own_gas_flow_replaces_the_default(tmp_path):
    """[[tests]] gas_flow (kg/s) is used for that test in the physical mode; others keep thermal.gas_flow."""
    from importlib import resources
    text = (resources.files("rotarydryer.cases") / "ajayi2011_mmg.toml").read_text()
    text = text.replace("test = 6\n", "test = 6\ngas_flow = 19.5\n", 1)
    path = tmp_path / "mmg_with_flow.toml"
    path.write_text(text)
    thesis = {"geometry.method": "ajayi2011_regressions"}   # one gas flow for all tests in its calibration record
    assert build_thermal_dryer(load_case(str(path), {"operating.test": 6, **thesis})).settings.gas_flow == 19.5
    assert build_thermal_dryer(load_case(str(path), {"operating.test": 4, **thesis})).settings.gas_flow == 16.25
    compat = build_thermal_dryer(load_case(str(path), {"operating.test": 6, "thermal.mode": "ajayi2011"}))
    assert compat.settings.gas_flow == pytest.approx(112675.6688 / 3600)

"""Stream enthalpies and the overall energy balance of Ajayi's Test 4 (issue 6 item 6: both readings)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.published import read_published_csv
from rotarydryer.thermal import burner as b
from rotarydryer.thermal import shell as sh
from rotarydryer.thermal import streams as s

PI = {r["test"]: r for r in read_published_csv("ajayi_pi_operating_conditions.csv")}
T4 = PI["4"]
F_AIN = 112675.6688 / 3600.0          # gPROMS code L3225
Y_AIN = 0.0193 / (1 - 0.0193)         # L3227


def _test4(method, gas_flow=F_AIN, y_in=Y_AIN):
    return s.implied_heat_loss(gas_flow, float(T4["gas_inlet_T_C"]), y_in, float(T4["gas_outlet_T_C"]),
                               146320 / 3600, float(T4["solid_inlet_moisture_pct"]) / 100,
                               float(T4["product_moisture_pct"]) / 100, 28.0, float(T4["product_T_C"]), method=method)


def test_test4_balance_as_in_the_notes():
    """Notes 2.2 (DERIVED): evaporation 1.81 kg/s; gas 18.04 -> 10.76 MW; solids 1.26 -> 1.72 MW; loss 6.8 MW."""
    r = _test4("ajayi2011_as_coded")
    assert r["evaporation"] == pytest.approx(1.81, abs=0.005)
    assert r["gas_in"] / 1e6 == pytest.approx(18.04, abs=0.01)
    assert r["gas_out"] / 1e6 == pytest.approx(10.76, abs=0.01)
    assert r["solids_in"] / 1e6 == pytest.approx(1.26, abs=0.01)
    assert r["solids_out"] / 1e6 == pytest.approx(1.72, abs=0.01)
    assert r["heat_loss"] / 1e6 == pytest.approx(6.8, abs=0.05)


def test_the_imbalance_is_the_gas_flow_not_the_vapour_heat_capacity():
    """Consistent Cp_v (kJ read) or full physical properties leave the 6.8-7.2 MW imbalance; the burner-consistent
    gas flow (750 kg/h fuel -> 500 degC, Appendix A) brings it to ~1.4 MW, of the order of a physical shell loss."""
    assert _test4("ajayi2011")["heat_loss"] / 1e6 == pytest.approx(7.19, abs=0.05)
    assert _test4("physical")["heat_loss"] / 1e6 == pytest.approx(6.91, abs=0.05)
    air_c = b.normal_volume_to_mass(23698.0)
    # dilution air that gives 500 degC with 750 kg/h of fuel
    lo, hi = 1.0, 30.0
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        t = float(b.combustion_chamber(750 / 3600, air_c, mid).temperature_c)
        lo, hi = (mid, hi) if t > 500 else (lo, mid)
    gas = b.combustion_chamber(750 / 3600, air_c, 0.5 * (lo + hi))
    r = _test4("physical", float(gas.mass_flow), float(gas.humidity))
    assert float(gas.mass_flow) == pytest.approx(17.0, abs=0.1)
    assert r["heat_loss"] / 1e6 == pytest.approx(1.36, abs=0.05)
    x = np.linspace(0.05, 22.15, 222)
    tg = 500.0 - 369.0 * x / 22.2
    shell = float(np.sum(sh.shell_heat_loss(tg, float(gas.mass_flow), x[1] - x[0]).heat_loss))
    assert 0.3 < shell / r["heat_loss"] < 1.0


def test_water_balance_closes():
    r = _test4("physical")
    dry_gas = F_AIN / (1 + Y_AIN)
    water_in = 146320 / 3600 * 0.163 + dry_gas * Y_AIN
    water_out = (146320 / 3600 - r["evaporation"]) * 0.124 + dry_gas * r["gas_out_humidity"]
    assert water_out == pytest.approx(water_in, rel=1e-12)


@settings(max_examples=30, deadline=None)
@given(t_out=st.floats(60.0, 300.0), dt=st.floats(1.0, 50.0))
def test_implied_loss_falls_as_gas_leaves_hotter(t_out, dt):
    a = s.implied_heat_loss(F_AIN, 500.0, Y_AIN, t_out, 40.0, 0.163, 0.124, 28.0, 46.0)
    b_ = s.implied_heat_loss(F_AIN, 500.0, Y_AIN, min(t_out + dt, 500.0), 40.0, 0.163, 0.124, 28.0, 46.0)
    assert b_["heat_loss"] < a["heat_loss"]


def test_methods_agree_for_dry_gas_heating():
    """Without water the three gas enthalpies differ only by the dry-gas heat capacity (1070 vs NASA air)."""
    h_phys = float(s.gas_stream_enthalpy(1.0, 300.0, 0.0))
    h_aj = float(s.gas_stream_enthalpy(1.0, 300.0, 0.0, "ajayi2011"))
    assert h_aj == pytest.approx(1070 * 300)
    assert h_phys == pytest.approx(h_aj, rel=0.06)


def test_bad_input():
    with pytest.raises(ValueError):
        s.gas_stream_enthalpy(1.0, 300.0, 0.0, method="ideal")
    with pytest.raises(ValueError):
        s.solids_stream_enthalpy(-1.0, 0.1, 30.0)
    with pytest.raises(ValueError):
        s.evaporation_rate(10.0, 0.1, 1.0)

"""Combustion chamber (Ajayi 2011 Appendix A): reproduction of Table A1/A2 numbers, balances, bad input."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.published import read_published_csv
from rotarydryer.thermal import burner as b

TABLE_A1 = {r["stream"]: r for r in read_published_csv("ajayi_combustion_appendixA.csv")}
TABLE_A2 = {r["property"]: r for r in read_published_csv("ajayi_fuel_oil_tableA2.csv")}
FUEL_750 = float(TABLE_A2["typical fuel consumption"]["value"]) / 3600.0  # kg/s
AIR_D = b.normal_volume_to_mass(float(TABLE_A1["dilution air"]["flow_Nm3_per_h"]))
AIR_C = b.normal_volume_to_mass(float(TABLE_A1["combustion air"]["flow_Nm3_per_h"]))


def test_table_a1_flows_from_fan_curves():
    d, c = TABLE_A1["dilution air"], TABLE_A1["combustion air"]
    assert float(b.fan_flow(float(d["fan_opening_pct"]), "dilution")) == pytest.approx(float(d["flow_Nm3_per_h"]),
                                                                                       rel=1e-4)
    # Table A1's combustion-air flow is Eq. A1 at 15.80 %, not Eq. A2 (which gives 9601 Nm3/h)
    op = float(c["fan_opening_pct"])
    assert float(b.fan_flow(op, "combustion", curve="a1_for_both")) == pytest.approx(float(c["flow_Nm3_per_h"]),
                                                                                     rel=1e-4)
    assert float(b.fan_flow(op, "combustion")) == pytest.approx(float(c["fan_curve_A2_check_Nm3_per_h"]), rel=1e-4)
    for row in (d, c):
        assert float(b.normal_volume_to_molar(float(row["flow_Nm3_per_h"]))) == pytest.approx(
            float(row["flow_kmol_per_h"]), abs=0.6)


def test_table_a2_fuel_composition_and_heating_value():
    fuel = b.AJAYI_FUEL_OIL
    assert fuel.water_mass_fraction == pytest.approx(float(TABLE_A2["water content"]["value"]) / 100)
    assert fuel.sulphur_mass_fraction == pytest.approx(float(TABLE_A2["sulphur content"]["value"]) / 100)
    assert fuel.carbon_mass_fraction / fuel.hydrogen_mass_fraction == pytest.approx(7.6)
    assert fuel.carbon_mass_fraction == pytest.approx(0.8722, abs=5e-4)   # notes ajayi_energy.md section 3
    molar = b.FuelOil(ratio_basis="molar")
    assert molar.carbon_mass_fraction == pytest.approx(0.976, abs=1e-3)
    # heavy fuel oil LHV 40-42.5 MJ/kg (typical); Channiwala-Parikh on Table A2 gives 41.6
    assert 40e6 < fuel.lhv < 42.5e6


def test_stoichiometric_oxygen_and_excess_air_of_appendix_a():
    """Notes (DERIVED): 750 kg/h needs ~76 kmol/h O2 (362 kmol/h air); hot gas holds ~19 % O2."""
    assert b.AJAYI_FUEL_OIL.stoichiometric_oxygen() * 750.0 == pytest.approx(76.0, rel=0.01)
    gas = b.combustion_chamber(FUEL_750, AIR_C, AIR_D)
    assert float(gas.oxygen_wet) == pytest.approx(0.19, abs=0.005)
    total_air_kmol_h = (float(TABLE_A1["dilution air"]["flow_kmol_per_h"])
                        + float(TABLE_A1["combustion air"]["flow_kmol_per_h"]))
    assert total_air_kmol_h / (76.0 / 0.2096) == pytest.approx(13.8, rel=0.02)  # ~14x stoichiometric


def test_gproms_gas_flow_is_the_dilution_air():
    """Ajayi's F_ain = 112675.6688 kg/h (L3225) equals the Table A1 dilution air as humid air at H_ain."""
    assert AIR_D * 3600 == pytest.approx(112675.6688, rel=0.003)


def test_energy_balance_shows_fuel_and_gas_flow_inconsistent():
    """750 kg/h of fuel cannot heat the Table A1 air to 500 degC: it reaches ~235 degC; 500 degC needs ~1.77 t/h."""
    gas = b.combustion_chamber(FUEL_750, AIR_C, AIR_D)
    assert float(gas.temperature_c) == pytest.approx(235.0, abs=3.0)
    assert gas.energy_balance_error < 1e-9
    assert gas.element_balance_error < 1e-12
    fuel = b.fuel_rate_for_temperature(500.0, AIR_C, AIR_D)
    assert fuel * 3600 == pytest.approx(1767.0, rel=0.01)
    assert float(b.combustion_chamber(fuel, AIR_C, AIR_D).temperature_c) == pytest.approx(500.0, abs=1e-6)
    with pytest.raises(ValueError, match="burner cannot reach target_temperature_c = 500"):
        b.fuel_rate_for_temperature(500.0, AIR_C, AIR_D, max_fuel_rate=FUEL_750)


def test_energy_balance_closes_by_independent_recount():
    """Recount the enthalpy balance from the returned composition (not the solver's residual)."""
    from rotarydryer.properties import combustion as comb
    gas = b.combustion_chamber(FUEL_750, AIR_C, AIR_D, air_temperature_c=30.0, heat_loss_fraction=0.05)
    h_out = float(gas.mass_flow) * float(comb.enthalpy(gas.temperature_c, gas.composition, reference_c=25.0))
    air = b._air_moles(AIR_C + AIR_D, b.AJAYI_AIR_HUMIDITY)
    h_air = sum(air[s] * b._h_molar(s, 30.0) for s in air) * 1000.0
    q = 0.95 * FUEL_750 * b.AJAYI_FUEL_OIL.lhv
    assert h_out == pytest.approx(h_air + q, rel=1e-8)
    assert float(gas.heat_loss) == pytest.approx(0.05 * FUEL_750 * b.AJAYI_FUEL_OIL.lhv)


def test_flame_needs_enough_combustion_air():
    with pytest.raises(ValueError, match="flame cannot burn"):
        b.combustion_chamber(1.0, 0.5, 40.0)


def test_target_below_air_temperature_raises():
    with pytest.raises(ValueError, match="below the air temperature"):
        b.fuel_rate_for_temperature(20.0, AIR_C, AIR_D)


@pytest.mark.parametrize("kwargs", [dict(fuel_rate=-1.0), dict(air_humidity=0.5), dict(heat_loss_fraction=1.5),
                                    dict(combustion_air=float("nan"))])
def test_bad_input(kwargs):
    args = dict(fuel_rate=FUEL_750, combustion_air=AIR_C, dilution_air=AIR_D)
    args.update(kwargs)
    with pytest.raises(ValueError):
        b.combustion_chamber(**args)


@settings(max_examples=30, deadline=None)
@given(f1=st.floats(0.0, 0.25), df=st.floats(0.01, 0.2), dil=st.floats(20.0, 40.0))
def test_temperature_increases_with_fuel_and_mass_is_conserved(f1, df, dil):
    g1 = b.combustion_chamber(f1, AIR_C, dil)
    g2 = b.combustion_chamber(f1 + df, AIR_C, dil)
    assert float(g2.temperature_c) > float(g1.temperature_c)
    assert float(g2.mass_flow) == pytest.approx(AIR_C + dil + f1 + df, rel=1e-9)


@settings(max_examples=20, deadline=None)
@given(dil=st.floats(10.0, 40.0), ddil=st.floats(1.0, 10.0))
def test_more_dilution_air_cools_the_gas(dil, ddil):
    assert float(b.combustion_chamber(FUEL_750, AIR_C, dil + ddil).temperature_c) < float(
        b.combustion_chamber(FUEL_750, AIR_C, dil).temperature_c)


def test_vectorised_over_fuel_rate():
    f = np.linspace(0.0, 0.4, 5)
    gas = b.combustion_chamber(f, AIR_C, AIR_D)
    assert gas.temperature_c.shape == (5,)
    assert np.all(np.diff(gas.temperature_c) > 0)
    assert float(gas.temperature_c[0]) == pytest.approx(26.0, abs=1e-6)

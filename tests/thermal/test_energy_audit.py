"""Issue 34 items 3-5: the energy audit of a coupled steady state (heat duties that add up to the
release, the exhaust's dew point, the shell against a limit), exhaust recycle and the site's altitude."""

from __future__ import annotations

import math
import warnings
from importlib import resources

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rotarydryer import Simulation
from rotarydryer.properties import humid_air as ha
from rotarydryer.thermal.audit import HEAT_DUTY_PARTS, ShellTemperatureWarning, shell_sections
from rotarydryer.thermal.burner import (
    fuel_rate_for_temperature,
    fuel_rate_with_recycle,
    normal_volume_to_mass,
)
from rotarydryer.thermal.settings import DryerError, ThermalSettings

TEMPLATE = str(resources.files("rotarydryer.cases") / "templates" / "dryer.toml")
#: every shipped case with heat and mass transfer, both modes of the MMG case, and the case `rotarydryer new` writes
CASES = [("ajayi2011_mmg", {}), ("ajayi2011_mmg", {"thermal.mode": "ajayi2011"}),
         ("ajayi2011_mmg", {"operating.test": 3}), ("lee2008_invicta", {}), ("song2003_ottawa", {}),
         (TEMPLATE, {})]


def _steady(case, ov=None):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")       # the predictive-range warnings of the pilot and template cases
        return Simulation(case, ov or {}).steady_state().thermal


def _closure(s: dict) -> float:
    """|release - the sum of the duties| / release, the duties summed without the closure term."""
    parts = math.fsum(s[k] for k in HEAT_DUTY_PARTS if k != "heat_duty_closure_W")
    return abs(s["heat_release_W"] - parts) / s["heat_release_W"]


@pytest.mark.parametrize("case,ov", CASES, ids=["mmg", "mmg-ajayi2011", "mmg-test3", "invicta", "song", "template"])
def test_heat_duties_add_up_to_the_release(case, ov):
    s = _steady(case, ov).summary()
    assert _closure(s) < 1e-9, s["heat_duty_closure_W"]
    assert math.fsum(s[k] for k in HEAT_DUTY_PARTS) == pytest.approx(s["heat_release_W"], rel=1e-14)
    # each duty is where the heat goes (the water heating may be negative: a feed warmer than where it evaporates)
    assert s["heat_duty_evaporation_W"] > 0 and s["shell_heat_loss_W"] > 0 and s["heat_duty_exhaust_sensible_W"] > 0
    assert s["heat_duty_burner_loss_W"] >= 0 and s["heat_duty_leak_air_W"] == 0.0
    # the efficiency is the evaporation duty over the heat put into the gas
    assert s["thermal_efficiency"] == pytest.approx(s["heat_duty_evaporation_W"] / s["heat_input_W"], rel=1e-12)
    # the exhaust's latent heat (not a part) is the evaporated water's at ambient: near the evaporation duty
    assert s["heat_duty_exhaust_latent_W"] == pytest.approx(s["heat_duty_evaporation_W"], rel=0.15)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(feed=st.floats(30.0, 50.0), t_in=st.floats(420.0, 560.0), recycle=st.floats(0.0, 0.4),
       leak=st.floats(0.0, 3.0), insulation=st.floats(0.0, 0.1))
def test_heat_duties_add_up_at_any_operating_point(feed, t_in, recycle, leak, insulation):
    s = _steady("ajayi2011_mmg", {"operating.feed_rate": feed, "gas.inlet_temperature": t_in,
                                  "gas.recycle_fraction": recycle, "gas.leak_air_flow": leak,
                                  "shell.insulation_thickness": insulation}).summary()
    assert _closure(s) < 1e-9
    assert (s["heat_duty_leak_air_W"] > 0) == (leak > 0)


def test_release_is_the_fuels_heat_where_the_case_has_a_burner():
    th = _steady("ajayi2011_mmg")
    s = th.summary()
    b = th.dryer.settings.burner
    assert s["heat_release_W"] == pytest.approx(s["fuel_rate_kg_s"] * b.fuel.lhv, rel=1e-15)
    # the adiabatic chamber: the burner loss is the combustion products' enthalpy beyond humid air (~2.5 %)
    assert 0.01 < s["heat_duty_burner_loss_W"] / s["heat_release_W"] < 0.04
    # without a burner the release is the heat put into the gas
    s2 = _steady("lee2008_invicta").summary()
    assert s2["heat_release_W"] == s2["heat_input_W"] and s2["heat_duty_burner_loss_W"] == 0.0


@pytest.mark.parametrize("altitude", [0.0, 2000.0])
def test_dew_point_margin_matches_humid_air(altitude):
    th = _steady("ajayi2011_mmg", {"site.altitude": altitude})
    s = th.summary()
    p = ha.standard_atmosphere_pressure(altitude)
    assert s["gas_pressure_Pa"] == pytest.approx(float(p), rel=1e-15)
    dew = float(ha.dew_point(s["gas_outlet_humidity_kg_kg"], p))
    assert s["gas_outlet_dew_point_degC"] == pytest.approx(dew, abs=1e-9)
    assert s["gas_outlet_dew_point_margin_K"] == pytest.approx(s["gas_outlet_temperature_degC"] - dew, abs=1e-9)
    # at the dew point the exhaust is saturated
    assert float(ha.relative_humidity(dew, s["gas_outlet_humidity_kg_kg"], p)) == pytest.approx(1.0, abs=1e-6)


def test_altitude_zero_is_todays_model_bit_for_bit():
    for case, ov in (("ajayi2011_mmg", {}), ("ajayi2011_mmg", {"thermal.mode": "ajayi2011"})):
        a, b = _steady(case, ov), _steady(case, {**ov, "site.altitude": 0.0, "gas.recycle_fraction": 0.0})
        assert a.state.tobytes() == b.state.tobytes()
        assert b.dryer.settings.pressure == (101325.0 if not ov else 101045.0)


def test_altitude_2000_m_lowers_the_pressure_and_dries_more():
    assert float(ha.standard_atmosphere_pressure(2000.0)) == pytest.approx(79495.2, abs=0.5)   # ISO 2533 table
    lo, hi = _steady("ajayi2011_mmg").summary(), _steady("ajayi2011_mmg", {"site.altitude": 2000.0}).summary()
    assert hi["gas_pressure_Pa"] == pytest.approx(79495.2, abs=0.5)
    # the same humidity ratio holds less vapour pressure: a lower dew point; the drying force p_sat - p_v is larger
    assert hi["product_moisture_kg_kg"] < lo["product_moisture_kg_kg"]
    assert hi["evaporation_kg_s"] > lo["evaporation_kg_s"]
    assert float(ha.dew_point(lo["gas_outlet_humidity_kg_kg"], 79495.2)) < lo["gas_outlet_dew_point_degC"]
    assert hi["gas_outlet_dew_point_margin_K"] > lo["gas_outlet_dew_point_margin_K"]
    # the burner's balance is per kg: the heat input at the same gas flow and temperatures is the same
    assert hi["heat_input_W"] == lo["heat_input_W"]


def test_recycle_closes_the_balances_and_saves_fuel_at_the_same_inlet_temperature():
    base, rec = _steady("ajayi2011_mmg"), _steady("ajayi2011_mmg", {"gas.recycle_fraction": 0.2})
    s0, s = base.summary(), rec.summary()
    assert s["water_balance_error"] < 1e-9 and s["energy_balance_error"] < 1e-9 and _closure(s) < 1e-9
    assert s["fuel_rate_kg_s"] < s0["fuel_rate_kg_s"] and s["heat_input_W"] < s0["heat_input_W"]
    # the drum's inlet gas: fresh gas and 20 % of the exhaust
    dr = rec.dryer
    y_in, _ = dr.inlet_gas(rec.gas_humidity)
    assert y_in == pytest.approx(dr.gas_inlet_Y + 0.2 * (s["gas_outlet_humidity_kg_kg"] - dr.hot_gas_Y), rel=1e-14)
    assert rec.gas_humidity[dr.gas_order[0]] > base.gas_humidity[base.dryer.gas_order[0]]
    # the stack carries 80 % of the exhaust: less sensible heat out
    assert s["heat_duty_exhaust_sensible_W"] < s0["heat_duty_exhaust_sensible_W"]


def test_recycle_adds_its_jacobian_entries_only_when_on():
    d0 = Simulation("ajayi2011_mmg").dryer()
    p0 = d0.sparsity()
    d1 = d0.with_parameters(settings=ThermalSettings(**{**d0.settings.__dict__, "recycle_fraction": 0.2}))
    p1 = d1.sparsity()
    assert p1.nnz == p0.nnz + 2 and d0.sparsity() is p0
    nt, ng = d0.n_tanks, d0.n_gas
    first, last = d0.gas_order[0], d0.gas_outlet_stage
    assert p1[3 * nt + first, 3 * nt + ng + last] == 1 and p1[3 * nt + ng + first, 3 * nt + ng + last] == 1
    # the dryer with recycle converges from the model without it
    assert d1.steady_state().energy_balance_error < 1e-9


def test_recycle_fraction_one_or_more_is_refused_naming_the_key():
    with pytest.raises(ValueError, match=r"gas\.recycle_fraction = 1 .*\[0, 1\)"):
        ThermalSettings(gas_flow=10.0, gas_inlet_temperature=300.0, recycle_fraction=1.0).validate()
    with pytest.raises(DryerError, match=r"gas\.recycle_fraction = 0\.9 .*gas\.leak_air_flow"):
        ThermalSettings(gas_flow=10.0, gas_inlet_temperature=300.0, recycle_fraction=0.9,
                        leak_air_flow=5.0).validate()


def test_fuel_with_recycle_is_the_chambers_balance():
    air_d, air_c = normal_volume_to_mass(88050.0), normal_volume_to_mass(23698.0)
    f0 = fuel_rate_for_temperature(500.0, air_c, air_d, air_temperature_c=26.0)
    # a "recycle" of the dilution air itself (same temperature and humidity): the same fuel
    from rotarydryer.thermal.burner import AJAYI_AIR_HUMIDITY
    f1 = fuel_rate_with_recycle(500.0, air_c, air_d - 5.0, 5.0, 26.0, AJAYI_AIR_HUMIDITY, air_temperature_c=26.0)
    assert f1 == pytest.approx(f0, rel=1e-12)
    # a hot recycle needs less fuel; more than the flame can burn is refused
    assert fuel_rate_with_recycle(500.0, air_c, air_d - 5.0, 5.0, 150.0, 0.1) < f0
    with pytest.raises(ValueError, match="dilution air"):
        fuel_rate_with_recycle(500.0, air_c, -1.0, 5.0, 150.0, 0.1)


def test_shell_temperatures_against_the_limit():
    th = _steady("ajayi2011_mmg", {"shell.insulation_thickness": 0.1, "shell.max_temperature": 300.0})
    s = th.summary()
    # lagging keeps the outside cool and the steel hot (Ajayi (2011) Ch. 7: the 593 degC limit with insulation)
    assert s["shell_max_wall_temperature_degC"] > 300.0 > s["shell_max_surface_temperature_degC"]
    assert s["shell_temperature_limit_degC"] == 300.0 and s["shell_temperature_limit_exceeded"] is True
    with pytest.warns(ShellTemperatureWarning, match=r"shell\.max_temperature = 300"):
        Simulation("ajayi2011_mmg", {"shell.insulation_thickness": 0.1, "shell.max_temperature": 300.0}).steady_state()
    bare = _steady("ajayi2011_mmg", {"shell.max_temperature": 593.0}).summary()
    assert bare["shell_temperature_limit_exceeded"] is False
    assert bare["shell_max_wall_temperature_degC"] >= bare["shell_max_surface_temperature_degC"]
    assert _steady("ajayi2011_mmg").summary()["shell_temperature_limit_exceeded"] is None


def test_shell_per_section_adds_up_to_the_models_loss():
    th = _steady("ajayi2011_mmg", {"shell.scale_thickness": 0.005})
    rows = shell_sections(th)
    assert [r["section"] for r in rows] == ["A", "B", "C", "D", "E"]
    assert math.fsum(r["shell_heat_loss_W"] for r in rows) == pytest.approx(th.shell_heat_loss_w, rel=1e-12)
    assert sum(r["length_m"] for r in rows) == pytest.approx(22.2, rel=1e-12)
    # the shell network re-solved at the state's gas: the model's loss per stage (the same root)
    from rotarydryer.thermal.shell import shell_heat_loss

    dr, p = th.dryer, th.shell_profile()
    s = dr.settings
    r = shell_heat_loss(th.gas_temperature_degC, dr.dry_gas_flow * (1 + th.gas_humidity), dr.gas_len,
                        s.ambient_temperature, gas_humidity=th.gas_humidity, co2_mole_fraction=s.co2_mole_fraction,
                        inner_radius=dr.shell_inner_radius, shell_thickness=dr.shell_thickness,
                        scale_thickness=s.scale_thickness, scale_conductivity=s.scale_conductivity,
                        pressure=s.pressure, ambient_humidity=s.ambient_humidity)
    assert np.allclose(r.heat_loss, p["shell_heat_loss_W"], rtol=1e-7)
    # the steel's inside face lies under the scale: cooler than the scale's surface, hotter than the outside
    assert np.all(p["wall_temperature_degC"] < r.inner_surface_temperature_c)
    assert np.all(p["wall_temperature_degC"] > p["surface_temperature_degC"])


def test_hot_dry_solids_at_altitude_stay_below_the_local_boiling_point():
    """The template's bone-dry product (~109 degC) at 1500 m: the surface-evaporation model's solids clip
    follows the local boiling point (99 degC at sea level, bit for bit; 94.7 degC at 1500 m)."""
    from rotarydryer.thermal.balances import solids_temperature_ceiling

    assert solids_temperature_ceiling(101325.0) == 99.0 and solids_temperature_ceiling(101045.0) == 99.0
    p = float(ha.standard_atmosphere_pressure(1500.0))
    from rotarydryer.properties.water import saturation_pressure

    assert float(saturation_pressure(solids_temperature_ceiling(p))) == pytest.approx(0.99 * p, rel=1e-9)  # below boiling
    s0 = _steady(TEMPLATE).summary()
    s = _steady(TEMPLATE, {"site.altitude": 1500.0}).summary()
    assert s0["product_temperature_degC"] > 100.0 and s["product_temperature_degC"] > 100.0
    assert _closure(s) < 1e-9 and s["gas_outlet_dew_point_degC"] < s0["gas_outlet_dew_point_degC"]


def test_the_audit_of_an_unconverged_state_still_reads():
    """The CLI saves a failed solve's last iterate with its summary (rotarydryer simulate --diagnostics):
    the audit's outputs of any state are numbers, never an exception."""
    from rotarydryer.thermal.states import ThermalSteadyState

    d = Simulation("ajayi2011_mmg", {"shell.ambient_temperature": -30.0}).dryer()
    s = ThermalSteadyState(d, d.initial_state()).summary(with_fuel=False)
    assert math.isfinite(s["heat_release_W"]) and math.isfinite(s["shell_max_wall_temperature_degC"])


def test_gas_below_the_ambient_has_no_specific_energy(tmp_path):
    """A gas at 22 degC under a 25 degC ambient puts no heat into the dryer (heat input < 0: the feed at 10 degC
    and the surroundings dry it): the specific energy and the efficiency are undefined on every surface (before:
    a negative kJ/kg, and 'thermal efficiency nan %' in the report)."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    ov = {"gas.inlet_temperature": 22.0, "gas.inlet_humidity": 0.005, "operating.feed_temperature": 10.0}
    sc = Simulation(TEMPLATE, ov).results(rtd=False).scalars
    assert sc["heat_input_W"] < 0 and sc["evaporation_kg_s"] > 0
    assert sc.get("specific_energy_kJ_kg_water") is None and sc.get("thermal_efficiency") is None
    sets = [a for k, v in ov.items() for a in ("--set", f"{k}={v}")]
    out = tmp_path / "r.html"
    res = CliRunner().invoke(app, ["report", TEMPLATE, *sets, "--out", str(out)])
    assert res.exit_code == 0, res.output
    text = out.read_text()
    assert "nan %" not in text and "efficiency nan" not in text and "kJ/kg</b>" not in text
    res = CliRunner().invoke(app, ["simulate", TEMPLATE, *sets])
    assert res.exit_code == 0 and " nan" not in res.output


def test_user_dryers_from_fuzzing_efficiency_residence_time_and_a_cold_gas():
    """Three findings on user dryers (tests/data/user_*.toml, made with `rotarydryer new`):
    * gas 4.6 K above a warm feed: the evaporation duty (289 kW) exceeds the heat put into the gas (155 kW), the feed's
      own heat paying for the rest; "thermal efficiency 1.86" is no efficiency: undefined (None), the duties stay;
    * gas not above the feed: the refusal says the model needs the gas as the heat source (it said the gas "cannot
      supply the latent heat", while 0.3 K warmer the case dries 0.11 kg/s);
    * half the solids leave as dust: the mean residence time is the dry holdup over every dry solids outflow (297 s),
      not over the product alone (599 s, above every size class's own); the product's own RTD mean is 530 s."""
    from pathlib import Path

    from rotarydryer import Simulation

    data = Path(__file__).resolve().parents[1] / "data"
    s = Simulation(str(data / "user_cool_gas.toml")).steady_state().summary()
    assert s["heat_duty_evaporation_W"] > 1.5 * s["heat_input_W"] > 0
    assert s["thermal_efficiency"] is None
    with pytest.raises(ValueError, match=r"gas too cold to dry: gas.inlet_temperature = 44.9 degC is not above the "
                                         r"solids inlet temperature 45.0405 degC: the model needs the gas to be the "
                                         r"heat source .* give gas.inlet_temperature above 45.0405 degC"):
        Simulation(str(data / "user_cool_gas.toml"), {"gas.inlet_temperature": 44.9}).steady_state()
    d = Simulation(str(data / "user_dusty.toml")).steady_state().summary()
    assert d["dust_rate_kg_s"] > 0.9 * d["outlet_flow_kg_s"]
    # the solids' residence time over both their outlets (Little's law on the dry solids): the dust leaves sooner
    # than the product, whose own RTD mean is longer
    r = Simulation(str(data / "user_dusty.toml")).steady_state()
    S = r.thermal.terms
    assert d["mean_residence_time_s"] == pytest.approx(float(S["S"].sum()) / (S["product_S"] + S["dust_S"]), rel=1e-12)
    assert d["mean_residence_time_s"] < d["rtd_mean_residence_time_s"]


def test_an_exhaust_below_its_dew_point_is_warned_about():
    """A user dryer whose exhaust leaves 2.1 K below its own dew point was reported as a normal steady state (only the
    margin, -2.07 K, said so; found by fuzzing): the gas in the drum is supersaturated, which the model does not
    represent. A warning names it and what to change; the shipped cases do not warn."""
    import warnings
    from pathlib import Path

    from rotarydryer import Simulation
    from rotarydryer.thermal.audit import SupersaturationWarning

    data = Path(__file__).resolve().parents[1] / "data"
    with pytest.warns(SupersaturationWarning, match=r"the exhaust leaves at 55.67 degC, 2.07 K below its own dew point "
                                                    r"57.75 degC: the gas in the drum is supersaturated.* raise "
                                                    r"gas.inlet_temperature or gas.flow"):
        s = Simulation(str(data / "user_supersaturated.toml")).steady_state().summary()
    assert s["gas_outlet_dew_point_margin_K"] == pytest.approx(-2.07, abs=0.01)
    with warnings.catch_warnings():
        warnings.simplefilter("error", SupersaturationWarning)
        Simulation("lee2008_invicta").steady_state()

"""Coupled transport + heat + mass model of the MMG dryer (rotarydryer.thermal.dryer)."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.cases import load_case
from rotarydryer.published import read_published_csv
from rotarydryer.simulation import build_thermal_dryer
from rotarydryer.thermal.dryer import DryerError, ThermalSettings

VALIDATION = {(int(r["test"]), r["variable"]): r for r in read_published_csv("ajayi_energy_validation_tables6_2to6_4.csv")}
PI = {int(r["test"]): r for r in read_published_csv("ajayi_pi_operating_conditions.csv")}


#: the thermal model was tuned on Test 4 with Ajayi's regression geometry (his thesis model)
THESIS = {"geometry.method": "ajayi2011_regressions"}


def _dryer(test=4, mode="physical", **over):
    c = load_case("ajayi2011_mmg", {"operating.test": test, "thermal.mode": mode, **THESIS, **over})
    return build_thermal_dryer(c)


@pytest.fixture(scope="module")
def test4():
    return _dryer(4).steady_state()


@pytest.fixture(scope="module")
def test4_ajayi():
    return _dryer(4, "ajayi2011").steady_state()


def _check_balances(ss):
    assert ss.water_balance_error < 1e-6
    assert ss.energy_balance_error < 1e-6
    assert ss.solids_balance_error < 1e-6


def test_balances_close_physical(test4):
    _check_balances(test4)
    # and the closure is not trivial: the terms are large
    assert test4.evaporation_rate > 1.0 and test4.shell_heat_loss_w > 1e5


def test_balances_close_ajayi_mode_but_not_physically(test4_ajayi):
    """Compatibility mode closes in Ajayi's own accounting; with physical enthalpies and the solved-shell
    loss network it misses ~6.8 MW (notes ajayi_energy.md §2.2: implied shell loss ~6.8 MW of ~19 MW in)."""
    _check_balances(test4_ajayi)
    assert test4_ajayi.physical_energy_balance_error > 0.25
    assert test4_ajayi.shell_heat_loss_w / 1e6 == pytest.approx(6.8, rel=0.15)
    assert test4_ajayi.physical_shell_loss_w < 0.1 * test4_ajayi.shell_heat_loss_w


def test_counter_current_closes_balances():
    ss = _dryer(4, **{"operating.gas_flow": "counter-current"}).steady_state()
    _check_balances(ss)
    # counter-current: the gas leaves at the feed end, where the solids are coldest
    assert ss.gas_outlet_temperature_degC > ss.solids_temperature_degC[0]


def test_tuned_on_test4(test4):
    """gas_flow and area_scale in the case were tuned on Test 4 (Table 6.1: 12.4 %, 131 degC)."""
    assert test4.product_moisture == pytest.approx(float(PI[4]["product_moisture_pct"]) / 100, abs=1e-3)
    assert test4.gas_outlet_temperature_degC == pytest.approx(float(PI[4]["gas_outlet_T_C"]), abs=1.0)


@pytest.mark.parametrize("test", [3, 5])
def test_validation_tests_3_5(test):
    """Tests 3 and 5 with Test-4 parameters: within Ajayi's own accuracy (0.007 moisture, 20 K gas outlet;
    Tables 6.2, 6.4)."""
    ss = _dryer(test).steady_state()
    _check_balances(ss)
    x_exp = float(VALIDATION[(test, "product_moisture")]["experimental"])
    tg_exp = float(VALIDATION[(test, "gas_outlet_temperature")]["experimental"])
    assert abs(ss.product_moisture - x_exp) <= 0.007
    assert abs(ss.gas_outlet_temperature_degC - tg_exp) <= 20.0


@pytest.mark.xfail(strict=True, reason="Test 6: gas outlet predicted ~125 degC vs 150 measured (Ajayi: 130). Its "
                                       "measured balance needs ~22 % more gas than Test 4 (unpublished); at Test 4's "
                                       "gas flow energy conservation caps the outlet at ~130 degC "
                                       "(tests/thermal/test_consistency.py)")
def test_validation_test_6():
    ss = _dryer(6).steady_state()
    x_exp = float(VALIDATION[(6, "product_moisture")]["experimental"])
    tg_exp = float(VALIDATION[(6, "gas_outlet_temperature")]["experimental"])
    assert abs(ss.product_moisture - x_exp) <= 0.007 and abs(ss.gas_outlet_temperature_degC - tg_exp) <= 20.0


@pytest.mark.parametrize("test", [3, 5, 6])
def test_ajayi_mode_reproduces_thesis_predictions(test):
    """Compatibility mode vs the thesis's own predictions (Tables 6.2-6.4 'predicted')."""
    ss = _dryer(test, "ajayi2011").steady_state()
    pred = {v: float(VALIDATION[(test, v)]["predicted"]) for v in
            ("product_moisture", "product_temperature", "gas_outlet_temperature")}
    assert abs(ss.product_moisture - pred["product_moisture"]) <= 0.009
    assert abs(ss.product_temperature_degC - pred["product_temperature"]) <= 2.0
    assert abs(ss.gas_outlet_temperature_degC - pred["gas_outlet_temperature"]) <= 12.0


def test_moisture_coupling_changes_transport():
    """Repose angle and bulk density follow the computed moisture (coupled) or Eq. 3.1 (uncoupled):
    with hotter gas the profile departs from Eq. 3.1 and so do the flighted holdups."""
    d = _dryer(4, **{"thermal.gas_inlet_temperature": 580.0})
    a = d.steady_state()
    d.settings.moisture_coupling = False
    b = d.steady_state(z0=a.state)
    _check_balances(b)
    act = d.kind == 2
    assert np.max(np.abs(a.holdup - b.holdup)[act] / b.holdup[act]) > 0.005
    assert a.product_moisture != b.product_moisture


@given(st.floats(420.0, 580.0))
@settings(max_examples=3, deadline=None)
def test_hotter_gas_dries_more(t_in):
    from rotarydryer.thermal.studies import perturbed
    d = _dryer(4)
    base = d.steady_state()
    hot = perturbed(d, gas_inlet_temperature=t_in).steady_state(z0=base.state)
    _check_balances(hot)
    if t_in > 500.5:
        assert hot.product_moisture < base.product_moisture
        assert hot.gas_outlet_temperature_degC > base.gas_outlet_temperature_degC
    elif t_in < 499.5:
        assert hot.product_moisture > base.product_moisture


def test_dynamics_stay_at_steady_state(test4):
    res = test4.dryer.simulate(test4.state, 600.0, t_eval=[0.0, 600.0])
    assert res.product_moisture[-1] == pytest.approx(test4.product_moisture, abs=1e-6)
    assert res.gas_outlet_temperature_degC[-1] == pytest.approx(test4.gas_outlet_temperature_degC, abs=0.01)


def test_dynamics_reach_new_steady_state(test4):
    from rotarydryer.thermal.studies import perturbed
    d2 = perturbed(test4.dryer, gas_inlet_temperature=550.0)
    new = d2.steady_state(z0=test4.state)
    res = d2.simulate(test4.state, 7200.0, t_eval=np.linspace(0, 7200, 25))
    assert res.product_moisture[-1] == pytest.approx(new.product_moisture, abs=2e-4)
    assert res.gas_outlet_temperature_degC[-1] == pytest.approx(new.gas_outlet_temperature_degC, abs=0.2)
    assert res.seconds < 20.0


def test_feed_too_wet():
    c = load_case("ajayi2011_mmg")
    with pytest.raises(DryerError, match="feed too wet") as e:
        build_thermal_dryer(c, feed_moisture=0.25)
    assert e.value.reason == "feed_too_wet"


def test_gas_too_cold():
    c = load_case("ajayi2011_mmg", {"thermal.gas_inlet_temperature": 25.0})
    with pytest.raises(DryerError, match="gas too cold") as e:
        build_thermal_dryer(c)
    assert e.value.reason == "gas_too_cold"


def test_gas_whose_wet_bulb_is_below_freezing_is_refused():
    """Dry air at 3 degC has a wet bulb near -3 degC: a wet feed would freeze (no ice in the model)."""
    c = load_case("ajayi2011_mmg", {"gas.inlet_temperature": 3.0, "gas.inlet_humidity": 0.0,
                                    "operating.feed_temperature": 1.0})
    with pytest.raises(DryerError, match=r"wet-bulb temperature of -\d") as e:
        build_thermal_dryer(c)
    assert e.value.reason == "gas_too_cold"


def test_no_steady_state_keeps_last_state():
    d = _dryer(4)
    with pytest.raises(DryerError, match="no steady state") as e:
        d.steady_state(max_iter=1, march=False)
    assert e.value.reason == "no_steady_state" and e.value.state is not None
    assert np.all(np.isfinite(e.value.state.state))


def test_burner_cannot_reach_set_temperature(test4):
    import copy
    ss = copy.copy(test4)
    ss.dryer = copy.copy(test4.dryer)
    ss.dryer.settings = ThermalSettings(gas_flow=16.25, gas_inlet_temperature=1500.0,
                                        burner=test4.dryer.settings.burner)
    with pytest.raises(DryerError, match="burner cannot reach") as e:
        ss.fuel_rate()
    assert e.value.reason == "burner"


def test_bad_setting_names_argument():
    with pytest.raises(ValueError, match="thermal.mode"):
        ThermalSettings(gas_flow=10.0, gas_inlet_temperature=200.0, mode="magic").validate()


def test_cli_simulate_adds_thermal_outputs(tmp_path):
    import json

    from typer.testing import CliRunner

    from rotarydryer.cli import app
    r = CliRunner().invoke(app, ["simulate", "ajayi2011_mmg", "--set", "operating.test=5", "--json",
                                 "--out", str(tmp_path)])
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    for k in ("product_moisture_kg_kg", "product_temperature_degC", "gas_outlet_temperature_degC", "fuel_rate_kg_s",
              "shell_heat_loss_W", "energy_balance_error"):
        assert k in d
    assert abs(d["product_moisture_kg_kg"] - 0.12) < 0.007 and d["energy_balance_error"] < 1e-6
    assert (tmp_path / "thermal_profiles.png").stat().st_size > 10000


def test_cli_simulate_reports_bad_thermal_input():
    from typer.testing import CliRunner

    from rotarydryer.cli import app
    r = CliRunner().invoke(app, ["simulate", "ajayi2011_mmg", "--set", "thermal.gas_inlet_temperature=20"])
    assert r.exit_code == 2
    assert "gas too cold" in r.output


def test_physical_gas_flow_implies_typical_fuel_rate(test4):
    """Independent check of the Test-4 tuning: the burner (App. A) needs ~750 kg/h of fuel oil for the tuned
    gas flow - Ajayi's 'typical' consumption (l.2426) - whereas the thesis gas flow needs ~1400 kg/h."""
    assert test4.fuel_rate() * 3600 == pytest.approx(750.0, rel=0.10)


def test_leak_air_closes_balances_and_cools_gas(test4):
    ss = _dryer(4, **{"thermal.leak_air_flow": 5.0}).steady_state(z0=test4.state)
    _check_balances(ss)
    assert ss.gas_outlet_temperature_degC < test4.gas_outlet_temperature_degC
    assert ss.fuel_rate() == pytest.approx(test4.fuel_rate(), rel=1e-9)   # the burner heats only its own gas


def test_moisture_profile_against_table_3_3(test4):
    """Spatial moisture samples (Ajayi Table 3.3, not used for tuning): RMS deviation of the Test-4 profile
    (passive/bed tanks, interpolated) below 0.006 kg/kg, and the profile decreases monotonically."""
    rows = read_published_csv("ajayi_moisture_profile_table3_3.csv")
    d = test4.dryer
    m = d.kind != 2
    z = np.array([float(r["position_m"]) for r in rows])
    x = np.array([float(r["moisture_kg_per_kg_wet"]) for r in rows])
    xp = np.interp(z, d.position[m], test4.moisture_wet[m])
    assert np.sqrt(np.mean((xp - x) ** 2)) < 0.006
    assert np.all(np.diff(test4.moisture_wet[d.kind == 1]) < 0)


def test_overrides_checked_and_caller_settings_untouched():
    from rotarydryer.cases.build import settings_from_case

    case = load_case("ajayi2011_mmg", {"operating.test": 4})
    st = settings_from_case(case)
    before = st.gas_flow
    d = build_thermal_dryer(case, settings=st, gas_flow=2 * before)
    assert d.settings.gas_flow == 2 * before and st.gas_flow == before
    with pytest.raises(ValueError, match="gas_flw"):
        build_thermal_dryer(case, gas_flw=10.0)


def test_compatibility_mode_physical_shell_loss_sees_insulation():
    """The physical re-evaluation of the compatibility mode uses the same shell network as the
    physical mode, including insulation (it ignored insulation and scale before)."""
    bare = _dryer(4, "ajayi2011").steady_state()
    lagged = build_thermal_dryer(load_case("ajayi2011_mmg", {"operating.test": 4, "thermal.mode": "ajayi2011"}),
                                 insulation_thickness=0.1).steady_state()
    assert lagged.physical_shell_loss_w < 0.3 * bare.physical_shell_loss_w


def test_profiles_carry_unit_suffixes_and_read_the_old_names(test4):
    p = test4.profiles()
    assert {"solids_temperature_degC", "gas_temperature_degC", "shell_loss_W"} <= set(p)
    with pytest.warns(DeprecationWarning, match="'gas_temperature_c' is deprecated: use 'gas_temperature_degC'"):
        old = p["gas_temperature_c"]
    assert old is p["gas_temperature_degC"]
    with pytest.raises(KeyError):
        p["no_such_profile"]

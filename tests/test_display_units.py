"""Display units chosen once (issue 31 item 5): the text surfaces show each quantity in one unit,
set by ``rotarydryer --units``, ``ROTARYDRYER_UNITS`` or ``[display]`` in the config file; JSON
and CSV keep the SI values under their suffixed names."""

from __future__ import annotations

import json
import math

import pytest
from hypothesis import given
from hypothesis import strategies as st
from typer.testing import CliRunner

from rotarydryer import _display as D
from rotarydryer.cli import app


@pytest.fixture(autouse=True)
def _clean(monkeypatch, tmp_path):
    """No user choice leaks in or out: an empty config path, no environment, no process choice."""
    monkeypatch.delenv("ROTARYDRYER_UNITS", raising=False)
    monkeypatch.setenv("ROTARYDRYER_CONFIG", str(tmp_path / "none.toml"))
    D.set_display_units(None)
    yield
    D.set_display_units(None)


def test_defaults_are_the_project_convention():
    u = D.display_units()
    assert u == D.DEFAULT_UNITS
    assert (u["moisture"], u["fuel_flow"], u["power"], u["time"], u["temperature"]) == ("%", "kg/h", "kW", "min", "degC")
    assert D.show(0.1312, "moisture") == "13.12 %"
    assert D.show(642.7 / 3600, "fuel_flow") == "642.7 kg/h"
    assert D.show(398_700.0, "power") == "398.7 kW"
    assert D.show(903.6, "time") == "15.06 min"
    assert D.show(61.04, "temperature") == "61.0 degC"


def test_every_unit_of_every_quantity_converts_and_back():
    for q, units in D.UNITS.items():
        assert D.DEFAULT_UNITS[q] in units
        for unit, (scale, offset) in units.items():
            assert D.to_display(2.0, q, unit) == pytest.approx(2.0 * scale + offset)
    assert D.to_display(100.0, "temperature", "degF") == pytest.approx(212.0)
    assert D.to_display(0.0, "temperature", "K") == pytest.approx(273.15)
    assert D.to_display(1.0, "mass_flow", "t/h") == pytest.approx(3.6)


@given(st.floats(min_value=-1e6, max_value=1e6, allow_nan=False))
def test_show_output_is_the_name_s_quantity(x):
    """An output name's suffix picks its quantity; the number shown is the SI value converted."""
    D.set_display_units({"mass_flow": "t/h", "fuel_flow": "kg/h", "moisture": "kg/kg"})
    assert D.show_output("feed_rate_kg_s", x).endswith(" t/h")
    assert D.show_output("fuel_rate_kg_s", x).endswith(" kg/h")
    assert D.show_output("product_moisture_kg_kg", x).endswith(" kg/kg")
    text = D.show_output("shell_heat_loss_W", x)
    number = float(text.split(" ")[0].replace(",", ""))
    assert math.isclose(number, x * 1e-3, rel_tol=5e-4, abs_tol=5e-4 * max(1.0, abs(x) * 1e-3))


def test_quantity_of_names():
    assert D.quantity_of("gas_outlet_humidity_kg_kg") == ("humidity", 1.0)
    assert D.quantity_of("product_moisture_kg_kg") == ("moisture", 1.0)
    assert D.quantity_of("gas_outlet_dew_point_margin_K") == ("temperature_difference", 1.0)
    assert D.quantity_of("specific_energy_kJ_kg_water") == ("specific_energy", 1e3)
    assert D.quantity_of("fill_fraction") is None


def test_environment_file_and_option_in_that_order(monkeypatch, tmp_path):
    cfg = tmp_path / "config.toml"
    cfg.write_text('[display]\nmoisture = "kg/kg"\npower = "MW"\n', encoding="utf-8")
    monkeypatch.setenv("ROTARYDRYER_CONFIG", str(cfg))
    assert D.unit_of("moisture") == "kg/kg" and D.unit_of("power") == "MW"
    monkeypatch.setenv("ROTARYDRYER_UNITS", "power=W")
    assert D.unit_of("power") == "W" and D.unit_of("moisture") == "kg/kg"
    D.set_display_units("power=kW")
    assert D.unit_of("power") == "kW"


@pytest.mark.parametrize("spec, match", [
    ("moisture=ppm", r"--units: moisture = 'ppm' is not a display unit of moisture; allowed: %, kg/kg"),
    ("speed=rpm", r"--units: unknown quantity 'speed'; allowed: moisture, humidity"),
    ("moisture", r"--units: 'moisture' is not QUANTITY=UNIT"),
])
def test_bad_choice_names_the_quantity_and_the_allowed_units(spec, match):
    with pytest.raises(ValueError, match=match):
        D.set_display_units(spec)


def test_bad_config_file_names_the_file(monkeypatch, tmp_path):
    cfg = tmp_path / "config.toml"
    cfg.write_text('[display]\nmass_flow = "lb/h"\n', encoding="utf-8")
    monkeypatch.setenv("ROTARYDRYER_CONFIG", str(cfg))
    with pytest.raises(ValueError, match=r"config.toml \[display\]: mass_flow = 'lb/h' is not a display unit"):
        D.display_units()
    cfg.write_text("[display\n", encoding="utf-8")
    with pytest.raises(ValueError, match="not valid TOML"):
        D.display_units()


def test_cli_units_option_changes_the_text_not_the_json():
    r = CliRunner().invoke(app, ["--units", "moisture=kg/kg,fuel_flow=t/h,power=MW,mass=t", "simulate",
                                 "ajayi2011_mmg", "--set", "operating.test=4"])
    assert r.exit_code == 0, r.output
    line = next(x for x in r.output.splitlines() if "product moisture" in x)
    assert "kg/kg" in line and "%" not in line
    assert next(x for x in r.output.splitlines() if "fuel rate" in x).endswith(" t/h")
    assert next(x for x in r.output.splitlines() if "shell heat loss" in x).endswith(" MW")
    assert next(x for x in r.output.splitlines() if x.strip().startswith("total holdup")).endswith(" t")
    plain = CliRunner().invoke(app, ["simulate", "ajayi2011_mmg", "--set", "operating.test=4"])
    assert next(x for x in plain.output.splitlines() if "product moisture" in x).endswith("% wet basis")
    j = CliRunner().invoke(app, ["--units", "moisture=kg/kg", "simulate", "ajayi2011_mmg", "--json"])
    assert j.exit_code == 0
    data = json.loads(j.stdout)
    assert 0.05 < data["product_moisture_kg_kg"] < 0.3 and "fuel_rate_kg_s" in data     # SI, suffixed names


def test_rtd_and_balance_text_follow_the_choice():
    """`rtd` printed its times in min and `balance` its flows in kg/s and temperatures in degC whatever --units said
    (the JSON of both stays SI)."""
    r = CliRunner().invoke(app, ["--units", "time=s", "rtd", "lee2008_invicta"])
    assert r.exit_code == 0, r.output
    mean = next(x for x in r.output.splitlines() if "mean residence time" in x)
    assert " s (the RTD's mean" in mean and "min" not in mean
    j = json.loads(CliRunner().invoke(app, ["--units", "time=s", "rtd", "lee2008_invicta", "--json"]).stdout)
    assert f"{j['mean_residence_time_s']:.4g} s" in mean.replace(",", "")
    r = CliRunner().invoke(app, ["--units", "mass_flow=t/h,temperature=degF,humidity=g/kg", "balance",
                                 "--ajayi-test", "4"])
    assert r.exit_code == 0, r.output
    j = json.loads(CliRunner().invoke(app, ["balance", "--ajayi-test", "4", "--json"]).stdout)
    flow = next(x for x in r.output.splitlines() if x.startswith("gas flow"))
    assert flow.split()[-3:] == [f"{j['gas_flow_kg_s'] * 3.6:.4g}", "t/h", "(wet)"]
    assert next(x for x in r.output.splitlines() if x.startswith("gas outlet")).endswith(
        f"{j['gas_outlet_temperature_degC'] * 1.8 + 32:.1f} degF")
    hum = next(x for x in r.output.splitlines() if x.startswith("exhaust humidity"))
    assert "g/kg" in hum and "degF" in hum and "degC" not in r.output and "kg/s" not in r.output


def test_mrt_flight_validate_and_sensitivity_text_follow_the_choice():
    """Four more text outputs printed SI whatever --units said (found by a check of every surface)."""
    run = CliRunner().invoke
    r = run(app, ["--units", "time=h", "mrt", "--length", "12", "--diameter", "2", "--slope", "0.0524", "--rpm", "4",
                  "--particle-size", "444e-6", "--gas-mass-flux", "1.91", "--solids-mass-flux", "1.12"])
    assert r.exit_code == 0, r.output
    rows = [x for x in r.output.splitlines() if x and not x.startswith(" ") and "error:" not in x]
    assert rows and all(x.endswith(" h") and " min" not in x for x in rows)
    r = run(app, ["--units", "length=mm,mass=t", "flight", "--radius", "1.2", "--n-flights", "18", "--s1", "0.15",
                  "--s2", "0.1", "--alpha1", "90", "--alpha2", "120", "--repose-angle", "33"])
    assert r.exit_code == 0, r.output
    assert "150 mm at 90 deg" in r.output and "R = 1,200 mm" in r.output
    assert all(x.endswith(" t") for x in r.output.splitlines() if "design load" in x)
    r = run(app, ["--units", "mass=t,time=h", "validate", "lee2008_invicta"])
    line = next(x for x in r.output.splitlines() if "/holdup" in x or "tracer_mean" in x)
    assert (" t " in line or " h " in line) and " kg " not in line and " min " not in line
    r = run(app, ["--units", "time=h", "sensitivity", "song2003_ottawa", "--set", "thermal.enabled=false",
                  "--param", "operating.rpm=3,5", "--samples", "4", "-q"])
    assert r.exit_code == 0, r.output
    mrt = next(x for x in r.output.splitlines() if x.startswith("mean_residence_time ") and x.endswith(" h"))
    assert 0.01 < float(mrt.split()[2]) < 1.0      # the mean, in hours
    # the name without its SI suffix where the value is in another unit ("mean_residence_time_s ... h" read as two
    # units for one number; found by review)
    assert not [x for x in r.output.splitlines() if x.startswith("mean_residence_time_s") and x.endswith(" h")]


def test_target_shows_its_input_in_the_chosen_unit():
    """`target` printed the input and its bounds in the key's own unit (degC, kg/s) whatever --units chose."""
    args = ["target", "ajayi2011_mmg", "--find", "gas.inlet_temperature=450,550", "--such-that",
            "product_moisture_kg_kg<=0.14"]
    r = CliRunner().invoke(app, ["--units", "temperature=degF", *args])
    assert r.exit_code == 0, r.output
    assert "bounds: [842, 1022] degF" in r.output and "gas.inlet_temperature = 842 degF" in r.output
    plain = CliRunner().invoke(app, args)
    assert "bounds: [450, 550] degC" in plain.output


def test_cli_refuses_a_bad_choice_with_exit_2(monkeypatch):
    r = CliRunner().invoke(app, ["--units", "power=hp", "simulate", "lee2008_invicta", "--json"])
    assert r.exit_code == 2
    assert r.output.strip().splitlines()[-1].startswith("error: --units: power = 'hp' is not a display unit")
    monkeypatch.setenv("ROTARYDRYER_UNITS", "temperature=Rankine")
    r = CliRunner().invoke(app, ["simulate", "lee2008_invicta", "--json"])
    assert r.exit_code == 2 and "error: ROTARYDRYER_UNITS: temperature = 'Rankine'" in r.output
    assert "Traceback" not in r.output


def test_report_follows_the_choice(monkeypatch):
    from rotarydryer.report.html import render_report
    from rotarydryer.simulation import run_case

    res = run_case("ajayi2011_mmg", {"operating.test": 4})
    monkeypatch.setenv("ROTARYDRYER_UNITS", "moisture=kg/kg,power=MW,time=h")
    text = render_report(res)
    s = res.scalars
    assert f"Product moisture <b>{D.fmt(s['product_moisture_kg_kg'])} kg/kg</b>" in text
    assert '<th class="">MW</th>' in text and "shell loss " in text
    assert f"{D.fmt(s['mean_residence_time_s'] / 3600)} h" in text
    # the operating conditions too (the model's fuel rate was in kg/h beside the summary's chosen unit)
    monkeypatch.setenv("ROTARYDRYER_UNITS", "fuel_flow=kg/s,temperature=degF,mass_flow=t/h")
    text = render_report(res)
    sec = text[text.index('id="operating"'):]
    sec = sec[:sec.index("</table>")]
    assert f'fuel rate (model)</td><td class="l">{D.fmt(s["fuel_rate_kg_s"])}</td><td class="l">kg/s</td>' in sec
    assert "degC" not in sec and "degF" in sec and "t/h" in sec and "kg/h" not in sec


def test_a_moisture_change_below_the_percent_resolution_is_none():
    """show_delta: moisture changes in percentage points with fmt_moisture's resolution (0.001 %): solver
    noise of a held moisture is no change, not "-1.25e-07 pp"."""
    assert D.show_delta(-1.25e-9, "moisture") == "0 pp"
    assert D.show_delta(-2e-5, "moisture") == "-0.002 pp"
    assert D.show_delta(0.0123, "moisture") == "1.23 pp"
    assert D.show_delta(1e-9, "temperature") != "0 K"          # the rule is the moisture's only


def test_undefined_values_and_temperature_differences():
    """None (an undefined output) prints n/a in every table; a temperature difference is shown in degF where the
    differences (or the temperatures) are."""
    assert D.fmt(None) == "n/a" and D.show_output("specific_energy_kJ_kg_water", None) == "n/a"
    assert D.show_delta(10.0, "temperature") == "10 K"
    D.set_display_units("temperature_difference=degF")
    assert D.show_delta(10.0, "temperature") == "18 degF"
    D.set_display_units("temperature=degF")
    assert D.show_delta(10.0, "temperature") == "18 degF"

import json

from typer.testing import CliRunner

from rotarydryer.cli import app

runner = CliRunner()


def test_balance_of_ajayi_test6_implies_gas_flow_and_flags_product_below_dew_point():
    res = runner.invoke(app, ["balance", "--ajayi-test", "6", "--shell-loss", "0.38e6", "--json"])
    assert res.exit_code == 0, res.output
    out = json.loads(res.output)
    assert 17.0 < out["gas_flow_kg_s"] < 20.0           # Test 4's tuned flow is 16.25 kg/s
    assert out["gas_outlet_temperature_degC"] == 150.0
    assert out["product_below_dew_point"] and out["exhaust_dew_point_degC"] > 55.0


def test_balance_with_given_gas_flow_solves_the_outlet_and_round_trips():
    first = json.loads(runner.invoke(app, ["balance", "--ajayi-test", "4", "--json"]).output)
    res = runner.invoke(app, ["balance", "--ajayi-test", "4", "--gas-flow", str(first["gas_flow_kg_s"]), "--json"])
    assert res.exit_code == 0, res.output
    assert abs(json.loads(res.output)["gas_outlet_temperature_degC"] - 131.0) < 1e-6
    table = runner.invoke(app, ["balance", "--ajayi-test", "4", "--product-temperature", "65"])
    assert table.exit_code == 0 and "gas flow" in table.output and "warning" not in table.output


def test_balance_bad_input_exits_2_naming_the_problem():
    res = runner.invoke(app, ["balance", "--gas-in", "500"])
    assert res.exit_code == 2 and "--gas-out" in res.output
    res = runner.invoke(app, ["balance", "--ajayi-test", "9"])
    assert res.exit_code == 2 and "test = 9" in res.output
    res = runner.invoke(app, ["balance", "--ajayi-test", "4", "--moisture-out", "0.2"])
    assert res.exit_code == 2 and "--moisture-out = 0.2" in res.output

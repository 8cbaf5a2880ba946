"""A thermal steady state that cannot be reached: clear message, exit 1, last state saved."""

import json

from typer.testing import CliRunner

from rotarydryer.cli import app
from rotarydryer.thermal import dryer as dryer_mod

runner = CliRunner()


def test_unreached_steady_state_saves_last_iterate(tmp_path, monkeypatch):
    original = dryer_mod.ThermalDryer.steady_state

    def capped(self, z0=None, **kw):           # two iterations: the solver cannot get there
        return original(self, z0=z0, max_iter=2, march=False)

    monkeypatch.setattr(dryer_mod.ThermalDryer, "steady_state", capped)
    res = runner.invoke(app, ["simulate", "ajayi2011_mmg", "--out", str(tmp_path)])
    assert res.exit_code == 1, res.output
    assert "no steady state reached" in res.output and "thermal_last_state.json" in res.output
    saved = json.loads((tmp_path / "thermal_last_state.json").read_text())
    assert saved["reason"] == "no_steady_state"
    assert set(saved["summary"]) >= {"product_moisture_kg_kg", "gas_outlet_temperature_degC", "energy_balance_error"}
    assert len(saved["state_vector"]) > 100 and len(saved["profiles"]["gas_temperature_degC"]) > 10


def test_bad_thermal_input_exits_2_without_a_state_file(tmp_path):
    res = runner.invoke(app, ["simulate", "ajayi2011_mmg", "--set", "thermal.gas_inlet_temperature=25",
                              "--out", str(tmp_path)])
    assert res.exit_code == 2, res.output
    assert "gas" in res.output and "cold" in res.output
    assert not (tmp_path / "thermal_last_state.json").exists()

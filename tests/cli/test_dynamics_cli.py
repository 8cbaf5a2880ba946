"""``rotarydryer dynamics`` (issue 31): a burner trip from a schedule file, its files and JSON."""

from __future__ import annotations

import csv
import json

from typer.testing import CliRunner

from rotarydryer.cli import app

TRIP = "[[trip]]\ninput = \"gas_inlet_temperature\"\nat_s = 600\nduration_s = 600\nvalue = 100\n"


def test_burner_trip_from_toml_writes_csv_json_png(tmp_path):
    sched = tmp_path / "trip.toml"
    sched.write_text(TRIP, encoding="utf-8")
    res = CliRunner().invoke(app, ["dynamics", "ajayi2011_mmg", "--set", "operating.test=4", "--schedule", str(sched),
                                   "--t-end", "3600", "--above", "product_moisture=0.14", "--out",
                                   str(tmp_path / "o"), "--json", "--quiet"])
    assert res.exit_code == 0, res.output
    summary = json.loads(res.stdout)
    assert summary["scheduled_inputs"] == ["gas_inlet_temperature"] and summary["integrations"] == 1
    assert summary["input_changes"] == 2        # the trip and the restart, taken over by one integration
    pm = summary["outlets"]["product_moisture_kg_kg"]
    assert pm["max"] > pm["start"] + 0.02 and 600 < pm["max_time_s"] < 3600
    assert 0 < summary["time_above"]["seconds"] < 3600
    rows = list(csv.DictReader((tmp_path / "o" / "dynamics.csv").open()))
    assert len(rows) == 61 and float(rows[10]["gas_inlet_temperature_degC"]) == 100.0
    assert float(rows[20]["gas_inlet_temperature_degC"]) == 500.0
    assert {"time_s", "product_moisture_kg_kg", "gas_outlet_temperature_degC", "total_holdup_kg"} <= set(rows[0])
    assert (tmp_path / "o" / "dynamics.png").stat().st_size > 1000


def test_without_schedule_text_output(tmp_path):
    res = CliRunner().invoke(app, ["dynamics", "ajayi2011_mmg", "--t-end", "600", "--dt", "120"])
    assert res.exit_code == 0, res.output
    assert "the case's own inputs" in res.stdout and "product_moisture_kg_kg" in res.stdout


def test_the_names_the_command_writes_read_back(tmp_path):
    """`--above` refused the outlet names dynamics prints (gas_outlet_temperature_degC) and a schedule CSV the input
    columns dynamics.csv writes (gas_inlet_temperature_degC); the threshold is shown in the display unit."""
    sched = tmp_path / "s.csv"
    sched.write_text("time_s,gas_inlet_temperature_degC\n0,500\n300,480\n", encoding="utf-8")
    res = CliRunner().invoke(app, ["--units", "temperature=degF", "dynamics", "ajayi2011_mmg", "--set",
                                   "operating.test=4", "--schedule", str(sched), "--t-end", "600", "--dt", "120",
                                   "--above", "gas_outlet_temperature_degC=50", "--quiet"])
    assert res.exit_code == 0, res.output
    assert "gas_outlet_temperature_degC above 122.0 degF:" in res.output
    res = CliRunner().invoke(app, ["dynamics", "ajayi2011_mmg", "--schedule", str(sched), "--t-end", "600",
                                   "--above", "total_holdup_kg=1", "--json", "--quiet"])
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    assert out["scheduled_inputs"] == ["gas_inlet_temperature"] and out["time_above"]["outlet"] == "holdup"

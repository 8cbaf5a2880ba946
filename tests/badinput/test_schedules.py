"""Bad schedules and dynamics options (issue 31): exit 2, one ``error:`` line naming the input,
the value or time and the allowed range; nothing written."""

from __future__ import annotations

import pytest

from .conftest import assert_bad, run_cli

CASE = ["ajayi2011_mmg", "--set", "operating.test=4"]

SCHEDULES = [
    ("unknown-input", "s.csv", "time_s,oven_temperature\n0,1\n", ["oven_temperature", "gas_inlet_temperature"]),
    ("outside-grid", "s.csv", "time_s,feed_rate\n0,40\n9000,30\n", ["9000", "time grid", "[0, 3600]"]),
    ("value-out-of-range", "s.csv", "time_s,gas_inlet_temperature\n0,500\n60,900\n",
     ["gas_inlet_temperature=900", "(0, 600] degC"]),
    ("material-range", "s.toml", '[[step]]\ninput = "feed_moisture"\nat_s = 60\nvalue = 0.5\n',
     ["feed_moisture=0.5", "60 s", "0.19"]),
    ("conflicting-inputs", "s.csv", "time_s,gas_inlet_temperature,burner_fuel_rate\n0,500,0.2\n",
     ["not both", "burner_fuel_rate"]),
    ("not-a-number", "s.csv", "time_s,feed_rate\n0,fast\n", ["feed_rate", "'fast'"]),
    ("bad-toml-table", "s.toml", "[[stop]]\nat_s = 1\n", ["stop", "step, ramp, trip, point"]),
    ("wrong-suffix", "s.txt", "x", [".csv or .toml"]),
    # accepted as "no input changed" before (found by fuzzing)
    ("no-input-column", "s.csv", "time_s\n0\n300\n", ["names no input", "feed_rate"]),
    ("no-values", "s.csv", "time_s,feed_rate\n0,\n60,\n", ["no values under feed_rate"]),
    # found by fuzzing: true ran as a feed of 1 kg/s; the last of two feed_rate columns won
    ("boolean-value", "s.toml", '[[step]]\ninput = "feed_rate"\nat_s = 60\nvalue = true\n', ["value", "True",
                                                                                            "not a number"]),
    ("duplicated-column", "s.csv", "time_s,feed_rate,feed_rate\n0,40,41\n", ["'feed_rate' appears twice"]),
]


@pytest.mark.parametrize("name, file, text, fragments", SCHEDULES, ids=[s[0] for s in SCHEDULES])
def test_bad_schedule(tmp_path, name, file, text, fragments):
    p = tmp_path / file
    p.write_text(text, encoding="utf-8")
    res = run_cli(["dynamics", *CASE, "--schedule", str(p), "--t-end", "3600", "--out", str(tmp_path / "o")],
                  cwd=tmp_path)
    assert_bad(res, *fragments)
    assert not (tmp_path / "o").exists()


OPTIONS = [
    ("t-end-negative", ["--t-end", "-5"], ["--t-end", "-5"]),
    ("dt-zero", ["--dt", "0"], ["--dt", "0"]),
    ("too-many-points", ["--t-end", "86400", "--dt", "0.1"], ["--dt", "100000"]),
    ("missing-schedule", ["--schedule", "nope.csv"], ["nope.csv", "no such file"]),
    ("above-unknown", ["--above", "colour=3"], ["--above", "product_moisture"]),
    ("above-not-number", ["--above", "product_moisture=wet"], ["--above", "'wet'"]),
]


@pytest.mark.parametrize("name, extra, fragments", OPTIONS, ids=[o[0] for o in OPTIONS])
def test_bad_dynamics_option(tmp_path, name, extra, fragments):
    assert_bad(run_cli(["dynamics", *CASE, *extra], cwd=tmp_path), *fragments)


def test_fuel_schedule_without_a_burner(tmp_path):
    p = tmp_path / "s.csv"
    p.write_text("time_s,burner_fuel_rate\n60,0.2\n", encoding="utf-8")
    assert_bad(run_cli(["dynamics", "song2003_ottawa", "--schedule", str(p), "--t-end", "600"], cwd=tmp_path),
               "burner_fuel_rate", "[burner]")


def test_control_refuses_a_schedule_of_its_manipulated_input(tmp_path):
    p = tmp_path / "trip.toml"
    p.write_text("[[trip]]\nat_s = 600\nduration_s = 600\nvalue = 100\n", encoding="utf-8")
    assert_bad(run_cli(["control", *CASE, "--duration", "1800", "--schedule", str(p)], cwd=tmp_path),
               "gas_inlet_temperature", "manipulated input")


def test_a_schedule_that_overfills_the_drum_warns(tmp_path):
    """A feed step to 500 kg/s put 127 t of sand (about 77 m^3) into the template's 37.7 m^3 drum without a word,
    where a steady state at that feed is refused for its fill (found by fuzzing): the run warns, naming the fill."""
    res = run_cli(["new", "mydryer", "--out", str(tmp_path / "d.toml")])
    assert res.exit_code == 0, res.output
    (tmp_path / "s.toml").write_text('[[step]]\ninput = "feed_rate"\nat_s = 10\nvalue = 500\n')
    res = run_cli(["dynamics", str(tmp_path / "d.toml"), "--schedule", str(tmp_path / "s.toml"), "--t-end", "600",
                   "--quiet"])
    assert res.exit_code == 0, res.output
    assert "warning: the solids fill about" in res.output and "beyond the 30% at which a steady state is refused" in \
        res.output

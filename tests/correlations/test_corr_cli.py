"""The ``rotarydryer mrt`` command (module rotarydryer.cli.correlations)."""

import json

from typer.testing import CliRunner

import rotarydryer.cli.correlations  # noqa: F401  (registers the command)
from rotarydryer.cli import app
from rotarydryer.correlations import perry_green_1984

ARGS = ["mrt", "--length", "3.05", "--diameter", "0.305", "--slope", "0.083", "--rpm", "5",
        "--particle-size", "444e-6", "--gas-mass-flux", "0.5", "--solids-mass-flux", "0.7"]


def test_mrt_table():
    result = CliRunner().invoke(app, ARGS)
    assert result.exit_code == 0, result.output
    assert "song_2003" in result.output and "perry_green_1984" in result.output


def test_mrt_json_matches_library():
    result = CliRunner().invoke(app, ARGS + ["--json", "--method", "perry_green_1984"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.output)
    assert data["perry_green_1984"]["tau_s"] == perry_green_1984(3.05, 0.305, 0.083, 5, 444e-6, 0.5, 0.7)


def test_mrt_warning_and_error():
    out = CliRunner().invoke(app, ARGS[:8] + ["12"] + ARGS[9:] + ["--method", "song_2003"])
    assert out.exit_code == 0 and "warning" in out.output and "rpm" in out.output
    bad = CliRunner().invoke(app, ["mrt", "--length", "-1", "--diameter", "0.3", "--slope", "0.08", "--rpm", "5"])
    assert bad.exit_code == 2 and "length" in bad.output


def test_mrt_cli_bad_option_exits_2():
    """A wrong --gas-flow or --method is bad input for every method (it used to exit 0 or 1)."""
    res = CliRunner().invoke(app, ARGS + ["--gas-flow", "sideways"])
    assert res.exit_code == 2 and "gas_flow = 'sideways'" in res.output
    res = CliRunner().invoke(app, ARGS + ["--method", "nope"])
    assert res.exit_code == 2 and "method = 'nope'" in res.output

"""`rotarydryer fit` on a built-in case and data set."""

import json

from typer.testing import CliRunner

from rotarydryer.cli import app

runner = CliRunner()


def test_fit_cli_json_and_plot(tmp_path):
    res = runner.invoke(app, ["fit", "ajayi2011_mmg", "ajayi2011_test4", "-p", "transport.solids_velocity",
                              "-p", "transport.dispersion", "--set", "operating.test=4", "--scale", "fit",
                              "--starts", "1", "--json", "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    data = json.loads(res.stdout.strip().splitlines()[-1])
    p = data["parameters"]["transport.solids_velocity"]
    assert p["ci_low"] <= p["value"] <= p["ci_high"]
    assert abs(p["value"] - 0.016) < 0.15 * 0.016  # Ajayi (2011) Table 5.2
    assert {"objective", "r_squared", "n_evaluations"} <= set(data)
    assert (tmp_path / "fit.png").stat().st_size > 10_000


def test_fit_cli_table_and_bad_key():
    res = runner.invoke(app, ["fit", "ajayi2011_mmg", "ajayi2011_test4", "-p", "transport.dispersion",
                              "--set", "operating.test=4", "--scale", "fit", "--starts", "1"])
    assert res.exit_code == 0, res.output
    assert "95% CI" in res.output and "correlation matrix" in res.output
    res = runner.invoke(app, ["fit", "ajayi2011_mmg", "ajayi2011_test4", "-p", "transport.bogus"])
    assert res.exit_code == 2 and "transport.bogus" in res.output

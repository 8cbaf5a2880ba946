"""CLI: rotarydryer rtd-moments / rtd-fit (module rotarydryer.cli.rtdfit)."""

import json

import pytest
from typer.testing import CliRunner

import rotarydryer.cli.rtdfit  # noqa: F401  (registers the commands if cli/__init__ does not yet)
from rotarydryer.cli import app
from rotarydryer.published import read_published_csv

runner = CliRunner()


def test_rtd_moments_json_invicta():
    row = next(r for r in read_published_csv("lee_rtd_moments.csv") if r["rtd"] == "Experiment")
    res = runner.invoke(app, ["rtd-moments", "lee2008_invicta", "--json"])
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout)
    assert d["mean_s"] / 60 == pytest.approx(float(row["mean_residence_time_min"]), abs=0.01)
    assert d["rtd_std_s"] / 60 == pytest.approx(float(row["standard_deviation_min"]), abs=0.01)
    assert d["tail_truncated"] is False


def test_rtd_moments_table_from_file(tmp_path):
    p = tmp_path / "c.csv"
    rows = "".join(f"{i},{max(0, 5 - abs(i - 5))}\n" for i in range(11))
    p.write_text("# signal_unit: ppm\ntime_min,signal\n" + rows)
    res = runner.invoke(app, ["rtd-moments", str(p), "--baseline", "0", "--tail", "auto"])
    assert res.exit_code == 0, res.output
    assert "mean residence time" in res.output and "5.000 min" in res.output


def test_rtd_moments_bad_file(tmp_path):
    p = tmp_path / "bad.csv"
    p.write_text("time_s,signal\n0,1\n1,-1\n2,1\n3,1\n4,1\n")
    res = runner.invoke(app, ["rtd-moments", str(p)])
    assert res.exit_code == 2
    assert "negative signal" in res.output
    res = runner.invoke(app, ["rtd-moments", "no_such_data"])
    assert res.exit_code == 2 and "neither an existing file" in res.output


def test_rtd_fit_json_and_plot(tmp_path):
    res = runner.invoke(app, ["rtd-fit", "lee2008_invicta", "--model", "tanks_in_series", "--delay", "--json",
                              "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    d = json.loads(res.output)
    p = d["parameters"]["n_tanks"]
    assert p["ci_low"] < p["value"] < p["ci_high"]
    assert d["r_squared"] > 0.99 and d["n_evaluations"] > 0 and d["objective"] > 0
    assert (tmp_path / "rtd_fit.png").stat().st_size > 10_000


def test_rtd_fit_table_raw_concentration():
    res = runner.invoke(app, ["rtd-fit", "ajayi2011_test4", "--baseline", "leading", "--model", "dispersion_open"])
    assert res.exit_code == 0, res.output
    assert "scale" in res.output and "correlation matrix" in res.output


def test_rtd_fit_bad_model():
    res = runner.invoke(app, ["rtd-fit", "lee2008_invicta", "--model", "plug"])
    assert res.exit_code == 2 and "model" in res.output


def test_rtd_moments_and_fit_messages_name_the_options(tmp_path):
    """rtd-moments said "give baseline_window_s" and "tail_points = 1000", fit "method = 'bogus'" (found by fuzzing)."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    runner = CliRunner()
    res = runner.invoke(app, ["rtd-moments", "lee2008_invicta", "--tail", "exponential", "--tail-points", "1000"])
    assert res.exit_code == 2 and "--tail-points = 1000" in res.output and "tail_points" not in res.output
    res = runner.invoke(app, ["fit", "lee2008_invicta", "lee2008_invicta", "-p", "transport.kiln_time", "--method",
                              "bogus", "-q"])
    assert res.exit_code == 2 and "--method = 'bogus' is not one of 'wls', 'ml'" in res.output
    res = runner.invoke(app, ["fit", "lee2008_invicta", "lee2008_invicta", "-p", "transport.kiln_time", "--scale",
                              "bogus", "-q"])
    assert res.exit_code == 2 and "--scale = 'bogus' is not one of 'known', 'fit'" in res.output


def test_rtd_moments_of_the_tools_own_curve_gives_its_residence_time(tmp_path):
    """`rtd --out`'s rtd.csv (the model's curve through the case's pulse) had no pulse lines, and rtd-moments called
    the curve's mean, half the pulse longer, the mean residence time: 416.2 s beside rtd's 386.2 s for one case
    (found by fuzzing). The file carries its pulse; rtd-moments takes it off, and names the curve's mean apart."""
    out = tmp_path / "r"
    res = runner.invoke(app, ["rtd", "lee2008_invicta", "--out", str(out), "--json"])
    assert res.exit_code == 0, res.output
    rtd = json.loads(res.stdout[res.stdout.index("{"):])
    text = (out / "rtd.csv").read_text()
    assert "# pulse_kind: rectangular" in text and "# pulse_duration_s:" in text
    res = runner.invoke(app, ["rtd-moments", str(out / "rtd.csv"), "--json"])
    assert res.exit_code == 0, res.output
    m = json.loads(res.stdout)
    assert m["tracer_mean_s"] == pytest.approx(rtd["tracer_mean_s"], rel=1e-3)
    assert m["mean_residence_time_s"] == pytest.approx(rtd["mean_residence_time_s"], rel=1e-3)
    assert m["rtd_std_s"] == pytest.approx(rtd["rtd_std_s"], rel=1e-2)
    assert m["tracer_mean_s"] - m["mean_residence_time_s"] == pytest.approx(m["pulse_duration_s"] / 2, rel=1e-9)


def test_rtd_moments_of_a_curve_without_a_pulse_keeps_its_mean(tmp_path):
    """A curve without pulse lines (a Dirac injection): the RTD's mean is the curve's; a file with a pulse gets both,
    and a warning that mean_residence_time_s no longer is the curve's mean (its meaning changed)."""
    p = tmp_path / "c.csv"
    p.write_text("time_s,signal\n" + "".join(f"{60 * i},{max(0, 5 - abs(i - 5))}\n" for i in range(11)))
    res = runner.invoke(app, ["rtd-moments", str(p), "--json"])
    assert res.exit_code == 0, res.output
    d = json.loads(res.stdout)
    assert d["mean_residence_time_s"] == d["tracer_mean_s"] == d["mean_s"] and d["pulse_duration_s"] == 0.0
    assert "warning" not in res.output
    res = runner.invoke(app, ["rtd-moments", "lee2008_invicta", "--json"])
    d = json.loads(res.stdout)
    assert d["mean_residence_time_s"] == pytest.approx(d["tracer_mean_s"] - d["pulse_duration_s"] / 2, rel=1e-12)
    assert "warning: mean_residence_time_s and rtd_std_s are the RTD's" in res.stderr

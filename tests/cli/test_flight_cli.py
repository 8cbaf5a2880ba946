import json

from typer.testing import CliRunner

from rotarydryer.cli import app

runner = CliRunner()


def test_flight_table_and_plots(tmp_path):
    res = runner.invoke(app, ["flight", "--drum", "invicta", "--repose-angle", "50", "--out", str(tmp_path)])
    assert res.exit_code == 0, res.output
    assert "2.22789" in res.output and "6,786 kg" in res.output
    assert (tmp_path / "flight_profile.png").stat().st_size > 10_000
    assert (tmp_path / "cross_section.png").stat().st_size > 10_000


def test_flight_json_custom_geometry():
    res = runner.invoke(app, ["flight", "--radius", "1.0", "--n-flights", "20", "--s1", "0.1", "--s2", "0.08",
                              "--alpha2", "130", "--repose-angle", "40", "--json"])
    assert res.exit_code == 0, res.output
    data = json.loads(res.output)
    assert data["n_flights"] == 20 and data["radius_m"] == 1.0
    assert data["passive_time_s"] > 0 and len(data["transition_angles_deg"]) == 5


def test_flight_bad_input_exit_code():
    res = runner.invoke(app, ["flight", "--s1", "3"])
    assert res.exit_code == 2
    assert "s1" in res.output and "radius" in res.output
    res = runner.invoke(app, ["flight", "--repose-angle", "95"])
    assert res.exit_code == 2 and "repose_angle" in res.output


def test_list_drums():
    res = runner.invoke(app, ["flight", "--list-drums"])
    assert res.exit_code == 0 and "invicta" in res.output and "mmg_B" in res.output

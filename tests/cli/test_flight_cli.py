import json
from pathlib import Path

import pytest
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


EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "three_section_flight.toml"


def test_flight_profile_file(tmp_path):
    """``--profile``: a flight of any shape, summary with the final discharge angle and the curtain, drawings."""
    res = runner.invoke(app, ["flight", "--profile", str(EXAMPLE), "--repose-angle", "40", "--json", "--out",
                              str(tmp_path)])
    assert res.exit_code == 0, res.output
    data = json.loads(res.output)
    assert data["geometry"] == "polygon" and len(data["flight_sections"]) == 3
    assert data["final_discharge_angle_deg"] == pytest.approx(220.0)
    assert 0.0 < data["curtain"]["cv_per_degree"] < 1.0 and sum(data["curtain"]["fraction"]) == pytest.approx(1.0)
    assert data["design_load_kg"]["lee2008"] > 0
    assert (tmp_path / "cross_section.png").stat().st_size > 10_000
    res = runner.invoke(app, ["flight", "--profile", str(EXAMPLE), "--repose-angle", "40"])
    assert res.exit_code == 0 and "final discharge angle" in res.output and "3 sections, polygon" in res.output


def test_flight_builtin_profiles_and_two_section_unchanged():
    res = runner.invoke(app, ["flight", "--list-drums"])
    assert "invicta_ead" in res.output and "invicta_three_section" in res.output
    res = runner.invoke(app, ["flight", "--drum", "invicta_ead", "--json"])
    assert res.exit_code == 0 and json.loads(res.output)["geometry"] == "polygon"
    res = runner.invoke(app, ["flight", "--drum", "invicta", "--json"])
    assert json.loads(res.output)["geometry"] == "lee2008"


@pytest.mark.parametrize("text,words", [
    ("segments = [[0.195, 90.0], [0.1, 20.0], [0.1, 20.0]]", ["segments", "intersects itself"]),
    ("vertices = [[0.01, 0.0], [0.0, 0.2]]", ["vertices[0]", "open"]),
    ("segments = [[1.5, 90.0], [1.5, 150.0]]\nradius = 2.5", ["centre"]),
    ("segments = [[0.195, 90.0], [0.0, 150.0]]", ["segments[1].length", "(0, inf) m"]),
    ("segment = [[0.195, 90.0]]", ["segment is not a key"]),
    ("radius = 2.5", ["segments (or vertices) is missing"]),
    ("segments = [[0.195, 90.0]", ["not valid TOML"]),
    ("vertices = [[0.0, 0.0], [0.0, 0.2], [0.0, 0.2]]", ["vertices[2] = vertices[1] = (0, 0.2) m", "zero length"]),
    ("segments = [[0.195, 90.0], [0.1, 200.0]]", ["segments[1].angle = 200 deg", "backwards"]),
    # a string iterated as characters: "segments[0] = ['a'] is not a (length, angle) pair" before
    ('segments = "abc"', ["segments = 'abc' is not a list of (length, angle) pairs"]),
])
def test_flight_bad_profile(tmp_path, text, words):
    p = tmp_path / "bad.toml"
    p.write_text(text)
    res = runner.invoke(app, ["flight", "--profile", str(p)])
    assert res.exit_code == 2, res.output
    lines = [ln for ln in res.output.strip().splitlines() if ln]
    assert len(lines) == 1 and lines[0].startswith("error:") and all(w in lines[0] for w in words), res.output
    assert lines[0].count(str(p)) <= 1, res.output          # the file named once (the keys after it)


def test_flight_profile_and_two_section_options_conflict(tmp_path):
    res = runner.invoke(app, ["flight", "--profile", str(EXAMPLE), "--s1", "0.2"])
    assert res.exit_code == 2 and "--profile and --s1" in res.output
    res = runner.invoke(app, ["flight", "--profile", str(tmp_path / "missing.toml")])
    assert res.exit_code == 2 and "no such file" in res.output


@pytest.mark.parametrize("option, allowed", [("--fall-height", "'chord', 'eq3.5', 'ajayi2011'"),
                                             ("--passive-branch", "'eq3.4', 'lee2008_ch7'"),
                                             ("--convention", "'root', 'tip'")])
def test_a_bad_choice_names_the_option(option, allowed):
    """The messages named the library's arguments (fall_height, passive_time_branch, convention; fuzzing)."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app

    res = CliRunner().invoke(app, ["flight", option, "bogus"])
    assert res.exit_code == 2 and f"error: {option} = 'bogus' is not one of {allowed}" in res.output


def test_a_profile_or_drum_design_repose_angle_is_the_default(tmp_path):
    """A profile's repose_angle was range-checked but ignored (the run used 45 deg); the EAD drum, designed at
    40 deg, was summarised at 45 (found by fuzzing). --repose-angle still wins."""
    p = tmp_path / "prof.toml"
    p.write_text("segments = [[0.195, 90.0], [0.10, 135.0], [0.09, 135.0]]\nrepose_angle = 30.0\n")
    res = runner.invoke(app, ["flight", "--profile", str(p), "--json"])
    assert res.exit_code == 0, res.output and json.loads(res.output)["repose_angle_deg"] == 30.0
    assert json.loads(res.output)["repose_angle_deg"] == 30.0
    res = runner.invoke(app, ["flight", "--profile", str(p), "--repose-angle", "42", "--json"])
    assert json.loads(res.output)["repose_angle_deg"] == 42.0
    res = runner.invoke(app, ["flight", "--drum", "invicta_ead", "--json"])
    assert json.loads(res.output)["repose_angle_deg"] == 40.0
    res = runner.invoke(app, ["flight", "--drum", "invicta", "--json"])
    assert json.loads(res.output)["repose_angle_deg"] == 45.0


@pytest.mark.parametrize("args,text,words", [
    # a polygon flight's neighbour check ran over N flights: 1e7 took 40-55 s before a misleading message
    (["--n-flights", "10000000"], None, ["--n-flights (n_flights) = 10000000 is outside the allowed range [2, 1000]"]),
    ([], "segments = [[0.195, 90.0], [0.1, 135.0]]\nn_flights = 10000000\n",
     ["n_flights = 10000000 is outside the allowed range: an integer in [2, 1000]"]),
    # true read as a 1 m section
    ([], "segments = [[true, 90.0], [0.1, 135.0]]\n", ["segments[0].length must be a real number, got True"]),
    # R*R underflowed to 0: an internal ZeroDivisionError
    ([], "segments = [[1e-201, 90.0], [1e-201, 135.0]]\nradius = 1e-200\n", ["radius = 1e-200 m", "[0.001, 20] m"]),
    # the message named no key ("the profile's or the 'invicta' drum's speed")
    ([], "segments = [[0.195, 90.0], [0.1, 135.0]]\nrpm = 40.0\n", [": rpm = 40 rev/min is at or above the critical"]),
])
def test_flight_profile_inputs_refused_naming_the_key(tmp_path, args, text, words):
    extra = []
    if text is not None:
        p = tmp_path / "bad.toml"
        p.write_text(text)
        extra = ["--profile", str(p)]
    else:
        extra = ["--drum", "invicta_ead"]
    res = runner.invoke(app, ["flight", *extra, *args])
    assert res.exit_code == 2, res.output
    line = res.output.strip().splitlines()[0]
    assert line.startswith("error: ") and all(w in line for w in words), line


def test_an_empty_flight_prints_no_nan():
    """--loading-factor 0 (in the allowed range) printed the curtain's span as '+nan to +nan m'."""
    res = runner.invoke(app, ["flight", "--drum", "invicta_three_section", "--loading-factor", "0"])
    assert res.exit_code == 0, res.output
    assert "nan" not in res.output.lower() and "none (the flight releases nothing)" in res.output


def test_report_of_a_polygon_flight_drum(tmp_path):
    """`rotarydryer report invicta_ead` was refused ("not ... a drum preset") though `flight --list-drums` lists it."""
    res = runner.invoke(app, ["report", "invicta_ead", "-o", str(tmp_path / "r.html")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "r.html").stat().st_size > 10_000


def test_the_drum_named_is_the_one_of_the_numbers():
    """`flight --json` reported "drum": "invicta" for a drum of the user's own dimensions (found by fuzzing): the
    preset stands in only for what is not given, and the label says what was."""
    dims = ["--radius", "1", "--n-flights", "18", "--s1", "0.15", "--s2", "0.1", "--alpha1", "90", "--alpha2", "120"]
    d = json.loads(CliRunner().invoke(app, ["flight", *dims, "--json"]).stdout)
    assert d["drum"] == "invicta with --radius, --n-flights, --s1, --s2, --alpha1, --alpha2 given"
    assert (d["radius_m"], d["n_flights"]) == (1.0, 18)
    assert json.loads(CliRunner().invoke(app, ["flight", "--json"]).stdout)["drum"] == "invicta"

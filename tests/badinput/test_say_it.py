"""Say it where the user looks (issue "Reliability under hostile and ordinary input", part B): the
reason for a missing or doubtful result is in the text output (not only in ``--json``), the exit
code tells whether the result is valid, and a message names the option actually at fault."""

from __future__ import annotations

import pytest

from .conftest import assert_bad, run_cli

#: Ajayi's MMG dryer with a burner whose combustion air cannot heat the gas to the set 500 degC
UNREACHABLE = ["ajayi2011_mmg", "--set", "gas.burner.combustion_air_share=0.02"]


# ------------------------------------------------------------------------------ burner set point
def test_simulate_says_why_the_fuel_rate_is_missing():
    """A burner that cannot reach the set gas inlet temperature: one warning line in the text output
    naming the set temperature and what the gas reaches; the steady state (of the set temperature)
    is valid, so the exit code is 0."""
    res = run_cli(["simulate", *UNREACHABLE])
    assert res.exit_code == 0, res.output
    lines = [ln for ln in res.output.splitlines() if ln.startswith("warning: burner cannot reach")]
    assert len(lines) == 1, res.output
    w = lines[0]
    assert "the set gas inlet temperature 500 degC" in w and "the gas reaches only" in w
    assert "simulated with the set gas inlet temperature" in w and "fuel rate n/a" in w
    assert "fuel rate" in res.output and "see the warning below" in res.output


def test_fuel_rate_note_of_a_summary():
    from rotarydryer.thermal.states import fuel_rate_note

    assert fuel_rate_note({"fuel_rate_kg_s": 0.1}) == ""
    note = fuel_rate_note({"fuel_rate_kg_s": None, "fuel_rate_error": "burner cannot reach the set gas inlet "
                           "temperature 900 degC:\n at the maximum fuel rate ..."})
    assert "\n" not in note and note.startswith("burner cannot reach the set gas inlet temperature 900 degC")


@pytest.mark.slow
def test_html_report_says_why_the_fuel_rate_is_missing(tmp_path):
    res = run_cli(["report", *UNREACHABLE, "-o", str(tmp_path / "r.html")])
    assert res.exit_code == 0, res.output
    text = (tmp_path / "r.html").read_text("utf-8")
    assert "<b>Warning:</b> burner cannot reach the set gas inlet temperature 500 degC" in text
    assert "n/a: burner cannot reach the set gas inlet temperature 500 degC" in text


# ------------------------------------------------------------------------------ design
@pytest.mark.slow
def test_design_verification_failure_exits_1(monkeypatch):
    from rotarydryer import design as D

    real = D.design

    def failing_verified(duty, limits=None, objective="volume", rounds=3, progress=None, **search):
        return real(duty, limits, objective=objective, progress=progress, **search), {
            "error": "coupled steady state did not converge", "rounds": [{"ua_factor": 1.0}]}

    monkeypatch.setattr(D, "design_verified", failing_verified)
    res = run_cli(["design", "--duty", "raw_sugar"])
    assert res.exit_code == 1, res.output
    assert "error: the design's verification (coupled model) failed: coupled steady state did not converge" \
        in res.output
    assert "Traceback" not in res.output


def test_design_verification_missing_the_target_is_a_failure():
    from rotarydryer.cli.design import _verification_failure

    assert _verification_failure(None, 0.1) == ""
    assert _verification_failure({"target_met": True, "rounds": [{}]}, 0.1) == ""
    msg = _verification_failure({"target_met": False, "product_moisture_kg_kg": 0.138, "rounds": [{}]}, 0.124)
    assert "failed" in msg and "13.8 %" in msg and "12.4 %" in msg     # moisture in its display unit


@pytest.mark.parametrize("args,fragments,absent", [
    (["--feed-temperature", "200"], ["--feed-temperature = 200", "(-20, 99)"], "--gas-in"),
    (["--feed-temperature", "90", "--gas-in", "80"], ["--gas-in = 80", "--feed-temperature = 90"], None),
], ids=["feed-temperature-range", "gas-below-feed"])
def test_design_names_the_option_out_of_range(workdir, args, fragments, absent):
    res = run_cli(["design", "--duty", "raw_sugar", "--no-verify", *args], cwd=workdir)
    assert_bad(res, *fragments)
    if absent:
        assert absent not in res.output


# ------------------------------------------------------------------------------ sensitivity
def test_sensitivity_counts_missing_outputs_by_reason():
    pytest.importorskip("SALib")
    from rotarydryer.studies.sensitivity import sobol_study

    def model(p):
        if p["x"] > 0.5:
            return {"y": p["x"] + p["z"], "fuel_rate_kg_s": None,
                    "fuel_rate_error": f"burner cannot reach the set gas inlet temperature 500 degC: the gas reaches "
                                       f"only {400 + p['x']:.4g} degC"}
        return {"y": p["x"] + p["z"], "fuel_rate_kg_s": p["x"]}

    res = sobol_study(model, {"x": (0.0, 1.0), "z": (0.0, 1.0)}, 8, outputs=["y", "fuel_rate_kg_s"])
    n_missing = sum(1 for r in res.runs_table() if r["fuel_rate_kg_s"] is None)
    assert n_missing > 0
    note = next(n for n in res.notes if n.startswith("fuel_rate_kg_s"))
    assert f"{n_missing} runs: burner cannot reach the set gas inlet temperature" in note, note
    saved = res.to_dict()["missing_outputs"]["fuel_rate_kg_s"]
    assert saved[0]["reason"] == "burner cannot reach the set gas inlet temperature"
    assert saved[0]["runs"] == n_missing and "the gas reaches only" in saved[0]["example"]


@pytest.mark.slow
def test_sensitivity_cli_gives_the_reasons(tmp_path):
    pytest.importorskip("SALib")
    import json

    res = run_cli(["sensitivity", "ajayi2011_mmg", "--param", "gas.burner.combustion_air_share=0.02,0.3",
                   "-n", "2", "--output", "fuel_rate_kg_s", "--output", "product_moisture_kg_kg",
                   "--out", str(tmp_path / "s")])
    assert res.exit_code == 0, res.output
    assert "runs: burner cannot reach the set gas inlet temperature" in res.output
    data = json.loads((tmp_path / "s" / "sensitivity.json").read_text())
    assert data["missing_outputs"]["fuel_rate_kg_s"][0]["reason"].startswith("burner cannot reach")


# ------------------------------------------------------------------------------ control
def test_control_default_gas_range_contains_the_case_temperature():
    from rotarydryer.control import default_gas_temperature_min

    assert default_gas_temperature_min(100.0, 55.0) == pytest.approx(77.5)     # Lee's Invicta dryer
    assert default_gas_temperature_min(517.0, 26.0) == pytest.approx(317.0)    # Ajayi's MMG dryer
    for t0, ts in ((100.0, 55.0), (60.0, 20.0), (30.0, 40.0), (600.0, 20.0)):
        assert default_gas_temperature_min(t0, ts) <= t0


@pytest.mark.slow
def test_control_runs_lee2008_with_its_defaults():
    res = run_cli(["control", "lee2008_invicta", "--duration", "1200", "--no-open-loop"])
    assert res.exit_code == 0, res.output
    assert "closed loop" in res.output


@pytest.mark.slow
def test_control_gas_range_error_names_the_option():
    res = run_cli(["control", "lee2008_invicta", "--duration", "1200", "--no-open-loop", "--gas-t-min", "150",
                   "--gas-t-max", "600"])
    assert_bad(res, "gas inlet temperature 100 degC", "--gas-t-min")

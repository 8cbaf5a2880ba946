"""The "Studies and sensitivity" page: its logic (rotarydryer.app.logic_studies) against the
library, and the page through Streamlit's headless AppTest harness."""

import math
import re
from importlib import resources

import numpy as np
import pytest

pytest.importorskip("streamlit")
pytest.importorskip("xarray")
pytest.importorskip("SALib")


from rotarydryer.app import logic, logic_studies  # noqa: E402
from rotarydryer.simulation import Simulation  # noqa: E402

from .apptest_support import image_urls as _img_urls  # noqa: E402
from .apptest_support import open_app


def test_whatif_points_are_the_library_steady_states():
    w = logic_studies.whatif_view("ajayi2011_mmg", "operating.feed_rate", 35.0, 45.0, 2)
    assert [r["operating.feed_rate"] for r in w["rows"]] == [35.0, 45.0]
    assert w["failed"] == 0 and w["plot"][:8] == b"\x89PNG\r\n\x1a\n"
    for row in w["rows"]:
        s = Simulation("ajayi2011_mmg", {"operating.feed_rate": row["operating.feed_rate"]}).steady_state().summary()
        assert row["product_moisture_kg_kg"] == pytest.approx(s["product_moisture_kg_kg"], rel=1e-9)
        assert row["gas_outlet_temperature_degC"] == pytest.approx(s["gas_outlet_temperature_degC"], rel=1e-9)
        assert row["fuel_rate_kg_s"] == pytest.approx(s["fuel_rate_kg_s"], rel=1e-9)   # the summary's names, SI
        assert row["mean_residence_time_s"] == pytest.approx(s["mean_residence_time_s"], rel=1e-9)
    assert w["rows"][1]["product_moisture_kg_kg"] > w["rows"][0]["product_moisture_kg_kg"]
    header = w["csv"].splitlines()[0].split(",")
    assert header[0] == "operating.feed_rate" and header[-1] == "error" and "fuel_rate_kg_s" in header


def test_whatif_limits_and_cli_messages():
    with pytest.raises(ValueError, match=r"points = 20 is outside the allowed range \[2, 15\]"):
        logic_studies.whatif_view("lee2008_invicta", "gas.flow", 20.0, 40.0, 20)
    with pytest.raises(ValueError, match="gas.flow: low = 40 must be below high = 20"):
        logic_studies.whatif_view("lee2008_invicta", "gas.flow", 40.0, 20.0, 3)
    with pytest.raises(ValueError, match=r"--set gas.inlet_temperature: gas.inlet_temperature = 700.0: "
                                         r"Input should be less than or equal to 600"):
        logic_studies.whatif_view("lee2008_invicta", "gas.inlet_temperature", 100.0, 700.0, 3)
    with pytest.raises(ValueError, match="is not one this page studies"):
        logic_studies.whatif_view("lee2008_invicta", "transport.n_cells", 10, 20, 3)


def test_whatif_keeps_a_point_the_model_refuses():
    """A speed above the critical speed (18.9 rev/min for the 5 m drum) is a row with its error."""
    w = logic_studies.whatif_view("lee2008_invicta", "operating.rpm", 3.0, 30.0, 2, images=False)
    assert w["failed"] == 1
    assert w["rows"][0]["error"] == "" and "critical speed" in w["rows"][1]["error"]
    assert w["rows"][1]["product_moisture_kg_kg"] is None


def test_sensitivity_is_the_library_study():
    from rotarydryer.studies.sensitivity import sobol_study

    params = {"gas.inlet_temperature": (110.0, 130.0)}
    r = logic_studies.sensitivity_view("song2003_ottawa", params, 4, seed=1)
    assert r["n_runs"] == 12 and r["n_failed"] == 0
    assert len(r["plots"]) == 2 and all(p[:8] == b"\x89PNG\r\n\x1a\n" for p in r["plots"])   # 2 outputs each
    ref = sobol_study("song2003_ottawa", params, 4, r["data"]["outputs"], seed=1)
    assert r["data"]["indices"] == ref.indices
    assert r["data"]["outputs"] == ["product_moisture_kg_kg", "gas_outlet_temperature_degC",
                                    "mean_residence_time_s", "product_temperature_degC"]   # no burner: no fuel
    assert len(r["runs_csv"].splitlines()) == 13


def test_sensitivity_of_an_uploaded_case():
    text = (resources.files("rotarydryer") / "cases" / "song2003_ottawa.toml").read_text()
    staged = logic.stage_case_file(text.encode())
    params = {"gas.inlet_temperature": (110.0, 130.0)}
    up = logic_studies.sensitivity_view(staged, params, 4, seed=1, images=False)
    ref = logic_studies.sensitivity_view("song2003_ottawa", params, 4, seed=1, images=False)
    for o in ref["data"]["outputs"]:   # cold starts (upload) vs warm starts: the same steady states
        for k in ("S1", "ST"):
            a, b = up["data"]["indices"][o]["gas.inlet_temperature"][k], ref["data"]["indices"][o]["gas.inlet_temperature"][k]
            assert (math.isnan(a) and math.isnan(b)) or a == pytest.approx(b, abs=1e-5)
    with pytest.raises(ValueError, match="gas.inlet_temperature = 700"):
        logic_studies.sensitivity_view(staged, {"gas.inlet_temperature": (100.0, 700.0)}, 4)


def test_sensitivity_limits():
    two = {"operating.feed_rate": (20.0, 30.0), "gas.flow": (25.0, 35.0)}
    with pytest.raises(ValueError, match="samples = 32 with 2 inputs gives 128 runs; the limit is 96 runs"):
        logic_studies.sensitivity_view("lee2008_invicta", two, 32)
    five = {s["key"]: (s["low"], s["high"]) for s in logic_studies.study_inputs("lee2008_invicta")[:5]}
    with pytest.raises(ValueError, match="5 uncertain inputs; the limit is 4"):
        logic_studies.sensitivity_view("lee2008_invicta", five, 4)
    with pytest.raises(ValueError, match="--param gas.flow: LOW = 35 must be below HIGH = 25"):
        logic_studies.sensitivity_view("lee2008_invicta", {"gas.flow": (35.0, 25.0)}, 4)
    with pytest.raises(ValueError, match="--param operating.feed_rate=0,30: operating.feed_rate = 0.0"):   # not --set
        logic_studies.sensitivity_view("lee2008_invicta", {"operating.feed_rate": (0.0, 30.0)}, 4)


def test_study_input_ranges_hold_the_case_value():
    for case in ("ajayi2011_mmg", "lee2008_invicta", "song2003_ottawa"):
        for s in logic_studies.study_inputs(case):
            assert s["min"] <= s["low"] < s["high"] <= s["max"], (case, s["key"])
            if s["value"]:
                assert s["low"] <= s["value"] <= s["high"] or np.isclose(s["value"], s["low"]), (case, s["key"])


# ---------------------------------------------------------------------------------- the page
@pytest.fixture()
def at():
    return open_app("Studies and sensitivity", timeout=180, no_error=True)


def test_page_whatif_updates_and_refuses_bad_range(at):
    assert len(at.image) == 1
    before = _img_urls(at)[0]
    at.number_input(key="studies_points").set_value(3).run()
    assert not at.exception and not at.error
    assert _img_urls(at)[0] != before
    key = "operating.feed_rate"
    at.number_input(key=f"studies_low__ajayi2011_mmg__{key}").set_value(60.0).run()    # above "To"
    assert not at.exception
    assert at.error and "must be below high" in at.error[0].value
    assert at.button(key="studies_run")        # the rest of the page is still there


def test_page_sensitivity_runs_on_the_button(at):
    at.sidebar.selectbox(key="studies_case").set_value("song2003_ottawa").run()
    assert not at.exception and not at.error
    assert not any(m.label == "Runs (failed)" for m in at.metric)
    at.multiselect(key="studies_sens_inputs__song2003_ottawa").set_value(["gas.inlet_temperature"]).run()
    at.selectbox(key="studies_samples").set_value(4).run()
    at.button(key="studies_run").click().run()
    assert not at.exception and not at.error, [e.value for e in at.error]
    runs = next(m for m in at.metric if m.label == "Runs (failed)")
    assert re.match(r"12 \(0\)", runs.value)
    assert len(at.image) == 3      # what-if plot and the Sobol figures (two outputs each)
    at.selectbox(key="studies_samples").set_value(8).run()       # changed inputs: the old result is not shown
    assert not any(m.label == "Runs (failed)" for m in at.metric)


def test_page_sensitivity_same_study_in_a_second_session():
    """A second visitor running the same study in the same server process (the progress bar is not
    replayed from a cache: that failed with CacheReplayClosureError once another session had run it)."""
    for _ in range(2):
        at = open_app("Studies and sensitivity", timeout=180, no_error=True)
        at.sidebar.selectbox(key="studies_case").set_value("song2003_ottawa").run()
        at.multiselect(key="studies_sens_inputs__song2003_ottawa").set_value(["gas.inlet_temperature"]).run()
        at.selectbox(key="studies_samples").set_value(4).run()
        at.button(key="studies_run").click().run()
        assert not at.exception and not at.error, [e.value for e in at.error]
        assert re.match(r"12 \(0\)", next(m for m in at.metric if m.label == "Runs (failed)").value)

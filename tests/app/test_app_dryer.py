"""The "Whole dryer" page: its logic (rotarydryer.app.logic_dryer) against the library, and the
page through Streamlit's headless AppTest harness."""

from importlib import resources

import pytest

pytest.importorskip("streamlit")
pytest.importorskip("xarray")


from rotarydryer.app import logic, logic_dryer  # noqa: E402
from rotarydryer.simulation import Simulation  # noqa: E402

from .apptest_support import metric_number as _metric  # noqa: E402
from .apptest_support import open_app


@pytest.fixture(scope="module")
def mmg():
    return logic_dryer.dryer_view("ajayi2011_mmg")


def test_metrics_are_the_library_steady_state(mmg):
    s = Simulation("ajayi2011_mmg").steady_state().summary()
    m = mmg["metrics"]
    for key in ("product_moisture_kg_kg", "product_temperature_degC", "gas_outlet_temperature_degC",
                "specific_energy_kJ_kg_water", "thermal_efficiency", "evaporation_kg_s", "mean_residence_time_s",
                "heat_input_W", "fuel_rate_kg_s"):      # the summary's names and SI values: one name per quantity
        assert m[key] == pytest.approx(s[key], rel=1e-9), key
    assert mmg["has_burner"]
    assert mmg["profiles"][:8] == b"\x89PNG\r\n\x1a\n" and mmg["waterfall"][:8] == b"\x89PNG\r\n\x1a\n"


def test_profile_rows_are_the_profiles_and_the_plant_values(mmg):
    """The interactive charts' rows: every gas stage and tank of the steady state, and Ajayi's
    test 4 measured values at the ends (gas in at the feed end: co-current)."""
    rows = mmg["profile_rows"]
    s = Simulation("ajayi2011_mmg").steady_state()
    p = s.thermal.profiles()
    gas_t = [r for r in rows if r["quantity"] == "temperature" and r["series"] == "gas"]
    assert [r["value"] for r in gas_t] == pytest.approx(list(p["gas_temperature_degC"]))
    solids = [r for r in rows if r["quantity"] == "moisture" and not r["measured"]]
    assert len(solids) == len(p["position"]) and {r["series"] for r in solids} <= {
        "solids (bed)", "solids (passive)", "solids (active)"}
    meas = {(r["quantity"], r["value"]) for r in rows if r["measured"]}
    m = mmg["measured"]
    # the chart's values are in the display units: degC and % by default
    assert ("temperature", m["gas_in_c"]) in meas and ("moisture", 100.0 * m["moisture_out"]) in meas
    assert [r["value"] for r in solids][:3] == pytest.approx(list(100.0 * p["moisture_wet"][:3]))
    x0 = min(r["position_m"] for r in rows)
    assert next(r for r in rows if r["measured"] and r["value"] == m["gas_in_c"])["position_m"] == x0
    assert not any(r["measured"] for r in logic_dryer.dryer_view("lee2008_invicta", images=False)["profile_rows"])


def test_page_profile_charts_have_a_read_out(at):
    """The profiles are Altair charts with a tooltip read-out and a nearest-position hover; the
    PNG figure stays downloadable."""
    import json

    specs = [json.loads(c.proto.spec) for c in at.get("vega_lite_chart")]
    for spec in specs:
        assert any("tooltip" in layer.get("encoding", {}) for layer in spec["layer"])
        params = spec.get("params", []) + [p for layer in spec["layer"] for p in layer.get("params", [])]
        assert any(p.get("select", {}).get("nearest") for p in params)
    assert "Download the profiles figure (PNG)" in [b.label for b in at.get("download_button")]


def test_energy_tab_shows_the_heat_duties(mmg):
    """Issue 34: the Energy tab shows the energy audit's heat duties (the summary's, in the display unit
    of power, kW by default; they add up to the release), not enthalpies against a reference."""
    from rotarydryer.thermal.audit import HEAT_DUTY_PARTS

    s = mmg["summary"]
    rows = {t["name"]: t for t in mmg["duties"]}
    assert list(rows) == ["heat_release_W", *HEAT_DUTY_PARTS, "heat_duty_exhaust_latent_W"]
    for k, t in rows.items():
        assert t["value"] == pytest.approx(s[k] / 1e3, rel=1e-12), k
    assert sum(rows[k]["value"] for k in HEAT_DUTY_PARTS) == pytest.approx(rows["heat_release_W"]["value"], rel=1e-9)
    assert sum(t["share_pct"] for t in mmg["duties"] if t["part"]) == pytest.approx(100.0, rel=1e-9)
    assert rows["heat_duty_exhaust_latent_W"]["share_pct"] is None and not rows["heat_duty_exhaust_latent_W"]["part"]
    assert [x["section"] for x in mmg["shell_sections"]] == ["A", "B", "C", "D", "E"]
    assert "energy_terms_w" not in mmg and "energy_table" not in mmg


def test_measured_plant_values_of_the_test(mmg):
    """Ajayi (2011) Table 3.9 (test 4): gas 500 -> 131 degC, product 12.4 % moisture."""
    meas = mmg["measured"]
    assert meas["test"] == 4
    assert meas["gas_in_c"] == pytest.approx(500.0) and meas["gas_out_c"] == pytest.approx(131.0)
    assert meas["moisture_out"] == pytest.approx(0.124)
    assert logic_dryer.dryer_view("lee2008_invicta", images=False)["measured"] is None


def test_operating_inputs_are_the_case_values():
    by = {s["key"]: s for s in logic_dryer.operating_inputs("lee2008_invicta")}
    assert by["gas.flow"]["value"] == pytest.approx(30.4)
    assert by["gas.inlet_temperature"]["value"] == pytest.approx(100.0)
    assert by["operating.feed_moisture"]["value"] == pytest.approx(0.02 / 1.02)
    assert by["operating.feed_rate"]["value"] == pytest.approx(98000 / 3600)
    t5 = {s["key"]: s for s in logic_dryer.operating_inputs("ajayi2011_mmg", 5)}
    assert t5["operating.rpm"]["value"] == pytest.approx(2.0)
    assert t5["operating.feed_rate"]["value"] == pytest.approx(32.333333)
    assert t5["gas.inlet_temperature"]["value"] == pytest.approx(509.0)          # the test's PI value
    assert t5["operating.feed_moisture"]["value"] == pytest.approx(0.1653)         # one schema: the same keys
    assert logic_dryer.plant_tests("ajayi2011_mmg") == [1, 2, 3, 4, 5, 6]   # every test has its calibrated u_s, D
    assert logic_dryer.plant_tests("song2003_ottawa") == list(range(74))  # the heated point + Song's 73 runs
    song = {s["key"] for s in logic_dryer.operating_inputs("song2003_ottawa")}
    assert {"operating.feed_moisture", "gas.flow", "gas.inlet_temperature"} <= song


def test_changed_inputs_give_the_library_values():
    ov = {"gas.inlet_temperature": 120.0, "operating.feed_rate": 25.0}
    r = logic_dryer.dryer_view("lee2008_invicta", ov, images=False)
    s = Simulation("lee2008_invicta", ov).steady_state().summary()
    assert r["metrics"]["gas_outlet_temperature_degC"] == pytest.approx(s["gas_outlet_temperature_degC"], rel=1e-9)
    assert r["metrics"]["product_moisture_kg_kg"] == pytest.approx(s["product_moisture_kg_kg"], rel=1e-9)
    assert not r["has_burner"] and r["metrics"]["fuel_rate_kg_s"] is None


def test_bad_value_gives_the_cli_message(cli):
    from typer.testing import CliRunner

    with pytest.raises(ValueError) as app_err:
        logic_dryer.dryer_view("ajayi2011_mmg", {"operating.feed_rate": 0.0}, images=False)
    out = CliRunner().invoke(cli, ["simulate", "ajayi2011_mmg", "--set", "operating.feed_rate=0"])
    assert out.exit_code == 2
    for part in ("--set operating.feed_rate: operating.feed_rate = ", "Input should be greater than 0"):
        assert part in str(app_err.value) and part in out.output
    with pytest.raises(ValueError, match=r"operating.rpm = 30 rev/min is at or above the critical speed"):
        logic_dryer.dryer_view("lee2008_invicta", {"operating.rpm": 30.0}, images=False)


def test_case_without_heat_and_mass_transfer_is_named():
    with pytest.raises(logic_dryer.NoThermalModel, match="no heat and mass transfer model"):
        logic_dryer.dryer_view("lee2008_invicta", {"thermal.enabled": False})
    text = (resources.files("rotarydryer") / "cases" / "song2003_ottawa.toml").read_text()
    staged = logic.stage_case_file(text.replace("[thermal]\n", "[thermal]\nenabled = false\n").encode())
    with pytest.raises(logic_dryer.NoThermalModel):
        logic_dryer.operating_inputs(staged)


def test_uploaded_case_runs_like_the_shipped_one():
    text = (resources.files("rotarydryer") / "cases" / "song2003_ottawa.toml").read_text()
    staged = logic.stage_case_file(text.encode())
    up = logic_dryer.dryer_view(staged, {"gas.inlet_temperature": 110.0}, images=False)
    ref = logic_dryer.dryer_view("song2003_ottawa", {"gas.inlet_temperature": 110.0}, images=False)
    assert up["metrics"] == ref["metrics"]
    assert up["profiles_csv"] == ref["profiles_csv"] and up["profiles_csv"].startswith("position_m,")


def test_profiles_csv_holds_the_whole_drum():
    """The download zipped the tanks with the evaporation per gas stage: MMG's solids table stopped at 11.85 m of its
    22.2 m (78 of 120 tanks) with another tank's evaporation on each row."""
    import csv
    import io

    th = Simulation("ajayi2011_mmg", {"operating.test": 4}).steady_state().thermal
    solids, gas = logic_dryer.dryer_view("ajayi2011_mmg", {"operating.test": 4}, images=False)["profiles_csv"].split("\n\n")
    rows = list(csv.DictReader(io.StringIO(solids)))
    assert len(rows) == th.dryer.n_tanks == 120
    assert sum(float(r["holdup_kg"]) for r in rows) == pytest.approx(th.total_holdup, rel=1e-12)
    assert max(float(r["position_m"]) for r in rows) > 22.0
    stages = list(csv.DictReader(io.StringIO(gas)))
    assert len(stages) == th.dryer.n_gas
    assert sum(float(r["evaporation_kg_s"]) for r in stages) == pytest.approx(th.evaporation_rate, rel=1e-12)


def test_the_runs_warnings_reach_the_page():
    """The CLI printed a run's warnings (an extrapolation of the transport law, a speed near the critical); the
    whole-dryer page showed the numbers alone (the warnings went to the server's log)."""
    song = logic_dryer.dryer_view("song2003_ottawa", images=False)
    assert any("outside the conditions the coefficients" in w for w in song["warnings"])
    assert len(song["warnings"]) == len(set(song["warnings"]))
    fast = logic_dryer.dryer_view("ajayi2011_mmg", {"operating.test": 4, "operating.rpm": 21.0}, images=False)
    assert any("critical" in w for w in fast["warnings"]), fast["warnings"]


# ---------------------------------------------------------------------------------- the page
@pytest.fixture()
def at():
    return open_app("Whole dryer", timeout=120, no_error=True)


def test_page_renders_and_feed_rate_changes_the_product(at):
    labels = [m.label for m in at.metric]
    for label in ("Product moisture", "Product temperature", "Gas outlet temperature", "Mean residence time",
                  "Specific energy", "Thermal efficiency", "Fuel rate"):
        assert label in labels
    assert len(at.image) == 1                                   # the energy waterfall; the profiles: charts
    assert len(at.get("vega_lite_chart")) == 3
    before = _metric(at, "Product moisture")
    s = Simulation("ajayi2011_mmg").steady_state().summary()
    assert before == pytest.approx(100 * s["product_moisture_kg_kg"], abs=1e-2)     # shown in % (display unit)
    assert before == pytest.approx(12.4, abs=1.0)       # Ajayi (2011) test 4, measured (docs/validation.md)
    at.number_input(key="dryer__operating.feed_rate__ajayi2011_mmg__4").set_value(50.0).run()
    assert not at.exception and not at.error
    assert _metric(at, "Product moisture") > before      # more feed, same gas: wetter product


def test_page_test_choice_and_bad_value(at):
    at.sidebar.selectbox(key="dryer_test__ajayi2011_mmg").set_value(5).run()
    assert not at.exception and not at.error
    assert at.number_input(key="dryer__operating.rpm__ajayi2011_mmg__5").value == pytest.approx(2.0)
    at.number_input(key="dryer__operating.feed_rate__ajayi2011_mmg__5").set_value(0.0).run()
    assert not at.exception
    assert at.error and "operating.feed_rate" in at.error[0].value and "greater than 0" in at.error[0].value
    assert "Traceback" not in at.error[0].value


def test_page_case_without_burner(at):
    at.sidebar.selectbox(key="dryer_case").set_value("lee2008_invicta").run()
    assert not at.exception and not at.error
    labels = [m.label for m in at.metric]
    assert "Heat input" in labels and "Fuel rate" not in labels
    before = _metric(at, "Gas outlet temperature")
    at.number_input(key="dryer__gas.inlet_temperature__lee2008_invicta__None").set_value(130.0).run()
    assert not at.exception and not at.error
    assert _metric(at, "Gas outlet temperature") > before


def test_downloads_hold_the_changed_operating_point():
    ov = {"gas.inlet_temperature": 110.0}
    html = logic_dryer.report_html("song2003_ottawa", ov)
    assert html.lstrip().lower().startswith("<!doctype html") and "song2003_ottawa" in html
    nc = logic_dryer.netcdf_bytes("song2003_ottawa", ov)
    assert nc[:4] in (b"\x89HDF", b"CDF\x01", b"CDF\x02")
    res = logic_dryer.results_of("song2003_ottawa", ov)
    ref = logic_dryer.dryer_view("song2003_ottawa", ov, images=False)["summary"]
    assert res.scalars["gas_outlet_temperature_degC"] == pytest.approx(ref["gas_outlet_temperature_degC"], rel=1e-9)


def test_uploaded_case_with_size_classes_has_the_particle_sizes_view():
    """A `rotarydryer new` template with its [particle_size] block uncommented, uploaded: a row per size
    class (the library's table) and the size-distribution figure for the "Particle sizes" tab."""
    text = (resources.files("rotarydryer") / "cases" / "templates" / "dryer.toml").read_text("utf-8")
    for line in ("[particle_size]", "classes = 5", "sieve_m =", "passing_pct ="):
        text = text.replace("# " + line, line, 1)
    staged = logic.stage_case_file(text.encode())
    v = logic_dryer.dryer_view(staged)
    rows = v["size_classes"]
    assert len(rows) == 5 and sum(r["feed_fraction"] for r in rows) == pytest.approx(1.0)
    assert v["summary"]["product_d50_m"] > 0 and v["size_plot"][:8] == b"\x89PNG\r\n\x1a\n"
    assert "size_classes" not in logic_dryer.dryer_view("song2003_ottawa", images=False)


def test_the_measured_tab_compares_the_product_temperature_at_the_sensor():
    """The app's model-against-measured table put the drum-outlet temperature (61.0 degC) beside the plant's sensor
    reading (46 degC), where validate and the report compare the model at the sensor (45.7 degC; found by a review)."""
    from rotarydryer.app.logic_dryer import dryer_view, measured_table

    v = dryer_view("ajayi2011_mmg", {"operating.test": 4}, images=False)
    t = measured_table(v["summary"], v["measured"])
    i = t["quantity"].index("product temperature at the sensor")
    model = float(t["model"][i].split()[0])
    assert abs(model - v["summary"]["product_temperature_at_sensor_degC"]) < 0.1
    assert abs(model - 46.0) < 2.0

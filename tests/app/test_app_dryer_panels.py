"""The "Whole dryer" page's run panels (Target, Schedule): their logic
(rotarydryer.app.logic_dryer_runs) and the page through Streamlit's headless AppTest harness."""

import pytest

pytest.importorskip("streamlit")
pytest.importorskip("altair")

from rotarydryer.app import logic, logic_dryer_runs  # noqa: E402

from .apptest_support import open_app  # noqa: E402


def test_schedule_fraction_reads_the_progress_messages():
    assert logic_dryer_runs.schedule_fraction("t = 600 / 7200 s") == pytest.approx(600 / 7200)
    assert logic_dryer_runs.schedule_fraction("steady state ...") is None


def test_find_spec_needs_both_bounds_or_none():
    assert logic_dryer_runs.find_spec("operating.feed_rate") == "operating.feed_rate"
    assert logic_dryer_runs.find_spec("operating.feed_rate", 20.0, 40.0) == "operating.feed_rate=20.0,40.0"
    with pytest.raises(ValueError, match="both bounds"):
        logic_dryer_runs.find_spec("operating.feed_rate", 20.0, None)


def test_custom_csv_schedule_and_bad_csv():
    s = logic_dryer_runs.preset_schedule(logic_dryer_runs.CUSTOM_CSV, "ajayi2011_mmg", {},
                                         b"time_s,gas_inlet_temperature\n600,400\n")
    assert s.points == {"gas_inlet_temperature": ((600.0, 400.0),)}
    with pytest.raises(ValueError, match="time_s"):
        logic_dryer_runs.preset_schedule(logic_dryer_runs.CUSTOM_CSV, "ajayi2011_mmg", {}, b"t,x\n1,2\n")


def test_target_on_an_uploaded_case_is_the_shipped_one():
    """An upload goes to the target study as a temporary .toml file: the same answer."""
    from importlib import resources

    text = (resources.files("rotarydryer") / "cases" / "ajayi2011_mmg.toml").read_bytes()
    up = logic.stage_case_file(text)
    args = ("operating.feed_rate", 20.0, 40.0, "product_moisture_kg_kg", "=", 0.12)
    a = logic_dryer_runs.run_target_view(up, {"operating.test": 4}, *args)
    b = logic_dryer_runs.run_target_view("ajayi2011_mmg", {"operating.test": 4}, *args)
    assert a["found"] and a["value"] == pytest.approx(b["value"], rel=1e-6)
    # named as an upload, not by the server's temporary file ("target of /tmp/tmp.../uploaded_case.toml")
    assert a["text"].startswith("target of uploaded case:") and a["dict"]["case"] == "uploaded case"
    assert b["text"].startswith("target of ajayi2011_mmg:")


def test_panels_on_a_case_made_by_rotarydryer_new(tmp_path):
    """A `rotarydryer new` template, uploaded: a target (default bounds) and a short schedule run."""
    from typer.testing import CliRunner

    from rotarydryer.cli import app as cli
    from rotarydryer.cli import schema as _schema  # noqa: F401  (registers the commands)

    p = tmp_path / "mine.toml"
    res = CliRunner().invoke(cli, ["new", "mine", "-o", str(p)])
    assert res.exit_code == 0, res.output
    up = logic.stage_case_file(p.read_bytes())
    t = logic_dryer_runs.run_target_view(up, {}, "gas.inlet_temperature", None, None, "product_temperature_degC",
                                         ">=", -50.0)
    assert t["text"] and t["active"]
    r = logic_dryer_runs.run_schedule_view(up, {}, logic_dryer_runs.TRIP, 1500.0, 100.0)
    assert r["points"] >= 16 and r["csv"].startswith("time_s,")


@pytest.fixture
def at():
    return open_app("Whole dryer", timeout=120, no_error=True)


def _target(at, lo, hi, value):
    at.selectbox(key="dryer_target_find").set_value("operating.feed_rate")
    at.number_input(key="dryer_target_lo").set_value(lo)
    at.number_input(key="dryer_target_hi").set_value(hi)
    at.selectbox(key="dryer_target_output").set_value("product_moisture_kg_kg")
    at.selectbox(key="dryer_target_op").set_value("=")
    at.number_input(key="dryer_target_value__product_moisture_kg_kg").set_value(value)
    at.button(key="dryer_target_run").click().run()
    assert not at.exception, [e.value for e in at.exception]
    return at


def test_page_target_finds_the_feed_rate(at):
    _target(at, 20.0, 40.0, 0.12)
    assert not at.error, [e.value for e in at.error]
    m = next(m for m in at.metric if m.label == "operating.feed_rate")
    assert 29.0 < float(m.value.split()[0]) < 31.0
    assert any("target met" in c.value for c in at.code)
    # a rerun (another widget) shows the kept result without a new run
    at.run()
    assert any(m.label == "operating.feed_rate" for m in at.metric)


def test_page_unreachable_target_warns(at):
    _target(at, 20.0, 40.0, 0.0001)
    assert not at.error, [e.value for e in at.error]
    assert any("not reached" in w.value for w in at.warning)


def test_page_bad_bounds_show_one_error(at):
    _target(at, 40.0, 20.0, 0.12)
    assert len(at.error) == 1 and "Target refused" in at.error[0].value


def test_page_burner_trip_schedule_draws_charts_and_a_download(at):
    at.selectbox(key="dryer_sched_preset").set_value(logic_dryer_runs.TRIP)
    at.number_input(key="dryer_sched_t_end").set_value(1800.0)
    at.button(key="dryer_sched_run").click().run()
    assert not at.exception, [e.value for e in at.exception]
    assert not at.error, [e.value for e in at.error]
    charts = [e for e in at.get("arrow_vega_lite_chart")] or [e for e in at.get("vega_lite_chart")]
    assert len(charts) >= 2 + 3          # the profile charts and the two schedule charts
    assert any("maximum" in md.value for md in at.markdown)
    dl = [e for e in at.get("download_button") if "schedule" in str(e.proto.label)]
    assert dl


def test_panels_refuse_a_case_without_heat_and_mass():
    from rotarydryer.app import logic_dryer

    ov = {"thermal.enabled": False}
    with pytest.raises(logic_dryer.NoThermalModel):
        logic_dryer_runs.run_schedule_view("lee2008_invicta", ov, logic_dryer_runs.TRIP, 1800.0, 60.0)
    with pytest.raises(logic_dryer.NoThermalModel):
        logic_dryer_runs.run_target_view("lee2008_invicta", ov, "operating.feed_rate", None, None,
                                         "product_moisture_kg_kg", "=", 0.1)


def test_feed_step_preset_is_ten_percent_above_the_case_feed():
    ov = {"operating.test": 4, "operating.feed_rate": 30.0}
    s = logic_dryer_runs.preset_schedule(logic_dryer_runs.FEED_STEP, "ajayi2011_mmg", ov)
    (t0, before), (t1, after) = s.points["feed_rate"]
    assert t0 == t1 == 600.0 and after == pytest.approx(1.1 * 30.0, rel=1e-9)

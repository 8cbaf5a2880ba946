"""Web app logic through Streamlit's headless AppTest harness (no browser, no server)."""

import csv
from importlib import resources

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

pytest.importorskip("streamlit")
pytest.importorskip("xarray")


from rotarydryer.app import logic  # noqa: E402

from .apptest_support import goto, open_app  # noqa: E402
from .apptest_support import image_urls as _img_urls
from .apptest_support import metric_number as _metric

runner = CliRunner()


def _csv(name):
    text = (resources.files("rotarydryer") / "data" / name).read_text()
    return list(csv.DictReader(line for line in text.splitlines() if not line.startswith("#")))


@pytest.fixture()
def at():
    return open_app(timeout=120)


def test_geometry_page_reproduces_lee_table_7_7_and_updates(at):
    """Lee (2008) Table 7.7: design load 6784 kg at phi = 50 deg (Invicta preset)."""
    row = next(r for r in _csv("lee_response_angle_of_repose_holdups.csv") if r["dynamic_angle_of_repose_deg"] == "50")
    before, imgs_before = _metric(at, "Design load (Lee 2008)"), _img_urls(at)
    assert len(imgs_before) == 2 and len(at.table) == 2
    at.number_input(key="repose_angle").set_value(50.0).run()
    assert not at.exception
    after = _metric(at, "Design load (Lee 2008)")
    assert after == pytest.approx(float(row["flighted_mass_kg"]), rel=3e-3)
    assert after > before
    imgs_after = _img_urls(at)
    assert imgs_after[0] != imgs_before[0] and imgs_after[1] != imgs_before[1]  # both pictures redrawn


def test_geometry_page_preset_and_bad_geometry(at):
    at.sidebar.selectbox(key="preset").set_value("ajayi_pilot").run()
    assert at.number_input(key="radius__ajayi_pilot").value == pytest.approx(0.375)
    small = _metric(at, "Design load (Lee 2008)")
    assert 0 < small < 100  # pilot drum: a few kg
    at.number_input(key="s1__ajayi_pilot").set_value(1.5).run()  # flight longer than the radius
    assert not at.exception
    assert at.error and "s1" in at.error[0].value


def test_geometry_page_polygonal_flights(at):
    """The EAD and three-section drums are on the page too (their flight shape as the preset's, its radius and
    flight count editable), with the numbers of `rotarydryer flight` for the same drum."""
    import json

    from rotarydryer.cli import app as cli_app

    at.sidebar.selectbox(key="preset").set_value("invicta_ead").run()
    assert not at.exception and not at.error
    assert any("Polygonal flight" in c.value and "deg" in c.value for c in at.caption)
    res = runner.invoke(cli_app, ["flight", "--drum", "invicta_ead", "--json"])
    cli = json.loads(res.stdout)
    assert _metric(at, "Passive time") == pytest.approx(cli["passive_time_s"], rel=1e-3)
    at.number_input(key="radius__invicta_ead").set_value(0.3).run()     # the flight no longer fits
    assert at.error and "radius = 0.3 m" in at.error[0].value
    g = logic.profile_view("invicta_three_section", 2.5, 28, 40.0, 3.0, 2.8, 800.0, 12.0, images=False)
    assert len(g["sections"]) == 3 and g["metrics"]["design_load_kg"] > 0
    with pytest.raises(ValueError, match="not a built-in drum with a polygonal flight"):
        logic.profile_view("invicta", 2.5, 28, 40.0, 3.0, 2.8, 800.0, 12.0, images=False)


def test_transport_page_speed_and_tracer_fit(at):
    """Co-current under-loaded MMG dryer: higher speed -> shorter residence time (in Lee's
    over-loaded counter-current Invicta case the kilning bed grows with speed instead);
    Ajayi (2011) test 4 tracer: fitted outlet mean vs the published measured mean
    15.21 min (Tables 3.12-3.13), 1 %."""
    goto(at, "Transport and RTD")
    assert not at.exception and not at.error
    assert _metric(at, "Total holdup") > 1000
    at.sidebar.selectbox(key="case").set_value("ajayi2011_mmg").run()
    assert not at.exception and not at.error
    mrt3 = _metric(at, "Mean residence time H/F")
    imgs = _img_urls(at)
    assert len(imgs) == 4
    at.number_input(key="trpm__ajayi2011_mmg").set_value(4.0).run()
    assert not at.exception
    mrt4 = _metric(at, "Mean residence time H/F")
    assert mrt4 < mrt3
    assert _img_urls(at)[:3] != imgs[:3]
    published = next(r for r in _csv("ajayi_rtd_tests_summary.csv") if r["test"] == "4")
    assert _metric(at, "Fitted outlet mean") == pytest.approx(float(published["MRT_measured_min"]), rel=0.01)


def test_logic_upload_equals_shipped_dataset():
    text = (resources.files("rotarydryer") / "data" / "tracer_ajayi2011_test4.csv").read_text()
    a = logic.fit_tracer(text=text, images=False)
    b = logic.fit_tracer(dataset="ajayi2011_test4", images=False)
    assert a["table"] == b["table"]
    with pytest.raises(ValueError, match="exactly one"):
        logic.fit_tracer(images=False)
    with pytest.raises(ValueError):
        logic.fit_tracer(text="time_s,signal\n0,abc\n", images=False)


@settings(max_examples=10, deadline=None)
@given(rpm=st.floats(0.5, 9.0), repose=st.floats(30.0, 60.0))
def test_logic_passive_time_inverse_to_speed(rpm, repose):
    e = logic.presets()["invicta"]
    args = [e[k] for k in ("radius", "n_flights", "s1", "s2", "alpha1", "alpha2")]
    v1 = logic.geometry_view(*args, repose, rpm, 2.8, 940.0, 12.0, images=False)["metrics"]
    v2 = logic.geometry_view(*args, repose, 2 * rpm, 2.8, 940.0, 12.0, images=False)["metrics"]
    assert v2["passive_time_s"] == pytest.approx(v1["passive_time_s"] / 2, rel=1e-9)
    assert v2["design_load_kg"] == v1["design_load_kg"]  # the design load does not depend on speed


def test_app_cli_print_command_and_bad_port(cli):
    res = runner.invoke(cli, ["app", "--print-command", "--port", "8765", "--json"])
    assert res.exit_code == 0, res.output
    assert "streamlit_app.py" in res.output and "8765" in res.output and "127.0.0.1" in res.output
    res = runner.invoke(cli, ["app", "--port", "70000"])
    assert res.exit_code == 2 and "port" in res.output


def test_logic_uploaded_case_file(tmp_path):
    text = (resources.files("rotarydryer.cases") / "lee2008_invicta.toml").read_text()
    text = text.replace("rpm = 3.0", "rpm = 4.0", 1)
    path = logic.stage_case_file(text.encode())
    assert logic.case_defaults(path)["rpm"] == 4.0
    assert logic.stage_case_file(text.encode()) == path  # content-addressed
    with pytest.raises(ValueError, match="TOML"):
        logic.stage_case_file(b"radius = = 3")
    bad = logic.stage_case_file(text.replace("radius = 2.5", "radius = -2.5", 1).encode())
    with pytest.raises(ValueError, match="drum.radius"):
        logic.case_defaults(bad)

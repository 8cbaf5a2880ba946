"""Web app page "Calibration" (issue 31 item 4): its logic is `rotarydryer calibrate`'s service, bad
choices give the CLI's messages, it runs on a case made by ``rotarydryer new`` with measured tests,
and the page shows the fit, model against measured and the downloads after a run with progress."""

import pytest
from typer.testing import CliRunner

pytest.importorskip("streamlit")

from rotarydryer.app import logic, logic_calibration  # noqa: E402
from rotarydryer.cases import load_case_text  # noqa: E402
from rotarydryer.services.calibration import run_calibration  # noqa: E402

from .apptest_support import open_app  # noqa: E402

ARGS = dict(parameters=["thermal.area_scale"], tests=[4, 5], responses=["gas_outlet_temperature", "product_moisture"])


@pytest.fixture(scope="module")
def mmg():
    return logic_calibration.calibration_view("ajayi2011_mmg", **ARGS)


def test_logic_is_the_cli_service(mmg):
    ref = run_calibration("ajayi2011_mmg", ARGS["parameters"], tests=ARGS["tests"], responses=ARGS["responses"])
    p = ref.calibration.fit.parameters["thermal.area_scale"]
    row = mmg["parameters"][0]
    assert row["key"] == "thermal.area_scale" and row["unit"] == "-"
    assert row["value"] == pytest.approx(p.value, rel=1e-9)
    assert (row["ci_low"], row["ci_high"]) == pytest.approx((p.ci_low, p.ci_high), rel=1e-9)
    assert row["ci_low"] < row["value"] < row["ci_high"]
    assert [c["name"] for c in mmg["comparison"]] == [c["name"] for c in ref.calibration.comparison()]
    assert mmg["plot"][:8] == b"\x89PNG\r\n\x1a\n"
    # the calibrated case loads and carries the record as a calibration of the case
    case = load_case_text(mmg["calibrated_case"], "calibrated")
    assert case.calibrations[-1].values["thermal.area_scale"] == pytest.approx(row["value"], rel=1e-6)


def test_defaults_offer_the_case_s_tests_and_record_keys():
    d = logic_calibration.calibration_defaults("ajayi2011_mmg")
    assert d["tests"] == [1, 2, 3, 4, 5, 6]
    assert "tests.*.solids_velocity" in d["parameters"] and "thermal.area_scale" in d["parameters"]
    assert not any(k.startswith("tests.") and k.split(".")[1].isdigit() for k in d["parameters"])


def test_progress_reports_model_runs_and_starts():
    seen = []
    logic_calibration.calibration_view("ajayi2011_mmg", images=False, progress=seen.append, **ARGS)
    assert any(m.startswith("model run ") for m in seen) and "start 1/1" in seen
    assert logic_calibration.progress_fraction("start 1/1") == 1.0
    assert logic_calibration.progress_fraction(seen[0]) is None


@pytest.mark.parametrize("kwargs, match", [
    (dict(parameters=[]), "parameters: choose at least one"),
    (dict(parameters=["a", "b", "c", "d", "e"]), r"parameters: 5 chosen; at most 4 on this page"),
    (dict(parameters=["thermal.area_scale"], starts=9), r"starts = 9 is outside the allowed range \[1, 4\]"),
    (dict(parameters=["thermal.area_scale"], responses=["colour"]), "response 'colour' is not one of"),
])
def test_bad_choices_are_refused(kwargs, match):
    with pytest.raises(ValueError, match=match):
        logic_calibration.calibration_view("ajayi2011_mmg", images=False, **kwargs)


def test_cli_messages_for_the_model_s_refusals():
    """An unknown test or key: the message of ``rotarydryer calibrate``."""
    from rotarydryer.cli import app

    with pytest.raises(ValueError) as exc:
        logic_calibration.calibration_view("ajayi2011_mmg", ["thermal.area_scale"], [9], images=False)
    res = CliRunner().invoke(app, ["calibrate", "ajayi2011_mmg", "-p", "thermal.area_scale", "--tests", "9"])
    assert res.exit_code == 2 and f"error: {exc.value}" in res.output


@pytest.fixture(scope="module")
def new_case_with_tests(tmp_path_factory):
    """A case written by ``rotarydryer new`` with two measured operating points added by the user."""
    from rotarydryer.cli import app

    path = tmp_path_factory.mktemp("new") / "mydryer.toml"
    res = CliRunner().invoke(app, ["new", "mydryer", "--out", str(path)])
    assert res.exit_code == 0, res.output
    text = path.read_text("utf-8")
    base = load_case_text(text, "new")
    f, x = float(base.operating.feed_rate), float(base.operating.feed_moisture)
    from rotarydryer.simulation import Simulation

    s = Simulation(base).steady_state().summary()
    rows = ""
    for i, scale in enumerate((0.9, 1.1), start=1):     # "measured": the model's exhaust +5 K, moisture as run
        rows += (f"\n[[tests]]\ntest = {i}\nfeed_rate = {f * scale!r}\nrpm = {float(base.operating.rpm)!r}\n"
                 f"feed_moisture = {x!r}\ngas_outlet_temperature = {s['gas_outlet_temperature_degC'] + 5.0!r}\n")
    return text + rows


def test_runs_on_a_new_case_with_measured_tests(new_case_with_tests):
    case = logic.stage_case_file(new_case_with_tests.encode("utf-8"))
    d = logic_calibration.calibration_defaults(case)
    assert d["tests"] == [1, 2]
    r = logic_calibration.calibration_view(case, ["thermal.area_scale"], [1, 2], ["gas_outlet_temperature"],
                                           images=False)
    assert r["parameters"][0]["value"] > 0 and len(r["comparison"]) == 2
    assert "appended by rotarydryer calibrate" in r["calibrated_case"]


def test_a_new_case_without_measurements_says_so(tmp_path):
    from rotarydryer.cli import app

    path = tmp_path / "bare.toml"
    assert CliRunner().invoke(app, ["new", "bare", "--out", str(path)]).exit_code == 0
    case = logic.stage_case_file(path.read_bytes())
    with pytest.raises(ValueError, match="has no measured data"):
        logic_calibration.calibration_view(case, ["thermal.area_scale"], images=False)


def test_page_runs_a_calibration_with_progress():
    at = open_app("Calibration", timeout=300)
    assert not at.exception and at.info            # "choose ..., then press Run"
    at.sidebar.multiselect(key="calibration_tests__ajayi2011_mmg").set_value([4, 5]).run()
    at.sidebar.multiselect(key="calibration_params__ajayi2011_mmg").set_value(["thermal.area_scale"]).run()
    at.sidebar.multiselect(key="calibration_responses__ajayi2011_mmg").set_value(
        ["gas_outlet_temperature", "product_moisture"]).run()
    at.button(key="calibration_run").click().run()
    assert not at.exception and not at.error, [e.value for e in at.error]
    assert len(at.table) == 2 and at.table[0].value.iloc[0, 0] == "thermal.area_scale"
    assert len(at.image) == 1
    assert {b.label for b in at.get("download_button")} >= {"Calibration record (TOML)", "Calibrated case file (TOML)"}

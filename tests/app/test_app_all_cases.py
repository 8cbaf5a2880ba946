"""Every page of the web app with every shipped case and a `rotarydryer new` template selected
(Streamlit's AppTest harness, no browser): no exception, no error box, the page's results shown.

Also: the widget bounds come from the case (a case value outside any former fixed limit is
inside its widget), the one failure boundary of the pages, and the limits on heavy runs."""

import threading
import time

import pytest
from typer.testing import CliRunner

pytest.importorskip("streamlit")
pytest.importorskip("xarray")

from rotarydryer.app import _runs, logic  # noqa: E402
from rotarydryer.cases import list_cases  # noqa: E402

from .apptest_support import goto, open_app  # noqa: E402

SHIPPED = ["ajayi2011_mmg", "lee2008_invicta", "song2003_ottawa"]
#: page -> the key of its case selectbox (pages without a case: None)
CASE_PAGES = {"Transport and RTD": "case", "Whole dryer": "dryer_case", "Studies and sensitivity": "studies_case",
              "Control": "control_case", "Calibration": "calibration_case"}
CASE_PICKER_PAGES = ("page_transport", "page_dryer", "page_studies", "page_control", "page_calibration")


def test_every_shipped_case_is_tested():
    assert sorted(list_cases()) == sorted(SHIPPED)


@pytest.fixture(scope="module")
def template_case(tmp_path_factory):
    """A case written by ``rotarydryer new`` (the commented general template), staged as an upload."""
    from rotarydryer.cli import app

    path = tmp_path_factory.mktemp("new") / "mydryer.toml"
    res = CliRunner().invoke(app, ["new", "mydryer", "--out", str(path)])
    assert res.exit_code == 0, res.output
    return path.read_bytes()


def _as_upload(monkeypatch, content: bytes, name: str = "mydryer.toml"):
    """Make every page's case picker return ``content`` as an uploaded case file (AppTest cannot
    drive a file uploader): the staged key, as the real picker does for an upload."""
    import importlib

    def picker(prefix, default="ajayi2011_mmg", cases=None, help_text=None):
        return logic.stage_case_file(content), name

    for mod in CASE_PICKER_PAGES:
        monkeypatch.setattr(importlib.import_module(f"rotarydryer.app.{mod}"), "case_picker", picker)


def _ok(at, where):
    assert not at.exception, (where, [e.value for e in at.exception])
    assert not at.error, (where, [e.value for e in at.error])


def _exercise(at, page, where, buttons=False):
    """Check the page's results are shown; with ``buttons``, also press its run buttons (short
    runs: a sensitivity study of 12 runs, a 20 min closed loop, a quick design search)."""
    if page == "Transport and RTD":
        labels = {m.label for m in at.metric}
        assert {"Total holdup", "Mean residence time H/F", "Fitted outlet mean"} <= labels, where
        assert len(at.image) == 4, where
    elif page == "Whole dryer":
        assert {"Product moisture", "Gas outlet temperature"} <= {m.label for m in at.metric}, where
        assert len(at.image) == 1, where                    # the energy waterfall
        assert len(at.get("vega_lite_chart")) == 3, where   # the interactive profiles
    elif page == "Studies and sensitivity":
        assert at.image, where     # the what-if plot
        if not buttons:
            return
        sens = next(w for w in at.multiselect if w.key.startswith("studies_sens_inputs__"))
        sens.set_value(["gas.inlet_temperature"]).run()
        at.selectbox(key="studies_samples").set_value(4).run()
        at.button(key="studies_run").click().run()
        _ok(at, where)
        assert any(m.label == "Runs (failed)" for m in at.metric), where
    elif page == "Control":
        if not buttons:
            assert at.info, where      # "press Run ..."
            return
        at.number_input(key="control_duration").set_value(1200.0)
        at.number_input(key="control_step_time").set_value(300.0)
        at.checkbox(key="control_open_loop").set_value(False)
        if "template" in where:
            # the template's product leaves bone-dry (1.8e-7 kg/kg): a product-moisture loop is refused there with
            # its reason (nothing to control); its exhaust temperature is what a loop can hold
            at.selectbox(key="control_measured").set_value("exhaust_temperature")
        at.button(key="control_run").click().run()
        _ok(at, where)
        assert any(m.label.startswith("Peak error, closed") for m in at.metric), where
    elif page == "Calibration":
        assert at.info and at.sidebar.multiselect, where     # "press Run ..." and the choices
    elif page == "Design":
        if not buttons:
            assert at.info, where
            return
        at.button(key="design_run").click().run()
        _ok(at, where)
        assert any(m.label == "Diameter D" for m in at.metric), where
    elif page == "Flight geometry":
        assert any(m.label == "Design load (Lee 2008)" for m in at.metric), where
    elif page == "Lab data":
        assert len(at.metric) >= 12, where       # four tabs of examples


@pytest.mark.parametrize("page", list(CASE_PAGES))
@pytest.mark.parametrize("case", SHIPPED)
def test_case_page_with_every_shipped_case(page, case):
    at = open_app(page, timeout=300)
    at.sidebar.selectbox(key=CASE_PAGES[page]).set_value(case).run()
    _ok(at, (page, case))
    _exercise(at, page, (page, case))


@pytest.mark.parametrize("page", list(CASE_PAGES))
def test_case_page_with_a_new_template_upload(page, template_case, monkeypatch):
    _as_upload(monkeypatch, template_case)
    at = open_app(page, timeout=300)
    _ok(at, (page, "template"))
    _exercise(at, page, (page, "template"))


@pytest.mark.parametrize("page", ["Flight geometry", "Design", "Lab data"])
def test_pages_without_a_case(page):
    at = open_app(page, timeout=300)
    _ok(at, page)
    _exercise(at, page, page)


@pytest.mark.slow
@pytest.mark.parametrize("page", ["Studies and sensitivity", "Control"])
@pytest.mark.parametrize("case", [*SHIPPED, "template"])
def test_run_buttons_with_every_case(page, case, template_case, monkeypatch):
    """The sensitivity study and the closed loop (run on a button press) with every case (~2 min)."""
    if case == "template":
        _as_upload(monkeypatch, template_case)
    at = open_app(page, timeout=300)
    if case != "template":
        at.sidebar.selectbox(key=CASE_PAGES[page]).set_value(case).run()
    _ok(at, (page, case))
    _exercise(at, page, (page, case), buttons=True)


def test_design_search_runs():
    at = open_app("Design", timeout=300)
    _exercise(at, "Design", "Design", buttons=True)


def test_transport_widgets_contain_values_beyond_the_former_fixed_limits(monkeypatch):
    """The former limits were feed >= 0.1 kg/s, 0.2 <= rpm <= 20, slope <= 10 deg; a pilot drum
    (Song's, D = 0.305 m, critical speed 77 rev/min) at 0.05 kg/s, 25 rev/min and 12 deg loads
    and runs."""
    from importlib import resources

    text = (resources.files("rotarydryer.cases") / "song2003_ottawa.toml").read_text()
    for key, old, new in (("feed_rate", "0.0835", "0.05"), ("rpm", "5.0", "25.0"), ("slope", "4.745", "12.0")):
        assert f"{key} = {old}" in text, key
        text = text.replace(f"{key} = {old}", f"{key} = {new}", 1)
    staged = logic.stage_case_file(text.encode())
    assert logic.case_defaults(staged) == {"feed_rate": 0.05, "rpm": 25.0, "slope": 12.0}
    _as_upload(monkeypatch, text.encode(), "pilot.toml")
    at = open_app("Transport and RTD", timeout=300)
    assert not at.exception, [e.value for e in at.exception]
    widgets = {w.label: w for w in at.sidebar.number_input}
    for label, v in (("Feed rate (kg/s)", 0.05), ("Speed (rev/min)", 25.0), ("Slope (deg)", 12.0)):
        w = widgets[label]
        assert w.value == pytest.approx(v)
        assert w.min is None or w.min <= v
        assert w.max is None or w.max >= v
    assert widgets["Speed (rev/min)"].max == 60.0     # the schema's (below the critical speed, 77 rev/min)
    assert widgets["Slope (deg)"].max == 45.0


def test_input_range_is_the_schema_range_and_contains_the_value():
    for case in SHIPPED:
        d = logic.case_defaults(case)
        for key, v in (("operating.feed_rate", d["feed_rate"]), ("operating.rpm", d["rpm"]),
                       ("drum.slope", d["slope"])):
            lo, hi = logic.input_range(case, key, v)
            assert (lo is None or lo <= v) and (hi is None or v <= hi), (case, key)
        assert logic.input_range(case, "drum.slope") == (0.0, 45.0)
    # the speed: below the critical speed of the case's drum, 42.3 / sqrt(D) (Invicta: D = 5 m)
    assert logic.input_range("lee2008_invicta", "operating.rpm") == (0.1, pytest.approx(42.3 / 5 ** 0.5))    # the schema's lower end
    assert logic.input_range("song2003_ottawa", "drum.slope", 50.0) == (0.0, 50.0)    # widened to the value
    assert logic.widen(2, 200, 500) == (2, 500) and logic.widen(None, 1.0, -3.0) == (None, 1.0)
    lo, hi = logic.geometry_range("repose_angle", 45.0)
    assert (lo, hi) == (0.0, 90.0)
    assert logic.geometry_range("n_flights", 1500) == (2, 1500)


def test_a_failing_page_shows_one_error_box(monkeypatch):
    """The failure boundary around every page: an exception a page does not catch gives an error
    box with a one-line reason (generic for a bug: no exception text), the sidebar stays."""
    from rotarydryer.app import page_design

    def broken():
        raise RuntimeError("secret detail /etc/passwd")

    monkeypatch.setattr(page_design, "render", broken)
    at = open_app()
    goto(at, "Design")
    assert not at.exception
    assert len(at.error) == 1
    msg = at.error[0].value
    assert "Design" in msg and "internal error (RuntimeError)" in msg and "secret" not in msg and "\n" not in msg
    goto(at, "Flight geometry")      # the app is alive
    _ok(at, "after the failure")

    def bad_input():
        raise ValueError("operating.rpm = 99 rev/min is at or above the critical speed\nsecond line")

    monkeypatch.setattr(page_design, "render", bad_input)
    goto(at, "Design")
    assert not at.exception and "operating.rpm = 99" in at.error[0].value and "\n" not in at.error[0].value


# ------------------------------------------------------------------ limits on heavy runs
def test_one_heavy_run_per_session_and_a_global_bound():
    started, release = threading.Event(), threading.Event()

    def hold(session):
        with _runs.heavy_run(session, slots=slots):
            started.set()
            release.wait(10)

    slots = threading.BoundedSemaphore(2)
    t = threading.Thread(target=hold, args=("s1",))
    t.start()
    assert started.wait(5)
    try:
        with pytest.raises(_runs.RunInProgress, match="a run is already in progress"):
            with _runs.heavy_run("s1", slots=slots, session_wait=0.05):
                pass
        with _runs.heavy_run("s2", slots=slots):          # another session: its own run
            with _runs.heavy_run("s2", slots=slots):      # nested in its own run: not a second one
                pass
            with pytest.raises(_runs.ServerBusy, match="server is busy"):
                with _runs.heavy_run("s3", wait=0.05, slots=slots):    # both slots taken
                    pass
    finally:
        release.set()
        t.join(5)
    with _runs.heavy_run("s1", slots=slots):           # released
        pass
    assert _runs.active_runs() == 0 and not _runs._latest
    assert issubclass(_runs.RunInProgress, ValueError) and issubclass(_runs.ServerBusy, ValueError)


def test_a_session_request_waits_for_its_running_run_and_only_the_newest_waits():
    """A widget change during a run (Streamlit's fast reruns start a new script run at once):
    the new request waits for the running one, then runs; of two waiting, only the newest."""
    slots = threading.BoundedSemaphore(4)
    started, release = threading.Event(), threading.Event()
    order, errors = [], []

    def run(name, hold=False):
        try:
            with _runs.heavy_run("s", slots=slots, session_wait=10):
                order.append(name)
                if hold:
                    started.set()
                    release.wait(10)
        except _runs.RunInProgress:
            errors.append(name)

    first = threading.Thread(target=run, args=("first", True))
    first.start()
    assert started.wait(5)
    older = threading.Thread(target=run, args=("older",))
    older.start()
    time.sleep(0.2)
    newer = threading.Thread(target=run, args=("newer",))
    newer.start()
    time.sleep(0.2)
    release.set()
    for t in (first, older, newer):
        t.join(10)
    assert order == ["first", "newer"] and errors == ["older"]
    assert _runs.active_runs() == 0 and not _runs._latest


def test_second_run_of_a_session_is_refused_on_the_page(monkeypatch):
    """While a session's heavy run is in progress (longer than the session's wait), the page of
    the same session shows the message instead of starting another run (the session id of the
    AppTest run is its own)."""
    monkeypatch.setattr(_runs, "SESSION_WAIT_S", 0.5)
    at = open_app("Flight geometry")
    from rotarydryer.app import page_transport

    seen = {}
    real = page_transport.heavy

    def heavy_spy(session=None):
        from rotarydryer.app._ui import session_id

        seen["sid"] = session_id()
        return real(session)

    monkeypatch.setattr(page_transport, "heavy", heavy_spy)
    goto(at, "Transport and RTD")
    at.sidebar.number_input(key="trpm__lee2008_invicta").set_value(3.17).run()    # not cached: a new run
    assert seen.get("sid"), "no session id in the script run"

    hold, release = threading.Event(), threading.Event()

    def busy():
        with _runs.heavy_run(seen["sid"]):
            hold.set()
            release.wait(30)

    t = threading.Thread(target=busy)
    t.start()
    assert hold.wait(5)
    try:
        at.sidebar.number_input(key="trpm__lee2008_invicta").set_value(3.23).run()
        assert not at.exception
        assert any("a run is already in progress" in e.value for e in at.error), [e.value for e in at.error]
    finally:
        release.set()
        t.join(10)
    t0 = time.monotonic()
    at.sidebar.number_input(key="trpm__lee2008_invicta").set_value(3.29).run()
    _ok(at, "after the run")
    assert time.monotonic() - t0 < 120

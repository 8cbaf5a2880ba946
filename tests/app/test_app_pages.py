"""The web app's pages with their own addresses (``st.navigation``, one ``st.Page`` per page),
through Streamlit's headless AppTest harness: every page opens by its page file, the widgets'
values and the session survive a visit to another page, the transport page's tracer fit starts
on the chosen case's own data set, and the long runs show a progress box (control, design,
what-if) whose fraction follows the services' progress messages."""

import pytest

pytest.importorskip("streamlit")
pytest.importorskip("xarray")

from rotarydryer.app import PAGES, _runs, logic, logic_control, logic_design  # noqa: E402

from .apptest_support import goto, open_app  # noqa: E402

#: page title -> its title on the page
HEADINGS = {"Flight geometry": "Flight geometry explorer", "Transport and RTD": "Solids transport and residence time",
            "Whole dryer": "Whole dryer", "Studies and sensitivity": "Studies and sensitivity",
            "Design": "Size a dryer for a duty", "Control": "Control: closed loop on the dynamic model",
            "Calibration": "Calibration: fit case keys to the plant data", "Lab data": "Laboratory data"}


def test_every_page_has_its_own_address():
    assert [url for _, url, _ in PAGES.values()] == ["geometry", "transport", "whole_dryer", "studies", "design",
                                                    "control", "calibration", "lab"]
    assert list(PAGES) == list(HEADINGS)
    at = open_app(timeout=300)
    assert [t.value for t in at.title] == ["Flight geometry explorer"]          # the landing page
    for title in ("Design", "Lab data", "Flight geometry", "Control", "Calibration"):
        goto(at, title)
        assert not at.exception, (title, [e.value for e in at.exception])
        assert [t.value for t in at.title] == [HEADINGS[title]]                # only this page's widgets


def test_widget_values_and_the_session_survive_another_page():
    at = open_app("Transport and RTD", timeout=300)
    at.sidebar.selectbox(key="case").set_value("ajayi2011_mmg").run()
    at.sidebar.number_input(key="trpm__ajayi2011_mmg").set_value(4.0).run()
    at.session_state["kept_by_the_session"] = 1
    goto(at, "Flight geometry")
    at.sidebar.selectbox(key="preset").set_value("ajayi_pilot").run()
    goto(at, "Transport and RTD")
    assert not at.exception and not at.error
    assert at.sidebar.selectbox(key="case").value == "ajayi2011_mmg"
    assert at.sidebar.number_input(key="trpm__ajayi2011_mmg").value == pytest.approx(4.0)
    goto(at, "Flight geometry")
    assert at.sidebar.selectbox(key="preset").value == "ajayi_pilot"
    assert at.session_state["kept_by_the_session"] == 1


# ------------------------------------------------------------------ the tracer fit follows the case
def test_case_tracer_data_set():
    assert logic.case_tracer_dataset("ajayi2011_mmg") == "ajayi2011_test4"      # tracer.dataset, test 4
    assert logic.case_tracer_dataset("lee2008_invicta") == "lee2008_invicta"
    assert logic.case_tracer_dataset("song2003_ottawa") == logic.tracer_sources()[0]   # none: the first


def test_transport_tracer_default_follows_the_case():
    at = open_app("Transport and RTD", timeout=300)
    assert at.selectbox(key="tracer_source__lee2008_invicta").value == "lee2008_invicta"
    assert any("published curve lee2008_invicta" in c.value for c in at.caption)
    at.sidebar.selectbox(key="case").set_value("ajayi2011_mmg").run()
    assert not at.exception and not at.error
    assert at.selectbox(key="tracer_source__ajayi2011_mmg").value == "ajayi2011_test4"
    assert any("published curve ajayi2011_test4" in c.value for c in at.caption)
    at.selectbox(key="tracer_source__ajayi2011_mmg").set_value("ajayi2011_test2").run()
    at.sidebar.selectbox(key="case").set_value("lee2008_invicta").run()
    assert at.selectbox(key="tracer_source__lee2008_invicta").value == "lee2008_invicta"
    at.sidebar.selectbox(key="case").set_value("ajayi2011_mmg").run()       # the visitor's choice kept
    assert at.selectbox(key="tracer_source__ajayi2011_mmg").value == "ajayi2011_test2"


# ---------------------------------------------------------------------------- progress of long runs
def test_control_progress_fraction_rises_through_the_stages():
    msgs = ["steady state ...", "identification: step of gas_inlet_temperature",
            "identification: step of feed_rate", "identification: step of feed_moisture_dry",
            "closed loop: t = 0 / 7200 s, product_moisture = 0.1312",
            "feed-forward: steady state for feed moisture 0.1894, feed rate 40.67 kg/s",
            "closed loop: t = 6600 / 7200 s, product_moisture = 0.1365",
            "open loop: t = 0 / 7200 s, product_moisture = 0.1312", "open loop: t = 7200 / 7200 s, x = 1"]
    f = [logic_control.progress_fraction(m) for m in msgs]
    assert f[5] is None
    known = [x for x in f if x is not None]
    assert known == sorted(known) and known[0] == 0.0 and known[-1] == 1.0
    assert logic_control.progress_fraction("closed loop: t = 7200 / 7200 s", open_loop=False) == 1.0


def test_design_progress_fraction():
    assert logic_design.progress_fraction("design: generation 5/20, 40 evaluations, 3 feasible, best volume 9") \
        == pytest.approx(0.225)
    assert logic_design.progress_fraction("design: local refinement (Nelder-Mead)") == 0.9
    assert logic_design.progress_fraction("verification 1: coupled heat-and-mass steady state") is None


def test_logic_views_pass_the_progress_callback():
    seen = []
    logic_design.design_view("raw_sugar", effort="quick", images=False, progress=seen.append)
    assert any(m.startswith("design: generation") for m in seen)
    seen.clear()
    logic_control.control_view("ajayi2011_mmg", images=False, duration=1200.0, sample_time=120.0, open_loop=False,
                               progress=seen.append)
    assert seen[0].startswith("steady state") and any(m.startswith("closed loop") for m in seen)


def test_kept_results_are_bounded_newest_first():
    k = _runs.Kept(2)
    k.put("a", 1)
    k.put("b", 2)
    assert k.get("a") == 1          # a is now the newest
    k.put("c", 3)
    assert k.get("b") is None and k.get("a") == 1 and k.get("c") == 3
    k.clear()
    assert k.get("a") is None


def test_control_and_design_pages_show_a_progress_box():
    from rotarydryer.app import page_control, page_design

    page_control._KEPT.clear()          # other tests of this process may have kept these runs
    page_design._KEPT.clear()
    at = open_app("Control", timeout=300)
    at.number_input(key="control_duration").set_value(1200.0)
    at.number_input(key="control_sample_time").set_value(120.0)
    at.checkbox(key="control_open_loop").uncheck()
    at.button(key="control_run").click().run()
    assert not at.exception and not at.error
    labels = [s.label for s in at.status]
    assert len(labels) == 1 and labels[0].startswith("Steady state, step-response identification, closed loop done in")
    at.run()                                            # the same inputs: the kept run, no new box
    assert not at.status and any(m.label == "Peak error, closed (pp)" for m in at.metric)
    goto(at, "Design")
    at.button(key="design_run").click().run()
    assert not at.exception and not at.error
    assert [s.label.startswith("Differential-evolution search done in") for s in at.status] == [True]
    assert any(m.label == "Diameter D" for m in at.metric)

"""Web app pages "Design" and "Control": their logic against the library, the CLI's messages,
and the pages through Streamlit's headless AppTest harness (short runs: a quick search, 20-30 min
of simulated time)."""

import re

import pytest
from typer.testing import CliRunner

pytest.importorskip("streamlit")


from rotarydryer.app import logic_control, logic_design  # noqa: E402

from .apptest_support import open_app  # noqa: E402

runner = CliRunner()


def _cli_error(cli, args):
    res = runner.invoke(cli, args)
    assert res.exit_code == 2, res.output
    m = re.search(r"error: (.*)", res.output, re.S)
    assert m, res.output
    return " ".join(m.group(1).split())


def _metric(at, label):
    return next(m for m in at.metric if m.label == label).value


def _page(name):
    return open_app(name, timeout=240)


# ------------------------------------------------------------------------------------------- design
def test_design_logic_equals_library():
    from rotarydryer import design as D

    r = logic_design.design_view("raw_sugar", effort="quick", images=False)
    maxiter, popsize = logic_design.SEARCH_EFFORT["quick"]
    lib = D.design(D.raw_sugar_duty(), D.Limits(), maxiter=maxiter, popsize=popsize, top=8)
    assert r["best"] == lib.best.row()
    assert r["binding"] == lib.best.binding() and r["binding"]
    assert [c[0] for c in r["constraints"]] == list(lib.best.constraints)
    assert len(r["table"]) == len(lib.table(8))


def test_design_logic_defaults_are_the_cli_presets():
    from rotarydryer import design as D

    d = logic_design.duty_defaults("mmg")
    m = D.mmg_duty()
    assert (d["material"], d["feed"], d["moisture_in"], d["gas_flow"]) == (m.material, m.feed_rate, m.moisture_in,
                                                                          m.gas_flow)


@pytest.mark.parametrize("kwargs, args", [
    (dict(fill_max=0.9), ["--fill-max", "0.9"]),
    (dict(moisture_out=0.02), ["--moisture-out", "0.02"]),
    (dict(ld_min=8.0, ld_max=6.0), ["--ld-min", "8", "--ld-max", "6"]),
    (dict(d_max=1.5), ["--d-max", "1.5", "--no-verify"]),     # infeasible duty: names the blocking constraint
])
def test_design_logic_bad_value_gives_the_cli_message(cli, kwargs, args):
    with pytest.raises(ValueError) as exc:
        logic_design.design_view("raw_sugar", images=False, **kwargs)
    msg = str(exc.value)
    if "infeasible" in msg:   # the app's quick search and the CLI's full one end at other least-infeasible designs
        assert "blocking constraint 'gas entrainment'" in msg
        assert "blocking constraint 'gas entrainment'" in _cli_error(cli, ["design", "--duty", "raw_sugar"] + args)
    else:
        assert _cli_error(cli, ["design", "--duty", "raw_sugar"] + args) == " ".join(msg.split())


def test_design_page_runs_and_updates():
    at = _page("Design")
    assert at.info and not at.metric                      # nothing is searched before the button
    at.button(key="design_run").click().run()
    assert not at.exception, [e.value for e in at.exception]
    d0 = _metric(at, "Diameter D")
    assert d0.endswith(" m") and len(at.image) == 1
    at.number_input(key="design_gas_flow__raw_sugar").set_value(40.0).run()
    assert _metric(at, "Diameter D") == d0                # shown: the last search until pressed
    at.button(key="design_run").click().run()
    assert not at.exception
    assert float(_metric(at, "Diameter D").split()[0]) > float(d0.split()[0])   # more gas: wider (entrainment)
    # an infeasible duty: the CLI's message, no traceback
    at.number_input(key="design_d_max").set_value(1.5).run()
    at.button(key="design_run").click().run()
    assert not at.exception
    assert at.error and "blocking constraint" in at.error[0].value


# ------------------------------------------------------------------------------------------- control
SHORT = dict(duration=1200.0, sample_time=120.0)


def test_control_logic_equals_library():
    from rotarydryer import control as C
    from rotarydryer.simulation import Simulation

    r = logic_control.control_view("ajayi2011_mmg", {"operating.test": 4}, images=False, **SHORT)
    sim = Simulation("ajayi2011_mmg", {"operating.test": 4})
    sim.transport_steady_state()
    steady = sim.thermal_steady_state()
    cfg = C.ControlConfig(sample_time_s=120.0).validate()
    models = C.identify(steady.dryer, steady)
    kw = dict(scenario="feed_moisture_step", magnitude=0.2, t_end_s=1200.0, t_step_s=600.0, config=cfg)
    closed = C.closed_loop(steady.dryer, steady, models=models, **kw)
    opened = C.closed_loop(steady.dryer, steady, models=models, controlled=False, **kw)
    assert r["performance"] == closed.performance
    assert r["open"] == opened.performance
    assert r["tuning"]["kc"] == closed.tuning["kc"]
    assert r["csv"].splitlines()[0].startswith("time_s,")


@pytest.mark.parametrize("kwargs, args", [
    (dict(duration=600.0, sample_time=900.0), ["--duration", "600", "--sample-time", "900"]),
    (dict(duration=300.0), ["--duration", "300", "--step-time", "600"]),
    (dict(scenario="fouling_ramp", magnitude=1.5), ["--scenario", "fouling_ramp", "--magnitude", "1.5"]),
    (dict(gas_t_max=700.0), ["--gas-t-max", "700"]),
    (dict(product_temperature_band=(50.0, 40.0)), ["--product-temperature-band", "50,40"]),
])
def test_control_logic_bad_value_gives_the_cli_message(cli, kwargs, args):
    kwargs = dict(dict(step_time=600.0), **kwargs)
    with pytest.raises(ValueError) as exc:
        logic_control.control_view("ajayi2011_mmg", images=False, **kwargs)
    assert _cli_error(cli, ["control", "ajayi2011_mmg"] + args) == " ".join(str(exc.value).split())


def test_control_cases_have_the_thermal_model():
    assert "ajayi2011_mmg" in logic_control.thermal_cases()
    assert logic_control.control_defaults("ajayi2011_mmg")["tests"] == [1, 2, 3, 4, 5, 6]


def test_control_page_runs_and_updates():
    at = _page("Control")
    assert at.info and not at.metric
    at.number_input(key="control_duration").set_value(SHORT["duration"])
    at.number_input(key="control_sample_time").set_value(SHORT["sample_time"])
    at.checkbox(key="control_open_loop").uncheck()
    at.button(key="control_run").click().run()
    assert not at.exception, [e.value for e in at.exception]
    before = _metric(at, "Peak error, closed (pp)")
    assert len(at.image) == 1
    at.number_input(key="control_magnitude").set_value(0.1).run()
    at.button(key="control_run").click().run()
    assert not at.exception
    after = _metric(at, "Peak error, closed (pp)")
    assert after != before                                          # another disturbance
    assert any("Within the tolerance" in m.value for m in at.markdown)
    assert any("IAE closed loop " in m.value and " pp s" in m.value for m in at.markdown)    # as the peak error
    at.checkbox(key="control_moisture_max_on").check().run()        # the product's specification
    at.button(key="control_run").click().run()
    assert not at.exception
    assert any("product within specification: moisture at most 12 %" in m.value for m in at.markdown)
    # a step time after the end: the CLI's message
    at.number_input(key="control_duration").set_value(300.0).run()
    at.button(key="control_run").click().run()
    assert at.error and "--step-time = 600 s is outside the allowed range" in at.error[0].value


def test_the_control_page_shows_every_warning_of_the_run():
    """The control page kept the controller's own warnings only: a run outside a law's calibration (Song's sand,
    calibrated dry, fed moist) warned in the CLI and reached only the server's log. Every warning of the run is
    shown now, each once (`logic.run_warnings`, as the dryer page)."""
    r = logic_control.control_view("song2003_ottawa", images=False, open_loop=False, **SHORT)
    assert any("outside the conditions the coefficients" in w for w in r["warnings"]), r["warnings"]
    assert len(r["warnings"]) == len(set(r["warnings"]))

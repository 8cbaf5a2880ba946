"""Issue 27 item 2: one heat-and-mass model, reused when only parameter values change."""

import warnings

import numpy as np
import pytest

from rotarydryer import Simulation
from rotarydryer.cases import load_case
from rotarydryer.cases.build import PARAMETER_KEYS, changed_keys, takes_as_parameters

#: Song's case with its fitted-step settings (its default, the predictive law, rebuilds on a speed or gas
#: change: test_the_predictive_law_rebuilds_on_speed_and_gas)
CASES = {"ajayi2011_mmg": {"operating.test": 4}, "lee2008_invicta": {},
         "song2003_ottawa": {"transport.parameter_source": "per_test"}}


def _sim(case, ov):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return Simulation(case, ov)


@pytest.fixture(scope="module", params=list(CASES))
def source(request):
    sim = _sim(request.param, CASES[request.param])
    return request.param, sim, sim.steady_state().warm_data()


@pytest.mark.parametrize("key, factor", [("operating.feed_rate", 1.05), ("operating.rpm", 0.9),
                                         ("gas.flow", 1.07), ("thermal.area_scale", 1.1),
                                         ("operating.feed_temperature", 1.1)])
def test_a_parameter_change_reuses_the_model_and_gives_the_fresh_state(source, key, factor):
    case, src, warm = source
    base = CASES[case]
    st, (F, rpm) = src.thermal_settings(), (src.dryer().feed_rate, src.dryer().rpm)
    now = {"operating.feed_rate": F, "operating.rpm": rpm, "gas.flow": st.gas_flow,
           "thermal.area_scale": max(st.area_scale, 0.5), "operating.feed_temperature": st.solids_inlet_temperature}
    ov = {**base, key: now[key] * factor}
    reused_sim = _sim(case, ov)
    reused = reused_sim.steady_state(warm=warm)
    assert reused_sim.dryer().model is src.dryer().model          # no network built
    fresh = _sim(case, ov).steady_state(warm={k: v for k, v in warm.items() if k != "simulation"})
    np.testing.assert_allclose(reused.thermal.state, fresh.thermal.state, rtol=1e-10, atol=1e-12)
    a, b = reused.summary(), fresh.summary()
    for name in ("total_holdup_kg", "product_moisture_kg_kg", "gas_outlet_temperature_degC", "tracer_mean_s"):
        assert a[name] == pytest.approx(b[name], rel=1e-10)
    # the source run's own state is untouched by the reuse
    assert src.steady_state().thermal.dryer.feed_rate == F


def test_structural_changes_build_a_new_model(source):
    case, src, warm = source
    for ov in ({"transport.fouling": 0.3}, {"thermal.mode": "ajayi2011"}, {"transport.unflighted_cells": 40}):
        sim = _sim(case, {**CASES[case], **ov})
        assert not takes_as_parameters(src.case, sim.case)
        sim.steady_state(warm=warm)
        assert sim.dryer().model is not src.dryer().model


def test_which_changes_are_parameters():
    mmg = load_case("ajayi2011_mmg")
    keys = changed_keys(mmg, load_case("ajayi2011_mmg", {"gas.flow": 17.0}))
    # a --set gas.flow replaces the tests' calibrated gas flows: parameters all
    assert keys[0] == "gas.flow" and all(k.startswith("tests.") and k.endswith(".gas_flow") for k in keys[1:])
    assert takes_as_parameters(mmg, load_case("ajayi2011_mmg", {"gas.flow": 17.0}))
    assert takes_as_parameters(mmg, load_case("ajayi2011_mmg", {"shell.insulation_thickness": 0.05}))
    assert not takes_as_parameters(mmg, load_case("ajayi2011_mmg", {"operating.test": 3}))   # a new test row
    # the predictive law's velocities depend on the operating point; the trajectory step on the gas
    pred = load_case("ajayi2011_mmg", {"operating.test": 1, "transport.parameter_source": "predictive"})
    assert not takes_as_parameters(pred, load_case("ajayi2011_mmg", {
        "operating.test": 1, "transport.parameter_source": "predictive", "operating.feed_rate": 30.0}))
    traj = {"transport.forward_step": "trajectory", "transport.n_cells": 20, "transport.kiln_time": 9.0,
            "transport.backmix": 0.5}
    assert not takes_as_parameters(load_case("lee2008_invicta", traj),
                                   load_case("lee2008_invicta", {**traj, "gas.flow": 25.0}))
    assert "transport.fouling" not in PARAMETER_KEYS        # the design loads of the specs carry it


def test_a_bad_value_on_the_reuse_path_is_refused_as_on_a_fresh_run(source):
    case, src, warm = source
    critical = 42.3 / (2 * src.case.drum.radius) ** 0.5
    if critical >= 60:
        pytest.skip("the pilot drum's critical speed is above the schema's 60 rev/min")
    sim = _sim(case, {**CASES[case], "operating.rpm": 59.0})      # above the drum's critical speed
    with pytest.raises(ValueError, match="operating.rpm = 59 rev/min"):
        sim.steady_state(warm=warm)


def test_a_reused_model_reports_its_cells_at_its_own_speed():
    per_test = CASES["song2003_ottawa"]
    src = _sim("song2003_ottawa", {**per_test, "operating.rpm": 5.0})
    warm = src.steady_state().warm_data()
    reused = _sim("song2003_ottawa", {**per_test, "operating.rpm": 7.5}).steady_state(warm=warm)
    fresh = _sim("song2003_ottawa", {**per_test, "operating.rpm": 7.5}).steady_state()
    a, b = reused.state.cell_info["passive_time_s"], fresh.state.cell_info["passive_time_s"]
    np.testing.assert_allclose(a, b, rtol=1e-9)


def test_the_predictive_law_rebuilds_on_speed_and_gas():
    """Song's default (the predictive law): the cascade kilning follows the speed and the trajectory step
    the gas, so those changes build a new model; a feed change reuses it and gives the fresh state."""
    src = _sim("song2003_ottawa", {})
    st = src.steady_state()
    warm = st.warm_data()
    for key, value in (("operating.rpm", 6.0), ("gas.flow", 0.15)):
        sim = _sim("song2003_ottawa", {key: value})
        assert sim.dryer() is not src.dryer(), key
    sim = _sim("song2003_ottawa", {"operating.feed_rate": 0.09})
    reused = sim.steady_state(warm=warm)
    fresh = _sim("song2003_ottawa", {"operating.feed_rate": 0.09}).steady_state()
    assert reused.summary()["mean_residence_time_s"] == pytest.approx(fresh.summary()["mean_residence_time_s"],
                                                                      rel=1e-7)

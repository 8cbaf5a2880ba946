"""The predictive transport law as case keys (issue 29): transport.parameter_source = "predictive".

Every expected number is computed here from the law's definition or the shipped data; the
published residence times come from the cases' [[tests]] rows and the package CSVs.
"""

from __future__ import annotations

import json
import math
import warnings
from importlib import resources

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from rotarydryer import Simulation
from rotarydryer.cases import load_case
from rotarydryer.cases.build import law_coefficient, material_of, predictive_range
from rotarydryer.cases.calibration import CalibrationWarning, PredictiveRangeWarning
from rotarydryer.cli import app
from rotarydryer.properties.materials import load_material
from rotarydryer.published import read_published_csv
from rotarydryer.studies import predictive_transport as pt

runner = CliRunner()
TEMPLATE = str(resources.files("rotarydryer.cases") / "templates" / "dryer.toml")
PRED = {"transport.parameter_source": "predictive"}


def steady(case, **ov):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return Simulation(case, ov).transport_steady_state()


# ---- the law ----------------------------------------------------------------------------------------
def test_cascade_kiln_rate_is_the_flight_borne_speed():
    """kiln_law = "cascade": 1/t_kiln = c_0 h_m sin(theta) / ((t_p + t_a) dL) in every cell, at the design
    load (Lee (2008) Eq. 3.3-3.9 with C_F^G = c_0)."""
    ss = steady("song2003_ottawa", **{"operating.test": 49})
    m = ss.model
    info = m.cell_info
    fam = next(f for f in m.network.families if f.name == "kiln")
    spec = m.specs[0]
    c0 = spec.gas.step_factor
    dl = spec.length / spec.n_cells
    want = c0 * info["fall_height_m"] * math.sin(math.radians(m.parameters["slope"])) / (
        (info["passive_time_s"] + info["fall_time_s"]) * dl)
    np.testing.assert_allclose(np.asarray(fam.rate, float), want, rtol=1e-10)
    assert c0 == pytest.approx(load_case("song2003_ottawa").transport.step_factor, rel=1e-12)


def test_without_gas_the_step_is_the_step_factor():
    """No gas: the trajectory step is c_0 h_m sin(theta), C_F^G = c_0 in every cell."""
    ss = steady("song2003_ottawa", **{"operating.test": 1})      # Song's first run, no air
    np.testing.assert_allclose(ss.model.cell_info["C_F_G"], law_coefficient(load_case("song2003_ottawa"),
                                                                           "step_factor"), rtol=1e-9)


@settings(max_examples=8, deadline=None)
@given(gas=st.floats(5.0, 60.0), rpm=st.floats(1.5, 5.0))
def test_two_cell_reach_conserves_mass_and_tracer(gas, rpm):
    """A counter-current cascade may reach two cells (Invicta at low speed, strong gas): mass balance,
    outflow = feed, tracer recovery 1, and the mean step of the split equals the trajectory step."""
    try:
        ss = steady("lee2008_invicta", **PRED, **{"gas.flow": gas, "operating.rpm": rpm})
    except ValueError as exc:       # refused up front with its reason (fill, entrainment, a step beyond 2 cells)
        assert any(k in str(exc) for k in ("gas.flow", "fill", "transport.n_cells")), str(exc)
        return
    assert ss.mass_balance_error < 1e-9
    assert ss.outlet_flow == pytest.approx(ss.model.feed_rate, rel=1e-9)
    sysm = ss.tracer_system()
    assert sysm.moments(ss.model.tracer_input)["recovery"] == pytest.approx(1.0, abs=1e-9)
    law = next(f.law for f in ss.model.network.families if f.name == "discharge")
    c = law.cascade(np.asarray(ss.model.cell_info["repose_angle_deg"]), np.ones(law.n))
    x = (c["CF"] + 2 * c.get("CF2", 0.0) - c["CB"] + 0 - 2 * c.get("CB2", 0.0)) * law.dl
    np.testing.assert_allclose(x, np.clip(c["step_free"], -2 * law.dl, 2 * law.dl), atol=1e-12)
    assert np.all(c["CR"] >= -1e-12)


def test_law_coefficients_precedence():
    """transport.<key> wins, else the calibration record, else the material class, else neutral."""
    inv = load_case("lee2008_invicta", PRED)
    rec = next(r for r in inv.calibrations if r.configuration.get("transport.parameter_source") == "predictive")
    assert law_coefficient(inv, "step_factor") == pytest.approx(rec.values["transport.step_factor"])
    assert law_coefficient(load_case("lee2008_invicta", {**PRED, "transport.step_factor": 1.7}), "step_factor") == 1.7
    tpl = load_case(TEMPLATE, PRED)           # no record: the sand's class value
    sand = load_material("ottawa_sand_song2003")
    assert law_coefficient(tpl, "step_factor") == sand.transport_coefficient("step_factor")
    # per_test runs never take the material's predictive coefficients
    assert law_coefficient(load_case(TEMPLATE), "step_factor") == 1.0
    assert law_coefficient(load_case(TEMPLATE), "curtain_coefficient") == 1.546


def test_a_record_of_the_other_law_is_not_used_and_not_warned():
    """The Invicta predictive record (step_factor, curtain_coefficient) is not applied to the default
    (fitted) run, and neither run warns."""
    for ov in ({}, PRED):
        with warnings.catch_warnings():
            warnings.simplefilter("error", CalibrationWarning)
            warnings.filterwarnings("ignore", category=PredictiveRangeWarning)
            c = load_case("lee2008_invicta", ov)
        assert (c.transport.step_factor is None) == (ov == {})


# ---- acceptance: trends --------------------------------------------------------------------------
def test_song_speed_ratio_and_flat_feed():
    """Song's no-gas series from the case: tau(8 rpm)/tau(3 rpm) within 15 % of the measured ratio, and a
    feed response within +-10 % over Song's feeds (3.1-15.3 kg/min)."""
    r = pt.song_speed_feed()
    assert 0.3 < r["speed_ratio_measured"] < 0.45        # Song: 9.0 -> 3.46 min
    assert r["speed_ratio_model"] == pytest.approx(r["speed_ratio_measured"], rel=0.15)
    assert r["feed_spread_model_pct"] <= 10.0 and r["n_feed_runs"] >= 10


def test_song_default_case_speed_ratio_from_the_cli():
    """The shipped case at Song's no-gas conditions: the CLI's MRT at 8 and 3 rpm."""
    out = {}
    for n in (3, 8):
        res = runner.invoke(app, ["rtd", "song2003_ottawa", "--set", "gas.flow=0", "--set", "thermal.enabled=false",
                                  "--set", f"operating.rpm={n}", "--set", "operating.feed_moisture=0", "--json"])
        assert res.exit_code == 0, res.output
        out[n] = json.loads(res.stdout)["mean_residence_time_s"]
    rows = [r for r in read_published_csv("song_appendixA_mrt.csv") if float(r["Ori_G_m3_s"]) == 0.0
            and float(r["slope_m_m"]) == 0.083]
    meas = {n: np.mean([float(r["tau_min"]) for r in rows if float(r["n_rpm"]) == n]) for n in (3, 8)}
    assert out[8] / out[3] == pytest.approx(meas[8] / meas[3], rel=0.15)


def test_invicta_mrt_falls_with_speed_in_predictive_mode():
    tau = [steady("lee2008_invicta", **PRED, **{"operating.rpm": n}).mean_residence_time for n in (1.5, 3.0, 5.0)]
    assert tau[2] < tau[1] < tau[0]
    # the fitted configuration keeps Lee's rising MRT (his C_B > C_F; Table 7.3 reproduced as shipped)
    fitted = [steady("lee2008_invicta", **{"operating.rpm": n}).mean_residence_time for n in (1.5, 5.0)]
    assert fitted[1] > fitted[0]


@pytest.mark.parametrize("case", ["song2003_ottawa", "lee2008_invicta", "ajayi2011_mmg", TEMPLATE],
                         ids=["song", "invicta", "mmg", "template"])
def test_predictive_works_on_every_case(case):
    ov = {**PRED, "thermal.enabled": False}
    if case == "ajayi2011_mmg":
        ov["operating.test"] = 4
    ss = steady(case, **ov)
    assert ss.mass_balance_error < 1e-9 and 0 < ss.mean_residence_time < 1e5


# ---- acceptance: Song from the case keys, cross-validated --------------------------------------
def test_song_in_sample_error_of_the_shipped_record():
    runs = pt.song_runs()
    assert len(runs) == 73
    tau = pt.song_predict({}, [r.test for r in runs])
    e = pt.error_stats(tau, [r.mrt_s for r in runs])
    assert e["mae_pct"] < 5.0 and e["max_pct"] < 20.0


@pytest.mark.slow
def test_song_cross_validation_out_of_sample():
    """Calibrated on each half (and on the 53 base runs) with calibrate(), predicted on the other."""
    from rotarydryer.estimation.calibrate import calibrate

    runs = pt.song_runs()
    sp = pt.song_splits(runs)
    cal = {}
    for name in ("odd", "even", "base"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            c = calibrate("song2003_ottawa", list(pt.SONG_KEYS), tests=sp[name], responses=["mrt"])
        cal[name] = {k: c.fit.parameters[k].value for k in pt.SONG_KEYS}
    cv = pt.song_cross_validation(cal)
    assert cv["odd/even"]["mae_pct"] <= 5.0
    assert cv["base->other"]["mae_pct"] <= 7.0 and cv["base->other"]["n"] == 20


# ---- bad input ---------------------------------------------------------------------------------
def test_entraining_counter_current_gas_is_refused():
    res = runner.invoke(app, ["rtd", "lee2008_invicta", "--set", "transport.parameter_source=predictive",
                              "--set", "gas.flow=200"])
    assert res.exit_code == 2
    msg = res.output.strip().splitlines()[-1]
    assert "gas.flow = 200 kg/s" in msg and "terminal velocity" in msg and "allowed range is gas.flow <" in msg


def test_outside_the_calibrated_range_warns_naming_the_quantity():
    with pytest.warns(PredictiveRangeWarning, match=r"drum speed 5 rev/min where every run of the calibration had 3 rev/min.*Froude"):
        steady_raw = Simulation("lee2008_invicta", {**PRED, "operating.rpm": 5.0})
        steady_raw.transport_steady_state()
    with warnings.catch_warnings():
        warnings.simplefilter("error", PredictiveRangeWarning)
        Simulation("song2003_ottawa", {"operating.test": 49}).transport_steady_state()     # inside Song's runs
    case = load_case("ajayi2011_mmg", {**PRED, "operating.test": 2})
    assert any(p.startswith("feed moisture 0.186") for p in predictive_range(case, 0.09))


def test_material_transport_table_is_checked():
    with pytest.raises(ValueError, match=r"material\.transport\.stepfactor is not a field"):
        material_of(load_case(TEMPLATE, {"material.transport": {"stepfactor": 2.0}}))
    with pytest.raises(ValueError, match=r"material\.transport\.calibrated_rpm = \[5, 3\]"):
        material_of(load_case(TEMPLATE, {"material.transport": {"calibrated_rpm": [5, 3]}}))
    with pytest.raises(ValueError, match=r"material\.transport\.step_factor = -1"):
        material_of(load_case(TEMPLATE, {"material.transport": {"step_factor": -1}}))


# ---- the test rows' slope ----------------------------------------------------------------------
def test_a_test_row_sets_the_slope_and_set_drum_slope_wins():
    row = next(t for t in load_case("song2003_ottawa").tests if t.test == 67)
    assert load_case("song2003_ottawa", {"operating.test": 67}).drum.slope == pytest.approx(row.slope)
    assert load_case("song2003_ottawa", {"operating.test": "67", "drum.slope": 5.0}).drum.slope == 5.0
    assert math.tan(math.radians(row.slope)) == pytest.approx(0.067, rel=1e-6)


def test_the_calibration_point_is_inside_its_own_ranges():
    """Invicta at its calibration point warned "Froude number 0.02516 outside [0.0252, 0.0252]" and "feed moisture
    0.01961 outside [0.0196, 0.0196]": the material gives the ranges to three figures."""
    from rotarydryer.cases import load_case
    from rotarydryer.cases.build import predictive_range

    case = load_case("lee2008_invicta", {"transport.parameter_source": "predictive"})
    assert predictive_range(case, 0.0691) == []
    out = predictive_range(load_case("lee2008_invicta", {"transport.parameter_source": "predictive",
                                                         "operating.rpm": 3.1}), 0.0691)
    assert any(p.startswith("drum speed 3.1 rev/min where every run of the calibration had 3 rev/min") for p in out)

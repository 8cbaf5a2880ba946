"""Lee (2008) compartment model: Ch. 7 acceptance (Tables 7.3, 7.5, 7.7, 7.9) and properties."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.transport import (
    NoSteadyStateError,
    TracerInput,
    lee2008,
    lee2008_repose_profile,
    sheehan2005_model1,
    sheehan2005_model2,
)

from .conftest import FEED, invicta, read_csv


def model(regressions, table_7_2, N=35, **kw):
    p = dict(table_7_2[N])
    p.update(kw)
    return lee2008(geometry=regressions, **invicta(N, **p))


@pytest.mark.parametrize("row", read_csv("lee_rtd_moments.csv")[1:], ids=lambda r: r["rtd"])
def test_table_7_3_rtd_moments(row, regressions, table_7_2):
    N = int(row["rtd"].split("=")[1])
    ss = model(regressions, table_7_2, N).steady_state()
    rtd = ss.rtd(simulate=False)  # default input: Lee's 39.6 s pulse, times from injection start
    assert rtd.tracer_mean / 60 == pytest.approx(float(row["mean_residence_time_min"]), rel=0.015)
    assert rtd.tracer_std / 60 == pytest.approx(float(row["standard_deviation_min"]), rel=0.03)
    # the RTD itself (impulse response) has mean = holdup / flow; the pulse adds half its width
    assert rtd.mean_residence_time == pytest.approx(ss.total_holdup / FEED, rel=1e-9)
    assert rtd.tracer_mean - rtd.mean_residence_time == pytest.approx(39.6 / 2, rel=1e-6)


@pytest.mark.parametrize("row", read_csv("lee_first_cell_flowrates_vs_N.csv"), ids=lambda r: r["N"])
def test_table_7_5_first_cell_flows(row, regressions, table_7_2):
    ss = model(regressions, table_7_2, int(row["N"])).steady_state()
    assert ss.flow("kiln")[0] == pytest.approx(float(row["kilning_flowrate"]), rel=0.02)
    assert ss.flow("forward")[0] == pytest.approx(float(row["forward_flowrate"]), rel=0.02)
    assert ss.flow("backmix")[0] == pytest.approx(float(row["backmix_flowrate"]), rel=0.02)


@pytest.mark.parametrize("row", read_csv("lee_response_feed_rate.csv"), ids=lambda r: r["feed_rate_pct_of_normal"])
def test_table_7_9_feed_rate(row, regressions, table_7_2):
    feed = FEED * float(row["feed_rate_pct_of_normal"]) / 100
    ss = model(regressions, table_7_2, 35, repose_angle=40.0, feed_rate=feed).steady_state()
    assert ss.passive_holdup == pytest.approx(float(row["total_passive_holdup_kg"]), rel=0.02)
    assert ss.flow("kiln")[0] == pytest.approx(float(row["kilning_flowrate_kg_s"]), rel=0.02)


@pytest.mark.parametrize("row", read_csv("lee_response_angle_of_repose_holdups.csv"),
                         ids=lambda r: r["dynamic_angle_of_repose_deg"])
def test_table_7_7_holdups(row, regressions, table_7_2):
    phi = float(row["dynamic_angle_of_repose_deg"])
    m = model(regressions, table_7_2, 35, repose_angle=phi)
    ss = m.steady_state()
    assert ss.active_holdup == pytest.approx(float(row["active_phase_mass_kg"]), rel=0.01)
    flighted = float(np.nansum(m.design_load))
    assert flighted == pytest.approx(float(row["flighted_mass_kg"]), abs=1.0)
    assert ss.passive_holdup == pytest.approx(float(row["total_passive_phase_mass_kg"]), rel=0.01)


def test_moisture_profile_eq_7_2():
    phi = lee2008_repose_profile(35, 0.02, 0.002)
    assert phi[0] == pytest.approx(58.944, abs=1e-3) and phi[-1] == pytest.approx(36.944, abs=1e-3)
    assert np.all(np.diff(phi) < 0)


@pytest.mark.parametrize("N", [30, 31, 33, 35])
def test_balance_recovery_and_mrt_identity(N, regressions, table_7_2):
    ss = model(regressions, table_7_2, N).steady_state()
    assert ss.mass_balance_error < 1e-9
    assert all(s == "over" for s in ss.loading_state)  # Lee: the Invicta dryer is overloaded
    mom = ss.tracer_system().moments()  # ideal impulse
    assert mom["recovery"] == pytest.approx(1.0, abs=1e-6)
    assert mom["mean"] == pytest.approx(ss.total_holdup / FEED, rel=1e-9)  # tau = H/F (Eq. 2.2)


def test_simulated_curve_matches_analytic_and_is_step_independent(regressions, table_7_2):
    ss = model(regressions, table_7_2, 35).steady_state()
    ref = ss.rtd(simulate=False).moments
    for method, dt, tol in [("expm", 10.0, 1e-6), ("expm", 30.0, 1e-6), ("bdf2", 5.0, 2e-3), ("bdf2", 2.5, 1e-3)]:
        sim = ss.rtd(t_end=3600.0, dt=dt, method=method).response.moments()
        assert sim["recovery"] == pytest.approx(1.0, abs=max(tol, 1e-6))
        assert sim["mean"] == pytest.approx(ref["mean"], rel=tol)
        assert sim["std"] == pytest.approx(ref["std"], rel=5 * tol)


@settings(max_examples=15, deadline=None)
@given(f1=st.floats(0.2, 1.5), f2=st.floats(0.2, 1.5))
def test_holdup_grows_with_feed(f1, f2, regressions, table_7_2):
    lo, hi = sorted((f1, f2))
    if hi - lo < 1e-3:
        return
    h = [model(regressions, table_7_2, 35, feed_rate=FEED * f).steady_state().total_holdup for f in (lo, hi)]
    assert h[1] > h[0]


CO_CURRENT = dict(kiln_time=9.95, backmix=0.0, drag_reduction=1.0, gas_flow="co-current")


@settings(max_examples=15, deadline=None)
@given(r1=st.floats(1.0, 8.0), r2=st.floats(1.0, 8.0), feed=st.sampled_from([2.0, 27.2]))
def test_holdup_falls_with_speed(r1, r2, feed, regressions):
    # forward-dominated curtain (no backmix).  With Lee's fitted counter-current sets the
    # backmix exceeds the forward step (net backward curtain flow), and holdup *rises* with
    # speed - see test_speed_trend_reverses_with_lee_backmix.
    lo, hi = sorted((r1, r2))
    if hi - lo < 1e-3:
        return
    h = [lee2008(geometry=regressions, **invicta(30, rpm=r, feed_rate=feed, **CO_CURRENT)).steady_state().total_holdup
         for r in (lo, hi)]
    assert h[1] < h[0]


def test_speed_trend_reverses_with_lee_backmix(regressions, table_7_2):
    h = [model(regressions, table_7_2, 35, rpm=r).steady_state() for r in (1.0, 2.0)]
    assert h[1].total_holdup > h[0].total_holdup
    assert h[1].flow("kiln")[0] > FEED  # kilning carries more than the feed: curtain flows back


@settings(max_examples=15, deadline=None)
@given(s1=st.floats(0.5, 6.0), s2=st.floats(0.5, 6.0))
def test_holdup_falls_with_slope(s1, s2, regressions, table_7_2):
    lo, hi = sorted((s1, s2))
    if hi - lo < 1e-3:
        return
    h = [model(regressions, table_7_2, 30, slope=s).steady_state().total_holdup for s in (lo, hi)]
    assert h[1] < h[0]


def test_state_dependent_loading(regressions, table_7_2):
    # overloaded everywhere: f_load = 1 in every cell, identical to the fixed reading
    a = model(regressions, table_7_2, 35).steady_state()
    b = model(regressions, table_7_2, 35, loading="state").steady_state()
    assert b.total_holdup == pytest.approx(a.total_holdup, rel=1e-9)
    # a light feed leaves the dryer under-loaded; the iteration still closes the balance, and the
    # fuller under-loaded flights (f_load < 1: later release, Lee Section 4.4.2) change the holdup
    c = lee2008(geometry=regressions, loading="state", **invicta(30, feed_rate=1.0, **CO_CURRENT)).steady_state()
    d = lee2008(geometry=regressions, loading="fixed", **invicta(30, feed_rate=1.0, **CO_CURRENT)).steady_state()
    assert c.mass_balance_error < 1e-9
    assert set(c.loading_state) == {"under"}
    assert np.all(c.dryer_loading > 0)
    assert abs(c.total_holdup / d.total_holdup - 1) > 0.05


def test_sheehan_model2_backmix_into_active(regressions, table_7_2):
    ss = sheehan2005_model2(geometry=regressions, **invicta(30, **table_7_2[30])).steady_state()
    assert ss.mass_balance_error < 1e-9
    fam = [f for f in ss.model.network.families if f.name == "backmix"][0]
    assert set(ss.phase[fam.dst[1:]]) == {"active"}
    mom = ss.tracer_system().moments()
    assert mom["mean"] == pytest.approx(ss.total_holdup / FEED, rel=1e-9)


def test_sheehan_model1_underloaded_closed_form():
    # below design load: F = k_PP M_P in every cell, M_A = (k_PA / k_AP) M_P (derivation in docstring)
    kpp, kpa, kap = 0.01, 0.05, 25.4 / 3600
    m = sheehan2005_model1(n_cells=10, feed_rate=5.0, length=12.0, passive_rate=kpp, exchange_rate=kpa, return_rate=kap,
                           kiln_rate=0.1, design_load=1e6)
    ss = m.steady_state()
    p = ss.masses[ss.phase == "passive"]
    a = ss.masses[ss.phase == "active"]
    np.testing.assert_allclose(p, 5.0 / kpp, rtol=1e-10)
    np.testing.assert_allclose(a, kpa / kap * 5.0 / kpp, rtol=1e-10)
    # air drag (counter-current) slows the passive path: holdup rises
    m2 = sheehan2005_model1(n_cells=10, feed_rate=5.0, length=12.0, passive_rate=kpp, exchange_rate=kpa, return_rate=kap,
                            kiln_rate=0.1, design_load=1e6, air_coefficient=1e-4, gas_mass_flow=20.0)
    assert m2.steady_state().total_holdup > ss.total_holdup


# ---- bad input ---------------------------------------------------------------------------
def test_too_many_cells_names_key_and_limit(regressions, table_7_2):
    with pytest.raises(ValueError, match=r"transport\.n_cells = 40.*<= 37"):
        lee2008(geometry=regressions, **invicta(40, **table_7_2[35]))


@pytest.mark.parametrize("kw, key", [
    (dict(backmix=-0.1), "transport.backmix"),
    (dict(backmix=1.5), "transport.backmix"),
    (dict(drag_reduction=-1.0), "transport.drag_reduction"),
    (dict(kiln_time=0.0), "transport.kiln_time"),
    (dict(kiln_time=float("nan")), "transport.kiln_time"),
    (dict(feed_rate=-1.0), "operating.feed_rate"),
    (dict(rpm=0.0), "operating.rpm"),
    (dict(slope=50.0), "drum.slope"),
    (dict(repose_angle=95.0), "solids.repose_angle"),
    (dict(gas_flow="co-current"), "transport.backmix"),
    (dict(loading="bogus"), "transport.loading"),
])
def test_bad_coefficients(kw, key, regressions, table_7_2):
    with pytest.raises(ValueError, match=key.replace(".", r"\.")):
        model(regressions, table_7_2, 35, **kw)


def test_feed_the_dryer_cannot_carry(regressions, table_7_2):
    # without kilning the flights carry at most the design load: the Invicta feed has no steady state
    m = model(regressions, table_7_2, 35, kiln_time=math.inf)
    with pytest.raises(NoSteadyStateError, match="feed_rate"):
        m.steady_state()
    assert issubclass(NoSteadyStateError, ValueError)


def test_custom_tracer_pulse_shape(regressions, table_7_2):
    ss = model(regressions, table_7_2, 35).steady_state()
    two = TracerInput(breakpoints=(0.0, 30.0, 60.0, 90.0), rates=(1.0, 0.0, 2.0))
    r = ss.rtd(two, t_end=3600.0, dt=5.0)
    sim, ana = r.response.moments(), r.moments
    assert r.tracer_input.mass == pytest.approx(90.0)
    assert sim["mean"] == pytest.approx(ana["mean"], rel=1e-6)


def test_dynamics_relax_to_steady_state(regressions, table_7_2):
    # stiff BDF integration of the mass balances (sparse Jacobian) from a half-full dryer
    m = model(regressions, table_7_2, 35)
    ss = m.steady_state()
    sol = m.network.simulate_masses(0.5 * ss.masses, (0.0, 20000.0), t_eval=[20000.0], rtol=1e-8, atol=1e-6)
    np.testing.assert_allclose(sol.y[:, -1], ss.masses, rtol=1e-4)

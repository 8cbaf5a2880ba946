"""Cell-level building blocks of the dryer balances (rotarydryer.thermal.balances)."""

import doctest
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.properties import humid_air as ha
from rotarydryer.published import read_published_csv
from rotarydryer.thermal import balances as bal
from rotarydryer.thermal.drying import MATERIAL_KINETICS


def test_doctests():
    r = doctest.testmod(bal, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert r.failed == 0 and r.attempted >= 5


def test_curtain_area_reproduces_ajayi_interfacial_areas():
    """Ajayi (2011) l.2278: theta_a = 1.2/0.6/0.42 give 0.086/0.054/0.056 m2 per kg of airborne solids
    (Eq. 6.63 with d_p = 0.015/0.012/0.008 m, rho_p = 2800)."""
    rows = {r["section"]: r for r in read_published_csv("ajayi_area_correction_factors.csv")}
    dp = {"B": 0.015, "C": 0.012, "D": 0.008}
    for sec, d in dp.items():
        a = bal.curtain_area(1.0, d, float(rows[sec]["area_correction_factor"]))
        assert float(a) == pytest.approx(float(rows[sec]["interfacial_area_m2_per_kg"]), abs=6e-4)


def test_ajayi_gas_enthalpy_matches_streams_module():
    """Per kg dry gas times the dry flow equals the wet-gas stream enthalpy of Ajayi's code (18.04 MW, notes §2.2)."""
    y_wet = 0.0193
    Y = y_wet / (1 - y_wet)
    F = 112675.6688 / 3600
    h = bal.gas_enthalpy(500.0, Y, "ajayi2011") * F * (1 - y_wet)
    assert float(h) / 1e6 == pytest.approx(18.04, abs=0.01)


def test_physical_gas_enthalpy_is_humid_air():
    assert float(bal.gas_enthalpy(200.0, 0.05)) == pytest.approx(float(ha.enthalpy(200.0, 0.05)), rel=1e-12)


def test_vapour_source_consistent_with_gas_enthalpy():
    """Adding dY of vapour at T to gas at T raises h by dY * h_v(T): the evaporation source is conservative."""
    for t in (20.0, 60.0, 95.0):
        dh = (bal.gas_enthalpy(t, 0.05 + 1e-5) - bal.gas_enthalpy(t, 0.05)) / 1e-5
        assert float(bal.vapour_source_enthalpy(t)) == pytest.approx(float(dh), rel=1e-6)


@given(st.floats(0.001, 0.999))
@settings(max_examples=50, deadline=None)
def test_kilning_angle_inverts_segment_area(f):
    th = bal.kilning_angle(f)
    assert (th - math.sin(th)) / (2 * math.pi) == pytest.approx(f, abs=2e-6)


@given(st.floats(50.0, 600.0), st.floats(1.0, 3.0))
@settings(max_examples=40, deadline=None)
def test_active_layer_area_monotone_in_holdup_below_half_fill(m, factor):
    a1 = bal.active_layer_area(m, 1600.0, 0.2, 1.95, 0.02, 1.0)
    a2 = bal.active_layer_area(m * factor, 1600.0, 0.2, 1.95, 0.02, 1.0)
    assert a2 >= a1 > 0


@given(st.floats(100.0, 550.0), st.floats(20.0, 70.0), st.floats(0.01, 0.15))
@settings(max_examples=40, deadline=None)
def test_stage_transfer_signs(tg, ts, y):
    """Hot dry gas heats the solids (Q > 0) and evaporates water (R_w > 0) when P_sat(T_s) > p_v."""
    from rotarydryer.properties import water
    rw, qc, qr = bal.stage_transfer(10.0, 0.2, ts, tg, y, 16.0, 0.01, 1.95,
                                    MATERIAL_KINETICS["zinc_concentrate_ajayi2011"])
    assert qc > 0 and qr > 0
    if water.saturation_pressure(ts) > ha.vapour_partial_pressure(y) * 1.001:
        assert rw > 0
    else:
        assert rw <= 1e-12


def test_transfer_vanishes_for_dry_solids():
    rw, _, _ = bal.stage_transfer(10.0, 0.0, 50.0, 300.0, 0.05, 16.0, 0.01, 1.95,
                                  MATERIAL_KINETICS["zinc_concentrate_ajayi2011"])
    assert rw == 0.0


def test_bad_enthalpy_method():
    with pytest.raises(ValueError, match="method"):
        bal.gas_enthalpy(100.0, 0.01, "nope")


def test_the_solids_temperature_ceiling_has_a_rounded_corner():
    """The surface-evaporation model holds the solids temperature at its ceiling (99 degC at sea level): the
    corner is rounded over +-CEILING_BLEND_K by the parabola with both slopes (the same in the compiled kernel),
    so the evaporation's slope in the solids temperature, steepest near the boiling point, falls to zero over 2 K
    instead of at once, where Newton cycled (a user dryer of dried zinc fines, tests/thermal/test_hard_cases.py).
    Below 98 degC nothing changes."""
    from rotarydryer.properties import _kernels
    from rotarydryer.thermal.balances import soft_ceiling, solids_temperature_ceiling, stage_transfer
    from rotarydryer.thermal.drying import DryingKinetics

    top, d = solids_temperature_ceiling(101325.0), _kernels.CEILING_BLEND_K
    t = np.linspace(80.0, 120.0, 40001)
    soft = soft_ceiling(t, top)
    outside = np.abs(t - top) >= d
    np.testing.assert_array_equal(soft[outside], np.minimum(t, top)[outside])
    assert np.all(soft <= np.minimum(t, top)) and np.all(np.diff(soft) >= 0)
    slope = np.diff(soft) / np.diff(t)
    assert np.max(np.abs(np.diff(slope))) < 1e-3          # no jump in the slope (it was 1 -> 0 at the ceiling)
    np.testing.assert_allclose([_kernels._soft_ceiling(float(v), top) for v in t[::97]], soft[::97], rtol=0,
                               atol=1e-12)
    kin = DryingKinetics("ajayi2011")
    ts = np.linspace(top - 3.0, top + 3.0, 601)
    rw = stage_transfer(np.full(ts.shape, 10.0), np.full(ts.shape, 0.1), ts, np.full(ts.shape, 300.0),
                        np.full(ts.shape, 0.05), np.full(ts.shape, 20.0), 0.002, 1.5, kin)[0]
    drw = np.diff(rw) / np.diff(ts)
    assert drw[0] > 0 and abs(drw[-1]) < 1e-12 * abs(rw[-1])       # rising below, flat above the corner
    assert np.max(np.abs(np.diff(drw))) < 0.05 * np.max(np.abs(drw))   # the slope falls off gradually

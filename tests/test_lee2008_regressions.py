"""Lee (2008) regression surrogates (Eq. 4.24-4.28) against Table 7.6 and properties."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.geometry.lee2008_regressions import (
    Lee2008Regressions,
    invicta_tip_radius,
)
from rotarydryer.published import read_published_csv as _csv

TABLE_7_6 = _csv("lee_response_angle_of_repose_cycle_times.csv")
GEOM = Lee2008Regressions()


def test_invicta_tip_radius_eq_4_6():
    assert GEOM.tip_radius == pytest.approx(2.22789, abs=5e-6)
    assert invicta_tip_radius() == pytest.approx(2.22789, abs=5e-6)


@pytest.mark.parametrize("row", TABLE_7_6, ids=lambda r: r["dynamic_angle_of_repose_deg"])
def test_table_7_6(row):
    phi = float(row["dynamic_angle_of_repose_deg"])
    c = GEOM.cascade(phi, 1.0, rpm=3.0, slope=2.8)
    fall = float(row["avg_particle_fall_time_s"])
    # fall time to 4 significant figures
    assert float(c.mean_fall_time) == pytest.approx(fall, abs=0.5 * 10 ** (math.floor(math.log10(fall)) - 3))
    # passive cycle time to 0.01 s (lee2008_ch7 branch, the default)
    assert float(c.passive_time) == pytest.approx(float(row["avg_passive_cycle_time_s"]), abs=0.01)
    # design load of the whole 12 m dryer at 940 kg/m3, within 1 kg
    load = 940.0 * 12.0 * float(GEOM.design_load_area(phi))
    assert load == pytest.approx(float(row["dryer_design_load_kg"]), abs=1.0)


def test_ch4_example_release_angle():
    # Lee (2008) Section 4.3: psi_m = 201.6 deg, h_m = 4.164 m, t_a = 0.824 s at phi ~ 50 deg
    c = GEOM.cascade(50.0, 1.0, rpm=3.0)
    assert float(c.mean_fall_height) == pytest.approx(4.164, abs=5e-4)
    assert float(c.mean_fall_time) == pytest.approx(0.824, abs=5e-4)
    assert float(c.mean_release_angle) == pytest.approx(201.6, abs=1.0)


@settings(max_examples=50, deadline=None)
@given(phi=st.floats(25, 65), f=st.floats(0, 1), rpm=st.floats(0.5, 10))
def test_branches_sum_to_one_revolution(phi, f, rpm):
    a = GEOM.cascade(phi, f, rpm=rpm, passive_time_branch="eq3.4")
    b = GEOM.cascade(phi, f, rpm=rpm, passive_time_branch="lee2008_ch7")
    assert float(a.passive_time + b.passive_time) == pytest.approx(60.0 / rpm, rel=1e-12)
    assert float(a.mean_release_angle + b.mean_release_angle) == pytest.approx(360.0, rel=1e-12)
    assert float(a.mean_fall_time) == float(b.mean_fall_time)
    assert 90.0 <= float(a.mean_release_angle) <= 180.0 <= float(b.mean_release_angle) <= 270.0


@settings(max_examples=50, deadline=None)
@given(phi=st.floats(25, 65), rpm=st.floats(0.5, 10), factor=st.floats(1.1, 4))
def test_passive_time_inverse_in_speed(phi, rpm, factor):
    a = GEOM.cascade(phi, rpm=rpm).passive_time
    b = GEOM.cascade(phi, rpm=rpm * factor).passive_time
    assert float(a / b) == pytest.approx(factor, rel=1e-12)


@settings(max_examples=100, deadline=None)
@given(d=st.floats(0, 5), phi=st.floats(25, 65))
def test_loading_factor_clipped(d, phi):
    f = float(GEOM.loading_factor(d, phi))
    assert 0.0 <= f <= 1.0
    if d > 1:
        assert f == 1.0


def test_loading_factor_values_and_clip_to_zero():
    # polynomial is negative at d = 0 -> clipped to 0 (Lee's code IF-clause)
    assert float(GEOM.loading_factor(0.0, 50.0)) == 0.0
    # code coefficient 1.15297 (not the printed 1.84): f(50, d=1) = 0.910
    assert float(GEOM.loading_factor(1.0, 50.0)) == pytest.approx(0.9097, abs=1e-3)
    assert float(GEOM.loading_factor(1.0 + 1e-9, 50.0)) == 1.0


def test_vectorised_broadcasting():
    phi = np.array([30.0, 40.0, 50.0])[:, None]
    f = np.array([0.5, 1.0])[None, :]
    c = GEOM.cascade(phi, f, rpm=3.0)
    for arr in (c.mean_release_angle, c.mean_fall_height, c.mean_fall_time, c.passive_time):
        assert arr.shape == (3, 2)
        assert np.all(np.isfinite(arr))
    assert GEOM.design_load_area(np.array([30.0, 40.0])).shape == (2,)
    assert GEOM.loading_factor(np.array([0.5, 2.0]), 40.0).shape == (2,)


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: GEOM.cascade(10.0, rpm=3.0), "repose_angle"),
        (lambda: GEOM.cascade(40.0, 1.5, rpm=3.0), "loading_factor"),
        (lambda: GEOM.cascade(40.0, rpm=0.0), "rpm"),
        (lambda: GEOM.cascade(40.0, rpm=3.0, passive_time_branch="bogus"), "passive_time_branch"),
        (lambda: GEOM.loading_factor(-0.1, 40.0), "dryer_loading"),
        (lambda: GEOM.design_load_area(float("nan")), "repose_angle"),
        (lambda: Lee2008Regressions(tip_radius=-1.0), "tip_radius"),
        (lambda: Lee2008Regressions(tip_radius=1.0).cascade(40.0, rpm=3.0), "repose_angle"),
    ],
)
def test_bad_input(call, name):
    with pytest.raises(ValueError, match=name):
        call()

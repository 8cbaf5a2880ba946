"""Mean-residence-time correlations: Song (2003) pilot-dryer comparison, hand values, properties."""

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.correlations import (
    CorrelationRangeWarning,
    alvarez_shene_1994,
    foust_1960,
    friedman_marshall_1949,
    mean_residence_time,
    mean_residence_time_methods,
    perry_green_1984,
    saeman_mitchell_1954,
    sai_1990,
    solids_holdup,
    song_2003,
    song_2003_appendix_a,
    sullivan_1927,
    sullivan_friedman_marshall_1949,
)
from rotarydryer.correlations.residence_time import _bed_angle_from_holdup

LITERATURE = ("friedman_marshall_1949", "foust_1960", "perry_green_1984")
OTTAWA = dict(length=3.05, diameter=0.305, slope=0.083, rpm=5.0, particle_size=444e-6)


@pytest.fixture(scope="module")
def song_data():
    return song_2003_appendix_a()


def _inputs(d):
    keys = ("length", "diameter", "slope", "rpm", "particle_size", "gas_mass_flux", "solids_mass_flux")
    return {k: d[k] for k in keys}


def _sse_minutes(method, d):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CorrelationRangeWarning)
        pred = mean_residence_time(method=method, allow_nonpositive=True, **_inputs(d))
    return float(np.sum(((pred - d["mean_residence_time"]) / 60.0) ** 2))


def test_appendix_a_data_loaded(song_data):
    assert len(song_data["rpm"]) == 73
    # F = Ori_F*60/A with A = pi/4*0.305^2 (Song's conversion, notes/song.md §7.2)
    area = math.pi / 4 * 0.305**2
    np.testing.assert_allclose(song_data["solids_feed_rate"] / area, song_data["solids_mass_flux"], rtol=2e-3)


def test_song_ranking_computed_from_printed_formulas(song_data):
    """Song (2003) ch. 4: Perry & Green best of the literature forms, Eq. 4.5 best overall."""
    sse = {m: _sse_minutes(m, song_data) for m in LITERATURE + ("song_2003",)}
    ranking = sorted(sse, key=sse.get)
    assert ranking[0] == "song_2003"
    best_literature = min(LITERATURE, key=sse.get)
    assert best_literature == "perry_green_1984"
    # "The sum of squares ... was reduced by a factor of four using equation (5) instead of equation (4)"
    assert 3.5 < sse["perry_green_1984"] / sse["song_2003"] < 4.7
    # review values (notes/song.md §7.3): 160.4, 1005.5, 29.9, 7.27 min^2
    assert sse["song_2003"] == pytest.approx(7.27, rel=0.01)
    assert sse["perry_green_1984"] == pytest.approx(29.9, rel=0.01)


def test_song_bias_directions(song_data):
    """F&M under-predicts, Foust over-predicts (Song 2003 L1407)."""
    meas = song_data["mean_residence_time"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CorrelationRangeWarning)
        fm = friedman_marshall_1949(**_inputs(song_data), allow_nonpositive=True)
        fo = foust_1960(**_inputs(song_data))
    assert np.mean((fm - meas) / meas) < -0.2
    assert np.mean((fo - meas) / meas) > 0.5


def test_song_constants_refit(song_data):
    """Least squares of the Eq. 4.5 structure on the 73 runs gives Song's constants 14.3 and 354."""
    d = song_data
    x1 = d["length"] / (d["slope"] * d["rpm"] * d["diameter"])
    x2 = -d["length"] * d["gas_mass_flux"] / d["solids_mass_flux"] / np.sqrt(d["particle_size"] * 1e6)
    coef, *_ = np.linalg.lstsq(np.c_[x1, x2], d["mean_residence_time"], rcond=None)
    assert coef[0] == pytest.approx(14.3, rel=0.01)
    assert coef[1] == pytest.approx(354.0, rel=0.01)
    # The model with the printed constants is within the refit's SSE by < 2 %
    pred = coef[0] * x1 + coef[1] * x2
    sse_fit = np.sum(((pred - d["mean_residence_time"]) / 60) ** 2)
    assert _sse_minutes("song_2003", d) < 1.02 * sse_fit


def test_foust_and_perry_first_terms():
    """Foust's first term is 98.5 % above F&M's; Perry & Green's is 30 % above (Song L652, L656)."""
    args = dict(OTTAWA, gas_mass_flux=0.0, solids_mass_flux=1.0)
    fm = friedman_marshall_1949(**args)
    assert foust_1960(**args) / fm == pytest.approx(1.985, abs=0.001)
    assert perry_green_1984(**args) / fm == pytest.approx(1.30, abs=0.005)
    assert sullivan_friedman_marshall_1949(3.05, 0.305, 0.083, 5.0) == pytest.approx(fm, rel=1e-12)


def test_sullivan_degree_reading_consistent_with_eq_2_2():
    """Eq. 2.1 with gamma = 40 deg and atan(s) in degrees is within 12 % of Eq. 2.2 at n = 1 rpm."""
    s = np.array([0.02, 0.083, 0.15])
    ratio = sullivan_1927(3.0, 0.3, s, 1.0, 40.0) / sullivan_friedman_marshall_1949(3.0, 0.3, s, 1.0)
    assert np.all((ratio > 1.0) & (ratio < 1.12))
    # hand value: 106.2*3.05*sqrt(40)/(4.7447 deg * 5 * 0.305)
    assert sullivan_1927(3.05, 0.305, 0.083, 5.0, 40.0) == pytest.approx(283.12, abs=0.01)


def test_table_4_1_holdup_from_mrt():
    """Song (2003) Eq. 4.1, H = tau F, reproduces Table 4.1 run 3: (54.63 + 56.13)/2 kg."""
    assert solids_holdup(6.98 * 60, 7.93 / 60) == pytest.approx((54.63 + 56.13) / 2, rel=0.002)


def test_song_range_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        song_2003(**OTTAWA, gas_mass_flux=2.0, solids_mass_flux=1.0)  # inside: no warning
    with pytest.warns(CorrelationRangeWarning, match=r"rpm = 10.*\[3, 8\]"):
        song_2003(3.05, 0.305, 0.083, 10.0, 444e-6, 0.5, 1.0)
    with pytest.warns(CorrelationRangeWarning, match="slope"):
        song_2003(3.05, 0.305, 0.2, 5.0, 444e-6, 0.5, 1.0)
    with pytest.warns(CorrelationRangeWarning, match="particle_size"):
        song_2003(3.05, 0.305, 0.083, 5.0, 1e-3, 0.5, 1.0)
    with pytest.warns(CorrelationRangeWarning, match="counter-current"):
        song_2003(**OTTAWA, gas_mass_flux=0.5, solids_mass_flux=1.0, gas_flow="counter-current")


def test_bad_input_raises():
    with pytest.raises(ValueError, match="length"):
        perry_green_1984(-1.0, 0.3, 0.08, 5, 444e-6, 0.5, 0.7)
    with pytest.raises(ValueError, match="slope"):
        perry_green_1984(3.0, 0.3, 0.0, 5, 444e-6, 0.5, 0.7)
    with pytest.raises(ValueError, match="gas_flow"):
        perry_green_1984(3.0, 0.3, 0.08, 5, 444e-6, 0.5, 0.7, gas_flow="sideways")
    with pytest.raises(ValueError, match="rpm"):
        perry_green_1984(3.0, 0.3, 0.08, float("nan"), 444e-6, 0.5, 0.7)
    with pytest.raises(ValueError, match="non-positive residence time"):
        friedman_marshall_1949(3.05, 0.305, 0.083, 5.0, 444e-6, 10.0, 0.5)
    with pytest.raises(ValueError, match="method"):
        mean_residence_time(method="nobody_2099", **OTTAWA)
    with pytest.raises(ValueError, match="needs the argument"):
        mean_residence_time(method="sullivan_1927", **OTTAWA)
    with pytest.raises(ValueError, match="not enough"):
        mean_residence_time(length=3.0)


def test_nonpositive_allowed_warns():
    with pytest.warns(CorrelationRangeWarning, match="non-positive"):
        tau = friedman_marshall_1949(3.05, 0.305, 0.083, 5.0, 444e-6, 10.0, 0.5, allow_nonpositive=True)
    assert tau < 0


def test_dispatcher_and_lister():
    full = dict(OTTAWA, gas_mass_flux=0.5, solids_mass_flux=0.7)
    methods = mean_residence_time_methods(**full)
    assert methods[:4] == ["song_2003", "perry_green_1984", "friedman_marshall_1949", "foust_1960"]
    assert "sullivan_1927" not in methods
    assert "sullivan_1927" in mean_residence_time_methods(**full, repose_angle=35.0)
    assert mean_residence_time(**full) == song_2003(**full)  # default = best in range
    out_of_range = dict(full, rpm=12.0)
    assert mean_residence_time_methods(check_ranges=True, **out_of_range)[0] == "perry_green_1984"
    assert mean_residence_time(**out_of_range) == perry_green_1984(**out_of_range)
    for m in methods:
        assert mean_residence_time(method=m, **full) > 0


def test_vectorised_matches_scalar():
    rpm = np.array([3.0, 5.0, 8.0])
    vec = perry_green_1984(3.05, 0.305, 0.083, rpm, 444e-6, 0.5, 0.7)
    for i, n in enumerate(rpm):
        assert vec[i] == perry_green_1984(3.05, 0.305, 0.083, float(n), 444e-6, 0.5, 0.7)


@pytest.mark.filterwarnings("ignore::rotarydryer.correlations.CorrelationRangeWarning")
@settings(max_examples=60, deadline=None)
@given(
    length=st.floats(1.0, 30.0),
    diameter=st.floats(0.2, 4.0),
    slope=st.floats(0.01, 0.2),
    rpm=st.floats(1.0, 10.0),
    dp=st.floats(100e-6, 5e-3),
    ratio=st.floats(0.0, 0.5),
    scale=st.floats(0.1, 10.0),
)
def test_friedman_marshall_family_properties(length, diameter, slope, rpm, dp, ratio, scale):
    solids = 1.0
    gas = ratio * solids
    for f in (friedman_marshall_1949, foust_1960, perry_green_1984):
        base = f(length, diameter, slope, rpm, dp, 0.0, solids)
        co = f(length, diameter, slope, rpm, dp, gas, solids, allow_nonpositive=True)
        counter = f(length, diameter, slope, rpm, dp, gas, solids, gas_flow="counter-current")
        assert co <= base <= counter
        # symmetric gas effect
        assert counter - base == pytest.approx(base - co, rel=1e-9, abs=1e-9)
        # only G/F matters
        assert f(length, diameter, slope, rpm, dp, gas * scale, solids * scale, gas_flow="counter-current") == \
            pytest.approx(counter, rel=1e-12)
        # linear in length, decreasing in rpm and slope without gas
        assert f(2 * length, diameter, slope, rpm, dp, 0.0, solids) == pytest.approx(2 * base, rel=1e-12)
        assert f(length, diameter, slope, rpm * 1.5, dp, 0.0, solids) < base
        assert f(length, diameter, slope * 1.5, rpm, dp, 0.0, solids) < base


def test_sai_bed_geometry_conserves_holdup():
    fill = np.array([1e-3, 0.5, 3.0, 6.0])
    theta = _bed_angle_from_holdup(fill)
    np.testing.assert_allclose(theta - np.sin(theta), fill, rtol=1e-9)


def test_sai_hand_value():
    # H = 30 kg in a 3.05 m x 0.305 m drum at 1650 kg/m3: theta from Eq. 2.6, h from Eq. 2.7.
    r = 0.1525
    fill = 2 * 30.0 / (1650.0 * 3.05 * r**2)
    theta = _bed_angle_from_holdup(np.array(fill))
    h = r * (1 - math.cos(float(theta) / 2))
    tau = 78912 * h**0.24 / (math.degrees(math.atan(0.083)) ** 1.02 * 5**0.88 * (math.pi * r**2 * 1.2318 * 3600) ** 0.072)
    assert sai_1990(3.05, 0.305, 0.083, 5.0, 1.2318, 30.0, 1650.0) == pytest.approx(tau, rel=1e-9)
    assert sai_1990(3.05, 0.305, 0.083, 5.0, 1.2318, 40.0, 1650.0) > sai_1990(3.05, 0.305, 0.083, 5.0, 1.2318,
                                                                               30.0, 1650.0)
    with pytest.raises(ValueError, match="holdup"):
        sai_1990(3.05, 0.305, 0.083, 5.0, 1.2318, 1e4, 1650.0)


def test_alvarez_shene_zero_slope_and_gas():
    tau0 = alvarez_shene_1994(0.305, 0.0, 5.0, 444e-6, 1650.0, 1.0, 0.0)
    # hand value at s = 0: 7856 dp^0.032 rho^0.956/(pi r^2 F[kg/h] n) + 1009 dp^-0.065 rho^0.002
    r = 0.1525
    hand = 7856 * 444e-6**0.032 * 1650**0.956 / (math.pi * r**2 * 3600 * 5) + 1009 * 444e-6**-0.065 * 1650**0.002
    assert tau0 == pytest.approx(hand, rel=1e-12)
    assert alvarez_shene_1994(0.305, 0.0, 5.0, 444e-6, 1650.0, 1.0, 2.0) < tau0


def test_saeman_mitchell_limits():
    no_gas = saeman_mitchell_1954(3.05, 0.305, 0.083, 5.0, 0.0, math.pi, 0.01)
    assert no_gas == pytest.approx(3.05 / (math.pi * 0.305 * 5 / 60 * 0.083), rel=1e-12)
    co = saeman_mitchell_1954(3.05, 0.305, 0.083, 5.0, 1.0, math.pi, 0.01)
    counter = saeman_mitchell_1954(3.05, 0.305, 0.083, 5.0, 1.0, math.pi, 0.01, gas_flow="counter-current")
    assert co < no_gas < counter
    with pytest.raises(ValueError, match="slope"):
        saeman_mitchell_1954(3.05, 0.305, 0.083, 5.0, 10.0, math.pi, 0.01, gas_flow="counter-current")

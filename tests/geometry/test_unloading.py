"""Mass-averaged cascade (Lee (2008) Eq. 3.3-3.6) and cycle times."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.geometry.unloading import GRAVITY, fall_height, first_unloading_angle


def _brute_force(drum, phi, f, rpm, definition, convention):
    """Independent fine-grid trapezoid of the dH-weighted averages."""
    from rotarydryer.geometry.unloading import discharge_start_angle

    start, h0 = discharge_start_angle(drum, phi, f, convention=convention)
    psi5 = float(drum.transition_angles(phi).psi5)
    psi = np.linspace(float(start), psi5, 400_001)
    H = drum.holdup_area(psi, phi)
    dH = -np.diff(H)
    mid = 0.5 * (psi[1:] + psi[:-1])
    h = fall_height(drum, mid, definition=definition)
    w = dH / dH.sum()
    psi_m = (w * mid).sum()
    return psi_m, (w * h).sum(), (w * np.sqrt(2 * h / GRAVITY)).sum(), (2 * psi_m - 180) / (6 * rpm)


@pytest.mark.parametrize("phi", [30.0, 50.0])
@pytest.mark.parametrize("f", [1.0, 0.4])
@pytest.mark.parametrize("definition", ["chord", "eq3.5"])
@pytest.mark.parametrize("convention", ["root", "tip"])
def test_quadrature_matches_brute_force(invicta, phi, f, definition, convention):
    cs = invicta.cascade(phi, f, rpm=3.0, fall_height=definition, convention=convention)
    ref = _brute_force(invicta, phi, f, 3.0, definition, convention)
    got = (cs.mean_release_angle, cs.mean_fall_height, cs.mean_fall_time, cs.passive_time)
    np.testing.assert_allclose(np.array(got, dtype=float), ref, rtol=2e-5)


def test_notes_reference_values(invicta):
    """Exact-geometry values of the independent reference implementation recorded in
    notes lee_models.md section 6.7 (tip convention, chord / Eq. 3.5, 3 rpm)."""
    cs = invicta.cascade([30, 40, 50, 60], rpm=3.0, convention="tip")
    np.testing.assert_allclose(cs.mean_release_angle, [130.1, 133.7, 136.2, 137.3], atol=0.06)
    np.testing.assert_allclose(cs.mean_fall_height, [2.795, 2.880, 2.876, 2.789], atol=6e-4)
    np.testing.assert_allclose(cs.mean_fall_time, [0.719, 0.729, 0.725, 0.710], atol=6e-4)
    np.testing.assert_allclose(cs.passive_time, [4.46, 4.86, 5.13, 5.26], atol=6e-3)
    eq35 = invicta.cascade([30, 40, 50, 60], rpm=3.0, convention="tip", fall_height="eq3.5")
    np.testing.assert_allclose(eq35.mean_fall_height, [3.625, 3.668, 3.666, 3.623], atol=6e-4)


def test_underloading_table(invicta):
    """notes section 6.7: phi = 40, tip convention, f = 0.75/0.5/0.25."""
    cs = invicta.cascade(40.0, [0.75, 0.5, 0.25], rpm=3.0, convention="tip")
    np.testing.assert_allclose(cs.mean_release_angle, [146.4, 159.4, 172.1], atol=0.06)
    np.testing.assert_allclose(cs.mean_fall_height, [3.58, 4.12, 4.38], atol=6e-3)
    np.testing.assert_allclose(cs.passive_time, [6.26, 7.71, 9.12], atol=6e-3)


def test_abstract_orders_of_magnitude(invicta):
    """Lee (2008) abstract: fall time ~0.9 s, time in flights ~9 s (orders of magnitude)."""
    cs = invicta.cascade(45.0, rpm=3.0)
    assert 0.5 < float(cs.mean_fall_time) < 1.2
    assert 3.0 < float(cs.passive_time) < 15.0


@settings(max_examples=40, deadline=None)
@given(st.floats(25.0, 70.0), st.floats(0.05, 0.95))
def test_underloading_raises_release_point_and_passive_time(phi, f):
    from rotarydryer.geometry import FlightedDrum, TwoSectionFlight

    drum = FlightedDrum(2.5, 28, TwoSectionFlight(0.195, 0.183, 90.0, 117.0))
    cs = drum.cascade(phi, [f, min(f + 0.05, 1.0)], rpm=3.0)
    assert cs.mean_release_angle[0] >= cs.mean_release_angle[1] - 1e-9
    assert cs.passive_time[0] >= cs.passive_time[1] - 1e-9
    assert np.all(cs.mean_release_angle <= float(drum.transition_angles(phi).psi5) + 1e-9)


def test_branches_complement(invicta):
    a = invicta.cascade(45.0, rpm=3.0, passive_time_branch="eq3.4").passive_time
    b = invicta.cascade(45.0, rpm=3.0, passive_time_branch="lee2008_ch7").passive_time
    assert float(a + b) == pytest.approx(20.0)  # one revolution at 3 rpm


def test_empty_flight_limit(invicta):
    cs = invicta.cascade(45.0, [0.0, 1e-6], rpm=3.0)
    assert cs.mean_release_angle[0] == pytest.approx(cs.mean_release_angle[1], abs=1e-2)


def test_slope_scales_fall_height(invicta):
    flat = invicta.cascade(45.0, rpm=3.0).mean_fall_height
    tilted = invicta.cascade(45.0, rpm=3.0, slope=2.8).mean_fall_height
    assert float(tilted / flat) == pytest.approx(1 / np.cos(np.radians(2.8)))


def test_first_unloading_angle(invicta):
    assert first_unloading_angle(invicta, "root") == 90.0
    assert first_unloading_angle(invicta, "tip") == pytest.approx(90.0 - invicta.tip_angle)


@pytest.mark.parametrize(
    "kwargs,field",
    [
        (dict(rpm=0.0), "rpm"),
        (dict(rpm=3.0, fall_height="bogus"), "fall_height"),
        (dict(rpm=3.0, passive_time_branch="x"), "passive_time_branch"),
        (dict(rpm=3.0, convention="middle"), "convention"),
        (dict(rpm=3.0, slope=60.0), "slope"),
    ],
)
def test_bad_cascade_input(invicta, kwargs, field):
    with pytest.raises(ValueError, match=field):
        invicta.cascade(45.0, **kwargs)


def test_bad_loading_factor(invicta):
    with pytest.raises(ValueError, match="loading_factor"):
        invicta.cascade(45.0, 1.5, rpm=3.0)


def test_drag_option_limits_and_direction(invicta):
    """Fall with drag (CascadeDrag): a heavy, large particle falls freely; without gas the
    axial step is the free-fall h tan(slope) (Lee (2008) Eq. 3.7); counter-current gas
    shortens the step, co-current lengthens it; drag lengthens the fall of fine sugar."""
    from rotarydryer.geometry import CascadeDrag

    free = invicta.cascade(45.0, rpm=3.0, slope=2.8)
    heavy = invicta.cascade(45.0, rpm=3.0, slope=2.8, drag=CascadeDrag(0.02, 2800.0))
    assert float(heavy.mean_fall_time) == pytest.approx(float(free.mean_fall_time), rel=0.03)
    assert float(free.mean_axial_step) == pytest.approx(
        float(free.mean_fall_height) * np.cos(np.radians(2.8)) * np.tan(np.radians(2.8)), rel=1e-9)
    sugar = dict(particle_diameter=850e-6, particle_density=1588.0)
    still = invicta.cascade(45.0, rpm=3.0, slope=2.8, drag=CascadeDrag(**sugar))
    counter = invicta.cascade(45.0, rpm=3.0, slope=2.8, drag=CascadeDrag(**sugar, gas_velocity=1.0,
                                                                         gas_flow="counter-current"))
    co = invicta.cascade(45.0, rpm=3.0, slope=2.8, drag=CascadeDrag(**sugar, gas_velocity=1.0))
    assert float(still.mean_axial_step) == pytest.approx(float(free.mean_axial_step), rel=1e-6)
    assert float(counter.mean_axial_step) < float(still.mean_axial_step) < float(co.mean_axial_step)
    assert float(still.mean_fall_time) > float(free.mean_fall_time)

"""Image analysis of drum cross-sections (Ajayi (2011) ch. 4) on rendered synthetic photographs."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.geometry.presets import preset_drum
from rotarydryer.lab import images as im
from rotarydryer.published import read_published_csv

AJAYI_PX_PER_M = 2 * 950 / 0.75  # Appendix C: 950 px drum radius, 75 cm diameter (25.33 px/cm)


@pytest.fixture(scope="module")
def pilot():
    return preset_drum("ajayi_pilot")[0]


def _thresholds():
    rows = {r["step"]: r for r in read_published_csv("ajayi_imagej_threshold_settings.csv")}
    fb = (float(rows["threshold_flight_borne"]["upper_half_drum"]), float(rows["threshold_flight_borne"]["lower_half_drum"]))
    ab = (float(rows["threshold_airborne"]["upper_half_drum"]), float(rows["threshold_airborne"]["lower_half_drum"]))
    return fb, ab


def test_thresholds_are_ajayis():
    fb, ab = _thresholds()
    assert fb == im.AJAYI_THRESHOLDS["flight_borne"] and ab == im.AJAYI_THRESHOLDS["airborne"]


@pytest.mark.parametrize("repose", [44.7, 51.1, 62.3])  # Ajayi Table 4.11 range
def test_flight_areas_within_2_percent_ajayi_scale(pilot, repose):
    """Acceptance: on a cross-section rendered at Ajayi's scale (25.33 px/cm), with 2 mm flight plates,
    grey-level noise and his fixed thresholds, every flight holding > 2 cm2, the FUF, UHD+LHD and the
    curtain are measured within 2 % of the exact visible areas."""
    fb, ab = _thresholds()
    s = im.render_cross_section(pilot, repose, reference_angle=91.0, px_per_m=AJAYI_PX_PER_M,
                                flight_thickness=0.002, noise_sd=10.0, seed=7, mirror=True)
    m = im.measure(s.image, pilot, s.calibration, reference_angle=91.0, threshold=fb, airborne_threshold=ab)
    big = s.flight_areas > 2e-4
    assert big.sum() >= 8
    assert np.all(np.abs(m.flight_areas[big] / s.flight_areas[big] - 1) < 0.02)
    assert m.fuf_area == pytest.approx(s.flight_areas[m.fuf_index], rel=0.02)
    assert m.total_passive == pytest.approx(s.flight_areas.sum(), rel=0.01)
    assert m.airborne == pytest.approx(s.airborne_area, rel=0.02)
    # the geometry model's FUF (zero-thickness flight) differs only by the plate's footprint
    assert s.flight_areas[m.fuf_index] < s.model_areas[m.fuf_index]


def test_zero_thickness_matches_geometric_holdup(pilot):
    """Without plates the rendered areas are the geometric holdups (Lee (2008) Eq. 4.14-4.17)."""
    s = im.render_cross_section(pilot, 46.7, reference_angle=88.0, px_per_m=1500.0, curtains=False)
    assert np.allclose(s.flight_areas, s.model_areas, rtol=2e-3, atol=1e-7)
    m = im.measure(s.image, pilot, s.calibration, reference_angle=88.0)
    big = s.model_areas > 2e-4
    assert np.all(np.abs(m.flight_areas[big] / s.model_areas[big] - 1) < 0.02)
    assert m.airborne == 0.0


def test_otsu_and_blur(pilot):
    """Otsu thresholds per region type with a 1-px blur: FUF and total passive still within 2 %."""
    s = im.render_cross_section(pilot, 46.7, reference_angle=92.0, px_per_m=AJAYI_PX_PER_M,
                                flight_thickness=0.002, noise_sd=8.0, blur_sigma=1.0, seed=1)
    m = im.measure(s.image, pilot, s.calibration, reference_angle=92.0, threshold="otsu", airborne_threshold="otsu")
    assert m.fuf_area == pytest.approx(s.flight_areas[m.fuf_index], rel=0.02)
    assert m.total_passive == pytest.approx(s.flight_areas.sum(), rel=0.02)
    assert m.airborne == pytest.approx(s.airborne_area, rel=0.05)


@settings(max_examples=12, deadline=None)
@given(ref=st.floats(0.0, 15.0), repose=st.floats(35.0, 65.0), mirror=st.booleans())
def test_total_area_conserved_any_orientation(pilot, ref, repose, mirror):
    """Property: whatever the flight phase, angle of repose and viewing side, per-flight areas sum to
    UHD + LHD and match the exact total within 1.5 %."""
    s = im.render_cross_section(pilot, repose, reference_angle=ref, px_per_m=1200.0, mirror=mirror)
    m = im.measure(s.image, pilot, s.calibration, reference_angle=ref)
    assert m.flight_areas.sum() == pytest.approx(m.upper_half + m.lower_half, rel=1e-12)
    assert m.total_passive == pytest.approx(s.flight_areas.sum(), rel=0.015)
    assert 0 <= m.airborne_fraction <= 1


def test_calibration_round_trip_and_known_length():
    cal = im.ImageCalibration.from_known_length((970, 960), 1900, 0.75, mirror=True, angle_offset=3.0)
    assert cal.px_per_m == pytest.approx(AJAYI_PX_PER_M)
    xy = np.array([[0.1, -0.2], [0.3, 0.05]])
    assert np.allclose(cal.to_metres(cal.to_pixels(xy)), xy)
    # mirror: the geometry's +x appears on the left of the picture
    assert cal.to_pixels([0.1, 0.0])[0] < 970


def test_fuf_convention(pilot):
    roots = 90.0 + pilot.flight_spacing * np.arange(pilot.n_flights) - 6.0
    assert im.first_unloading_flight(pilot, roots, "root") == 0
    k_tip = im.first_unloading_flight(pilot, roots, "tip")
    assert abs((roots[k_tip] + pilot.tip_angle) % 360 - 90) <= pilot.flight_spacing / 2


def test_annotate_writes_png(tmp_path, pilot):
    s = im.render_cross_section(pilot, 46.7, px_per_m=500.0)
    m = im.measure(s.image, pilot, s.calibration, reference_angle=90.0)
    p = tmp_path / "annotated.png"
    im.annotate(s.image, m, p)
    assert p.stat().st_size > 5_000
    d = m.as_dict()
    assert d["FUF_cm2"] == pytest.approx(m.fuf_area * 1e4) and len(d["flight_areas_cm2"]) == 24


def test_bad_inputs(pilot):
    s = im.render_cross_section(pilot, 46.7, px_per_m=300.0)
    with pytest.raises(ValueError, match="threshold"):
        im.measure(s.image, pilot, s.calibration, reference_angle=90.0, threshold="triangle")
    with pytest.raises(ValueError, match="px_per_m"):
        im.ImageCalibration((0, 0), -1.0)
    with pytest.raises(ValueError, match="centre"):
        im.ImageCalibration((0, 0, 1), 100.0)
    with pytest.raises(ValueError, match="repose_angle"):
        im.render_cross_section(pilot, 95.0)
    with pytest.raises(ValueError, match="channel"):
        im.measure(s.image, pilot, s.calibration, reference_angle=90.0, channel=5)

"""Widget ranges come from the case and its material (issue 31 item 4)."""

from __future__ import annotations

import pytest

pytest.importorskip("streamlit")

from rotarydryer.app import logic  # noqa: E402
from rotarydryer.cases import load_case  # noqa: E402
from rotarydryer.cases.build import material_of  # noqa: E402


@pytest.mark.parametrize("case", ["ajayi2011_mmg", "lee2008_invicta", "song2003_ottawa"])
def test_feed_moisture_range_is_the_materials(case):
    lo, hi = logic.input_range(case, "operating.feed_moisture")
    assert lo == 0.0
    assert hi == pytest.approx(min(float(material_of(load_case(case)).wet_range()[1]), 1.0))


def test_speed_range_stops_at_the_critical_speed():
    from rotarydryer.geometry.drum import critical_speed

    c = load_case("lee2008_invicta")
    assert logic.input_range("lee2008_invicta", "operating.rpm")[1] == pytest.approx(
        float(critical_speed(float(c.drum.radius))))


def test_bad_geometry_values_and_unknown_keys_are_refused():
    """The geometry page's logic truncated 2.7 flights to 2, took a bulk density of -5 kg/m3 (a design load of
    -32.6 kg) and a length of 0; input_range gave (None, None) for a key the case does not have (fuzzing)."""
    import pytest

    from rotarydryer.app import logic as L

    args = dict(radius=1.0, n_flights=12, s1=0.1, s2=0.05, alpha1=90.0, alpha2=120.0, repose_angle=40.0, rpm=3.0,
                slope=2.0, bulk_density=800.0, length=10.0, images=False)
    assert L.geometry_view(**args)["metrics"]["design_load_kg"] > 0
    for bad, match in ((dict(n_flights=2.7), "n_flights = 2.7 is not a whole number"),
                       (dict(bulk_density=-5.0), "bulk_density = -5 kg/m"), (dict(length=0.0), "length = 0 m")):
        with pytest.raises(ValueError, match=match):
            L.geometry_view(**{**args, **bad})
    with pytest.raises(ValueError, match="'nope' is not a key of case 'lee2008_invicta'"):
        L.input_range("lee2008_invicta", "nope")

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

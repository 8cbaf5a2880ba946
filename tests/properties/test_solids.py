"""Moisture-dependent solids properties (Ajayi (2011) Eq. 3.2, 3.4; Lee (2008) Eq. 7.2)."""

import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from rotarydryer.properties import bulk_density, lee2008_moisture_profile, repose_angle
from rotarydryer.properties.solids import PropertyRangeWarning
from rotarydryer.published import read_published_csv as read_csv


def test_ajayi_table_3_3_fit_quality():
    """Eq. 3.2 is a fit to Table 3.3: residuals within the measured standard deviations."""
    rows = read_csv("ajayi_angle_of_repose_vs_moisture.csv")
    x = np.array([float(r["moisture_kg_per_kg_wet"]) for r in rows])
    phi = np.array([float(r["dynamic_angle_of_repose_deg"]) for r in rows])
    sd = np.array([float(r["std_dev_deg"]) for r in rows])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", PropertyRangeWarning)
        res = repose_angle(x) - phi
    assert np.sqrt(np.mean((res / np.maximum(sd, 1.0)) ** 2)) < 1.5
    # and the least-squares line through the table is Eq. 3.2 (slope within 5 %)
    slope, _ = np.polyfit(x, phi, 1)
    assert slope == pytest.approx(419.6, rel=0.05)


def test_lee_profile_end_points():
    w = lee2008_moisture_profile(35)
    assert w[0] == pytest.approx(0.02) and w[-1] == pytest.approx(0.002)
    phi = repose_angle(w, "raw_sugar_lee2008")
    assert phi[0] == pytest.approx(58.944) and phi[-1] == pytest.approx(36.9444)


def test_bulk_density_table_3_4():
    """Eq. 3.4 between the inlet (1530) and outlet (1660 kg/m^3) tapped densities."""
    rho = bulk_density(np.array([0.166, 0.12]))
    assert 1500 < rho[0] < rho[1] < 1700


@given(st.floats(0.12, 0.166), st.floats(0.12, 0.166))
def test_monotone_in_moisture(a, b):
    lo, hi = sorted((a, b))
    assert repose_angle(lo) <= repose_angle(hi)
    assert bulk_density(lo) >= bulk_density(hi)


def test_out_of_range_warns_and_nonphysical_raises():
    with pytest.warns(PropertyRangeWarning, match="0.12"):
        repose_angle(0.1)
    with pytest.raises(ValueError, match="moisture"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", PropertyRangeWarning)
            repose_angle(0.01)
    with pytest.raises(ValueError, match="material"):
        repose_angle(0.15, "cheese")

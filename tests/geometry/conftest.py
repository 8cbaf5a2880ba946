import pytest

from rotarydryer.geometry import FlightedDrum, TwoSectionFlight


@pytest.fixture(scope="session")
def invicta():
    """CSR Invicta Mill dryer No. 2 (Lee (2008) Table 4.1)."""
    return FlightedDrum(2.5, 28, TwoSectionFlight(0.195, 0.183, 90.0, 117.0))

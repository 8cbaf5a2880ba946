"""The Simulation API's own argument checks."""

import pytest

from rotarydryer import Simulation


def test_bad_arguments_are_named():
    """Simulation(None) raised AttributeError, sweep(123) TypeError, dynamics(dt=0) ZeroDivisionError and
    dynamics(t_end=-10) returned one point (found by fuzzing)."""
    for case in (None, 123):
        with pytest.raises(ValueError, match=f"case = {case!r}: give a case name"):
            Simulation(case)
    sim = Simulation("lee2008_invicta")
    with pytest.raises(ValueError, match=r"grid = 123: give a list of override dicts"):
        sim.sweep(123)
    with pytest.raises(ValueError, match=r"dt = 0 s is outside the allowed range"):
        sim.dynamics(dt=0)
    with pytest.raises(ValueError, match=r"t_end = -10 s is outside the allowed range"):
        sim.dynamics(t_end=-10)

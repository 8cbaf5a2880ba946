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


def test_an_unknown_output_name_and_a_boolean_number_are_refused():
    """A sweep's rows for an output name the runs do not give had the error "'nonexistent'" (a KeyError's text);
    an override of True for a number read as 1.0 kg/s (found by fuzzing)."""
    rows = Simulation("lee2008_invicta").sweep({"operating.rpm": [3.0]}, outputs=["nonexistent"])
    assert rows[0]["error"].startswith("outputs ['nonexistent']: not among this run's outputs (")
    assert "total_holdup_kg" in rows[0]["error"]
    with pytest.raises(ValueError, match=r"--set operating.feed_rate: operating.feed_rate = True is not a number"):
        Simulation("lee2008_invicta", {"operating.feed_rate": True})


def test_a_new_speed_at_or_above_the_critical_speed_is_refused():
    """A dynamic run's (or a study's) new drum speed is checked against the drum's critical speed as the case's
    is: ``dynamics(rotational_speed=30)`` on the 5 m Invicta drum (N_c = 18.9 rev/min) ran (found by fuzzing)."""
    sim = Simulation("lee2008_invicta")
    with pytest.raises(ValueError, match=r"^operating.rpm = 30 rev/min is at or above the critical speed .* "
                                         r"the allowed range is \(0, 18.9\) rev/min"):
        sim.dynamics(t_end=120.0, dt=60.0, rotational_speed=30.0)

"""Issue 16 (part 1): the coupled solver reuses exact work — the section-law coefficients of
unchanged inputs and a warm-started shell root — and gives the same numbers."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer import Simulation
from rotarydryer.thermal.shell import shell_heat_loss


@settings(max_examples=25, deadline=None)
@given(tg=st.floats(60.0, 590.0), shift=st.floats(-30.0, 30.0), flow=st.floats(1.0, 40.0),
       ins=st.sampled_from([0.0, 0.05]))
def test_warm_started_shell_root_is_the_same_root(tg, shift, flow, ins):
    t = np.array([tg, 0.5 * (tg + 26.0) + 20.0])
    cold = shell_heat_loss(t, flow, 1.0, 26.0, insulation_thickness=ins)
    warm = shell_heat_loss(t, flow, 1.0, 26.0, insulation_thickness=ins,
                           outer_guess=cold.outer_surface_temperature_c + shift)
    assert np.allclose(warm.outer_surface_temperature_c, cold.outer_surface_temperature_c, rtol=0, atol=1e-8)
    assert np.allclose(warm.heat_loss, cold.heat_loss, rtol=1e-9)


def test_law_cache_returns_the_evaluation_of_the_same_inputs():
    d = Simulation("song2003_ottawa").thermal_dryer()
    law = d.laws[0]
    n = law.P.size
    mp, x = np.full(n, 5.0), np.full(n, 0.01)
    a = d._law_values(law, mp, x, 0.0)
    b = d._law_values(law, mp.copy(), x.copy(), 0.0)
    assert a is b
    c = d._law_values(law, mp * 1.01, x, 0.0)
    ref = law.evaluate(mp * 1.01, x, rpm=d.rpm, fouling=0.0)
    for k in ref:
        assert np.array_equal(np.asarray(c[k]), np.asarray(ref[k]))
    assert d._law_values(law, mp, x, 0.0) is a          # two entries kept: the base state survives
    assert d._law_values(law, mp, x, 0.5) is not a      # fouling is part of the key


def test_repeated_steady_states_are_identical():
    d = Simulation("lee2008_invicta").thermal_dryer()
    z1 = d.steady_state().state
    z2 = d.steady_state().state
    assert np.max(np.abs(z1 - z2) / np.maximum(np.abs(z1), 1e-12)) < 1e-8
    assert z1 == pytest.approx(z2, rel=1e-8)

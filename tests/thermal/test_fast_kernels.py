"""Issue 16 (part 1): kernels made cheaper give the numbers of the slower forms."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer.thermal import burner as B
from rotarydryer.thermal import radiation as rad


@settings(max_examples=60, deadline=None)
@given(t=st.floats(60.0, 720.0), ac=st.floats(0.5, 30.0), ad=st.floats(0.0, 60.0), ta=st.floats(-15.0, 60.0),
       y=st.floats(0.0, 0.08), loss=st.floats(0.0, 0.4))
def test_closed_form_fuel_rate_equals_the_bracketed_search(t, ac, ad, ta, y, loss):
    kw = dict(air_temperature_c=ta, air_humidity=y, heat_loss_fraction=loss)

    def run():
        try:
            return B.fuel_rate_for_temperature(t, ac, ad, **kw)
        except ValueError as exc:
            return str(exc)
    fast = run()
    with pytest.MonkeyPatch.context() as m:
        m.setattr(B, "_fuel_rate_in_range", lambda *a, **k: None)
        slow = run()
    if isinstance(slow, str):
        assert fast == slow                    # the same error message
    else:
        assert fast == pytest.approx(slow, rel=1e-10, abs=2e-12)   # the search stops at 1e-12 kg/s
        gas = B.combustion_chamber(fast, ac, ad, **kw)
        assert float(gas.temperature_c) == pytest.approx(t, abs=1e-6)


def test_no_fuel_for_the_air_temperature():
    """A target equal to the air temperature needs no fuel (the bracketed search had no bracket)."""
    for ac, ad in ((0.5, 2.0), (1.5, 0.0)):
        assert B.fuel_rate_for_temperature(60.0, ac, ad, air_temperature_c=60.0, air_humidity=0.0) == 0.0
        assert B._fuel_rate_scalar(60.0, ac, ad, air_temperature_c=np.array([60.0]), air_humidity=0.0) == 0.0  # bracketed path


def _emissivity_all_anchors(t_k, p_h2o, p_co2, path):
    """The WSGG mixture rule with every anchor set evaluated (the form before the speed-up)."""
    ph, pc = p_h2o / rad.ATM, p_co2 / rad.ATM
    pa = ph + pc
    fc = np.where(pa > 0, pc / np.where(pa > 0, pa, 1.0), 0.0)
    def absorption(n):
        pl = (ph if n == "h2o" else pc if n == "co2" else pa) * path
        return [1.0 - np.exp(-kappa * pl) for kappa in rad._SMITH[n][0]]

    vals = [rad._wsgg(n, t_k, absorption(n)) for n, _ in rad._ANCHORS]
    xs = [x for _, x in rad._ANCHORS]
    out = np.zeros(np.broadcast(fc, *vals).shape)
    for k in range(len(xs) - 1):
        w = (fc - xs[k]) / (xs[k + 1] - xs[k])
        seg = (fc >= xs[k]) & ((fc < xs[k + 1]) | ((k == len(xs) - 2) & (fc <= xs[k + 1])))
        out = np.where(seg, (1 - w) * vals[k] + w * vals[k + 1], out)
    return np.clip(out, 0.0, 1.0)


@settings(max_examples=60, deadline=None)
@given(t=st.floats(300.0, 2000.0), ph=st.lists(st.floats(0.0, 4e4), min_size=1, max_size=6),
       pc=st.floats(0.0, 3e4), path=st.floats(0.1, 5.0))
def test_emissivity_evaluates_only_the_bracketing_anchors(t, ph, pc, path):
    ph = np.array(ph)
    # the compiled kernel (numba) sums in the same order; exp may differ in the last bit
    np.testing.assert_allclose(rad._emissivity(t, ph, pc, path), _emissivity_all_anchors(t, ph, pc, path),
                               rtol=1e-13, atol=1e-15)


def test_emissivity_at_a_fixed_composition_equals_the_full_evaluation():
    """A shell solve prepares the gas composition once (_wsgg_paths) and evaluates many wall temperatures."""
    ph, pc = np.array([5e3, 9e3, 2e4]), 1.1e3
    paths = rad._wsgg_paths(ph, pc, 3.7)
    for t in (np.array([400.0, 600.0, 900.0]), np.array([[350.0, 500.0, 700.0], [351.0, 501.0, 701.0]])):
        np.testing.assert_allclose(rad._emissivity_at(t, paths), rad._emissivity(t, ph, pc, 3.7), rtol=1e-13)
        np.testing.assert_array_equal(rad._emissivity_at(t, rad._wsgg_paths_numpy(ph, pc, 3.7)),
                                      _emissivity_all_anchors(t, ph, pc, 3.7))


def test_emissivity_anchor_points_and_pure_gases():
    for ph, pc in ((1e4, 0.0), (0.0, 1e4), (2e4, 1e4), (1e4, 1e4), (0.0, 0.0)):
        np.testing.assert_allclose(rad._emissivity(1000.0, ph, pc, 1.0), _emissivity_all_anchors(1000.0, ph, pc, 1.0),
                                   rtol=1e-13, atol=1e-15)


@pytest.mark.parametrize("field, value, key", [("scale_conductivity", 0.0, "shell.scale_conductivity"),
                                               ("insulation_conductivity", -1.0, "shell.insulation_conductivity"),
                                               ("co2_mole_fraction", 0.5, "gas.co2_mole_fraction")])
def test_shell_settings_checked_once_where_they_enter(field, value, key):
    """The dryer's shell solves skip the checks of shell_heat_loss: its settings are checked at construction."""
    from rotarydryer.thermal.dryer import ThermalSettings

    with pytest.raises(ValueError, match=key):
        ThermalSettings(gas_flow=10.0, gas_inlet_temperature=200.0, **{field: value}).validate()


def test_trusted_shell_call_equals_the_checked_one():
    from rotarydryer.thermal.shell import shell_heat_loss

    tg = np.array([480.0, 300.0, 150.0])
    kw = dict(gas_humidity=np.array([0.03, 0.08, 0.12]), insulation_thickness=0.05, scale_thickness=0.01)
    a = shell_heat_loss(tg, 20.0, 0.5, 26.0, **kw)
    b = shell_heat_loss(tg, 20.0, 0.5, 26.0, _trusted=True, **kw)
    np.testing.assert_array_equal(a.heat_loss, b.heat_loss)

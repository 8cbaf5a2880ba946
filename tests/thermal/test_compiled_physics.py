"""Issue 16: the compiled shell network and gas-solids transfer (numba) give the numbers of their NumPy
references, and the shipped steady states are the same with the compiled kernels on and off."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from rotarydryer import _jit
from rotarydryer.properties import _kernels
from rotarydryer.thermal import balances as bal
from rotarydryer.thermal import shell as sh
from rotarydryer.thermal.drying import DryingKinetics

pytestmark = pytest.mark.skipif(not _jit.available(), reason="compiled kernels off (no numba or ROTARYDRYER_JIT=0)")

KINETICS = (DryingKinetics("ajayi2011"),
            DryingKinetics("constant_falling", critical_moisture=0.1, equilibrium_moisture=0.01),
            DryingKinetics("characteristic_curve", critical_moisture=0.12, equilibrium_moisture=0.02, exponent=1.7),
            DryingKinetics("characteristic_curve", critical_moisture=0.12, curve=((0.0, 0.5, 1.0), (0.0, 0.8, 1.0))))


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31), radius=st.floats(0.1, 3.0), scale=st.sampled_from([0.0, 0.01]),
       insulation=st.sampled_from([0.0, 0.08]), wind=st.sampled_from([0.0, 4.0]), ambient=st.floats(-20.0, 45.0),
       guess=st.sampled_from([None, 0.0, 2.0, 40.0]))
@example(seed=74483746, radius=0.10546875, scale=0.01, insulation=0.08, wind=4.0, ambient=0.0, guess=2.0)
def test_shell_network_equals_shell_heat_loss(seed, radius, scale, insulation, wind, ambient, guess):
    """The same root to its 1e-9 K tolerance (Newton stops per element, not for all at once), from a guess
    or bracketed, for bare, scaled, lagged and wind-swept shells of any size."""
    rng = np.random.default_rng(seed)
    n = 12
    tg = rng.uniform(ambient + 1.0, 600.0, n)
    tg[:3] = ambient + np.array([0.05, 1.0, 5.0])    # gas near ambient: tiny, steep losses
    # gas mass fluxes of 0.1-20 kg/(m2 s) through the drum (velocities up to about 30 m/s); beyond that the
    # inside coefficient is so steep that 1e-9 K of root tolerance moves a loss of a watt by 1e-5 of it
    y, seg = rng.uniform(0.0, 0.3, n), rng.uniform(0.05, 2.0, n)
    mg = rng.uniform(0.1, 20.0, n) * np.pi * radius**2
    kw = dict(gas_humidity=y, co2_mole_fraction=0.011, inner_radius=radius, shell_thickness=0.026 * radius,
              scale_thickness=scale * radius, scale_conductivity=1.0, insulation_thickness=insulation,
              insulation_conductivity=0.07, pressure=101325.0, wind_speed=wind, ambient_humidity=0.012)
    want = sh.shell_heat_loss(tg, mg, seg, ambient, _trusted=True, **kw)     # bracketed: the reference root
    start = None if guess is None else want.outer_surface_temperature_c + rng.normal(0.0, guess, n)
    loss, outer, slope = sh._shell_loss_compiled(tg, mg, seg, ambient, outer_guess=start, **kw)
    np.testing.assert_allclose(outer, want.outer_surface_temperature_c, rtol=0, atol=2e-9)
    # the next solve of a solver nearby starts from these temperatures and their last Newton slopes
    assert slope.shape == outer.shape and (guess is not None or np.isnan(slope).all())   # NaN: bracketed
    moved = tg + rng.uniform(0.0, 2.0, n)
    near = sh.shell_heat_loss(moved, mg, seg, ambient, _trusted=True, **kw)
    _, outer2, _ = sh._shell_loss_compiled(moved, mg, seg, ambient, outer_guess=outer, slope_guess=slope, **kw)
    np.testing.assert_allclose(outer2, near.outer_surface_temperature_c, rtol=0, atol=2e-9)
    # the loss is the mean of the inside and outside fluxes at the root, which differ there by the network's
    # energy_balance_error (a steep inside coefficient: small drum, large gas flow): where the gas is 20 K or
    # more above ambient the losses agree to 1e-8 plus that; nearer, the inside flux moves by 1e-9 K times
    # its slope (up to 1e-6 of a loss of a few watts; compared with the drum's largest loss)
    # (or a billionth of the drum's largest loss: a lagged stage of a 0.1 m drum loses 1.76 W beside 709 W, and its
    # 1e-9 K of root moves that by 6e-8 W, 3.5e-8 of it; found by a CI run)
    far = tg >= ambient + 20.0
    np.testing.assert_allclose(loss[far], want.heat_loss[far], rtol=1e-8 + 2 * want.energy_balance_error,
                               atol=1e-9 * float(np.max(want.heat_loss)))
    np.testing.assert_allclose(loss[~far], want.heat_loss[~far], rtol=1e-6, atol=1e-8 * np.max(want.heat_loss))


def test_shell_kernel_declines_gas_below_ambient():
    kw = dict(gas_humidity=0.05, co2_mole_fraction=0.011, inner_radius=1.9, shell_thickness=0.05,
              scale_thickness=0.0, scale_conductivity=1.0, insulation_thickness=0.0, insulation_conductivity=0.07,
              pressure=101325.0)
    assert sh._shell_loss_compiled(np.array([300.0, 20.0]), 30.0, 1.0, 26.0, **kw) is None
    assert sh._shell_loss_compiled(np.array([300.0, np.nan]), 30.0, 1.0, 26.0, **kw) is None
    assert sh._shell_loss_compiled(np.array([300.0, 200.0]), 30.0, 1.0, 26.0, **kw) is not None


def _numpy_transfer(monkeypatch, *args):
    with monkeypatch.context() as m:
        m.setattr(bal, "_stage_transfer_compiled", lambda *a, **k: None)
        return bal._stage_transfer(*args)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31), kinetics=st.sampled_from(KINETICS), batch=st.booleans())
def test_stage_transfer_equals_its_numpy_form(seed, kinetics, batch):
    """Evaporation, convection and radiation of each stage, over and beyond the clipped ranges (trial
    states of the solvers), every kinetics method; a batch (k, n) with per-stage particle sizes."""
    rng = np.random.default_rng(seed)
    shape = (3, 9) if batch else (9,)
    a, x = rng.uniform(0.0, 200.0, shape), rng.uniform(-0.02, 0.3, shape)
    ts, tg = rng.uniform(-5.0, 104.0, shape), rng.uniform(-10.0, 620.0, shape)
    y, fg = rng.uniform(-0.01, 0.32, shape), rng.uniform(0.5, 40.0, shape)
    dp = rng.uniform(0.001, 0.02, shape[-1])
    args = (a, x, ts, tg, y, fg, dp, 1.95, kinetics, "physical", 101325.0, 0.011, 0.9, 2e-3, 0.95 * 3.9)
    got = bal._stage_transfer(*args)
    with pytest.MonkeyPatch.context() as m:
        want = _numpy_transfer(m, *args)
    for g, w in zip(got, want):
        assert g.shape == shape
        np.testing.assert_allclose(g, w, rtol=1e-13, atol=1e-13 * np.max(np.abs(w)))


def test_transfer_kernel_leaves_other_bases_to_numpy():
    args = (np.ones(3), np.full(3, 0.1), np.full(3, 40.0), np.full(3, 300.0), np.full(3, 0.05), np.full(3, 10.0),
            np.full(3, 0.01), 1.95)
    tail = (101325.0, 0.011, 0.9, 2e-3, 3.7)
    assert bal._stage_transfer_compiled(*args, DryingKinetics("ajayi2011"), *tail) is not None
    assert bal._stage_transfer_compiled(*args, DryingKinetics("ajayi2011", basis="total_pressure"), *tail) is None
    assert bal._stage_transfer_compiled(*args, DryingKinetics("ajayi2011", saturation_method="antoine_ajayi2011"),
                                        *tail) is None


def test_failing_shell_kernel_falls_back_with_a_warning(monkeypatch):
    from rotarydryer import Simulation

    d = Simulation("song2003_ottawa").thermal_dryer()
    S, W, T, Tg, Y = d.split(d.initial_state())
    want = d.physical_shell_loss(Tg, Y)

    def broken(*args):
        raise RuntimeError("no LLVM here")
    monkeypatch.setattr(_jit, "_DISABLED", _jit._DISABLED)
    monkeypatch.setitem(_kernels._compiled, "shell", broken)
    with pytest.warns(RuntimeWarning, match="compiled kernels disabled"):
        got = d.physical_shell_loss(Tg, Y)
    np.testing.assert_allclose(got, want, rtol=1e-8)


_STEADY = """
import json, sys
from rotarydryer import Simulation, _jit
out = {"enabled": _jit.enabled()}
for case, ov in (("ajayi2011_mmg", {"operating.test": 4}), ("ajayi2011_mmg", {"operating.test": 2}),
                 ("lee2008_invicta", {}), ("song2003_ottawa", {})):
    ss = Simulation(case, ov).thermal_dryer().steady_state()
    s = ss.summary(with_fuel=False)
    out[case + str(ov)] = {k: v for k, v in s.items() if isinstance(v, float) and k not in ("solver_time_s",)}
    out[case + str(ov) + "_state"] = ss.state.tolist()
json.dump(out, sys.stdout)
"""


def test_shipped_steady_states_equal_with_the_kernels_on_and_off():
    """Issue 16: results equal to 1e-8 relative whichever way the physics is evaluated."""
    def run(jit):
        env = dict(os.environ, ROTARYDRYER_JIT="1" if jit else "0")
        r = subprocess.run([sys.executable, "-c", _STEADY], capture_output=True, text=True, env=env, check=True)
        return json.loads(r.stdout)
    on, off = run(True), run(False)
    assert on.pop("enabled") is True and off.pop("enabled") is False
    for key in on:
        if key.endswith("_state"):
            a, b = np.array(on[key]), np.array(off[key])
            np.testing.assert_allclose(a, b, rtol=1e-8, atol=1e-10 * np.max(np.abs(b)), err_msg=key)
            continue
        for name, value in on[key].items():
            # the heat duties' closure is the balance residual (W): rounding, within 1e-9 of the release
            floor = 1e-9 * on[key]["heat_release_W"] if name == "heat_duty_closure_W" else 1e-12
            assert value == pytest.approx(off[key][name], rel=1e-8, abs=floor), f"{key} {name}"


def test_transfer_kernel_leaves_per_stage_parameters_and_subclasses_to_numpy(monkeypatch):
    """The public stage_transfer accepts per-stage arrays of its scalar parameters (NumPy broadcasts
    them), and a DryingKinetics subclass may override its rate: the kernel declines both."""
    n = 3
    args = (np.ones(n), np.full(n, 0.1), np.full(n, 40.0), np.full(n, 300.0), np.full(n, 0.05), np.full(n, 10.0),
            np.full(n, 0.01))
    kin = DryingKinetics("ajayi2011")
    for radius, pressure in ((np.array([1.0, 1.5, 2.0]), 101325.0), (1.95, np.array([101325.0, 1e5, 9e4]))):
        assert bal._stage_transfer_compiled(*args, radius, kin, pressure, 0.011, 0.9, 2e-3, 3.7) is None
        got = bal.stage_transfer(*args, radius, kin, pressure=pressure)
        with monkeypatch.context() as m:
            m.setattr(bal, "_stage_transfer_compiled", lambda *a, **k: None)
            want = bal.stage_transfer(*args, radius, kin, pressure=pressure)
        for g, w in zip(got, want):
            np.testing.assert_array_equal(g, w)

    class Faster(DryingKinetics):
        def _rate(self, *a, **k):
            return 2.0 * super()._rate(*a, **k)
    assert bal._stage_transfer_compiled(*args, 1.95, Faster("ajayi2011"), 101325.0, 0.011, 0.9, 2e-3, 3.7) is None

"""Compiled trajectory forward step (issue 32): ``FlightedSectionLaw._trajectory_rates`` against its NumPy reference.

The reference is `FlightedSectionLaw._trajectory_step` (Sherritt's curtain velocity ratio, the forward-step table,
the cap at the cells' reach and the split into C_F, C_B, C_R and the second-cell fractions, Lee (2008) Eq. 2.14 and
3.3-3.8) followed by `rates_of`. Bound: 1e-12 relative, on Song's pilot law and on variants that take the other
branches (a fixed velocity ratio, a step factor, a fitted backmix, steps beyond one cell both ways); Song's steady
state is the same with the kernel on and off.
"""

import dataclasses

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer import Simulation, _jit
from rotarydryer.transport import _step_kernel
from rotarydryer.transport.sections import FlightedSectionLaw

pytestmark = pytest.mark.skipif(not _jit.available(), reason="compiled kernels off (numba not installed, or ROTARYDRYER_JIT=0)")


@pytest.fixture(scope="module")
def song_law():
    d = Simulation("song2003_ottawa").thermal_dryer()
    law = next(law for law in d.laws if isinstance(law, FlightedSectionLaw) and law.trajectory)
    return law


def _variant(law, **changes):
    """The law with ``changes`` to its spec (``gas`` a dict of changes to its CurtainGas)."""
    spec = law.spec
    gas = changes.pop("gas", None)
    if gas:
        changes["gas"] = dataclasses.replace(spec.gas, **gas)
    return FlightedSectionLaw(dataclasses.replace(spec, **changes), law.material, law.rpm, law.slope, law.P,
                              law.assumed_moisture)


def _compare(law, tp, ta, h, fm):
    got = law._trajectory_rates(tp, ta, h, fm)
    assert got is not None
    want = law.rates_of(law._trajectory_step(tp, ta, h, fm))
    assert set(got) == set(want)
    for name in want:
        np.testing.assert_allclose(got[name], want[name], rtol=1e-12, atol=1e-15, err_msg=name)
    return got


def _cells(law, rng, k=None, spread=1.0):
    """Passive times, fall times, fall heights and flight masses around the law's own cells (a batch of k)."""
    n = law.n
    shape = (n,) if k is None else (k, n)
    tp = rng.uniform(1.0, 8.0, shape)
    ta = rng.uniform(0.1, 1.0, shape)
    h = rng.uniform(0.0, 2.0 * spread * law.dl / max(law.sin_t, 1e-3), shape) * rng.uniform(0.0, 1.0, shape)
    fm = rng.uniform(0.0, 50.0, shape) * rng.choice([0.0, 1e-9, 1.0], shape, p=[0.05, 0.05, 0.9])
    return tp, ta, h, fm


@pytest.mark.parametrize("variant", ["song", "fixed_ratio", "step_factor", "backmix", "no_gas_speed"])
def test_kernel_equals_the_numpy_step(song_law, variant):
    law = {"song": lambda: song_law,
           "fixed_ratio": lambda: _variant(song_law, gas={"velocity_ratio": 0.35}),
           "step_factor": lambda: _variant(song_law, gas={"step_factor": 1.7}),
           "backmix": lambda: _variant(song_law, backmix=0.2),
           "no_gas_speed": lambda: _variant(song_law, gas={"velocity_ratio": 0.0})}[variant]()
    rng = np.random.default_rng(3)
    for spread in (0.3, 1.0, 3.0):         # steps inside one cell, into the next, capped at the reach
        got = _compare(law, *_cells(law, rng, spread=spread))
    assert ("forward_far" in got) == (law.spec.backmix == 0.0)
    _compare(law, *_cells(law, rng, k=4))         # a Jacobian's batch (k, n)


@given(seed=st.integers(0, 2**31 - 1), ratio=st.one_of(st.none(), st.floats(0.0, 1.0)),
       factor=st.floats(0.5, 3.0), backmix=st.sampled_from([0.0, 0.1, 0.5]))
@settings(max_examples=40, deadline=None)
def test_kernel_equals_the_numpy_step_for_random_laws(song_law, seed, ratio, factor, backmix):
    law = _variant(song_law, backmix=backmix, gas={"velocity_ratio": ratio, "step_factor": factor})
    _compare(law, *_cells(law, np.random.default_rng(seed), spread=2.0))


def test_not_finite_or_kernels_off_fall_back(song_law, monkeypatch):
    rng = np.random.default_rng(5)
    tp, ta, h, fm = _cells(song_law, rng)
    ta[2] = np.nan
    assert song_law._trajectory_rates(tp, ta, h, fm) is None       # evaluate() then composes the NumPy step
    monkeypatch.setattr(_step_kernel, "compiled", lambda: None)
    assert song_law._trajectory_rates(tp, ta, h, fm) is None


def test_song_steady_state_is_the_same_without_the_kernel(song_law, monkeypatch):
    d = Simulation("song2003_ottawa").thermal_dryer()
    on = d.steady_state()
    monkeypatch.setattr(_step_kernel, "compiled", lambda: None)
    off = Simulation("song2003_ottawa").thermal_dryer().steady_state()
    np.testing.assert_allclose(on.state, off.state, rtol=1e-10, atol=1e-12)

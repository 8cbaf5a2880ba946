"""Compiled cell kernel (issue 16 part 1): ``GeometryTable.cell_values`` against its NumPy reference.

The reference is the composition the section laws use without numba: the tabulated design-load
area, the loading factor (Lee (2008) Eq. 4.22 inverted, with and without the smoothing of its
kinks) and the cascade. Bound: 1e-12 relative on every shipped drum, every design-load method,
both passive-time branches, with slopes and speeds; the section laws give the same coefficients
with the kernel on and off (a subprocess with ``ROTARYDRYER_JIT=0``).
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from rotarydryer import _jit
from rotarydryer.geometry import FlightedDrum, TwoSectionFlight
from rotarydryer.geometry.presets import drum_presets
from rotarydryer.geometry.tabulated import PHI_RANGE, geometry_table

pytestmark = pytest.mark.skipif(not _jit.available(), reason="compiled kernels off (numba not installed, or ROTARYDRYER_JIT=0)")

PRESETS = drum_presets()
METHODS = ("lee2008", "ajayi2011", "porter1963", "kelly1977")


def _drum(e):
    return FlightedDrum(e["radius"], int(e["n_flights"]), TwoSectionFlight(e["s1"], e["s2"], e["alpha1"], e["alpha2"]))


def _reference(t, phi, rho, mp, *, length, fouling, method, smoothing, rpm, slope, branch, fixed=False):
    """The section law's NumPy composition (FlightedSectionLaw.evaluate without the kernel)."""
    des = rho * length * t.design_load_area(phi, method=method) * (1.0 - fouling)
    if fixed:
        f = np.ones_like(phi)
    else:
        f = np.clip(t.loading_factor(np.clip(mp / des, 1e-6, None), phi, smoothing), 1e-6, 1.0)
    c = t.cascade(phi, f, rpm=rpm, slope=slope, passive_time_branch=branch)
    return des, f, c.passive_time, c.mean_fall_height, c.mean_fall_time


def _compare(t, phi, rho, mp, **kw):
    got = t.cell_values(phi, rho, mp, length=kw["length"], fouling=kw["fouling"], method=kw["method"],
                        smoothing=kw["smoothing"], rpm=kw["rpm"], slope=kw["slope"],
                        passive_time_branch=kw["branch"], fixed_loading=kw.get("fixed", False))
    assert got is not None
    want = _reference(t, phi, rho, mp, **kw)
    for name, a, b in zip(("design load", "loading factor", "passive time", "fall height", "fall time"), got, want):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-15, err_msg=name)


@pytest.mark.parametrize("preset", sorted(PRESETS))
@pytest.mark.parametrize("smoothing", [0.0, 1e-3])
def test_kernel_equals_the_numpy_composition_on_every_shipped_drum(preset, smoothing):
    t = geometry_table(_drum(PRESETS[preset]))
    rng = np.random.default_rng(7)
    n = 3000
    phi = rng.uniform(*PHI_RANGE, n)
    rho = rng.uniform(600.0, 2500.0, n)
    des = rho * 0.5 * t.design_load_area(phi)
    mp = des * rng.uniform(0.0, 1.6, n)          # under-, design- and over-loaded cells
    mp[:20] = 0.0                                 # empty
    mp[20:60] = des[20:60] * (1.0 + rng.uniform(-1e-4, 1e-4, 40))   # at the design load (the kink)
    for i, method in enumerate(METHODS):
        branch = "eq3.4" if i % 2 == 0 else "lee2008_ch7"
        _compare(t, phi, rho, mp, length=0.5, fouling=0.1 * i, method=method, smoothing=smoothing,
                 rpm=1.0 + i, slope=(-2.0, 0.0, 2.8, 4.0)[i], branch=branch)
    _compare(t, phi, rho, mp, length=0.5, fouling=0.0, method="lee2008", smoothing=smoothing, rpm=3.0, slope=1.0,
             branch="eq3.4", fixed=True)


@settings(max_examples=15, deadline=None)
@given(radius=st.floats(0.3, 2.5), n_flights=st.integers(8, 36), s1=st.floats(0.03, 0.12), ratio=st.floats(0.5, 1.5),
       alpha2=st.floats(100.0, 150.0), seed=st.integers(0, 2**16), smoothing=st.sampled_from([0.0, 1e-3, 1e-2]))
def test_kernel_equals_the_numpy_composition_on_random_drums(radius, n_flights, s1, ratio, alpha2, seed, smoothing):
    try:
        drum = FlightedDrum(radius, n_flights, TwoSectionFlight(s1 * radius, ratio * s1 * radius, 90.0, alpha2))
    except ValueError:          # overlapping flights, outside Lee's four-phase model
        assume(False)
    t = geometry_table(drum)
    rng = np.random.default_rng(seed)
    phi = rng.uniform(*PHI_RANGE, 200)
    rho = rng.uniform(600.0, 2500.0, 200)
    mp = rho * 0.3 * t.design_load_area(phi) * rng.uniform(0.0, 1.5, 200)
    _compare(t, phi, rho, mp, length=0.3, fouling=0.0, method="lee2008", smoothing=smoothing, rpm=2.0, slope=2.0,
             branch="eq3.4")


def test_outside_the_table_the_kernel_declines():
    t = geometry_table(_drum(PRESETS[sorted(PRESETS)[0]]))
    phi = np.array([30.0, PHI_RANGE[1] + 1.0])
    assert t.cell_values(phi, 1000.0, 1.0, length=1.0, rpm=3.0) is None   # the caller composes the methods


_LAWS = """
import json, sys
import numpy as np
from rotarydryer import Simulation, _jit
out = {"enabled": _jit.enabled()}
for case, ov in (("ajayi2011_mmg", {"operating.test": 4}), ("lee2008_invicta", {}), ("song2003_ottawa", {})):
    d = Simulation(case, ov).thermal_dryer()
    z = d.initial_state()
    S, W, T, Tg, Y = d.split(z)
    m = S + W
    for i, law in enumerate(d.laws):
        mp = m[law.P] * np.linspace(0.2, 1.4, law.n)
        x = W[law.P] / m[law.P]
        v = law.evaluate(mp, x, rpm=d.rpm, smoothing=1e-3)
        out[f"{case}{i}"] = {k: np.asarray(a).tolist() for k, a in v.items()}
    out[case + "_rhs"] = d.rhs(0.0, z).tolist()
json.dump(out, sys.stdout)
"""


def _laws(jit):
    env = dict(os.environ, ROTARYDRYER_JIT="1" if jit else "0")
    r = subprocess.run([sys.executable, "-c", _LAWS], capture_output=True, text=True, env=env, check=True)
    return json.loads(r.stdout)


def test_section_laws_and_residuals_equal_with_the_kernel_on_and_off():
    on, off = _laws(True), _laws(False)
    assert on.pop("enabled") is True and off.pop("enabled") is False
    assert on.keys() == off.keys()
    for key in on:
        if key.endswith("_rhs"):
            a, b = np.array(on[key]), np.array(off[key])
            np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-12 * np.max(np.abs(b)), err_msg=key)
            continue
        assert on[key].keys() == off[key].keys()
        for name in on[key]:
            np.testing.assert_allclose(on[key][name], off[key][name], rtol=1e-12, atol=0, err_msg=f"{key} {name}")


def test_a_kernel_that_fails_falls_back_to_numpy_with_a_warning(monkeypatch):
    from rotarydryer import Simulation
    from rotarydryer.geometry import _cell_kernel

    d = Simulation("song2003_ottawa", {"transport.parameter_source": "per_test"}).thermal_dryer()  # the fitted step
    law = d.laws[0]
    mp, x = np.full(law.n, 0.5), np.full(law.n, 0.03)
    want = law.evaluate(mp, x, rpm=d.rpm)

    def broken(*args):
        raise RuntimeError("no LLVM here\nmore detail")
    monkeypatch.setattr(_cell_kernel, "compiled", lambda: broken)
    monkeypatch.setattr(_jit, "_DISABLED", _jit._DISABLED)    # restored after the test
    with pytest.warns(RuntimeWarning, match="compiled kernels disabled .RuntimeError: no LLVM here.; using NumPy"):
        got = law.evaluate(mp, x, rpm=d.rpm)
    assert not _jit.enabled()
    for k in want:
        np.testing.assert_allclose(got[k], want[k], rtol=1e-12, atol=0, err_msg=k)


def test_kernel_declines_what_the_reference_would_refuse():
    """Inputs the table's methods reject with a message (non-finite loading, rpm <= 0, slope beyond
    45 deg) give None, so the caller's NumPy composition names the problem."""
    t = geometry_table(_drum(PRESETS[sorted(PRESETS)[0]]))
    phi = np.array([30.0, 40.0])
    assert t.cell_values(phi, 1000.0, np.array([1.0, np.nan]), length=1.0, rpm=3.0) is None
    assert t.cell_values(phi, 1000.0, 1.0, length=1.0, rpm=0.0) is None
    assert t.cell_values(phi, 1000.0, 1.0, length=1.0, rpm=3.0, slope=50.0) is None
    assert t.cell_values(phi, 1000.0, 1.0, length=1.0, rpm=3.0) is not None
    # the fixed arguments are cached per (method, branch, slope): any number type for the slope, and a
    # choice that is not one is named (also when it cannot be a cache key)
    a = t.cell_values(phi, 1000.0, 1.0, length=1.0, rpm=3.0, slope=np.array(2.0))
    b = t.cell_values(phi, 1000.0, 1.0, length=1.0, rpm=3.0, slope=2)
    assert all(np.array_equal(x, y) for x, y in zip(a, b))
    for bad in (["lee2008"], "bogus"):
        with pytest.raises(ValueError, match="method"):
            t.cell_values(phi, 1000.0, 1.0, length=1.0, rpm=3.0, method=bad)


@pytest.mark.parametrize("env", [{"ROTARYDRYER_JIT": "0"}, {"NUMBA_DISABLE_JIT": "1"}])
def test_kernels_off_by_environment(env):
    """ROTARYDRYER_JIT=0, or numba's own NUMBA_DISABLE_JIT=1 (njit would then run plain Python loops,
    slower than NumPy), switch the compiled kernels off."""
    code = "from rotarydryer import _jit; print(_jit.enabled())"
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                       env=dict(os.environ, **env))
    assert r.stdout.strip() == "False"

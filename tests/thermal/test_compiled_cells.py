"""Issue 32 item 2: the cell balance of a dryer of one size class in one compiled pass
(`rotarydryer.properties._kernels._cell_balance_loop`, `ThermalDryer._rhs_compiled`) gives the residual of
the NumPy form (`ThermalDryer._rhs` without it) - single states, batches (the Jacobian's perturbations, with
the last single state's transfer reused) and every configuration the pass takes; the others keep the NumPy
form."""

import dataclasses
from importlib import resources

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from rotarydryer import Simulation, _jit
from rotarydryer.properties import _kernels, psd
from rotarydryer.thermal.dryer import ThermalDryer

MMG4 = {"operating.test": 4}
CASES = {
    "mmg": ("ajayi2011_mmg", MMG4),
    "mmg-regressions": ("ajayi2011_mmg", {**MMG4, "geometry.method": "ajayi2011_regressions"}),
    "mmg-no-kiln-bed": ("ajayi2011_mmg", {**MMG4, "thermal.kiln_bed_area": False}),
    "mmg-recycle": ("ajayi2011_mmg", {**MMG4, "gas.recycle_fraction": 0.2}),
    "mmg-uncoupled": ("ajayi2011_mmg", {**MMG4, "thermal.moisture_coupling": False}),
    "invicta": ("lee2008_invicta", {}),
    "mmg-counter-current": ("ajayi2011_mmg", {**MMG4, "gas.direction": "counter-current"}),
    "song": ("song2003_ottawa", {}),
}

pytestmark = pytest.mark.skipif(not _jit.available(), reason="compiled kernels not available here")


def _numpy_rhs(d, z, monkeypatch):
    with monkeypatch.context() as m:
        m.setattr(d, "_rhs_compiled", lambda z: None)
        return d._rhs(z)


def _assert_same(got, want):
    scale = np.maximum(np.abs(want), 1e-12 * np.max(np.abs(want)))
    assert np.all(np.isfinite(got))
    assert float(np.max(np.abs(got - want) / scale)) <= 1e-13


@pytest.fixture(scope="module", params=sorted(CASES))
def solved(request):
    case, ov = CASES[request.param]
    d = Simulation(case, ov).thermal_dryer()
    z = d.steady_state().state
    return d, z


def test_the_shipped_cases_take_the_compiled_pass(solved):
    d, _ = solved
    assert d._cell_plan() is not None


def test_single_states_equal_the_numpy_form(solved, monkeypatch):
    d, z = solved
    rng = np.random.default_rng(1)
    d.freeze_shell(z)
    try:
        for scale in (0.0, 1e-6, 1e-2, 0.3):
            x = z * (1.0 + scale * rng.standard_normal(z.size))
            got = d._rhs_compiled(x)
            assert got is not None
            _assert_same(got, _numpy_rhs(d, x, monkeypatch))
    finally:
        d.unfreeze_shell()


def test_the_exact_shell_loss_is_the_numpy_forms(solved, monkeypatch):
    d, z = solved
    d.unfreeze_shell()
    x = z * (1.0 + 1e-4 * np.random.default_rng(2).standard_normal(z.size))
    d._shell_outer = d._shell_slope = d._shell_memo = None      # the shell's Newton from the same start
    want = _numpy_rhs(d, x, monkeypatch)
    d._shell_outer = d._shell_slope = d._shell_memo = None
    _assert_same(d._rhs_compiled(x), want)


def test_a_batch_equals_its_states_and_the_numpy_batch(solved, monkeypatch):
    """A Jacobian's batch after a single state (whose transfer and gas properties it reuses where its inputs are
    the same) equals each state evaluated alone, and the NumPy form's batch."""
    d, z = solved
    d.freeze_shell(z)
    try:
        rng = np.random.default_rng(3)
        cols = [z.copy()]
        for _ in range(8):
            x = z.copy()
            j = rng.choice(d.n, size=int(rng.integers(1, 30)), replace=False)
            x[j] *= 1.0 + rng.uniform(-1e-3, 1e-3, j.size)
            cols.append(x)
        B = np.stack(cols, axis=1)
        d.rhs(0.0, z)                       # the base of the batch
        batch = d.rhs(0.0, B)
        alone = np.stack([d.rhs(0.0, B[:, j]) for j in range(B.shape[1])], axis=1)
        np.testing.assert_array_equal(batch, alone)
        d.rhs(0.0, z)
        with monkeypatch.context() as m:
            m.setattr(d, "_rhs_compiled", lambda z: None)
            want = d.rhs(0.0, B)
        _assert_same(batch, want)
    finally:
        d.unfreeze_shell()


@pytest.fixture(scope="module")
def user_dryer(tmp_path_factory):
    """The `rotarydryer new` template's dryer, solved."""
    path = tmp_path_factory.mktemp("user") / "dryer.toml"
    path.write_text((resources.files("rotarydryer.cases") / "templates" / "dryer.toml").read_text())
    d = Simulation(str(path)).thermal_dryer()
    return d, d.steady_state().state


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), spread=st.sampled_from([1e-8, 1e-4, 1e-1]))
def test_random_states_of_a_user_dryer_equal_the_numpy_form(user_dryer, seed, spread):
    d, z = user_dryer
    assert d._cell_plan() is not None
    x = z * (1.0 + spread * np.random.default_rng(seed).standard_normal(z.size))
    d.freeze_shell(z)
    try:
        got = d._rhs_compiled(x)
        d._rhs_compiled = lambda z: None
        try:
            want = d._rhs(x)
        finally:
            del d._rhs_compiled
        _assert_same(got, want)
    finally:
        d.unfreeze_shell()


def _with(d, **changes):
    s = dataclasses.replace(d.settings, **changes)
    return ThermalDryer(d.model, material=d.material, feed_rate=d.feed_rate, feed_moisture=d.feed_moisture, rpm=d.rpm,
                        radius=d.radius, sections=d.section_thermal, settings=s)


def test_configurations_the_pass_does_not_take_keep_the_numpy_form(monkeypatch):
    d = Simulation("song2003_ottawa").thermal_dryer()
    assert d._cell_plan() is not None
    two = _with(d, size_classes=psd.SizeClasses(diameters=(200e-6, 400e-6), fractions=(0.5, 0.5),
                                                 edges=(100e-6, 300e-6, 600e-6), source="two"), entrainment=False)
    dusty = _with(d, size_classes=psd.single_class(d.material.particle_diameter), entrainment=True)
    thesis = Simulation("ajayi2011_mmg", {**MMG4, "thermal.mode": "ajayi2011",
                                          "geometry.method": "ajayi2011_regressions"}).thermal_dryer()
    for other in (two, dusty, thesis):
        assert other._cell_plan() is None
        assert np.all(np.isfinite(other.rhs(0.0, other.initial_state())))
    monkeypatch.setattr(_jit, "_DISABLED", True)     # kernels off: the NumPy form
    off = Simulation("song2003_ottawa").thermal_dryer()
    assert off._cell_plan() is None


def test_the_kernel_argument_kinds_match_its_signature():
    import inspect

    params = inspect.signature(_kernels._cell_balance_loop).parameters
    assert len(_kernels._KINDS["cells"]) == len(params)


@pytest.mark.parametrize("smoothing", [0.0, 1e-3])
def test_the_trajectory_step_on_the_compiled_cascade_equals_the_numpy_form(monkeypatch, smoothing):
    """A section of the trajectory forward step takes the cells' design load and cascade from the compiled pass
    (`ExactGeometry.cell_values`) and the step through the gas from them: the coefficients of the NumPy form."""
    law = Simulation("song2003_ottawa").thermal_dryer().laws[0]
    assert law.trajectory and law._kernel_applies()
    lo, hi = law.material.wet_range()
    rng = np.random.default_rng(4)
    des = law.design_load(*law.properties(np.full(law.n, 0.5 * (lo + hi))))
    for _ in range(5):
        mp = des * rng.uniform(0.05, 2.0, law.n)
        x = rng.uniform(lo, hi, law.n)
        got = law.evaluate(mp, x, smoothing=smoothing)
        with monkeypatch.context() as m:
            m.setattr(law, "_kernel_applies", lambda: False)
            want = law.evaluate(mp, x, smoothing=smoothing)
        assert set(got) == set(want)
        for name in want:
            np.testing.assert_allclose(got[name], want[name], rtol=1e-12, atol=0.0, err_msg=name)


@pytest.mark.parametrize("change", [("moisture_coupling", False), ("design_load_smoothing", 0.0)])
def test_a_batch_after_a_setting_changed_in_place_equals_the_numpy_form(change, monkeypatch):
    """A Jacobian's batch right after a setting was changed in place (as a test or a study does), with no single
    state since: the kiln beds took the design loads of the last single state, evaluated at the old setting (found by
    review: residuals off up to 6-fold, Jacobian entries by 7.7e6 against 193), and a changed smoothing reused the
    section laws' coefficients of the old one in both forms. Both forms now give the Jacobian of a dryer that
    remembers nothing."""
    name, value = change
    d = Simulation("ajayi2011_mmg", MMG4).thermal_dryer()
    z = d.steady_state().state
    d.freeze_shell(z)
    ua, old = d._shell_ua, getattr(d.settings, name)

    def forget():
        d._reset_caches()
        d._shell_ua = ua

    setattr(d.settings, name, value)
    forget()
    f0 = d.rhs(0.0, z)
    want = d.jacobian(z, f0=f0).toarray()
    for compiled in (True, False):
        setattr(d.settings, name, old)
        forget()
        d.rhs(0.0, z)                          # a single state at the old setting: the base of the next batch
        setattr(d.settings, name, value)
        with monkeypatch.context() as m:
            if not compiled:
                m.setattr(d, "_rhs_compiled", lambda z: None)
            got = d.jacobian(z, f0=f0).toarray()
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * np.max(np.abs(want)), err_msg=str(compiled))


@pytest.fixture(scope="module")
def _step_dryers():
    _jit.long_runs()
    out = {}
    for name, (case, ov) in (("invicta", ("lee2008_invicta", {})),
                             ("song-3-classes-dust", ("song2003_ottawa", {
                                 "particle_size.classes": 3, "particle_size.entrainment": True,
                                 "particle_size.distribution": "lognormal", "particle_size.d50": 3e-4,
                                 "particle_size.sigma_g": 2.0}))):
        d = Simulation(case, ov).thermal_dryer()
        out[name] = (d, d.steady_state().state)
    return out


def _same_bits(got, want):
    """Equal values, NaN where NaN, and the same sign of every zero (np.testing takes -0.0 for 0.0)."""
    got, want = np.asarray(got, dtype=float), np.asarray(want, dtype=float)
    np.testing.assert_array_equal(got, want)
    assert np.array_equal(np.signbit(got) | np.isnan(got), np.signbit(want) | np.isnan(want))


@pytest.mark.parametrize("name", ["invicta", "song-3-classes-dust"])
@given(seed=st.integers(0, 2**32 - 1), size=st.sampled_from([1e-3, 0.3, 3.0]),
       special=st.sampled_from([None, "nan-z", "nan-dz", "nan-f", "inf-z", "inf-dz", "zeros", "humid"]))
@settings(max_examples=80, deadline=None)
def test_the_solver_steps_compiled_are_the_numpy_steps(_step_dryers, name, seed, size, special):
    """The steady-state solver's step kernels (`_step_radius_loop`, `_step_bounded_loop`, `_step_admissible_loop`,
    `_step_norm_loop`) give `_radius_step`, `_bounded_step`, `_admissible` and `_residual_norm` of the NumPy form bit
    for bit (the sign of a zero too), at states near and far from the solution, admissible or not, with a NaN or an
    infinity in the state, the step or the residual, signed zeros, and a gas near the humidity's bound."""
    d, z0 = _step_dryers[name]
    _jit.long_runs()
    if _kernels.compiled("step_norm") is None:
        pytest.skip("compiled kernels off")
    rng = np.random.default_rng(seed)
    sc = d._scale()
    z = z0 * (1 + rng.normal(size=z0.size) * size)
    dz = z0 * rng.normal(size=z0.size) * size
    f = rng.normal(size=z0.size) * sc
    k, ng = 3 * d.n_classes * d.n_tanks, d.n_gas
    i = rng.integers(z0.size)
    if special in ("nan-z", "nan-dz", "nan-f", "inf-z", "inf-dz"):
        arr = {"z": z, "dz": dz, "f": f}[special[4:]]
        arr[i] = np.nan if special.startswith("nan") else rng.choice([np.inf, -np.inf])
    elif special == "zeros":      # signed zeros in the state and the step (the bounds' ties)
        pick = rng.random(z0.size) < 0.3
        z[pick] = rng.choice([0.0, -0.0], size=pick.sum())
        dz[pick] = rng.choice([0.0, -0.0], size=pick.sum())
    elif special == "humid":      # humidities at and past the top of the admissible range
        hi_y = d._state_bounds()[4]
        z[k + ng:] = hi_y * (1 - rng.choice([0.0, 1e-12, 0.1], size=ng))
        dz[k + ng:] = hi_y * rng.normal(size=ng)

    def steps():
        return (d._bounded_step(z, dz), d._admissible(z), d._admissible(z0), d._residual_norm(f, z, sc),
                d._residual_norm(f, z, sc, 100.0), *d._radius_step(dz, sc))

    calls = []
    real_call = _kernels.call

    def spied(kernel, *args):
        calls.append(kernel)
        return real_call(kernel, *args)
    _kernels.call = spied
    try:
        got = steps()
    finally:
        _kernels.call = real_call
    assert {"step_bounded", "step_admissible", "step_norm", "step_radius"} <= set(calls) and _jit.enabled()
    real = _kernels.compiled
    try:
        _kernels.compiled = lambda kernel: None if kernel.startswith("step_") else real(kernel)
        want = steps()
    finally:
        _kernels.compiled = real
    _same_bits(got[0], want[0])
    assert got[1:3] == want[1:3] and got[2]
    _same_bits(got[3:5], want[3:5])
    _same_bits(got[5], want[5])
    assert got[6] == want[6]

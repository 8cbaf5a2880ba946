"""Issue 16 (part 1): the coupled solver reuses exact work — the section-law coefficients of
unchanged inputs and a warm-started shell root — and gives the same numbers."""

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from rotarydryer import Simulation
from rotarydryer.thermal.dryer import ThermalDryer
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


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), off=st.floats(0.3, 0.4))
@example(seed=892176, off=0.3046875)        # a draw whose chord steps end in 25 (2n + 1) steps
def test_secant_corrected_chord_steps_converge_faster_to_the_same_root(seed, off):
    """Broyden's corrections of chord steps on a kept, stale factorisation (Kelley (1995) Alg. 7.3.1, used
    by a study's runs that start from a nearby run's factorisation): on a linear system they reach the
    root, which the plain chord steps approach only linearly (or not at all), within Gay's 2n bound."""
    from rotarydryer.thermal.dryer import _broyden_step

    rng = np.random.default_rng(seed)
    n = 12
    A = np.eye(n) * 3.0 + rng.normal(0.0, 0.3, (n, n))
    M = A + off * rng.normal(0.0, 1.0, (n, n))          # the stale matrix of the chord steps
    b = rng.normal(0.0, 1.0, n)
    root = np.linalg.solve(A, b)

    def run(secant):
        x, steps = np.zeros(n), []
        for k in range(1, 200):
            f = b - A @ x
            if np.linalg.norm(f) < 1e-12 * np.linalg.norm(b):
                return x, k
            dz = np.linalg.solve(M, f)
            if secant and steps:
                corrected = _broyden_step(steps, dz)
                dz = dz if corrected is None else corrected
                steps = steps if corrected is not None else []
            steps.append(dz)
            x = x + dz
        return x, 200

    with np.errstate(over="ignore", invalid="ignore"):      # a chord iteration may diverge (kc = 200)
        xc, kc = run(False)
    xb, kb = run(True)
    assert np.allclose(xb, root, rtol=0, atol=1e-9)
    # on a linear problem Broyden's method ends in at most 2n steps (Gay 1979); the chord steps here mostly
    # need more (in 98 % of these draws; some diverge), so a correction that did nothing would fail the bound
    assert kb <= 2 * n + 1 and kb <= kc


def test_warm_started_study_runs_land_on_the_cold_steady_state(monkeypatch):
    """A run started from a nearby run's state and factorisation (chord steps with secant corrections)
    lands on the steady state of its own cold start, to the convergence test's tolerance, for less work:
    residuals plus Jacobians at about 2.6 residuals each (MMG's; its chord steps may be more iterations)."""
    near = Simulation("ajayi2011_mmg", {"operating.test": 4, "operating.feed_rate": 40.0}).steady_state()
    ov = {"operating.test": 4, "operating.feed_rate": 41.5, "gas.flow": 16.8, "operating.rpm": 3.08}
    calls = {"rhs": 0, "_jacobian_data": 0}      # the solver's Jacobians (their entries)
    for name in calls:
        def counted(self, *a, _name=name, _f=getattr(ThermalDryer, name), **k):
            calls[_name] += 1
            return _f(self, *a, **k)
        monkeypatch.setattr(ThermalDryer, name, counted)

    def work(run):
        calls.update(rhs=0, _jacobian_data=0)
        out = run()
        return out, calls["rhs"] + 2.6 * calls["_jacobian_data"]
    warm, warm_work = work(lambda: Simulation("ajayi2011_mmg", ov).steady_state(warm=near.warm_data()))
    cold, cold_work = work(lambda: Simulation("ajayi2011_mmg", ov).steady_state())
    a, b = warm.thermal.state, cold.thermal.state
    assert np.max(np.abs(a - b) / np.maximum(np.abs(b), 1e-6 * np.max(np.abs(b)))) < 1e-7
    assert warm_work < 0.5 * cold_work        # 10 residuals, no Jacobian, against 15 and 6


def test_a_step_the_growth_test_would_refuse_is_tried_with_the_gas_caught_up(monkeypatch):
    """Issue 32 item 2: Song's pilot dryer once took 16 iterations and 14 factorisations, four of them fourfold cuts
    of the pseudo-time step after one step whose largest residual was a gas humidity's (the gas, seconds of flow,
    left behind by the solids' step). The gas's own Newton step from the refused state passes the test: 9
    iterations. Without it, the same steady state in more iterations."""
    import rotarydryer.thermal.dryer as dryer_module

    d = Simulation("song2003_ottawa").thermal_dryer()
    ss = d.steady_state()
    assert ss.iterations <= 10
    monkeypatch.setattr(dryer_module, "GAS_CORRECTION", False)
    plain = Simulation("song2003_ottawa").thermal_dryer().steady_state()
    assert plain.iterations > ss.iterations
    scale = d._scale()
    assert np.max(np.abs(ss.state - plain.state) / scale) < 1e-9
    assert ss.residual < 1e-11 and plain.residual < 1e-11


def test_the_gas_correction_moves_only_the_gas_and_lowers_its_residual():
    d = Simulation("song2003_ottawa").thermal_dryer()
    z = d.steady_state().state
    sc = d._scale()
    k = 3 * d.n_classes * d.n_tanks
    d.freeze_shell(z)
    J = d.jacobian(z, d.rhs(0.0, z))
    zp = z.copy()
    zp[k:k + d.n_gas] += 5.0                 # every gas stage 5 K hotter, the solids as they were
    fp = d.rhs(0.0, zp)
    zc, fc, norm = d._gas_corrected(J, zp, fp, sc)
    d.unfreeze_shell()
    assert np.array_equal(zc[:k], zp[:k])
    assert norm < 0.01 * d._residual_norm(fp, zp, sc)
    assert np.max(np.abs(zc[k:] - z[k:]) / sc[k:]) < 1e-3


def _dense_jacobian(d, z):
    d.freeze_shell(z)
    f0 = d.rhs(0.0, z)
    J = np.zeros((d.n, d.n))
    for j in range(d.n):
        zp = z.copy()
        zp[j] += max(abs(z[j]) * 1e-6, 1e-9)
        J[:, j] = d.rhs(0.0, zp) - f0
    d.unfreeze_shell()
    return J


@pytest.mark.parametrize("case, overrides", [
    ("song2003_ottawa", {}), ("lee2008_invicta", {}), ("ajayi2011_mmg", {}),
    ("song2003_ottawa", {"particle_size.classes": 2, "particle_size.entrainment": True, "gas.recycle_fraction": 0.2,
                         "particle_size.distribution": "lognormal", "particle_size.d50": 3e-4, "particle_size.sigma_g": 2.0}),
], ids=["song", "invicta", "mmg", "song-classes-dust-recycle"])
def test_the_jacobian_pattern_holds_every_dependence_of_the_tanks_on_each_other(case, overrides):
    """The solids' balances of a tank depend on the S and W of the tanks that feed it and of its flows' control node,
    and its temperature on theirs (ThermalDryer.sparsity): every nonzero entry of a dense finite-difference Jacobian
    among the tanks' S, W and T, at the start and at the steady state, is in the pattern; a temperature column
    of another tank is never in a mass row (issue 32: Song's colour groups 27 -> 17)."""
    d = Simulation(case, overrides).thermal_dryer()
    pattern = d.sparsity().toarray() != 0
    k = 3 * d.n_classes * d.n_tanks
    for z in (d.initial_state(), d.steady_state().state):
        J = _dense_jacobian(d, z)
        outside = (J[:k, :k] != 0) & ~pattern[:k, :k]
        assert not outside.any(), np.argwhere(outside)[:5]
    nt = d.n_tanks * d.n_classes
    other = ~np.equal.outer(np.arange(nt) % d.n_tanks, np.arange(nt) % d.n_tanks)     # another tank, any class
    assert not pattern[:2 * nt, 2 * nt:3 * nt][np.tile(other, (2, 1))].any()
    if case == "song2003_ottawa" and not overrides:
        assert len(np.unique(d._groups)) <= 17

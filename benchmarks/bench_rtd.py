"""Benchmarks for rotarydryer.rtd (never fail on timing).

Run: ``python -m pytest benchmarks/bench_rtd.py --benchmark-only``

* moments of a 10,000-point curve (uniform and irregular grid, with and
  without a baseline + exponential tail);
* least-squares fits of the classical models to Lee's Invicta tracer curve
  (32 points, 39.6 s rectangular input, fitted dead time);
* E(t) of the closed-closed ADM on 10,000 points (Talbot branch, Pe < 100, and
  closed-form branch, Pe >= 100).
"""

import warnings

import numpy as np
import pytest

from rotarydryer.rtd import axial_dispersion_e, fit_tracer_data, load_tracer_dataset, rtd_moments, tanks_in_series_e

T_UNIFORM = np.linspace(0.0, 6000.0, 10_000)
Y_UNIFORM = tanks_in_series_e(T_UNIFORM, 900.0, 6.0) + 1e-6
_rng = np.random.default_rng(0)
T_IRREG = np.unique(np.sort(_rng.uniform(0, 6000.0, 10_000)))
Y_IRREG = tanks_in_series_e(T_IRREG, 900.0, 6.0)
INVICTA = load_tracer_dataset("lee2008_invicta")


def test_moments_10k_uniform(benchmark):
    m = benchmark(rtd_moments, T_UNIFORM, Y_UNIFORM)
    assert m.n_points == 10_000


def test_moments_10k_irregular(benchmark):
    m = benchmark(rtd_moments, T_IRREG, Y_IRREG)
    assert m.mean_s == pytest.approx(900.0, rel=1e-3)


def test_moments_10k_baseline_and_tail(benchmark):
    m = benchmark(rtd_moments, T_UNIFORM, Y_UNIFORM, baseline="leading", tail="exponential", tail_points=200)
    assert m.tail_extrapolated


@pytest.mark.parametrize("model", ["tanks_in_series", "dispersion_open", "dispersion_closed"])
def test_fit_invicta(benchmark, model):
    def run():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            return fit_tracer_data(INVICTA, model, fit_delay=True)

    f = benchmark.pedantic(run, rounds=5, iterations=1)
    benchmark.extra_info["n_evaluations"] = f.n_evaluations
    benchmark.extra_info["r_squared"] = f.r_squared
    assert f.r_squared > 0.99


@pytest.mark.parametrize("pe", [10.0, 300.0])
def test_closed_adm_e_10k(benchmark, pe):
    e = benchmark(axial_dispersion_e, T_UNIFORM, 900.0, pe, "closed")
    assert e.shape == (10_000,)

"""Benchmarks for parameter estimation (issue 4).

Run: pytest benchmarks/bench_estimation.py --benchmark-only   (or python benchmarks/bench_estimation.py)
"""

import time
import warnings

import pytest

from rotarydryer.estimation.cases import case_parameter, fit_case_to_tracer

LEE_BASE = {"transport.n_cells": 35, "geometry.method": "lee2008_regressions"}
LEE_START = {"transport.kiln_time": 8.69, "transport.backmix": 0.68, "transport.drag_reduction": 0.48}


def lee_fit():
    from rotarydryer.rtd import load_tracer_dataset

    data = load_tracer_dataset("lee2008_invicta")
    params = [case_parameter("lee2008_invicta", k, LEE_BASE, initial=v) for k, v in LEE_START.items()]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fit_case_to_tracer("lee2008_invicta", data, params, base_overrides=LEE_BASE, n_starts=1)


def ajayi_fit():
    from rotarydryer.rtd import load_tracer_dataset

    data = load_tracer_dataset("ajayi2011_test4")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fit_case_to_tracer("ajayi2011_mmg", data, ["transport.solids_velocity", "transport.dispersion"],
                                  base_overrides={"operating.test": 4}, n_starts=1, scale="fit")


def test_ajayi_test4_two_parameter_fit(benchmark):
    pytest.importorskip("rotarydryer.rtd")
    cf = benchmark.pedantic(ajayi_fit, rounds=2, iterations=1)
    benchmark.extra_info["n_evaluations"] = cf.fit.n_evaluations


def test_lee_invicta_three_parameter_fit(benchmark):
    pytest.importorskip("rotarydryer.rtd")
    cf = benchmark.pedantic(lee_fit, rounds=2, iterations=1)
    benchmark.extra_info["n_evaluations"] = cf.fit.n_evaluations
    benchmark.extra_info["seconds_per_evaluation"] = cf.fit.seconds / cf.fit.n_evaluations


if __name__ == "__main__":
    for name, fn in (("Lee Invicta 3-parameter fit", lee_fit), ("Ajayi test 4 2-parameter fit", ajayi_fit)):
        t0 = time.perf_counter()
        cf = fn()
        dt = time.perf_counter() - t0
        print(f"{name}: {dt:.2f} s, {cf.fit.n_evaluations} evaluations, "
              f"{1e3 * dt / cf.fit.n_evaluations:.1f} ms per evaluation, objective {cf.fit.objective:.4g}")

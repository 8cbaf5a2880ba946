"""Benchmarks of the stagnant-core variants (pytest-benchmark; never fail on timing).

Run: OPENBLAS_NUM_THREADS=1 python -m pytest benchmarks/bench_variants.py --benchmark-only -q
Results: benchmarks/results_variants.md.
"""

import numpy as np
import pytest

from rotarydryer.studies.invicta_rtd_spread import INVICTA_FITS, _response, invicta_data, invicta_model

T, _ = invicta_data()


def _model(key):
    f = INVICTA_FITS[key]
    return invicta_model(f["values"], core_model=f.get("core_model", "first_order"), n_cells=f.get("n_cells", 35))


KEYS = ["lee2008", "first_order_core", "diffusive_core_n35", "diffusive_core"]


@pytest.mark.parametrize("key", KEYS)
def test_build_and_steady_state(benchmark, key):
    benchmark(lambda: _model(key).steady_state())


@pytest.mark.parametrize("key", KEYS)
def test_analytic_moments(benchmark, key):
    ss = _model(key).steady_state()
    benchmark(lambda: ss.rtd(simulate=False))


@pytest.mark.parametrize("solver", ["expm", "bdf2"])
@pytest.mark.parametrize("key", KEYS)
def test_response_at_data_times(benchmark, key, solver):
    m = _model(key)
    e = benchmark(_response, m, T, solver)
    assert np.all(np.isfinite(e))

"""Benchmarks for the exact flight geometry (issue: foundation and flight geometry).

Run: pytest benchmarks/bench_geometry.py --benchmark-only
"""

import numpy as np
import pytest

from rotarydryer.geometry import FlightedDrum, TwoSectionFlight

DRUM = FlightedDrum(2.5, 28, TwoSectionFlight(0.195, 0.183, 90.0, 117.0))
PSI = np.arange(0.0, 360.0, 0.1)
RNG = np.random.default_rng(1)
PHI = RNG.uniform(25.0, 65.0, 10_000)
LOAD = RNG.uniform(0.0, 1.0, 10_000)


def one_profile():
    """One full profile (0-360 deg at 0.1 deg): holdup and discharge rate, plus mass averages."""
    h = DRUM.holdup_area(PSI, 45.0)
    q = DRUM.discharge_rate(PSI, 45.0, 3.0)
    cs = DRUM.cascade(45.0, rpm=3.0)
    return h, q, cs


def exact_10k():
    """Mass-averaged fall time, passive time and design load for 10,000 (repose, loading) pairs."""
    cs = DRUM.cascade(PHI, LOAD, rpm=3.0)
    area = DRUM.design_load_area(PHI)
    return cs.mean_fall_time, cs.passive_time, area


def regressions_10k():
    from rotarydryer.geometry.lee2008_regressions import Lee2008Regressions

    reg = Lee2008Regressions()
    cs = reg.cascade(PHI, LOAD, rpm=3.0)
    return cs.mean_fall_time, cs.passive_time, reg.design_load_area(PHI)


def test_profile(benchmark):
    benchmark(one_profile)


def test_exact_10k_pairs(benchmark):
    benchmark(exact_10k)


def test_lee_regressions_10k_pairs(benchmark):
    pytest.importorskip("rotarydryer.geometry.lee2008_regressions")
    benchmark(regressions_10k)


if __name__ == "__main__":  # plain script: print timings without pytest-benchmark
    import timeit

    for f, n in ((one_profile, 200), (exact_10k, 5), (regressions_10k, 50)):
        t = min(timeit.repeat(f, number=n, repeat=3)) / n
        print(f"{f.__name__:16s} {t * 1e3:9.3f} ms")

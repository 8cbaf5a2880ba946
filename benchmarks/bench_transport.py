"""Solids-transport benchmarks (pytest-benchmark; never fail on timing).

Run: python -m pytest benchmarks/bench_transport.py --benchmark-only -q
Targets (issue 3): Invicta N = 35 steady state < 20 ms, tracer RTD over 60 min < 50 ms;
MMG tracer RTD over 60 min < 200 ms; cost ~linear from 35 to 1000 cells.
"""

import math
import time

import numpy as np
import pytest

from rotarydryer.cases import build_model, load_case
from rotarydryer.geometry.lee2008_regressions import Lee2008Regressions
from rotarydryer.transport import lee2008, lee2008_repose_profile


def _invicta(method):
    return build_model(load_case("lee2008_invicta", {"geometry.method": method}))


@pytest.mark.parametrize("method", ["lee2008_regressions", "exact"])
def test_invicta_build(benchmark, method):
    benchmark(_invicta, method)


@pytest.mark.parametrize("method", ["lee2008_regressions", "exact"])
def test_invicta_steady_state(benchmark, method):
    m = _invicta(method)
    ss = benchmark(m.steady_state)
    assert ss.mass_balance_error < 1e-9


@pytest.mark.parametrize("sim", ["expm", "bdf2"])
def test_invicta_rtd_60min(benchmark, sim):
    ss = _invicta("lee2008_regressions").steady_state()
    r = benchmark(ss.rtd, None, 3600.0, 10.0, sim)
    assert abs(r.response.moments()["recovery"] - 1) < 1e-3


def test_invicta_analytic_moments(benchmark):
    ss = _invicta("lee2008_regressions").steady_state()
    benchmark(lambda: ss.tracer_system().moments())


def scaled_model(n):
    """Invicta with n cells; C_F^G and t_kiln scaled by 35/n so that C_R >= 0 (Lee Ch. 7:
    t ~ 1/N)."""
    return lee2008(geometry=Lee2008Regressions(), n_cells=n, feed_rate=98000 / 3600, length=12.0, rpm=3.0, slope=2.8,
                   bulk_density=940.0, repose_angle=lee2008_repose_profile(n, 0.02, 0.002),   # Lee's Invicta
                   kiln_time=8.69 * 35 / n, backmix=0.68, drag_reduction=0.48 * 35 / n)


@pytest.mark.parametrize("n", [35, 100, 300, 1000])
def test_scaling_steady(benchmark, n):
    m = scaled_model(n)
    benchmark(m.steady_state)


@pytest.mark.parametrize("n", [35, 100, 300, 1000])
def test_scaling_rtd_bdf2(benchmark, n):
    ss = scaled_model(n).steady_state()
    benchmark(ss.rtd, None, 3600.0, 10.0, "bdf2")


def _ajayi_available():
    try:
        build_model(load_case("ajayi2011_mmg"))
        return True
    except Exception:
        return False


@pytest.mark.skipif(not _ajayi_available(), reason="ajayi2011_mmg case not available")
def test_mmg_rtd_60min(benchmark):
    ss = build_model(load_case("ajayi2011_mmg")).steady_state()
    benchmark(ss.rtd, None, 3600.0, 10.0, "auto")


@pytest.mark.skipif(not _ajayi_available(), reason="ajayi2011_mmg case not available")
def test_mmg_steady_state(benchmark):
    m = build_model(load_case("ajayi2011_mmg"))
    benchmark(m.steady_state)


def scaling_exponent(ns=(35, 100, 300, 1000), repeat=5):
    """Least-squares slope of log(time) vs log(n) for steady state and BDF2 tracer RTD."""
    out = {}
    for what in ("steady", "rtd_bdf2"):
        ts = []
        for n in ns:
            ss = scaled_model(n).steady_state()
            m = scaled_model(n)
            best = math.inf
            for _ in range(repeat):
                t0 = time.perf_counter()
                if what == "steady":
                    m.steady_state()
                else:
                    ss.rtd(None, 3600.0, 10.0, "bdf2")
                best = min(best, time.perf_counter() - t0)
            ts.append(best)
        out[what] = (np.polyfit(np.log(ns), np.log(ts), 1)[0], ts)
    return out


if __name__ == "__main__":
    for k, (p, ts) in scaling_exponent().items():
        print(k, f"exponent {p:.2f}", " ".join(f"{t * 1e3:.2f}ms" for t in ts))
